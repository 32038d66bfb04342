"""Work limits that count the whole call of the batch entry points (issue 31): epochs x cells of the ML
series, points x coefficients of the IGRF, times x satellites of the lines of sight, epochs x antennas x
satellites of the simulator. Each reproducer of the issue is refused with a ``WorkLimitError`` naming the
parameter, the amount and the limit, before the batch is copied: checked by counting the memory the call
allocates (tracemalloc), never by timing it.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
import pytest
from allocation import traced_peak
from scipy.spatial.transform import Rotation

from gnssatt import (
    likelihood_grid,
    magnetic,
    matrix_attitude,
    ml_attitude,
    ml_attitude_series,
    ml_baseline,
    ml_baseline_series,
    sim,
    triad,
    wahba,
    yaw_from_magnetometer,
)
from gnssatt.attitude import dynamics
from gnssatt.attitude.likelihood import MAX_SERIES_WORK
from gnssatt.attitude.wahba import MAX_VECTOR_PAIRS
from gnssatt.errors import DegenerateGeometryError, InvalidInputError, WorkLimitError
from gnssatt.geometry import attitude_dop
from gnssatt.orbit.constellation import gps_nominal
from gnssatt.orbit.line_of_sight import MAX_GEOMETRY_VALUES
from gnssatt.orbit.receivers import GroundReceiver
from gnssatt.rotation import rotation_from_euler
from gnssatt.sim.measurements import MAX_SIMULATED_VALUES

LOS = sim.random_los(1, 6, min_elevation_deg=15.0)
BASELINES = sim.equilateral_triangle(1.0, plane="xz")[1:]
SD = (-2 * np.pi / 0.19 * (rotation_from_euler([30.0, 10.0, -5.0]).apply(BASELINES) @ LOS.T))[None]
BIG = 3_000_000

# name: (call, parameter named, amount in the message)
REPRODUCERS: dict[str, tuple[Callable[[], object], str, str]] = {
    "ml_attitude_series": (
        lambda: ml_attitude_series(np.broadcast_to(SD[:1], (BIG, 2, 6)), LOS, BASELINES, 0.19, step_deg=3.0),
        "sd_phase",
        "3000000 epochs",
    ),
    "ml_baseline_series": (
        lambda: ml_baseline_series(np.broadcast_to(SD[0, :1], (BIG, 6)), LOS, 0.8, 0.19, step_deg=1.0),
        "sd_phase",
        "3000000 epochs",
    ),
    "igrf_field_ecef": (
        lambda: magnetic.igrf_field_ecef(np.broadcast_to([[4e6, 3e6, 4e6]], (BIG, 3)), 2021.0, max_degree=8),
        "position_ecef_m",
        "3000000 points",
    ),
    "line_of_sight": (
        lambda: sim.line_of_sight(GroundReceiver(35, 139, 50), gps_nominal(), np.broadcast_to(0.0, (BIG,))),
        "t",
        "3000000 times x 24 satellites",
    ),
    "simulate_array": (
        lambda: sim.simulate_array(
            sim.line_of_sight(GroundReceiver(35, 139, 50), gps_nominal(), 0.0),
            Rotation.identity(),
            np.broadcast_to(np.zeros((1, 3)), (BIG, 3)),
            gps_nominal().wavelengths_m(),
        ),
        "antennas_body_m",
        "3000000 antennas x 24 satellites",
    ),
}


@pytest.mark.parametrize("name", list(REPRODUCERS))
def test_the_reproducers_are_refused_before_the_batch_is_copied(name: str) -> None:
    call, parameter, amount = REPRODUCERS[name]
    with traced_peak() as peak, pytest.raises(WorkLimitError, match=parameter) as info:
        call()
    message = str(info.value)
    assert amount in message and "limit" in message, message
    # the batch as float64 is 24-144 MB; a refusal made from its shape allocates nothing of its size
    assert peak.bytes < 8_000_000, peak


def test_the_series_limit_counts_cells_epochs_signals_and_rovers() -> None:
    # step 3 deg on a 1 m baseline is an exhaustive pass over 120 x 61 x 120 cells (2 pi / 3 deg nodes a
    # turn, pi / 3 deg + 1 of pitch), charged with 8192 cells of refinement and 6 signals x 2 rovers
    from gnssatt import _core

    per_epoch = (120 * 61 * 120 + 8192) * 12
    work = _core.ml_series_work(
        10,
        2,
        6,
        step_rad=np.radians(3.0),
        wavelength_m=0.19,
        longest_baseline_m=1.0,
        window_rad=None,
        two_dimensional=False,
    )
    assert work == 10 * per_epoch
    # with a window, the later epochs are charged their window: 3 nodes a side of +-3 deg at 3 deg
    windowed = _core.ml_series_work(
        10,
        2,
        6,
        step_rad=np.radians(3.0),
        wavelength_m=0.19,
        longest_baseline_m=1.0,
        window_rad=np.radians(3.0),
        two_dimensional=False,
    )
    assert windowed == per_epoch + 9 * (27 + 8192) * 12
    # the most epochs accepted at this step: refused one above it
    n = int(MAX_SERIES_WORK // per_epoch)
    sd = np.broadcast_to(SD[:1], (n + 1, 2, 6))
    with pytest.raises(WorkLimitError, match=f"{n + 1} epochs"):
        ml_attitude_series(sd, LOS, BASELINES, 0.19, step_deg=3.0)


def test_the_core_counts_each_epoch_after_an_unsolved_one_on_the_whole_domain() -> None:
    # Alternate epochs lack every signal: each solved epoch follows an unsolved one and searches the whole
    # domain, not the window. The shapes alone (all epochs solved, windows after the first) stay under the
    # limit; the core's count from the epochs themselves does not, and refuses before any search.
    per_full = (120 * 61 * 120 + 8192) * 12
    n = 2 * (int(MAX_SERIES_WORK // per_full) + 1)
    sd = np.array(np.broadcast_to(SD[:1], (n, 2, 6)))
    sd[1::2] = np.nan
    with pytest.raises(WorkLimitError, match="kernel terms"):
        ml_attitude_series(sd, LOS, BASELINES, 0.19, step_deg=3.0, window_deg=3.0)


def test_batches_within_the_limits_run() -> None:
    n = MAX_GEOMETRY_VALUES // 24
    assert sim.line_of_sight(GroundReceiver(35, 139, 50), gps_nominal(), np.zeros(2)).los.shape == (2, 24, 3)
    with pytest.raises(WorkLimitError):
        sim.line_of_sight(GroundReceiver(35, 139, 50), gps_nominal(), np.zeros(n + 1))
    geometry = sim.line_of_sight(GroundReceiver(35, 139, 50), gps_nominal(), 0.0)
    ants = np.zeros((MAX_SIMULATED_VALUES // 24 + 1, 3))
    with pytest.raises(WorkLimitError, match="antennas_body_m"):
        sim.simulate_array(geometry, Rotation.identity(), ants, gps_nominal().wavelengths_m())
    assert magnetic.igrf_field_ecef([[7e6, 0.0, 0.0]], 2021.0).shape == (1, 3)
    too_many = magnetic.MAX_IGRF_TERMS // magnetic.IGRF_COEFFICIENTS + 1
    with pytest.raises(WorkLimitError, match=f"{too_many} points"):
        magnetic.igrf_field_ecef(np.broadcast_to([7e6, 0.0, 0.0], (too_many, 3)), 2021.0)


# The whole-call row limits of the other batch entry points (one mechanism, gnssatt._arrays.batch_limit):
# name -> (call with a zero-stride view of BIG rows, parameter named, limit constant named)
def _view(row: object, n: int = BIG) -> np.ndarray:
    arr = np.asarray(row, dtype=float)
    return np.broadcast_to(arr, (n, *arr.shape))


_E = np.eye(3)
ROW_LIMITS: dict[str, tuple[Callable[[], object], str, str]] = {
    "wahba": (lambda: wahba(_view([1.0, 0.0, 0.0]), _view([1.0, 0.0, 0.0])), "body", "MAX_VECTOR_PAIRS"),
    "triad": (lambda: triad(_view(_E[0]), _E[1], _E[0], _E[1]), "b1", "MAX_BATCH_ROWS"),
    "yaw_from_magnetometer": (
        lambda: yaw_from_magnetometer(_view([20.0, -5.0, 40.0]), [20.0, -5.0, 40.0], 0.0, 0.0),
        "b_body",
        "MAX_YAW_EPOCHS",
    ),
    "matrix_attitude": (
        lambda: matrix_attitude(_view([1.0, 0.0, 0.0]), LOS, np.zeros((2, 6))),
        "baselines",
        "MAX_BASELINES",
    ),
    "ml_attitude los": (lambda: ml_attitude(SD[0], _view(LOS[0]), BASELINES, 0.19), "los", "MAX_SIGNALS"),
    "likelihood_grid phase_diffs": (
        lambda: likelihood_grid(_view(SD[0, 0]), LOS, BASELINES, 0.19),
        "phase_diffs",
        "MAX_BASELINES x MAX_SIGNALS",
    ),
    "ml_baseline": (lambda: ml_baseline(_view(0.1), LOS, 1.0, 0.19), "phase_diffs", "MAX_SIGNALS"),
    "propagate": (lambda: dynamics.propagate(np.zeros(6), _view(0.0)), "t", "MAX_PROPAGATE_TIMES"),
    "dipole_field_ecef": (
        lambda: magnetic.dipole_field_ecef(_view([7e6, 0.0, 0.0]), 2021.0),
        "position_ecef_m",
        "MAX_DIPOLE_POINTS",
    ),
    "dipole_orbital": (lambda: magnetic.dipole_orbital(_view(0.1), 7e6, 1.0), "u", "MAX_DIPOLE_POINTS"),
    "elevation_mask": (lambda: sim.elevation_mask(_view([0.0, 0.6, 0.8])), "los_ref", "MAX_BATCH_ROWS"),
    "elevation_azimuth": (lambda: sim.elevation_azimuth(_view([0.0, 0.6, 0.8])), "los_enu", "MAX_BATCH_ROWS"),
    "los_body": (lambda: sim.los_body(_view([0.0, 0.6, 0.8]), Rotation.identity()), "los", "MAX_BATCH_ROWS"),
    "solve_kepler": (lambda: sim.solve_kepler(_view(0.3), 0.1), "mean_anomaly_rad", "MAX_BATCH_ROWS"),
    "ecef_to_geodetic": (lambda: sim.ecef_to_geodetic(_view([7e6, 0.0, 0.0])), "r_ecef", "MAX_BATCH_ROWS"),
    "attitude_dop": (
        lambda: attitude_dop(np.eye(3), _view([0.0, 0.6, 0.8]), Rotation.identity()),
        "los",
        "MAX_SIGNALS",
    ),
}


@pytest.mark.parametrize("name", list(ROW_LIMITS))
def test_batches_over_a_row_limit_are_refused_from_the_shapes(name: str) -> None:
    call, parameter, constant = ROW_LIMITS[name]
    with traced_peak() as peak, pytest.raises(WorkLimitError, match=f"^{parameter} asks for") as info:
        call()
    assert constant in str(info.value) and "limit" in str(info.value), info.value
    assert peak.bytes < 8_000_000, peak.bytes


def test_the_row_limit_takes_the_limit_and_refuses_one_more() -> None:
    from gnssatt._arrays import MAX_BATCH_ROWS, batch_limit

    batch_limit(MAX_BATCH_ROWS, "MAX_BATCH_ROWS", "rows", x=(_view([1.0, 2.0, 3.0], MAX_BATCH_ROWS), 1))
    with pytest.raises(WorkLimitError, match=f"x asks for {MAX_BATCH_ROWS + 1} rows"):
        batch_limit(
            MAX_BATCH_ROWS, "MAX_BATCH_ROWS", "rows", x=(_view([1.0, 2.0, 3.0], MAX_BATCH_ROWS + 1), 1)
        )
    # the argument with the most items is the one named; a scalar counts one
    with pytest.raises(WorkLimitError, match=r"^b asks for 11 rows"):
        batch_limit(10, "C", "rows", a=(np.zeros((5, 3)), 1), b=(np.zeros(11), 0), c=(None, 0))
    # a batch at a function's own limit runs: the largest accepted wahba of two pairs an epoch
    n = MAX_VECTOR_PAIRS // 2
    assert n * 2 <= MAX_VECTOR_PAIRS
    with pytest.raises(WorkLimitError, match=f"body asks for {MAX_VECTOR_PAIRS + 2} vector pairs"):
        wahba(_view(_E[:2], n + 1), _view(_E[:2], n + 1))


def test_shape_mismatches_name_the_arguments_the_caller_passed() -> None:
    # matrix_attitude's range_diffs is (m, n) from baselines and los: a baselines or los of another size
    # is named itself, with the shape expected and the one that came (not only the derived range_diffs)
    with pytest.raises(
        InvalidInputError, match=r"baselines \(5, 3\) and los \(6, 3\), got range_diffs \(2, 6\)"
    ):
        matrix_attitude(np.tile(BASELINES, (3, 1))[:5], LOS, np.zeros((2, 6)))
    with pytest.raises(InvalidInputError, match=r"\(2, 7\) for baselines \(2, 3\) and los \(7, 3\)"):
        matrix_attitude(BASELINES, np.vstack([LOS, LOS[:1]]), np.zeros((2, 6)))
    # attitude_dop's degenerate Fisher information is a property of the arguments: they are named
    with pytest.raises(DegenerateGeometryError, match=r"baselines \(2, 3\) and los \(3, 3\) do not fix"):
        attitude_dop(
            [[1.0, 0.0, 0.0], [2.0, 0.0, 0.0]], np.tile([[1.0, 0.0, 0.0]], (3, 1)), Rotation.identity()
        )
