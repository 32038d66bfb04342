"""Rotation from visibility (Belokonov et al.), timings: one differential-evolution fit (time, objective
evaluations), the Rust batch objective against a vectorised numpy RK4 of the same equations (ratio) and at the
fit's search step (axes interpolated), and the 400-case study extrapolated from ``--trials`` trials run
through the Monte Carlo driver on this machine's cores.

Run: ``python benches/python/visibility_fit.py [--trials 8]`` (``RAYON_NUM_THREADS`` sets rayon's threads).
"""

from __future__ import annotations

import argparse
import os
import time

import numpy as np

from gnssatt import montecarlo
from gnssatt.attitude import dynamics as tumble
from gnssatt.experiments import visibility_rotation as vr


def numpy_cost(params: np.ndarray, t: np.ndarray, meas: np.ndarray, m: tumble.TumbleModel) -> np.ndarray:
    """Objective (1) for a (S, 6) population: RK4 with 1 s steps on (S, 7) arrays, same model as the core."""
    from scipy.spatial.transform import Rotation

    q = Rotation.from_euler("YZY", params[:, :3]).as_quat()  # x, y, z, w
    s = np.c_[q[:, 3], q[:, :3], params[:, 3:]]
    inertia = np.array(m.inertia_kg_m2)
    w0 = m.orbital_rate_rad_s
    k = 0.5 * m.density_kg_m3 * m.drag_coefficient * m.area_m2 * m.speed_m_s**2
    cp = np.array(m.cp_offset_m)

    def f(s: np.ndarray) -> np.ndarray:
        w, x, y, z = s[:, 0], s[:, 1], s[:, 2], s[:, 3]
        om = s[:, 4:]
        er = np.c_[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)]
        ev = np.c_[2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)]
        en = np.c_[2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]
        mom = np.cross(inertia * om, om) + 3 * w0**2 * np.cross(er, inertia * er) + np.cross(cp, -k * ev)
        u = om - w0 * en
        dq = (
            0.5
            * np.c_[
                -x * u[:, 0] - y * u[:, 1] - z * u[:, 2],
                w * u[:, 0] + y * u[:, 2] - z * u[:, 1],
                w * u[:, 1] + z * u[:, 0] - x * u[:, 2],
                w * u[:, 2] + x * u[:, 1] - y * u[:, 0],
            ]
        )
        return np.c_[dq, mom / inertia]

    def axis(s: np.ndarray) -> np.ndarray:
        w, x, y, z = s[:, 0], s[:, 1], s[:, 2], s[:, 3]
        return np.c_[1 - 2 * (x * x + z * z), 2 * (y * z + w * x), 2 * (x * y - w * z)]

    cost = np.sum((axis(s) - meas[0]) ** 2, axis=1)
    for kk in range(1, len(t)):
        h = t[kk] - t[kk - 1]
        k1 = f(s)
        k2 = f(s + 0.5 * h * k1)
        k3 = f(s + 0.5 * h * k2)
        k4 = f(s + h * k3)
        s = s + h / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
        s[:, :4] /= np.linalg.norm(s[:, :4], axis=1, keepdims=True)
        cost += np.sum((axis(s) - meas[kk]) ** 2, axis=1)
    return cost


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--trials", type=int, default=8)
    args = ap.parse_args()
    model = tumble.TumbleModel.circular(500e3)
    t = np.arange(0.0, 1501.0)
    rng = np.random.default_rng(5)
    truth = vr.random_initial_state(rng)
    meas = vr.noisy_axes(rng, tumble.propagate_axes(truth, t, model), 5.0)
    print(f"cores: {os.cpu_count()}, RAYON_NUM_THREADS={os.environ.get('RAYON_NUM_THREADS', 'unset')}")

    t0 = time.perf_counter()
    fit = tumble.fit_rotation(t, meas, model, rng=1)
    dt = time.perf_counter() - t0
    print(
        f"one fit (1501 epochs, 1500 s): {dt:.2f} s, {fit.nfev} objective evaluations, {fit.nit} generations,"
    )
    print(f"  {dt / fit.nfev * 1e6:.0f} us per evaluation, stopped by {fit.stopped_by}")

    pop = np.c_[
        rng.uniform(0, 2 * np.pi, 90), rng.uniform(0, np.pi, 90), rng.uniform(0, 2 * np.pi, 90),
        rng.uniform(-0.05, 0.05, (90, 3)),
    ]  # fmt: skip
    reps = 5
    t0 = time.perf_counter()
    for _ in range(reps):
        c_rust = tumble.axis_cost(pop, t, meas, model)
    t_rust = (time.perf_counter() - t0) / reps
    t0 = time.perf_counter()
    c_np = numpy_cost(pop, t, meas, model)
    t_np = time.perf_counter() - t0
    agree = np.max(np.abs(c_rust - c_np) / np.maximum(c_np, 1.0))
    print(f"batch objective, 90 states x 1501 epochs: Rust {t_rust * 1e3:.1f} ms, numpy {t_np * 1e3:.0f} ms,")
    print(f"  ratio {t_np / t_rust:.0f}x; max relative difference {agree:.1e}")

    # The fit's global search: RK4 steps of SEARCH_TURN_RAD at the box's fastest rate, axes interpolated.
    h = tumble.SEARCH_TURN_RAD / (np.sqrt(3.0) * tumble.MAX_RATE_RAD_S + 2.0 * model.orbital_rate_rad_s)
    t0 = time.perf_counter()
    for _ in range(reps):
        c_search = tumble.axis_cost(pop, t, meas, model, step_s=h)
    t_search = (time.perf_counter() - t0) / reps
    diff = np.max(np.abs(c_search - c_rust) / c_rust)
    print(f"  at the search step {h:.2f} s: {t_search * 1e3:.1f} ms ({t_rust / t_search:.1f}x faster,")
    print(f"  max relative difference of the objective from 1 s steps {diff:.1e})")

    # The driver's default pool uses the spawn start method: a forked worker would inherit rayon's threads
    # (already started above) and deadlock.
    n = args.trials
    t0 = time.perf_counter()
    montecarlo.run(vr.trial, n, seed=1, progress=False)
    dt = time.perf_counter() - t0
    print(
        f"study: {n} trials in {dt:.1f} s on {os.cpu_count()} cores -> 400 trials extrapolated to "
        f"{dt / n * 400 / 60:.1f} min (linear extrapolation from {n} trials, not a full run)"
    )


if __name__ == "__main__":
    main()
