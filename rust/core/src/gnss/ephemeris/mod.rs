//! Broadcast ephemerides: the record of each satellite usable at a time, and its orbit and clock.
//!
//! Record choice: among the records of a satellite that are healthy by the system's ICD and whose
//! reference time (toe, or t_b for GLONASS) lies within the validity interval [`max_age_s`] of the
//! requested time, the nearest one. Orbits and clocks: [`kepler`] (GPS, Galileo, BeiDou, QZSS) and
//! [`glonass`]. Group delays per frequency slot: [`Ephemerides::group_delay_s`].

pub mod glonass;
pub mod kepler;

use nalgebra::Vector3;

use super::geometry::WGS84_A_M;
use super::navdata::{GlonassRecord, KeplerRecord, NavData};
use super::signal::{carrier_frequency_hz, SatId, System};
use super::time::seconds_between;
use crate::error::{Error, Result};

/// Most navigation records of a session (a day of every constellation is about 10^4).
pub const MAX_RECORDS: usize = 1_000_000;

/// Finite-difference step of the velocity and clock drift of Keplerian orbits, s (RTKLIB's value: the
/// truncation error, |acceleration| h / 2, stays below 1 mm/s).
const DIFFERENCE_STEP_S: f64 = 1e-3;

/// Satellite state at transmit time: ECEF of that instant (no Earth rotation applied), clock including the
/// relativistic term, without group delay.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SatState {
    pub position_m: Vector3<f64>,
    pub velocity_m_s: Vector3<f64>,
    pub clock_s: f64,
    pub clock_drift_s_s: f64,
}

/// The records of a session indexed per satellite (each list sorted by reference time), and those left
/// out because the models cannot use them.
#[derive(Debug, Clone, Default)]
pub struct Ephemerides {
    kepler: PerSatellite<KeplerRecord>,
    glonass: PerSatellite<GlonassRecord>,
    skipped: Vec<SkippedRecord>,
}

/// Records per satellite in a table indexed by system and PRN: the engine looks a satellite's records
/// up several times per satellite, iteration and receiver of every epoch, where a hash map's SipHash cost
/// 4 % of a simulated all-signal session's instructions.
#[derive(Debug, Clone)]
struct PerSatellite<R>(Vec<Vec<R>>);

impl<R> Default for PerSatellite<R> {
    fn default() -> Self {
        PerSatellite(Vec::new())
    }
}

impl<R> PerSatellite<R> {
    fn slot(sat: SatId) -> usize {
        sat.system.index() * 256 + usize::from(sat.prn)
    }

    fn push(&mut self, sat: SatId, record: R) {
        if self.0.is_empty() {
            self.0.resize_with(System::ALL.len() * 256, Vec::new);
        }
        self.0[Self::slot(sat)].push(record);
    }

    /// The satellite's records; `None` where it has none.
    fn get(&self, sat: SatId) -> Option<&[R]> {
        self.0
            .get(Self::slot(sat))
            .filter(|v| !v.is_empty())
            .map(Vec::as_slice)
    }

    fn lists_mut(&mut self) -> impl Iterator<Item = &mut Vec<R>> {
        self.0.iter_mut()
    }
}

/// Why a record is left out by [`Ephemerides::new`]: one warning per reason.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum SkipReason {
    /// A value that is NaN or infinite: no orbit or clock can be computed from it.
    NotFinite,
    /// sqrt(A) <= 0 or an eccentricity outside [0, 1): not an ellipse, Kepler's equation has no
    /// solution the model can use.
    NotAnEllipse,
    /// An orbit that meets the Earth or reaches beyond 1e8 m, or rates and clock terms beyond those of
    /// any navigation satellite: positions would be computed, but not of a satellite.
    NotASatellite,
    /// A health word that is not an integer in 0..2^32 (the health bits cannot be read).
    HealthWord,
}

