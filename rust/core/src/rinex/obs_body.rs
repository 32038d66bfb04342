//! The walk over the epochs of an observation body: epoch lines, satellite lists (RINEX 2 continuation
//! lines), event records and the observation records, then the fields of every record converted into the
//! dense arrays (epochs x satellites x codes) that `gnssatt.rinex.RinexObs` holds.
//!
//! The order of the checks is part of the behaviour: the structure of the whole file is checked first
//! (the first structural fault is reported), then the fields, system by system in the order the systems
//! first appear; a file cut inside its last epoch (by the end of the file, or without a line end inside a
//! field) gives the epochs before it and a note for the caller's warning.

use super::epoch::{continues_sat_list, datetime64_text, epoch_line, starts_epoch};
use super::lines::{blank, push_padded, rstrip, rstrip_blanks, slice, split_lines, strip, tail};
use super::obs_fields::field;
use super::text::py_repr;

const SYSTEMS: &[u8] = b"GRESJCI";
/// Header records that change the layout or scaling of the observation records after them.
const LAYOUT_LABELS: [&[u8]; 3] = [
    b"SYS / # / OBS TYPES",
    b"# / TYPES OF OBSERV",
    b"SYS / SCALE FACTOR",
];

/// How the records of one system are laid out (RINEX 2: one layout, key `*`, for every system).
#[derive(Clone, Debug)]
pub struct SystemLayout {
    /// System letter (`b'G'`), or `b'*'` for the one layout of a RINEX 2 file.
    pub key: u8,
    /// Observation fields of a record (every code of the header's types line, used or not).
    pub n_fields: usize,
    /// The fields read (0-based, increasing); the others are read past unparsed.
    pub keep: Vec<usize>,
    /// For each kept field, its index on the last axis of the dense arrays.
    pub columns: Vec<usize>,
    /// For each kept field, the `SYS / SCALE FACTOR` the values are divided by (1 where none).
    pub factors: Vec<f64>,
}

/// What the header says about the body.
#[derive(Clone, Debug)]
pub struct BodyOptions {
    pub v3: bool,
    /// The system of a RINEX 2 satellite field with a blank letter (`G` for mixed files).
    pub default_system: u8,
    pub layouts: Vec<SystemLayout>,
    /// Length of the last axis of the dense arrays (the union of the used codes).
    pub n_codes: usize,
    /// Header labels of RINEX 2.11, 3.05 and 4.00 (`gnssatt.rinex._fields.HEADER_LABELS`), for the
    /// records of event epochs.
    pub header_labels: Vec<String>,
    /// Most epochs x satellites x codes the dense arrays may hold.
    pub max_cells: u64,
    /// Index (0-based) of the first line after `END OF HEADER`.
    pub first_line: usize,
}

/// The epochs of a body and their records as dense arrays (row-major epochs x satellites x codes).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ObsBody {
    pub time_ns: Vec<i64>,
    pub flag: Vec<u8>,
    pub clock_s: Vec<f64>,
    /// Satellite ids (`G03`), sorted.
    pub sats: Vec<String>,
    pub data: Vec<f64>,
    pub lli: Vec<u8>,
    pub ssi: Vec<u8>,
    /// Where the file ends inside its last epoch (left out): the record for the caller's warning.
    pub cut: Option<String>,
}

#[derive(Clone, Debug, PartialEq)]
pub enum BodyError {
    /// The file breaks the RINEX rules at `line` (1-based; None where not on one line).
    Malformed {
        line: Option<usize>,
        message: String,
    },
    /// The dense arrays would exceed `BodyOptions::max_cells`.
    TooLarge {
        epochs: usize,
        sats: usize,
        codes: usize,
    },
}

/// The error for a record that breaks the RINEX rules at the 1-based `line` (every body reader's).
pub(super) fn err(line: usize, message: String) -> BodyError {
    BodyError::Malformed {
        line: Some(line),
        message,
    }
}

