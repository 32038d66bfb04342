"""Time per epoch of maximum-likelihood attitude on a recorded-like batch: one call of
:func:`gnssatt.ml_attitude_series` against the Python per-epoch loop of
:func:`gnssatt.ml_attitude`, whole domain and windowed, at RAYON_NUM_THREADS = 1, 2 (and 16 where the
machine has them), in one run.

The batch is the simulated part of ``reproduce recorded-methods``: a 1 m equilateral triangle in the body
X-Z plane, heading turning 3 deg per epoch, pitch and roll oscillating by a few degrees, 1 s epochs above
50 N 36.2 E, the highest GPS L1 satellites of the nominal constellation, 2 mm white phase noise (the
simulator behind :mod:`gnssatt.sim.rinex_scenario`). Default step (eq. (15), ``lambda / (10 L)`` = 1.09 deg:
1.8e7 cells, searched by branch-and-bound), window +-10 deg around the previous epoch as in that study.
Each child also checks that the batch and the loop give the same angles bit for bit and prints the
worst angle error against the truth.

Run from anywhere: ``python benches/python/ml_series_speed.py [--epochs 60] [--sats 8] [--reps 3]``.
"""

from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import time

import numpy as np

import gnssatt
from gnssatt import sim
from gnssatt.rotation import rotation_from_euler

WINDOW_DEG = 10.0


def batch(n_ep: int, n_sats: int, seed: int = 3):
    """Single differences (n_ep, 2, n_sats) rad, lines of sight (n_ep, n_sats, 3), wavelengths (n_sats,),
    body baselines (2, 3) and true angles (n_ep, 3) degrees."""
    rng = np.random.default_rng(seed)
    ant = sim.equilateral_triangle(1.0, plane="xz")
    k = np.arange(n_ep)
    euler = np.stack([40.0 + 3.0 * k, 5.0 * np.sin(k / 3.0), 3.0 * np.cos(k / 4.0)], axis=1)
    rx = sim.GroundReceiver(lat_deg=50.0, lon_deg=36.2, height_m=150.0)
    gps = sim.gps_nominal()
    t = 1800.0 + k.astype(float)
    el = np.arcsin(sim.line_of_sight(rx, gps, t).los[..., 2])
    order = np.argsort(-np.where(np.all(el > np.radians(10.0), axis=0), el[0], -1.0))
    vis = gps.select(list(np.array(gps.ids)[order[:n_sats]]))
    geom = sim.line_of_sight(rx, vis, t)
    lam = vis.wavelengths_m()
    meas = sim.simulate_array(geom, rotation_from_euler(euler), ant, lam, rng, phase_sigma_m=0.002)
    cycles = meas.carrier_phase_cycles
    sd = 2.0 * np.pi * (cycles[:, 1:, :] - cycles[:, :1, :])
    return np.mod(sd, 2.0 * np.pi), meas.los, lam, ant[1:] - ant[0], euler


def timed_pair(first, second, reps):
    """Median seconds of each of two calls, run alternately so that a change of machine load between them
    (the shared machine) falls on both."""
    out: tuple[list[float], list[float]] = ([], [])
    for _ in range(reps):
        for fn, times in ((first, out[0]), (second, out[1])):
            t = time.perf_counter()
            fn()
            times.append(time.perf_counter() - t)
    return statistics.median(out[0]), statistics.median(out[1])


def loop(p, los, b, lam, window):
    """The per-epoch Python loop: each epoch's window around the previous epoch's angles."""
    out, prev = [], None
    for k in range(p.shape[0]):
        win = None if window is None or prev is None else np.stack([prev - window, prev + window], axis=1)
        prev = gnssatt.ml_attitude(p[k], los[k], b, lam, window_deg=win).euler_gost_deg
        out.append(prev)
    return np.array(out)


def child(n_ep, n_sats, reps):
    p, los, lam, b, truth = batch(n_ep, n_sats)
    row = []
    for window in (None, WINDOW_DEG):
        series = gnssatt.ml_attitude_series(p, los, b, lam, window_deg=window)
        looped = loop(p, los, b, lam, window)
        if not np.array_equal(series.euler_gost_deg, looped):
            raise AssertionError(f"window {window}: batch and loop differ")
        err = np.max(np.abs((series.euler_gost_deg - truth + 180.0) % 360.0 - 180.0))
        t_series, t_loop = timed_pair(
            lambda w=window: gnssatt.ml_attitude_series(p, los, b, lam, window_deg=w),
            lambda w=window: loop(p, los, b, lam, w),
            reps,
        )
        row += [t_series / n_ep, t_loop / n_ep, err]
    print(" ".join(repr(float(x)) for x in row))


def in_child(threads, args):
    env = {**os.environ, "RAYON_NUM_THREADS": str(threads), "OMP_NUM_THREADS": str(threads)}
    cmd = [sys.executable, __file__, "--child", "--epochs", str(args.epochs), "--sats", str(args.sats)]
    out = subprocess.run(
        [*cmd, "--reps", str(args.reps)], env=env, capture_output=True, text=True, check=True
    )
    return [float(x) for x in out.stdout.split()]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--epochs", type=int, default=60)
    ap.add_argument("--sats", type=int, default=8)
    ap.add_argument("--reps", type=int, default=3)
    ap.add_argument("--child", action="store_true", help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.child:
        child(args.epochs, args.sats, args.reps)
        return
    threads = [1, 2] + ([16] if (os.cpu_count() or 1) >= 16 else [])
    print(
        f"ML attitude per epoch, {args.epochs} epochs, 1 m triangle, {args.sats} GPS L1 satellites, "
        f"default step, median of {args.reps}"
    )
    print(
        f"{'threads':>7} {'search':>14} {'batch ms':>9} {'loop ms':>9} {'loop/batch':>10} {'max err deg':>11}"
    )
    for n in threads:
        r = in_child(n, args)
        for name, (ts, tl, err) in zip(
            ("whole domain", f"window +-{WINDOW_DEG:g}"), (r[:3], r[3:]), strict=True
        ):
            print(f"{n:>7} {name:>14} {1e3 * ts:>9.2f} {1e3 * tl:>9.2f} {tl / ts:>10.2f} {err:>11.2e}")


if __name__ == "__main__":
    main()