impl SkipReason {
    fn describe(self) -> &'static str {
        match self {
            SkipReason::NotFinite => "a value that is not finite",
            SkipReason::NotAnEllipse => {
                "not an elliptical orbit (sqrt(A) <= 0 or eccentricity outside [0, 1))"
            }
            SkipReason::NotASatellite => {
                "not the orbit or clock of a navigation satellite (perigee below the Earth's radius, \
                 apogee beyond 1e8 m, or rates and clock terms beyond any broadcast)"
            }
            SkipReason::HealthWord => "a health word that is not an integer in 0..2^32",
        }
    }
}

/// A navigation record left out by [`Ephemerides::new`]: its table (`"Keplerian"` or `"GLONASS"`),
/// index in that table of [`NavData`], satellite, reason and the value that gave it.
#[derive(Debug, Clone, PartialEq)]
pub struct SkippedRecord {
    pub kind: &'static str,
    pub index: usize,
    pub sat: SatId,
    pub reason: SkipReason,
    pub detail: String,
}

/// Records named in full per warning of [`Ephemerides::skip_warnings`]; the rest are counted.
const NAMED_SKIPPED: usize = 8;

/// Half-width of the validity interval around a record's reference time, s: GPS half its fit interval
/// (IS-GPS-200 20.3.4.4; 4 h when the record gives none), QZSS 1 h (IS-QZSS-PNT: 2 h fit interval;
/// RINEX gives a flag there, not hours), Galileo 4 h, BeiDou 6 h and GLONASS 30 min (RTKLIB's
/// MAXDTOE_GAL, MAXDTOE_CMP, MAXDTOE_GLO: BeiDou and Galileo broadcast no fit interval).
pub fn max_age_s(system: System, fit_interval_h: f64) -> f64 {
    match system {
        System::Gps if fit_interval_h.is_finite() && fit_interval_h > 0.0 => {
            fit_interval_h * 1800.0
        }
        System::Gps => 7200.0,
        System::Qzss => 3600.0,
        System::Galileo => 14_400.0,
        System::BeiDou => 21_600.0,
        System::Glonass => 1800.0,
    }
}

/// Galileo data-source bits (RINEX 3.04 table A8): I/NAV (bits 0, 2, 9) or F/NAV (bits 1, 8).
fn galileo_fnav(record: &KeplerRecord) -> bool {
    let bits = word(record.data_source);
    bits & 0x002 != 0 && bits & 0x005 == 0
}

/// A flag word stored as a float (validated to be an integer in 0..2^32 by [`Ephemerides::new`]).
fn word(x: f64) -> u32 {
    if x.is_finite() && (0.0..=f64::from(u32::MAX)).contains(&x) {
        x as u32
    } else {
        0
    }
}

/// Health of a Keplerian record by its system's ICD: GPS any nonzero health; QZSS all but bit 0, which
/// flags the L6/LEX signal (masked as RTKLIB masks it); Galileo the signal health and data validity bits
/// of the signals of the record's message (I/NAV: E1-B and E5b, F/NAV: E5a); BeiDou SatH1.
pub fn kepler_healthy(record: &KeplerRecord) -> bool {
    let h = word(record.health);
    match record.sat.system {
        System::Qzss => h & !1 == 0,
        // bit 0 E1-B DVS, 1-2 E1-B HS, 3 E5a DVS, 4-5 E5a HS, 6 E5b DVS, 7-8 E5b HS.
        System::Galileo if galileo_fnav(record) => h & 0x038 == 0,
        System::Galileo => h & 0x1C7 == 0,
        _ => h == 0,
    }
}

