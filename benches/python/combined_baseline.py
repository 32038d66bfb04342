"""The static session's combined baseline (``AttitudeSeries.combined_baseline``) against its per-epoch
series: on GEONET (0759 -> 3040, 3.3 km, GPS) against RTKLIB 2.4.3's static L1+L2 fixed solution (ENU
953.6732, -3196.1396, 4.6497 m; docs/rtklib_comparison.md), and on the simulated static 1 m pair
(benches/python/rtklib_compare.py's ``sim``: heading 30 degrees, 300 epochs, seed 1) against its truth.

Run: ``python benches/python/combined_baseline.py``. Prints, per case, the 3-D error of the combined
baseline and its one-sigma (sqrt of the covariance trace), and the RMS 3-D error of the per-epoch baselines.
"""

from __future__ import annotations

import tempfile
import warnings
from pathlib import Path

import numpy as np

from gnssatt.data import geonet_dir
from gnssatt.gnss.attitude import AttitudeSeries, attitude_from_rinex
from gnssatt.sim.rinex_scenario import simulate_gnss_rinex

RTKLIB_GEONET_ENU_M = np.array([953.6732, -3196.1396, 4.6497])


def row(name: str, series: AttitudeSeries, truth: np.ndarray) -> None:
    c = series.combined_baseline()
    err = 1e3 * np.linalg.norm(c.baselines_enu_m[0] - truth)
    sigma = 1e3 * np.sqrt(np.trace(c.covariances_enu_m2[0]))
    ok = series.fixed == 1
    per = 1e3 * np.sqrt(np.mean(np.sum((series.baselines_enu_m[ok, 0] - truth) ** 2, axis=1)))
    print(
        f"{name:34s} {c.epochs:4d} epochs  combined {err:6.2f} mm (sigma {sigma:5.2f})  "
        f"per-epoch RMS {per:6.2f} mm"
    )


def main() -> None:
    d = geonet_dir()
    obs = [d / "07590920.05o", d / "30400920.05o"]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for f in (1, 2):
            s = attitude_from_rinex(obs, d / "07590920.05n", method="lambda", motion="static", systems="G",
                                    frequencies=f)  # fmt: skip
            row(f"geonet static GPS, {f} slot(s)", s, RTKLIB_GEONET_ENU_M)
        with tempfile.TemporaryDirectory() as tmp:
            ants = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]])
            sim = simulate_gnss_rinex(Path(tmp), ants, np.tile([30.0, 0.0, 0.0], (300, 1)), systems="GRECJ",
                                      frequencies=3, rng=1)  # fmt: skip
            truth = sim.baselines_enu_m[0, 0]
            for systems, f in (("G", 1), ("G", 2), ("GECJ", 1)):
                s = attitude_from_rinex(list(sim.obs_paths), sim.nav_path, method="lambda", motion="static",
                                        systems=systems, frequencies=f)  # fmt: skip
                row(f"sim 1 m static {systems}, {f} slot(s)", s, truth)


if __name__ == "__main__":
    main()
