//! `lambda::ils` (two candidates) on a problem file of `benches/lambda.rs`'s RTKLIB harness format (n, k as
//! int32, Q n x n column-major, then k float vectors, float64), cycling through the k problems `CALLS`
//! times, for instruction counts beside RTKLIB's harness on the same file:
//! `valgrind --tool=callgrind target/release/examples/lambda_problems FILE CALLS` at two values of CALLS;
//! the difference of the totals divided by the difference of the calls is the count per problem.
use gnssatt_core::lambda::ils;
use nalgebra::{DMatrix, DVector};

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let (Some(file), Some(calls)) = (args.get(1), args.get(2)) else {
        eprintln!("usage: lambda_problems FILE CALLS");
        std::process::exit(2);
    };
    let calls: usize = calls.parse().expect("CALLS is an integer");
    let bytes = std::fs::read(file).expect("problem file");
    let int = |i: usize| i32::from_le_bytes(bytes[4 * i..4 * i + 4].try_into().unwrap()) as usize;
    let (n, k) = (int(0), int(1));
    let values: Vec<f64> = bytes[8..]
        .chunks_exact(8)
        .map(|b| f64::from_le_bytes(b.try_into().unwrap()))
        .collect();
    let q = DMatrix::from_column_slice(n, n, &values[..n * n]);
    let draws: Vec<DVector<f64>> = (0..k)
        .map(|p| DVector::from_column_slice(&values[n * n + p * n..n * n + (p + 1) * n]))
        .collect();
    let mut check = 0i64;
    for c in 0..calls {
        check = check.wrapping_add(ils(&draws[c % k], &q, 2).expect("solved").fixed[(0, 0)]);
    }
    println!("{check}");
}
