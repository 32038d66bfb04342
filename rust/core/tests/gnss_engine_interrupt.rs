//! The GNSS engine polls the process-wide interrupt flag between epochs: a binary of its own, so that no
//! other test sees the flag set.

use gnssatt_core::gnss::navdata::NavData;
use gnssatt_core::gnss::observations::{Observations, ReceiverObservations};
use gnssatt_core::gnss::options::EngineOptions;
use gnssatt_core::gnss::session::run;
use gnssatt_core::gnss::signal::{SatId, System};
use gnssatt_core::interrupt::{clear, request};
use gnssatt_core::Error;

#[test]
fn a_requested_interrupt_stops_the_session_until_cleared() {
    let rx = ReceiverObservations::absent(3, 1, None);
    let obs = Observations {
        time_gpst_ns: vec![0, 1_000_000_000, 2_000_000_000],
        sats: vec![SatId {
            system: System::Gps,
            prn: 5,
        }],
        glonass_channel: vec![None],
        receivers: vec![rx.clone(), rx],
    };
    let nav = NavData::default();
    let opts = EngineOptions::default();
    request();
    let stopped = run(&obs, &nav, &opts);
    clear();
    assert!(
        matches!(stopped, Err(Error::Interrupted { .. })),
        "{stopped:?}"
    );
    // Cleared: the same empty session runs to its own error (no usable signal), not an interrupt.
    let err = run(&obs, &nav, &opts).unwrap_err();
    assert!(
        matches!(
            err,
            Error::OutOfRange {
                name: "observations",
                ..
            }
        ),
        "{err}"
    );
}
