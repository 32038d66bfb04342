//! One mechanism: a stream in chunks, epoch by epoch or in parallel blocks gives the whole session.

use super::simulation::{options, simulate};
use crate::gnss::options::{ElevationSigma, EngineOptions};
use crate::gnss::signal::MAX_FREQUENCIES;
use crate::gnss::stream::{parallel, Engine};

#[test]
fn streaming_in_chunks_gives_the_whole_session() {
    let truth = simulate(9, &[[0.6, -0.8, 0.05]], 4);
    let mut opts = options();
    opts.continuity = true;
    // `run` calibrates the code noise on the session's first epochs before solving them, which a stream
    // cannot: the whole session here is one engine fed every epoch in one call.
    let engine = || {
        Engine::new(
            &truth.nav,
            opts.clone(),
            truth.obs.sats.clone(),
            truth.obs.glonass_channel.clone(),
            2,
        )
        .unwrap()
    };
    let whole = engine().process(&truth.obs).unwrap();
    let mut engine = engine();
    let mut streamed = Vec::new();
    for range in [0..4, 4..5, 5..9] {
        streamed.extend(engine.process(&truth.obs.epochs(range)).unwrap());
    }
    assert_eq!(streamed, whole);
    // Epochs must come after those processed.
    assert!(engine.process(&truth.obs.epochs(8..9)).is_err());
}

#[test]
fn epochs_cuts_every_receiver_array_at_the_epoch_boundaries() {
    let truth = simulate(4, &[[0.6, -0.8, 0.05]], 2);
    let part = truth.obs.epochs(1..3);
    assert_eq!(part.time_gpst_ns, truth.obs.time_gpst_ns[1..3]);
    for (r, whole) in part.receivers.iter().zip(&truth.obs.receivers) {
        for k in 0..2 {
            for s in 0..part.n_sats() {
                for slot in 0..MAX_FREQUENCIES {
                    let (i, j) = (part.index(k, s, slot), truth.obs.index(k + 1, s, slot));
                    assert_eq!(r.code_m[i].to_bits(), whole.code_m[j].to_bits());
                    assert_eq!(r.phase_cycles[i].to_bits(), whole.phase_cycles[j].to_bits());
                    assert_eq!(r.lli[i], whole.lli[j]);
                }
            }
        }
    }
    part.validate().unwrap();
}

#[test]
fn single_epochs_in_parallel_are_those_of_one_epoch_at_a_time() {
    // More epochs than a block of `parallel::BLOCK`, two rovers, and the three regimes of the code noise
    // scale: the model about right (the factor moves every epoch once it stands), the model five times
    // the noise (the factor clamped at its floor, where the float solutions are computed ahead), and a
    // known length (its own range). The engine starts uncalibrated (no `run`), so each regime also
    // passes the epoch where the estimate starts to stand. One epoch per call on one thread is the
    // epoch-by-epoch engine; the whole session on four threads must give it bit for bit.
    let n = parallel::BLOCK + 9;
    let truth = simulate(n, &[[0.6, -0.8, 0.05], [2.0, 1.0, -0.1]], 21);
    let loud = ElevationSigma { a_m: 1.5, b_m: 1.5 };
    let regimes = [
        options(),
        EngineOptions {
            code_sigma: loud,
            ..options()
        },
        EngineOptions {
            baseline_lengths_m: vec![(0.36f64 + 0.64 + 0.0025).sqrt(), 5.01f64.sqrt()],
            ..options()
        },
    ];
    let pool = |threads| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
    };
    for opts in regimes {
        let engine = || {
            Engine::new(
                &truth.nav,
                opts.clone(),
                truth.obs.sats.clone(),
                truth.obs.glonass_channel.clone(),
                3,
            )
            .unwrap()
        };
        let (whole, whole_engine) = pool(4).install(|| {
            let mut e = engine();
            (e.process(&truth.obs).unwrap(), e)
        });
        let (single, single_engine) = pool(1).install(|| {
            let mut e = engine();
            let mut out = Vec::new();
            for k in 0..n {
                out.extend(e.process(&truth.obs.epochs(k..k + 1)).unwrap());
            }
            (out, e)
        });
        // Debug text: every float to its last bit, NaN equal to NaN.
        assert_eq!(format!("{whole:?}"), format!("{single:?}"));
        assert_eq!(whole_engine.warnings(), single_engine.warnings());
        assert_eq!(
            format!("{:?}", whole_engine.code_sigma_scale()),
            format!("{:?}", single_engine.code_sigma_scale())
        );
        assert_eq!(
            whole_engine.double_differences(),
            single_engine.double_differences()
        );
        assert!(whole_engine.code_scale_calibrated());
        assert!(whole.iter().filter(|e| e.fixed).count() > n / 2);
    }
}
