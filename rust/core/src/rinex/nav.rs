//! RINEX 2.xx, 3.xx and 4.xx navigation files: the header values the engine uses (version, Klobuchar
//! coefficients, leap seconds) and the broadcast records, Keplerian (G, E, C, J) and GLONASS, parsed from
//! the decompressed bytes of the file. Opening, decompression and the conversion of the records into
//! GPST arrays stay in Python (`gnssatt.rinex.nav`).
//!
//! The order of the checks is part of the behaviour (the first fault met is the one reported), and the
//! messages are those of the Python reader this replaced, word for word: a fault the Python reader met
//! as an `IndexError` or `OverflowError` (a record start shorter than its separators, an empty line after
//! a RINEX 4 marker, a sqrt(A) whose square overflows) reads as the message its guard wrote for those.

use super::epoch::{epoch_ns, fortran, integer, number};
use super::lines::{blank, is_space, slice, split_lines, strip, tail};
use super::obs_body::{err, quoted, BodyError};
use super::text::{py_float_repr, py_format_g};
use crate::gnss::geometry::WGS84_A_M;

/// Values of a Keplerian record: af0-af2, then the 26 fields of its broadcast orbit lines
/// (`gnssatt.rinex.nav.KEPLER_FIELDS`).
pub const KEPLER_VALUES: usize = 29;
/// Values of a GLONASS record: clock bias, gamma_n, message frame time, then 12 orbit fields.
pub const GLONASS_VALUES: usize = 15;

/// Why a record was left out (the caller words the warning).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum NavSkip {
    /// A Keplerian record whose perigee a (1 - e) is below the Earth's equatorial radius.
    NotAnOrbit,
    /// The last record, cut by the end of the file.
    CutRecord,
}

/// The records of a navigation file, in file order, repeated ones included.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct NavRecords {
    /// Row-major (records x `KEPLER_VALUES`).
    pub kepler_values: Vec<f64>,
    pub kepler_sats: Vec<String>,
    /// Time of clock as written (ns since 1970 of the label, in the record's system time).
    pub kepler_toc_ns: Vec<i64>,
    /// Row-major (records x `GLONASS_VALUES`).
    pub glonass_values: Vec<f64>,
    pub glonass_sats: Vec<String>,
    /// Reference time as written (UTC label, ns since 1970).
    pub glonass_tb_ns: Vec<i64>,
    /// GPS Klobuchar alpha and beta (NaN where the file gives none).
    pub iono_alpha: [f64; 4],
    pub iono_beta: [f64; 4],
    pub leap_seconds: Option<i64>,
    /// Records of messages or systems not read, per `"<type> <system> <message>"`, in order of first
    /// appearance.
    pub unused: Vec<(String, u64)>,
    /// Records left out, each with its description for the warning.
    pub skips: Vec<(NavSkip, String)>,
    /// Lines of the file.
    pub lines: usize,
}

/// The text of `s` as Python holds it (a byte of 0x80 or above is U+FFFD).
fn decoded(s: &[u8]) -> String {
    s.iter()
        .map(|&b| if b < 0x80 { b as char } else { '\u{fffd}' })
        .collect()
}

/// The message of the Python reader's guard for an exception other than its own errors.
fn crashed(line: usize, what: &str) -> BodyError {
    err(
        line,
        format!("cannot read this line ({what}); the file is malformed"),
    )
}

const INDEX_ERROR: &str = "IndexError: string index out of range";

/// Record-start layout (0-based slices): year, month, day, hour, minute, second; separators; first field.
struct Head {
    dates: [(usize, usize); 6],
    seps: &'static [usize],
    first_field: usize,
}

const HEAD_V3: Head = Head {
    dates: [(4, 8), (9, 11), (12, 14), (15, 17), (18, 20), (21, 23)],
    seps: &[3, 8, 11, 14, 17, 20],
    first_field: 23,
};
const HEAD_V2: Head = Head {
    dates: [(3, 5), (6, 8), (9, 11), (12, 14), (15, 17), (17, 22)],
    seps: &[2, 5, 8, 11, 14],
    first_field: 22,
};

