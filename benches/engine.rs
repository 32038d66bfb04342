//! Criterion benchmarks of the observation engine per epoch (`gnssatt_core::gnss::stream::Engine`, every
//! step: code solutions, satellite geometry, signal selection, arcs, double differences, LAMBDA fix and
//! gate), one whole session per iteration; criterion's `Elements` throughput is the session's epochs, so
//! its "elem/s" inverts to the time per epoch:
//! - `engine/geonet_gps_l1l2`: the shipped GEONET pair 0759 -> 3040 (`python/gnssatt/data/`, RINEX 2.10,
//!   GPS L1+L2, 120 epochs), read with the core's RINEX readers and converted here (as
//!   `gnssatt.gnss.session_input` does for these files: C1/L1 in slot 0, P2/L2 in slot 1, epochs matched
//!   within 25 ms and moved onto the first file's labels, the header positions);
//! - `engine/sim_gec_3f`: a simulated two-antenna all-signal epoch set ([`gnssatt_core::gnss::synthetic`]:
//!   GPS, Galileo and BeiDou, three frequencies, a 1 m baseline), 120 epochs.
//!
//! Both are single-epoch (moving, no continuity), LAMBDA, mask 10 degrees, base at its known position, as
//! `benches/python/engine_per_epoch.py` runs the engine from Python. Threads: rayon's default (every CPU;
//! `RAYON_NUM_THREADS=1` for one). `GNSSATT_ENGINE_BENCH_OUT=DIR` writes each session's solutions (Debug
//! text, every float to its last bit) to `DIR/NAME.txt`, to compare two builds.
use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use gnssatt_core::gnss::navdata::{KeplerRecord, NavData};
use gnssatt_core::gnss::observations::{Observations, ReceiverObservations};
use gnssatt_core::gnss::options::{EngineOptions, Method};
use gnssatt_core::gnss::signal::{
    carrier_frequency_hz, SatId, System, MAX_FREQUENCIES, SPEED_OF_LIGHT_M_S,
};
use gnssatt_core::gnss::solution::EpochSolution;
use gnssatt_core::gnss::stream::Engine;
use gnssatt_core::gnss::synthetic;
use gnssatt_core::rinex::{
    read_nav, read_obs_body, BodyOptions, ObsBody, SystemLayout, KEPLER_VALUES,
};
use std::hint::black_box;
use std::path::PathBuf;

/// 1980-01-06 (the GPS epoch) in ns since 1970.
const GPS_EPOCH_UNIX_NS: i64 = 315_964_800 * 1_000_000_000;
const WEEK_NS: i64 = 604_800 * 1_000_000_000;
/// Labels of two files this close are one epoch, ns (`gnssatt.gnss.session_input.MATCH_TOLERANCE_NS`).
const MATCH_TOLERANCE_NS: i64 = 25_000_000;

/// A session: its observations, navigation data and options.
struct Session {
    obs: Observations,
    nav: NavData,
    opts: EngineOptions,
}

impl Session {
    /// Every epoch through a new engine (what one `gnss_run` call does after reading): the number of
    /// fixed epochs and the solutions.
    fn run(&self) -> (usize, Vec<EpochSolution>) {
        let mut engine = Engine::new(
            &self.nav,
            self.opts.clone(),
            self.obs.sats.clone(),
            self.obs.glonass_channel.clone(),
            self.obs.receivers.len(),
        )
        .expect("valid session");
        let epochs = engine.process(&self.obs).expect("session solves");
        (epochs.iter().filter(|e| e.fixed).count(), epochs)
    }
}

