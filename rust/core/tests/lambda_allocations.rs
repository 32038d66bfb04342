//! The batch path of LAMBDA allocates per batch and per thread, not per problem: after a warm-up, a batch
//! of 32 problems makes exactly as many heap allocations as a batch of 2 (its outputs), and one `ils` call
//! makes only its two outputs (n = 8; above `identity::OWN_PRODUCT_MAX_N` = 8 the identity check's four
//! blocked products allocate their packing buffers inside nalgebra). Counted by a global allocator (per thread, so the test harness's own
//! threads do not count); this asserts allocations, not time.

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;

use gnssatt_core::lambda::{ils, ils_batch};
use nalgebra::{DMatrix, DVector};

struct Counting;

thread_local! {
    // const-initialised, no destructor: reading it never allocates.
    static ALLOCATIONS: Cell<u64> = const { Cell::new(0) };
}

fn count() {
    let _ = ALLOCATIONS.try_with(|c| c.set(c.get() + 1));
}

// SAFETY: every call is forwarded to the system allocator unchanged; only a counter is added.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        count();
        unsafe { System.alloc(layout) }
    }
    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        count();
        unsafe { System.alloc_zeroed(layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        count();
        unsafe { System.realloc(ptr, layout, new_size) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }
}

#[global_allocator]
static ALLOCATOR: Counting = Counting;

fn allocations_of<T>(f: impl FnOnce() -> T) -> (u64, T) {
    let before = ALLOCATIONS.with(Cell::get);
    let out = f();
    (ALLOCATIONS.with(Cell::get) - before, out)
}

/// `k` problems of `n` ambiguities: float vectors far from the integers and covariances `A A^T / n +
/// 0.05 I` (row-major, one per problem), from a fixed linear congruential sequence.
fn problems(k: usize, n: usize) -> (Vec<f64>, Vec<f64>) {
    let mut s = 12_345u64;
    let mut uniform = move || {
        s = s
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (s >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    };
    let mut q = Vec::with_capacity(k * n * n);
    for _ in 0..k {
        let a = DMatrix::from_fn(n, n, |_, _| uniform());
        let c = &a * a.transpose() / n as f64 + DMatrix::identity(n, n) * 0.05;
        q.extend(c.transpose().iter());
    }
    let a = (0..k * n).map(|_| 40.0 * uniform()).collect();
    (a, q)
}

#[test]
fn batch_and_ils_allocate_nothing_per_problem_after_warm_up() {
    // 32 problems of n = 8 are a short batch: solved on this thread, whose allocations are counted.
    let (n, k, m) = (8, 32, 2);
    let (a, q) = problems(k, n);
    let shared = &q[..n * n];
    let small = (&a[..2 * n], &q[..2 * n * n]);
    // Warm-up: the workspace grows to the largest of these problems.
    ils_batch(&a, &q, n, m).unwrap();
    ils_batch(&a, shared, n, m).unwrap();
    let (two, _) = allocations_of(|| ils_batch(small.0, small.1, n, m).unwrap());
    let (all, out) = allocations_of(|| ils_batch(&a, &q, n, m).unwrap());
    assert_eq!(out.nodes_visited.len(), k);
    assert_eq!(
        all, two,
        "a batch of {k} problems made {all} allocations, one of 2 made {two}"
    );
    assert!(two <= 6, "{two} allocations for a batch of 2");
    let (two_shared, _) = allocations_of(|| ils_batch(&a[..2 * n], shared, n, m).unwrap());
    let (all_shared, _) = allocations_of(|| ils_batch(&a, shared, n, m).unwrap());
    assert_eq!(all_shared, two_shared, "shared covariance");
    // One call: its returned matrix and vector only.
    let qm = DMatrix::from_row_slice(n, n, &q[..n * n]);
    let av = DVector::from_column_slice(&a[..n]);
    ils(&av, &qm, m).unwrap();
    let (one, _) = allocations_of(|| ils(&av, &qm, m).unwrap());
    assert_eq!(one, 2, "allocations of one ils call after warm-up");
}
