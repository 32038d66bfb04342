"""Times the full 1.5 deg likelihood grid (3 antennas, 0.71 m triangle, M = 8) in one run: the gnssatt
Python API (exhaustive pass), a plain numpy evaluation, optionally a reference native kernel (``--reference
PATH``: a script run as ``bash PATH STEP M`` that prints ``cells N ... threads T ... seconds S``), thread
scaling (RAYON_NUM_THREADS = 1, 2, and 16 when available), and branch-and-bound against the exhaustive
pass on the paper's scenario and on a 5 m triangle (0.5 deg grid) at 1 and 2 threads, as ratios of medians.

Run from anywhere: ``python benches/python/likelihood_speed.py [--reps 5] [--reference PATH]``.
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
from gnssatt.attitude.likelihood import rotation_from_euler

L1 = 0.19029367279836487
STEP = 1.5
UNIT_TRIANGLE = np.array([[1.0, 0.0, 0.0], [0.5, 0.0, np.sqrt(3) / 2]])
TRIANGLE = 0.71 * UNIT_TRIANGLE
# (name, side of the triangle in metres, grid step in degrees) for branch-and-bound vs exhaustive.
BNB_CASES = [("paper 0.71 m, 1.5 deg", 0.71, 1.5), ("5 m, 0.5 deg", 5.0, 0.5)]


def scenario(m: int = 8, seed: int = 1, side: float = 0.71):
    rng = np.random.default_rng(seed)
    az, el = rng.uniform(0, 2 * np.pi, m), rng.uniform(0.2, 1.4, m)
    los = np.stack([np.sin(az) * np.cos(el), np.cos(az) * np.cos(el), np.sin(el)], axis=1)
    r = rotation_from_euler([40.0, 3.0, -5.0])
    tri = side * UNIT_TRIANGLE
    p = np.mod(-2 * np.pi / L1 * (r.apply(tri) @ los.T) + rng.uniform(-3, 3, (2, 1)), 2 * np.pi)
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


def reference_kernel(path, reps, env=None):
    times = []
    for _ in range(reps):
        out = subprocess.run(
            ["bash", str(path), str(STEP), "8"], env=env, capture_output=True, text=True, check=True
        )
        m = re.search(r"cells (\d+).*threads (\d+).*seconds ([0-9.]+)", out.stdout)
        if m is None:
            raise RuntimeError(out.stdout + out.stderr)
        times.append(float(m.group(3)))
        cells, threads = int(m.group(1)), int(m.group(2))
    return statistics.median(times), cells, threads


def child(reps, search, side, step):
    p, los = scenario(side=side)
    tri = side * UNIT_TRIANGLE

    def run():
        return gnssatt.ml_attitude(p, los, tri, L1, step_deg=step, search=search, refine=False)

    run()  # warm-up
    t = timed(run, reps)
    r = run()
    print(f"{t:.6f} {r.z_max!r} {' '.join(repr(float(a)) for a in r.grid_euler_gost_deg)}")


def in_child(n, reps, search, side=0.71, step=STEP):
    """Median seconds, z_max and grid angles of one search in a fresh process with ``n`` threads."""
    env = {**os.environ, "RAYON_NUM_THREADS": str(n), "OMP_NUM_THREADS": str(n)}
    args = ["--child", "--reps", str(reps), "--search", search, "--side", str(side), "--step", str(step)]
    out = subprocess.run(
        [sys.executable, __file__, *args], env=env, capture_output=True, text=True, check=True
    )
    t, z, *angles = out.stdout.split()
    return float(t), float(z), tuple(float(a) for a in angles)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--reps", type=int, default=5)
    ap.add_argument(
        "--reference",
        type=Path,
        default=None,
        help="optional native reference kernel script, run as `bash PATH STEP M`",
    )
    ap.add_argument("--child", action="store_true", help=argparse.SUPPRESS)
    ap.add_argument("--search", default="exhaustive", help=argparse.SUPPRESS)
    ap.add_argument("--side", type=float, default=0.71, help=argparse.SUPPRESS)
    ap.add_argument("--step", type=float, default=STEP, help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.child:
        child(args.reps, args.search, args.side, args.step)
        return
    p, los = scenario()
    kw = {"step_deg": STEP, "search": "exhaustive"}
    gnssatt.ml_attitude(p, los, TRIANGLE, L1, **kw)  # warm-up
    res = gnssatt.ml_attitude(p, los, TRIANGLE, L1, **kw)
    cells = res.cells_evaluated
    t_api = timed(lambda: gnssatt.ml_attitude(p, los, TRIANGLE, L1, **kw), args.reps)
    t_np = timed(lambda: numpy_grid(p, los), max(1, args.reps // 2))
    threads = os.cpu_count() or 1
    print(f"machine: {threads} CPUs; grid step {STEP} deg, M = 8, 3 antennas (0.71 m triangle)")
    print(
        f"gnssatt API (exhaustive, {cells} cells incl. refinement): {t_api * 1e3:8.1f} ms  "
        f"{cells * 8 / t_api:.3e} cell-satellite/s"
    )
    print(
        f"numpy reference (float64):                  {t_np * 1e3:8.1f} ms   numpy / API: {t_np / t_api:.1f}x"
    )
    if args.reference is not None:
        t_ref, ref_cells, ref_threads = reference_kernel(args.reference, args.reps)
        print(
            f"reference kernel ({ref_cells} cells, {ref_threads} threads): {t_ref * 1e3:8.1f} ms  "
            f"{ref_cells * 8 / t_ref:.3e} cell-satellite/s   ratio API / reference: {t_api / t_ref:.2f}"
        )
    for n in [1, 2, 16]:
        if n > threads:
            print(f"threads {n:2d}: not available on this machine")
            continue
        t, _, _ = in_child(n, args.reps, "exhaustive")
        line = f"threads {n:2d}: API exhaustive {t * 1e3:7.1f} ms"
        if args.reference is not None:
            env = {**os.environ, "RAYON_NUM_THREADS": str(n), "OMP_NUM_THREADS": str(n)}
            t_r, _, _ = reference_kernel(args.reference, 1, env)
            line += f"   reference kernel {t_r * 1e3:7.1f} ms   ratio {t / t_r:.2f}"
        print(line)
    b = np.ascontiguousarray
    print("branch-and-bound vs exhaustive (grid maximum only, refine=False; medians, fresh process each):")
    for name, side, step in BNB_CASES:
        ps, ls = scenario(side=side)
        stats = _core.bnb_stats(
            b(ps[None]),
            b(ls[None]),
            b(np.full((1, 8), L1)),
            b(side * UNIT_TRIANGLE),
            statistic="ambiguity_function",
            step_rad=np.radians(step),
            window_rad=None,
        )
        boxes, leaves, grid_cells = stats.boxes_bounded, stats.leaf_cells, stats.grid_cells
        reps = args.reps if grid_cells < 5e7 else max(1, min(args.reps, 3))
        for n in [1, 2, 16]:
            if n > threads:
                continue
            t_ex, z_ex, a_ex = in_child(n, reps, "exhaustive", side, step)
            t_bb, z_bb, a_bb = in_child(n, reps, "branch_and_bound", side, step)
            same = z_ex == z_bb and a_ex == a_bb
            print(
                f"  {name}, threads {n:2d}: exhaustive {t_ex * 1e3:9.1f} ms   branch-and-bound "
                f"{t_bb * 1e3:7.1f} ms   ratio {t_ex / t_bb:6.1f}x   same cell: {same}"
            )
        print(
            f"  {name}: {boxes} boxes + {leaves} kernel cells of {grid_cells} "
            f"({grid_cells / (boxes + leaves):.0f}x fewer)"
        )


if __name__ == "__main__":
    main()