/// Nearest usable record (`usable(record, age_s)`) by reference time; the lower `rank` breaks ties, then
/// the order of `records`, which is sorted by reference time.
///
/// The sort bounds the search: ages grow away from `t_gpst_ns` on either side, so the scan stops on a side
/// at the first record older than the best usable one found, and the choice among the records scanned is
/// the one a scan of every record makes (a record left out is older than the one chosen). A day of
/// Galileo I/NAV is about 140 records per satellite, asked for 10 times per epoch and receiver.
fn nearest<R>(
    records: &[R],
    t_gpst_ns: i64,
    reference_ns: impl Fn(&R) -> i64,
    usable: impl Fn(&R, f64) -> bool,
    rank: impl Fn(&R) -> u8,
) -> Option<&R> {
    let age = |r: &R| seconds_between(t_gpst_ns, reference_ns(r)).abs();
    let split = records.partition_point(|r| reference_ns(r) < t_gpst_ns);
    let mut best = f64::INFINITY;
    let mut lo = split;
    while lo > 0 {
        let a = age(&records[lo - 1]);
        if a > best {
            break;
        }
        lo -= 1;
        if a < best && usable(&records[lo], a) {
            best = a;
        }
    }
    let mut hi = split;
    while hi < records.len() {
        let a = age(&records[hi]);
        if a > best {
            break;
        }
        if a < best && usable(&records[hi], a) {
            best = a;
        }
        hi += 1;
    }
    records[lo..hi]
        .iter()
        .filter_map(|r| {
            let age = age(r);
            usable(r, age).then_some((age, rank(r), r))
        })
        .min_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)))
        .map(|(_, _, r)| r)
}

impl Ephemerides {
    /// Indexes the records of `nav` per satellite; a record the models cannot use (a value that is not
    /// finite, not an ellipse, not a navigation satellite's orbit or clock, an unreadable health word:
    /// [`SkipReason`]) is left out and listed in [`Ephemerides::skipped`], never fatal to the others.
    /// Any eccentricity in [0, 1) is used (Galileo E14 and E18 fly at 0.16-0.17): Kepler propagation
    /// is exact for every ellipse ([`kepler::eccentric_anomaly`]).
    ///
    /// # Errors
    /// [`Error::TooLarge`] beyond [`MAX_RECORDS`]; [`Error::OutOfRange`] naming the record (satellite and
    /// index) for a record in the table of the wrong system (a GLONASS satellite among the Keplerian
    /// records or the reverse: a defect of the caller, not of a file).
    pub fn new(nav: &NavData) -> Result<Ephemerides> {
        let n = nav.kepler.len().saturating_add(nav.glonass.len());
        if n > MAX_RECORDS {
            return Err(Error::too_large(
                "nav",
                n as f64,
                MAX_RECORDS as f64,
                "navigation records",
            ));
        }
        let mut eph = Ephemerides::default();
        for (i, r) in nav.kepler.iter().enumerate() {
            match check_kepler(i, r)? {
                None => eph.kepler.push(r.sat, *r),
                Some((reason, detail)) => eph.skip("Keplerian", i, r.sat, reason, detail),
            }
        }
        for (i, r) in nav.glonass.iter().enumerate() {
            match check_glonass(i, r)? {
                None => eph.glonass.push(r.sat, *r),
                Some((reason, detail)) => eph.skip("GLONASS", i, r.sat, reason, detail),
            }
        }
        for v in eph.kepler.lists_mut() {
            v.sort_by_key(|r| r.toe_gpst_ns);
        }
        for v in eph.glonass.lists_mut() {
            v.sort_by_key(|r| r.tb_gpst_ns);
        }
        Ok(eph)
    }

    fn skip(
        &mut self,
        kind: &'static str,
        index: usize,
        sat: SatId,
        reason: SkipReason,
        detail: String,
    ) {
        self.skipped.push(SkippedRecord {
            kind,
            index,
            sat,
            reason,
            detail,
        });
    }

    /// The records left out by [`Ephemerides::new`], in the order of the navigation data.
    pub fn skipped(&self) -> &[SkippedRecord] {
        &self.skipped
    }

