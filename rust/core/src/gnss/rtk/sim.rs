//! Synthetic double-difference epochs with a known truth, for the tests: satellites in random directions
//! above the mask at their system's orbit radius, receivers with random clocks, integer ambiguities and
//! Gaussian noise drawn with the sigmas the model is given (elevation-weighted).

use std::collections::HashMap;

use nalgebra::{Matrix3, Vector3};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use super::enu_at;
use super::{DdEpoch, SignalPair};
use crate::gnss::atmosphere::troposphere_delay_m;
use crate::gnss::geometry::{geodetic_from_ecef, SatGeometry};
use crate::gnss::signal::{carrier_frequency_hz, System, SPEED_OF_LIGHT_M_S};

/// Orbit radius of each system's MEO satellites, m.
fn orbit_radius_m(system: System) -> f64 {
    match system {
        System::Gps | System::Qzss => 26_560e3,
        System::Glonass => 25_510e3,
        System::Galileo => 29_600e3,
        System::BeiDou => 27_906e3,
    }
}

/// A satellite of the scenario.
#[derive(Debug, Clone)]
pub struct Sat {
    pub index: usize,
    pub system: System,
    pub channel: Option<i8>,
    pub position0_m: Vector3<f64>,
    pub velocity_m_s: Vector3<f64>,
    pub clock_s: f64,
    /// Ambiguities per slot at base and rover, cycles.
    pub n_base: [i64; 3],
    pub n_rover: [i64; 3],
}

/// A scenario: base, satellites, slots per system, noise.
pub struct Scenario {
    pub rng: ChaCha8Rng,
    pub base_m: Vector3<f64>,
    pub sats: Vec<Sat>,
    pub slots: HashMap<System, Vec<usize>>,
    /// Phase and code sigma models `a + b / sin(el)` (one receiver), m.
    pub phase_ab: (f64, f64),
    pub code_ab: (f64, f64),
    /// Standard deviation of the rover prior's error per axis, m.
    pub prior_sigma_m: f64,
}

