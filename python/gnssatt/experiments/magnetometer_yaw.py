"""The experiment of Ryzhkov and Holembiovskyi: yaw from an Earth sensor plus a magnetometer, TRIAD against
eq. (3).

The paper: psi = 5, theta = 3, phi = 4 deg; a magnetometer scale-factor error of 1.05 on the x channel
(fig. 2), then on the y channel (fig. 3); yaw error of TRIAD (local vertical + magnetic field) and of
eq. (3) along one orbit; conclusion "the accuracies of the two are close". It gives no inclination,
altitude or numbers: here a moderate (51.6 deg) and a near-polar (87 deg) circular orbit at 700 km, the
axial dipole of eq. (2) as both truth and model, pitch and roll from the Earth sensor without error, and
no noise, so the run is deterministic (``runs`` and ``seed`` are recorded but unused). The field's scale
cancels in both methods, so the altitude does not change the errors.
"""

from __future__ import annotations

import warnings
from concurrent.futures import Executor
from pathlib import Path
from typing import Any

import numpy as np
from scipy.spatial.transform import Rotation

from gnssatt.attitude.magnetometer import yaw_from_magnetometer
from gnssatt.attitude.wahba import triad
from gnssatt.errors import NearDegenerateWarning
from gnssatt.experiments import Experiment
from gnssatt.experiments.report import format_table, write_report
from gnssatt.magnetic import dipole_orbital

NAME = "magnetometer-yaw"
TRUTH_DEG = (5.0, 3.0, 4.0)  # psi, theta, phi: ZYX body -> orbital
SCALE = 1.05
INCLINATIONS_DEG = (51.6, 87.0)
RADIUS_M = 6_378_137.0 + 700e3
CHANNELS = ("x", "y")
METHODS = ("triad", "eq3")


def yaw_errors(inclination_deg: float, channel: str, u_deg: np.ndarray) -> dict[str, np.ndarray]:
    """Yaw error (deg) of TRIAD and of eq. (3) along the orbit with the scale error on ``channel``."""
    truth = Rotation.from_euler("ZYX", TRUTH_DEG, degrees=True)
    b_orb = dipole_orbital(np.radians(u_deg), np.radians(inclination_deg), RADIUS_M)
    scale = np.ones(3)
    scale["xyz".index(channel)] = SCALE
    measured = truth.inv().apply(b_orb) * scale
    theta, phi = np.radians(TRUTH_DEG[1]), np.radians(TRUTH_DEG[2])
    up = np.tile([0.0, 0.0, 1.0], (len(u_deg), 1))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", NearDegenerateWarning)  # near-polar: reported, not hidden (below)
        eq3 = yaw_from_magnetometer(measured, b_orb, np.full(len(u_deg), theta), np.full(len(u_deg), phi))
        tri = triad(truth.inv().apply(up), measured, up, b_orb)

    def wrap(a: np.ndarray) -> np.ndarray:
        return (a - TRUTH_DEG[0] + 180.0) % 360.0 - 180.0

    return {
        "triad": wrap(tri.rotation.as_euler("ZYX", degrees=True)[:, 0]),
        "eq3": wrap(np.degrees(eq3.yaw_rad)),
        "horizontal_fraction": np.asarray(eq3.horizontal_fraction),
    }


def run(
    *, runs: int = 1, seed: int = 0, out: Path, executor: Executor | None = None, progress: bool = True
) -> dict[str, Any]:
    from gnssatt import plots

    out.mkdir(parents=True, exist_ok=True)
    u_deg = np.linspace(0.0, 360.0, 721)
    measured: dict[str, Any] = {}
    curves: dict[str, dict[float, dict[str, np.ndarray]]] = {}
    for channel in CHANNELS:
        curves[channel] = {}
        for inc in INCLINATIONS_DEG:
            err = yaw_errors(inc, channel, u_deg)
            curves[channel][inc] = err
            tag = f"i{inc:g}".replace(".", "p")
            for m in METHODS:
                measured[f"{m}_{channel}_scale_{tag}_max_yaw_error_deg"] = float(np.max(np.abs(err[m])))
                measured[f"{m}_{channel}_scale_{tag}_rms_yaw_error_deg"] = float(
                    np.sqrt(np.mean(err[m] ** 2))
                )
            measured[f"{channel}_scale_{tag}_max_triad_minus_eq3_deg"] = float(
                np.max(np.abs(err["triad"] - err["eq3"]))
            )
    for inc in INCLINATIONS_DEG:
        tag = f"i{inc:g}".replace(".", "p")
        measured[f"{tag}_min_horizontal_fraction"] = float(np.min(curves["x"][inc]["horizontal_fraction"]))
    paper: dict[str, Any] = {k: None for k in measured}
    paper["conclusion"] = "TRIAD and eq. (3) are close (figs. 2, 3; no numbers given)"
    for channel, fig in (("x", 2), ("y", 3)):
        plots.yaw_error_along_orbit(
            u_deg,
            curves[channel],
            out / f"{NAME}-{channel}-scale.png",
            title=f"Ryzhkov and Holembiovskyi, fig. {fig}: scale factor {SCALE} on magnetometer {channel}, "
            f"psi, theta, phi = {TRUTH_DEG} deg",
        )
    unavailable: dict[str, str] = {}
    try:
        measured |= plots.dipole_vs_igrf(out / f"{NAME}-dipole-vs-igrf.png", RADIUS_M, INCLINATIONS_DEG[1])
    except ImportError:
        measured["dipole_vs_igrf_max_angle_deg"] = None
        unavailable["dipole_vs_igrf_max_angle_deg"] = "needs the igrf extra: pip install 'gnssatt[igrf]'"
    doc = write_report(out, NAME, paper, measured, runs, seed, unavailable=unavailable)
    print(format_table(doc))
    return doc


EXPERIMENT = Experiment(
    name=NAME,
    summary=(
        "Ryzhkov and Holembiovskyi: yaw from Earth sensor + magnetometer, TRIAD vs eq. (3) with a 5% "
        "scale-factor error"
    ),
    run=run,
    default_runs=1,
    quick_runs=1,
)
