//! The relaxed modulus bound: the largest `|sum_j exp(j x_j')|` when each phase `x_j'` may lie anywhere
//! within `delta_j` of `x_j`.
//!
//! One modulus `|sum_j exp(j x_j)| = max_w sum_j cos(x_j - w)` is at most `max_w sum_j h_j(w)`, where
//! `h_j(w) = 1` if `|x_j - w| <= delta_j` (mod 2 pi) and `cos(|x_j - w| - delta_j)` otherwise. Between
//! consecutive breakpoints `x_j +- delta_j`, `x_j + pi` each term is either 1 or `Re(exp(j(x_j -+ delta_j -
//! w)))`, so the sum is `P + Re(exp(-j w) C)` <= `P + |C|`; the bound is the largest `P + |C|` over the
//! segments (and never above the triangle bound `|sum_j exp(j x_j)| + sum_j 2 sin(delta_j / 2)` nor the
//! number of terms). It treats the phases as independent: how they are tied to one attitude is forgotten.

use std::f64::consts::{PI, TAU};

use super::direction::wrap_turn;

/// `x` in `[0, 2 pi)`; exactly, unlike [`wrap_turn`], so that the breakpoints sort into one turn.
fn wrap2pi(x: f64) -> f64 {
    x.rem_euclid(TAU)
}

/// One phase of the bound: centre `x` in `[0, 2 pi)` (to a few ulps), half-width `d < pi`, the unit
/// vectors at `x - d` and `x + d`, and which of the three pieces of `h_j` the sweep is on.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Member {
    x: f64,
    d: f64,
    minus: (f64, f64),
    plus: (f64, f64),
    piece: Piece,
}

/// The piece of `h_j(w)`: inside the arc (1), or `cos` of the distance to its lower (`x - d`, where
/// `x - w > d`) or upper end.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Piece {
    Inside,
    Below,
    Above,
}

impl Member {
    /// The piece at `w` in `[0, 3 pi)`.
    fn piece_at(&self, w: f64) -> Piece {
        // x - w in (-pi, pi]: both are in [0, 2 pi + pi).
        let mut a = self.x - w;
        if a > PI {
            a -= TAU;
        } else if a <= -PI {
            a += TAU;
        }
        if a <= -PI {
            a += TAU;
        }
        if a.abs() <= self.d {
            Piece::Inside
        } else if a > 0.0 {
            Piece::Below
        } else {
            Piece::Above
        }
    }

    /// Adds (`sign` 1) or removes (-1) this member's share of `(P, C)` on its current piece.
    fn share(&self, sign: f64, (p, cs, sn): &mut (f64, f64, f64)) {
        match self.piece {
            Piece::Inside => *p += sign,
            Piece::Below => {
                *cs += sign * self.minus.0;
                *sn += sign * self.minus.1;
            }
            Piece::Above => {
                *cs += sign * self.plus.0;
                *sn += sign * self.plus.1;
            }
        }
    }
}

/// Upper bound of `|sum_j exp(j x_j')|` over `|x_j' - x_j| <= delta_j` (module docs). `scratch` holds
/// the breakpoints and whose they are, `members` the phases with `delta_j < pi`.
///
/// The sweep visits the segments in order and moves only the member whose breakpoint it crossed to
/// the piece it has at the new segment's midpoint (the rest keep theirs): `n` updates instead of `n`
/// pieces per segment. Where breakpoints coincide, the empty segment between them may mix pieces of
/// two points; that only adds a candidate to the maximum. The running sums differ from sums taken
/// afresh by a few ulps of `n`, far inside the search's tolerances (`bnb`'s 1e-6 on every target).
pub(crate) fn modulus_bound(
    xs: &[f64],
    deltas: &[f64],
    scratch: &mut Vec<(f64, u32)>,
    members: &mut Vec<Member>,
) -> f64 {
    let n = xs.len() as f64;
    let (mut s, mut c, mut tri) = (0.0, 0.0, 0.0);
    let mut always = 0.0;
    scratch.clear();
    members.clear();
    for (&x, &d) in xs.iter().zip(deltas) {
        let x = wrap_turn(x);
        let (sx, cx) = x.sin_cos();
        s += sx;
        c += cx;
        // sin and cos of x -+ d by the angle-addition formulas from those of x and d / 2 (two sin_cos
        // per term instead of four: this bound is most of a leaf box's cost).
        let (sh, ch) = (0.5 * d.min(PI)).sin_cos();
        tri += 2.0 * sh;
        if d >= PI {
            always += 1.0;
        } else {
            let (sd, cd) = (2.0 * sh * ch, 1.0 - 2.0 * sh * sh);
            let k = members.len() as u32;
            members.push(Member {
                x,
                d,
                minus: (cx * cd + sx * sd, sx * cd - cx * sd),
                plus: (cx * cd - sx * sd, sx * cd + cx * sd),
                piece: Piece::Inside,
            });
            scratch.extend([
                (wrap2pi(x - d), k),
                (wrap2pi(x + d), k),
                (wrap2pi(x + PI), k),
            ]);
        }
    }
    // |.| <= n: no overflow, so no need for hypot's scaling (a tenth of a box's cost).
    let triangle = (s * s + c * c).sqrt() + tri;
    if scratch.is_empty() || triangle <= always + 1e-12 {
        return n.min(triangle);
    }
    scratch.sort_unstable_by(|a, b| a.0.total_cmp(&b.0));
    let nb = scratch.len();
    // The last segment wraps round to the first breakpoint; every piece is taken there.
    let w = 0.5 * (scratch[nb - 1].0 + scratch[0].0 + TAU);
    let mut sums = (always, 0.0, 0.0);
    for m in members.iter_mut() {
        m.piece = m.piece_at(w);
        m.share(1.0, &mut sums);
    }
    let value = |(p, cs, sn): (f64, f64, f64)| p + (cs * cs + sn * sn).sqrt();
    let mut sweep = value(sums);
    for b in 0..nb - 1 {
        let w = 0.5 * (scratch[b].0 + scratch[b + 1].0);
        let m = &mut members[scratch[b].1 as usize];
        let piece = m.piece_at(w);
        if piece != m.piece {
            m.share(-1.0, &mut sums);
            m.piece = piece;
            m.share(1.0, &mut sums);
        }
        sweep = sweep.max(value(sums));
    }
    n.min(triangle).min(sweep)
}

