//! Single-point positioning: one receiver's position and one clock per system at one epoch from its
//! pseudoranges, by weighted, iterated least squares.
//!
//! Model of the code of satellite k: `P = |r_k(t_tx) - x| + c (dt_sys - dt_k - gd_k) + I_k + T_k`,
//! with the transmit-time position in the ECEF frame of reception
//! ([`super::geometry::satellite_geometry`]), the broadcast clock `dt_k` and group delay `gd_k` of the
//! slot used ([`Ephemerides::group_delay_s`]), the Klobuchar ionosphere `I_k` scaled to the slot's
//! frequency and the standard troposphere `T_k` ([`crate::gnss::atmosphere`]). Each satellite contributes the code of its lowest frequency slot
//! among those used (`opts.frequencies`); weights are `1 / sigma^2` of [`code_variance_m2`]. The
//! elevation mask applies once the position is known (after the first iteration, or from a prior).
//! Residual check: where the residual RMS exceeds [`MAX_RESIDUAL_RMS_M`] and the satellites
//! over-determine the solution by two or more, the one satellite whose exclusion leaves the smallest
//! RMS is dropped (once).

use nalgebra::{DMatrix, DVector, Vector3};

use super::atmosphere::{day_of_year, klobuchar_delay_m, niell_mapping, troposphere_delay_at_m};
use super::ephemeris::Ephemerides;
use super::geometry::{satellite_geometry_from, SatGeometry, Site, MIN_HORIZON_RADIUS_M};
use super::navdata::NavData;
use super::observations::Observations;
use super::options::EngineOptions;
use super::signal::{carrier_frequency_hz, MAX_FREQUENCIES, SPEED_OF_LIGHT_M_S};
use super::solution::N_SYSTEMS;
use super::weights::code_variance_m2;
use crate::error::{Error, Result};

/// Most least-squares iterations of one solution (from the Earth's centre, 5 to 7 reach 1e-4 m).
pub const MAX_ITERATIONS: usize = 20;
/// Position step below which the iteration has converged, m.
pub const CONVERGED_STEP_M: f64 = 1e-4;
/// Residual RMS above which one satellite is dropped, m (single-frequency code with broadcast
/// corrections leaves 1-5 m): the one whose exclusion leaves the smallest RMS (one solution per
/// satellite used, only at such epochs; a blunder can hide in the residuals of others, so the
/// largest residual does not always mark it).
pub const MAX_RESIDUAL_RMS_M: f64 = 10.0;
/// Largest condition number of the normal matrix accepted.
pub const MAX_CONDITION: f64 = 1e12;
/// Pseudoranges outside this interval are not ranges to a navigation satellite (with a receiver clock
/// within +-1e6 m, i.e. 3 ms), m.
pub const PSEUDORANGE_RANGE_M: (f64, f64) = (1.0e6, 1.0e8);

/// Code solution of one receiver at one epoch.
#[derive(Debug, Clone, PartialEq)]
pub struct SppSolution {
    /// ECEF, m.
    pub position_m: Vector3<f64>,
    /// Receiver clock per system ([`crate::gnss::signal::System::index`]), s: true reception = label - clock; NaN where the
    /// system was not estimated.
    pub clock_s: [f64; 5],
    /// Satellites used.
    pub satellites: usize,
    /// Satellites used per system ([`crate::gnss::signal::System::index`]).
    pub satellites_per_system: [usize; N_SYSTEMS],
    /// Position dilution of precision of the satellites used: `sqrt(trace)` of the position block of
    /// `(G^T G)^-1`, G the unweighted design matrix (lines of sight and one clock per system).
    pub pdop: f64,
    /// RMS of the residuals of the satellites used, m.
    pub residual_rms_m: f64,
    /// Geometry of every session satellite (`obs.sats` order) the receiver observes at the epoch, at
    /// the solution, with the clock of its system (or of the first system estimated); `None` where the
    /// satellite is not observed or has no usable ephemeris ([`observed_geometry`]).
    pub geometry: Vec<Option<SatGeometry>>,
}

