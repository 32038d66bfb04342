"""Belokonov et al.: how often the differential-evolution fit ends in a local minimum, and what restarts buy.

Runs the ``visibility-rotation`` trials (paper setup: 1500 s, 5 deg per axis component, rates up to
3 deg/s) on the same seeds with each restart kind of ``gnssatt.attitude.dynamics.fit_rotation`` and
prints, per kind, the share of fits whose objective exceeds ``dynamics.noise_cost_threshold`` (tail 1e-3:
more than the noise explains) and of attitude errors over 15 deg, for the first run alone and after
restarts, with the mean restarts and the wall time. The first run is the same for every kind (same seed).

Run: ``RAYON_NUM_THREADS=1 python benches/python/visibility_restarts.py [--trials 24] [--seed 1]``
(two worker processes).
"""

from __future__ import annotations

import argparse
import functools
import multiprocessing
import time
from concurrent.futures import ProcessPoolExecutor

import numpy as np

from gnssatt import montecarlo
from gnssatt.experiments import visibility_rotation as vr


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--trials", type=int, default=24)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--workers", type=int, default=2)
    args = ap.parse_args()
    ctx = multiprocessing.get_context("spawn")
    for kind in ("horizon", "fresh"):
        t0 = time.perf_counter()
        with ProcessPoolExecutor(args.workers, mp_context=ctx) as pool:
            rows = montecarlo.run(
                functools.partial(vr.trial, restart=kind, min_restarts=0),
                args.trials,
                seed=args.seed,
                executor=pool,
                progress=False,
            )
        dt = time.perf_counter() - t0
        col = {k: np.array([r[k] for r in rows]) for k in rows[0]}
        print(
            f"restart={kind}: {args.trials} trials (seed {args.seed}) in {dt:.0f} s on "
            f"{args.workers} workers; mean restarts {col['restarts'].mean():.2f}"
        )
        print(
            f"  above noise threshold: first run {col['first_run_cost_over_threshold'].mean():.3f}, "
            f"after restarts {col['cost_over_threshold'].mean():.3f}"
        )
        print(
            f"  attitude error > 15 deg: first run {np.mean(col['first_run_attitude_error_deg'] > 15):.3f}, "
            f"after restarts {np.mean(col['attitude_error_deg'] > 15):.3f}"
        )


if __name__ == "__main__":
    main()
