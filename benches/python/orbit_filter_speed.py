"""One orbit (5670 s) at 1 Hz through the tightly coupled GPS + GLONASS orbit filter: the Rust inner loop
(gnssatt.orbit.determination.orbit_filter) against the numpy implementation of the same filter
(tests/references/orbit_reference.py, tight_filter). Prints medians and the ratio.

    PYTHONPATH=python python benches/python/orbit_filter_speed.py [--repeats 5] [--numpy-repeats 1]
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time
from pathlib import Path

import numpy as np

from gnssatt import sim
from gnssatt.experiments.orbit_filter import ORBIT, P0, Q_M2_S3
from gnssatt.orbit.determination import noisy_orbit, orbit_filter

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "tests"))  # the numpy references

from references.orbit_reference import tight_filter


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--numpy-repeats", type=int, default=1)
    args = ap.parse_args()
    rng = np.random.default_rng(0)
    t = np.arange(0.0, 5670.0, 1.0)
    r, v = ORBIT.state_ecef(t[:1])
    truth = noisy_orbit(np.concatenate([r[0], v[0]]), t, rng=rng, accel_psd_m2_s3=Q_M2_S3)
    cons = sim.gps_nominal() + sim.glonass_nominal()
    meas = sim.simulate_spaceborne(truth[:, :3], truth[:, 3:], t, cons, rng)
    x0 = truth[0] + rng.multivariate_normal(np.zeros(6), P0)
    print(f"{t.size} epochs, median {np.median(meas.visible.sum(axis=1)):.0f} satellites tracked")

    def rust() -> np.ndarray:
        return orbit_filter(meas, x0, P0, coupling="tight", accel_psd_m2_s3=Q_M2_S3, step_s=10.0).states

    def numpy() -> np.ndarray:
        return tight_filter(meas, x0, P0, accel_psd_m2_s3=Q_M2_S3, step_s=10.0)[0]

    times = {}
    for name, fn, n in (("rust", rust, args.repeats), ("numpy", numpy, args.numpy_repeats)):
        samples = []
        for _ in range(n):
            t0 = time.perf_counter()
            fn()
            samples.append(time.perf_counter() - t0)
        times[name] = statistics.median(samples)
        print(f"{name:6s} median {times[name]:.4f} s over {n} runs")
    diff = np.abs(rust() - numpy()).max()
    print(f"max |rust - numpy| state difference: {diff:.2e}")
    print(f"ratio numpy / rust: {times['numpy'] / times['rust']:.1f}x")


if __name__ == "__main__":
    main()
