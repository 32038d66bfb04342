"""Fixed epochs and wrong fixes of single-epoch LAMBDA per success-rate gate, on simulated 1 m baselines.

Usage: ``python benches/python/success_rate_gate.py [EPOCHS]`` (default 120 epochs at 30 s). Prints one line
per signal set and gate: epochs fixed, wrong fixes (fixed baselines more than 5 cm from the simulation's
truth) and the median bootstrapped success rate. The ratio-test threshold is 3 throughout. The measured table
and the default it justifies are in ``docs/observation_engine.md``.
"""

from __future__ import annotations

import sys
import tempfile
import warnings

import numpy as np

from gnssatt.rinex.attitude import attitude_from_rinex
from gnssatt.rinex.scenario import simulate_gnss_rinex

GATES = (0.0, 0.5, 0.8, 0.9, 0.95, 0.99, 0.999)
CASES = (("G", 1), ("G", 2), ("GECJ", 1), ("GRECJ", 2))


def main(n_epochs: int) -> None:
    warnings.simplefilter("ignore")
    antennas = np.array([[0.0, 0, 0], [1.0, 0, 0]])
    for systems, frequencies in CASES:
        folder = tempfile.mkdtemp()
        sim = simulate_gnss_rinex(
            folder, antennas, [30, 0, 0], systems=systems, frequencies=frequencies,
            n_epochs=n_epochs, interval_s=30.0, rng=3,
        )  # fmt: skip
        truth = np.asarray(sim.baselines_enu_m)[:, 0, :]
        for gate in GATES:
            s = attitude_from_rinex(
                list(sim.obs_paths), sim.nav_path, motion="moving", method="lambda", systems=systems,
                frequencies=frequencies, min_success_rate=gate, ratio_threshold=3.0,
            )  # fmt: skip
            err = np.linalg.norm(s.baselines_enu_m[:, 0] - truth, axis=-1)
            fixed = s.fixed.astype(bool)
            print(
                f"{systems} f{frequencies} gate {gate}: fixed {fixed.sum()}/{len(fixed)} "
                f"wrong(>5cm) {(err[fixed] > 0.05).sum()} SR median {np.median(s.success_rate):.4f}",
                flush=True,
            )


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 120)
