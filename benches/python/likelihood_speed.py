"""Times the full 1.5 deg likelihood grid (3 antennas, 0.71 m triangle, M = 8) three ways in one run: the
gnssatt Python API, a plain numpy evaluation, and the reference native kernel ../shared/perf/run.sh; prints
the ratios, thread scaling (RAYON_NUM_THREADS = 1, 2, and 16 when available) and branch-and-bound cells.

Run from anywhere: ``python benches/python/likelihood_speed.py [--reps 5]``.
"""

from __future__ import annotations

import argparse
import os
import re
import statistics
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

import gnssatt
from gnssatt import _core
from gnssatt.likelihood import rotation_from_euler

HERE = Path(__file__).resolve().parent
RUN_SH = HERE.parents[2] / "shared" / "perf" / "run.sh"  # ../shared/perf/run.sh from the repository root
L1 = 0.19029367279836487
STEP = 1.5
TRIANGLE = 0.71 * np.array([[1.0, 0.0, 0.0], [0.5, 0.0, np.sqrt(3) / 2]])


def scenario(m: int = 8, seed: int = 1):
    rng = np.random.default_rng(seed)
    az, el = rng.uniform(0, 2 * np.pi, m), rng.uniform(0.2, 1.4, m)
    los = np.stack([np.sin(az) * np.cos(el), np.cos(az) * np.cos(el), np.sin(el)], axis=1)
    r = rotation_from_euler([40.0, 3.0, -5.0])
    p = np.mod(-2 * np.pi / L1 * (r.apply(TRIANGLE) @ los.T) + rng.uniform(-3, 3, (2, 1)), 2 * np.pi)
    return p + 0.1 * rng.standard_normal(p.shape), los


