"""One orbit of the gyro + GNSS filter: Rust core (gnssatt.gyro_gnss_filter) against the numpy reference.

Scenario of ``gnssatt reproduce gyro-gnss`` (700 km orbit, 10 Hz gyro, GPS + GLONASS first differences at
1 Hz from a three-antenna array), tightly coupled with float ambiguities (the numpy reference has no LAMBDA
fixing or slip test, so both run with those off) and loosely coupled. The Rust filter is timed as the median
of ``--reps`` runs, the numpy reference once (it takes tens of seconds). Prints times and ratios.
Set OPENBLAS_NUM_THREADS=1 to keep BLAS threading out of the small-matrix numpy timings.
"""

from __future__ import annotations

import argparse
import math
import os
import sys
import time
from pathlib import Path

import numpy as np
from scipy.spatial.transform import Rotation

from gnssatt.attitude.gyro_gnss import gyro_gnss_filter
from gnssatt.experiments import gyro_gnss as exp
from gnssatt.sim import attitude_scenario as sc

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "tests"))  # the numpy references

from references.gyro_gnss_numpy import run_reference


def median_time(fn, reps: int) -> float:  # type: ignore[no-untyped-def]
    times = []
    for _ in range(reps):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return float(np.median(times))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--duration", type=float, default=math.floor(exp.RX.period_s))
    parser.add_argument("--reps", type=int, default=5)
    args = parser.parse_args()
    rng = np.random.default_rng(0)
    t, att = exp._motion(args.duration)
    g = sc.gyro_output(t, att, rng, drift_rad_s=np.array(exp.DRIFT_DEG_H) * exp.DEG_H, arw=exp.ARW)
    k = np.arange(0, len(t), exp.GNSS_EVERY)
    b = exp._baselines()
    ph = sc.phase_observations(
        exp.RX, exp._gnss(), t[k], att[k], b, rng, phase_sigma_cycles=exp.PHASE_SIGMA_CYCLES
    )
    fixes = sc.attitude_fixes(ph, att[k], b, rng, phase_sigma_cycles=exp.PHASE_SIGMA_CYCLES)
    p0 = exp._p0()
    q0 = att[0] * Rotation.from_rotvec(np.radians([0.3, -0.2, 0.4]))
    print(
        f"machine: {os.cpu_count()} CPUs; {args.duration:.0f} s, {len(t)} gyro samples, "
        f"{len(ph.epoch_t)} GNSS epochs, {len(ph.epoch)} satellite rows "
        f"({ph.n_visible().mean():.1f} satellites per epoch)"
    )
    for mode, meas in (("tight", {"phases": ph}), ("loose", {"attitude_fixes": fixes})):
        kw = {
            "initial_rotation": q0,
            "initial_covariance": p0,
            "arw": exp.ARW,
            "baselines_m": b,
            "phase_sigma_cycles": exp.PHASE_SIGMA_CYCLES,
            "fix_ambiguities": False,
            "slip_false_alarm": None,
        }
        t_rust = median_time(lambda kw=kw, meas=meas: gyro_gnss_filter(t, g.rates, **kw, **meas), args.reps)
        t0 = time.perf_counter()
        run_reference(
            t, g.rates, q0, np.zeros(3), p0, exp.ARW, 0.0, b, exp.PHASE_SIGMA_CYCLES,
            meas.get("attitude_fixes"), meas.get("phases"),
        )  # fmt: skip
        t_np = time.perf_counter() - t0
        print(
            f"{mode}ly coupled: Rust {t_rust:.3f} s (median of {args.reps}), numpy {t_np:.1f} s, "
            f"ratio {t_np / t_rust:.0f}x"
        )


if __name__ == "__main__":
    main()
