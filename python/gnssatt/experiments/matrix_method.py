"""The experiment of Ryzhkov and Oliinyk: matrix-method attitude of a small satellite from GPS range
differences.

The paper: 3 antennas on a 1 m equilateral triangle, 3 GPS satellites, heading 180 deg, roll 0, pitch 0;
differential receiver with 0.3 m code and 4 mm carrier-phase noise; mean errors 0.282 / 1.234 / 0.851 deg
(heading, roll, pitch). The paper does not give the satellite geometry, so each trial draws 3 satellites
uniformly over the sky above a 10 deg elevation mask of the orbital frame (z to zenith) and the study reports
how the error depends on that geometry. Range differences come from carrier phase with integer ambiguities
resolved (a difference of two 4 mm phase measurements: sigma = 4 sqrt(2) mm); the 0.3 m code noise matters
only for ambiguity fixing, which the paper does not model.
"""

from __future__ import annotations

import functools
from concurrent.futures import Executor
from pathlib import Path
from typing import Any

import numpy as np
from scipy.spatial.transform import Rotation

from gnssatt import montecarlo
from gnssatt.attitude.matrix_method import Method, matrix_attitude
from gnssatt.errors import DegenerateGeometryError
from gnssatt.experiments import Experiment
from gnssatt.experiments.report import format_table, write_report
from gnssatt.geometry import attitude_dop
from gnssatt.sim import equilateral_triangle, random_los

NAME = "matrix-method"
SIDE_M = 1.0
TRUTH_DEG = (180.0, 0.0, 0.0)  # heading, pitch, roll (intrinsic ZYX, docs/conventions.md)
PHASE_SIGMA_M = 0.004
RANGE_DIFF_SIGMA_M = PHASE_SIGMA_M * np.sqrt(2.0)
ELEVATION_MASK_DEG = 10.0
N_SATELLITES = 3
METHODS: tuple[Method, ...] = ("svd", "ml")
ANGLES = ("heading", "pitch", "roll")
# A trial whose total error exceeds this many Cramer-Rao bounds fell into the mirror solution.
OUTLIER_BOUNDS = 5.0


def trial(rng: np.random.Generator, *, sigma_m: float = RANGE_DIFF_SIGMA_M) -> dict[str, float]:
    """One Monte Carlo trial: random 3-satellite geometry, noisy range differences, SVD matrix method."""
    truth = Rotation.from_euler("ZYX", TRUTH_DEG, degrees=True)
    baselines = equilateral_triangle(SIDE_M)[1:]  # relative to antenna 0
    while True:
        los = random_los(rng, N_SATELLITES, min_elevation_deg=ELEVATION_MASK_DEG)
        try:
            dop = attitude_dop(baselines, los, truth)
        except DegenerateGeometryError:
            continue
        break
    clean = baselines @ truth.inv().as_matrix() @ los.T
    noisy = clean + rng.normal(0.0, sigma_m, clean.shape)
    row: dict[str, float] = {"adop": dop}
    for method in METHODS:
        est = matrix_attitude(baselines, los, noisy, method=method)
        err = (est.heading_pitch_roll_deg - np.array(TRUTH_DEG) + 180.0) % 360.0 - 180.0
        row |= {f"{method}_{k}": float(e) for k, e in zip(ANGLES, err, strict=True)}
        row[f"{method}_total"] = float(np.degrees((est.rotation * truth.inv()).magnitude()))
    return row


def run(
    *, runs: int, seed: int, out: Path, executor: Executor | None = None, progress: bool = True
) -> dict[str, Any]:
    from gnssatt import plots

    rows = montecarlo.run(
        functools.partial(trial, sigma_m=RANGE_DIFF_SIGMA_M),
        runs,
        seed=seed,
        executor=executor,
        progress=progress,
    )
    crb_deg = np.degrees(np.array([r["adop"] for r in rows]) * RANGE_DIFF_SIGMA_M)
    measured: dict[str, Any] = {}
    for method in METHODS:
        err = {k: np.array([r[f"{method}_{k}"] for r in rows]) for k in (*ANGLES, "total")}
        tag = "" if method == "svd" else f"{method}_"
        for k in ("heading", "roll", "pitch"):
            measured[f"{tag}{k}_mean_abs_error_deg"] = float(np.mean(np.abs(err[k])))
            measured[f"{tag}{k}_median_abs_error_deg"] = float(np.median(np.abs(err[k])))
            measured[f"{tag}{k}_rms_error_deg"] = float(np.sqrt(np.mean(err[k] ** 2)))
        inlier = err["total"] < OUTLIER_BOUNDS * crb_deg
        measured[f"{tag}total_rms_error_deg"] = float(np.sqrt(np.mean(err["total"] ** 2)))
        measured[f"{tag}total_rms_error_inliers_deg"] = float(np.sqrt(np.mean(err["total"][inlier] ** 2)))
        measured[f"{tag}outlier_fraction"] = float(np.mean(~inlier))
    measured["total_rms_crb_deg"] = float(np.sqrt(np.mean(crb_deg**2)))
    ml_total = np.array([r["ml_total"] for r in rows])
    measured["total_rms_crb_inliers_deg"] = float(
        np.sqrt(np.mean(crb_deg[ml_total < OUTLIER_BOUNDS * crb_deg] ** 2))
    )
    paper = {f"{k}_mean_abs_error_deg": v for k, v in (("heading", 0.282), ("roll", 1.234), ("pitch", 0.851))}
    # The paper gives no satellite geometry, only the order of its mean errors can be compared (results page)
    doc = write_report(out, NAME, paper, measured, runs, seed, tolerance=dict.fromkeys(paper, 10.0))
    plots.error_vs_geometry(
        crb_deg,
        {m: np.array([r[f"{m}_total"] for r in rows]) for m in METHODS},
        out / f"{NAME}-geometry.png",
        title="Ryzhkov and Oliinyk: matrix method, 1 m triangle, 3 satellites, 4 mm phase noise",
    )
    print(format_table(doc))
    return doc


EXPERIMENT = Experiment(
    name=NAME,
    summary=(
        "Ryzhkov and Oliinyk: matrix least-squares attitude from range differences (1 m triangle, "
        "3 GPS satellites)"
    ),
    run=run,
    default_runs=5000,
    quick_runs=1000,
)
