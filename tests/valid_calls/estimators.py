"""Valid calls of the estimators (``gnssatt``: ambiguities, attitude), the rotations, geometry and
visibility."""

from __future__ import annotations

from typing import Any

import numpy as np
from hostile import scenario as s
from scipy.spatial.transform import Rotation

from gnssatt.attitude import dynamics as tumble

from .spec import WORK_TINY_STEP, Arg, Call


def _unit(rows: list[list[float]]) -> np.ndarray:
    v = np.array(rows)
    return v / np.linalg.norm(v, axis=1, keepdims=True)


def _amb() -> dict[str, Any]:
    p = s.ambiguity_problem()
    return {"float_ambiguities": p["float"].copy(), "covariance": p["cov"].copy()}


def _att() -> dict[str, Any]:
    return s.attitude_problem()


def _phase_args(n_base: int = 2) -> dict[str, Any]:
    p = _att()
    return {
        "phase_diffs": p["phase"][:n_base].copy(),
        "los": p["los"].copy(),
        "baselines": s.BASELINES[:n_base].copy(),
        "wavelength": p["wavelength"],
    }


def _fit_args() -> dict[str, Any]:
    t = np.arange(0.0, 61.0, 5.0)
    axes = tumble.propagate_axes(s.TUMBLE_TRUTH, t, s.TUMBLE_MODEL)
    return {
        "t": t,
        "measured_axes": axes,
        "model": s.TUMBLE_MODEL,
        "rng": 1,
        "axis_sigma_deg": 1.0,
        "max_restarts": 0,
        "popsize": 5,
        "maxiter": 5,
        "polish": False,
    }


def _gyro_filter() -> dict[str, Any]:
    g = s.gyro()
    ph = s.phases()
    p0 = np.diag([np.radians(0.5) ** 2] * 3 + [(np.radians(20.0) / 3600.0) ** 2] * 3)
    return {
        "gyro_t": g["t"].copy(),
        "gyro_rates": g["rates"].copy(),
        "initial_rotation": g["att"][0],
        "initial_covariance": p0,
        "arw": 1e-5,
        "baselines_m": s.BASELINES.copy(),
        "phases": ph,
        "phase_sigma_cycles": 0.01,
        "ratio_threshold": 3.0,
        "output_every": 1,
    }


_WINDOW = np.array([[-60.0, 60.0], [-20.0, 20.0], [-20.0, 20.0]])  # (3, 2) psi, theta, phi bounds, degrees