/// RINEX 4 ephemeris messages read, per system (the others are counted and skipped: the engine uses the
/// legacy messages only).
fn v4_message_read(system: &[u8], message: &[u8]) -> bool {
    let read: &[&[u8]] = match system {
        b"G" | b"J" => &[b"LNAV"],
        b"E" => &[b"INAV", b"FNAV"],
        b"C" => &[b"D1", b"D2"],
        b"R" => &[b"FDMA"],
        _ => &[],
    };
    read.contains(&message)
}

/// Lines of a record per system letter (GLONASS: 5 lines from RINEX 3.05 on).
fn record_lines(system: u8) -> Option<usize> {
    match system {
        b'G' | b'E' | b'C' | b'J' | b'I' => Some(8),
        b'S' | b'R' => Some(4),
        _ => None,
    }
}

/// `count` D19.12 fields from column `start` appended to `out`; a blank field is 0, a field the line
/// ends inside is refused (a cut number would read as another value).
fn values(
    lineno: usize,
    line: &[u8],
    start: usize,
    count: usize,
    out: &mut Vec<f64>,
) -> Result<(), BodyError> {
    for k in 0..count {
        let text = slice(line, start + 19 * k, start + 19 * (k + 1));
        if blank(text) {
            out.push(0.0);
            continue;
        }
        if text.len() < 19 {
            return Err(err(
                lineno,
                format!(
                    "the line ends inside broadcast field {} (a field cut short)",
                    k + 1
                ),
            ));
        }
        // the message is written only for a field refused
        out.push(match fortran(strip(text)) {
            Some(v) if v.is_finite() => v,
            _ => number(lineno, text, &format!("broadcast field {}", k + 1))?,
        });
    }
    Ok(())
}

/// Refuse a broadcast value that must be an integer in [lo, hi].
fn whole(lineno: usize, value: f64, lo: f64, hi: f64, what: &str) -> Result<(), BodyError> {
    if value.fract() != 0.0 || !(lo..=hi).contains(&value) {
        return Err(err(
            lineno,
            format!(
                "expected {what} as a whole number in [{lo}, {hi}], got {}",
                py_float_repr(value)
            ),
        ));
    }
    Ok(())
}

/// Count one record under `key`, keeping the order of first appearance.
fn count_unused(unused: &mut Vec<(String, u64)>, key: String) {
    match unused.iter_mut().find(|(k, _)| *k == key) {
        Some((_, n)) => *n += 1,
        None => unused.push((key, 1)),
    }
}

/// The header: version, RINEX 2 system, Klobuchar coefficients, leap seconds and the first body line.
struct Header {
    version: f64,
    v2_system: u8,
    body: usize,
}

/// The version and (RINEX 2) the system of a navigation file from its first line.
fn version_and_type(lines: &[&[u8]]) -> Result<(f64, u8), BodyError> {
    if lines.is_empty() || strip(slice(lines[0], 60, 80)) != b"RINEX VERSION / TYPE" {
        return Err(err(
            1,
            "expected 'RINEX VERSION / TYPE' in columns 61-80".into(),
        ));
    }
    let version = number(1, slice(lines[0], 0, 9), "the RINEX version")?;
    if !(2.0..5.0).contains(&version) {
        return Err(err(
            1,
            format!(
                "unknown navigation file version {}: expected 2.xx, 3.xx or 4.xx",
                py_float_repr(version)
            ),
        ));
    }
    let ftype = slice(lines[0], 20, 21);
    let v2_type = match ftype {
        b"N" => Some(b'G'),
        b"G" => Some(b'R'),
        b"E" => Some(b'E'),
        b"H" => Some(b'S'),
        _ => None,
    };
    if version < 3.0 && v2_type.is_none() {
        return Err(err(
            1,
            format!(
                "expected a GPS ('N'), GLONASS ('G'), Galileo ('E') or SBAS ('H') navigation file, got \
                 type {}",
                quoted(ftype)
            ),
        ));
    }
    if version >= 3.0 && ftype != b"N" {
        return Err(err(
            1,
            format!(
                "expected a navigation file (type 'N'), got {}",
                quoted(ftype)
            ),
        ));
    }
    Ok((version, v2_type.unwrap_or(b'G')))
}

