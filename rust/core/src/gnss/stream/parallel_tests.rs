//! The parallel paths of [`super::parallel`] against the epoch-by-epoch engine, on the synthetic sessions
//! of [`crate::gnss::synthetic`].

use super::Engine;
use crate::gnss::options::{ElevationSigma, EngineOptions, Method};
use crate::gnss::synthetic;

fn pool(threads: usize) -> rayon::ThreadPool {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap()
}

#[test]
fn attitude_single_epochs_in_parallel_are_those_of_one_epoch_at_a_time() {
    // Three antennas (two rovers, attitude mode, no continuity), more epochs than a block, and two
    // regimes of the code noise scale: the model about right (its estimate moves every epoch once it
    // stands: the fixes run in order) and the model five times the noise (the factor clamped at its
    // floor: the fixes run ahead in parallel). The engine starts uncalibrated (no `run`), so each regime
    // also passes the epoch where the estimate starts to stand. One epoch per call on one thread is the
    // epoch-by-epoch engine; the whole session on four threads must give it bit for bit.
    let n = super::parallel::BLOCK + 9;
    let body = [[1.0, 0.2, 0.0], [-0.3, 1.2, 0.05]];
    let sim = synthetic::session(n, &body, 5);
    let opts = EngineOptions {
        systems: vec![
            crate::gnss::signal::System::Gps,
            crate::gnss::signal::System::Galileo,
        ],
        frequencies: 2,
        method: Method::Lambda,
        body_baselines_m: body.to_vec(),
        ..EngineOptions::default()
    };
    let loud = ElevationSigma { a_m: 1.5, b_m: 1.5 };
    for opts in [
        opts.clone(),
        EngineOptions {
            code_sigma: loud,
            ..opts
        },
    ] {
        let engine = || {
            Engine::new(
                &sim.nav,
                opts.clone(),
                sim.obs.sats.clone(),
                sim.obs.glonass_channel.clone(),
                3,
            )
            .unwrap()
        };
        let (whole, whole_engine) = pool(4).install(|| {
            let mut e = engine();
            (e.process(&sim.obs).unwrap(), e)
        });
        let (single, single_engine) = pool(1).install(|| {
            let mut e = engine();
            let mut out = Vec::new();
            for k in 0..n {
                out.extend(e.process(&sim.obs.epochs(k..k + 1)).unwrap());
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
