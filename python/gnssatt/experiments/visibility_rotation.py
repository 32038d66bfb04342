"""The experiment of Belokonov et al.: a tumbling spacecraft's initial attitude and rates from its
antenna-axis history.

The paper: 400 random initial conditions (precession and spin uniform in [0, 360) deg, attack in [0, 180]
deg, |omega| up to 3 deg/s), axis directions "with 3 sigma = 15 deg" over T = 1500 s, differential evolution
on objective (1), stop when the objective changes by less than 0.001; worst sigma about 5 deg in the angles
and 0.12 deg/s in the rates (figures 3-4).

Here each trial draws the angles as the paper does and the rate uniformly in the 3 deg/s ball; the
measured axis at every second is the true one (``gnssatt.attitude.dynamics.propagate_axes``, the default
:class:`~gnssatt.attitude.dynamics.TumbleModel`,
an assumed 3U-class nanosatellite at 500 km) tilted by a Gaussian
tangent-plane error of 5 deg per component (3 sigma = 15 deg). ``measurements="visibility"`` instead
derives each axis from simulated GPS + GLONASS visibility (``gnssatt.attitude.visibility``, centroid
estimator).
The fit's 180-deg spin ambiguity (``tumble.fold_symmetric``) is removed before the errors are taken.

A single DE run over the whole 1500 s ends in a local minimum in about a third of the trials; the fit
therefore restarts while its objective exceeds what the axis noise explains (``tumble.noise_cost_threshold``,
chi-square tail 1e-3; up to 3 "horizon" restarts, see ``tumble.fit_rotation``), and restarts once in any
case: a local minimum whose objective lies within the noise spread passes the threshold (five of the six
fits more than 15 deg off in a 400-trial study without it). ``measured`` holds the
errors after restarts and, prefixed ``first_run_``, those of the first run alone on the same seeds, with
the share of fits above the threshold (``first_run_local_minimum_fraction``, ``local_minimum_fraction``).
``visibility-rotation-trials.csv`` holds every trial's row (true state, errors, objective ratios).
"""

from __future__ import annotations

import csv
import functools
import math
from concurrent.futures import Executor
from pathlib import Path
from typing import Any

import numpy as np

from gnssatt import montecarlo
from gnssatt.attitude import dynamics as tumble
from gnssatt.experiments import Experiment
from gnssatt.experiments.report import format_table, write_report

NAME = "visibility-rotation"
DURATION_S = 1500.0
AXIS_SIGMA_DEG = 5.0  # per tangent component: 3 sigma = 15 deg
MAX_RATE_DEG_S = 3.0
ANGLES = ("psi", "alpha", "phi")
RATES = ("wx", "wy", "wz")


def random_initial_state(rng: np.random.Generator) -> np.ndarray:
    """(psi, alpha, phi, wx, wy, wz): paper-uniform angles (rad), rate uniform in the 3 deg/s ball."""
    angles = [rng.uniform(0, 2 * math.pi), rng.uniform(0, math.pi), rng.uniform(0, 2 * math.pi)]
    while True:
        w = rng.uniform(-1.0, 1.0, 3)
        if w @ w <= 1.0:
            break
    state: np.ndarray = np.r_[angles, w * math.radians(MAX_RATE_DEG_S)]  # numpy types np.r_ as Any
    return state


def noisy_axes(rng: np.random.Generator, axes: np.ndarray, sigma_deg: float) -> np.ndarray:
    """Each unit axis tilted by a Gaussian tangent-plane error of ``sigma_deg`` per component."""
    helper = np.where(np.abs(axes[:, :1]) < 0.9, [[1.0, 0.0, 0.0]], [[0.0, 1.0, 0.0]])
    e1 = np.cross(axes, helper)
    e1 /= np.linalg.norm(e1, axis=1, keepdims=True)
    e2 = np.cross(axes, e1)
    d = rng.normal(0.0, math.radians(sigma_deg), (len(axes), 2))
    out = axes + d[:, :1] * e1 + d[:, 1:] * e2
    unit: np.ndarray = out / np.linalg.norm(out, axis=1, keepdims=True)  # norm over an axis is typed Any
    return unit


