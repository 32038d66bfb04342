"""The shared intake on the forms of input the first hostile sweep did not try (issue 15 follow-up):
``numpy.ma`` masked arrays, Python integers beyond float range, read-only arrays, zero-stride views of
absurd size and 0-d integer seeds. Each case failed before the fix named in its docstring."""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
import pytest
from allocation import traced_peak
from scipy.spatial.transform import Rotation

from gnssatt import _arrays, constants, montecarlo, sim
from gnssatt.errors import ConvergenceError, InvalidInputError, InvalidTypeError, WorkLimitError
from gnssatt.geometry import attitude_dop
from gnssatt.orbit import teme_to_ecef

BASELINES = np.array([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]])
LOS = np.array([[0.0, 0.0, 1.0], [0.6, 0.0, 0.8], [0.0, 0.6, 0.8], [-0.6, 0.0, 0.8]])


def test_masked_value_is_refused_not_used() -> None:
    """np.asarray dropped the mask, so the value under it (here 1e6 m) was silently used."""
    side = np.ma.masked_array([1.0, 1e6], mask=[False, True])
    with pytest.raises(InvalidInputError, match=r"x without masked values.*index \(1,\)"):
        _arrays.float_array("x", side, ndim=1, shape="(n,)")
    with pytest.raises(InvalidInputError, match="side_m without masked values"):
        sim.equilateral_triangle(np.ma.masked)


def test_masked_array_without_masked_values_is_its_data() -> None:
    data = np.array([[1.0, 2.0], [3.0, 4.0]])
    out = _arrays.float_array("x", np.ma.masked_array(data), ndim=2, shape="(n, 2)")
    assert type(out) is np.ndarray
    np.testing.assert_array_equal(out, data)


def test_masked_values_are_nan_where_nan_is_documented() -> None:
    out = _arrays.real_array("x", np.ma.masked_array([1.0, 2.0, 3.0], mask=[False, True, False]))
    assert type(out) is np.ndarray
    np.testing.assert_array_equal(out, [1.0, np.nan, 3.0])


@pytest.mark.parametrize("big", [10**400, -(10**400)])
def test_integer_beyond_float_range_is_refused_by_name(big: int) -> None:
    """float(10**400) raised OverflowError, which is not an input error."""
    with pytest.raises(InvalidInputError, match="finite side_m, got an integer of 401 digits"):
        sim.equilateral_triangle(big)


def test_read_only_array_is_accepted() -> None:
    """scipy's Rotation.apply refuses read-only buffers: attitude_dop raised a bare ValueError."""
    b = BASELINES.copy()
    b.flags.writeable = False
    expected = attitude_dop(BASELINES, LOS, Rotation.identity())
    assert attitude_dop(b, LOS, Rotation.identity()) == expected
    assert not b.flags.writeable  # the caller's array is left as it was


def test_zero_stride_view_of_absurd_size_is_refused_before_copying() -> None:
    """The intake copied first: numpy raised MemoryError for the 24 TiB copy."""
    huge = np.broadcast_to(np.array([0.0, 0.0, 1.0]), (2**40, 3))
    with traced_peak() as peak:
        with pytest.raises(WorkLimitError, match=rf"los has {2**40 * 3} elements.*limit of {2**28}"):
            attitude_dop(BASELINES, huge, Rotation.identity())
        with pytest.raises(WorkLimitError, match="x has"):
            _arrays.real_array("x", huge)
    assert peak.bytes < 1_000_000, peak  # nothing of the view's size was copied


def test_zero_d_integer_array_is_a_seed() -> None:
    a = sim.random_los(np.array(5), 4)
    b = sim.random_los(5, 4)
    np.testing.assert_array_equal(a, b)


BIG = float(np.finfo(np.float64).max)


@pytest.mark.parametrize(
    "call",
    [
        pytest.param(lambda: sim.eci_to_ecef([BIG, BIG, 0.0], [0.0, 0.0, 0.0], 10.0), id="eci_to_ecef"),
        pytest.param(lambda: sim.ecef_to_eci([BIG, BIG, 0.0], [0.0, 0.0, 0.0], 10.0), id="ecef_to_eci"),
        pytest.param(lambda: teme_to_ecef([BIG, BIG, 0.0], [0.0, 0.0, 0.0], 2460000.5), id="teme_to_ecef"),
        pytest.param(
            lambda: sim.los_body([[BIG, BIG, 0.0]], Rotation.from_euler("z", 45.0, degrees=True)),
            id="los_body",
        ),
        pytest.param(lambda: sim.equilateral_triangle(BIG), id="equilateral_triangle"),
    ],
)
def test_finite_input_whose_rotation_overflows_raises_not_inf(call: Callable[[], object]) -> None:
    """A rotation of (1.8e308, 1.8e308, 0) by an angle between the axes has a component beyond the float
    limit (sqrt(2) 1.8e308 at 45 deg); the functions returned inf."""
    with pytest.raises(ConvergenceError, match="not finite"):
        call()


