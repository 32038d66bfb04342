//! A baseline's direction set as a sparse raster: for each elevation bin of the grid's step, the
//! azimuth bins some kept direction box touches, with the largest bound `U_i` of those boxes.
//!
//! The branch-and-bound's row scan looks a node's direction up here instead of walking the box list: a
//! row at elevation `e` reads one raster row, and a heading node's azimuth `a = psi + beta` falls in one
//! bin. Boxes are closed and rasterised with a tolerance (`EPS`) wider than the f64 rounding of a node's
//! direction, so a node inside a box always finds a bin holding at least that box's bound; a node in no
//! box may find a bin too (it is then evaluated, never missed).

use std::f64::consts::FRAC_PI_2;

use super::direction::{floor, wrap_turn, DirBox};

/// Tolerance on box edges (radians): far above the f64 rounding of a node's direction (about 1e-15
/// rad), far below a bin.
const EPS: f64 = 1e-9;

/// Sparse raster of one baseline's direction set (module docs).
pub(crate) struct DirMap {
    /// Bin width on both axes, radians.
    width: f64,
    /// Azimuth bins per turn.
    na: i64,
    /// Per elevation bin `floor((e + pi/2) / width)`, the sorted azimuth bins and their bounds.
    rows: Vec<Vec<(u32, f32)>>,
}

impl DirMap {
    /// Rasterises `boxes` on bins of `width` radians (`na` of them per turn of azimuth). Bounds are
    /// rounded up to f32.
    pub fn new(boxes: &[DirBox], width: f64, na: usize) -> Self {
        let ne = (std::f64::consts::PI / width).ceil() as usize + 1;
        let mut rows: Vec<Vec<(u32, f32)>> = vec![vec![]; ne];
        let na = na as i64;
        for b in boxes {
            let e0 = (((b.e0 - EPS + FRAC_PI_2) / width).floor().max(0.0)) as usize;
            let e1 = (((b.e1 + EPS + FRAC_PI_2) / width).floor() as usize).min(ne - 1);
            let a0 = ((b.a0 - EPS) / width).floor() as i64;
            let a1 = (((b.a1 + EPS) / width).floor() as i64).min(a0 + na - 1);
            let u = round_up(b.bound);
            for row in &mut rows[e0..=e1] {
                row.extend((a0..=a1).map(|a| (a.rem_euclid(na) as u32, u)));
            }
        }
        for row in &mut rows {
            row.sort_unstable_by(|x, y| x.0.cmp(&y.0).then(y.1.total_cmp(&x.1)));
            row.dedup_by_key(|x| x.0);
        }
        DirMap { width, na, rows }
    }

    /// The raster row holding elevation `e` (radians).
    pub fn row(&self, e: f64) -> &[(u32, f32)] {
        let j = floor((e + FRAC_PI_2) / self.width);
        if j < 0.0 || j as usize >= self.rows.len() {
            return &[];
        }
        &self.rows[j as usize]
    }

    /// Azimuth bin of azimuth `a` (radians, any turn).
    pub fn bin(&self, a: f64) -> u32 {
        let k = floor(wrap_turn(a) / self.width) as i64;
        // wrap_turn may pass either end of the turn by a few ulps.
        (if k >= self.na {
            k - self.na
        } else if k < 0 {
            k + self.na
        } else {
            k
        }) as u32
    }

    /// Bin width, radians.
    pub fn width(&self) -> f64 {
        self.width
    }
}

/// Bound of azimuth bin `bin` in a raster row, if the row holds it.
pub(crate) fn lookup(row: &[(u32, f32)], bin: u32) -> Option<f32> {
    row.binary_search_by_key(&bin, |x| x.0)
        .ok()
        .map(|k| row[k].1)
}

/// The smallest f32 not below `x`.
fn round_up(x: f64) -> f32 {
    let f = x as f32;
    if f64::from(f) >= x {
        f
    } else {
        f.next_up()
    }
}