#[cfg(test)]
mod tests {
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    use super::*;

    /// `|sum_j exp(j x_j)|`.
    fn modulus(xs: &[f64]) -> f64 {
        let (s, c) = xs
            .iter()
            .fold((0.0, 0.0), |(s, c), x| (s + x.sin(), c + x.cos()));
        s.hypot(c)
    }

    /// The module docs' bound taken afresh on every segment (midpoint pieces, `sin` and `cos` of the
    /// arc ends directly): the oracle for the sweep's running sums.
    fn bound_afresh(xs: &[f64], ds: &[f64]) -> f64 {
        let n = xs.len() as f64;
        let tri: f64 = ds.iter().map(|d| 2.0 * (d.min(PI) / 2.0).sin()).sum();
        let mut cuts: Vec<f64> = vec![];
        for (&x, &d) in xs.iter().zip(ds) {
            if d < PI {
                cuts.extend([x - d, x + d, x + PI].map(|c| c.rem_euclid(TAU)));
            }
        }
        let mut best = n.min(modulus(xs) + tri);
        if cuts.is_empty() {
            return best;
        }
        cuts.sort_by(f64::total_cmp);
        let mut sweep: f64 = 0.0;
        for b in 0..cuts.len() {
            let next = cuts.get(b + 1).copied().unwrap_or(cuts[0] + TAU);
            let w = 0.5 * (cuts[b] + next);
            let (mut p, mut cs, mut sn) = (0.0, 0.0, 0.0);
            for (&x, &d) in xs.iter().zip(ds) {
                let a = (x - w + PI).rem_euclid(TAU) - PI;
                if a.abs() <= d {
                    p += 1.0;
                } else {
                    let end = if a > 0.0 { x - d } else { x + d };
                    cs += end.cos();
                    sn += end.sin();
                }
            }
            sweep = sweep.max(p + cs.hypot(sn));
        }
        best = best.min(sweep);
        best
    }

    #[test]
    fn bound_is_never_below_a_brute_force_maximum() {
        // 1-4 phases anywhere (unwrapped, up to +-50 rad), half-widths 0-4 rad (0 and just under pi
        // included): every combination of 13
        // points across each arc (ends included) stays at or below the bound, and the bound stays at or
        // below the number of terms and the triangle bound.
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        let (mut scratch, mut members) = (vec![], vec![]);
        for trial in 0..400 {
            let n = rng.random_range(1..=4);
            let xs: Vec<f64> = (0..n).map(|_| rng.random_range(-50.0..50.0)).collect();
            let ds: Vec<f64> = (0..n)
                .map(|_| match rng.random_range(0..10) {
                    // Coinciding breakpoints: x - d = x + d, or x + d next to x + pi.
                    0 | 1 => 0.0,
                    2 => PI - 1e-15,
                    _ => rng.random_range(0.0..4.0),
                })
                .collect();
            let bound = modulus_bound(&xs, &ds, &mut scratch, &mut members);
            let k = 13usize;
            let mut best: f64 = 0.0;
            let mut x = vec![0.0; n];
            for combo in 0..k.pow(n as u32) {
                let mut c = combo;
                for j in 0..n {
                    x[j] = xs[j] - ds[j] + 2.0 * ds[j] * (c % k) as f64 / (k - 1) as f64;
                    c /= k;
                }
                best = best.max(modulus(&x));
            }
            let triangle: f64 = modulus(&xs)
                + ds.iter()
                    .map(|d| 2.0 * (d.min(PI) / 2.0).sin())
                    .sum::<f64>();
            assert!(best <= bound + 1e-12, "trial {trial}: {best} > {bound}");
            assert!(bound <= n as f64 + 1e-12 && bound <= triangle + 1e-12);
            // The running sums give the formula's value (more only where breakpoints coincide).
            let afresh = bound_afresh(&xs, &ds);
            assert!(bound >= afresh - 1e-12, "trial {trial}: {bound} < {afresh}");
            if ds.iter().all(|&d| d > 1e-9 && d < PI - 1e-9) {
                assert!(bound <= afresh + 1e-12, "trial {trial}: {bound} > {afresh}");
            }
        }
    }
}