/// A field quoted as Python's `repr` of the decoded line quotes it (a byte of 0x80 or above is U+FFFD).
pub(super) fn quoted(s: &[u8]) -> String {
    py_repr(s, '\u{fffd}')
}

/// `"G03"` from a satellite field (RINEX 2 allows a blank system letter, meaning the file's system).
fn sat_id(lineno: usize, token: &[u8], default: Option<u8>) -> Result<[u8; 3], BodyError> {
    let fail = || {
        err(
            lineno,
            format!(
                "expected a satellite id such as 'G03', got {}",
                quoted(token)
            ),
        )
    };
    if token.len() < 3 {
        return Err(fail());
    }
    let letter = match (token[0], default) {
        (b' ', Some(d)) => d,
        (l, _) => l,
    };
    let (a, b) = (token[1], token[2]);
    let prn_ok = ((a == b' ' || a == b'0') && (b'1'..=b'9').contains(&b))
        || ((b'1'..=b'9').contains(&a) && b.is_ascii_digit());
    if !SYSTEMS.contains(&letter) || !prn_ok {
        return Err(fail());
    }
    let tens = if a == b' ' { b'0' } else { a };
    Ok([letter, tens, b])
}

/// Refuse a record line that ends inside a number (a cut field) or holds more fields than announced.
/// Observations are F14.3 right-justified in 16 columns (then the LLI and signal-strength digits), so a
/// line whose blanks at the end were stripped still ends at column 14, 15 or 16 of a field.
fn check_fields(
    lineno: usize,
    text: &[u8],
    n_fields: usize,
    sat: &[u8; 3],
) -> Result<(), BodyError> {
    let what = String::from_utf8_lossy(sat);
    let content = rstrip_blanks(text).len();
    if content > 16 * n_fields {
        return Err(err(
            lineno,
            format!("satellite {what}: more than the {n_fields} observation fields the header announces"),
        ));
    }
    let cut = content % 16;
    if (1..=13).contains(&cut) {
        return Err(err(
            lineno,
            format!(
                "satellite {what}: the line ends inside observation field {} (a field cut short)",
                content / 16 + 1
            ),
        ));
    }
    Ok(())
}

/// One observation record found by the walk.
struct Record {
    epoch: usize,
    sat: [u8; 3],
    /// 0-based line of the record's first line.
    line: usize,
    /// Index into `BodyOptions::layouts`.
    layout: usize,
}

#[derive(Default)]
struct Walk {
    time_ns: Vec<i64>,
    flag: Vec<u8>,
    clock_s: Vec<f64>,
    records: Vec<Record>,
    cut: Option<String>,
}

fn plural(event: bool) -> &'static str {
    if event {
        "special records"
    } else {
        "satellites"
    }
}

/// Walks the epochs from `opts.first_line`: their lines, lists and records, checked for structure.
fn walk(lines: &[&[u8]], ended: bool, opts: &BodyOptions) -> Result<Walk, BodyError> {
    let v3 = opts.v3;
    let n_lines = lines.len();
    let n_types2 = opts.layouts.first().map_or(0, |l| l.n_fields);
    let body = Body {
        lines,
        opts,
        n_types2,
        sat_lines2: n_types2.div_ceil(5),
    };
    let mut w = Walk::default();
    let mut previous: Option<(i64, usize)> = None;
    let mut block: Option<(usize, usize)> = None;
    let mut i = opts.first_line;
    while i < n_lines {
        let line = lines[i];
        let lineno = i + 1;
        if blank(line) {
            i += 1;
            continue;
        }
        if v3 && line[0] != b'>' {
            if let Some((at, n)) = block {
                if SYSTEMS.contains(&line[0]) {
                    return Err(err(
                        at,
                        format!("the epoch announces {n} satellites, but line {lineno} holds one more record"),
                    ));
                }
            }
            return Err(err(
                lineno,
                format!(
                    "expected an epoch line starting with '>', got {}",
                    quoted(slice(line, 0, 40))
                ),
            ));
        }
        let saved = (w.time_ns.len(), w.records.len());
        let mut reach = 0usize;
        let step = epoch_block(&body, i, &mut w, &mut previous, &mut reach);
        match step {
            Ok(Step::Cut(note)) => {
                w.cut = Some(note);
                break;
            }
            Ok(Step::Next { next, block: b }) => {
                i = next;
                block = b;
            }
            Err(BodyError::Malformed {
                line: Some(at),
                message,
            }) if !ended && at >= lineno && (at >= n_lines || reach >= n_lines) => {
                // the file has no line end and this epoch reaches it: the file was cut inside the epoch
                w.time_ns.truncate(saved.0);
                w.flag.truncate(saved.0);
                w.clock_s.truncate(saved.0);
                w.records.truncate(saved.1);
                w.cut = Some(format!(
                    "the epoch at line {lineno}, cut at line {n_lines} ({message})"
                ));
                break;
            }
            Err(e) => return Err(e),
        }
    }
    Ok(w)
}

