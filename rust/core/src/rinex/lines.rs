//! Lines and fixed-width slices of a RINEX file with the semantics of Python's `str` on text decoded as
//! ASCII with replacement: a byte of 0x80 or above stands for one U+FFFD character (never blank, never a
//! digit), so that columns, blanks and digits are the same as the header reader's.

/// The lines of `text`, split at `\n` only, one `\r` before it dropped, and whether the last line ended
/// with a line end (a file without its final line end may be cut inside its last record).
pub fn split_lines(text: &[u8]) -> (Vec<&[u8]>, bool) {
    let mut lines: Vec<&[u8]> = text.split(|&b| b == b'\n').collect();
    let ended = lines.last().is_some_and(|l| l.is_empty());
    if ended {
        lines.pop();
    }
    for line in &mut lines {
        if let Some(stripped) = line.strip_suffix(b"\r") {
            *line = stripped;
        }
    }
    (lines, ended)
}

/// Python's `str.isspace()` on one character of the decoded text.
pub fn is_space(b: u8) -> bool {
    matches!(b, 9..=13 | 28..=32)
}

pub fn is_digit(b: u8) -> bool {
    b.is_ascii_digit()
}

/// `s[a:b]` with Python's clamping.
pub fn slice(s: &[u8], a: usize, b: usize) -> &[u8] {
    let b = b.min(s.len());
    if a >= b {
        &[]
    } else {
        &s[a..b]
    }
}

/// `s[a:]`.
pub fn tail(s: &[u8], a: usize) -> &[u8] {
    slice(s, a, s.len())
}

/// `not s.strip()`.
pub fn blank(s: &[u8]) -> bool {
    s.iter().all(|&b| is_space(b))
}

/// `s.strip()`.
pub fn strip(s: &[u8]) -> &[u8] {
    rstrip(lstrip(s))
}

pub fn lstrip(s: &[u8]) -> &[u8] {
    let start = s.iter().position(|&b| !is_space(b)).unwrap_or(s.len());
    &s[start..]
}

/// `s.rstrip()`.
pub fn rstrip(s: &[u8]) -> &[u8] {
    let end = s.iter().rposition(|&b| !is_space(b)).map_or(0, |k| k + 1);
    &s[..end]
}

/// `s.rstrip(" ")`.
pub fn rstrip_blanks(s: &[u8]) -> &[u8] {
    let end = s.iter().rposition(|&b| b != b' ').map_or(0, |k| k + 1);
    &s[..end]
}

/// `s[a:b].ljust(b - a)` appended to `out`.
pub fn push_padded(out: &mut Vec<u8>, s: &[u8], a: usize, b: usize) {
    let part = slice(s, a, b);
    out.extend_from_slice(part);
    out.resize(out.len() + (b - a - part.len()), b' ');
}
