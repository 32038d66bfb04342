//! Epoch lines of RINEX 2 and 3 observation files: flag, count, label and clock offset, with the checks
//! of the numbers and the calendar that the header reader (`gnssatt.rinex._fields`) makes.

use super::lines::{blank, is_digit, slice, strip, tail};
use super::obs_body::{err, quoted, BodyError};
use super::text::{py_float_repr, py_format_g};

/// Years a label may carry (`gnssatt.rinex._fields.YEARS`): datetime64[ns] holds 1678-2262.
const YEARS: (i64, i64) = (1980, 2200);
const FLAG_NAMES: &str =
    "0 (OK), 1 (power failure), 2-5 (events followed by special records) or 6 (cycle slip records)";

/// Column layout of an epoch line (0-based slices).
struct Layout {
    dates: [(usize, usize); 6],
    seps: [(usize, usize); 6],
    flag: usize,
    count: (usize, usize),
    clock: (usize, usize),
    shortest: usize,
}

const V3: Layout = Layout {
    dates: [(2, 6), (7, 9), (10, 12), (13, 15), (16, 18), (18, 29)],
    seps: [(1, 2), (6, 7), (9, 10), (12, 13), (15, 16), (29, 31)],
    flag: 31,
    count: (32, 35),
    clock: (41, 56),
    shortest: 35,
};
const V2: Layout = Layout {
    dates: [(1, 3), (4, 6), (7, 9), (10, 12), (13, 15), (15, 26)],
    seps: [(0, 1), (3, 4), (6, 7), (9, 10), (12, 13), (26, 28)],
    flag: 28,
    count: (29, 32),
    clock: (68, 80),
    shortest: 32,
};

pub struct EpochLine {
    pub flag: u8,
    pub count: usize,
    /// Nanoseconds since 1970 (GPST as written); None for an event epoch whose time is not significant.
    pub time_ns: Option<i64>,
    pub clock_s: f64,
}

/// `gnssatt.rinex._fields.integer`: digits with an optional sign between blanks.
pub fn integer(lineno: usize, text: &[u8], what: &str) -> Result<i64, BodyError> {
    let core = strip(text);
    let digits = core
        .strip_prefix(b"+")
        .or_else(|| core.strip_prefix(b"-"))
        .unwrap_or(core);
    let fail = || {
        err(
            lineno,
            format!("expected an integer for {what}, got {}", quoted(core)),
        )
    };
    if digits.is_empty() || !digits.iter().all(|&b| is_digit(b)) {
        return Err(fail());
    }
    std::str::from_utf8(core)
        .ok()
        .and_then(|s| s.parse::<i64>().ok())
        .ok_or_else(fail)
}

/// Length of a run of ASCII digits at the start of `s`.
fn digit_run(s: &[u8]) -> usize {
    s.iter().take_while(|&&b| is_digit(b)).count()
}

/// The value of a Fortran number (`D` or `E` exponent) with no blank around it, or None where `core` is
/// not one (`gnssatt.rinex._fields._NUMBER`: `[+-]?(?:\d+\.?\d*|\.\d+)(?:[EeDd][+-]?\d+)?`); an
/// overflow reads as infinity.
pub fn fortran(core: &[u8]) -> Option<f64> {
    let mut k = usize::from(matches!(core.first(), Some(b'+' | b'-')));
    let whole = digit_run(&core[k..]);
    k += whole;
    if core.get(k) == Some(&b'.') {
        let frac = digit_run(&core[k + 1..]);
        if whole == 0 && frac == 0 {
            return None;
        }
        k += 1 + frac;
    } else if whole == 0 {
        return None;
    }
    if matches!(core.get(k), Some(b'E' | b'e' | b'D' | b'd')) {
        let mut m = k + 1;
        m += usize::from(matches!(core.get(m), Some(b'+' | b'-')));
        let exp = digit_run(&core[m.min(core.len())..]);
        if exp == 0 {
            return None;
        }
        k = m + exp;
    }
    if k != core.len() {
        return None;
    }
    // Rust's parser takes `e` only: the number is copied with its `D` replaced (on the stack where short)
    let mut buf = [0u8; 40];
    let mut owned = Vec::new();
    let text: &mut [u8] = if core.len() <= buf.len() {
        let part = &mut buf[..core.len()];
        part.copy_from_slice(core);
        part
    } else {
        owned.extend_from_slice(core);
        &mut owned
    };
    for b in text.iter_mut() {
        if matches!(*b, b'D' | b'd') {
            *b = b'e';
        }
    }
    std::str::from_utf8(text).ok()?.parse().ok()
}