/// One satellite's code and the constants of its model.
struct Candidate {
    sat: usize,
    system: usize,
    code_m: f64,
    frequency_hz: f64,
    group_delay_m: f64,
}

/// One epoch's problem: the observations' epoch time, the models and the satellites' codes.
struct Problem<'a> {
    obs: &'a Observations,
    t: i64,
    eph: &'a Ephemerides,
    nav: &'a NavData,
    opts: &'a EngineOptions,
    candidates: Vec<Candidate>,
}

/// The candidates usable at one linearisation point: their indices, residuals (observed - computed,
/// m), sigmas (m) and unit lines of sight (ECEF, receiver -> satellite).
struct Linearised {
    rows: Vec<usize>,
    residual_m: Vec<f64>,
    sigma_m: Vec<f64>,
    los: Vec<Vector3<f64>>,
}

/// Weighted, iterated code solution of `receiver` at `epoch` (module documentation); `prior` (ECEF, m)
/// starts the iteration (else the receiver's header position, else the Earth's centre). Its `geometry`
/// is [`observed_geometry`] at the solution.
///
/// # Errors
/// [`Error::OutOfRange`] for a receiver or epoch index outside `obs` or invalid options;
/// [`Error::Degenerate`] with fewer usable satellites than unknowns (3 + one clock per system);
/// [`Error::DegenerateGeometry`] for a normal matrix beyond [`MAX_CONDITION`];
/// [`Error::Convergence`] after [`MAX_ITERATIONS`] without convergence.
pub fn single_point(
    obs: &Observations,
    receiver: usize,
    epoch: usize,
    eph: &Ephemerides,
    nav: &NavData,
    opts: &EngineOptions,
    prior: Option<&Vector3<f64>>,
) -> Result<SppSolution> {
    let mut out = single_point_position(obs, receiver, epoch, eph, nav, opts, prior)?;
    out.geometry = observed_geometry(
        obs,
        receiver,
        epoch,
        eph,
        opts.frequencies,
        &out.clock_s,
        &out.position_m,
    );
    Ok(out)
}

/// [`single_point`] without the geometry (`geometry` left empty): for a receiver whose geometry is
/// wanted elsewhere (the engine's base at a surveyed position), or positioning alone.
///
/// # Errors
/// Those of [`single_point`].
pub fn single_point_position(
    obs: &Observations,
    receiver: usize,
    epoch: usize,
    eph: &Ephemerides,
    nav: &NavData,
    opts: &EngineOptions,
    prior: Option<&Vector3<f64>>,
) -> Result<SppSolution> {
    let inputs = Inputs {
        obs,
        eph,
        nav,
        opts,
    };
    code_solution(inputs, receiver, epoch, prior)
}

/// Geometry (`obs.sats` order) seen from `position_m` at `epoch` of every satellite `receiver` observes
/// there (a finite code or phase in a slot below `frequencies`), with the receiver's clock of the
/// satellite's system (else the first finite one); `None` for the others, where the satellite has no
/// usable ephemeris, or where no clock is finite. Satellites not observed are left out because nothing
/// selects their signals: computing them cost as much as the code solution itself. Which systems are
/// used is the engine's signal selection's to decide, not the geometry's.
pub fn observed_geometry(
    obs: &Observations,
    receiver: usize,
    epoch: usize,
    eph: &Ephemerides,
    frequencies: usize,
    clock_s: &[f64; N_SYSTEMS],
    position_m: &Vector3<f64>,
) -> Vec<Option<SatGeometry>> {
    let t = obs.time_gpst_ns[epoch];
    let rx = &obs.receivers[receiver];
    let fallback = clock_s.iter().copied().find(|c| c.is_finite());
    let site = Site::new(position_m);
    let slots = frequencies.clamp(1, MAX_FREQUENCIES);
    obs.sats
        .iter()
        .enumerate()
        .map(|(k, &id)| {
            let observed = (0..slots).any(|slot| {
                let i = obs.index(epoch, k, slot);
                rx.code_m[i].is_finite() || rx.phase_cycles[i].is_finite()
            });
            if !observed {
                return None;
            }
            let own = clock_s[id.system.index()];
            let clock = if own.is_finite() { Some(own) } else { fallback }?;
            satellite_geometry_from(eph, id, t, clock, &site)
        })
        .collect()
}

