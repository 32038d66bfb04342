//! Per-baseline direction sets: where on its sphere one baseline can point for the ambiguity function
//! to reach a threshold.
//!
//! With the per-baseline grouping, `Z(R) = sum_i F_i(R r_i)` with `F_i(v) = |sum_k exp(j (d_ik + g_k .
//! v))|`: baseline `i` enters only through the direction of `R r_i`. A heading turn `Ry(psi)` moves that
//! direction along a parallel, so it is parametrised as `u(a, e) = (cos e cos a, sin e, -cos e sin a)`
//! (normal frame N, U, E): elevation `e`, and "azimuth" `a = psi + beta` with `beta = atan2(-w_E, w_N)`
//! of `w = Rz(theta) Rx(phi) r_i` (the pitch-roll part of the row, as in the kernel's row coefficients).
//!
//! [`direction_set`] covers `{(a, e) : F_i(u(a, e)) >= tau}` by closed parameter boxes: a 2-D
//! branch-and-bound whose test needs no trigonometry. Over a box of centre `c` and half-widths `(h_a,
//! h_e)` each phase stays within `delta_k = |r_i| (|g_k . d_a u| h_a + |g_k . d_e u| h_e + |g_k| (h_a +
//! h_e)^2 / 2)` of its value at `c` (Taylor; every second derivative of `u` along a segment of the box
//! has norm at most `(h_a + h_e)^2`, since `|u_aa| = cos e`, `|u_ae| = |sin e|`, `|u_ee| = 1`). If `F_i
//! >= tau = n - s` somewhere in the box, one phase direction `w` makes every term contribute at least
//! `1 - s` (the others contribute at most 1), i.e. every phase lies within `delta_k + acos(1 - s)` of
//! `w`: the arcs of those radii around the centre phases share a point. A box whose arcs do not is
//! dropped. Leaf boxes (half-width `h_min`, a fraction of the grid step) are kept if the relaxed bound
//! of [`modulus_bound`] (each phase free in its arc, maximised exactly) reaches `tau`.

use std::f64::consts::{FRAC_PI_2, PI, TAU};
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};

use nalgebra::Vector3;
use rayon::prelude::*;

use super::bound::{modulus_bound, Member};
use super::model::Model;

/// A closed box of direction parameters (radians): azimuth `a0..=a1`, elevation `e0..=e1`, and an upper
/// bound of `F_i` over it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct DirBox {
    pub a0: f64,
    pub a1: f64,
    pub e0: f64,
    pub e1: f64,
    pub bound: f64,
}

/// Unit direction of parameters `(a, e)` in the normal frame (the box test builds it from the sines it
/// needs anyway).
#[cfg(test)]
pub(crate) fn unit(a: f64, e: f64) -> Vector3<f64> {
    let (sa, ca) = a.sin_cos();
    let (se, ce) = e.sin_cos();
    Vector3::new(ce * ca, se, -ce * sa)
}

/// Parameters `(beta, e)` of `w = Rz(theta) Rx(phi) r` for a baseline of length `len`: `R r` points
/// along `u(psi + beta, e)`.
pub(crate) fn row_direction(w: &Vector3<f64>, len: f64) -> (f64, f64) {
    ((-w.z).atan2(w.x), (w.y / len).clamp(-1.0, 1.0).asin())
}

/// Elevation bins of the top boxes of the direction search for baseline `i` (twice as many azimuth
/// bins): wide enough that the phases move about 1.5 rad across a box (where the test starts to prune),
/// at least 8 (to spread over threads and follow a window). A float: the caller checks the count
/// against its work limit before anything of that size is allocated.
pub(crate) fn top_rows(model: &Model, i: usize) -> f64 {
    let g_max = model.g.iter().map(|g| g.norm()).fold(0.0, f64::max);
    let h = 1.5 / (g_max * model.baselines[i].norm()).max(1e-9);
    (PI / (2.0 * h)).ceil().max(8.0)
}

/// Top boxes `(na, ne)` of the direction search for baseline `i` ([`top_rows`]; the count must have
/// been checked).
pub(crate) fn top_bins(model: &Model, i: usize) -> (usize, usize) {
    let ne = top_rows(model, i) as usize;
    (2 * ne, ne)
}

/// Which top boxes a baseline's direction can reach from the grid's cells.
pub(crate) struct Reach {
    bins: Vec<bool>,
    na: usize,
    ne: usize,
}