enum Step {
    Next {
        next: usize,
        block: Option<(usize, usize)>,
    },
    Cut(String),
}

/// The lines of a body and what the header says about them, for the walk over its epochs.
struct Body<'a> {
    lines: &'a [&'a [u8]],
    opts: &'a BodyOptions,
    /// RINEX 2: the observation fields of a record, and the lines they take (5 per line).
    n_types2: usize,
    sat_lines2: usize,
}

impl Body<'_> {
    /// Index into `BodyOptions::layouts` of system `sys`'s layout (RINEX 3).
    fn layout_of(&self, sys: u8) -> Option<usize> {
        self.opts.layouts.iter().position(|l| l.key == sys)
    }
}

/// One epoch block starting at line `i`: appended to `w`; `reach` is set to the end of its lines once
/// known (to tell a fault at the end of a file without a line end from one inside it).
fn epoch_block(
    b: &Body,
    i: usize,
    w: &mut Walk,
    previous: &mut Option<(i64, usize)>,
    reach: &mut usize,
) -> Result<Step, BodyError> {
    let (lines, opts) = (b.lines, b.opts);
    let sat_lines2 = b.sat_lines2;
    let v3 = opts.v3;
    let n_lines = lines.len();
    let lineno = i + 1;
    let ep = epoch_line(lineno, lines[i], v3)?;
    let (flag, n) = (ep.flag, ep.count);
    let event = (2..=5).contains(&flag);
    // RINEX 2 lists the satellites on the epoch line and its continuation lines (12 per line)
    let n_head = 1 + if n > 0 && !v3 && !event {
        (n - 1) / 12
    } else {
        0
    };
    let per_sat = if v3 { 1 } else { sat_lines2 };
    let n_body = if v3 || event { n } else { n * sat_lines2 };
    *reach = i + n_head + n_body;
    if *reach > n_lines {
        if !lines[i + 1..].iter().any(|ln| starts_epoch(ln, v3)) {
            // the last epoch, cut by the end of the file (no epoch follows it): the epochs before it
            return Ok(Step::Cut(format!(
                "the epoch at line {lineno} announces {n} {} in {} lines, the file ends {} line(s) later",
                plural(event),
                n_head + n_body,
                n_lines - i - 1
            )));
        }
        return Err(err(
            lineno,
            format!(
                "the epoch announces {n} {}, but the file ends {} line(s) later, with other epochs among them",
                plural(event),
                n_lines - i - 1
            ),
        ));
    }
    if event {
        check_header_records(b, i, n, flag)?;
        return Ok(Step::Next {
            next: i + 1 + n,
            block: None,
        });
    }
    let ids = satellite_ids(b, i, n, n_head)?;
    if flag == 6 {
        // cycle-slip records repeat observations of an epoch already given
        return Ok(Step::Next {
            next: i + n_head + n_body,
            block: None,
        });
    }
    let Some(t_ns) = ep.time_ns else {
        return Err(err(
            lineno,
            "an observation epoch needs its date and time".into(),
        ));
    };
    check_increasing(previous, t_ns, lineno)?;
    let e = w.time_ns.len();
    w.time_ns.push(t_ns);
    w.flag.push(flag);
    w.clock_s.push(ep.clock_s);
    let start = i + n_head;
    push_records(b, w, &ids, e, start, lineno)?;
    Ok(Step::Next {
        next: start + n * per_sat,
        block: Some((lineno, n)),
    })
}

