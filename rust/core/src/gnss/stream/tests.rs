//! A synthetic session with a known truth: a made-up constellation (GPS, GLONASS, Galileo, BeiDou
//! broadcast records of near-circular orbits), observations computed from the engine's own orbit model
//! ([`Ephemerides::state`] through [`satellite_geometry`]) for antennas at known baselines, millisecond
//! receiver clocks, random integer ambiguities, white code and phase noise from a fixed seed, and slips.
//! The truth the tests check against is the baselines put in, which nothing in the engine sees.

use nalgebra::Vector3;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use super::Engine;
use crate::error::Error;
use crate::gnss::ephemeris::Ephemerides;
use crate::gnss::geometry::satellite_geometry;
use crate::gnss::geometry::{enu_from_ecef, geodetic_from_ecef};
use crate::gnss::navdata::{GlonassRecord, KeplerRecord, NavData};
use crate::gnss::observations::{Observations, ReceiverObservations};
use crate::gnss::options::{EngineOptions, Method, Motion};
use crate::gnss::rtk::filter::Dynamics;
use crate::gnss::session::run;
use crate::gnss::signal::{SatId, System, MAX_FREQUENCIES, SPEED_OF_LIGHT_M_S};
use crate::gnss::solution::{EpochSolution, FixState};

/// GPS week 2300, Monday 01:00 (GPST ns).
const T0_NS: i64 = (2300 * 604_800 + 86_400 + 3600) * 1_000_000_000;
const MU_M3_S2: f64 = 3.986_004_418e14;
const OMEGA_E_RAD_S: f64 = 7.292_115_146_7e-5;

fn sat(system: System, prn: u8) -> SatId {
    SatId { system, prn }
}

/// A Keplerian record of a near-circular orbit: plane `plane` of six (60 degrees of right ascension
/// apart), `slot` of four along it.
fn kepler(s: SatId, radius_m: f64, incl_deg: f64, plane: usize, slot: usize) -> KeplerRecord {
    let galileo = s.system == System::Galileo;
    KeplerRecord {
        sat: s,
        toc_gpst_ns: T0_NS,
        toe_gpst_ns: T0_NS,
        af: [1e-5 * (slot as f64 - 1.5), 1e-12, 0.0],
        crs: 0.0,
        delta_n: 0.0,
        m0: (slot as f64 * 90.0 + plane as f64 * 15.0).to_radians(),
        cuc: 0.0,
        e: 0.002,
        cus: 0.0,
        sqrt_a: radius_m.sqrt(),
        cic: 0.0,
        omega0: (plane as f64 * 60.0).to_radians(),
        cis: 0.0,
        i0: incl_deg.to_radians(),
        crc: 0.0,
        omega: 0.3,
        omega_dot: -8e-9,
        idot: 0.0,
        health: 0.0,
        tgd_s: if s.system == System::Gps {
            [0.0, f64::NAN]
        } else {
            [0.0, 0.0]
        },
        iode: 1.0,
        accuracy_m: 2.0,
        fit_interval_h: 4.0,
        data_source: if galileo { 517.0 } else { f64::NAN },
    }
}

/// A GLONASS record of a circular orbit (radius 25 510 km, 64.8 degrees) at `tb`, state in ECEF.
fn glonass(s: SatId, plane: usize, slot: usize, channel: i8, tb_ns: i64) -> GlonassRecord {
    let r = 25_510e3;
    let (raan, u) = (
        (plane as f64 * 120.0).to_radians(),
        (slot as f64 * 45.0 + plane as f64 * 15.0).to_radians(),
    );
    let inc = 64.8f64.to_radians();
    let n = (MU_M3_S2 / (r * r * r)).sqrt();
    let pos_i = Vector3::new(
        r * (raan.cos() * u.cos() - raan.sin() * u.sin() * inc.cos()),
        r * (raan.sin() * u.cos() + raan.cos() * u.sin() * inc.cos()),
        r * u.sin() * inc.sin(),
    );
    let vel_i = Vector3::new(
        r * n * (-raan.cos() * u.sin() - raan.sin() * u.cos() * inc.cos()),
        r * n * (-raan.sin() * u.sin() + raan.cos() * u.cos() * inc.cos()),
        r * n * u.cos() * inc.sin(),
    );
    // Inertial = ECEF at tb (the Earth-fixed frame's angle is irrelevant for a made-up orbit); the
    // ECEF velocity lacks the frame's rotation.
    let w = Vector3::new(0.0, 0.0, OMEGA_E_RAD_S);
    let vel = vel_i - w.cross(&pos_i);
    GlonassRecord {
        sat: s,
        tb_gpst_ns: tb_ns,
        clock_bias_s: 2e-5,
        gamma_n: 0.0,
        position_m: pos_i.into(),
        velocity_m_s: vel.into(),
        acceleration_m_s2: [0.0; 3],
        channel,
        health: 0.0,
    }
}