/// `gnssatt.rinex._fields.number`: a finite Fortran number (`D` or `E` exponent) between blanks.
pub fn number(lineno: usize, text: &[u8], what: &str) -> Result<f64, BodyError> {
    let core = strip(text);
    match fortran(core) {
        Some(value) if value.is_finite() => Ok(value),
        Some(_) => Err(err(
            lineno,
            format!("expected a finite number for {what}, got {}", quoted(core)),
        )),
        None => Err(err(
            lineno,
            format!("expected a number for {what}, got {}", quoted(core)),
        )),
    }
}

/// Days since 1970-01-01 of a proleptic Gregorian date, or None where it is not a date.
fn days_from_civil(y: i64, m: i64, d: i64) -> Option<i64> {
    if !(1..=12).contains(&m) {
        return None;
    }
    let leap = (y % 4 == 0 && y % 100 != 0) || y % 400 == 0;
    let month_days = [
        31,
        if leap { 29 } else { 28 },
        31,
        30,
        31,
        30,
        31,
        31,
        30,
        31,
        30,
        31,
    ];
    if d < 1 || d > month_days[(m - 1) as usize] {
        return None;
    }
    // Howard Hinnant's days_from_civil
    let y = if m <= 2 { y - 1 } else { y };
    let era = y.div_euclid(400);
    let yoe = y - era * 400;
    let mp = (m + 9) % 12;
    let doy = (153 * mp + 2) / 5 + d - 1;
    let doe = yoe * 365 + yoe / 4 - yoe / 100 + doy;
    Some(era * 146_097 + doe - 719_468)
}

fn civil_from_days(z: i64) -> (i64, i64, i64) {
    let z = z + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z - era * 146_097;
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let d = doy - (153 * mp + 2) / 5 + 1;
    let m = if mp < 10 { mp + 3 } else { mp - 9 };
    (yoe + era * 400 + i64::from(m <= 2), m, d)
}

/// numpy's `str(np.datetime64(ns, "ns"))`: `2024-03-01T00:00:00.000000000`.
pub fn datetime64_text(ns: i64) -> String {
    let day = ns.div_euclid(86_400_000_000_000);
    let rest = ns.rem_euclid(86_400_000_000_000);
    let (y, m, d) = civil_from_days(day);
    let secs = rest / 1_000_000_000;
    format!(
        "{y:04}-{m:02}-{d:02}T{:02}:{:02}:{:02}.{:09}",
        secs / 3600,
        secs / 60 % 60,
        secs % 60,
        rest % 1_000_000_000
    )
}

