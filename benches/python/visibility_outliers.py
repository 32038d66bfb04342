"""Belokonov et al.: all restarts of chosen ``visibility-rotation`` trials (local minimum or weak
observability?).

Rebuilds trials ``--trials`` of ``gnssatt reproduce visibility-rotation --runs RUNS --seed SEED`` (same
random streams), forces the first DE run and three "horizon" restarts (``axis_sigma_deg`` tiny, so the
noise threshold never accepts) and prints each run's objective relative to the objective at the true state
(below 1: the global basin) and its attitude error.

Run: ``python benches/python/visibility_outliers.py --seed 2026 --runs 200 --trials 46 109 166``
"""

from __future__ import annotations

import argparse

import numpy as np

from gnssatt import montecarlo
from gnssatt.attitude import dynamics as tumble
from gnssatt.experiments import visibility_rotation as vr


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--seed", type=int, default=2026)
    ap.add_argument("--runs", type=int, default=200)
    ap.add_argument("--trials", type=int, nargs="+", required=True)
    args = ap.parse_args()
    gens = montecarlo.trial_generators(args.seed, args.runs)
    model = tumble.TumbleModel.circular(500e3)
    t = np.arange(0.0, vr.DURATION_S + 1.0, 1.0)
    for i in args.trials:
        rng = gens[i]  # the draws below repeat vr.trial's, in its order
        truth = vr.random_initial_state(rng)
        meas = vr.noisy_axes(rng, tumble.propagate_axes(truth, t, model), vr.AXIS_SIGMA_DEG)
        seed = int(rng.integers(2**31))
        truth_cost = tumble.axis_cost(truth, t, meas, model)[0]
        fit = tumble.fit_rotation(t, meas, model, rng=seed, axis_sigma_deg=1e-3, max_restarts=3)
        errors = [vr.state_errors(p, truth)["attitude_error_deg"] for p in fit.attempt_params]
        print(
            f"trial {i}: alpha {np.degrees(truth[1]):.1f} deg, "
            f"rates {np.round(np.degrees(truth[3:]), 2)} deg/s; "
            f"objective / objective at truth {np.round(fit.attempt_costs / truth_cost, 4)}; "
            f"attitude error {np.round(errors, 2)} deg (first DE run, then horizon restarts)"
        )


if __name__ == "__main__":
    main()