fn geonet(name: &str) -> Vec<u8> {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../python/gnssatt/data/rtklib_geonet_0759_3040")
        .join(name);
    std::fs::read(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// The line index after `END OF HEADER` and the header's APPROX POSITION XYZ.
fn header(text: &[u8]) -> (usize, [f64; 3]) {
    let lines: Vec<&str> = std::str::from_utf8(text).expect("ASCII").lines().collect();
    let end = lines
        .iter()
        .position(|l| l.contains("END OF HEADER"))
        .expect("a header");
    let xyz = lines
        .iter()
        .find(|l| l.contains("APPROX POSITION XYZ"))
        .expect("a position");
    let v: Vec<f64> = xyz[..42]
        .split_whitespace()
        .map(|x| x.parse().unwrap())
        .collect();
    (end + 1, [v[0], v[1], v[2]])
}

/// The body of a GEONET file (`# / TYPES OF OBSERV`: L1 C1 L2 P2).
fn geonet_body(text: &[u8]) -> ObsBody {
    let (first_line, _) = header(text);
    let opts = BodyOptions {
        v3: false,
        default_system: b'G',
        layouts: vec![SystemLayout {
            key: b'*',
            n_fields: 4,
            keep: vec![0, 1, 2, 3],
            columns: vec![0, 1, 2, 3],
            factors: vec![1.0; 4],
        }],
        n_codes: 4,
        header_labels: vec!["END OF HEADER".into(), "COMMENT".into()],
        max_cells: 1 << 30,
        first_line,
    };
    read_obs_body(text, &opts).expect("a valid body")
}

fn gps(id: &str) -> SatId {
    SatId {
        system: System::Gps,
        prn: id[1..].trim().parse().unwrap(),
    }
}

/// The GEONET pair: the epochs common to both files, the union of their satellites.
fn geonet_session() -> Session {
    let files = ["07590920.05o", "30400920.05o"];
    let texts: Vec<Vec<u8>> = files.iter().map(|f| geonet(f)).collect();
    let bodies: Vec<ObsBody> = texts.iter().map(|t| geonet_body(t)).collect();
    // Per common epoch, its index in each file: the receivers label epochs up to 9 ms off the second.
    let matched: Vec<[usize; 2]> = (0..bodies[0].time_ns.len())
        .filter_map(|e| {
            let t = bodies[0].time_ns[e];
            let j = bodies[1]
                .time_ns
                .iter()
                .position(|u| (u - t).abs() <= MATCH_TOLERANCE_NS)?;
            Some([e, j])
        })
        .collect();
    let times: Vec<i64> = matched.iter().map(|m| bodies[0].time_ns[m[0]]).collect();
    let mut names: Vec<String> = bodies.iter().flat_map(|b| b.sats.clone()).collect();
    names.sort();
    names.dedup();
    let sats: Vec<SatId> = names.iter().map(|s| gps(s)).collect();
    let receivers = bodies
        .iter()
        .zip(&texts)
        .enumerate()
        .map(|(r, (b, text))| {
            let mut rx =
                ReceiverObservations::absent(times.len(), sats.len(), Some(header(text).1));
            for (k, m) in matched.iter().enumerate() {
                let e = m[r];
                // Onto the first file's label: code and phase less what the label offset adds.
                let delta_s = (b.time_ns[e] - times[k]) as f64 * 1e-9;
                for (s, name) in names.iter().enumerate() {
                    let Some(j) = b.sats.iter().position(|x| x == name) else {
                        continue;
                    };
                    let cell = (e * b.sats.len() + j) * 4;
                    for (slot, phase, code) in [(0, 0, 1), (1, 2, 3)] {
                        let i = (k * sats.len() + s) * MAX_FREQUENCIES + slot;
                        let f = carrier_frequency_hz(System::Gps, slot, None).unwrap();
                        rx.phase_cycles[i] = b.data[cell + phase] - f * delta_s;
                        rx.lli[i] = b.lli[cell + phase];
                        rx.code_m[i] = b.data[cell + code] - SPEED_OF_LIGHT_M_S * delta_s;
                    }
                }
            }
            rx
        })
        .collect();
    let obs = Observations {
        time_gpst_ns: times.iter().map(|t| t - GPS_EPOCH_UNIX_NS).collect(),
        glonass_channel: vec![None; sats.len()],
        sats,
        receivers,
    };
    let base = obs.receivers[0].approx_position_m;
    let opts = EngineOptions {
        systems: vec![System::Gps],
        frequencies: 2,
        method: Method::Lambda,
        base_position_m: base,
        ..EngineOptions::default()
    };
    Session {
        nav: geonet_nav(&["07590920.05n", "30400920.05n"]),
        obs,
        opts,
    }
}

/// The Kepler records of the navigation files (layout of `gnssatt_core::rinex::KEPLER_VALUES`: af0..2,
/// then the broadcast orbit lines).
fn geonet_nav(files: &[&str]) -> NavData {
    let mut nav = NavData::default();
    for f in files {
        let r = read_nav(&geonet(f), &["END OF HEADER".into(), "COMMENT".into()]).expect("nav");
        nav.klobuchar = Some([
            r.iono_alpha[0],
            r.iono_alpha[1],
            r.iono_alpha[2],
            r.iono_alpha[3],
            r.iono_beta[0],
            r.iono_beta[1],
            r.iono_beta[2],
            r.iono_beta[3],
        ]);
        nav.leap_seconds = r.leap_seconds.map(|l| l as i32);
        for (i, sat) in r.kepler_sats.iter().enumerate() {
            let v = &r.kepler_values[i * KEPLER_VALUES..(i + 1) * KEPLER_VALUES];
            let field = |k: usize| v[3 + k];
            nav.kepler.push(KeplerRecord {
                sat: gps(sat),
                toc_gpst_ns: r.kepler_toc_ns[i] - GPS_EPOCH_UNIX_NS,
                toe_gpst_ns: field(18) as i64 * WEEK_NS + (field(8) * 1e9).round() as i64,
                af: [v[0], v[1], v[2]],
                crs: field(1),
                delta_n: field(2),
                m0: field(3),
                cuc: field(4),
                e: field(5),
                cus: field(6),
                sqrt_a: field(7),
                cic: field(9),
                omega0: field(10),
                cis: field(11),
                i0: field(12),
                crc: field(13),
                omega: field(14),
                omega_dot: field(15),
                idot: field(16),
                health: field(21),
                tgd_s: [field(22), f64::NAN],
                iode: field(0),
                accuracy_m: field(20),
                fit_interval_h: field(25),
                data_source: f64::NAN,
            });
        }
    }
    nav
}

/// The simulated all-signal pair (`gnssatt_core::gnss::synthetic`): a 1 m baseline, `n` epochs.
fn sim_session(n: usize) -> Session {
    let sim = synthetic::session(n, &[[0.6, 0.8, 0.0]], 1);
    let opts = EngineOptions {
        systems: vec![System::Gps, System::Galileo, System::BeiDou],
        frequencies: 3,
        method: Method::Lambda,
        base_position_m: Some(sim.base_m),
        ..EngineOptions::default()
    };
    Session {
        obs: sim.obs,
        nav: sim.nav,
        opts,
    }
}

fn engine(c: &mut Criterion) {
    let mut g = c.benchmark_group("engine");
    g.sample_size(10);
    for (name, session) in [
        ("geonet_gps_l1l2", geonet_session()),
        ("sim_gec_3f", sim_session(120)),
    ] {
        let epochs = session.obs.n_epochs();
        // Not a test (that is tests/): a session that stopped fixing would time something else.
        let (fixed, solutions) = session.run();
        assert!(
            fixed * 2 > epochs,
            "{name}: {fixed} of {epochs} epochs fixed"
        );
        eprintln!("{name}: {epochs} epochs, {fixed} fixed");
        if let Some(dir) = std::env::var_os("GNSSATT_ENGINE_BENCH_OUT") {
            // Every float to its last bit: two builds' files compare equal when their results do.
            let path = PathBuf::from(dir).join(format!("{name}.txt"));
            std::fs::write(&path, format!("{solutions:#?}")).expect("writable folder");
        }
        g.throughput(Throughput::Elements(epochs as u64));
        g.bench_function(name, |b| b.iter(|| black_box(&session).run()));
    }
    g.finish();
}

criterion_group!(benches, engine);
criterion_main!(benches);
