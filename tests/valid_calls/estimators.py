"""Valid calls of the estimators (``gnssatt``: ambiguities, attitude), the rotations, geometry and
visibility."""

from __future__ import annotations

from typing import Any

import numpy as np
from hostile import scenario as s
from scipy.spatial.transform import Rotation

from gnssatt.attitude import dynamics as tumble

from .spec import WORK_TINY_STEP, Arg, Call

# For the estimators' intake cases (``test_intake_estimators``): an attitude, an array and lines of sight
# from which the wrong shapes and out-of-range values of the arguments are made.
TRUTH = Rotation.from_euler("ZYX", [30.0, 10.0, -5.0], degrees=True)
BASELINES = np.array([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.2, 1.0]])
LOS = np.array([[0.0, 0.0, 1.0], [0.6, 0.0, 0.8], [0.0, 0.6, 0.8], [-0.48, -0.36, 0.8], [0.36, -0.48, 0.8]])
RANGE_DIFFS = BASELINES @ TRUTH.inv().apply(LOS).T  # (m, n): b_i . (A s_j)
L1 = 0.19029367279836487
ARRAY_SHAPE_3 = (np.zeros(2), np.zeros((1, 3)), np.zeros(4))
# zero, sub-micrometre (a Rust panic in matrix_attitude before) and longer than the Earth
BAD_BASELINES = (BASELINES * 0, BASELINES * 1e-60, BASELINES * 1e8)
BAD_WAVELENGTHS = (0.0, -L1, 1e-300, 1e300)
BAD_STEPS = (0.0, -1.0, 1e-9, 200.0)
VEC3_OR_N3 = (np.zeros(2), np.zeros((2, 2)), np.zeros((1, 1, 3)))
MATRIX_33 = (np.eye(2), np.zeros(9), np.zeros((3, 3, 3)))
WINDOW = np.array([[0.0, 40.0], [-10.0, 20.0], [-20.0, 20.0]])


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
        },
        args={
            "baselines": Arg("array", shapes=(BASELINES[:, :2], BASELINES[0]), out_of_range=BAD_BASELINES),
            "los": Arg("array", shapes=(LOS[:, :2], LOS[0]), out_of_range=(LOS * 2,)),
            "range_diffs": Arg(
                "array",
                shapes=(RANGE_DIFFS[:, :2], RANGE_DIFFS[0], RANGE_DIFFS.T),
                out_of_range=(RANGE_DIFFS * 1e300,),
            ),
            "method": Arg("choice"),
        },
    ),
    "gnssatt.likelihood_grid": Call(
        lambda: {**_phase_args(), "step_deg": 5.0, "window_deg": _WINDOW.copy()},
        args={
            "phase_diffs": Arg(
                "array",
                shapes=(np.zeros(5), np.zeros((2, 4)), np.zeros((3, 5))),
                out_of_range=(np.full((2, 5), 1e13),),
            ),
            "los": Arg("array", shapes=(LOS[:, :2], LOS[:4]), out_of_range=(LOS * 2,)),
            "baselines": Arg(
                "array",
                shapes=(BASELINES[:, :2], BASELINES),
                out_of_range=tuple(b[:2] for b in BAD_BASELINES),
            ),
            "wavelength": Arg("array", shapes=(np.full(4, L1),), out_of_range=BAD_WAVELENGTHS),
            "statistic": Arg("choice"),
            "step_deg": Arg("scalar", out_of_range=BAD_STEPS, optional=True),
            "window_deg": Arg(
                "array",
                shapes=(WINDOW[:2], WINDOW.T),
                out_of_range=(WINDOW[:, ::-1], WINDOW * 1e20, WINDOW - 5000.0),
                optional=True,
            ),
        },
    ),
    "gnssatt.ml_attitude": Call(
        lambda: {**_phase_args(), "step_deg": 5.0, "window_deg": _WINDOW.copy()},
        args={
            "phase_diffs": Arg(
                "array",
                shapes=(np.zeros(5), np.zeros((2, 4)), np.zeros((3, 5))),
                out_of_range=(np.full((2, 5), 1e13),),
            ),
            "los": Arg("array", shapes=(LOS[:, :2], LOS[:4]), out_of_range=(LOS * 2,)),
            "baselines": Arg(
                "array",
                shapes=(BASELINES[:, :2], BASELINES),
                out_of_range=tuple(b[:2] for b in BAD_BASELINES),
            ),
            "wavelength": Arg("array", shapes=(np.full(4, L1),), out_of_range=BAD_WAVELENGTHS),
            "statistic": Arg("choice"),
            "step_deg": Arg("scalar", out_of_range=BAD_STEPS, optional=True),
            "window_deg": Arg(
                "array",
                shapes=(WINDOW[:2], WINDOW.T),
                out_of_range=(WINDOW[:, ::-1], WINDOW * 1e20, WINDOW - 5000.0),
                optional=True,
            ),
            "search": Arg("choice"),
            "refine": Arg("choice"),
        },
    ),
    "gnssatt.ml_baseline": Call(
        lambda: {
            "phase_diffs": _att()["phase"][0].copy(),
            "los": _att()["los"].copy(),
            "baseline_length_m": 1.0,
            "wavelength": _att()["wavelength"],
            "step_deg": 2.0,
            "window_deg": np.array([[0.0, 40.0], [-10.0, 20.0]]),
        },
        args={
            "phase_diffs": Arg(
                "array", shapes=(np.zeros(4), np.zeros((2, 2, 5))), out_of_range=(np.full(5, -1e13),)
            ),
            "los": Arg("array", shapes=(LOS[:, :2], LOS[:4]), out_of_range=(LOS * 2,)),
            "baseline_length_m": Arg("scalar", out_of_range=(0.0, -1.0, 1e-60, 1e8)),
            "wavelength": Arg("array", shapes=(np.full(4, L1),), out_of_range=BAD_WAVELENGTHS),
            "statistic": Arg("choice"),
            "step_deg": Arg("scalar", out_of_range=BAD_STEPS, optional=True),
            "window_deg": Arg(
                "array",
                shapes=(WINDOW, WINDOW[:2].T[:1]),
                out_of_range=(WINDOW[:2, ::-1], WINDOW[:2] * 1e20),
                optional=True,
            ),
            "refine": Arg("choice"),
        },
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
        },
        args={
            "velocity_enu": Arg("array", shapes=ARRAY_SHAPE_3, out_of_range=([0.0, 0.0, 5.0],)),
            "acceleration_enu": Arg("array", shapes=ARRAY_SHAPE_3, optional=True),
            "half_width_deg": Arg(
                "array", shapes=ARRAY_SHAPE_3, out_of_range=(np.zeros(3), [400.0, 5.0, 5.0])
            ),
            "gravity": Arg("scalar", out_of_range=(0.0, -9.8)),
        },
    ),
    "gnssatt.triad": Call(
        lambda: {
            "b1": np.array([1.0, 0.0, 0.0]),
            "b2": np.array([0.0, 1.0, 0.0]),
            "r1": np.array([0.0, 1.0, 0.0]),
            "r2": np.array([-1.0, 0.0, 0.0]),
        },
        args={n: Arg("array", shapes=VEC3_OR_N3) for n in ("b1", "b2", "r1", "r2")},
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
        },
        args={
            "b_body": Arg("array", shapes=VEC3_OR_N3),
            "b_orbital": Arg("array", shapes=VEC3_OR_N3),
            "pitch": Arg("array", shapes=(np.zeros((2, 2)),)),
            "roll": Arg("array", shapes=(np.zeros((2, 2)),)),
            "degrees": Arg("flag"),
        },
    ),
    "gnssatt.gyro_propagate": Call(
        lambda: {
            "q0": np.array([0.0, 0.0, 0.0, 1.0]),
            "t": np.arange(0.0, 1.01, 0.1),
            "rates": np.full((11, 3), 0.01),
        },
        args={
            "q0": Arg("array", shapes=(np.zeros(3), np.zeros((1, 4))), out_of_range=(np.zeros(4),)),
            # equal times; an interval of 1e300 s at 0.01 rad/s (NaN quaternions before)
            "t": Arg(
                "array",
                shapes=(np.arange(4.0), np.zeros((5, 1))),
                out_of_range=(np.zeros(5), [0, 1, 2, 3, 1e300]),
            ),
            "rates": Arg(
                "array",
                shapes=(np.zeros((5, 2)), np.zeros((4, 3)), np.zeros(15)),
                out_of_range=(np.full((5, 3), 1e300), np.full((5, 3), 1e6)),
            ),
        },
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
        },
        args={
            "visible_los": Arg("array", shapes=(LOS[:3, :2], LOS[0]), out_of_range=(LOS[:3] * 2,)),
            "invisible_los": Arg("array", shapes=(LOS[3:, :2], LOS[3]), out_of_range=(LOS[3:] * 2,)),
            "method": Arg("choice"),
        },
    ),
    # --- gnssatt.attitude.visibility ---
    "gnssatt.attitude.visibility.visibility_sets": Call(
        lambda: {
            "receiver": s.ORBITAL,
            "constellation": s.gps(),
            "t": np.arange(0.0, 21.0, 10.0),
            "axes_orbital": np.tile([0.0, 0.0, 1.0], (3, 1)),
            "half_angle_deg": 90.0,
        },
        args={
            "receiver": Arg("object"),
            "constellation": Arg("object"),
            "t": Arg("array", shapes=(np.zeros((3, 1)),)),
            "axes_orbital": Arg(
                "array", shapes=(np.zeros((3, 2)), np.zeros((2, 3))), out_of_range=(np.zeros((3, 3)),)
            ),
            "half_angle_deg": Arg("scalar", out_of_range=(0.0, 181.0)),
        },
    ),
    # --- gnssatt.rotation, gnssatt.geometry ---
    "gnssatt.rotation.dcm_to_euler": Call(
        lambda: {
            "seq": "ZYX",
            "dcm": Rotation.from_euler("ZYX", [0.3, 0.2, 0.1]).as_matrix(),
        },
        args={"seq": Arg("choice"), "dcm": Arg("array", shapes=MATRIX_33, out_of_range=(2 * np.eye(3),))},
    ),
    "gnssatt.rotation.dcm_to_quat": Call(
        lambda: {"dcm": Rotation.from_euler("ZYX", [0.3, 0.2, 0.1]).as_matrix()},
        args={"dcm": Arg("array", shapes=MATRIX_33, out_of_range=(2 * np.eye(3),))},
    ),
    "gnssatt.rotation.euler_to_dcm": Call(
        lambda: {"seq": "ZYX", "angles": np.array([0.3, 0.2, 0.1])},
        args={"seq": Arg("choice"), "angles": Arg("array", shapes=ARRAY_SHAPE_3), "degrees": Arg("flag")},
    ),
    "gnssatt.rotation.nearest_rotation": Call(
        lambda: {"matrix": np.eye(3) + 0.01}, args={"matrix": Arg("array", shapes=MATRIX_33)}
    ),
    "gnssatt.rotation.quat_to_dcm": Call(
        lambda: {"quat": np.array([0.1, 0.2, 0.3, 0.9])},
        args={"quat": Arg("array", shapes=(np.zeros(3), np.zeros((1, 4))), out_of_range=(np.zeros(4),))},
    ),
    "gnssatt.rotation.rotation_from_euler": Call(
        lambda: {"euler_gost_deg": np.array([-40.0, 5.0, 3.0])},
        args={"euler_gost_deg": Arg("array", shapes=(np.zeros(2), np.zeros((3, 2)), np.zeros((1, 1, 3))))},
    ),
    "gnssatt.rotation.euler_from_rotation": Call(
        lambda: {"rotation": Rotation.from_euler("YZX", [10.0, 5.0, 3.0], degrees=True)},
        args={"rotation": Arg("object")},
    ),
    "gnssatt.geometry.attitude_dop": Call(
        lambda: {
            "baselines": s.BASELINES.copy(),
            "los": _att()["los"].copy(),
            "rotation": _att()["rotation"],
        },
        args={
            "baselines": Arg("array", shapes=(BASELINES[:, :2], BASELINES[0]), out_of_range=BAD_BASELINES),
            "los": Arg("array", shapes=(LOS[:, :2], LOS[0]), out_of_range=(LOS * 2,)),
            "rotation": Arg("object"),
        },
    ),
    "gnssatt.data.geonet_dir": Call(dict),
    "gnssatt.geometry.range_difference_fisher": Call(
        lambda: {
            "baselines": s.BASELINES.copy(),
            "los": _att()["los"].copy(),
            "rotation": _att()["rotation"],
        },
        args={
            "baselines": Arg("array", shapes=(BASELINES[:, :2], BASELINES[0]), out_of_range=BAD_BASELINES),
            "los": Arg("array", shapes=(LOS[:, :2], LOS[0]), out_of_range=(LOS * 2,)),
            "rotation": Arg("object"),
        },
    ),
}