/// Navigation data of 24 satellites of each of GPS, Galileo, BeiDou (MEO) and GLONASS.
fn nav(n_epochs: usize) -> (NavData, Vec<SatId>, Vec<Option<i8>>) {
    let mut nav = NavData::default();
    let (mut sats, mut channels) = (Vec::new(), Vec::new());
    for i in 0..24 {
        let (plane, slot) = (i / 4, i % 4);
        for (system, prn, radius, incl) in [
            (System::Gps, 1 + i as u8, 26_560e3, 55.0),
            (System::Galileo, 1 + i as u8, 29_600e3, 56.0),
            (System::BeiDou, 19 + i as u8, 27_906e3, 55.0),
        ] {
            let s = sat(system, prn);
            nav.kepler.push(kepler(s, radius, incl, plane, slot));
            sats.push(s);
            channels.push(None);
        }
        let s = sat(System::Glonass, 1 + i as u8);
        let channel = (i as i8 % 14) - 7;
        let tb = T0_NS + n_epochs as i64 * 500_000_000;
        nav.glonass.push(glonass(s, i / 8, i % 8, channel, tb));
        sats.push(s);
        channels.push(Some(channel));
    }
    (nav, sats, channels)
}

/// Base antenna: 35.7 N, 139.7 E, 50 m.
fn base_position() -> Vector3<f64> {
    let (lat, lon, h) = (35.7f64.to_radians(), 139.7f64.to_radians(), 50.0);
    let a = 6_378_137.0;
    let e2 = 6.694_379_990_14e-3;
    let n = a / (1.0 - e2 * lat.sin().powi(2)).sqrt();
    Vector3::new(
        (n + h) * lat.cos() * lon.cos(),
        (n + h) * lat.cos() * lon.sin(),
        (n * (1.0 - e2) + h) * lat.sin(),
    )
}

/// ECEF offset of an ENU vector at the base.
fn ecef_offset(enu: [f64; 3]) -> Vector3<f64> {
    let (lat, lon, _) = geodetic_from_ecef(&base_position());
    enu_from_ecef(lat, lon).transpose() * Vector3::from(enu)
}

struct Truth {
    obs: Observations,
    nav: NavData,
    baselines_enu_m: Vec<[f64; 3]>,
}

