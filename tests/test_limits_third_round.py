"""Whole-call limits of the last unlimited public transforms (issue 31, third round): ``wrap_rad``,
``rotation_from_euler``, the troposphere and its mapping, ``right_jacobian``, ``phase_diffs``,
``correlator_amplitude``; the lines of sight of ``visibility_axis`` and the baselines of the attitude
scenario, which the batch-size sweep found scanned before their limits; and shapes refused before the copy
(``window_deg`` of 10^7 rows). Each is refused with a ``WorkLimitError`` (or a shape error) naming the
parameter, the amount and the limit, before the batch is copied: checked by counting the memory the call
allocates (tracemalloc), never by timing it.
"""

from __future__ import annotations

import functools
import re
from collections.abc import Callable
from typing import Any

import numpy as np
import pytest
from allocation import traced_peak

from gnssatt import likelihood_grid, ml_attitude, sim, visibility_axis
from gnssatt._arrays import MAX_BATCH_ROWS, MAX_BATCH_VALUES
from gnssatt.errors import InvalidInputError, WorkLimitError
from gnssatt.rotation import rotation_from_euler, wrap_rad
from gnssatt.sim.atmosphere import niell_mapping, troposphere_delay_m
from gnssatt.sim.attitude_scenario import orbital_hold_motion, right_jacobian
from gnssatt.sim.measurements import correlator_amplitude, phase_diffs

ROWS = MAX_BATCH_ROWS + 1
VALUES = MAX_BATCH_VALUES + 1


def _view(row: object, n: int) -> np.ndarray:
    arr = np.asarray(row, dtype=float)
    return np.broadcast_to(arr, (n, *arr.shape))


@functools.cache
def _valid(entry: str) -> dict[str, Any]:
    """The shared valid arguments of ``entry``, built once (outside the traced block)."""
    from valid_calls import CALLS

    return CALLS[entry].build()


def _with_rows(entry: str, parameter: str, row: object, n: int = 10_000_000) -> object:
    """The valid call of ``entry`` with ``parameter`` a zero-stride view of ``n`` rows."""
    from valid_calls import resolve

    return resolve(entry)(**{**_valid(entry), parameter: _view(row, n)})