fn header(
    lines: &[&[u8]],
    header_labels: &[String],
    nav: &mut NavRecords,
) -> Result<Header, BodyError> {
    let label = |l: &[u8]| strip(slice(l, 60, 80)).to_vec();
    let (version, v2_system) = version_and_type(lines)?;
    let mut last_known = 1;
    for (i, &line) in lines.iter().enumerate().skip(1) {
        let lab = label(line);
        if header_labels.iter().any(|h| h.as_bytes() == lab.as_slice()) {
            last_known = i + 1;
        }
        let four = |first: usize, what: &str| -> Result<[f64; 4], BodyError> {
            let mut v = [0.0; 4];
            for (k, x) in v.iter_mut().enumerate() {
                *x = number(
                    i + 1,
                    slice(line, first + 12 * k, first + 12 + 12 * k),
                    what,
                )?;
            }
            Ok(v)
        };
        match lab.as_slice() {
            b"END OF HEADER" => {
                return Ok(Header {
                    version,
                    v2_system,
                    body: i + 1,
                })
            }
            // a Galileo file's ION ALPHA holds NeQuick's three
            b"ION ALPHA" if v2_system == b'G' => nav.iono_alpha = four(2, "ION ALPHA")?,
            b"ION BETA" if v2_system == b'G' => nav.iono_beta = four(2, "ION BETA")?,
            b"IONOSPHERIC CORR" if matches!(slice(line, 0, 4), b"GPSA" | b"GPSB") => {
                let v = four(5, "IONOSPHERIC CORR")?;
                if line[3] == b'A' {
                    nav.iono_alpha = v;
                } else {
                    nav.iono_beta = v;
                }
            }
            b"LEAP SECONDS" => {
                nav.leap_seconds = Some(integer(i + 1, slice(line, 0, 6), "LEAP SECONDS")?)
            }
            _ => {}
        }
    }
    Err(err(
        (last_known + 1).min(lines.len()),
        "missing header line 'END OF HEADER': expected it here, after the last line with a known header \
         label"
            .into(),
    ))
}

/// Alpha and beta of a RINEX 4 `> ION G.. LNAV` record (marker at 0-based `i`, next marker at `end`): an
/// epoch with alpha0-2, then alpha3 and beta0-2, then beta3 and the region flag.
fn v4_klobuchar(lines: &[&[u8]], i: usize, end: usize) -> Result<([f64; 4], [f64; 4]), BodyError> {
    if end - i < 4 {
        return Err(err(
            i + 1,
            format!("a GPS ION record has 3 lines, this one {}", end - i - 1),
        ));
    }
    let mut v = Vec::with_capacity(8);
    values(i + 2, lines[i + 1], 23, 3, &mut v)?;
    values(i + 3, lines[i + 2], 4, 4, &mut v)?;
    values(i + 4, lines[i + 3], 4, 1, &mut v)?;
    Ok(([v[0], v[1], v[2], v[3]], [v[4], v[5], v[6], v[7]]))
}

/// One record parsed (the part of the walk whose faults in the last line of a file without a final
/// line end mean that the file was cut there).
enum Parsed {
    Record(Record),
    /// The record runs past the end of the file: the description for the warning.
    Cut(String),
}

/// A record's start and values, before the checks of its system.
struct Record {
    system: u8,
    sat: String,
    n_lines: usize,
    toc_ns: i64,
    values: Vec<f64>,
}

/// What a RINEX 4 record marker is followed by.
enum Marker {
    /// A record the reader reads, on the next line.
    Record,
    /// Something else, skipped (or the Klobuchar values, read): the walk goes on at the next marker.
    Next(usize),
}

/// A fault inside a record: one of the reader's own (a file cut inside its last line may explain it),
/// or one its Python predecessor met as an exception of the language (never explained by a cut).
enum Fault {
    Rinex(BodyError),
    Crash(BodyError),
}

impl From<BodyError> for Fault {
    fn from(e: BodyError) -> Self {
        Fault::Rinex(e)
    }
}

struct Walk<'a> {
    lines: &'a [&'a [u8]],
    v3: bool,
    glonass_lines: usize,
    v2_system: u8,
    head: &'static Head,
    start: usize,
    /// The line the Python reader's guard would name (1-based).
    cursor: usize,
}