    /// One sentence per [`SkipReason`] met: the count, the first `NAMED_SKIPPED` records named with
    /// their values, and that the others of the file are used.
    pub fn skip_warnings(&self) -> Vec<String> {
        let mut reasons: Vec<SkipReason> = self.skipped.iter().map(|s| s.reason).collect();
        reasons.sort_unstable();
        reasons.dedup();
        reasons
            .into_iter()
            .map(|reason| {
                let of: Vec<&SkippedRecord> =
                    self.skipped.iter().filter(|s| s.reason == reason).collect();
                let named: Vec<String> = of
                    .iter()
                    .take(NAMED_SKIPPED)
                    .map(|s| format!("{} record {} ({}): {}", s.kind, s.index, s.sat, s.detail))
                    .collect();
                let more = of.len().saturating_sub(NAMED_SKIPPED);
                let tail = if more > 0 {
                    format!("; and {more} more")
                } else {
                    String::new()
                };
                format!(
                    "{} navigation record(s) skipped, {}: {}{tail}; the other records are used",
                    of.len(),
                    reason.describe(),
                    named.join("; ")
                )
            })
            .collect()
    }

    /// Whether any record of `sat` exists (healthy or not).
    pub fn has(&self, sat: SatId) -> bool {
        self.kepler.get(sat).is_some() || self.glonass.get(sat).is_some()
    }

    fn kepler_record(&self, sat: SatId, t_gpst_ns: i64) -> Option<&KeplerRecord> {
        let records = self.kepler.get(sat)?;
        nearest(
            records,
            t_gpst_ns,
            |r| r.toe_gpst_ns,
            |r, age| age <= max_age_s(sat.system, r.fit_interval_h) && kepler_healthy(r),
            // Galileo: I/NAV (the E1/E5b clock) before F/NAV at the same toe.
            |r| u8::from(sat.system == System::Galileo && galileo_fnav(r)),
        )
    }

    fn glonass_record(&self, sat: SatId, t_gpst_ns: i64) -> Option<&GlonassRecord> {
        let records = self.glonass.get(sat)?;
        nearest(
            records,
            t_gpst_ns,
            |r| r.tb_gpst_ns,
            |r, age| age <= max_age_s(System::Glonass, f64::NAN) && r.health == 0.0,
            |_| 0,
        )
    }

    /// State at transmit time `t = t_gpst_ns + offset_s` (offset small, e.g. minus the light time);
    /// `None` when no usable record (healthy per the system's ICD, within its validity interval
    /// [`max_age_s`]) exists, for an offset that is not finite or beyond a day, or where the result
    /// would not be finite.
    pub fn state(&self, sat: SatId, t_gpst_ns: i64, offset_s: f64) -> Option<SatState> {
        if !offset_s.is_finite() || offset_s.abs() > 86_400.0 {
            return None;
        }
        // Record choice at the whole nanoseconds nearest the instant (the offset is small).
        let t_select = t_gpst_ns.saturating_add((offset_s * 1e9).round() as i64);
        let state = if sat.system == System::Glonass {
            let r = self.glonass_record(sat, t_select)?;
            let (p, v, clock) = glonass::state(r, t_gpst_ns, offset_s);
            SatState {
                position_m: p,
                velocity_m_s: v,
                clock_s: clock,
                clock_drift_s_s: r.gamma_n,
            }
        } else {
            let r = self.kepler_record(sat, t_select)?;
            let (p0, c0) = kepler::position_clock(r, t_gpst_ns, offset_s);
            let (p1, c1) = kepler::position_clock(r, t_gpst_ns, offset_s + DIFFERENCE_STEP_S);
            SatState {
                position_m: p0,
                velocity_m_s: (p1 - p0) / DIFFERENCE_STEP_S,
                clock_s: c0,
                clock_drift_s_s: (c1 - c0) / DIFFERENCE_STEP_S,
            }
        };
        let finite = state.position_m.iter().all(|x| x.is_finite())
            && state.velocity_m_s.iter().all(|x| x.is_finite())
            && state.clock_s.is_finite()
            && state.clock_drift_s_s.is_finite();
        finite.then_some(state)
    }

