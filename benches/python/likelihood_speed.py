"""Times the full 1.5 deg likelihood grid (3 antennas, 0.71 m triangle, M = 8) in one run: the gnssatt
Python API (exhaustive pass), a plain numpy evaluation, optionally a reference native kernel (``--reference
PATH``: a script run as ``bash PATH STEP M`` that prints ``cells N ... threads T ... seconds S``), thread
scaling (RAYON_NUM_THREADS = 1, 2, and 16 when available), and branch-and-bound against the exhaustive
pass at 1 and 2 threads, as ratios of medians: on the paper's scenario, on a 5 m triangle at 0.45 deg (a
coarse grid: 0.41 of the coarsest step accepted; issue 30's case) and on the 5 m triangle at eq. (15)'s
default step (2.3e9 cells: the exhaustive pass runs as two windows of half the pitch range each, which
together hold every cell). Then the spread over random skies and attitudes (``--skies``) on the 5 m
triangle, at the machine's thread count.

Run from anywhere: ``python benches/python/likelihood_speed.py [--reps 5] [--skies 8] [--reference PATH]``.
"""

from __future__ import annotations

import argparse
import functools
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
from gnssatt.rotation import rotation_from_euler

L1 = 0.19029367279836487
STEP = 1.5
# The coarse grid of the 5 m triangle, degrees (issue 30).
COARSE = 0.45
UNIT_TRIANGLE = np.array([[1.0, 0.0, 0.0], [0.5, 0.0, np.sqrt(3) / 2]])
TRIANGLE = 0.71 * UNIT_TRIANGLE
# (name, side of the triangle in metres, grid step in degrees or None for eq. (15)'s default) for
# branch-and-bound vs exhaustive.
BNB_CASES = [
    ("paper 0.71 m, 1.5 deg", 0.71, 1.5),
    ("5 m, 0.45 deg", 5.0, COARSE),
    ("5 m, eq. (15) step", 5.0, None),
]


def scenario(m: int = 8, seed: int = 1, side: float = 0.71, euler_deg=(40.0, 3.0, -5.0)):
    rng = np.random.default_rng(seed)
    az, el = rng.uniform(0, 2 * np.pi, m), rng.uniform(0.2, 1.4, m)
    los = np.stack([np.sin(az) * np.cos(el), np.cos(az) * np.cos(el), np.sin(el)], axis=1)
    r = rotation_from_euler(list(euler_deg))
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


def search_work(p, los, tri, step):
    """``_core.bnb_stats`` of the branch-and-bound search (``step`` in degrees; None: eq. (15)'s default)."""
    b = np.ascontiguousarray
    return _core.bnb_stats(
        b(p[None]),
        b(los[None]),
        b(np.full((1, len(los)), L1)),
        b(tri),
        statistic="ambiguity_function",
        step_rad=None if step is None else np.radians(step),
        window_rad=None,
    )