impl Walk<'_> {
    /// The time of clock of the record starting with `line` (its 1-based `lineno`), ns of its label.
    fn toc_ns(&self, lineno: usize, line: &[u8]) -> Result<i64, Fault> {
        let h = self.head;
        let bad_start = || {
            err(
                lineno,
                format!(
                    "expected a record start 'sat yy mm dd hh mm ss', got {}",
                    quoted(slice(line, 0, 23))
                ),
            )
        };
        for &c in h.seps {
            match line.get(c) {
                None => return Err(Fault::Crash(crashed(self.cursor, INDEX_ERROR))),
                Some(&b' ') => {}
                Some(_) => return Err(bad_start().into()),
            }
        }
        if line.len() < h.first_field {
            return Err(bad_start().into());
        }
        let mut ymdhm = [0i64; 5];
        for (v, &(a, b)) in ymdhm.iter_mut().zip(&h.dates[..5]) {
            *v = integer(lineno, slice(line, a, b), "the epoch")?;
        }
        let (a, b) = h.dates[5];
        let sec = number(lineno, slice(line, a, b), "the epoch seconds")?;
        let [mut y, mo, d, hh, mi] = ymdhm;
        if !self.v3 {
            if !(0..=99).contains(&y) {
                return Err(err(lineno, format!("expected a two-digit year, got {y}")).into());
            }
            y += if y >= 80 { 1900 } else { 2000 };
        }
        Ok(epoch_ns(lineno, y, mo, d, hh, mi, sec)?)
    }

    /// The record starting at 0-based line `i`: its satellite, lines, time of clock and values.
    fn record(&mut self, i: usize) -> Result<Parsed, Fault> {
        let (lines, n, lineno) = (self.lines, self.lines.len(), i + 1);
        let line = lines[i];
        let (system, prn) = if self.v3 {
            let Some(&system) = line.first() else {
                return Err(Fault::Crash(crashed(self.cursor, INDEX_ERROR)));
            };
            (
                system,
                integer(lineno, slice(line, 1, 3), "the satellite number")?,
            )
        } else {
            (
                self.v2_system,
                integer(lineno, slice(line, 0, 2), "the satellite number")?,
            )
        };
        let Some(mut n_lines) = record_lines(system) else {
            return Err(err(
                lineno,
                format!(
                    "unknown satellite system {} in a navigation record",
                    quoted(&[system])
                ),
            )
            .into());
        };
        if !(1..=99).contains(&prn) {
            return Err(err(
                lineno,
                format!("expected a satellite number 1-99, got {prn}"),
            )
            .into());
        }
        if system == b'R' {
            n_lines = self.glonass_lines;
        }
        let sat = format!("{}{prn:02}", system as char);
        if i + n_lines > n {
            return Ok(Parsed::Cut(format!(
                "{sat} at line {lineno} ({} of its {n_lines} lines)",
                n - i
            )));
        }
        let start = self.start;
        for q in 1..n_lines {
            if !blank(slice(lines[i + q], 0, start)) {
                return Err(err(
                    lineno,
                    format!(
                        "the record has {q} line(s), but a {} record has {n_lines}: line {} does not \
                         continue it (columns 1-{start} not blank)",
                        system as char,
                        lineno + q
                    ),
                )
                .into());
            }
        }
        let toc_ns = self.toc_ns(lineno, line)?;
        let mut vals = Vec::with_capacity(3 + 4 * (n_lines - 1));
        values(lineno, line, self.head.first_field, 3, &mut vals)?;
        for q in 1..n_lines {
            self.cursor = lineno + q;
            values(lineno + q, lines[i + q], start, 4, &mut vals)?;
        }
        Ok(Parsed::Record(Record {
            system,
            sat,
            n_lines,
            toc_ns,
            values: vals,
        }))
    }
}