/// What every epoch's code solution of a session reads (one value, so that [`single_point_position`]
/// and [`single_points`] pass it on instead of repeating the list).
#[derive(Clone, Copy)]
struct Inputs<'a> {
    obs: &'a Observations,
    eph: &'a Ephemerides,
    nav: &'a NavData,
    opts: &'a EngineOptions,
}

/// [`single_point`] without the geometry of every session satellite (`geometry` left empty): what
/// positioning alone needs.
fn code_solution(
    inputs: Inputs<'_>,
    receiver: usize,
    epoch: usize,
    prior: Option<&Vector3<f64>>,
) -> Result<SppSolution> {
    let Inputs {
        obs,
        eph,
        nav,
        opts,
    } = inputs;
    if receiver >= obs.receivers.len() || epoch >= obs.n_epochs() {
        return Err(Error::out_of_range(
            "single_point",
            format!(
                "expected receiver < {} and epoch < {}, got {receiver} and {epoch}",
                obs.receivers.len(),
                obs.n_epochs()
            ),
        ));
    }
    if obs.glonass_channel.len() != obs.n_sats() {
        return Err(Error::Shape {
            name: "glonass_channel",
            expected: format!("({},)", obs.n_sats()),
            actual: format!("({},)", obs.glonass_channel.len()),
        });
    }
    let rx = &obs.receivers[receiver];
    if rx.code_m.len() != obs.n_epochs() * obs.n_sats() * MAX_FREQUENCIES {
        return Err(Error::Shape {
            name: "code_m",
            expected: format!("({}, {}, 3)", obs.n_epochs(), obs.n_sats()),
            actual: format!("{} values", rx.code_m.len()),
        });
    }
    let t = obs.time_gpst_ns[epoch];
    let candidates = candidates(inputs, receiver, epoch);
    let start = prior
        .copied()
        .filter(|p| p.iter().all(|x| x.is_finite()))
        .or_else(|| {
            rx.approx_position_m
                .map(Vector3::from)
                .filter(|p| p.norm() > MIN_HORIZON_RADIUS_M && p.iter().all(|x| x.is_finite()))
        })
        .unwrap_or_else(Vector3::zeros);
    let masked_from_start = start.norm() > MIN_HORIZON_RADIUS_M;
    let problem = Problem {
        obs,
        t,
        eph,
        nav,
        opts,
        candidates,
    };
    let (mut solution, used) = solve(&problem, None, start, masked_from_start)?;
    let mut systems: Vec<usize> = used.iter().map(|&r| problem.candidates[r].system).collect();
    systems.sort_unstable();
    systems.dedup();
    // Leave-one-out only where the remaining satellites still over-determine the solution.
    if solution.residual_rms_m > MAX_RESIDUAL_RMS_M && used.len() > 4 + systems.len() {
        let best = used
            .iter()
            .filter_map(|&r| solve(&problem, Some(r), solution.position_m, true).ok())
            .min_by(|a, b| a.0.residual_rms_m.total_cmp(&b.0.residual_rms_m));
        if let Some((s, _)) = best {
            if s.residual_rms_m < solution.residual_rms_m {
                solution = s;
            }
        }
    }
    Ok(solution)
}

/// The code of every satellite of `opts.systems` that `receiver` observes at `epoch`: its lowest slot
/// below `opts.frequencies` with a pseudorange in [`PSEUDORANGE_RANGE_M`].
fn candidates(inputs: Inputs<'_>, receiver: usize, epoch: usize) -> Vec<Candidate> {
    let Inputs { obs, eph, opts, .. } = inputs;
    let rx = &obs.receivers[receiver];
    let t = obs.time_gpst_ns[epoch];
    let frequencies = opts.frequencies.clamp(1, MAX_FREQUENCIES);
    let mut candidates = Vec::new();
    for (k, &id) in obs.sats.iter().enumerate() {
        if !opts.systems.contains(&id.system) {
            continue;
        }
        let found = (0..frequencies).find_map(|slot| {
            let p = rx.code_m[obs.index(epoch, k, slot)];
            let in_range = p >= PSEUDORANGE_RANGE_M.0 && p <= PSEUDORANGE_RANGE_M.1;
            // GLONASS without a channel: the nominal carrier is close enough for the ionosphere.
            let f = obs
                .frequency_hz(k, slot)
                .or_else(|| carrier_frequency_hz(id.system, slot, Some(0)))?;
            in_range.then_some((slot, p, f))
        });
        if let Some((slot, p, f)) = found {
            candidates.push(Candidate {
                sat: k,
                system: id.system.index(),
                code_m: p,
                frequency_hz: f,
                group_delay_m: SPEED_OF_LIGHT_M_S * eph.group_delay_s(id, slot, t),
            });
        }
    }
    candidates
}

