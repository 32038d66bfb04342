//! Lanes of initial states integrated together: [`Real`] is `f64` (one state) or [`F4`] (four states,
//! element by element). The batch functions step four states through the same operations as one, which
//! the compiler packs into SIMD registers and overlaps in the pipeline; every lane does exactly the scalar
//! arithmetic, so a state's result does not depend on the states that share its pack.

use std::ops::{Add, Mul, Neg, Sub};

/// Arithmetic of one value per lane.
pub trait Real:
    Copy + Add<Output = Self> + Sub<Output = Self> + Mul<Output = Self> + Neg<Output = Self>
{
    /// Number of lanes.
    const LANES: usize;
    /// The same value in every lane.
    fn splat(v: f64) -> Self;
    /// Lane `i` (`i < LANES`).
    fn lane(self, i: usize) -> f64;
    /// Square root per lane.
    fn sqrt(self) -> Self;
    /// `1 / x` per lane.
    fn recip(self) -> Self;
}

impl Real for f64 {
    const LANES: usize = 1;
    #[inline(always)]
    fn splat(v: f64) -> Self {
        v
    }
    #[inline(always)]
    fn lane(self, _: usize) -> f64 {
        self
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        f64::sqrt(self)
    }
    #[inline(always)]
    fn recip(self) -> Self {
        1.0 / self
    }
}

/// Four `f64` lanes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct F4(pub [f64; 4]);

impl Real for F4 {
    const LANES: usize = 4;
    #[inline(always)]
    fn splat(v: f64) -> Self {
        F4([v; 4])
    }
    #[inline(always)]
    fn lane(self, i: usize) -> f64 {
        self.0[i]
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        let a = self.0;
        F4([a[0].sqrt(), a[1].sqrt(), a[2].sqrt(), a[3].sqrt()])
    }
    #[inline(always)]
    fn recip(self) -> Self {
        let a = self.0;
        F4([1.0 / a[0], 1.0 / a[1], 1.0 / a[2], 1.0 / a[3]])
    }
}

// The lanes are written out rather than built with `array::from_fn` / `map`, whose per-lane closures a
// profile showed partly out of line (`core::array::try_from_fn`); the results are the same IEEE
// operations, lane by lane.
macro_rules! lanewise {
    ($trait:ident, $f:ident, $op:tt) => {
        impl $trait for F4 {
            type Output = F4;
            #[inline(always)]
            fn $f(self, o: F4) -> F4 {
                let (a, b) = (self.0, o.0);
                F4([a[0] $op b[0], a[1] $op b[1], a[2] $op b[2], a[3] $op b[3]])
            }
        }
    };
}
lanewise!(Add, add, +);
lanewise!(Sub, sub, -);
lanewise!(Mul, mul, *);

impl Neg for F4 {
    type Output = F4;
    #[inline(always)]
    fn neg(self) -> F4 {
        let a = self.0;
        F4([-a[0], -a[1], -a[2], -a[3]])
    }
}