def exhaustive_in_halves(p, los, tri, step, step_used_deg):
    """The exhaustive pass over every cell of the whole-domain grid of ``step`` (degrees or None, as given
    to ``ml_attitude``; ``step_used_deg`` the step it used) as two windows (pitch below and above a
    half-step boundary, heading and roll whole turns): ``(z_max, grid angles)`` of the grid maximum, ties
    to the lower pitch as in the whole-grid order."""
    n = round(360 / step_used_deg)
    mid = -90 + (n // 4 + 0.5) * step_used_deg
    best = None
    for theta in [(-90.0, mid), (mid, 90.0)]:
        window = [[-1.0, 361.0], list(theta), [-181.0, 181.0]]
        r = gnssatt.ml_attitude(
            p, los, tri, L1, step_deg=step, window_deg=window, search="exhaustive", refine=False
        )
        if best is None or r.z_max > best.z_max:
            best = r
    return best.z_max, tuple(float(a) for a in best.grid_euler_gost_deg)


def child(reps, search, side, step):
    p, los = scenario(side=side)
    tri = side * UNIT_TRIANGLE
    if search == "halves":
        used = gnssatt.ml_attitude(p, los, tri, L1, step_deg=step, refine=False).step_deg
        t = time.perf_counter()
        z, angles = exhaustive_in_halves(p, los, tri, step, used)
        t = time.perf_counter() - t
        print(f"{t:.6f} {z!r} {' '.join(repr(a) for a in angles)}")
        return

    def run():
        return gnssatt.ml_attitude(p, los, tri, L1, step_deg=step, search=search, refine=False)

    run()  # warm-up
    t = timed(run, reps)
    r = run()
    print(f"{t:.6f} {r.z_max!r} {' '.join(repr(float(a)) for a in r.grid_euler_gost_deg)}")


def in_child(n, reps, search, side=0.71, step=STEP):
    """Median seconds, z_max and grid angles of one search in a fresh process with ``n`` threads."""
    env = {**os.environ, "RAYON_NUM_THREADS": str(n), "OMP_NUM_THREADS": str(n)}
    args = ["--child", "--reps", str(reps), "--search", search, "--side", str(side)]
    args += ["--step", "eq15" if step is None else str(step)]
    out = subprocess.run(
        [sys.executable, __file__, *args], env=env, capture_output=True, text=True, check=True
    )
    t, z, *angles = out.stdout.split()
    return float(t), float(z), tuple(float(a) for a in angles)


def sky_spread(n_skies, reps, eq15_checks):
    """Branch-and-bound against the exhaustive pass on random skies (8 satellites) and attitudes, 5 m
    triangle, 0.1 rad noise, at 0.45 deg and at eq. (15)'s step, in this process (all threads)."""
    tri = 5.0 * UNIT_TRIANGLE
    print(
        f"spread over {n_skies} random skies and attitudes, 5 m triangle, 0.1 rad noise, "
        f"{os.cpu_count()} threads (medians of {reps}; rounds from _core.bnb_stats):"
    )
    rows = []
    t_halves: list[float] = []
    eq15_checks = max(1, eq15_checks)
    for k in range(n_skies):
        rng = np.random.default_rng(1000 + k)
        euler = (rng.uniform(0, 360), rng.uniform(-30, 30), rng.uniform(-30, 30))
        p, los = scenario(seed=1000 + k, side=5.0, euler_deg=euler)
        line = f"  sky {k:2d}:"
        row = []
        for step in (COARSE, None):
            kw = {"step_deg": step, "refine": False}
            bb = gnssatt.ml_attitude(p, los, tri, L1, search="branch_and_bound", **kw)
            run = functools.partial(gnssatt.ml_attitude, p, los, tri, L1, search="branch_and_bound", **kw)
            t_bb = timed(run, reps)
            stats = search_work(p, los, tri, step)
            if step is not None:
                t = time.perf_counter()
                ex = gnssatt.ml_attitude(p, los, tri, L1, search="exhaustive", **kw)
                t_ex = time.perf_counter() - t
                z_ex, a_ex = ex.z_max, tuple(float(a) for a in ex.grid_euler_gost_deg)
            elif k < eq15_checks:
                t = time.perf_counter()
                z_ex, a_ex = exhaustive_in_halves(p, los, tri, None, bb.step_deg)
                t_ex = time.perf_counter() - t
                t_halves.append(t_ex)
            else:
                z_ex = None
                t_ex = statistics.median(t_halves)
            same = (
                "not checked"
                if z_ex is None
                else str(z_ex == bb.z_max and a_ex == tuple(float(a) for a in bb.grid_euler_gost_deg))
            )
            name = f"{COARSE} deg" if step is not None else "eq. (15)"
            line += (
                f"  {name} {t_bb * 1e3:7.1f} ms, {t_ex / t_bb:6.1f}x, {stats.rounds} round(s), "
                f"same cell {same}"
            )
            row.append(t_ex / t_bb)
        rows.append(row)
        print(line, flush=True)
    r = np.array(rows)
    for j, name in enumerate([f"{COARSE} deg", "eq. (15) step"]):
        print(
            f"  {name}: ratio median {np.median(r[:, j]):.1f}x, min {r[:, j].min():.1f}x, "
            f"max {r[:, j].max():.1f}x"
        )
    print(
        f"  (eq. (15) ratios against the median of {len(t_halves)} exhaustive passes in halves, "
        f"{statistics.median(t_halves):.1f} s; its cost does not depend on the sky)"
    )


def _parser() -> argparse.ArgumentParser:
    ap = argparse.ArgumentParser()
    ap.add_argument("--reps", type=int, default=5)
    ap.add_argument(
        "--reference",
        type=Path,
        default=None,
        help="optional native reference kernel script, run as `bash PATH STEP M`",
    )
    ap.add_argument("--skies", type=int, default=8, help="random skies of the spread (0: none)")
    ap.add_argument(
        "--eq15-checks",
        type=int,
        default=2,
        help="skies whose eq. (15) grid is also searched exhaustively (about 15 s each on 2 cores)",
    )
    ap.add_argument("--child", action="store_true", help=argparse.SUPPRESS)
    ap.add_argument("--search", default="exhaustive", help=argparse.SUPPRESS)
    ap.add_argument("--side", type=float, default=0.71, help=argparse.SUPPRESS)
    ap.add_argument("--step", default=str(STEP), help=argparse.SUPPRESS)
    return ap


def threads_table(reference: Path | None, reps: int, threads: int) -> None:
    """The API's exhaustive search (and the reference kernel's) on 1, 2 and 16 threads."""
    for n in [1, 2, 16]:
        if n > threads:
            print(f"threads {n:2d}: not available on this machine")
            continue
        t, _, _ = in_child(n, reps, "exhaustive")
        line = f"threads {n:2d}: API exhaustive {t * 1e3:7.1f} ms"
        if reference is not None:
            env = {**os.environ, "RAYON_NUM_THREADS": str(n), "OMP_NUM_THREADS": str(n)}
            t_r, _, _ = reference_kernel(reference, 1, env)
            line += f"   reference kernel {t_r * 1e3:7.1f} ms   ratio {t / t_r:.2f}"
        print(line)


def branch_and_bound_table(repeats: int, threads: int) -> None:
    """Branch-and-bound against the exhaustive search in each case of :data:`BNB_CASES`."""
    print("branch-and-bound vs exhaustive (grid maximum only, refine=False; medians, fresh process each):")
    for name, side, step in BNB_CASES:
        ps, ls = scenario(side=side)
        stats = search_work(ps, ls, side * UNIT_TRIANGLE, step)
        boxes, leaves, grid_cells = stats.boxes_bounded, stats.leaf_cells, stats.grid_cells
        reps = repeats if grid_cells < 5e7 else max(1, min(repeats, 3))
        # Over 2^31 cells the exhaustive pass runs in two halves, once (about 15 s on 2 cores).
        ex_search, ex_reps = ("halves", 1) if grid_cells > 2**31 else ("exhaustive", reps)
        for n in [1, 2, 16]:
            if n > threads:
                continue
            t_ex, z_ex, a_ex = in_child(n, ex_reps, ex_search, side, step)
            t_bb, z_bb, a_bb = in_child(n, reps, "branch_and_bound", side, step)
            same = z_ex == z_bb and a_ex == a_bb
            print(
                f"  {name}, threads {n:2d}: exhaustive {t_ex * 1e3:9.1f} ms   branch-and-bound "
                f"{t_bb * 1e3:7.1f} ms   ratio {t_ex / t_bb:6.1f}x   same cell: {same}"
            )
        print(
            f"  {name}: {grid_cells:.3e} cells, {stats.rounds} round(s); {boxes} units of work "
            f"(direction boxes, plus rows scanned over 2^31 cells) + {leaves} kernel cells"
        )


def main():
    args = _parser().parse_args()
    if args.child:
        child(args.reps, args.search, args.side, None if args.step == "eq15" else float(args.step))
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
    threads_table(args.reference, args.reps, threads)
    branch_and_bound_table(args.reps, threads)
    if args.skies > 0:
        sky_spread(args.skies, max(1, min(args.reps, 3)), args.eq15_checks)


if __name__ == "__main__":
    main()
