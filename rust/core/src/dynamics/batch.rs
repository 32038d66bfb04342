//! Many initial states in parallel (rayon over packs of four, each pack stepped in SIMD lanes): the
//! antenna axes, or the paper's objective (1) directly.

use rayon::prelude::*;

use crate::error::{ensure_finite, Result};
use crate::guard;

use super::integrate::{check_stable, check_state, check_times, check_work, walk, Plan};
use super::lanes::{Real, F4};
use super::model::{State, TumbleModel};

/// States per pack: the lanes of [`F4`].
const PACK: usize = F4::LANES;

/// The initial state of a parameter vector `b = (psi, alpha, phi, wx, wy, wz)` (rad, rad/s).
#[inline]
fn state_of(b: &[f64; 6]) -> State {
    State::from_angles([b[0], b[1], b[2]], [b[3], b[4], b[5]])
}

/// The initial states of up to [`PACK`] parameter vectors in lanes; missing lanes repeat the last row
/// (computed and dropped).
fn pack_of(rows: &[[f64; 6]]) -> State<F4> {
    let s: [State; PACK] = std::array::from_fn(|l| state_of(&rows[l.min(rows.len() - 1)]));
    State {
        q: std::array::from_fn(|i| F4(std::array::from_fn(|l| s[l].q[i]))),
        omega: std::array::from_fn(|i| F4(std::array::from_fn(|l| s[l].omega[i]))),
    }
}

/// [`walk`] over one pack of rows, compiled for AVX2 where the CPU has it. Without FMA the AVX2 build does
/// the same IEEE operations in wider registers, so its results equal the baseline build's bit for bit
/// (on any x86-64 CPU).
fn walk_pack(
    model: &TumbleModel,
    rows: &[[f64; 6]],
    times_s: &[f64],
    plan: &Plan,
    visit: impl FnMut(usize, &State<F4>) -> bool,
) -> Result<()> {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") {
        // SAFETY: the CPU supports the feature the function is compiled for.
        return unsafe { walk_avx2(model, pack_of(rows), times_s, plan, visit) };
    }
    walk(model, pack_of(rows), times_s, plan, visit)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn walk_avx2(
    model: &TumbleModel,
    initial: State<F4>,
    times_s: &[f64],
    plan: &Plan,
    visit: impl FnMut(usize, &State<F4>) -> bool,
) -> Result<()> {
    walk(model, initial, times_s, plan, visit)
}

/// Objective (1) of one pack of rows, compiled for AVX2 where the CPU has it (bit for bit the baseline
/// build's, as [`walk_pack`]).
fn cost_pack(
    model: &TumbleModel,
    rows: &[[f64; 6]],
    times_s: &[f64],
    measured: &[[f64; 3]],
    plan: &Plan,
) -> Result<F4> {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") {
        // SAFETY: the CPU supports the feature the function is compiled for.
        return unsafe { cost_avx2(model, pack_of(rows), times_s, measured, plan) };
    }
    cost_walk(model, pack_of(rows), times_s, measured, plan)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn cost_avx2(
    model: &TumbleModel,
    initial: State<F4>,
    times_s: &[f64],
    measured: &[[f64; 3]],
    plan: &Plan,
) -> Result<F4> {
    cost_walk(model, initial, times_s, measured, plan)
}

/// The sum over times of `|a(t_k) - m_k|^2`, each lane one state, instantiated inside [`cost_avx2`]
/// (the accumulation written out per component rather than through `array::from_fn`). A profile
/// (`perf`, 128 states at 4.8 s steps) still shows the visiting closure as its own symbol, about a fifth
/// of the objective's time: inlining it is left to a later change.
#[inline(always)]
fn cost_walk(
    model: &TumbleModel,
    initial: State<F4>,
    times_s: &[f64],
    measured: &[[f64; 3]],
    plan: &Plan,
) -> Result<F4> {
    let mut cost = F4::splat(0.0);
    walk(model, initial, times_s, plan, |k, s| {
        let a = s.axis_orbital();
        let m = measured[k];
        let d0 = a[0] - F4::splat(m[0]);
        let d1 = a[1] - F4::splat(m[1]);
        let d2 = a[2] - F4::splat(m[2]);
        cost = cost + (d0 * d0 + d1 * d1 + d2 * d2);
        true
    })?;
    Ok(cost)
}

