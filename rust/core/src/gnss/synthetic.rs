//! Synthetic sessions with a known truth, for benchmarks and tests: 24 satellites each of GPS, Galileo
//! and BeiDou (MEO) on circular broadcast orbits (six planes of four, 55 degrees), three frequencies,
//! antennas at given East-North-Up offsets from a base at 35.7 N 139.7 E, millisecond receiver clocks,
//! random integer ambiguities, white code (0.3 m) and phase (3 mm) noise from a fixed seed and the
//! standard troposphere ([`crate::gnss::atmosphere::troposphere_delay_at_m`]), no ionosphere. The
//! observations are computed with the engine's own orbit model ([`satellite_geometry`]); the truth a
//! caller checks against is the offsets put in.

use nalgebra::Vector3;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use super::atmosphere::troposphere_delay_at_m;
use super::ephemeris::Ephemerides;
use super::geometry::{enu_from_ecef, geodetic_from_ecef, satellite_geometry};
use super::navdata::{KeplerRecord, NavData};
use super::observations::{Observations, ReceiverObservations};
use super::signal::{SatId, System, MAX_FREQUENCIES, SPEED_OF_LIGHT_M_S};

/// First epoch: GPS week 2300, Monday 01:00 (GPST ns).
pub const T0_GPST_NS: i64 = (2300 * 604_800 + 86_400 + 3600) * 1_000_000_000;
/// Satellites below this elevation at an antenna are not observed by it, rad.
const TRACKING_MASK_RAD: f64 = 5.0 * std::f64::consts::PI / 180.0;
/// Receiver clocks of the antennas in turn (repeated beyond four), s.
const CLOCKS_S: [f64; 4] = [4.1e-4, -2.7e-4, 6.3e-4, -8.9e-4];

/// A synthetic session: its observations, navigation data and the base's position.
pub struct Session {
    pub obs: Observations,
    pub nav: NavData,
    /// The base (receiver 0), ECEF m.
    pub base_m: [f64; 3],
}

/// A circular-orbit broadcast record: plane `plane` of six, `slot` of four along it.
fn circular(sat: SatId, radius_m: f64, plane: usize, slot: usize) -> KeplerRecord {
    let gps = sat.system == System::Gps;
    KeplerRecord {
        sat,
        toc_gpst_ns: T0_GPST_NS,
        toe_gpst_ns: T0_GPST_NS,
        af: [1e-5 * (slot as f64 - 1.5), 1e-12, 0.0],
        crs: 0.0,
        delta_n: 0.0,
        m0: (slot as f64 * 90.0 + plane as f64 * 15.0).to_radians(),
        cuc: 0.0,
        e: 0.0,
        cus: 0.0,
        sqrt_a: radius_m.sqrt(),
        cic: 0.0,
        omega0: (plane as f64 * 60.0).to_radians(),
        cis: 0.0,
        i0: 55f64.to_radians(),
        crc: 0.0,
        omega: 0.0,
        omega_dot: 0.0,
        idot: 0.0,
        health: 0.0,
        tgd_s: [0.0, if gps { f64::NAN } else { 0.0 }],
        iode: 1.0,
        accuracy_m: 2.0,
        fit_interval_h: if gps { 4.0 } else { f64::NAN },
        data_source: if sat.system == System::Galileo {
            517.0
        } else {
            f64::NAN
        },
    }
}

/// `n_epochs` epochs 1 s apart of the base and one antenna per `offsets_enu_m` entry (module
/// documentation), noise from `seed`.
pub fn session(n_epochs: usize, offsets_enu_m: &[[f64; 3]], seed: u64) -> Session {
    let (nav, sats) = constellation();
    let eph = Ephemerides::new(&nav).expect("circular records are valid");
    let (lat, lon, h) = (35.7f64.to_radians(), 139.7f64.to_radians(), 50.0);
    let base = ecef_from_geodetic_m(lat, lon, h);
    let (glat, _, gh) = geodetic_from_ecef(&base);
    let ecef_from_enu = enu_from_ecef(lat, lon).transpose();
    let mut positions = vec![base];
    positions.extend(
        offsets_enu_m
            .iter()
            .map(|o| base + ecef_from_enu * Vector3::from(*o)),
    );
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut obs = Observations {
        time_gpst_ns: (0..n_epochs as i64)
            .map(|k| T0_GPST_NS + k * 1_000_000_000)
            .collect(),
        glonass_channel: vec![None; sats.len()],
        sats,
        receivers: Vec::new(),
    };
    // The receivers in turn draw from one generator: each its ambiguities, then its noise.
    for (r, pos) in positions.iter().enumerate() {
        let clock_s = CLOCKS_S[r % CLOCKS_S.len()];
        let rx = receiver(&obs, &eph, pos, clock_s, (glat, gh), &mut rng);
        obs.receivers.push(rx);
    }
    Session {
        obs,
        nav,
        base_m: base.into(),
    }
}