/// The `n` records of an event epoch (flag 2-5) at line `i`: header records, none of them one that
/// changes how the observation records after it are laid out.
fn check_header_records(b: &Body, i: usize, n: usize, flag: u8) -> Result<(), BodyError> {
    let (lines, opts) = (b.lines, b.opts);
    let lineno = i + 1;
    for (j, line) in lines.iter().enumerate().take(i + 1 + n).skip(i + 1) {
        let label = strip(slice(line, 60, 80));
        let known = opts.header_labels.iter().any(|h| h.as_bytes() == label);
        if !known || line.first() == Some(&b'>') {
            return Err(err(
                lineno,
                format!(
                    "epoch flag {flag} announces {n} header records, but line {} is not one (no header \
                     label in columns 61-80)",
                    j + 1
                ),
            ));
        }
        if LAYOUT_LABELS.contains(&label) {
            // the records after it would be laid out otherwise: reading them with the old types (or
            // factors) would put values under wrong codes
            return Err(err(
                j + 1,
                format!(
                    "'{}' inside the data (epoch flag {flag} at line {lineno}) changes how the records \
                     after it are laid out, which this reader does not follow: split the file at that \
                     epoch with a RINEX tool (gfzrnx -splice, teqc) and read the parts",
                    String::from_utf8_lossy(label)
                ),
            ));
        }
    }
    Ok(())
}

/// The ids of the `n` satellites of the observation epoch at line `i` (RINEX 3: one per record line;
/// RINEX 2: listed on the epoch line and its `n_head - 1` continuation lines).
fn satellite_ids(b: &Body, i: usize, n: usize, n_head: usize) -> Result<Vec<[u8; 3]>, BodyError> {
    let (lines, opts) = (b.lines, b.opts);
    let (v3, n_lines, lineno) = (opts.v3, lines.len(), i + 1);
    let mut ids: Vec<[u8; 3]> = Vec::with_capacity(n);
    if v3 {
        for (j, line) in lines.iter().enumerate().take(i + 1 + n).skip(i + 1) {
            if line.first() == Some(&b'>') {
                return Err(err(
                    lineno,
                    format!(
                        "the epoch announces {n} satellites, but line {} starts the next epoch after {}",
                        j + 1,
                        j - i - 1
                    ),
                ));
            }
            ids.push(sat_id(j + 1, slice(line, 0, 3), None)?);
        }
    } else {
        let mut listed = Vec::with_capacity(36 * n_head);
        for c in 0..n_head {
            push_padded(&mut listed, lines[i + c], 32, 68);
        }
        for c in 1..n_head {
            if !blank(slice(lines[i + c], 0, 32)) {
                return Err(err(
                    lineno,
                    format!(
                        "the epoch lists {n} satellites, but line {} does not continue the list (columns \
                         1-32 not blank)",
                        i + c + 1
                    ),
                ));
            }
        }
        if !blank(tail(&listed, 3 * n)) || rstrip(slice(&listed, 0, 3 * n)).len() + 2 < 3 * n {
            return Err(err(
                lineno,
                format!(
                    "the epoch announces {n} satellites, but lists {}",
                    quoted(strip(&listed))
                ),
            ));
        }
        for j in 0..n {
            ids.push(sat_id(
                lineno + j / 12,
                &listed[3 * j..3 * j + 3],
                Some(opts.default_system),
            )?);
        }
    }
    if !v3 && n.is_multiple_of(12) && i + n_head < n_lines && continues_sat_list(lines[i + n_head])
    {
        return Err(err(
            lineno,
            format!(
                "the epoch announces {n} satellites, but line {} continues the list",
                i + n_head + 1
            ),
        ));
    }
    Ok(ids)
}