class _NoFutureExecutor:
    def submit(self, fn: object, *args: object) -> None:
        return None


class _Down(RuntimeError):
    pass


class _RaisingExecutor:
    def submit(self, fn: object, *args: object) -> None:
        raise _Down("cluster went away")


def _trial(rng: np.random.Generator) -> float:
    return float(rng.normal())


def test_executor_whose_submit_returns_no_future_is_refused_by_name() -> None:
    """as_completed failed with AttributeError: 'NoneType' object has no attribute '_condition'."""
    with pytest.raises(InvalidTypeError, match=r"executor\.submit to return a concurrent\.futures\.Future"):
        montecarlo.run(_trial, 3, seed=1, executor=_NoFutureExecutor(), progress=False)


def test_executor_error_comes_out_unchanged() -> None:
    with pytest.raises(_Down, match="cluster went away"):
        montecarlo.run(_trial, 3, seed=1, executor=_RaisingExecutor(), progress=False)


def test_glonass_channels_share_the_intake_limits() -> None:
    """constants cannot import gnssatt._arrays (same layer): its copy of the limit must agree."""
    assert constants._MAX_ELEMENTS == _arrays.MAX_ELEMENTS
    with pytest.raises(WorkLimitError, match="k has"):
        constants.glonass_frequency_hz(np.broadcast_to(np.array([1]), (2**40,)))
    with pytest.raises(InvalidInputError, match="k without masked values"):
        constants.glonass_wavelength_m(np.ma.masked_array([1, 99], mask=[False, True]))


def test_nan_gaps_intake_checks_size_and_masks() -> None:
    """ml_attitude_series ran np.isnan over a 2^40-row view (MemoryError) before the intake's size check;
    a masked phase is a gap like NaN."""
    from gnssatt.attitude.likelihood._intake import gapped as _gaps

    with pytest.raises(WorkLimitError, match="sd_phase has"):
        _gaps("sd_phase", np.broadcast_to(np.zeros((1, 2, 3)), (2**40, 2, 3)), ndim=3, shape="(n, 2, 3)")
    values, gaps = _gaps(
        "sd_phase", np.ma.masked_array([[0.5, 7.0]], mask=[[False, True]]), ndim=2, shape="(n, 2)"
    )
    np.testing.assert_array_equal(values, [[0.5, 0.0]])
    np.testing.assert_array_equal(gaps, [[False, True]])


@pytest.mark.parametrize(
    ("bad", "what"),
    [("a\x00b.24o", "without NUL characters"), ("x" * 5000, "at most 4095 bytes"), ("d/" + "y" * 300, "255")],
)
def test_path_that_the_os_cannot_open_is_refused_by_name(bad: str, what: str) -> None:
    """open() raised ValueError (embedded null byte) or OSError (File name too long)."""
    with pytest.raises(InvalidInputError, match=f"path .*{what}"):
        _arrays.path_text(bad)
    with pytest.raises(InvalidInputError, match=f"folder .*{what}"):
        _arrays.folder_path("folder", bad)


def test_masked_count_is_refused() -> None:
    """operator.index took the value under the mask: random_attitude drew 3 rotations."""
    with pytest.raises(InvalidInputError, match="n without masked values"):
        sim.random_attitude(1, np.ma.masked_array(3, mask=True))
    assert len(sim.random_attitude(1, np.ma.masked_array(3))) == 3


def test_step_coarser_than_the_lobe_names_what_sets_the_lobe() -> None:
    """The core's message named step_deg only, although baseline_length_m or wavelength set the bound."""
    from gnssatt import ml_baseline

    los = np.array([[0.0, 0.0, 1.0], [0.6, 0.0, 0.8], [0.0, 0.6, 0.8], [-0.6, 0.0, 0.8]])
    with pytest.raises(InvalidInputError, match="main lobe") as info:
        ml_baseline(np.zeros(4), los, baseline_length_m=1e4, wavelength=0.19, step_deg=2.0)
    assert "baseline_length_m" in str(info.value) and "wavelength" in str(info.value)


def test_masked_seed_is_refused() -> None:
    """The 0-d seed's .item() read the value under the mask."""
    with pytest.raises(InvalidInputError, match="rng without masked values"):
        sim.random_attitude(np.ma.masked_array(np.int64(3), mask=True), 2)


def test_degenerate_pairs_name_the_arguments() -> None:
    """Range differences that no rotation of the baselines makes can leave the attitude profile matrix of
    rank one; the core's message spoke of "vector pairs" without naming an argument."""
    from gnssatt import DegenerateGeometryError, matrix_attitude

    b = np.array([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])
    # every row of range_diffs the same multiple of one vector: B = sum_ij r_ij b_i s_j^T has rank one
    r = np.outer([1.0, 0.0], [1.0, 1.0, 1.0, 1.0])
    with pytest.raises(DegenerateGeometryError) as info:
        matrix_attitude(b, LOS, r, method="svd")
    assert "range_diffs" in str(info.value)