/// The RINEX 4 record marker at 0-based line `i` (`> EPH G01 LNAV`): a record the reader reads follows,
/// or the walk goes on at the next marker (the Klobuchar values of the first GPS ION record are read; other
/// records are counted as unused).
fn v4_marker(lines: &[&[u8]], i: usize, nav: &mut NavRecords) -> Result<Marker, BodyError> {
    let (n, line, marker_line) = (lines.len(), lines[i], i + 1);
    if line[0] != b'>' {
        return Err(err(
            marker_line,
            format!(
                "expected a record marker such as '> EPH G01 LNAV', got {}",
                quoted(slice(line, 0, 40))
            ),
        ));
    }
    let mut words = tail(line, 1)
        .split(|&b| is_space(b))
        .filter(|w| !w.is_empty());
    let kind = words.next().unwrap_or(b"");
    let sat4 = words.next().unwrap_or(b"");
    let message = words.next().unwrap_or(b"");
    let system = slice(sat4, 0, 1);
    let mut end = i + 1;
    while end < n && !lines[end].starts_with(b">") {
        end += 1;
    }
    if kind == b"EPH" && v4_message_read(system, message) {
        if end == i + 1 {
            return Err(err(
                marker_line,
                format!(
                    "the record marker {} has no record after it",
                    quoted(strip(line))
                ),
            ));
        }
        Ok(Marker::Record)
    } else {
        if kind == b"ION" && system == b"G" && message == b"LNAV" && nav.iono_alpha[0].is_nan() {
            (nav.iono_alpha, nav.iono_beta) = v4_klobuchar(lines, i, end)?;
        } else {
            let key = format!("{} {} {}", decoded(kind), decoded(system), decoded(message));
            count_unused(&mut nav.unused, key);
        }
        Ok(Marker::Next(end))
    }
}

/// Record `rec` (its first line 1-based `lineno`, the Python guard's line `cursor`) checked for its
/// system and appended to `nav`, or skipped (with a note) or counted as unused.
fn store(nav: &mut NavRecords, rec: Record, lineno: usize, cursor: usize) -> Result<(), BodyError> {
    let Record {
        system,
        sat,
        toc_ns,
        values: vals,
        ..
    } = rec;
    match system {
        b'S' => count_unused(&mut nav.unused, "EPH S SBAS".into()),
        b'I' => count_unused(&mut nav.unused, "EPH I LNAV".into()),
        b'R' => {
            let orbit = &vals[3..];
            whole(
                lineno + 2,
                orbit[7],
                -7.0,
                13.0,
                "the GLONASS frequency channel",
            )?;
            nav.glonass_values
                .extend_from_slice(&vals[..GLONASS_VALUES]);
            nav.glonass_sats.push(sat);
            nav.glonass_tb_ns.push(toc_ns);
        }
        _ => store_kepler(nav, sat, toc_ns, &vals, lineno, cursor)?,
    }
    Ok(())
}

/// A Keplerian record (G, E, C, J) appended to `nav`: a shape that is not an ellipse refused, an ellipse
/// inside the Earth skipped with a note.
fn store_kepler(
    nav: &mut NavRecords,
    sat: String,
    toc_ns: i64,
    vals: &[f64],
    lineno: usize,
    cursor: usize,
) -> Result<(), BodyError> {
    let orbit = &vals[3..];
    let (sqrt_a, e) = (orbit[7], orbit[5]);
    // (NaN, which `number` never gives, would be refused too)
    if sqrt_a.is_nan() || sqrt_a <= 0.0 {
        return Err(err(
            lineno + 2,
            format!(
                "expected sqrt(A) > 0 m^0.5 (broadcast field 4), got {}",
                py_float_repr(sqrt_a)
            ),
        ));
    }
    if !(0.0..1.0).contains(&e) {
        return Err(err(
            lineno + 2,
            format!(
                "expected an eccentricity in [0, 1) (broadcast field 2), got {}",
                py_float_repr(e)
            ),
        ));
    }
    let a = sqrt_a * sqrt_a;
    if a.is_infinite() {
        return Err(crashed(
            cursor,
            "OverflowError: (34, 'Numerical result out of range')",
        ));
    }
    // A perigee below the equatorial radius is inside the Earth.
    if a * (1.0 - e) < WGS84_A_M {
        nav.skips.push((
            NavSkip::NotAnOrbit,
            format!(
                "{sat} at line {lineno} (sqrt(A) {} m^0.5, e {})",
                py_format_g(sqrt_a),
                py_format_g(e)
            ),
        ));
        return Ok(());
    }
    whole(lineno + 5, orbit[18], 0.0, 9999.0, "the week")?;
    if !(0.0..=604_800.0).contains(&orbit[8]) {
        return Err(err(
            lineno + 3,
            format!(
                "expected a time of ephemeris in [0, 604800] s, got {}",
                py_float_repr(orbit[8])
            ),
        ));
    }
    nav.kepler_values.extend_from_slice(&vals[..KEPLER_VALUES]);
    nav.kepler_sats.push(sat);
    nav.kepler_toc_ns.push(toc_ns);
    Ok(())
}