impl Reach {
    /// No bin reached yet, `(na, ne)` from [`top_bins`]; every bin when `all`.
    pub fn new((na, ne): (usize, usize), all: bool) -> Self {
        Reach {
            bins: vec![all; na * ne],
            na,
            ne,
        }
    }

    /// Marks the directions within `a_lo..=a_hi` (any length; a span of a turn or more is every azimuth)
    /// and `e_lo..=e_hi`, with one bin of slack for rounding.
    pub fn add(&mut self, a_lo: f64, a_hi: f64, e_lo: f64, e_hi: f64) {
        let (na, ne) = (self.na as i64, self.ne as i64);
        let wa = TAU / na as f64;
        let we = PI / ne as f64;
        let e0 = (((e_lo + FRAC_PI_2) / we).floor() as i64 - 1).max(0);
        let e1 = (((e_hi + FRAC_PI_2) / we).floor() as i64 + 1).min(ne - 1);
        let (a0, a1) = if a_hi - a_lo >= TAU - 2.0 * wa {
            (0, na - 1)
        } else {
            (
                (a_lo / wa).floor() as i64 - 1,
                (a_hi / wa).floor() as i64 + 1,
            )
        };
        for e in e0..=e1 {
            for a in a0..=a1 {
                self.bins[(e * na + a.rem_euclid(na)) as usize] = true;
            }
        }
    }
}

/// Work shared by the searches of all baselines: boxes tested, against a limit.
pub(crate) struct Budget {
    used: AtomicU64,
    limit: u64,
    over: AtomicBool,
}

impl Budget {
    pub fn new(limit: u64) -> Self {
        Budget {
            used: AtomicU64::new(0),
            limit,
            over: AtomicBool::new(false),
        }
    }

    /// Counts `n` units of work; false once the limit is passed (by any thread).
    pub fn spend(&self, n: u64) -> bool {
        if self.used.fetch_add(n, Ordering::Relaxed) + n > self.limit {
            self.over.store(true, Ordering::Relaxed);
        }
        !self.over.load(Ordering::Relaxed)
    }

    pub fn used(&self) -> u64 {
        self.used.load(Ordering::Relaxed)
    }

    pub fn exceeded(&self) -> bool {
        self.over.load(Ordering::Relaxed)
    }
}

/// `x` reduced to `[0, 2 pi)` up to a few ulps of `x` (either end may be passed by that much), without
/// the division remainder of `rem_euclid` or a call of `floor` (not inlined without SSE4.1), which cost
/// more than the rest of a box test. For `|x| < 2^62` (phases here are below 1e4 rad).
#[inline]
pub(crate) fn wrap_turn(x: f64) -> f64 {
    x - TAU * floor(x * (1.0 / TAU))
}

/// `x.floor()` for `|x| < 2^62` through a truncating conversion.
#[inline]
pub(crate) fn floor(x: f64) -> f64 {
    let t = x as i64 as f64;
    if t > x {
        t - 1.0
    } else {
        t
    }
}

/// Circular distance of two angles in `[0, 2 pi)` (a few ulps outside is harmless).
fn circ_dist(a: f64, b: f64) -> f64 {
    let d = (a - b).abs();
    d.min(TAU - d)
}

/// Whether the closed arcs `x_k +- r_k` (centres in `[0, 2 pi)`) share a point. A non-empty
/// intersection that is not the whole circle starts at the start of one of the arcs, so those `n` points
/// are the only ones to try. The tolerance only ever keeps a box.
fn arcs_meet(x: &[f64], r: &[f64]) -> bool {
    let mut partial = false;
    for (&xk, &rk) in x.iter().zip(r) {
        if rk >= PI {
            continue;
        }
        partial = true;
        // xk - rk lies in (-pi, 2 pi): adding a turn below 0 wraps it without a floor (see wrap_turn).
        let w = if xk < rk { xk - rk + TAU } else { xk - rk };
        if x.iter()
            .zip(r)
            .all(|(&xj, &rj)| rj >= PI || circ_dist(w, xj) <= rj + 1e-9)
        {
            return true;
        }
    }
    !partial
}

/// A box of the direction search with `sin`, `cos` of its centre's azimuth and elevation and how many
/// times its top box was halved along each axis.
#[derive(Clone, Copy)]
struct Node {
    b: DirBox,
    trig: [f64; 4],
    level: (u8, u8),
}