pub fn normal(rng: &mut ChaCha8Rng) -> f64 {
    // Box-Muller from two uniforms in (0, 1].
    let u1: f64 = 1.0 - rng.random::<f64>();
    let u2: f64 = rng.random::<f64>();
    (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos()
}

/// Geodetic (deg, deg, m) to ECEF on WGS-84.
pub fn ecef(lat_deg: f64, lon_deg: f64, h: f64) -> Vector3<f64> {
    let (lat, lon) = (lat_deg.to_radians(), lon_deg.to_radians());
    let e2 = 6.694_379_990_141_316e-3;
    let n = 6_378_137.0 / (1.0 - e2 * lat.sin().powi(2)).sqrt();
    Vector3::new(
        (n + h) * lat.cos() * lon.cos(),
        (n + h) * lat.cos() * lon.sin(),
        (n * (1.0 - e2) + h) * lat.sin(),
    )
}

impl Scenario {
    /// `counts`: satellites per system; `slots`: slots observed per system; directions uniform in
    /// azimuth and in sin(elevation) above `mask_deg`.
    pub fn new(seed: u64, counts: &[(System, usize, &[usize])], mask_deg: f64) -> Scenario {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let base_m = ecef(35.7, 139.5, 60.0);
        let to_ecef = enu_at(&base_m).transpose();
        let mut sats = Vec::new();
        let mut slots = HashMap::new();
        let mut channels: Vec<i8> = (-7..=6).collect();
        for &(system, n, sl) in counts {
            slots.insert(system, sl.to_vec());
            for _ in 0..n {
                let az = rng.random::<f64>() * std::f64::consts::TAU;
                let smin = mask_deg.to_radians().sin();
                let el = (smin + (1.0 - smin) * rng.random::<f64>()).asin();
                let u = to_ecef * Vector3::new(el.cos() * az.sin(), el.cos() * az.cos(), el.sin());
                let r = orbit_radius_m(system);
                let bu = base_m.dot(&u);
                let rho = -bu + (bu * bu - base_m.norm_squared() + r * r).sqrt();
                let pos = base_m + rho * u;
                // Velocity of a circular orbit, in a random direction perpendicular to the radius.
                let w = Vector3::new(normal(&mut rng), normal(&mut rng), normal(&mut rng));
                let radial = pos.normalize();
                let along = (w - radial * radial.dot(&w)).normalize();
                let channel = (system == System::Glonass).then(|| {
                    let k = rng.random_range(0..channels.len());
                    channels.swap_remove(k)
                });
                let mut amb = || rng.random_range(-5_000_000i64..5_000_000);
                let n_base = [amb(), amb(), amb()];
                let n_rover = [amb(), amb(), amb()];
                sats.push(Sat {
                    index: sats.len(),
                    system,
                    channel,
                    position0_m: pos,
                    velocity_m_s: along * (3.986e14 / r).sqrt(),
                    clock_s: (rng.random::<f64>() - 0.5) * 2e-4,
                    n_base,
                    n_rover,
                });
            }
        }
        Scenario {
            rng,
            base_m,
            sats,
            slots,
            phase_ab: (0.003, 0.003),
            code_ab: (0.3, 0.3),
            prior_sigma_m: 2.0,
        }
    }

    /// Wavelength of `slot` of satellite `s`, m.
    pub fn wavelength(s: &Sat, slot: usize) -> f64 {
        SPEED_OF_LIGHT_M_S / carrier_frequency_hz(s.system, slot, s.channel).unwrap_or(f64::NAN)
    }

    /// True DD integer of (arc of `k`, arc of `r`) in `slot` (see [`Scenario::arc`]).
    pub fn dd_integer(&self, k: usize, r: usize, slot: usize) -> i64 {
        let sd = |s: &Sat| s.n_rover[slot] - s.n_base[slot];
        sd(&self.sats[k]) - sd(&self.sats[r])
    }

    /// Arc identity of satellite `sat`, `slot` (no slips in the scenarios).
    pub fn arc(sat: usize, slot: usize) -> u64 {
        (sat * 3 + slot) as u64
    }

    /// The satellite and slot of an arc.
    pub fn of_arc(arc: u64) -> (usize, usize) {
        ((arc / 3) as usize, (arc % 3) as usize)
    }

    /// One epoch at time `t_s` (satellites moved linearly) with the rover at `base + baseline`.
    pub fn epoch(&mut self, baseline_m: &Vector3<f64>, t_s: f64) -> DdEpoch {
        let base = self.base_m;
        let rover = base + baseline_m;
        let clock_b = (self.rng.random::<f64>() - 0.5) * 2e-3;
        let clock_r = (self.rng.random::<f64>() - 0.5) * 2e-3;
        let up = enu_at(&base).row(2).transpose();
        let mut signals = Vec::new();
        let sats = self.sats.clone();
        for s in &sats {
            let pos = s.position0_m + s.velocity_m_s * t_s;
            let el = (pos - base).normalize().dot(&up).asin();
            if el < 0.0 {
                continue;
            }
            let Some(slots) = self.slots.get(&s.system).cloned() else {
                continue;
            };
            for slot in slots {
                let lam = Self::wavelength(s, slot);
                let sp = (self.phase_ab.0.powi(2) + (self.phase_ab.1 / el.sin()).powi(2)).sqrt();
                let sc = (self.code_ab.0.powi(2) + (self.code_ab.1 / el.sin()).powi(2)).sqrt();
                // The standard atmosphere at each antenna's own height (the engine models it: rtk::model).
                let obs = |rx: &Vector3<f64>, clock: f64| {
                    let (lat, _, h) = geodetic_from_ecef(rx);
                    (pos - rx).norm() - SPEED_OF_LIGHT_M_S * (s.clock_s - clock)
                        + troposphere_delay_m(lat, h, el)
                };
                let (rb, rr) = (obs(&base, clock_b), obs(&rover, clock_r));
                let rng = &mut self.rng;
                let geometry = |rx: &Vector3<f64>| SatGeometry {
                    position_m: pos,
                    clock_s: s.clock_s,
                    range_m: (pos - rx).norm(),
                    los_ecef: (pos - rx).normalize(),
                    elevation_rad: el,
                    azimuth_rad: 0.0,
                };
                signals.push(SignalPair {
                    sat: s.index,
                    system: s.system,
                    slot,
                    wavelength_m: lam,
                    base: geometry(&base),
                    rover: geometry(&rover),
                    base_code_m: rb + sc * normal(rng),
                    rover_code_m: rr + sc * normal(rng),
                    base_phase_cycles: (rb + sp * normal(rng)) / lam + s.n_base[slot] as f64,
                    rover_phase_cycles: (rr + sp * normal(rng)) / lam + s.n_rover[slot] as f64,
                    sigma_code_m: sc,
                    sigma_phase_m: sp,
                    arc: Self::arc(s.index, slot),
                });
            }
        }
        let prior = Vector3::new(
            normal(&mut self.rng),
            normal(&mut self.rng),
            normal(&mut self.rng),
        ) * self.prior_sigma_m;
        DdEpoch {
            base_m: base,
            rover_prior_m: rover + prior,
            signals,
        }
    }

    /// A random baseline of length `length_m` (uniform direction).
    pub fn random_baseline(&mut self, length_m: f64) -> Vector3<f64> {
        let v = Vector3::new(
            normal(&mut self.rng),
            normal(&mut self.rng),
            normal(&mut self.rng),
        );
        v.normalize() * length_m
    }
}

/// A uniformly random rotation (unit quaternion from four normals).
pub fn random_rotation(rng: &mut ChaCha8Rng) -> Matrix3<f64> {
    let q = nalgebra::Quaternion::new(normal(rng), normal(rng), normal(rng), normal(rng));
    nalgebra::UnitQuaternion::from_quaternion(q)
        .to_rotation_matrix()
        .into_inner()
}
