//! A synthetic session with a known truth: a made-up constellation (GPS, GLONASS, Galileo, BeiDou
//! broadcast records of near-circular orbits), observations computed from the engine's own orbit model
//! ([`Ephemerides::state`] through [`satellite_geometry`]) for antennas at known baselines, millisecond
//! receiver clocks, random integer ambiguities, white code and phase noise from a fixed seed, and slips.
//! The truth the tests check against is the baselines put in, which nothing in the engine sees.

use nalgebra::Vector3;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use crate::gnss::ephemeris::Ephemerides;
use crate::gnss::geometry::satellite_geometry;
use crate::gnss::geometry::{enu_from_ecef, geodetic_from_ecef};
use crate::gnss::navdata::{GlonassRecord, KeplerRecord, NavData};
use crate::gnss::observations::{Observations, ReceiverObservations};
use crate::gnss::options::{EngineOptions, Method};
use crate::gnss::signal::{SatId, System, MAX_FREQUENCIES, SPEED_OF_LIGHT_M_S};
use crate::gnss::solution::EpochSolution;

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
pub(super) fn base_position() -> Vector3<f64> {
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

pub(super) struct Truth {
    pub(super) obs: Observations,
    pub(super) nav: NavData,
    pub(super) baselines_enu_m: Vec<[f64; 3]>,
}

/// Observations of the base and one rover per `baselines_enu_m` entry over `n` epochs 1 s apart:
/// code noise 0.3 m, phase noise 3 mm (one receiver, white, seed `seed`), no atmosphere.
pub(super) fn simulate(n: usize, baselines_enu_m: &[[f64; 3]], seed: u64) -> Truth {
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

pub(super) fn options() -> EngineOptions {
    EngineOptions {
        frequencies: 2,
        method: Method::Lambda,
        ..EngineOptions::default()
    }
}

/// Largest error of the first baseline over fixed epochs, m, and the number of fixed epochs.
pub(super) fn fixed_error(truth: &Truth, epochs: &[EpochSolution]) -> (f64, usize) {
    let t = Vector3::from(truth.baselines_enu_m[0]);
    let fixed: Vec<f64> = epochs
        .iter()
        .filter(|e| e.fixed)
        .map(|e| (Vector3::from(e.baselines_enu_m[0]) - t).norm())
        .collect();
    (fixed.iter().copied().fold(0.0, f64::max), fixed.len())
}