# name -> (call one item above its limit, parameter named, amount in the message, limit constant named)
LIMITS: dict[str, tuple[Callable[[], object], str, str, str]] = {
    "wrap_rad": (lambda: wrap_rad(_view(1.0, VALUES)), "x", f"{VALUES} angles", "MAX_BATCH_VALUES"),
    "wrap_rad 2-d": (
        # the values of every dimension count: 2^24 + 1 rows of 2 angles
        lambda: wrap_rad(_view([1.0, 2.0], MAX_BATCH_VALUES // 2 + 1)),
        "x",
        f"{MAX_BATCH_VALUES + 2} angles",
        "MAX_BATCH_VALUES",
    ),
    "rotation_from_euler": (
        lambda: rotation_from_euler(_view([10.0, 5.0, 3.0], ROWS)),
        "euler_gost_deg",
        f"{ROWS} attitudes",
        "MAX_BATCH_ROWS",
    ),
    "niell_mapping": (
        lambda: niell_mapping(0.6, 100.0, _view(0.5, VALUES)),
        "elevation_rad",
        f"{VALUES} elevations",
        "MAX_BATCH_VALUES",
    ),
    "troposphere_delay_m": (
        lambda: troposphere_delay_m(0.6, 100.0, _view(0.5, VALUES)),
        "elevation_rad",
        f"{VALUES} elevations",
        "MAX_BATCH_VALUES",
    ),
    "right_jacobian": (
        lambda: right_jacobian(_view([0.1, -0.2, 0.3], ROWS)),
        "a",
        f"{ROWS} rotation vectors",
        "MAX_BATCH_ROWS",
    ),
    "orbital_hold_motion": (
        lambda: orbital_hold_motion(sim.OrbitalReceiver(7e6, 0.9, 0.3, 0.0), _view(0.0, ROWS)),
        "t",
        f"{ROWS} times",
        "MAX_BATCH_ROWS",
    ),
    "phase_diffs": (
        lambda: phase_diffs(_view([[0.1, 0.2], [0.3, 0.4]], VALUES // 4 + 1)),
        "phases",
        f"{4 * (VALUES // 4 + 1)} phases",
        "MAX_BATCH_VALUES",
    ),
    "phase_diffs complex": (
        lambda: phase_diffs(np.broadcast_to(np.complex128(1.0), (VALUES // 4 + 1, 2, 2))),
        "phases",
        f"{4 * (VALUES // 4 + 1)} phases",
        "MAX_BATCH_VALUES",
    ),
    "visibility_axis": (
        lambda: visibility_axis(_view([0.0, 0.0, 1.0], 10_000_000), [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]),
        "len(visible_los) + len(invisible_los)",
        "= 10000002",
        "limit of 2000",
    ),
    "attitude_fixes": (
        lambda: _with_rows("gnssatt.sim.attitude_scenario.attitude_fixes", "baselines_m", [1.0, 0.0, 0.0]),
        "baselines_m",
        "10000000 baselines",
        "MAX_BASELINES",
    ),
    "phase_observations": (
        lambda: _with_rows(
            "gnssatt.sim.attitude_scenario.phase_observations", "baselines_m", [1.0, 0.0, 0.0]
        ),
        "baselines_m",
        "10000000 baselines",
        "MAX_BASELINES",
    ),
    "correlator_amplitude": (
        lambda: correlator_amplitude(_view(45.0, VALUES), 1e-3),
        "cn0_dbhz",
        f"{VALUES} values",
        "MAX_BATCH_VALUES",
    ),
}


@pytest.mark.parametrize("name", list(LIMITS))
def test_one_item_over_the_limit_is_refused_before_the_batch_is_copied(name: str) -> None:
    call, parameter, amount, constant = LIMITS[name]
    if name in ("attitude_fixes", "phase_observations"):
        _valid(f"gnssatt.sim.attitude_scenario.{name}")  # the simulated valid arguments, before tracing
    with traced_peak() as peak, pytest.raises(WorkLimitError, match=re.escape(parameter)) as info:
        call()
    message = str(info.value)
    assert message.startswith(parameter + " "), message
    assert amount in message and constant in message, message
    # the batch as float64 is 50-270 MB; a refusal made from its shape allocates nothing of its size
    assert peak.bytes < 1_000_000, peak


def test_the_limits_leave_batches_at_the_limit_alone() -> None:
    # at the limit exactly (small arrays stand for the big ones: the count is of the shape, checked above)
    assert wrap_rad(np.full((4, 3), 7.0)).shape == (4, 3)
    np.testing.assert_allclose(wrap_rad([3 * np.pi]), [-np.pi], atol=1e-12)
    assert rotation_from_euler(np.zeros((5, 3))).as_matrix().shape == (5, 3, 3)
    # right_jacobian of a zero rotation vector is the identity (the series' first term)
    np.testing.assert_allclose(right_jacobian(np.zeros((2, 4, 3))), np.broadcast_to(np.eye(3), (2, 4, 3, 3)))
    assert phase_diffs(np.zeros((3, 2, 5))).shape == (3, 1, 5)
    np.testing.assert_allclose(correlator_amplitude([50.0], 1e-3), [np.sqrt(200.0)])


def test_a_wrong_shape_of_many_rows_is_refused_before_the_copy() -> None:
    # window_deg of ml_attitude / likelihood_grid is (3, 2); 10^7 rows of it were copied and scanned (7 s)
    # before the shape was looked at
    los = sim.random_los(1, 6, min_elevation_deg=15.0)
    baselines = sim.equilateral_triangle(1.0, plane="xz")[1:]
    sd = np.zeros((2, 6))
    for fn in (ml_attitude, likelihood_grid):
        with traced_peak() as peak, pytest.raises(InvalidInputError, match=r"window_deg of shape") as info:
            fn(sd, los, baselines, 0.19, step_deg=5.0, window_deg=_view([-10.0, 10.0], 10_000_000))
        assert "(10000000, 2)" in str(info.value)
        assert peak.bytes < 1_000_000, peak


def test_the_shape_checked_before_the_copy_is_the_converted_one() -> None:
    # a 0-d value converts to shape (1,), as before the shape moved ahead of the copy: a scalar time stays
    # a one-element series
    from gnssatt._arrays import float_array, shaped

    assert float_array("t", 2.0, ndim=1, shape="(n_t,)").shape == (1,)
    assert shaped("t", np.float64(2.0), "(n,)", (None,)).shape == (1,)
    with pytest.raises(InvalidInputError, match=r"expected los of shape \(n, 3\), got \(1,\)"):
        shaped("los", 2.0, "(n, 3)", (None, 3))