CALLS: dict[str, Call] = {
    # --- gnssatt (estimators, ambiguities) ---
    "gnssatt.bootstrap_success_rate": Call(lambda: {"covariance": _amb()["covariance"]}),
    "gnssatt.lambda_decorrelate": Call(lambda: {"covariance": _amb()["covariance"]}),
    "gnssatt.lambda_ils": Call(lambda: {**_amb(), "candidates": 2}, args={"candidates": Arg(count=True)}),
    "gnssatt.lambda_ils_batch": Call(
        lambda: {
            "float_ambiguities": np.stack([_amb()["float_ambiguities"] + k for k in range(3)]),
            "covariance": _amb()["covariance"],
            "candidates": 2,
        },
        args={"candidates": Arg(count=True)},
    ),
    # inf when the best squared norm is 0 (integer float vector), documented
    "gnssatt.ratio_test": Call(
        lambda: {**_amb(), "failure_rate": 1e-3, "samples": 2000, "seed": 0},
        args={"samples": Arg(count=True)},
        nan_fields=frozenset({"ratio"}),
    ),
    # NaN when nothing is fixed, ratio inf on integers: documented
    "gnssatt.partial_fix": Call(
        lambda: {
            **_amb(),
            "min_success_rate": 0.5,
            "threshold": 2.0,
            "samples": 2000,
            "seed": 0,
        },
        args={"samples": Arg(count=True)},
        nan_fields=frozenset({"ratio", "threshold"}),
    ),
    "gnssatt.ratio_threshold_fixed_failure_rate": Call(
        lambda: {
            "covariance": _amb()["covariance"],
            "failure_rate": 1e-3,
            "samples": 2000,
            "seed": 0,
        },
        args={"samples": Arg(count=True)},
    ),
    "gnssatt.matrix_attitude": Call(
        lambda: {
            "baselines": s.BASELINES.copy(),
            "los": _att()["los"].copy(),
            "range_diffs": _att()["range_diffs"].copy(),
            "method": "svd",
        }
    ),
    "gnssatt.likelihood_grid": Call(lambda: {**_phase_args(), "step_deg": 5.0, "window_deg": _WINDOW.copy()}),
    "gnssatt.ml_attitude": Call(lambda: {**_phase_args(), "step_deg": 5.0, "window_deg": _WINDOW.copy()}),
    "gnssatt.ml_baseline": Call(
        lambda: {
            "phase_diffs": _att()["phase"][0].copy(),
            "los": _att()["los"].copy(),
            "baseline_length_m": 1.0,
            "wavelength": _att()["wavelength"],
            "step_deg": 2.0,
            "window_deg": np.array([[0.0, 40.0], [-10.0, 20.0]]),
        }
    ),
    # NaN marks absent signals, documented
    # NaN at unsolved epochs, flagged by solved
    "gnssatt.ml_attitude_series": Call(
        lambda: {
            "sd_phase": np.stack([_att()["phase"][:2], _att()["phase"][:2]]),
            "los": _att()["los"].copy(),
            "baselines": s.BASELINES[:2].copy(),
            "wavelength": _att()["wavelength"],
            "step_deg": 5.0,
            "window_deg": 10.0,
        },
        args={
            "sd_phase": Arg(nonfinite_ok=True),
            "los": Arg(nonfinite_ok=True),
            "wavelength": Arg(nonfinite_ok=True),
        },
        nan_fields=frozenset({"euler_gost_deg", "z_max"}),
    ),
    # NaN marks absent signals, documented
    # unsolved epochs
    "gnssatt.ml_baseline_series": Call(
        lambda: {
            "sd_phase": np.stack([_att()["phase"][0], _att()["phase"][0]]),
            "los": _att()["los"].copy(),
            "baseline_length_m": 1.0,
            "wavelength": _att()["wavelength"],
            "step_deg": 2.0,
            "window_deg": 5.0,
        },
        args={
            "sd_phase": Arg(nonfinite_ok=True),
            "los": Arg(nonfinite_ok=True),
            "wavelength": Arg(nonfinite_ok=True),
        },
        nan_fields=frozenset({"heading_deg", "elevation_deg", "direction_enu", "z_max"}),
    ),
    "gnssatt.prior_from_velocity": Call(
        lambda: {
            "velocity_enu": np.array([10.0, 20.0, 0.5]),
            "acceleration_enu": np.array([0.1, -0.2, 0.0]),
            "half_width_deg": (7.0, 7.0, 7.0),
            "gravity": 9.80665,
        }
    ),
    "gnssatt.triad": Call(
        lambda: {
            "b1": np.array([1.0, 0.0, 0.0]),
            "b2": np.array([0.0, 1.0, 0.0]),
            "r1": np.array([0.0, 1.0, 0.0]),
            "r2": np.array([-1.0, 0.0, 0.0]),
        }
    ),
    "gnssatt.wahba": Call(
        lambda: {
            "body": np.eye(3),
            "ref": Rotation.from_euler("z", 30, degrees=True).apply(np.eye(3)),
            "weights": np.array([1.0, 2.0, 3.0]),
        }
    ),
    "gnssatt.yaw_from_magnetometer": Call(
        lambda: {
            "b_body": np.array([2e-5, 1e-5, -3e-5]),
            "b_orbital": np.array([1e-5, 2e-5, -3e-5]),
            "pitch": 0.01,
            "roll": -0.02,
        }
    ),
    "gnssatt.gyro_propagate": Call(
        lambda: {
            "q0": np.array([0.0, 0.0, 0.0, 1.0]),
            "t": np.arange(0.0, 1.01, 0.1),
            "rates": np.full((11, 3), 0.01),
        }
    ),
    "gnssatt.gyro_gnss_filter": Call(_gyro_filter, args={"output_every": Arg(count=True)}),
    "gnssatt.phase_attitude_fixes": Call(
        lambda: {
            "phases": s.phases(),
            "baselines_m": s.BASELINES.copy(),
            "ambiguities": s.phases().ambiguity.copy(),
            "phase_sigma_cycles": 0.01,
        }
    ),
    # inf when axis_sigma_deg is None (no restart test), documented
    "gnssatt.fit_rotation": Call(
        _fit_args,
        args={
            "max_restarts": Arg(count=True),
            "popsize": Arg(count=True),
            "maxiter": Arg(count=True),
            "patience": Arg(count=True),
            "step_s": Arg(work=WORK_TINY_STEP),
        },
        nan_fields=frozenset({"cost_threshold"}),
    ),
    "gnssatt.visibility_axis": Call(
        lambda: {
            "visible_los": _unit([[0.0, 0.0, 1.0], [0.3, 0.0, 0.95], [0.0, 0.3, 0.95]]),
            "invisible_los": _unit([[0.0, 0.0, -1.0], [0.3, 0.0, -0.95]]),
            "method": "paper",
        }
    ),
    # --- gnssatt.attitude.visibility ---
    "gnssatt.attitude.visibility.visibility_sets": Call(
        lambda: {
            "receiver": s.ORBITAL,
            "constellation": s.gps(),
            "t": np.arange(0.0, 21.0, 10.0),
            "axes_orbital": np.tile([0.0, 0.0, 1.0], (3, 1)),
            "half_angle_deg": 90.0,
        }
    ),
    # --- gnssatt.rotation, gnssatt.geometry ---
    "gnssatt.rotation.dcm_to_euler": Call(
        lambda: {
            "seq": "ZYX",
            "dcm": Rotation.from_euler("ZYX", [0.3, 0.2, 0.1]).as_matrix(),
        }
    ),
    "gnssatt.rotation.dcm_to_quat": Call(
        lambda: {"dcm": Rotation.from_euler("ZYX", [0.3, 0.2, 0.1]).as_matrix()}
    ),
    "gnssatt.rotation.euler_to_dcm": Call(lambda: {"seq": "ZYX", "angles": np.array([0.3, 0.2, 0.1])}),
    "gnssatt.rotation.nearest_rotation": Call(lambda: {"matrix": np.eye(3) + 0.01}),
    "gnssatt.rotation.quat_to_dcm": Call(lambda: {"quat": np.array([0.1, 0.2, 0.3, 0.9])}),
    "gnssatt.rotation.rotation_from_euler": Call(lambda: {"euler_gost_deg": np.array([-40.0, 5.0, 3.0])}),
    "gnssatt.rotation.euler_from_rotation": Call(
        lambda: {"rotation": Rotation.from_euler("YZX", [10.0, 5.0, 3.0], degrees=True)}
    ),
    "gnssatt.geometry.attitude_dop": Call(
        lambda: {
            "baselines": s.BASELINES.copy(),
            "los": _att()["los"].copy(),
            "rotation": _att()["rotation"],
        }
    ),
    "gnssatt.data.geonet_dir": Call(dict),
    "gnssatt.geometry.range_difference_fisher": Call(
        lambda: {
            "baselines": s.BASELINES.copy(),
            "los": _att()["los"].copy(),
            "rotation": _att()["rotation"],
        }
    ),
}
