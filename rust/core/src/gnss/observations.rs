//! Observations of a session: several receivers on the same epochs and satellites, after the signal of
//! each frequency slot was chosen (the reader picks one RINEX code per system and slot; see
//! [`crate::gnss::signal`]).

use super::signal::{carrier_frequency_hz, SatId, MAX_FREQUENCIES};
use crate::error::{Error, Result};

/// Largest number of epochs, satellites and receivers of one session (bounds memory: 10^5 epochs x 150
/// satellites x 3 slots x 8 receivers x 21 bytes is about 7.6 GB, so the product is bounded too).
pub const MAX_EPOCHS: usize = 1_000_000;
pub const MAX_SATELLITES: usize = 256;
pub const MAX_RECEIVERS: usize = 16;
/// Largest `epochs x satellites x receivers` of one session.
pub const MAX_OBSERVATION_CELLS: usize = 100_000_000;

/// One receiver's observations; every array is `[epoch][satellite][slot]` row-major, of length
/// `n_epochs * n_sats * MAX_FREQUENCIES`, NaN (or 0 for `lli`) where there is no observation.
#[derive(Debug, Clone, PartialEq)]
pub struct ReceiverObservations {
    /// Pseudoranges, m.
    pub code_m: Vec<f64>,
    /// Carrier phases, cycles, with the RINEX sign (grows with range).
    pub phase_cycles: Vec<f64>,
    /// Doppler, Hz (RINEX sign: positive for an approaching satellite); NaN where absent.
    pub doppler_hz: Vec<f64>,
    /// Carrier-to-noise density, dB-Hz; NaN where absent.
    pub snr_dbhz: Vec<f64>,
    /// RINEX loss-of-lock indicator of the phase (bit 0: lock lost since the previous observation,
    /// bit 1: half-cycle ambiguity possible).
    pub lli: Vec<u8>,
    /// Header APPROX POSITION XYZ, ECEF m; `None` where the file gives none (zeros).
    pub approx_position_m: Option<[f64; 3]>,
}

/// The session: common epochs, the satellites seen, one [`ReceiverObservations`] per antenna (the
/// reference antenna, the "base", first).
#[derive(Debug, Clone, PartialEq)]
pub struct Observations {
    /// Epoch labels (receiver time, nominally GPST), ns since the GPS epoch, strictly increasing; the
    /// same labels for every receiver (the reader keeps the epochs common to all files).
    pub time_gpst_ns: Vec<i64>,
    /// Satellites, the second axis of every array.
    pub sats: Vec<SatId>,
    /// GLONASS FDMA channel of each satellite (`None` for other systems or where unknown).
    pub glonass_channel: Vec<Option<i8>>,
    pub receivers: Vec<ReceiverObservations>,
}

impl Observations {
    pub fn n_epochs(&self) -> usize {
        self.time_gpst_ns.len()
    }

    pub fn n_sats(&self) -> usize {
        self.sats.len()
    }

    /// Flat index of (epoch, satellite, slot) in the receiver arrays.
    #[inline]
    pub fn index(&self, epoch: usize, sat: usize, slot: usize) -> usize {
        (epoch * self.sats.len() + sat) * MAX_FREQUENCIES + slot
    }

    /// The epochs `range` of the session (every receiver, every satellite), a copy.
    ///
    /// # Panics
    /// When `range` reaches past the last epoch (a caller's defect).
    pub fn epochs(&self, range: std::ops::Range<usize>) -> Observations {
        let cells = self.sats.len() * MAX_FREQUENCIES;
        let (a, b) = (range.start * cells, range.end * cells);
        Observations {
            time_gpst_ns: self.time_gpst_ns[range].to_vec(),
            sats: self.sats.clone(),
            glonass_channel: self.glonass_channel.clone(),
            receivers: self
                .receivers
                .iter()
                .map(|r| ReceiverObservations {
                    code_m: r.code_m[a..b].to_vec(),
                    phase_cycles: r.phase_cycles[a..b].to_vec(),
                    doppler_hz: r.doppler_hz[a..b].to_vec(),
                    snr_dbhz: r.snr_dbhz[a..b].to_vec(),
                    lli: r.lli[a..b].to_vec(),
                    approx_position_m: r.approx_position_m,
                })
                .collect(),
        }
    }

