//! GPST nanosecond time labels: differences in seconds and seconds of week of each system's time scale.
//!
//! Times stay integer nanoseconds since the GPS epoch so that differences of large times are exact; a
//! small float offset (a light time, a clock) is added in seconds only after the difference.

use super::signal::System;

/// Nanoseconds per second.
pub const NS_PER_S: i64 = 1_000_000_000;
/// Nanoseconds per week.
pub const WEEK_NS: i64 = 604_800 * NS_PER_S;
/// BDT = GPST - 14 s (BDS-SIS-ICD 3.2: BDT started at 2006-01-01 00:00:00 UTC, GPST - UTC was 14 s).
pub const BDT_MINUS_GPST_NS: i64 = -14 * NS_PER_S;

/// `a - b` in seconds (exact in i128, then one rounding to f64). The difference of two times of one
/// session fits an i64, whose conversion rounds the same integer the same way and costs a tenth of the
/// i128 one (the record choice of every satellite state takes several).
#[inline]
pub fn seconds_between(a_ns: i64, b_ns: i64) -> f64 {
    match a_ns.checked_sub(b_ns) {
        Some(d) => d as f64 * 1e-9,
        None => (i128::from(a_ns) - i128::from(b_ns)) as f64 * 1e-9,
    }
}

/// Seconds of week of GPST instant `t_gpst_ns` in the time scale of `system` (GPS, Galileo and QZSS
/// weeks start with the GPS week; BeiDou's 14 s later; GLONASS: GPST seconds of week).
pub fn seconds_of_week(system: System, t_gpst_ns: i64) -> f64 {
    let t = match system {
        System::BeiDou => t_gpst_ns.saturating_add(BDT_MINUS_GPST_NS),
        _ => t_gpst_ns,
    };
    t.rem_euclid(WEEK_NS) as f64 * 1e-9
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn week_seconds_of_each_scale() {
        // 2021-01-01 00:00:14 GPST = week 2138, Friday: 5 days + 14 s = 432014 s GPST; BDT 432000 s
        // (CBW1 C05 record: toe 432000 s of BDT week 782).
        let t = 2138 * WEEK_NS + 432_014 * NS_PER_S;
        assert_eq!(seconds_of_week(System::Gps, t), 432_014.0);
        assert_eq!(seconds_of_week(System::BeiDou, t), 432_000.0);
        // Just after the GPS week boundary BDT is still in the previous week.
        assert_eq!(seconds_of_week(System::BeiDou, 2138 * WEEK_NS), 604_786.0);
        assert_eq!(seconds_between(3 * NS_PER_S, 5 * NS_PER_S), -2.0);
        assert_eq!(seconds_between(i64::MAX, i64::MIN), 2f64.powi(64) * 1e-9);
    }
}