/// Refuses an epoch time `t_ns` (line `lineno`) not after the previous epoch's; it becomes the previous.
fn check_increasing(
    previous: &mut Option<(i64, usize)>,
    t_ns: i64,
    lineno: usize,
) -> Result<(), BodyError> {
    if let Some((t_prev, at)) = *previous {
        if t_ns <= t_prev {
            let what = if t_ns == t_prev {
                "repeats"
            } else {
                "comes before"
            };
            return Err(err(
                lineno,
                format!(
                    "epoch {} {what} the epoch at line {at}: epochs must increase strictly (merge \
                     duplicated files with a RINEX tool first)",
                    datetime64_text(t_ns)
                ),
            ));
        }
    }
    *previous = Some((t_ns, lineno));
    Ok(())
}

/// The records of satellites `ids` of epoch `e` (epoch line `lineno`), from line `start`, appended to
/// `w` once their fields are checked.
fn push_records(
    b: &Body,
    w: &mut Walk,
    ids: &[[u8; 3]],
    e: usize,
    start: usize,
    lineno: usize,
) -> Result<(), BodyError> {
    let (lines, opts) = (b.lines, b.opts);
    let (v3, n_types2, sat_lines2) = (opts.v3, b.n_types2, b.sat_lines2);
    let per_sat = if v3 { 1 } else { sat_lines2 };
    let first_record = w.records.len();
    for (j, sat) in ids.iter().enumerate() {
        let base = start + j * per_sat;
        if w.records[first_record..].iter().any(|r| &r.sat == sat) {
            return Err(err(
                base + 1,
                format!(
                    "satellite {} appears twice in the epoch of line {lineno}",
                    String::from_utf8_lossy(sat)
                ),
            ));
        }
        let layout = if v3 {
            let Some(k) = b.layout_of(sat[0]) else {
                return Err(err(
                    base + 1,
                    format!(
                        "satellite system {} has no 'SYS / # / OBS TYPES' header line",
                        quoted(&sat[..1])
                    ),
                ));
            };
            check_fields(
                base + 1,
                tail(lines[base], 3),
                opts.layouts[k].n_fields,
                sat,
            )?;
            k
        } else {
            for q in 0..sat_lines2 {
                let fields = 5.min(n_types2 - 5 * q);
                check_fields(base + q + 1, lines[base + q], fields, sat)?;
            }
            0
        };
        w.records.push(Record {
            epoch: e,
            sat: *sat,
            line: base,
            layout,
        });
    }
    Ok(())
}

/// The record text of `r`: RINEX 3 the columns after the satellite id; RINEX 2 its lines, each padded to
/// 80 columns, joined.
fn record_text(lines: &[&[u8]], r: &Record, opts: &BodyOptions, width: usize, out: &mut Vec<u8>) {
    out.clear();
    if opts.v3 {
        push_padded(out, lines[r.line], 3, 3 + width);
    } else {
        for line in &lines[r.line..r.line + width.div_ceil(80)] {
            out.extend_from_slice(line);
            out.resize(out.len().max(out.len() - line.len() + 80), b' ');
        }
        out.resize(width, b' ');
    }
}