/// Iterated solution without candidate `excluded`: the solution (geometry left empty) and the
/// candidates it used.
fn solve(
    p: &Problem,
    excluded: Option<usize>,
    start: Vector3<f64>,
    masked_from_start: bool,
) -> Result<(SppSolution, Vec<usize>)> {
    let (t, candidates) = (p.t, &p.candidates);
    let mut x = start;
    let mut clock_m = [0.0; N_SYSTEMS];
    for it in 0..MAX_ITERATIONS {
        let mask = masked_from_start || it > 0;
        let lin = linearise(p, excluded, &x, &clock_m, mask);
        let systems: Vec<usize> = (0..N_SYSTEMS)
            .filter(|s| lin.rows.iter().any(|&r| candidates[r].system == *s))
            .collect();
        let n_unknowns = 3 + systems.len();
        if lin.rows.len() < n_unknowns {
            return Err(Error::Degenerate {
                what: format!("single point at GPST {t} ns"),
                quantity: "usable satellites",
                value: lin.rows.len() as f64,
                limit: n_unknowns as f64,
            });
        }
        let dx = step(&lin, candidates, &systems, t)?;
        x += Vector3::new(dx[0], dx[1], dx[2]);
        for (col, &s) in systems.iter().enumerate() {
            clock_m[s] += dx[3 + col];
        }
        let step = Vector3::new(dx[0], dx[1], dx[2]).norm();
        if step < CONVERGED_STEP_M && mask {
            // Residuals at the solution.
            let fin = linearise(p, excluded, &x, &clock_m, true);
            let n = fin.rows.len().max(1) as f64;
            let rms = (fin.residual_m.iter().map(|v| v * v).sum::<f64>() / n).sqrt();
            let mut clock_s = [f64::NAN; N_SYSTEMS];
            for &s in &systems {
                clock_s[s] = clock_m[s] / SPEED_OF_LIGHT_M_S;
            }
            let mut satellites_per_system = [0; N_SYSTEMS];
            for &r in &fin.rows {
                satellites_per_system[candidates[r].system] += 1;
            }
            return Ok((
                SppSolution {
                    position_m: x,
                    clock_s,
                    satellites: fin.rows.len(),
                    satellites_per_system,
                    pdop: pdop(&fin, candidates),
                    residual_rms_m: rms,
                    geometry: Vec::new(),
                },
                fin.rows,
            ));
        }
    }
    Err(Error::Convergence {
        what: "single point",
        iterations: MAX_ITERATIONS,
    })
}