impl<'a> Walk<'a> {
    /// The walk over the body of a file of `lines` with header `hdr`, at its first body line.
    fn new(lines: &'a [&'a [u8]], hdr: &Header) -> Self {
        let version = hdr.version;
        let v3 = version >= 3.0;
        Walk {
            lines,
            v3,
            glonass_lines: if version >= 3.05 { 5 } else { 4 },
            v2_system: hdr.v2_system,
            head: if v3 { &HEAD_V3 } else { &HEAD_V2 },
            start: if v3 { 4 } else { 3 },
            cursor: hdr.body,
        }
    }
}

/// A fault `e` in the record starting with `line` (1-based `lineno`) of a file of `n` lines, `ended`
/// when its last line has a line end: the skip of a record cut by the end of the file when the file has
/// no line end and the fault is in its last line (the file was cut inside it), else `e` itself.
fn cut_in_last_line(
    e: BodyError,
    ended: bool,
    n: usize,
    lineno: usize,
    line: &[u8],
) -> Result<(NavSkip, String), BodyError> {
    let BodyError::Malformed {
        line: Some(at),
        message,
    } = &e
    else {
        return Err(e);
    };
    if ended || *at != n {
        return Err(e);
    }
    Ok((
        NavSkip::CutRecord,
        format!(
            "{} at line {lineno} (line {n} is cut: {message})",
            decoded(strip(slice(line, 0, 3)))
        ),
    ))
}

/// Reads the navigation file `text` (decompressed). `header_labels` are the labels of RINEX 2.11, 3.05
/// and 4.00 (`gnssatt.rinex._fields.HEADER_LABELS`): where `END OF HEADER` is missing, the fault is
/// reported after the last of them.
///
/// # Errors
/// The first fault of the file (1-based line and message), in the order the checks are made.
pub fn read_nav(text: &[u8], header_labels: &[String]) -> Result<NavRecords, BodyError> {
    let (lines, ended) = split_lines(text);
    let n = lines.len();
    let mut nav = NavRecords {
        iono_alpha: [f64::NAN; 4],
        iono_beta: [f64::NAN; 4],
        lines: n,
        ..NavRecords::default()
    };
    let hdr = header(&lines, header_labels, &mut nav)?;
    let version = hdr.version;
    let mut walk = Walk::new(&lines, &hdr);
    let mut i = hdr.body;
    while i < n {
        let mut line = lines[i];
        let marker_line = i + 1;
        walk.cursor = marker_line;
        if blank(line) {
            i += 1;
            continue;
        }
        if version >= 4.0 {
            match v4_marker(&lines, i, &mut nav)? {
                Marker::Record => {
                    i += 1; // the record follows in the layout of RINEX 3
                    line = lines[i];
                }
                Marker::Next(end) => {
                    i = end;
                    continue;
                }
            }
        }
        let lineno = i + 1;
        let parsed = match walk.record(i) {
            Ok(p) => p,
            Err(Fault::Crash(e)) => return Err(e),
            Err(Fault::Rinex(e)) => {
                nav.skips.push(cut_in_last_line(e, ended, n, lineno, line)?);
                break;
            }
        };
        let rec = match parsed {
            Parsed::Cut(what) => {
                // the last record, cut by the end of the file: the records before it are complete
                nav.skips.push((NavSkip::CutRecord, what));
                break;
            }
            Parsed::Record(rec) => rec,
        };
        let n_lines = rec.n_lines;
        store(&mut nav, rec, lineno, walk.cursor)?;
        i += n_lines;
    }
    Ok(nav)
}

#[cfg(test)]
#[path = "nav_tests.rs"]
mod tests;
