//! The 16-column observation fields of RINEX 2 and 3 records: an F14.3 number right-justified in 14
//! columns (blank where not observed), then the loss-of-lock and signal-strength digits (blank = 0).

/// One field read: the value (NaN where blank), the two indicator digits, or None where the field is not
/// an F14.3 number with blank or digit indicators.
pub fn field(f: &[u8; 16]) -> Option<(f64, u8, u8)> {
    let lli = indicator(f[14])?;
    let ssi = indicator(f[15])?;
    let num = &f[..14];
    let start = num.iter().position(|&b| b != b' ');
    let Some(start) = start else {
        return Some((f64::NAN, lli, ssi));
    };
    // right-justified with no blank inside: ' *[+-]?(?:\d+\.?\d*|\.\d+)' over the 14 columns
    let body = &num[start..];
    let mut k = usize::from(matches!(body[0], b'+' | b'-'));
    let whole = body[k..].iter().take_while(|b| b.is_ascii_digit()).count();
    k += whole;
    if body.get(k) == Some(&b'.') {
        let frac = body[k + 1..]
            .iter()
            .take_while(|b| b.is_ascii_digit())
            .count();
        if whole == 0 && frac == 0 {
            return None;
        }
        k += 1 + frac;
    } else if whole == 0 {
        return None;
    }
    if k != body.len() {
        return None;
    }
    // ASCII by the checks above
    let text = std::str::from_utf8(body).ok()?;
    Some((text.parse().ok()?, lli, ssi))
}

fn indicator(b: u8) -> Option<u8> {
    match b {
        b' ' => Some(0),
        b'0'..=b'9' => Some(b - b'0'),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn f(s: &str) -> [u8; 16] {
        s.as_bytes().try_into().unwrap()
    }

    #[test]
    fn fields_read_as_fortran_writes_them() {
        assert_eq!(field(&f("  23619095.450 7")), Some((23_619_095.45, 0, 7)));
        assert_eq!(field(&f("       -1234.514")), Some((-1234.5, 1, 4)));
        assert_eq!(field(&f("           .25  ")), Some((0.25, 0, 0)));
        let (v, l, s) = field(&f("              15")).unwrap();
        assert!(v.is_nan() && l == 1 && s == 5);
        for bad in [
            "  1.2.3         ",
            "  12 3.4        ",
            "  1-2           ",
            "  12.5 x        ",
            "1.5e3           ",
            "  12.5        A ",
            "             .  ",
            "             -  ",
        ] {
            assert_eq!(field(&f(bad)), None, "{bad}");
        }
    }
}
