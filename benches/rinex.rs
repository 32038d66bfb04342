//! Criterion benchmarks of the RINEX readers (`gnssatt_core::rinex`), throughput in bytes of decompressed
//! text per second (criterion prints MiB/s):
//! - `rinex_nav`: whole navigation files of `tests/data/real` (SEPT2650, RINEX 3.04 mixed of a Septentrio
//!   receiver; ESBC00DNK, RINEX 3.05 mixed), their records repeated 40 times after the header so that the
//!   per-record cost, not the header, is measured;
//! - `rinex_obs`: the observation body of ACOR00ESP (RINEX 3.04, GPS/GLONASS/Galileo/BeiDou, 12-15 codes per
//!   system), every code kept, as `gnssatt.rinex.obs` passes it.
//!
//! The Python readers add the opening, the decompression and the conversion into arrays
//! (`benches/python/rinex_read_speed.py` measures the whole read against the Python loops it replaced).
use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use gnssatt_core::rinex::{read_nav, read_obs_body, BodyOptions, SystemLayout};
use std::hint::black_box;
use std::path::PathBuf;

fn data(name: &str) -> Vec<u8> {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../tests/data/real")
        .join(name);
    std::fs::read(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// The header labels the readers know (a subset is enough: the files' headers end with `END OF HEADER`).
fn labels() -> Vec<String> {
    [
        "RINEX VERSION / TYPE",
        "PGM / RUN BY / DATE",
        "COMMENT",
        "END OF HEADER",
    ]
    .iter()
    .map(|s| s.to_string())
    .collect()
}

/// `text` with the lines after its header repeated `times` times.
fn repeated_body(text: &[u8], times: usize) -> Vec<u8> {
    let end = text
        .windows(13)
        .position(|w| w == b"END OF HEADER")
        .expect("a header");
    let body_start = end
        + text[end..]
            .iter()
            .position(|&b| b == b'\n')
            .expect("a line end")
        + 1;
    let mut out = text[..body_start].to_vec();
    for _ in 0..times {
        out.extend_from_slice(&text[body_start..]);
    }
    out
}

fn nav(c: &mut Criterion) {
    let mut g = c.benchmark_group("rinex_nav");
    let labels = labels();
    for name in ["SEPT2650_excerpt.21P", "ESBC00DNK_excerpt_MN.rnx"] {
        let text = repeated_body(&data(name), 40);
        let records = read_nav(&text, &labels).expect("a valid file");
        assert!(!records.kepler_sats.is_empty());
        g.throughput(Throughput::Bytes(text.len() as u64));
        g.bench_function(name, |b| b.iter(|| read_nav(black_box(&text), &labels)));
    }
    g.finish();
}

/// The layout of a RINEX 3 header's `SYS / # / OBS TYPES` records: every code kept, on one axis of the
/// union of the codes.
fn v3_layouts(text: &[u8]) -> (Vec<SystemLayout>, usize, usize) {
    let lines: Vec<&[u8]> = text.split(|&b| b == b'\n').collect();
    let mut systems: Vec<(u8, Vec<String>)> = Vec::new();
    let mut first_line = 0;
    for (i, line) in lines.iter().enumerate() {
        let label = String::from_utf8_lossy(&line[60.min(line.len())..])
            .trim()
            .to_string();
        if label == "END OF HEADER" {
            first_line = i + 1;
            break;
        }
        if label == "SYS / # / OBS TYPES" {
            if line[0] != b' ' {
                systems.push((line[0], Vec::new()));
            }
            let codes = String::from_utf8_lossy(&line[7..60]).to_string();
            let last = systems.last_mut().expect("a system line first");
            last.1.extend(codes.split_whitespace().map(str::to_string));
        }
    }
    let mut union: Vec<String> = systems.iter().flat_map(|s| s.1.clone()).collect();
    union.sort();
    union.dedup();
    let layouts = systems
        .iter()
        .map(|(key, codes)| SystemLayout {
            key: *key,
            n_fields: codes.len(),
            keep: (0..codes.len()).collect(),
            columns: codes
                .iter()
                .map(|c| union.binary_search(c).expect("in the union"))
                .collect(),
            factors: vec![1.0; codes.len()],
        })
        .collect();
    (layouts, union.len(), first_line)
}

fn obs(c: &mut Criterion) {
    let mut g = c.benchmark_group("rinex_obs");
    let name = "ACOR00ESP_R_20213550000_01D_30S_MO.rnx";
    let text = data(name);
    let (layouts, n_codes, first_line) = v3_layouts(&text);
    let opts = BodyOptions {
        v3: true,
        default_system: b'G',
        layouts,
        n_codes,
        header_labels: labels(),
        max_cells: 1 << 30,
        first_line,
    };
    let body = read_obs_body(&text, &opts).expect("a valid body");
    assert!(!body.time_ns.is_empty());
    g.throughput(Throughput::Bytes(text.len() as u64));
    g.bench_function(name, |b| b.iter(|| read_obs_body(black_box(&text), &opts)));
    g.finish();
}

criterion_group!(benches, nav, obs);
criterion_main!(benches);