/// The broadcast records of the 24 satellites each of GPS, Galileo and BeiDou, and the satellites in
/// the order of the observations.
fn constellation() -> (NavData, Vec<SatId>) {
    let mut nav = NavData::default();
    let mut sats = Vec::new();
    for i in 0..24 {
        for (system, prn, radius_m) in [
            (System::Gps, 1 + i as u8, 26_560e3),
            (System::Galileo, 1 + i as u8, 29_600e3),
            (System::BeiDou, 19 + i as u8, 27_906e3),
        ] {
            let sat = SatId { system, prn };
            nav.kepler.push(circular(sat, radius_m, i / 4, i % 4));
            sats.push(sat);
        }
    }
    (nav, sats)
}

/// ECEF position (m) of WGS 84 geodetic latitude and longitude `lat`, `lon` (rad) and height `h` (m).
fn ecef_from_geodetic_m(lat: f64, lon: f64, h: f64) -> Vector3<f64> {
    let (a, e2) = (6_378_137.0, 6.694_379_990_14e-3);
    let nu = a / (1.0 - e2 * lat.sin().powi(2)).sqrt();
    Vector3::new(
        (nu + h) * lat.cos() * lon.cos(),
        (nu + h) * lat.cos() * lon.sin(),
        (nu * (1.0 - e2) + h) * lat.sin(),
    )
}

/// A Gaussian draw of standard deviation `sigma` (Box-Muller, one uniform pair per draw).
fn gauss(rng: &mut ChaCha8Rng, sigma: f64) -> f64 {
    let (u1, u2): (f64, f64) = (rng.random::<f64>().max(1e-300), rng.random());
    sigma * (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos()
}

/// The observations of the antenna at `pos` (ECEF m, clock `clock_s` s) for every epoch and signal of
/// `obs` the satellite is above the tracking mask; `site` is the base's geodetic latitude (rad) and
/// height (m) for the troposphere.
fn receiver(
    obs: &Observations,
    eph: &Ephemerides,
    pos: &Vector3<f64>,
    clock_s: f64,
    (glat, gh): (f64, f64),
    rng: &mut ChaCha8Rng,
) -> ReceiverObservations {
    let n_epochs = obs.time_gpst_ns.len();
    let mut rx = ReceiverObservations::absent(n_epochs, obs.n_sats(), Some((*pos).into()));
    let ambiguities: Vec<f64> = (0..obs.n_sats() * MAX_FREQUENCIES)
        .map(|_| (gauss(rng, 1.0) * 1e5).round())
        .collect();
    for k in 0..n_epochs {
        let t = obs.time_gpst_ns[k];
        for (s, &id) in obs.sats.iter().enumerate() {
            let Some(g) = satellite_geometry(eph, id, t, clock_s, pos) else {
                continue;
            };
            if g.elevation_rad < TRACKING_MASK_RAD {
                continue;
            }
            let rho_m = g.range_m
                + SPEED_OF_LIGHT_M_S * (clock_s - g.clock_s)
                + troposphere_delay_at_m(glat, gh, g.elevation_rad, t);
            for slot in 0..MAX_FREQUENCIES {
                let Some(f) = obs.frequency_hz(s, slot) else {
                    continue;
                };
                let i = obs.index(k, s, slot);
                rx.code_m[i] = rho_m + gauss(rng, 0.3);
                rx.phase_cycles[i] = (rho_m + gauss(rng, 0.003)) * f / SPEED_OF_LIGHT_M_S
                    + ambiguities[s * MAX_FREQUENCIES + slot];
            }
        }
    }
    rx
}