    /// Position and clock of [`Ephemerides::state`] (the same record, the same values) without the
    /// velocity and clock drift: what the light-time iteration of
    /// [`crate::gnss::geometry::satellite_geometry`] asks for several times per satellite and epoch, at
    /// half the Keplerian work (`state` evaluates the orbit twice for its finite differences).
    pub fn position_clock(
        &self,
        sat: SatId,
        t_gpst_ns: i64,
        offset_s: f64,
    ) -> Option<(Vector3<f64>, f64)> {
        if sat.system == System::Glonass {
            return self
                .state(sat, t_gpst_ns, offset_s)
                .map(|s| (s.position_m, s.clock_s));
        }
        if !offset_s.is_finite() || offset_s.abs() > 86_400.0 {
            return None;
        }
        let t_select = t_gpst_ns.saturating_add((offset_s * 1e9).round() as i64);
        let r = self.kepler_record(sat, t_select)?;
        let (p, clock) = kepler::position_clock(r, t_gpst_ns, offset_s);
        (p.iter().all(|x| x.is_finite()) && clock.is_finite()).then_some((p, clock))
    }

    /// Group delay to ADD to the satellite clock for a single-frequency pseudorange of `slot`, s, from
    /// the record [`Ephemerides::state`] uses at `t_gpst_ns`: GPS/QZSS `-(f_L1/f)^2 TGD` (IS-GPS-200
    /// 20.3.3.3.3.2; L5 with the same scaling, LNAV having no ISC); Galileo `-(f_E1/f)^2 BGD` with
    /// BGD(E1,E5b) for E1 and E5b and BGD(E1,E5a) for E5a (OS SIS ICD 5.1.5); BeiDou `-TGD1` on B1I,
    /// `-TGD2` on B2I, 0 on B3I (the broadcast clock is that of B3I, BDS-SIS-ICD 5.2.4.10); 0 for
    /// GLONASS, where no record is usable, or where the record gives none (NaN).
    pub fn group_delay_s(&self, sat: SatId, slot: usize, t_gpst_ns: i64) -> f64 {
        let Some(r) = (sat.system != System::Glonass)
            .then(|| self.kepler_record(sat, t_gpst_ns))
            .flatten()
        else {
            return 0.0;
        };
        let scale = |f1: f64| {
            carrier_frequency_hz(sat.system, slot, None).map_or(f64::NAN, |f| (f1 / f).powi(2))
        };
        let f1 = carrier_frequency_hz(sat.system, 0, None).unwrap_or(f64::NAN);
        let delay = match (sat.system, slot) {
            (System::Gps | System::Qzss, _) => -scale(f1) * r.tgd_s[0],
            (System::Galileo, 2) => -scale(f1) * r.tgd_s[0],
            (System::Galileo, _) => -scale(f1) * r.tgd_s[1],
            (System::BeiDou, 0) => -r.tgd_s[0],
            (System::BeiDou, 1) => -r.tgd_s[1],
            _ => 0.0,
        };
        if delay.is_finite() {
            delay
        } else {
            0.0
        }
    }
}

fn record_error(kind: &str, i: usize, sat: SatId, detail: String) -> Error {
    Error::out_of_range("nav", format!("{kind} record {i} ({sat}): {detail}"))
}

/// Why a record is skipped and the value that says so; `None` for a usable record.
type Verdict = Option<(SkipReason, String)>;

fn check_health_word(health: f64) -> Verdict {
    let integer = health.is_finite()
        && health.fract() == 0.0
        && (0.0..=f64::from(u32::MAX)).contains(&health);
    (!integer).then(|| (SkipReason::HealthWord, format!("health {health}")))
}

/// Largest apogee of a navigation satellite's orbit, m (GEO and IGSO: 4.2e7 m).
const MAX_APOGEE_M: f64 = 1e8;

