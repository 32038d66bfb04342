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
        F4(self.0.map(f64::sqrt))
    }
    #[inline(always)]
    fn recip(self) -> Self {
        F4(self.0.map(|v| 1.0 / v))
    }
}

macro_rules! lanewise {
    ($trait:ident, $f:ident, $op:tt) => {
        impl $trait for F4 {
            type Output = F4;
            #[inline(always)]
            fn $f(self, o: F4) -> F4 {
                F4(std::array::from_fn(|i| self.0[i] $op o.0[i]))
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
        F4(self.0.map(|v| -v))
    }
}