/// `f` over the packs of `params`, in order: on rayon's pool, or on the calling thread when there is one
/// pack or the pool has one thread (handing the work to the pool's thread and waiting for it costs a
/// wake-up per call, more than a one-pack call's work on a loaded machine). The results do not depend on
/// the path.
fn map_packs<T: Send>(
    params: &[[f64; 6]],
    f: impl Fn(&[[f64; 6]]) -> Result<T> + Sync + Send,
) -> Result<Vec<T>> {
    if params.len() <= PACK || rayon::current_num_threads() <= 1 {
        params.chunks(PACK).map(f).collect()
    } else {
        params.par_chunks(PACK).map(f).collect()
    }
}

fn check_params(model: &TumbleModel, params: &[[f64; 6]], plan: &Plan) -> Result<()> {
    ensure_finite("params", params.iter().flatten())?;
    for (i, b) in params.iter().enumerate() {
        let s = state_of(b);
        check_state(&s)?;
        check_stable(model, &s, plan, Some(i))?;
    }
    Ok(())
}

/// Axes (library orbital frame) of each parameter vector at each time: `out[i][k]`.
///
/// # Arguments
/// * `params` - `(psi, alpha, phi, wx, wy, wz)` at `t = 0`: the paper's angles (rad, intrinsic `YZY`) and
///   the absolute angular velocity in body axes (rad/s).
/// * `times_s`, `step_s` - as [`super::propagate`].
///
/// Runs on rayon's global pool (set its size with `RAYON_NUM_THREADS`).
///
/// # Errors
/// As [`super::propagate`]: [`crate::Error::NonFinite`] or [`crate::Error::OutOfRange`] for invalid
/// inputs or a step too long for a row's rate; [`crate::Error::TooLarge`] for more than
/// [`super::MAX_RK4_STEPS`] steps over all rows or [`super::MAX_OUTPUT_VALUES`] output values;
/// [`crate::Error::Numerical`] if a row's integration diverges; [`crate::Error::Interrupted`].
pub fn propagate_axes_batch(
    model: &TumbleModel,
    params: &[[f64; 6]],
    times_s: &[f64],
    step_s: f64,
) -> Result<Vec<Vec<[f64; 3]>>> {
    model.validate()?;
    let plan = check_times(times_s, step_s)?;
    check_work(&plan, params.len(), 3 * times_s.len())?;
    check_params(model, params, &plan)?;
    let packs = map_packs(params, |rows| {
        let mut out = vec![Vec::with_capacity(times_s.len()); rows.len()];
        walk_pack(model, rows, times_s, &plan, |_, s| {
            let a = s.axis_orbital();
            for (l, o) in out.iter_mut().enumerate() {
                o.push([a[0].lane(l), a[1].lane(l), a[2].lane(l)]);
            }
            true
        })?;
        Ok(out)
    })?;
    Ok(packs.into_iter().flatten().collect())
}

/// The paper's objective (1) for each parameter vector: the sum over times of the squared distance
/// between the modelled axis and the measured one, `sum_k |a(t_k; b) - a_meas_k|^2` (dimensionless).
///
/// # Arguments
/// * `measured` - measured axis directions (library orbital frame), one per time.
///
/// # Errors
/// As [`propagate_axes_batch`] (the output is one value per row); [`crate::Error::Shape`] unless one
/// measurement per time; [`crate::Error::Numerical`] for a cost that overflows.
pub fn axis_cost_batch(
    model: &TumbleModel,
    params: &[[f64; 6]],
    times_s: &[f64],
    measured: &[[f64; 3]],
    step_s: f64,
) -> Result<Vec<f64>> {
    model.validate()?;
    let plan = check_times(times_s, step_s)?;
    check_work(&plan, params.len(), 1)?;
    check_params(model, params, &plan)?;
    if measured.len() != times_s.len() {
        return Err(crate::Error::Shape {
            name: "measured",
            expected: format!("({}, 3)", times_s.len()),
            actual: format!("({}, 3)", measured.len()),
        });
    }
    ensure_finite("measured", measured.iter().flatten())?;
    let packs = map_packs(params, |rows| {
        let cost = cost_pack(model, rows, times_s, measured, &plan)?;
        Ok(cost.0[..rows.len()].to_vec())
    })?;
    let cost: Vec<f64> = packs.into_iter().flatten().collect();
    // Unit axes against finite measurements: only measurements near the f64 limit overflow the squares.
    guard::finite_output(
        "tumble objective",
        &cost,
        "the measured axes are expected as unit vectors",
    )?;
    Ok(cost)
}