/// `gnssatt.rinex._fields.epoch_ns`: nanoseconds since 1970 of a calendar label, after checking that it
/// is one (seconds in [0, 60), up to 61 at 23:59 for a UTC leap second).
#[allow(clippy::too_many_arguments)]
pub(super) fn epoch_ns(
    lineno: usize,
    y: i64,
    mo: i64,
    d: i64,
    hh: i64,
    mi: i64,
    sec: f64,
) -> Result<i64, BodyError> {
    let label = format!("{y:04}-{mo:02}-{d:02} {hh:02}:{mi:02}:{}", py_format_g(sec));
    if !(YEARS.0..=YEARS.1).contains(&y) {
        return Err(err(
            lineno,
            format!(
                "epoch {label}: expected a year in {}-{}, got {y}",
                YEARS.0, YEARS.1
            ),
        ));
    }
    let Some(day) = days_from_civil(y, mo, d) else {
        return Err(err(
            lineno,
            format!("epoch {label}: not a calendar date (month {mo}, day {d})"),
        ));
    };
    if !((0..=23).contains(&hh) && (0..=59).contains(&mi)) {
        return Err(err(
            lineno,
            format!("epoch {label}: expected hour 0-23 and minute 0-59"),
        ));
    }
    let leap = hh == 23 && mi == 59;
    if !(0.0 <= sec && sec < if leap { 61.0 } else { 60.0 }) {
        let limit = if leap {
            "61 (a leap second at 23:59)"
        } else {
            "60 (61 only at 23:59, a leap second)"
        };
        return Err(err(
            lineno,
            format!(
                "epoch {label}: expected seconds in [0, {limit}), got {}",
                py_float_repr(sec)
            ),
        ));
    }
    Ok((day * 86_400 + hh * 3600 + mi * 60) * 1_000_000_000 + (sec * 1e9).round_ties_even() as i64)
}

/// The epoch (ns since 1970 of its label) written on the epoch line `line` (1-based `lineno`) in the
/// columns of layout `l` (RINEX 2: a two-digit year, 1980-2079).
fn epoch_time(lineno: usize, line: &[u8], l: &Layout, v3: bool) -> Result<i64, BodyError> {
    let mut ymdhm = [0i64; 5];
    for (value, &(a, b)) in ymdhm.iter_mut().zip(&l.dates[..5]) {
        *value = integer(lineno, slice(line, a, b), "the epoch")?;
    }
    let sec = number(
        lineno,
        slice(line, l.dates[5].0, l.dates[5].1),
        "the epoch seconds",
    )?;
    let [mut y, mo, d, hh, mi] = ymdhm;
    if !v3 {
        if !(0..=99).contains(&y) {
            return Err(err(lineno, format!("expected a two-digit year, got {y}")));
        }
        y += if y >= 80 { 1900 } else { 2000 };
    }
    epoch_ns(lineno, y, mo, d, hh, mi, sec)
}

/// Flag, count, label and clock offset (NaN where blank) of the epoch line `line` (1-based `lineno`).
pub fn epoch_line(lineno: usize, line: &[u8], v3: bool) -> Result<EpochLine, BodyError> {
    let l = if v3 { &V3 } else { &V2 };
    if line.len() < l.shortest {
        return Err(err(
            lineno,
            format!(
                "epoch line cut short: expected at least {} columns, got {}",
                l.shortest,
                line.len()
            ),
        ));
    }
    let flag_byte = line[l.flag];
    if !(b'0'..=b'6').contains(&flag_byte) {
        return Err(err(
            lineno,
            format!(
                "unknown epoch flag {}: expected {FLAG_NAMES}",
                quoted(&line[l.flag..=l.flag])
            ),
        ));
    }
    let flag = flag_byte - b'0';
    let n = integer(
        lineno,
        slice(line, l.count.0, l.count.1),
        "the number of satellites (or special records)",
    )?;
    if n < 0 {
        return Err(err(
            lineno,
            format!("expected a number of satellites >= 0, got {n}"),
        ));
    }
    // RINEX 3/4: the offset (F15.12, columns 42-56) ends the line; take all after the count so that a
    // writer one column off (gLAB writes the count as I2) cannot cut the sign from the number
    let clk_text = if v3 {
        tail(line, l.count.1)
    } else {
        slice(line, l.clock.0, l.clock.1)
    };
    let clock_s = if blank(clk_text) {
        f64::NAN
    } else {
        number(lineno, clk_text, "the receiver clock offset")?
    };
    let date_area = slice(line, l.dates[0].0, l.dates[5].1);
    let count = n as usize;
    if (2..=5).contains(&flag) && blank(date_area) {
        return Ok(EpochLine {
            flag,
            count,
            time_ns: None,
            clock_s,
        });
    }
    if !l.seps.iter().all(|&(a, b)| blank(slice(line, a, b))) {
        return Err(err(
            lineno,
            format!(
                "expected an epoch 'yyyy mm dd hh mm ss.sssssss', got {}",
                quoted(date_area)
            ),
        ));
    }
    let time_ns = Some(epoch_time(lineno, line, l, v3)?);
    Ok(EpochLine {
        flag,
        count,
        time_ns,
        clock_s,
    })
}

