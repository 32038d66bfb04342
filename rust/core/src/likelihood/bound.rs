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

fn wrap2pi(x: f64) -> f64 {
    x.rem_euclid(TAU)
}

/// Upper bound of `|sum_j exp(j x_j')|` over `|x_j' - x_j| <= delta_j` (module docs). `scratch` holds
/// the breakpoints, `members` per member `(x, delta, cos(x - delta), sin(x - delta), cos(x + delta),
/// sin(x + delta))`.
pub(crate) fn modulus_bound(
    xs: &[f64],
    deltas: &[f64],
    scratch: &mut Vec<f64>,
    members: &mut Vec<[f64; 6]>,
) -> f64 {
    let n = xs.len() as f64;
    let (mut s, mut c, mut tri) = (0.0, 0.0, 0.0);
    let mut always = 0.0;
    scratch.clear();
    members.clear();
    for (&x, &d) in xs.iter().zip(deltas) {
        let x = x.rem_euclid(TAU);
        let (sx, cx) = x.sin_cos();
        s += sx;
        c += cx;
        tri += 2.0 * (d.min(PI) / 2.0).sin();
        if d >= PI {
            always += 1.0;
        } else {
            let (sm, cm) = (x - d).sin_cos();
            let (sp, cp) = (x + d).sin_cos();
            members.push([x, d, cm, sm, cp, sp]);
            scratch.extend([wrap2pi(x - d), wrap2pi(x + d), wrap2pi(x + PI)]);
        }
    }
    let triangle = s.hypot(c) + tri;
    if scratch.is_empty() || triangle <= always + 1e-12 {
        return n.min(triangle);
    }
    scratch.sort_by(f64::total_cmp);
    let nb = scratch.len();
    let mut sweep: f64 = 0.0;
    for b in 0..nb {
        let (a0, a1) = (
            scratch[b],
            if b + 1 < nb {
                scratch[b + 1]
            } else {
                scratch[0] + TAU
            },
        );
        let w = 0.5 * (a0 + a1);
        let (mut p, mut cs, mut sn) = (always, 0.0, 0.0);
        for m in members.iter() {
            // x - w in (-pi, pi]: both are in [0, 2 pi + pi).
            let mut a = m[0] - w;
            if a > PI {
                a -= TAU;
            } else if a <= -PI {
                a += TAU;
            }
            if a <= -PI {
                a += TAU;
            }
            if a.abs() <= m[1] {
                p += 1.0;
            } else if a > 0.0 {
                cs += m[2];
                sn += m[3];
            } else {
                cs += m[4];
                sn += m[5];
            }
        }
        sweep = sweep.max(p + cs.hypot(sn));
    }
    n.min(triangle).min(sweep)
}