/// Observations of the base and one rover per `baselines_enu_m` entry over `n` epochs 1 s apart:
/// code noise 0.3 m, phase noise 3 mm (one receiver, white, seed `seed`), no atmosphere.
fn simulate(n: usize, baselines_enu_m: &[[f64; 3]], seed: u64) -> Truth {
    let (nav, sats, glonass_channel) = nav(n);
    let eph = Ephemerides::new(&nav).expect("made-up records are valid");
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut gauss = move |sigma: f64| {
        // Box-Muller.
        let (u1, u2): (f64, f64) = (rng.random::<f64>().max(1e-300), rng.random());
        sigma * (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos()
    };
    let base = base_position();
    let mut positions = vec![base];
    positions.extend(baselines_enu_m.iter().map(|b| base + ecef_offset(*b)));
    let clocks = [4.1e-4, -2.7e-4, 6.3e-4, -8.9e-4];
    let time_gpst_ns: Vec<i64> = (0..n as i64).map(|k| T0_NS + k * 1_000_000_000).collect();
    let ns = sats.len();
    let cells = n * ns * MAX_FREQUENCIES;
    let probe = Observations {
        time_gpst_ns: time_gpst_ns.clone(),
        sats: sats.clone(),
        glonass_channel: glonass_channel.clone(),
        receivers: Vec::new(),
    };
    let mut receivers = Vec::new();
    for (r, pos) in positions.iter().enumerate() {
        let mut rx = ReceiverObservations {
            code_m: vec![f64::NAN; cells],
            phase_cycles: vec![f64::NAN; cells],
            doppler_hz: vec![f64::NAN; cells],
            snr_dbhz: vec![f64::NAN; cells],
            lli: vec![0; cells],
            approx_position_m: None,
        };
        let ambiguities: Vec<f64> = (0..ns * MAX_FREQUENCIES)
            .map(|_| (gauss(1.0) * 1e5).round())
            .collect();
        for (k, &t) in time_gpst_ns.iter().enumerate() {
            let clock = clocks[r] + 1e-9 * k as f64;
            for (s, &id) in sats.iter().enumerate() {
                let Some(g) = satellite_geometry(&eph, id, t, clock, pos) else {
                    continue;
                };
                if g.elevation_rad < 5f64.to_radians() {
                    continue;
                }
                let rho = g.range_m + SPEED_OF_LIGHT_M_S * (clock - g.clock_s);
                for slot in 0..MAX_FREQUENCIES {
                    let Some(f) = probe.frequency_hz(s, slot) else {
                        continue;
                    };
                    let i = probe.index(k, s, slot);
                    let lambda = SPEED_OF_LIGHT_M_S / f;
                    rx.code_m[i] = rho + gauss(0.3);
                    rx.phase_cycles[i] =
                        (rho + gauss(0.003)) / lambda + ambiguities[s * MAX_FREQUENCIES + slot];
                }
            }
        }
        receivers.push(rx);
    }
    Truth {
        obs: Observations { receivers, ..probe },
        nav,
        baselines_enu_m: baselines_enu_m.to_vec(),
    }
}

fn options() -> EngineOptions {
    EngineOptions {
        frequencies: 2,
        method: Method::Lambda,
        ..EngineOptions::default()
    }
}

/// Largest error of the first baseline over fixed epochs, m, and the number of fixed epochs.
fn fixed_error(truth: &Truth, epochs: &[EpochSolution]) -> (f64, usize) {
    let t = Vector3::from(truth.baselines_enu_m[0]);
    let fixed: Vec<f64> = epochs
        .iter()
        .filter(|e| e.fixed)
        .map(|e| (Vector3::from(e.baselines_enu_m[0]) - t).norm())
        .collect();
    (fixed.iter().copied().fold(0.0, f64::max), fixed.len())
}

#[test]
fn single_epoch_fixes_a_one_metre_and_a_three_kilometre_baseline() {
    // Four systems on two frequencies (about 30 satellites) give success rates near 1 on both; an
    // error above 5 cm would be a wrong fix (one L1 cycle is 19 cm), the float noise is centimetres.
    for (baseline, tol) in [([0.6, -0.8, 0.05], 0.01), ([1800.0, -2400.0, 12.0], 0.02)] {
        let truth = simulate(10, &[baseline], 1);
        let sol = run(&truth.obs, &truth.nav, &options()).expect("session solves");
        let (err, fixed) = fixed_error(&truth, &sol.epochs);
        assert_eq!(fixed, 10, "every epoch fixed for {baseline:?}");
        assert!(err < tol, "baseline error {err} m for {baseline:?}");
        assert!(sol.epochs.iter().all(|e| e.satellites() >= 20));
        assert!(sol.epochs.iter().all(|e| e.frequency_slots_used == 0b11));
        // Per system: GPS, GLONASS, Galileo, BeiDou all formed double differences on both slots.
        for sys in [
            System::Gps,
            System::Glonass,
            System::Galileo,
            System::BeiDou,
        ] {
            assert!(sol.double_differences[sys.index()]
                .iter()
                .take(2)
                .all(|&n| n > 0));
        }
        // Angles are those of the ENU baseline.
        let e = &sol.epochs[0];
        let [east, north, _] = e.baselines_enu_m[0];
        let az = east.atan2(north).to_degrees().rem_euclid(360.0);
        assert!((e.angles_deg[0] - az).abs() < 1e-9);
        assert!(e.angle_sigmas_deg.iter().all(|s| s.is_finite() && *s > 0.0));
    }
}

#[test]
fn static_and_moving_agree_and_a_surveyed_base_is_used() {
    let truth = simulate(8, &[[0.6, -0.8, 0.05]], 2);
    let moving = run(&truth.obs, &truth.nav, &options()).unwrap();
    let mut opts = options();
    opts.motion = Motion::Static;
    opts.base_position_m = Some(base_position().into());
    let stat = run(&truth.obs, &truth.nav, &opts).unwrap();
    let (err, fixed) = fixed_error(&truth, &stat.epochs);
    assert_eq!(fixed, 8);
    assert!(err < 0.01, "static error {err} m");
    for (a, b) in moving.epochs.iter().zip(&stat.epochs) {
        let d = Vector3::from(a.baselines_enu_m[0]) - Vector3::from(b.baselines_enu_m[0]);
        assert!(d.norm() < 0.01);
        assert_eq!(b.base_position_m, <[f64; 3]>::from(base_position()));
    }
    assert!(stat.warnings.is_empty(), "{:?}", stat.warnings);
}

#[test]
fn continuity_holds_integers_across_an_undetected_and_a_flagged_slip() {
    let mut truth = simulate(12, &[[0.6, -0.8, 0.05]], 3);
    let ns = truth.obs.n_sats();
    let rover = &mut truth.obs.receivers[1];
    // Two satellites observed throughout: a 5-cycle slip on L1 at epoch 5 flagged by LLI, and a
    // 3-cycle slip on both L1 and L2 at epoch 8 with no flag (the geometry-free combination moves by
    // 3 (lambda1 - lambda2) = 0.16 m).
    let seen: Vec<usize> = (0..ns)
        .filter(|&s| {
            (0..12).all(|k| rover.phase_cycles[(k * ns + s) * MAX_FREQUENCIES].is_finite())
        })
        .collect();
    let (a, b) = (seen[0], seen[1]);
    for k in 5..12 {
        rover.phase_cycles[(k * ns + a) * MAX_FREQUENCIES] += 5.0;
    }
    rover.lli[(5 * ns + a) * MAX_FREQUENCIES] = 1;
    for k in 8..12 {
        for slot in 0..2 {
            rover.phase_cycles[(k * ns + b) * MAX_FREQUENCIES + slot] += 3.0;
        }
    }
    // At epoch 10 a slip no test on one receiver sees: 9 L1 and 7 L2 cycles (1.713 and 1.709 m: the
    // geometry-free combination moves 3 mm, phase minus code 1.7 m); only the held integers' residuals
    // show it.
    let c = seen[2];
    for k in 10..12 {
        rover.phase_cycles[(k * ns + c) * MAX_FREQUENCIES] += 9.0;
        rover.phase_cycles[(k * ns + c) * MAX_FREQUENCIES + 1] += 7.0;
    }
    let mut opts = options();
    opts.continuity = true;
    let sol = run(&truth.obs, &truth.nav, &opts).unwrap();
    let (err, fixed) = fixed_error(&truth, &sol.epochs);
    assert_eq!(fixed, 12);
    assert!(err < 0.01, "error {err} m across the slips");
}

#[test]
fn the_filter_restarts_arcs_at_flagged_detected_and_undetected_slips() {
    // The slips of the continuity test above: a 5-cycle L1 slip flagged by LLI at epoch 5, a 3-cycle slip
    // of L1 and L2 at epoch 8 that the geometry-free test finds, and at epoch 10 one that no test on one
    // receiver sees (9 L1 and 7 L2 cycles), which only the held integers' residuals show.
    let mut truth = simulate(14, &[[0.6, -0.8, 0.05]], 3);
    let ns = truth.obs.n_sats();
    let rover = &mut truth.obs.receivers[1];
    let seen: Vec<usize> = (0..ns)
        .filter(|&s| {
            (0..14).all(|k| rover.phase_cycles[(k * ns + s) * MAX_FREQUENCIES].is_finite())
        })
        .collect();
    let (a, b, c) = (seen[0], seen[1], seen[2]);
    for k in 5..14 {
        rover.phase_cycles[(k * ns + a) * MAX_FREQUENCIES] += 5.0;
    }
    rover.lli[(5 * ns + a) * MAX_FREQUENCIES] = 1;
    for k in 8..14 {
        for slot in 0..2 {
            rover.phase_cycles[(k * ns + b) * MAX_FREQUENCIES + slot] += 3.0;
        }
    }
    for k in 10..14 {
        rover.phase_cycles[(k * ns + c) * MAX_FREQUENCIES] += 9.0;
        rover.phase_cycles[(k * ns + c) * MAX_FREQUENCIES + 1] += 7.0;
    }
    for dynamics in [Dynamics::KINEMATIC, Dynamics::VELOCITY, Dynamics::Static] {
        let mut opts = options();
        opts.filter = Some(dynamics);
        let sol = run(&truth.obs, &truth.nav, &opts).unwrap();
        let (err, fixed) = fixed_error(&truth, &sol.epochs);
        // Every epoch up to the undetected slip fixed; after it the filter restarts arcs and may stay
        // float for a few epochs (docs/observation_engine.md), but fixes nothing wrong.
        assert!(
            sol.epochs[..10]
                .iter()
                .all(|e| e.fix_state == FixState::Fixed),
            "{dynamics:?}"
        );
        assert!(fixed >= 10, "{dynamics:?}");
        assert!(err < 0.01, "{dynamics:?}: error {err} m across the slips");
    }
    // The filter holds its own integers: continuity with it is refused, not ignored.
    let mut opts = options();
    opts.filter = Some(Dynamics::KINEMATIC);
    opts.continuity = true;
    assert!(run(&truth.obs, &truth.nav, &opts).is_err());
}

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
fn ml_agrees_with_lambda_on_a_one_metre_baseline() {
    let truth = simulate(5, &[[0.6, -0.8, 0.05]], 5);
    let lambda = run(&truth.obs, &truth.nav, &options()).unwrap();
    let mut opts = options();
    opts.method = Method::Ml;
    let ml = run(&truth.obs, &truth.nav, &opts).unwrap();
    for (a, b) in lambda.epochs.iter().zip(&ml.epochs) {
        assert_eq!(b.method, Method::Ml);
        assert!(b.solved);
        // The grid's direction from ~8 L1 phases of 3 mm noise on 1 m: a few tenths of a degree.
        let daz = (a.angles_deg[0] - b.angles_deg[0] + 180.0).rem_euclid(360.0) - 180.0;
        assert!(
            daz.abs() < 1.5,
            "azimuth {} vs {}",
            a.angles_deg[0],
            b.angles_deg[0]
        );
        assert!((a.angles_deg[1] - b.angles_deg[1]).abs() < 1.5);
        // And the truth, azimuth 143.13 and elevation 2.86 degrees: one system's ~8 L1 single
        // differences of 4.2 mm give about 0.25 degree (horizontal) and 0.45 degree (vertical) on 1 m;
        // the bounds are 3-4 sigma.
        let truth_az = 0.6f64.atan2(-0.8).to_degrees();
        let truth_el = 0.05f64.atan2(1.0).to_degrees();
        assert!(
            (b.angles_deg[0] - truth_az).abs() < 1.0,
            "{}",
            b.angles_deg[0]
        );
        assert!(
            (b.angles_deg[1] - truth_el).abs() < 1.5,
            "{}",
            b.angles_deg[1]
        );
    }
}

#[test]
fn ml_attitude_of_three_antennas_matches_the_truth() {
    // Heading 30, pitch 5, roll -3 degrees (psi = -30): body X nose, Y up, Z right wing.
    let m = crate::likelihood::dcm_enu_from_body(
        (-30f64).to_radians(),
        5f64.to_radians(),
        (-3f64).to_radians(),
    );
    let body = [[1.2, 0.0, 0.0], [0.0, 0.0, 0.9]];
    let enu: Vec<[f64; 3]> = body
        .iter()
        .map(|b| (m * Vector3::from(*b)).into())
        .collect();
    let truth = simulate(4, &enu, 7);
    let opts = EngineOptions {
        method: Method::Ml,
        body_baselines_m: body.to_vec(),
        ..options()
    };
    let sol = run(&truth.obs, &truth.nav, &opts).unwrap();
    for e in &sol.epochs {
        assert!(e.solved && e.method == Method::Ml);
        let [h, p, r] = [e.angles_deg[0], e.angles_deg[1], e.angles_deg[2]];
        // ~8 single differences of 4.2 mm: about 0.3 degree in heading and 0.5 degree in pitch and
        // roll (vertical components of 1 m baselines); the bounds are 3 sigma.
        assert!((h - 30.0).abs() < 1.0, "heading {h}");
        assert!(
            (p - 5.0).abs() < 1.5 && (r + 3.0).abs() < 1.5,
            "pitch {p} roll {r}"
        );
        let rot = e.rotation_enu_from_body.unwrap();
        assert!((rot[0] - m[(0, 0)]).abs() < 0.02);
    }
}

#[test]
fn bad_sessions_are_errors_or_warnings() {
    let truth = simulate(3, &[[0.6, -0.8, 0.05]], 6);
    // No QZSS satellite observed: no usable signal at all is an error naming what was expected.
    let mut opts = options();
    opts.systems = vec![System::Qzss];
    let err = run(&truth.obs, &truth.nav, &opts).unwrap_err().to_string();
    assert!(err.contains("--systems J"), "{err}");
    // A base position 100 m off the truth: warned once, naming the option.
    let mut opts = options();
    let off = base_position() + Vector3::new(100.0, 0.0, 0.0);
    opts.base_position_m = Some(off.into());
    let sol = run(&truth.obs, &truth.nav, &opts).unwrap();
    assert_eq!(
        sol.warnings
            .iter()
            .filter(|w| w.contains("--base-position"))
            .count(),
        1
    );
    // No Galileo ephemeris: warned.
    let mut nav = truth.nav.clone();
    nav.kepler.retain(|r| r.sat.system != System::Galileo);
    let sol = run(&truth.obs, &nav, &options()).unwrap();
    assert!(sol
        .warnings
        .iter()
        .any(|w| w.contains("--systems includes E")));
    // Mismatched engine and observations.
    let mut engine = Engine::new(
        &truth.nav,
        options(),
        truth.obs.sats[1..].to_vec(),
        truth.obs.glonass_channel[1..].to_vec(),
        2,
    )
    .unwrap();
    assert!(engine.process(&truth.obs).is_err());
    assert!(Engine::new(&truth.nav, options(), truth.obs.sats.clone(), vec![], 2).is_err());
}

#[test]
fn lambda_attitude_of_three_antennas_matches_the_truth() {
    // Heading 200, pitch -4, roll 6 degrees; fixed baselines of 1-2 m give the angles to a few
    // hundredths of a degree, so 0.2 degree would already be a wrong fix.
    let m = crate::likelihood::dcm_enu_from_body(
        (-200f64).to_radians(),
        (-4f64).to_radians(),
        6f64.to_radians(),
    );
    let body = [[2.0, 0.1, 0.0], [0.3, 0.0, -1.5]];
    let enu: Vec<[f64; 3]> = body
        .iter()
        .map(|b| (m * Vector3::from(*b)).into())
        .collect();
    let truth = simulate(6, &enu, 8);
    let opts = EngineOptions {
        body_baselines_m: body.to_vec(),
        ..options()
    };
    let sol = run(&truth.obs, &truth.nav, &opts).unwrap();
    for e in &sol.epochs {
        // The constrained acceptance is rtk's (ratio of the two best combined objectives): not
        // asserted here; a fixed epoch must be right and every epoch close.
        assert!(e.solved && e.method == Method::Lambda);
        let [h, p, r] = [e.angles_deg[0], e.angles_deg[1], e.angles_deg[2]];
        assert!(
            (h - 200.0).abs() < 0.2 && (p + 4.0).abs() < 0.2 && (r - 6.0).abs() < 0.2,
            "{h} {p} {r}"
        );
        // The sigmas are those of baselines of a few millimetres (the engine's elevation-weighted
        // sigmas, larger than the simulated 3 mm) over 1.5-2 m: tenths of a degree at most.
        let bound = if e.fixed { 0.5 } else { 5.0 };
        assert!(
            e.angle_sigmas_deg.iter().all(|s| *s > 1e-4 && *s < bound),
            "{:?}",
            e.angle_sigmas_deg
        );
        for (b, t) in e.baselines_enu_m.iter().zip(&enu) {
            assert!((Vector3::from(*b) - Vector3::from(*t)).norm() < 0.01);
        }
    }
}

#[test]
fn auto_keeps_the_integer_fix_and_falls_back_to_the_grid_when_the_gate_refuses() {
    // With four systems on two slots every epoch is fixed and Auto is Lambda.
    let mut truth = simulate(8, &[[0.6, -0.8, 0.05]], 9);
    let auto = EngineOptions {
        method: Method::Auto,
        ..options()
    };
    let all = run(&truth.obs, &truth.nav, &auto).unwrap();
    assert!(all
        .epochs
        .iter()
        .all(|e| e.fixed && e.method == Method::Lambda));
    // GPS alone, L1 + L2 for three epochs, then L1 alone (L2 lost at the rover), with a strict gate:
    // no epoch is fully fixed, the partially fixed L1 + L2 epochs give the length to a millimetre,
    // and every epoch goes to the grid with it.
    let ns = truth.obs.n_sats();
    for k in 3..8 {
        for s in 0..ns {
            truth.obs.receivers[1].phase_cycles[(k * ns + s) * MAX_FREQUENCIES + 1] = f64::NAN;
        }
    }
    let gps = EngineOptions {
        systems: vec![System::Gps],
        min_success_rate: 0.99999,
        ..auto
    };
    let sol = run(&truth.obs, &truth.nav, &gps).unwrap();
    let az = 0.6f64.atan2(-0.8).to_degrees();
    for e in &sol.epochs {
        assert!(e.solved);
        assert_eq!(e.method, if e.fixed { Method::Lambda } else { Method::Ml });
        // 8 L1 single differences on 1 m: 0.25 degree of azimuth noise; 1 degree is 4 sigma.
        assert!((e.angles_deg[0] - az).abs() < 1.0, "{}", e.angles_deg[0]);
    }
    assert!(sol.epochs.iter().any(|e| e.method == Method::Ml));
}

#[test]
fn fix_rate_and_no_wrong_fix_over_a_minute_of_gps_l1_l2() {
    // GPS alone on L1 + L2, 60 single epochs on 1 m: the gate at 0.999 allows one wrong fix per
    // thousand fixed epochs in expectation, so none is expected here; an error above 5 cm is wrong.
    let truth = simulate(60, &[[0.6, -0.8, 0.05]], 10);
    let opts = EngineOptions {
        systems: vec![System::Gps],
        ..options()
    };
    let sol = run(&truth.obs, &truth.nav, &opts).unwrap();
    let t = Vector3::from(truth.baselines_enu_m[0]);
    let errors: Vec<f64> = sol
        .epochs
        .iter()
        .filter(|e| e.fixed)
        .map(|e| (Vector3::from(e.baselines_enu_m[0]) - t).norm())
        .collect();
    assert!(errors.len() >= 57, "fixed {} of 60", errors.len());
    assert!(errors.iter().all(|&e| e < 0.05), "{errors:?}");
    assert!(sol.epochs.iter().all(|e| e.satellites_per_system[0] >= 6));
}

#[test]
fn ml_without_a_known_length_keeps_the_double_difference_solution() {
    // GPS L1 alone with a gate nothing passes: each float length has decimetres of sigma on 1 m, far from
    // the 1 % the grid needs, so the grid is not run and a warning says why.
    let truth = simulate(3, &[[0.6, -0.8, 0.05]], 11);
    let opts = EngineOptions {
        systems: vec![System::Gps],
        frequencies: 1,
        method: Method::Ml,
        min_success_rate: 0.99999,
        ..EngineOptions::default()
    };
    let sol = run(&truth.obs, &truth.nav, &opts).unwrap();
    assert!(sol
        .epochs
        .iter()
        .all(|e| e.solved && !e.fixed && e.method == Method::Lambda));
    assert!(
        sol.warnings
            .iter()
            .any(|w| w.contains("needs the baseline length")),
        "{:?}",
        sol.warnings
    );
}

#[test]
fn the_code_noise_scale_recovers_the_simulated_noise() {
    // The simulation draws code noise of 0.3 m per receiver; a model of 0.15 m at every elevation is half
    // of it, so the estimated sigma scale is 2 (its relative standard error sqrt(1 / (2 dof)) is about 2 %
    // with the few hundred residual degrees of freedom of 20 epochs: 0.15 is over 3 sigma).
    let truth = simulate(20, &[[0.6, -0.8, 0.05]], 13);
    let opts = EngineOptions {
        code_sigma: crate::gnss::options::ElevationSigma {
            a_m: 0.15,
            b_m: 0.0,
        },
        ..options()
    };
    let sol = run(&truth.obs, &truth.nav, &opts).unwrap();
    let scale = sol.code_sigma_scale[0];
    assert!((scale - 2.0).abs() < 0.15, "{scale}");
    // Static mode estimates nothing.
    let stat = run(
        &truth.obs,
        &truth.nav,
        &EngineOptions {
            motion: Motion::Static,
            ..opts
        },
    )
    .unwrap();
    assert!(stat.code_sigma_scale[0].is_nan());
}

#[test]
fn a_session_gates_its_first_epochs_with_the_calibrated_code_noise() {
    // Receivers twice as noisy as a model of 0.15 m (as above): a streaming engine gates its first epoch
    // with the model's variances, a quarter of the truth, and overstates its success rate; the session
    // calibrates on its first epochs before solving any, so its first epoch is gated as the later ones.
    let truth = simulate(6, &[[0.6, -0.8, 0.05]], 13);
    let opts = EngineOptions {
        code_sigma: crate::gnss::options::ElevationSigma {
            a_m: 0.15,
            b_m: 0.0,
        },
        frequencies: 1,
        ..options()
    };
    let session = run(&truth.obs, &truth.nav, &opts).unwrap();
    let mut engine = Engine::new(
        &truth.nav,
        opts.clone(),
        truth.obs.sats.clone(),
        truth.obs.glonass_channel.clone(),
        2,
    )
    .unwrap();
    let streamed = engine.process(&truth.obs).unwrap();
    let (first_session, first_streamed) = (&session.epochs[0], &streamed[0]);
    assert!(first_session.solved && first_streamed.solved);
    assert!(
        first_session.success_rate < first_streamed.success_rate,
        "{} vs {}",
        first_session.success_rate,
        first_streamed.success_rate
    );
    // Both end with the same estimate of the noise (2, the simulated over the model's sigma), the
    // session's counting its first epochs twice (in the calibration and in the run): within 2.5 %, about
    // the estimate's own standard error with these few hundred degrees of freedom.
    let (s, e) = (session.code_sigma_scale[0], engine.code_sigma_scale()[0]);
    assert!(
        (s - e).abs() < 0.025 * e && (e - 2.0).abs() < 0.15,
        "{s} vs {e}"
    );
    let (err, _) = fixed_error(&truth, &session.epochs);
    assert!(err < 0.05, "a wrong fix: {err} m");
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
fn a_known_length_gives_the_grid_its_length_at_once_and_is_checked() {
    // As above (GPS L1, a gate nothing passes), with the length given: the grid runs from the first epoch
    // and returns the baseline at that length, within the grid's direction error (a few degrees: 5 cm).
    let b = [0.6, -0.8, 0.05];
    let truth = simulate(3, &[b], 11);
    let length = Vector3::from(b).norm();
    let opts = EngineOptions {
        systems: vec![System::Gps],
        frequencies: 1,
        method: Method::Ml,
        min_success_rate: 0.99999,
        baseline_lengths_m: vec![length],
        ..EngineOptions::default()
    };
    let sol = run(&truth.obs, &truth.nav, &opts).unwrap();
    for e in &sol.epochs {
        assert!(e.solved && e.method == Method::Ml, "{e:?}");
        let got = Vector3::from(e.baselines_enu_m[0]);
        assert!((got.norm() - length).abs() < 1e-9);
        assert!((got - Vector3::from(b)).norm() < 0.05, "{got}");
    }
    // One length per rover, and not with body baselines.
    let two = EngineOptions {
        baseline_lengths_m: vec![1.0, 2.0],
        ..options()
    };
    let e = Engine::new(
        &truth.nav,
        two,
        truth.obs.sats.clone(),
        truth.obs.glonass_channel.clone(),
        2,
    );
    assert!(matches!(
        e,
        Err(Error::OutOfRange {
            name: "--baseline-length",
            ..
        })
    ));
    let both = EngineOptions {
        baseline_lengths_m: vec![1.0],
        body_baselines_m: vec![[1.0, 0.0, 0.0]],
        ..options()
    };
    assert!(matches!(
        both.validate(),
        Err(Error::OutOfRange {
            name: "--baseline-length",
            ..
        })
    ));
    let short = EngineOptions {
        baseline_lengths_m: vec![0.001],
        ..options()
    };
    assert!(matches!(
        short.validate(),
        Err(Error::OutOfRange {
            name: "--baseline-length",
            ..
        })
    ));
}

#[test]
fn options_that_would_be_ignored_are_refused() {
    // Attitude mode has no static session (one set of integers for a moving array is meaningless): refused
    // by name, not ignored. Holding integers along arcs (continuity) is attitude mode's too.
    let body = vec![[1.0, 0.0, 0.0]];
    let e = EngineOptions {
        motion: Motion::Static,
        body_baselines_m: body.clone(),
        ..options()
    }
    .validate()
    .unwrap_err()
    .to_string();
    assert!(e.contains("--motion") && e.contains("attitude mode"), "{e}");
    EngineOptions {
        continuity: true,
        motion: Motion::Moving,
        body_baselines_m: body,
        ..options()
    }
    .validate()
    .unwrap();
    // Continuity is moving mode's; a static session has one set of integers already.
    let moving = EngineOptions {
        continuity: true,
        motion: Motion::Moving,
        ..options()
    };
    moving.validate().unwrap();
    let e = EngineOptions {
        motion: Motion::Static,
        ..moving
    }
    .validate()
    .unwrap_err()
    .to_string();
    assert!(e.contains("--continuity") && e.contains("static"), "{e}");
}

#[test]
fn single_epochs_in_parallel_are_those_of_one_epoch_at_a_time() {
    // More epochs than a block of `parallel::BLOCK`, two rovers, and the three regimes of the code noise
    // scale: the model about right (the factor moves every epoch once it stands), the model five times
    // the noise (the factor clamped at its floor, where the float solutions are computed ahead), and a
    // known length (its own range). The engine starts uncalibrated (no `run`), so each regime also
    // passes the epoch where the estimate starts to stand. One epoch per call on one thread is the
    // epoch-by-epoch engine; the whole session on four threads must give it bit for bit.
    let n = super::parallel::BLOCK + 9;
    let truth = simulate(n, &[[0.6, -0.8, 0.05], [2.0, 1.0, -0.1]], 21);
    let loud = crate::gnss::options::ElevationSigma { a_m: 1.5, b_m: 1.5 };
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