fn check_kepler(i: usize, r: &KeplerRecord) -> Result<Verdict> {
    if r.sat.system == System::Glonass {
        return Err(record_error(
            "Keplerian",
            i,
            r.sat,
            "expected a GPS, Galileo, BeiDou or QZSS satellite, got GLONASS".into(),
        ));
    }
    let values = [
        ("af0", r.af[0]),
        ("af1", r.af[1]),
        ("af2", r.af[2]),
        ("crs", r.crs),
        ("delta_n", r.delta_n),
        ("m0", r.m0),
        ("cuc", r.cuc),
        ("e", r.e),
        ("cus", r.cus),
        ("sqrt_a", r.sqrt_a),
        ("cic", r.cic),
        ("omega0", r.omega0),
        ("cis", r.cis),
        ("i0", r.i0),
        ("crc", r.crc),
        ("omega", r.omega),
        ("omega_dot", r.omega_dot),
        ("idot", r.idot),
    ];
    if let Some((name, v)) = values.iter().find(|(_, v)| !v.is_finite()) {
        return Ok(Some((SkipReason::NotFinite, format!("{name} {v}"))));
    }
    // The numerics: Kepler's equation E - e sin E = M has one root for every M where 0 <= e < 1, and
    // the mean motion needs A > 0.
    if !(r.sqrt_a > 0.0 && (0.0..1.0).contains(&r.e)) {
        return Ok(Some((
            SkipReason::NotAnEllipse,
            format!("sqrt_a {} m^0.5, e {}", r.sqrt_a, r.e),
        )));
    }
    let a = r.sqrt_a * r.sqrt_a;
    let (perigee, apogee) = (a * (1.0 - r.e), a * (1.0 + r.e));
    // A perigee below the WGS-84 equatorial radius is inside the Earth.
    if perigee < WGS84_A_M || apogee > MAX_APOGEE_M {
        return Ok(Some((
            SkipReason::NotASatellite,
            format!(
                "sqrt_a {} m^0.5 and e {}: perigee {perigee:.4e} m, apogee {apogee:.4e} m",
                r.sqrt_a, r.e
            ),
        )));
    }
    // Rates and clock terms beyond these are not orbits or clocks of navigation satellites (a broadcast
    // af0 is below 1 ms in magnitude by its field width; 1 s bounds any misread).
    let rates = [
        ("delta_n", r.delta_n, 1e-6),
        ("omega_dot", r.omega_dot, 1e-6),
        ("idot", r.idot, 1e-6),
        ("af0", r.af[0], 1.0),
        ("af1", r.af[1], 1e-3),
        ("af2", r.af[2], 1e-3),
    ];
    if let Some((name, v, limit)) = rates.iter().find(|(_, v, l)| v.abs() > *l) {
        return Ok(Some((
            SkipReason::NotASatellite,
            format!("|{name}| {} > {limit:e}", v.abs()),
        )));
    }
    Ok(check_health_word(r.health))
}

fn check_glonass(i: usize, r: &GlonassRecord) -> Result<Verdict> {
    if r.sat.system != System::Glonass {
        return Err(record_error(
            "GLONASS",
            i,
            r.sat,
            "expected a GLONASS satellite".into(),
        ));
    }
    let all = r
        .position_m
        .iter()
        .chain(&r.velocity_m_s)
        .chain(&r.acceleration_m_s2)
        .chain([&r.clock_bias_s, &r.gamma_n]);
    if all.clone().any(|v| !v.is_finite()) {
        return Ok(Some((
            SkipReason::NotFinite,
            "state, acceleration or clock".into(),
        )));
    }
    let radius = Vector3::from(r.position_m).norm();
    let speed = Vector3::from(r.velocity_m_s).norm();
    let acc = Vector3::from(r.acceleration_m_s2).norm();
    if !(1e7..=1e8).contains(&radius) || speed > 1e4 || acc > 1e-3 {
        return Ok(Some((
            SkipReason::NotASatellite,
            format!(
                "|r| {radius:.6e} m, |v| {speed:.6e} m/s, luni-solar |a| {acc:.3e} m/s^2 (expected \
                 1e7..1e8 m, <= 1e4 m/s, <= 1e-3 m/s^2)"
            ),
        )));
    }
    if r.clock_bias_s.abs() > 1.0 || r.gamma_n.abs() > 1e-3 {
        return Ok(Some((
            SkipReason::NotASatellite,
            format!(
                "tau_n {} s, gamma_n {} (expected |tau_n| <= 1 s, |gamma_n| <= 1e-3)",
                r.clock_bias_s, r.gamma_n
            ),
        )));
    }
    Ok(check_health_word(r.health))
}

#[cfg(test)]
mod tests;