struct Tester<'a> {
    model: &'a Model,
    i: usize,
    tau: f64,
    /// `acos(1 - s)`, `s = n - tau`.
    arc: f64,
    /// `|g_k|` per term, rad/m.
    g_norm: Vec<f64>,
    xs: Vec<f64>,
    radii: Vec<f64>,
    ds: Vec<f64>,
    scratch: Vec<(f64, u32)>,
    members: Vec<Member>,
}

impl Tester<'_> {
    /// Centre phases and their deviations over the box (`sin`, `cos` of the centre's azimuth and
    /// elevation given); returns the azimuth and elevation shares of the
    /// deviation (which axis to split).
    fn phases(&mut self, b: &DirBox, [sa, ca, se, ce]: [f64; 4], halvings: u32) -> (f64, f64) {
        let m = self.model;
        let len = m.baselines[self.i].norm();
        let (ha, he) = (0.5 * (b.a1 - b.a0), 0.5 * (b.e1 - b.e0));
        // The centre's sines come from `halvings` angle additions, each off by at most a few ulps
        // (values <= 1): each component of `u` by at most 8 ulps per addition, so a phase by at most
        // `|r| |g| 16 (halvings + 1) eps` (per metre of baseline and rad/m of `g`). Counted in the
        // deviation, so the test stays a bound whatever the baseline's length.
        let rounding = len * 16.0 * f64::from(halvings + 1) * f64::EPSILON;
        let u = Vector3::new(ce * ca, se, -ce * sa);
        let du_a = Vector3::new(-ce * sa, 0.0, -ce * ca);
        let du_e = Vector3::new(-se * ca, ce, se * sa);
        let quad = 0.5 * (ha + he) * (ha + he);
        let nt = m.n_terms();
        self.xs.clear();
        self.ds.clear();
        let (mut share_a, mut share_e) = (0.0, 0.0);
        for ((k, g), gn) in m.g.iter().enumerate().zip(&self.g_norm) {
            let x = m.d[self.i * nt + k] + len * g.dot(&u);
            let (da, de) = (len * g.dot(&du_a).abs() * ha, len * g.dot(&du_e).abs() * he);
            share_a += da;
            share_e += de;
            self.xs.push(wrap_turn(x));
            self.ds.push(da + de + len * gn * quad + rounding * gn);
        }
        (share_a, share_e)
    }

    /// The kept leaves below `top` (module docs), empty once `budget` runs out; `off` the angle-addition
    /// tables of [`Tester::children`].
    fn search(&mut self, top: Node, h_min: f64, off: Offsets, budget: &Budget) -> Vec<DirBox> {
        let mut out = vec![];
        if budget.exceeded() {
            return out;
        }
        let s = self.model.n_terms() as f64 - self.tau;
        let mut stack = vec![top];
        let mut tested = 0u64;
        while let Some(node) = stack.pop() {
            // Counted in batches: one shared atomic per box would serialise the threads.
            tested += 1;
            if tested.is_multiple_of(64) && !budget.spend(64) {
                return out;
            }
            let Node { b, trig, level } = node;
            let halvings = u32::from(level.0) + u32::from(level.1);
            let (share_a, share_e) = self.phases(&b, trig, halvings);
            if s < 2.0 && !self.may_reach() {
                continue;
            }
            let (ha, he) = (0.5 * (b.a1 - b.a0), 0.5 * (b.e1 - b.e0));
            let last = ha <= h_min && he <= h_min;
            if last || s >= 2.0 {
                let bound = modulus_bound(&self.xs, &self.ds, &mut self.scratch, &mut self.members);
                if bound < self.tau {
                    continue;
                }
                if last {
                    out.push(DirBox { bound, ..b });
                    continue;
                }
            }
            let split_a = he <= h_min || (ha > h_min && share_a >= share_e);
            stack.extend(children(node, split_a, off));
        }
        budget.spend(tested % 64);
        out
    }

    /// Whether `F_i` may reach `tau` in the box (module docs).
    fn may_reach(&mut self) -> bool {
        self.radii.clear();
        self.radii.extend(self.ds.iter().map(|d| d + self.arc));
        arcs_meet(&self.xs, &self.radii)
    }
}