/// The weighted least-squares update (position, then one clock per system of `systems`) of the rows of
/// `lin`, its normal matrix checked against [`MAX_CONDITION`].
fn step(
    lin: &Linearised,
    candidates: &[Candidate],
    systems: &[usize],
    t: i64,
) -> Result<DVector<f64>> {
    let m = lin.rows.len();
    let mut a = DMatrix::<f64>::zeros(m, 3 + systems.len());
    let mut b = DVector::<f64>::zeros(m);
    for (i, &r) in lin.rows.iter().enumerate() {
        let sw = 1.0 / lin.sigma_m[i];
        for j in 0..3 {
            a[(i, j)] = -lin.los[i][j] * sw;
        }
        if let Some(col) = systems.iter().position(|&s| s == candidates[r].system) {
            a[(i, 3 + col)] = sw;
        }
        b[i] = lin.residual_m[i] * sw;
    }
    let normal = a.transpose() * &a;
    let eig = normal.clone().symmetric_eigenvalues();
    let (lo, hi) = eig.iter().fold((f64::INFINITY, 0.0f64), |(lo, hi), &e| {
        (lo.min(e), hi.max(e))
    });
    let condition = hi / lo;
    if !(lo > 0.0 && condition <= MAX_CONDITION) {
        return Err(Error::DegenerateGeometry {
            what: format!("single point at GPST {t} ns with {m} satellites"),
            matrix: "normal matrix",
            condition: if lo > 0.0 { condition } else { f64::INFINITY },
        });
    }
    let Some(chol) = normal.cholesky() else {
        return Err(Error::DegenerateGeometry {
            what: format!("single point at GPST {t} ns with {m} satellites"),
            matrix: "normal matrix",
            condition,
        });
    };
    let dx = chol.solve(&(a.transpose() * b));
    if !dx.iter().all(|v| v.is_finite()) {
        return Err(Error::numerical(
            "single point",
            format!("the update at GPST {t} ns is not finite"),
        ));
    }
    Ok(dx)
}

/// PDOP of the rows of `lin` (field [`SppSolution::pdop`]); NaN where the design is singular.
fn pdop(lin: &Linearised, candidates: &[Candidate]) -> f64 {
    let systems: Vec<usize> = (0..N_SYSTEMS)
        .filter(|s| lin.rows.iter().any(|&r| candidates[r].system == *s))
        .collect();
    let n = 3 + systems.len();
    let mut g = DMatrix::<f64>::zeros(lin.rows.len(), n);
    for (i, &r) in lin.rows.iter().enumerate() {
        for j in 0..3 {
            g[(i, j)] = -lin.los[i][j];
        }
        if let Some(col) = systems.iter().position(|&s| s == candidates[r].system) {
            g[(i, 3 + col)] = 1.0;
        }
    }
    (g.transpose() * &g).cholesky().map_or(f64::NAN, |c| {
        let q = c.inverse();
        (q[(0, 0)] + q[(1, 1)] + q[(2, 2)]).sqrt()
    })
}

/// [`single_point`] of `receiver` at every epoch of `obs` (without `geometry`), each started from the
/// receiver's header position (else the Earth's centre) on its own: epochs are independent, solved in
/// parallel on rayon's pool; `None` at an epoch without a solution.
///
/// # Errors
/// [`Error::OutOfRange`] for a receiver outside `obs` or invalid options; [`Error::Interrupted`].
pub fn single_points(
    obs: &Observations,
    receiver: usize,
    eph: &Ephemerides,
    nav: &NavData,
    opts: &EngineOptions,
) -> Result<Vec<Option<SppSolution>>> {
    use rayon::prelude::*;
    opts.validate()?;
    if receiver >= obs.receivers.len() {
        return Err(Error::out_of_range(
            "single_points",
            format!(
                "expected receiver < {}, got {receiver}",
                obs.receivers.len()
            ),
        ));
    }
    let inputs = Inputs {
        obs,
        eph,
        nav,
        opts,
    };
    (0..obs.n_epochs())
        .into_par_iter()
        .map(|e| {
            // every epoch (a relaxed load beside a least-squares solution): the epochs run in parallel
            // chunks, so a poll on every 1024th epoch index was reached once per chunk, if at all
            crate::interrupt::check("single point")?;
            match code_solution(inputs, receiver, e, None) {
                Ok(s) => Ok(Some(s)),
                Err(err @ (Error::Shape { .. } | Error::Interrupted { .. })) => Err(err),
                Err(_) => Ok(None),
            }
        })
        .collect()
}