def visibility_axes(rng: np.random.Generator, t: np.ndarray, axes: np.ndarray) -> np.ndarray:
    """Axes estimated from simulated GPS + GLONASS visibility (500 km, 51.6 deg, random orbit phase)."""
    from gnssatt import sim
    from gnssatt.attitude.visibility import visibility_axis, visibility_sets

    rx = sim.OrbitalReceiver(
        altitude_m=500e3,
        inclination_deg=51.6,
        raan_deg=rng.uniform(0, 360),
        arg_latitude_deg=rng.uniform(0, 360),
    )
    sets = visibility_sets(rx, sim.gps_nominal() + sim.glonass_nominal(), t, axes)
    return np.array([visibility_axis(v, h, method="centroid") for v, h in sets])


def state_errors(est: np.ndarray, truth: np.ndarray) -> dict[str, float]:
    """Angle (deg), rate (deg/s) and total attitude (deg) errors of ``est`` after the 180-deg fold."""
    from scipy.spatial.transform import Rotation

    est = tumble.fold_symmetric(est, truth)
    ang = np.degrees((est[:3] - truth[:3] + math.pi) % (2 * math.pi) - math.pi)
    rate = np.degrees(est[3:] - truth[3:])
    row = {f"{k}_error_deg": float(v) for k, v in zip(ANGLES, ang, strict=True)}
    row |= {f"{k}_error_deg_s": float(v) for k, v in zip(RATES, rate, strict=True)}
    total = Rotation.from_euler("YZY", est[:3]) * Rotation.from_euler("YZY", truth[:3]).inv()
    row["attitude_error_deg"] = float(np.degrees(total.magnitude()))
    return row


def trial(
    rng: np.random.Generator,
    *,
    measurements: str = "noise",
    max_restarts: int = 3,
    min_restarts: int = 1,
    restart: str = "horizon",
    duration_s: float = DURATION_S,
) -> dict[str, float]:
    """One trial: random initial state, measured axes over ``duration_s`` at 1 Hz, DE fit; errors in deg,
    deg/s.

    With ``measurements="noise"`` the fit restarts (up to ``max_restarts`` times, seeds from this
    trial's stream, ``restart`` as in :func:`gnssatt.attitude.dynamics.fit_rotation`) while its
    objective exceeds what 5-deg axis noise explains (:func:`gnssatt.attitude.dynamics.noise_cost_threshold`,
    tail 1e-3). The row
    also holds the first run's errors (``first_run_*``): the fit without restarts, on the same seed.
    ``min_restarts`` restarts run whatever the first objective (a local minimum within the noise spread
    passes the threshold).
    """
    model = tumble.TumbleModel.circular(500e3)
    truth = random_initial_state(rng)
    t = np.arange(0.0, duration_s + 1.0, 1.0)
    axes = tumble.propagate_axes(truth, t, model)
    if measurements == "visibility":
        meas, sigma = visibility_axes(rng, t, axes), None
    else:
        meas, sigma = noisy_axes(rng, axes, AXIS_SIGMA_DEG), AXIS_SIGMA_DEG
    fit = tumble.fit_rotation(
        t,
        meas,
        model,
        rng=int(rng.integers(2**31)),
        axis_sigma_deg=sigma,
        max_restarts=max_restarts,
        min_restarts=min_restarts,
        restart=restart,  # type: ignore[arg-type]
    )
    row = state_errors(fit.params, truth)
    row |= {f"first_run_{k}": v for k, v in state_errors(fit.attempt_params[0], truth).items()}
    row |= {f"{k}_true_deg": float(v) for k, v in zip(ANGLES, np.degrees(truth[:3]), strict=True)}
    row |= {f"{k}_true_deg_s": float(v) for k, v in zip(RATES, np.degrees(truth[3:]), strict=True)}
    row["residual_rms_deg"] = fit.residual_rms_deg
    row["nfev"] = float(fit.nfev)
    row["restarts"] = float(len(fit.attempt_costs) - 1)
    row["cost_over_threshold"] = float(fit.cost > fit.cost_threshold)
    row["first_run_cost_over_threshold"] = float(fit.attempt_costs[0] > fit.cost_threshold)
    row["cost_to_threshold"] = fit.cost / fit.cost_threshold
    # The global minimum lies at or below the objective at the truth: a fit above it is a local minimum.
    row["cost_to_truth_cost"] = fit.cost / float(tumble.axis_cost(truth, t, meas, model)[0])
    row["first_run_cost_to_threshold"] = float(fit.attempt_costs[0] / fit.cost_threshold)
    return row