/// Whether `line` starts like an epoch line (RINEX 3: `>`; RINEX 2: a two-digit-year label, flag and
/// count), to tell a file cut inside its last epoch from an epoch that announces more records than follow.
pub fn starts_epoch(line: &[u8], v3: bool) -> bool {
    if v3 {
        return line.first() == Some(&b'>');
    }
    // ' [ \d]\d [ \d]\d [ \d]\d [ \d]\d [ \d]\d [ \d]\d\.\d{7}  [0-6][ \d]{2}\d'
    const PATTERN: &[u8] = b" sd sd sd sd sd sd.ddddddd  fssd";
    line.len() >= PATTERN.len()
        && PATTERN.iter().zip(line).all(|(&p, &b)| match p {
            b's' => b == b' ' || is_digit(b),
            b'd' => is_digit(b),
            b'f' => (b'0'..=b'6').contains(&b),
            _ => b == p,
        })
}

/// Whether `line` continues a RINEX 2 satellite list (32 blanks, then satellites `[A-Z ][ \d]\d`, then
/// blanks): a fullmatch of `" {32}(?:[A-Z ][ \d]\d)+ *"`.
pub fn continues_sat_list(line: &[u8]) -> bool {
    if line.len() < 35 || !line[..32].iter().all(|&b| b == b' ') {
        return false;
    }
    let end = line.iter().rposition(|&b| b != b' ').map_or(0, |k| k + 1);
    let sats = &line[32..end.max(32)];
    !sats.is_empty()
        && sats.len().is_multiple_of(3)
        && sats.chunks(3).all(|t| {
            (t[0].is_ascii_uppercase() || t[0] == b' ')
                && (t[1] == b' ' || is_digit(t[1]))
                && is_digit(t[2])
        })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn calendar_round_trips() {
        for (y, m, d) in [
            (1970, 1, 1),
            (2000, 2, 29),
            (2024, 3, 1),
            (2200, 12, 31),
            (1980, 1, 6),
        ] {
            let day = days_from_civil(y, m, d).unwrap();
            assert_eq!(civil_from_days(day), (y, m, d));
        }
        assert_eq!(days_from_civil(1970, 1, 1), Some(0));
        // 1980-01-06, the GPS epoch, is day 3657 (10 years of 365 days, 2 leap days, 5 days)
        assert_eq!(days_from_civil(1980, 1, 6), Some(3657));
        assert_eq!(days_from_civil(2023, 2, 29), None);
        assert_eq!(days_from_civil(2024, 13, 1), None);
        assert_eq!(datetime64_text(0), "1970-01-01T00:00:00.000000000");
    }

    #[test]
    fn numbers_follow_the_fortran_grammar() {
        assert_eq!(number(1, b" 1.5D+01 ", "x").unwrap(), 15.0);
        assert_eq!(number(1, b"-.5", "x").unwrap(), -0.5);
        assert_eq!(number(1, b"3.", "x").unwrap(), 3.0);
        for bad in [
            &b"nan"[..],
            b"inf",
            b"1e999",
            b".",
            b"1E",
            b"1_0",
            b"",
            b"1 2",
        ] {
            assert!(number(1, bad, "x").is_err(), "{bad:?}");
        }
        assert_eq!(integer(1, b" -12", "x").unwrap(), -12);
        assert!(integer(1, b"1.0", "x").is_err());
    }
}