/// Residuals (observed - computed), lines of sight and sigmas of the usable candidates at `x`.
fn linearise(
    p: &Problem,
    excluded: Option<usize>,
    x: &Vector3<f64>,
    clock_m: &[f64; N_SYSTEMS],
    mask: bool,
) -> Linearised {
    let site = Site::new(x);
    let known = x.norm() > MIN_HORIZON_RADIUS_M;
    let (lat, lon, height) = match (known, &site.horizon) {
        (true, Some((geodetic, _))) => *geodetic,
        _ => (0.0, 0.0, 0.0),
    };
    let mut lin = Linearised {
        rows: Vec::new(),
        residual_m: Vec::new(),
        sigma_m: Vec::new(),
        los: Vec::new(),
    };
    let (t, eph, opts) = (p.t, p.eph, p.opts);
    for (r, c) in p.candidates.iter().enumerate() {
        if excluded == Some(r) {
            continue;
        }
        let id = p.obs.sats[c.sat];
        let Some(g) =
            satellite_geometry_from(eph, id, t, clock_m[c.system] / SPEED_OF_LIGHT_M_S, &site)
        else {
            continue;
        };
        let (iono, tropo, mapping, el) = if known {
            if mask && (g.elevation_rad.is_nan() || g.elevation_rad < opts.elevation_mask_rad) {
                continue;
            }
            let iono = p.nav.klobuchar.map_or(0.0, |k| {
                klobuchar_delay_m(
                    &k,
                    t,
                    lat,
                    lon,
                    g.azimuth_rad,
                    g.elevation_rad,
                    c.frequency_hz,
                )
            });
            let tropo = troposphere_delay_at_m(lat, height, g.elevation_rad, t);
            (
                iono,
                tropo,
                niell_mapping(lat, height, g.elevation_rad, Some(day_of_year(t))).0,
                g.elevation_rad,
            )
        } else {
            (0.0, 0.0, 1.0, std::f64::consts::FRAC_PI_2)
        };
        let model =
            g.range_m + clock_m[c.system] - SPEED_OF_LIGHT_M_S * g.clock_s - c.group_delay_m
                + iono
                + tropo;
        let v = c.code_m - model;
        let var = code_variance_m2(&opts.code_sigma, el, iono, mapping);
        if !(v.is_finite() && var > 0.0 && var.is_finite()) {
            continue;
        }
        lin.rows.push(r);
        lin.residual_m.push(v);
        lin.sigma_m.push(var.sqrt());
        lin.los.push(g.los_ecef);
    }
    lin
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gnss::geometry::{enu_from_ecef, geodetic_from_ecef, satellite_geometry};
    use crate::gnss::navdata::KeplerRecord;
    use crate::gnss::observations::ReceiverObservations;
    use crate::gnss::signal::{SatId, System};

    const T0: i64 = 2138 * 604_800 * 1_000_000_000 + 432_000 * 1_000_000_000;

    /// 24 circular GPS orbits: 6 planes of 4 satellites.
    fn constellation() -> NavData {
        let kepler = (0..24u8)
            .map(|k| KeplerRecord {
                sat: SatId {
                    system: System::Gps,
                    prn: k + 1,
                },
                toc_gpst_ns: T0,
                toe_gpst_ns: T0,
                af: [1e-5 * f64::from(k), 0.0, 0.0],
                crs: 0.0,
                delta_n: 0.0,
                m0: f64::from(k % 4) * 1.571 + f64::from(k / 4) * 0.3,
                cuc: 0.0,
                e: 0.0,
                cus: 0.0,
                sqrt_a: 5153.7,
                cic: 0.0,
                omega0: f64::from(k / 4) * 1.047,
                cis: 0.0,
                i0: 0.96,
                crc: 0.0,
                omega: 0.0,
                omega_dot: 0.0,
                idot: 0.0,
                health: 0.0,
                tgd_s: [0.0, f64::NAN],
                iode: 1.0,
                accuracy_m: 2.0,
                fit_interval_h: 4.0,
                data_source: f64::NAN,
            })
            .collect();
        NavData {
            kepler,
            ..NavData::default()
        }
    }

    fn observations(nav: &NavData, truth: &Vector3<f64>, clock_s: f64) -> Observations {
        let eph = Ephemerides::new(nav).unwrap();
        let sats: Vec<SatId> = nav.kepler.iter().map(|r| r.sat).collect();
        let (lat, _, h) = geodetic_from_ecef(truth);
        let mut code = vec![f64::NAN; sats.len() * MAX_FREQUENCIES];
        for (k, &id) in sats.iter().enumerate() {
            let g = satellite_geometry(&eph, id, T0, clock_s, truth).unwrap();
            code[k * MAX_FREQUENCIES] = g.range_m
                + SPEED_OF_LIGHT_M_S * (clock_s - g.clock_s)
                + troposphere_delay_at_m(lat, h, g.elevation_rad.max(0.0), T0);
        }
        let receiver = ReceiverObservations {
            code_m: code,
            ..ReceiverObservations::absent(1, sats.len(), None)
        };
        Observations {
            time_gpst_ns: vec![T0],
            glonass_channel: vec![None; sats.len()],
            sats,
            receivers: vec![receiver],
        }
    }

    #[test]
    fn recovers_a_noise_free_position_and_clock_from_the_earth_centre() {
        let nav = constellation();
        let eph = Ephemerides::new(&nav).unwrap();
        let (lat, lon) = (36f64.to_radians(), 140f64.to_radians());
        let truth = enu_from_ecef(lat, lon).transpose() * Vector3::new(0.0, 0.0, 6_371_000.0);
        let obs = observations(&nav, &truth, 2.5e-4);
        let s = single_point(&obs, 0, 0, &eph, &nav, &EngineOptions::default(), None).unwrap();
        assert!(s.satellites >= 5, "{}", s.satellites);
        assert!(
            (s.position_m - truth).norm() < 1e-3,
            "{}",
            (s.position_m - truth).norm()
        );
        assert!((s.clock_s[0] - 2.5e-4).abs() < 1e-11);
        assert!(s.clock_s[1..].iter().all(|c| c.is_nan()));
        assert!(s.residual_rms_m < 1e-3);
        assert_eq!(s.geometry.len(), 24);
    }

    #[test]
    fn parallel_epochs_and_pdop() {
        let nav = constellation();
        let eph = Ephemerides::new(&nav).unwrap();
        let (lat, lon) = (36f64.to_radians(), 140f64.to_radians());
        let truth = enu_from_ecef(lat, lon).transpose() * Vector3::new(0.0, 0.0, 6_371_000.0);
        let one = observations(&nav, &truth, 2.5e-4);
        // The same epoch three times, the second without code: two solutions, one None.
        let mut obs = one.clone();
        obs.time_gpst_ns = vec![T0, T0 + 1, T0 + 2];
        let rx = &mut obs.receivers[0];
        let n = rx.code_m.len();
        let mut code = rx.code_m.clone();
        code.extend(vec![f64::NAN; n]);
        code.extend(rx.code_m.clone());
        rx.code_m = code;
        for v in [&mut rx.phase_cycles, &mut rx.doppler_hz, &mut rx.snr_dbhz] {
            *v = vec![f64::NAN; 3 * n];
        }
        rx.lli = vec![0; 3 * n];
        let opts = EngineOptions::default();
        let all = single_points(&obs, 0, &eph, &nav, &opts).unwrap();
        let s = single_point(&one, 0, 0, &eph, &nav, &opts, None).unwrap();
        assert!(all[1].is_none());
        let a = all[0].as_ref().unwrap();
        assert!((a.position_m - s.position_m).norm() < 1e-6);
        assert_eq!(a.satellites_per_system, [s.satellites, 0, 0, 0, 0]);
        // PDOP from the lines of sight of the satellites above the mask, written out here: the
        // inverse of the 4x4 normal matrix by nalgebra's LU.
        let rows: Vec<Vector3<f64>> = s
            .geometry
            .iter()
            .flatten()
            .filter(|g| g.elevation_rad >= opts.elevation_mask_rad)
            .map(|g| g.los_ecef)
            .collect();
        assert_eq!(rows.len(), s.satellites);
        let mut normal = nalgebra::Matrix4::<f64>::zeros();
        for u in &rows {
            let g = nalgebra::Vector4::new(-u.x, -u.y, -u.z, 1.0);
            normal += g * g.transpose();
        }
        let q = normal.lu().try_inverse().unwrap();
        let want = (q[(0, 0)] + q[(1, 1)] + q[(2, 2)]).sqrt();
        assert!((s.pdop - want).abs() < 1e-9 * want, "{} vs {want}", s.pdop);
        assert!(single_points(&obs, 1, &eph, &nav, &opts).is_err());
    }

    #[test]
    fn one_clock_per_system() {
        // GPS plus a Galileo constellation (its own mu, planes shifted) whose codes carry a 120 ns
        // inter-system bias: the bias is Galileo's clock minus GPS's, the position is unaffected.
        let mut nav = constellation();
        let galileo: Vec<KeplerRecord> = nav
            .kepler
            .iter()
            .map(|r| KeplerRecord {
                sat: SatId {
                    system: System::Galileo,
                    prn: r.sat.prn,
                },
                sqrt_a: 5440.6,
                omega0: r.omega0 + 0.5,
                ..*r
            })
            .collect();
        nav.kepler.extend(galileo);
        let eph = Ephemerides::new(&nav).unwrap();
        let truth = enu_from_ecef(-0.5, 0.3).transpose() * Vector3::new(0.0, 0.0, 6_371_000.0);
        let mut obs = observations(&nav, &truth, 1e-4);
        let bias_s = 120e-9;
        for k in 24..48 {
            obs.receivers[0].code_m[k * MAX_FREQUENCIES] += SPEED_OF_LIGHT_M_S * bias_s;
        }
        let s = single_point(&obs, 0, 0, &eph, &nav, &EngineOptions::default(), None).unwrap();
        assert!((s.position_m - truth).norm() < 1e-3);
        assert!((s.clock_s[0] - 1e-4).abs() < 1e-11);
        assert!((s.clock_s[2] - s.clock_s[0] - bias_s).abs() < 1e-11);
        assert!(s.clock_s[1].is_nan() && s.clock_s[3].is_nan() && s.clock_s[4].is_nan());
        // Galileo alone (the systems option): its own clock only.
        let opts = EngineOptions {
            systems: vec![System::Galileo],
            ..EngineOptions::default()
        };
        let g = single_point(&obs, 0, 0, &eph, &nav, &opts, None).unwrap();
        assert!(g.clock_s[0].is_nan() && (g.clock_s[2] - 1e-4 - bias_s).abs() < 1e-11);
    }

    #[test]
    fn an_outlier_is_dropped_once() {
        let nav = constellation();
        let eph = Ephemerides::new(&nav).unwrap();
        let truth = enu_from_ecef(0.6, 2.4).transpose() * Vector3::new(0.0, 0.0, 6_371_000.0);
        let mut obs = observations(&nav, &truth, 0.0);
        let clean = single_point(&obs, 0, 0, &eph, &nav, &EngineOptions::default(), None).unwrap();
        let used = clean.satellites;
        // 300 m on the highest satellite's code.
        let top = (0..24)
            .max_by(|&a, &b| {
                let el = |k: usize| clean.geometry[k].map_or(-1.0, |g| g.elevation_rad);
                el(a).total_cmp(&el(b))
            })
            .unwrap();
        obs.receivers[0].code_m[top * MAX_FREQUENCIES] += 300.0;
        let s = single_point(&obs, 0, 0, &eph, &nav, &EngineOptions::default(), None).unwrap();
        assert_eq!(s.satellites, used - 1);
        assert!((s.position_m - truth).norm() < 1e-3);
    }

    #[test]
    fn too_few_satellites_and_bad_indices_are_errors() {
        let nav = constellation();
        let eph = Ephemerides::new(&nav).unwrap();
        let truth = enu_from_ecef(0.6, 2.4).transpose() * Vector3::new(0.0, 0.0, 6_371_000.0);
        let mut obs = observations(&nav, &truth, 0.0);
        for k in 3..24 {
            obs.receivers[0].code_m[k * MAX_FREQUENCIES] = f64::NAN;
        }
        let opts = EngineOptions::default();
        assert!(matches!(
            single_point(&obs, 0, 0, &eph, &nav, &opts, None),
            Err(Error::Degenerate { .. })
        ));
        assert!(matches!(
            single_point(&obs, 1, 0, &eph, &nav, &opts, None),
            Err(Error::OutOfRange { .. })
        ));
    }
}