/// Per level of halving, `sin_cos` of a child's offset from its parent's centre on the azimuth and the
/// elevation axis.
type Offsets<'a> = (&'a [(f64, f64)], &'a [(f64, f64)]);

/// The two halves of `node` along azimuth (`split_a`) or elevation, their centre sines by the
/// angle-addition formulas from the parent's (`off`; a `sin_cos` pair per box was a sixth of the search;
/// the rounding this accumulates over the levels is added to each phase's deviation,
/// [`Tester::phases`]).
fn children(Node { b, trig, level }: Node, split_a: bool, (off_a, off_e): Offsets) -> [Node; 2] {
    let [sa, ca, se, ce] = trig;
    let (mut l, mut h) = (b, b);
    let (trig_l, trig_h, level) = if split_a {
        let mid = 0.5 * (b.a0 + b.a1);
        (l.a1, h.a0) = (mid, mid);
        let (so, co) = off_a[usize::from(level.0.saturating_add(1))];
        (
            [sa * co - ca * so, ca * co + sa * so, se, ce],
            [sa * co + ca * so, ca * co - sa * so, se, ce],
            (level.0.saturating_add(1), level.1),
        )
    } else {
        let mid = 0.5 * (b.e0 + b.e1);
        (l.e1, h.e0) = (mid, mid);
        let (so, co) = off_e[usize::from(level.1.saturating_add(1))];
        (
            [sa, ca, se * co - ce * so, ce * co + se * so],
            [sa, ca, se * co + ce * so, ce * co - se * so],
            (level.0, level.1.saturating_add(1)),
        )
    };
    let node = |b, trig| Node { b, trig, level };
    [node(l, trig_l), node(h, trig_h)]
}

/// Boxes of direction parameters covering every direction where `F_i >= tau` (module docs), each of
/// half-width at most `h_min` (radians) on both axes. `None` when `budget` ran
/// out (the caller falls back to the exhaustive pass). With `n - tau >= 2` the arc test is powerless
/// and every box is bounded by [`modulus_bound`].
pub(crate) fn direction_set(
    model: &Model,
    i: usize,
    tau: f64,
    h_min: f64,
    reach: &Reach,
    budget: &Budget,
) -> Option<Vec<DirBox>> {
    let n = model.n_terms() as f64;
    let s = n - tau;
    // The arc test needs s < 2; beyond, every box gets the relaxed bound (slower, still exact).
    let arc = if s <= 0.0 {
        0.0
    } else {
        (1.0 - s.min(2.0)).acos()
    };
    let (na, ne) = (reach.na, reach.ne);
    let (half_a, half_e) = (PI / na as f64, FRAC_PI_2 / ne as f64);
    // The angle-addition tables of `children`.
    let offsets = |h: f64| -> Vec<(f64, f64)> {
        (0..=u8::MAX)
            .map(|k| (h * 0.5f64.powi(i32::from(k))).sin_cos())
            .collect()
    };
    let (off_a, off_e) = (offsets(half_a), offsets(half_e));
    let tops: Vec<Node> = (0..na * ne)
        .filter(|&j| reach.bins[j])
        .map(|j| {
            let (ja, je) = ((j % na) as f64, (j / na) as f64);
            let b = DirBox {
                a0: TAU * ja / na as f64,
                a1: TAU * (ja + 1.0) / na as f64,
                e0: -FRAC_PI_2 + PI * je / ne as f64,
                e1: -FRAC_PI_2 + PI * (je + 1.0) / ne as f64,
                bound: n,
            };
            let (sa, ca) = (0.5 * (b.a0 + b.a1)).sin_cos();
            let (se, ce) = (0.5 * (b.e0 + b.e1)).sin_cos();
            Node {
                b,
                trig: [sa, ca, se, ce],
                level: (0, 0),
            }
        })
        .collect();
    let found: Vec<Vec<DirBox>> = tops
        .par_iter()
        .map_init(
            || Tester {
                model,
                i,
                tau,
                arc,
                g_norm: model.g.iter().map(|g| g.norm()).collect(),
                xs: vec![],
                radii: vec![],
                ds: vec![],
                scratch: vec![],
                members: vec![],
            },
            |t, top| t.search(*top, h_min, (&off_a, &off_e), budget),
        )
        .collect();
    if budget.exceeded() {
        return None;
    }
    Some(found.into_iter().flatten().collect())
}
