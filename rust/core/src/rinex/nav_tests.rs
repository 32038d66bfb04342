//! The navigation reader's unit tests.

use super::*;

fn labels() -> Vec<String> {
    ["RINEX VERSION / TYPE", "END OF HEADER", "LEAP SECONDS"]
        .iter()
        .map(|s| s.to_string())
        .collect()
}

fn header_line(content: &str, label: &str) -> String {
    format!("{content:<60}{label:<20}\n")
}

/// A RINEX 3.04 GPS record with sqrt(A) and e as given (other fields plausible).
fn gps_record(sqrt_a: &str, e: &str) -> String {
    let f = |v: [&str; 4]| format!("    {:>19}{:>19}{:>19}{:>19}\n", v[0], v[1], v[2], v[3]);
    let mut s = format!(
        "G01 2021 09 22 00 00 00{:>19}{:>19}{:>19}\n",
        "1.0D-04", "1.0D-12", "0.0D+00"
    );
    s += &f(["1.0D+01", "1.0D+01", "4.0D-09", "1.0D+00"]);
    s += &f(["1.0D-06", e, "1.0D-06", sqrt_a]);
    s += &f(["2.6D+05", "1.0D-08", "1.0D+00", "1.0D-08"]);
    s += &f(["9.6D-01", "2.0D+02", "1.0D+00", "-8.0D-09"]);
    s += &f(["1.0D-10", "1.0D+00", "2.1750D+03", "0.0D+00"]);
    s += &f(["2.0D+00", "0.0D+00", "-1.0D-08", "1.0D+01"]);
    s += &f(["2.5D+05", "4.0D+00", "", ""]);
    s
}

fn file(body: &str) -> String {
    header_line(
        "     3.04           N: GNSS NAV DATA    G: GPS",
        "RINEX VERSION / TYPE",
    ) + &header_line("    18", "LEAP SECONDS")
        + &header_line("", "END OF HEADER")
        + body
}

#[test]
fn a_record_is_read_with_its_header_values() {
    let nav = read_nav(
        file(&gps_record("5.153D+03", "1.0D-02")).as_bytes(),
        &labels(),
    )
    .unwrap();
    assert_eq!(nav.kepler_sats, ["G01"]);
    assert_eq!(nav.leap_seconds, Some(18));
    assert_eq!(nav.kepler_values.len(), KEPLER_VALUES);
    // af0, then iode (broadcast orbit 1, field 1), sqrt(A) (line 2, field 4), week (line 5, field 3)
    assert_eq!(nav.kepler_values[0], 1.0e-4);
    assert_eq!(nav.kepler_values[3], 10.0);
    assert_eq!(nav.kepler_values[3 + 7], 5153.0);
    assert_eq!(nav.kepler_values[3 + 18], 2175.0);
    // 2021-09-22 is day 18892 since 1970-01-01
    assert_eq!(nav.kepler_toc_ns, [18_892 * 86_400 * 1_000_000_000]);
    assert!(nav.iono_alpha[0].is_nan() && nav.skips.is_empty());
}

#[test]
fn an_ellipse_inside_the_earth_is_skipped_and_a_parabola_refused() {
    // a = 1000^2 m, far below the Earth's radius
    let nav = read_nav(
        file(&gps_record("1.0D+03", "1.0D-02")).as_bytes(),
        &labels(),
    )
    .unwrap();
    assert!(nav.kepler_sats.is_empty());
    assert_eq!(nav.skips[0].0, NavSkip::NotAnOrbit);
    let e = read_nav(
        file(&gps_record("5.153D+03", "1.0D+00")).as_bytes(),
        &labels(),
    );
    assert_eq!(
        e,
        Err(err(
            6,
            "expected an eccentricity in [0, 1) (broadcast field 2), got 1.0".into()
        ))
    );
    let e = read_nav(
        file(&gps_record("1.0D+200", "0.0D+00")).as_bytes(),
        &labels(),
    );
    assert!(
        matches!(e, Err(BodyError::Malformed { line: Some(11), message }) if message.contains("OverflowError"))
    );
}

#[test]
fn a_file_cut_inside_its_last_record_gives_the_records_before_it() {
    let rec = gps_record("5.153D+03", "1.0D-02");
    let text = file(&(rec.clone() + &rec[..rec.len() / 2]));
    let nav = read_nav(text.as_bytes(), &labels()).unwrap();
    assert_eq!(nav.kepler_sats.len(), 1);
    assert_eq!(nav.skips[0].0, NavSkip::CutRecord);
}

#[test]
fn a_missing_end_of_header_is_named_after_the_last_known_label() {
    let text = header_line("     3.04           N", "RINEX VERSION / TYPE")
        + &header_line("    18", "LEAP SECONDS")
        + &header_line("x", "MY OWN LABEL")
        + &header_line("x", "MY OWN LABEL");
    assert_eq!(
        read_nav(text.as_bytes(), &labels()),
        Err(err(3, "missing header line 'END OF HEADER': expected it here, after the last line with a known header label".into()))
    );
}