def numpy_grid(p, los, step_deg=STEP):
    """Plain numpy ambiguity function over the whole grid (float64, vectorised per pitch slab)."""
    n = 2 * int(np.ceil(180 / step_deg))
    step = 2 * np.pi / n
    psi, theta, phi = (
        np.arange(n) * step,
        -np.pi / 2 + np.arange(n // 2 + 1) * step,
        -np.pi + np.arange(n) * step,
    )
    g = 2 * np.pi / L1 * los[:, [1, 2, 0]]  # (M, 3) normal frame (N, U, E)
    cps, sps = np.cos(psi)[:, None, None], np.sin(psi)[:, None, None]
    best = -np.inf
    for th in theta:
        ct, st = np.cos(th), np.sin(th)
        cf, sf = np.cos(phi), np.sin(phi)
        z = np.zeros((n, n))
        for i, r in enumerate(TRIANGLE):
            # w = Rz(theta) Rx(phi) r for every phi, normal frame.
            y = cf * r[1] - sf * r[2]
            wz = sf * r[1] + cf * r[2]
            wn, wu, we = ct * r[0] - st * y, st * r[0] + ct * y, wz
            a = p[i][None, :] + np.outer(wu, g[:, 1])  # (n_phi, M)
            b = np.outer(wn, g[:, 0]) + np.outer(we, g[:, 2])
            c = np.outer(we, g[:, 0]) - np.outer(wn, g[:, 2])
            x = a[None] + b[None] * cps + c[None] * sps  # (n_psi, n_phi, M)
            z += np.abs(np.exp(1j * x).sum(axis=2))
        best = max(best, float(z.max()))
    return best


def timed(fn, reps):
    out = []
    for _ in range(reps):
        t = time.perf_counter()
        fn()
        out.append(time.perf_counter() - t)
    return statistics.median(out)


def reference_kernel(reps):
    times = []
    for _ in range(reps):
        out = subprocess.run(
            ["bash", str(RUN_SH), str(STEP), "8"], capture_output=True, text=True, check=True
        )
        m = re.search(r"cells (\d+).*threads (\d+).*seconds ([0-9.]+)", out.stdout)
        if m is None:
            raise RuntimeError(out.stdout + out.stderr)
        times.append(float(m.group(3)))
        cells, threads = int(m.group(1)), int(m.group(2))
    return statistics.median(times), cells, threads


def child(reps):
    p, los = scenario()
    t = timed(lambda: gnssatt.ml_attitude(p, los, TRIANGLE, L1, step_deg=STEP), reps)
    print(f"{t:.6f}")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--reps", type=int, default=5)
    ap.add_argument("--child", action="store_true", help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.child:
        child(args.reps)
        return
    p, los = scenario()
    gnssatt.ml_attitude(p, los, TRIANGLE, L1, step_deg=STEP)  # warm-up
    res = gnssatt.ml_attitude(p, los, TRIANGLE, L1, step_deg=STEP)
    cells = res.cells_evaluated
    t_api = timed(lambda: gnssatt.ml_attitude(p, los, TRIANGLE, L1, step_deg=STEP), args.reps)
    t_np = timed(lambda: numpy_grid(p, los), max(1, args.reps // 2))
    t_ref, ref_cells, ref_threads = reference_kernel(args.reps)
    threads = os.cpu_count() or 1
    print(f"machine: {threads} CPUs; grid step {STEP} deg, M = 8, 3 antennas (0.71 m triangle)")
    print(
        f"gnssatt API (exhaustive, {cells} cells incl. refinement): {t_api * 1e3:8.1f} ms  "
        f"{cells * 8 / t_api:.3e} cell-satellite/s"
    )
    print(f"numpy reference (float64):                  {t_np * 1e3:8.1f} ms")
    print(
        f"reference kernel run.sh ({ref_cells} cells, {ref_threads} threads): {t_ref * 1e3:8.1f} ms  "
        f"{ref_cells * 8 / t_ref:.3e} cell-satellite/s"
    )
    print(
        f"ratio API / reference kernel: {t_api / t_ref:.2f}  "
        f"(per cell: {t_api / cells / (t_ref / ref_cells):.2f})"
        f"   numpy / API: {t_np / t_api:.1f}x"
    )
    for n in [1, 2, 16]:
        if n > threads:
            print(f"threads {n:2d}: not available on this machine")
            continue
        env = {**os.environ, "RAYON_NUM_THREADS": str(n), "OMP_NUM_THREADS": str(n)}
        out = subprocess.run(
            [sys.executable, __file__, "--child", "--reps", str(args.reps)],
            env=env,
            capture_output=True,
            text=True,
            check=True,
        )
        t = float(out.stdout.strip())
        ref = subprocess.run(
            ["bash", str(RUN_SH), str(STEP), "8"], env=env, capture_output=True, text=True, check=True
        )
        t_r = float(re.search(r"seconds ([0-9.]+)", ref.stdout).group(1))
        print(
            f"threads {n:2d}: API {t * 1e3:7.1f} ms   reference kernel {t_r * 1e3:7.1f} ms   "
            f"ratio {t / t_r:.2f}"
        )
    b = np.ascontiguousarray
    boxes, leaves, grid_cells = _core.bnb_stats(
        b(p[None]),
        b(los[None]),
        b(np.full((1, 8), L1)),
        b(TRIANGLE),
        "ambiguity_function",
        np.radians(STEP),
        None,
    )
    t_bb = timed(
        lambda: gnssatt.ml_attitude(p, los, TRIANGLE, L1, step_deg=STEP, search="branch_and_bound"), 3
    )
    bb = gnssatt.ml_attitude(p, los, TRIANGLE, L1, step_deg=STEP, search="branch_and_bound")
    print(
        f"branch-and-bound: {boxes} boxes bounded + {leaves} leaf cells = {boxes + leaves} of {grid_cells} "
        f"({grid_cells / (boxes + leaves):.1f}x fewer), {t_bb * 1e3:.0f} ms sequential; "
        f"same maximum as exhaustive: {bb.z_max == res.z_max and np.array_equal(bb.euler_deg, res.euler_deg)}"
    )


if __name__ == "__main__":
    main()
