"""Valid calls that are not a public function by their name: classes, methods, and a second form of a
public function (other values, which specific cases are written against), keyed by the intake tests' names."""

from __future__ import annotations

from functools import cache
from typing import Any

import numpy as np

from gnssatt.attitude import gyro_gnss, likelihood, phase_attitude
from gnssatt.attitude import wahba as vector_attitude
from gnssatt.sim import attitude_scenario as sc

from .estimators import ARRAY_SHAPE_3, BAD_BASELINES, BASELINES, L1, LOS, TRUTH
from .spec import Arg, Call


@cache
def observations() -> sc.PhaseObservations:
    """Error-free first differences, cycles, at 3 epochs of 5 satellites; attitude TRUTH (body -> ECI)."""
    n_e, m = 3, len(BASELINES)
    epoch = np.repeat(np.arange(n_e), len(LOS))
    los = np.tile(LOS, (n_e, 1))
    lam = np.full(len(epoch), L1)
    phase = -(TRUTH.inv().apply(los) @ BASELINES.T) / lam[:, None]
    track = np.tile(np.arange(len(LOS)), n_e)
    amb = np.zeros((len(epoch), m), np.int64)
    return sc.PhaseObservations(np.arange(n_e) * 10.0, epoch, track, los, lam, phase, amb, track)


def gyro_filter_call() -> dict[str, Any]:
    return {
        "gyro_t": np.arange(0.0, 21.0),
        "gyro_rates": np.zeros((21, 3)),
        "initial_rotation": TRUTH,
        "initial_covariance": np.diag([1e-4] * 3 + [1e-10] * 3),
        "arw": 1e-5,
        "baselines_m": BASELINES,
        "phases": observations().without_ambiguities(),
        "known_ambiguities": True,
    }


CALLS: dict[str, Call] = {
    "vector_attitude.wahba": Call(
        lambda: {"body": TRUTH.inv().apply(LOS), "ref": LOS, "weights": np.ones(len(LOS))},
        args={
            "body": Arg("array", shapes=(LOS[:, :2], LOS[0], LOS[:1])),
            "ref": Arg("array", shapes=(LOS[:, :2], LOS[0], LOS[:3])),
            "weights": Arg(
                "array",
                shapes=(np.ones(3), np.ones((2, 2, 5))),
                out_of_range=(-np.ones(5), np.zeros(5)),
                optional=True,
            ),
            "method": Arg("choice"),
        },
        function=vector_attitude.wahba,
    ),
    "likelihood.AttitudePrior": Call(
        lambda: {"euler_gost_deg": np.array([10.0, 5.0, -3.0]), "half_width_deg": np.array([5.0, 5.0, 5.0])},
        args={
            "euler_gost_deg": Arg("array", shapes=ARRAY_SHAPE_3, out_of_range=([400.0, 0.0, 0.0],)),
            "half_width_deg": Arg(
                "array", shapes=ARRAY_SHAPE_3, out_of_range=(np.zeros(3), [5.0, -1.0, 5.0], [400.0, 5.0, 5.0])
            ),
        },
        function=likelihood.AttitudePrior,
    ),
    "gyro_gnss.gyro_gnss_filter": Call(
        gyro_filter_call,
        args={
            "gyro_t": Arg("array", shapes=(np.zeros((21, 1)), np.arange(20.0)), out_of_range=(np.zeros(21),)),
            "gyro_rates": Arg(
                "array",
                shapes=(np.zeros((21, 2)), np.zeros((20, 3))),
                out_of_range=(np.full((21, 3), 1e300),),
            ),
            "initial_rotation": Arg("object"),
            "initial_covariance": Arg(
                "array",
                shapes=(np.eye(3), np.eye(36)),
                out_of_range=(-np.eye(6), np.eye(6) + np.triu(np.ones((6, 6)), 1)),
            ),
            "arw": Arg("scalar", out_of_range=(-1.0,)),
            "rrw": Arg("scalar", out_of_range=(-1.0,)),
            "initial_drift": Arg("array", shapes=ARRAY_SHAPE_3),
            "baselines_m": Arg(
                "array", shapes=(BASELINES[:, :2], BASELINES[:2]), out_of_range=BAD_BASELINES, optional=True
            ),
            "phase_sigma_cycles": Arg("scalar", out_of_range=(0.0, -0.01)),
            "phases": Arg("object", optional=True),
            "attitude_fixes": Arg("object", optional=True),
            "fix_ambiguities": Arg("flag"),
            "ratio_threshold": Arg("scalar", out_of_range=(0.5,)),
            "min_success_rate": Arg("scalar", out_of_range=(1.5, -0.1)),
            "slip_false_alarm": Arg("scalar", out_of_range=(0.0, 1.0), optional=True),
            "known_ambiguities": Arg("flag"),
            "misalignment_sigma_rad": Arg("scalar", out_of_range=(0.0, -1.0), optional=True),
            "output_every": Arg("integer", out_of_range=(0, -1), limited=False),
        },
        function=gyro_gnss.gyro_gnss_filter,
    ),
    "phase_attitude.phase_attitude_fixes": Call(
        lambda: {
            "phases": observations(),
            "baselines_m": BASELINES,
            "ambiguities": observations().ambiguity,
            "phase_sigma_cycles": 0.01,
        },
        args={
            "phases": Arg("object"),
            "baselines_m": Arg("array", shapes=(BASELINES[:, :2], BASELINES[:2]), out_of_range=BAD_BASELINES),
            "ambiguities": Arg(
                "array", shapes=(np.zeros((15, 2)), np.zeros(15)), out_of_range=(np.full((15, 3), 0.5),)
            ),
            "phase_sigma_cycles": Arg("scalar", out_of_range=(0.0, -1.0, 1e160)),
        },
        function=phase_attitude.phase_attitude_fixes,
    ),
}