/// Reads the body of an observation file (`text`: the whole file, decompressed).
///
/// # Errors
/// `BodyError::Malformed` naming the first line that breaks the RINEX rules (structure first, then the
/// fields system by system); `BodyError::TooLarge` before the dense arrays are allocated.
pub fn read_obs_body(text: &[u8], opts: &BodyOptions) -> Result<ObsBody, BodyError> {
    let (lines, ended) = split_lines(text);
    let w = walk(&lines, ended, opts)?;
    let mut sats: Vec<[u8; 3]> = w.records.iter().map(|r| r.sat).collect();
    sats.sort_unstable();
    sats.dedup();
    let (n_ep, n_sat, n_code) = (w.time_ns.len(), sats.len(), opts.n_codes);
    let cells = (n_ep as u128) * (n_sat as u128) * (n_code as u128);
    if cells > u128::from(opts.max_cells) {
        return Err(BodyError::TooLarge {
            epochs: n_ep,
            sats: n_sat,
            codes: n_code,
        });
    }
    let cells = cells as usize;
    let mut data = vec![f64::NAN; cells];
    let mut lli = vec![0u8; cells];
    let mut ssi = vec![0u8; cells];
    // the systems in the order their first record appears
    let mut order: Vec<usize> = Vec::new();
    for r in &w.records {
        if !order.contains(&r.layout) {
            order.push(r.layout);
        }
    }
    let mut buf = Vec::new();
    for k in order {
        let layout = &opts.layouts[k];
        let width = 16 * layout.n_fields;
        for r in w.records.iter().filter(|r| r.layout == k) {
            record_text(&lines, r, opts, width, &mut buf);
            let s = sats.binary_search(&r.sat).unwrap_or(0);
            let row = (r.epoch * n_sat + s) * n_code;
            for ((&f, &col), &factor) in
                layout.keep.iter().zip(&layout.columns).zip(&layout.factors)
            {
                let bytes: &[u8; 16] = buf[16 * f..16 * f + 16].try_into().unwrap_or(&[b'?'; 16]);
                let Some((value, l, q)) = field(bytes) else {
                    // RINEX 2 puts five fields on a line; RINEX 3 a whole record on one
                    let line = r.line + 1 + if opts.v3 { 0 } else { f / 5 };
                    return Err(err(
                        line,
                        format!(
                            "expected a number (F14.3) with blank or digit indicators in observation field \
                             {}, got {}",
                            f + 1,
                            py_repr(bytes, '?')
                        ),
                    ));
                };
                data[row + col] = value / factor;
                lli[row + col] = l;
                ssi[row + col] = q;
            }
        }
    }
    Ok(ObsBody {
        time_ns: w.time_ns,
        flag: w.flag,
        clock_s: w.clock_s,
        sats: sats
            .iter()
            .map(|s| String::from_utf8_lossy(s).into_owned())
            .collect(),
        data,
        lli,
        ssi,
        cut: w.cut,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn opts(v3: bool, layouts: Vec<SystemLayout>, n_codes: usize) -> BodyOptions {
        BodyOptions {
            v3,
            default_system: b'G',
            layouts,
            n_codes,
            header_labels: vec!["COMMENT".into(), "END OF HEADER".into()],
            max_cells: 1 << 30,
            first_line: 0,
        }
    }

    fn v3_layout() -> Vec<SystemLayout> {
        vec![SystemLayout {
            key: b'G',
            n_fields: 2,
            keep: vec![0, 1],
            columns: vec![0, 1],
            factors: vec![1.0, 10.0],
        }]
    }

    /// A RINEX 3 record line: the satellite, then F14.3 values (blank where None) with their LLI and SSI.
    fn rec(sat: &str, fields: &[(Option<f64>, &str)]) -> String {
        let mut line = sat.to_string();
        for (v, ind) in fields {
            match v {
                Some(v) => line += &format!("{v:14.3}{ind}"),
                None => line += &format!("{:14}{ind}", ""),
            }
        }
        line + "\n"
    }

    const E0: &str = "> 2024 03 01 00 00  0.0000000  0";

    fn malformed(r: Result<ObsBody, BodyError>) -> (Option<usize>, String) {
        match r {
            Err(BodyError::Malformed { line, message }) => (line, message),
            other => panic!("expected a refusal, got {other:?}"),
        }
    }

    #[test]
    fn rinex3_records_fill_the_arrays() {
        let text = format!(
            "{E0}  2\n{}{}> 2024 03 01 00 00 30.0000000  0  1\n{}",
            rec("G05", &[(Some(23_619_095.45), " 7"), (Some(-12.5), "  ")]),
            rec("G03", &[(Some(2e7), "  ")]),
            rec("G05", &[(Some(23_619_100.0), "1 ")]),
        );
        let body = read_obs_body(text.as_bytes(), &opts(true, v3_layout(), 2)).unwrap();
        assert_eq!(body.sats, ["G03", "G05"]);
        assert_eq!(body.time_ns[1] - body.time_ns[0], 30_000_000_000);
        // epoch 0, G05: 23619095.450 and -12.5 / 10 (the scale factor); LLI 0, SSI 7
        assert_eq!(body.data[2], 23_619_095.45);
        assert_eq!(body.data[3], -1.25);
        assert_eq!((body.lli[2], body.ssi[2]), (0, 7));
        assert!(body.data[1].is_nan() && body.data[7].is_nan());
        assert_eq!(body.lli[6], 1);
        assert!(body.cut.is_none());
    }

    #[test]
    fn faults_name_their_line() {
        let one = rec("G05", &[(Some(1.0), "  ")]);
        let dup = format!("{E0}  2\n{one}{one}");
        assert_eq!(
            malformed(read_obs_body(dup.as_bytes(), &opts(true, v3_layout(), 2))),
            (
                Some(3),
                "satellite G05 appears twice in the epoch of line 1".into()
            )
        );
        let bad = format!("{E0}  1\nG05         1.2.3  \n");
        let (line, message) = malformed(read_obs_body(bad.as_bytes(), &opts(true, v3_layout(), 2)));
        assert_eq!(line, Some(2));
        assert!(
            message.ends_with("observation field 1, got '         1.2.3  '"),
            "{message}"
        );
        let back = format!("> 2024 03 01 00 00 30.0000000  0  0\n{E0}  0\n");
        let (line, message) =
            malformed(read_obs_body(back.as_bytes(), &opts(true, v3_layout(), 2)));
        assert_eq!(line, Some(2));
        assert!(message
            .starts_with("epoch 2024-03-01T00:00:00.000000000 comes before the epoch at line 1"));
    }

    #[test]
    fn a_file_cut_inside_its_last_epoch_keeps_the_epochs_before() {
        let first = format!("{E0}  1\n{}", rec("G05", &[(Some(1.0), "  ")]));
        let text = format!(
            "{first}> 2024 03 01 00 00 30.0000000  0  3\n{}",
            rec("G05", &[(Some(2.0), "  ")])
        );
        let body = read_obs_body(text.as_bytes(), &opts(true, v3_layout(), 2)).unwrap();
        assert_eq!(body.time_ns.len(), 1);
        assert_eq!(
            body.cut.as_deref(),
            Some("the epoch at line 3 announces 3 satellites in 4 lines, the file ends 1 line(s) later")
        );
        // no line end, and the last line ends inside a field
        let text = format!("{first}> 2024 03 01 00 00 30.0000000  0  1\nG05         2.0");
        let body = read_obs_body(text.as_bytes(), &opts(true, v3_layout(), 2)).unwrap();
        assert_eq!(body.time_ns.len(), 1);
        let cut = body.cut.unwrap();
        assert!(
            cut.starts_with("the epoch at line 3, cut at line 4 (satellite G05: the line ends"),
            "{cut}"
        );
    }

    #[test]
    fn rinex2_lists_continue_over_lines() {
        // 13 satellites: 12 on the epoch line, one on a continuation line; one code, one line per record
        let mut text =
            b" 24  3  1  0  0  0.0000000  0 13G01G02G03G04G05G06G07G08G09G10G11G12\n".to_vec();
        text.extend_from_slice(format!("{}G13\n", " ".repeat(32)).as_bytes());
        for k in 1..=13 {
            text.extend_from_slice(format!("{:14.3}  \n", 1000.0 + f64::from(k)).as_bytes());
        }
        let layout = vec![SystemLayout {
            key: b'*',
            n_fields: 1,
            keep: vec![0],
            columns: vec![0],
            factors: vec![1.0],
        }];
        let body = read_obs_body(&text, &opts(false, layout, 1)).unwrap();
        assert_eq!(body.sats.len(), 13);
        assert_eq!(body.data[12], 1013.0);
    }
}