    /// Carrier frequency of satellite `sat` (index) in `slot`, Hz, if that signal exists.
    pub fn frequency_hz(&self, sat: usize, slot: usize) -> Option<f64> {
        let id = self.sats[sat];
        carrier_frequency_hz(id.system, slot, self.glonass_channel[sat])
    }

    /// Checks sizes, limits and ordering; values may be NaN (absent) but not infinite.
    ///
    /// # Errors
    /// [`Error::Shape`] for arrays of the wrong length, [`Error::TooLarge`] beyond the limits,
    /// [`Error::OutOfRange`] for unordered epochs, repeated satellites or infinite values.
    pub fn validate(&self) -> Result<()> {
        let (ne, ns, nr) = (self.n_epochs(), self.n_sats(), self.receivers.len());
        for (name, n, limit) in [
            ("epochs", ne, MAX_EPOCHS),
            ("satellites", ns, MAX_SATELLITES),
            ("receivers", nr, MAX_RECEIVERS),
            (
                "observation cells",
                ne.saturating_mul(ns).saturating_mul(nr),
                MAX_OBSERVATION_CELLS,
            ),
        ] {
            if n > limit {
                return Err(Error::TooLarge {
                    name: "observations",
                    requested: n as f64,
                    unit: name,
                    limit: limit as f64,
                });
            }
        }
        if nr < 2 {
            return Err(Error::out_of_range(
                "observations",
                format!("expected two or more receivers, got {nr}"),
            ));
        }
        if self.glonass_channel.len() != ns {
            return Err(Error::Shape {
                name: "glonass_channel",
                expected: format!("({ns},)"),
                actual: format!("({},)", self.glonass_channel.len()),
            });
        }
        if let Some(k) = self.time_gpst_ns.windows(2).position(|w| w[1] <= w[0]) {
            return Err(Error::out_of_range(
                "time_gpst_ns",
                format!(
                    "expected strictly increasing epochs, epoch {} is not after epoch {k}",
                    k + 1
                ),
            ));
        }
        let mut sorted = self.sats.clone();
        sorted.sort();
        if let Some(w) = sorted.windows(2).find(|w| w[0] == w[1]) {
            return Err(Error::out_of_range(
                "sats",
                format!("expected each satellite once, got {} twice", w[0]),
            ));
        }
        for r in &self.receivers {
            r.validate(ne, ns)?;
        }
        Ok(())
    }
}

impl ReceiverObservations {
    /// A receiver that observed nothing yet: `n_epochs` x `n_sats` x [`MAX_FREQUENCIES`] values of each
    /// array, every observation absent (NaN, loss-of-lock indicator 0), to be filled in by a simulation
    /// or a reader.
    pub fn absent(n_epochs: usize, n_sats: usize, approx_position_m: Option<[f64; 3]>) -> Self {
        let cells = n_epochs * n_sats * MAX_FREQUENCIES;
        ReceiverObservations {
            code_m: vec![f64::NAN; cells],
            phase_cycles: vec![f64::NAN; cells],
            doppler_hz: vec![f64::NAN; cells],
            snr_dbhz: vec![f64::NAN; cells],
            lli: vec![0; cells],
            approx_position_m,
        }
    }

    /// Checks one receiver's arrays: `n_epochs` x `n_sats` x [`MAX_FREQUENCIES`] values each, none
    /// infinite.
    fn validate(&self, n_epochs: usize, n_sats: usize) -> Result<()> {
        let (ne, ns, r) = (n_epochs, n_sats, self);
        let len = ne * ns * MAX_FREQUENCIES;
        for (name, n) in [
            ("code_m", r.code_m.len()),
            ("phase_cycles", r.phase_cycles.len()),
            ("doppler_hz", r.doppler_hz.len()),
            ("snr_dbhz", r.snr_dbhz.len()),
            ("lli", r.lli.len()),
        ] {
            if n != len {
                return Err(Error::Shape {
                    name,
                    expected: format!("({ne}, {ns}, {MAX_FREQUENCIES}) = {len} values"),
                    actual: format!("{n} values"),
                });
            }
        }
        for (name, v) in [
            ("code_m", &r.code_m),
            ("phase_cycles", &r.phase_cycles),
            ("doppler_hz", &r.doppler_hz),
            ("snr_dbhz", &r.snr_dbhz),
        ] {
            if let Some(i) = v.iter().position(|x| x.is_infinite()) {
                return Err(Error::NonFinite { name, index: i });
            }
        }
        Ok(())
    }
}