def _robust_sigma(x: np.ndarray) -> float:
    return float(1.4826 * np.median(np.abs(x - np.median(x))))


def run(
    *,
    runs: int,
    seed: int,
    out: Path,
    executor: Executor | None = None,
    progress: bool = True,
    measurements: str = "noise",
    duration_s: float = DURATION_S,
) -> dict[str, Any]:
    from gnssatt import plots

    rows = montecarlo.run(
        functools.partial(trial, measurements=measurements, duration_s=duration_s),
        runs,
        seed=seed,
        executor=executor,
        progress=progress,
    )
    col = {k: np.array([r[k] for r in rows]) for k in rows[0]}
    measured: dict[str, Any] = {}
    for prefix in ("", "first_run_"):
        for k in ANGLES:
            e = col[f"{prefix}{k}_error_deg"]
            measured[f"{prefix}{k}_error_mean_deg"] = float(np.mean(e))
            measured[f"{prefix}{k}_error_sigma_deg"] = float(np.std(e))
            measured[f"{prefix}{k}_error_robust_sigma_deg"] = _robust_sigma(e)
        for k in RATES:
            e = col[f"{prefix}{k}_error_deg_s"]
            measured[f"{prefix}{k}_error_mean_deg_s"] = float(np.mean(e))
            measured[f"{prefix}{k}_error_sigma_deg_s"] = float(np.std(e))
            measured[f"{prefix}{k}_error_robust_sigma_deg_s"] = _robust_sigma(e)
        for stat in ("sigma", "robust_sigma"):
            measured[f"{prefix}angle_error_{stat}_deg"] = max(
                measured[f"{prefix}{k}_error_{stat}_deg"] for k in ANGLES
            )
            measured[f"{prefix}rate_error_{stat}_deg_s"] = max(
                measured[f"{prefix}{k}_error_{stat}_deg_s"] for k in RATES
            )
        att = col[f"{prefix}attitude_error_deg"]
        measured[f"{prefix}attitude_error_median_deg"] = float(np.median(att))
        measured[f"{prefix}attitude_error_p95_deg"] = float(np.percentile(att, 95))
        measured[f"{prefix}attitude_error_over_15deg_fraction"] = float(np.mean(att > 15.0))
    if measurements == "noise":
        # Fits whose objective exceeds what the axis noise explains (tumble.noise_cost_threshold).
        measured["first_run_local_minimum_fraction"] = float(np.mean(col["first_run_cost_over_threshold"]))
        measured["local_minimum_fraction"] = float(np.mean(col["cost_over_threshold"]))
        measured["restarted_fraction"] = float(np.mean(col["restarts"] > 0))
        measured["restarts_mean"] = float(np.mean(col["restarts"]))
    measured["axis_residual_rms_mean_deg"] = float(np.mean(col["residual_rms_deg"]))
    measured["objective_evaluations_mean"] = float(np.mean(col["nfev"]))
    paper = {
        "angle_error_sigma_deg": 5.0,
        "rate_error_sigma_deg_s": 0.12,
        "attitude_error_over_15deg_fraction": None,
    }
    # The paper's body and torques are not given (an assumed TumbleModel here): its error sigmas within a
    # factor 2.
    tolerance = {"angle_error_sigma_deg": 2.0, "rate_error_sigma_deg_s": 2.0}
    doc = write_report(out, NAME, paper, measured, runs, seed, tolerance=tolerance)
    with open(out / f"{NAME}-trials.csv", "w", newline="") as f:  # one row per trial, in trial order
        writer = csv.DictWriter(f, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
    plots.error_histograms(
        {k: col[f"{k}_error_deg_s"] for k in RATES},
        out / f"{NAME}-rates.png",
        title=f"Belokonov et al.: angular-rate errors, {runs} runs (paper fig. 3)",
        unit="deg/s",
    )
    plots.error_histograms(
        {k: col[f"{k}_error_deg"] for k in ANGLES},
        out / f"{NAME}-angles.png",
        title=f"Belokonov et al.: angle errors, {runs} runs (paper fig. 4)",
        unit="deg",
    )
    print(format_table(doc))
    return doc


EXPERIMENT = Experiment(
    name=NAME,
    summary=(
        "Belokonov et al.: tumbling-spacecraft rotation from GNSS-visibility axis directions (DE fit, 1500 s)"
    ),
    run=run,
    default_runs=400,
    quick_runs=4,
)
