"""Bad input to every public function of the estimators (issue 15, part C): each argument, each category of
bad value, gets an :class:`~gnssatt.errors.InvalidInputError` (a :class:`~gnssatt.errors.InvalidTypeError`
for values of the wrong kind) whose message names the parameter, before any work starts; finite input never
gives a NaN.

The table ``FUNCTIONS`` lists, per public function, a valid call (checked to run) and the arguments with
their kind; ``bad_values`` derives the categories from the valid value (wrong shape, complex, boolean, object,
text, ``None``, NaN, infinity, out of range, absurd sizes), so that a function or argument added to the table
is covered in every category. ``EXTRA`` covers the fields of measurement containers. The NaN section scales
every argument by 1e-300 to 1e300 (finite output or a gnssatt error, never ``InternalError``), checks scale
invariance against the unscaled answer and the gyro step against its closed form; a derandomized hypothesis
test throws random hostile values (dtypes, shapes, NaN, huge, ragged, objects) at every argument.
"""

from __future__ import annotations

import dataclasses
import functools
import warnings
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from functools import cache
from typing import Any

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp
from numpy.typing import NDArray
from scipy.spatial.transform import Rotation
from valid_calls import CALLS, OTHER_CALLS, Arg, Call
from valid_calls.estimators import BASELINES, L1, LOS, TRUTH, WINDOW
from valid_calls.other_estimators import gyro_filter_call, observations

from gnssatt import geometry, rotation
from gnssatt.attitude import (
    gyro_gnss,
    likelihood,
    magnetometer,
    matrix_method,
    phase_attitude,
    visibility,
)
from gnssatt.attitude import (
    wahba as vector_attitude,
)
from gnssatt.errors import (
    GnssattError,
    InternalError,
    InvalidInputError,
    InvalidTypeError,
    NearDegenerateWarning,
    WorkLimitError,
)
from gnssatt.sim import attitude_scenario as sc


@dataclass(frozen=True)
class Function:
    """One public function (or class) of the table, under the name its test IDs use, with its valid call."""

    name: str
    call: Callable[..., Any]
    spec: Call

    def valid(self) -> dict[str, Any]:
        return self.spec.build()

    @property
    def args(self) -> dict[str, Arg]:
        """The arguments of the intake cases (those with a ``kind``)."""
        return {n: a for n, a in self.spec.args.items() if a.kind}


def _replace(value: Any, bad: float) -> Any:
    a = np.array(value, dtype=np.float64)
    a.flat[0] = bad
    return a


def bad_values(arg: Arg, value: Any) -> Iterator[tuple[str, Any, type[Exception]]]:
    """(category, replacement, expected class) for one argument whose valid value is ``value``."""
    if arg.kind in ("array", "scalar"):
        yield "complex", np.asarray(value, dtype=np.complex128) + 1j, InvalidTypeError
        yield "bool", np.ones(np.shape(value), dtype=bool), InvalidTypeError
        yield "object", np.array(value, dtype=object) if np.ndim(value) else object(), InvalidTypeError
        yield "text", "1.0", InvalidTypeError
        if not arg.optional:
            yield "none", None, InvalidTypeError
        yield "nan", _replace(value, np.nan) if arg.kind == "array" else float("nan"), InvalidInputError
        yield "inf", _replace(value, np.inf) if arg.kind == "array" else float("inf"), InvalidInputError
        yield "-inf", _replace(value, -np.inf) if arg.kind == "array" else float("-inf"), InvalidInputError
    elif arg.kind == "integer":
        yield "float", 2.0, InvalidTypeError
        yield "text", "2", InvalidTypeError
        yield "bool", True, InvalidTypeError
        if not arg.optional:
            yield "none", None, InvalidTypeError
        if arg.limited:
            yield "absurd", 10**18, WorkLimitError
    elif arg.kind == "choice":
        yield "unknown", "no-such-option", InvalidInputError
        yield "number", 1.0, InvalidTypeError
        if not arg.optional:
            yield "none", None, InvalidTypeError
    elif arg.kind == "flag":
        yield "number", 1.0, InvalidTypeError
        yield "text", "yes", InvalidTypeError
        yield "none", None, InvalidTypeError
    elif arg.kind == "object":
        yield "number", 1.0, InvalidTypeError
        yield "array", np.zeros(3), InvalidTypeError
        if not arg.optional:
            yield "none", None, InvalidTypeError
    for k, v in enumerate(arg.shapes):
        yield f"shape{k}", v, InvalidInputError
    for k, v in enumerate(arg.out_of_range):
        yield f"range{k}", v, InvalidInputError


# --- the table (valid calls and arguments: ``valid_calls``) ----------------------------------------

FUNCTIONS: tuple[Function, ...] = (
    Function("rotation.euler_to_dcm", rotation.euler_to_dcm, CALLS["gnssatt.rotation.euler_to_dcm"]),
    Function("rotation.dcm_to_euler", rotation.dcm_to_euler, CALLS["gnssatt.rotation.dcm_to_euler"]),
    Function("rotation.quat_to_dcm", rotation.quat_to_dcm, CALLS["gnssatt.rotation.quat_to_dcm"]),
    Function("rotation.dcm_to_quat", rotation.dcm_to_quat, CALLS["gnssatt.rotation.dcm_to_quat"]),
    Function(
        "rotation.nearest_rotation", rotation.nearest_rotation, CALLS["gnssatt.rotation.nearest_rotation"]
    ),
    Function(
        "matrix_method.matrix_attitude", matrix_method.matrix_attitude, CALLS["gnssatt.matrix_attitude"]
    ),
    Function("vector_attitude.triad", vector_attitude.triad, CALLS["gnssatt.triad"]),
    Function("vector_attitude.wahba", vector_attitude.wahba, OTHER_CALLS["vector_attitude.wahba"]),
    Function(
        "magnetometer.yaw_from_magnetometer",
        magnetometer.yaw_from_magnetometer,
        CALLS["gnssatt.yaw_from_magnetometer"],
    ),
    Function(
        "geometry.range_difference_fisher",
        geometry.range_difference_fisher,
        CALLS["gnssatt.geometry.range_difference_fisher"],
    ),
    Function("geometry.attitude_dop", geometry.attitude_dop, CALLS["gnssatt.geometry.attitude_dop"]),
    Function(
        "rotation.rotation_from_euler",
        rotation.rotation_from_euler,
        CALLS["gnssatt.rotation.rotation_from_euler"],
    ),
    Function(
        "rotation.euler_from_rotation",
        rotation.euler_from_rotation,
        CALLS["gnssatt.rotation.euler_from_rotation"],
    ),
    Function("likelihood.AttitudePrior", likelihood.AttitudePrior, OTHER_CALLS["likelihood.AttitudePrior"]),
    Function(
        "likelihood.prior_from_velocity", likelihood.prior_from_velocity, CALLS["gnssatt.prior_from_velocity"]
    ),
    Function("likelihood.ml_attitude", likelihood.ml_attitude, CALLS["gnssatt.ml_attitude"]),
    Function("likelihood.likelihood_grid", likelihood.likelihood_grid, CALLS["gnssatt.likelihood_grid"]),
    Function("likelihood.ml_baseline", likelihood.ml_baseline, CALLS["gnssatt.ml_baseline"]),
    Function("gyro_gnss.gyro_propagate", gyro_gnss.gyro_propagate, CALLS["gnssatt.gyro_propagate"]),
    Function(
        "gyro_gnss.gyro_gnss_filter", gyro_gnss.gyro_gnss_filter, OTHER_CALLS["gyro_gnss.gyro_gnss_filter"]
    ),
    Function(
        "phase_attitude.phase_attitude_fixes",
        phase_attitude.phase_attitude_fixes,
        OTHER_CALLS["phase_attitude.phase_attitude_fixes"],
    ),
    Function("visibility.visibility_axis", visibility.visibility_axis, CALLS["gnssatt.visibility_axis"]),
    Function(
        "visibility.visibility_sets",
        visibility.visibility_sets,
        CALLS["gnssatt.attitude.visibility.visibility_sets"],
    ),
)


def _cases() -> Iterator[Any]:
    for f in FUNCTIONS:
        valid = f.valid()
        for name, arg in f.args.items():
            for category, bad, error in bad_values(arg, valid.get(name)):
                yield pytest.param(f, name, arg, bad, error, id=f"{f.name}-{name}-{category}")


@pytest.mark.parametrize("f", FUNCTIONS, ids=lambda f: f.name)
def test_the_valid_call_runs(f: Function) -> None:
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        f.call(**f.valid())


@pytest.mark.parametrize(("f", "name", "arg", "bad", "error"), list(_cases()))
def test_bad_argument_is_refused_naming_it(
    f: Function, name: str, arg: Arg, bad: Any, error: type[Exception]
) -> None:
    kwargs = f.valid()
    kwargs[name] = bad
    with pytest.raises(error) as info:
        f.call(**kwargs)
    assert (arg.label or name) in str(info.value)


# --- arguments inside containers, and combinations the table cannot express ---------------------------------


# The containers check their own fields when built (gnssatt.sim), and the estimators check them again where
# they use them: a bad field is built lazily, inside the test's pytest.raises, so either refusal counts.
def _obs(**fields: Any) -> Callable[[], sc.PhaseObservations]:
    return functools.partial(dataclasses.replace, observations(), **fields)


def _fixes(**fields: Any) -> Callable[[], sc.AttitudeFixes]:
    valid = {
        "t": np.array([5.0]),
        "rotation": Rotation.concatenate([TRUTH]),
        "covariance": 1e-6 * np.eye(3)[None],
    }
    return functools.partial(sc.AttitudeFixes, **(valid | fields))


@cache
def _result() -> gyro_gnss.GyroGnssResult:
    return gyro_gnss.gyro_gnss_filter(**gyro_filter_call())


OBS = observations()
EXTRA = [
    # (id, call, kwargs, expected class, name the message must hold)
    (
        "filter-sensitivity-negative",
        gyro_gnss.gyro_gnss_filter,
        {"sensitivity": (-1.0, 0.0)},
        InvalidInputError,
    ),
    ("filter-sensitivity-text", gyro_gnss.gyro_gnss_filter, {"sensitivity": "ab"}, InvalidTypeError),
    (
        "filter-sensitivity-shape",
        gyro_gnss.gyro_gnss_filter,
        {"sensitivity": (1.0, 2.0, 3.0)},
        InvalidInputError,
    ),
    (
        "filter-phases.epoch",
        gyro_gnss.gyro_gnss_filter,
        {"phases": _obs(epoch=OBS.epoch + 10)},
        InvalidInputError,
    ),
    (
        "filter-phases.epoch-float",
        gyro_gnss.gyro_gnss_filter,
        {"phases": _obs(epoch=OBS.epoch + 0.5)},
        InvalidInputError,
    ),
    (
        "filter-phases.track-text",
        gyro_gnss.gyro_gnss_filter,
        {"phases": _obs(track=["a"] * 15)},
        InvalidTypeError,
    ),
    ("filter-phases.los", gyro_gnss.gyro_gnss_filter, {"phases": _obs(los=OBS.los + 0j)}, InvalidTypeError),
    (
        "filter-phases.wavelength",
        gyro_gnss.gyro_gnss_filter,
        {"phases": _obs(wavelength=OBS.wavelength[:3])},
        InvalidInputError,
    ),
    (
        "filter-phases.phase",
        gyro_gnss.gyro_gnss_filter,
        {"phases": _obs(phase=OBS.phase * np.nan)},
        InvalidInputError,
    ),
    (
        "filter-attitude_fixes.t",
        gyro_gnss.gyro_gnss_filter,
        {"attitude_fixes": _fixes(t=np.array([np.nan]))},
        InvalidInputError,
    ),
    (
        "filter-attitude_fixes.rotation",
        gyro_gnss.gyro_gnss_filter,
        {"attitude_fixes": _fixes(rotation=np.eye(3))},
        InvalidTypeError,
    ),
    (
        "filter-attitude_fixes.covariance",
        gyro_gnss.gyro_gnss_filter,
        {"attitude_fixes": _fixes(covariance=np.eye(2)[None])},
        InvalidInputError,
    ),
    (
        "fixes-phases.epoch",
        phase_attitude.phase_attitude_fixes,
        {"phases": _obs(epoch=OBS.epoch - 1)},
        InvalidInputError,
    ),
    (
        "fixes-phases.los",
        phase_attitude.phase_attitude_fixes,
        {"phases": _obs(los=OBS.los * 2)},
        InvalidInputError,
    ),
    (
        "fixes-phases.wavelength",
        phase_attitude.phase_attitude_fixes,
        {"phases": _obs(wavelength=-OBS.wavelength)},
        InvalidInputError,
    ),
    (
        "fixes-phases.phase",
        phase_attitude.phase_attitude_fixes,
        {"phases": _obs(phase=OBS.phase + 1e300)},
        InvalidInputError,
    ),
    (
        "fixes-phases.epoch_t",
        phase_attitude.phase_attitude_fixes,
        {"phases": _obs(epoch_t=None)},
        InvalidTypeError,
    ),
]


def _extra_valid(call: Callable[..., Any]) -> dict[str, Any]:
    return next(f for f in FUNCTIONS if f.call is call).valid()


@pytest.mark.parametrize(
    ("call", "kwargs", "error", "name"),
    [pytest.param(c, kw, e, i.split("-")[1], id=i) for i, c, kw, e in EXTRA],
)
def test_bad_container_field_is_refused_naming_it(
    call: Callable[..., Any], kwargs: dict[str, Any], error: type[Exception], name: str
) -> None:
    with pytest.raises(error) as info:
        built = {k: v() if isinstance(v, functools.partial) else v for k, v in kwargs.items()}
        call(**(_extra_valid(call) | built))
    # named as the estimator sees it ("phases.epoch") or as the container's own check does ("epoch")
    assert name in str(info.value) or name.split(".")[-1] in str(info.value)


@pytest.mark.parametrize(
    ("method", "args", "error", "name"),
    [
        ("errors", (1.0, np.zeros(3)), InvalidTypeError, "true_rotation"),
        ("errors", (TRUTH, np.zeros((2, 3))), InvalidInputError, "true_drift"),
        ("errors", (TRUTH, np.zeros(3) + 1j), InvalidTypeError, "true_drift"),
        ("nees", (np.zeros((21, 5)),), InvalidInputError, "errors"),
        ("nees", (np.full((21, 6), np.nan),), InvalidInputError, "errors"),
    ],
)
def test_result_methods_check_their_arguments(
    method: str, args: tuple, error: type[Exception], name: str
) -> None:
    with pytest.raises(error, match=name):
        getattr(_result(), method)(*args)


# --- no NaN from finite input ------------------------------------------------------------------------------


def _leaves(x: Any) -> Iterator[NDArray[np.float64]]:
    """Every number in a result: arrays, floats, the quaternions of rotations, fields of dataclasses."""
    if isinstance(x, Rotation):
        yield x.as_quat()
    elif dataclasses.is_dataclass(x):
        for f in dataclasses.fields(x):
            yield from _leaves(getattr(x, f.name))
    elif isinstance(x, list | tuple):
        for v in x:
            yield from _leaves(v)
    elif isinstance(x, np.ndarray | float | int):
        yield np.asarray(x, dtype=np.float64)


SCALES = (1e-300, 1e-160, 1e-20, 1e20, 1e160, 1e300, -1e300)


def _scaled_cases() -> Iterator[Any]:
    for f in FUNCTIONS:
        valid = f.valid()
        for name, arg in f.args.items():
            if arg.kind in ("array", "scalar") and valid.get(name) is not None:
                for s in SCALES:
                    yield pytest.param(f, name, s, id=f"{f.name}-{name}-{s:g}")


@pytest.mark.slow
@pytest.mark.parametrize(("f", "name", "scale"), list(_scaled_cases()))
def test_finite_input_of_any_magnitude_gives_finite_output_or_an_error(
    f: Function, name: str, scale: float
) -> None:
    # Each argument multiplied by a factor from 1e-300 to 1e300: the call either refuses with a gnssatt
    # error (never a defect: InternalError) or returns finite numbers only.
    kwargs = f.valid()
    kwargs[name] = np.asarray(kwargs[name], dtype=np.float64) * scale
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", NearDegenerateWarning)
        try:
            result = f.call(**kwargs)
        except InternalError:
            raise
        except GnssattError:
            return
    assert all(np.all(np.isfinite(v)) for v in _leaves(result))


@pytest.mark.parametrize("scale", [1e-160, 1e-100, 1e100, 1e160, 1e300])
def test_vector_attitude_does_not_depend_on_the_scale_of_the_vectors(scale: float) -> None:
    # Directions are what TRIAD, Wahba and eq. (3) use: vectors of 1e160 (whose squared norms overflow)
    # were reported parallel, 1e-160 zero; now they give the attitude of the unscaled vectors.
    b, r = TRUTH.inv().apply(LOS), LOS
    tri = vector_attitude.triad(b[0] * scale, b[1] * scale, r[0] * scale, r[1] * scale)
    assert tri.rotation.approx_equal(TRUTH, atol=1e-12)
    wah = vector_attitude.wahba(b * scale, r * scale)
    assert wah.rotation.approx_equal(TRUTH, atol=1e-12)
    args = ([2e-5, 1e-5, 3e-5], [1e-5, 2e-5, -3e-5], 0.1, -0.2)
    yaw = magnetometer.yaw_from_magnetometer(*args).yaw_rad
    scaled = magnetometer.yaw_from_magnetometer(
        np.multiply(args[0], scale), np.multiply(args[1], scale), *args[2:]
    )
    assert scaled.yaw_rad == pytest.approx(yaw, abs=1e-12)


@pytest.mark.parametrize("scale", [1e-250, 1e-100, 1e100, 1e250])
def test_wahba_weights_of_any_scale_give_the_rotation_and_scale_the_covariance(scale: float) -> None:
    # Only ratios of weights fix the rotation; P = [sum w (I - r r^T)]^-1 scales like 1/w and the loss like w.
    b, r, w = TRUTH.inv().apply(LOS), LOS, np.array([1.0, 2.0, 3.0, 4.0, 5.0])
    ref = vector_attitude.wahba(b, r, w)
    got = vector_attitude.wahba(b, r, w * scale)
    assert got.rotation.approx_equal(ref.rotation, atol=1e-12)
    np.testing.assert_allclose(got.covariance * scale, ref.covariance, rtol=1e-12)
    assert got.information_ratio == pytest.approx(ref.information_ratio, rel=1e-12)


def test_nearest_rotation_of_a_huge_matrix_is_that_of_the_matrix() -> None:
    m = TRUTH.as_matrix() + 0.01
    ref = rotation.nearest_rotation(m)
    for scale in (1e-300, 1e160, 1e300):
        np.testing.assert_allclose(rotation.nearest_rotation(m * scale), ref, atol=1e-14)


def test_gyro_propagation_is_exact_up_to_the_step_angle_limit_and_refuses_beyond() -> None:
    # constant rate about z: q(t) = [0, 0, sin(w t / 2), cos(w t / 2)]; one step of 1e5 rad, rounding 1e-11
    t = np.array([0.0, 1e3])
    q = gyro_gnss.gyro_propagate([0.0, 0.0, 0.0, 1.0], t, [[0.0, 0.0, 100.0]] * 2).quaternions
    angle = 100.0 * 1e3
    expected = np.array([0.0, 0.0, np.sin(angle / 2), np.cos(angle / 2)]) * np.sign(np.cos(angle / 2))
    np.testing.assert_allclose(q[1], expected, atol=1e-9)
    with pytest.raises(InvalidInputError, match=r"rates times the interval of t .* at most 1e\+06 rad"):
        gyro_gnss.gyro_propagate([0.0, 0.0, 0.0, 1.0], t, [[0.0, 0.0, 1e4]] * 2)


def test_prior_from_velocity_refuses_a_non_finite_or_non_positive_gravity() -> None:
    for g in (np.nan, np.inf, 0.0, -9.8):
        with pytest.raises(InvalidInputError, match="gravity"):
            likelihood.prior_from_velocity([100.0, 200.0, 5.0], [1.0, -2.0, 0.0], gravity=g)
    # an absurd but finite acceleration still has a bank angle: 90 deg, not NaN
    prior = likelihood.prior_from_velocity([0.0, 100.0, 0.0], [1e308, 0.0, 0.0])
    assert prior.euler_gost_deg[2] == pytest.approx(90.0)


def _phases() -> dict[str, Any]:
    """Phase differences (m, M) of the Bunyaeva et al. model for BASELINES[:2] at TRUTH-like angles,
    radians."""
    r = rotation.rotation_from_euler([20.0, 5.0, -3.0])
    p = -2 * np.pi / L1 * (r.apply(BASELINES[:2]) @ LOS.T)
    return {"phase_diffs": np.mod(p, 2 * np.pi), "los": LOS, "baselines": BASELINES[:2], "wavelength": L1}


def test_a_single_node_grid_reports_its_step() -> None:
    # 360 / n with n = 2 ceil(180 / step): 3.7 deg -> n = 98 -> 3.6734... deg, as the axis spacing of a wider
    # window shows
    kw = _phases()
    wide = likelihood.likelihood_grid(**kw, step_deg=3.7, window_deg=WINDOW)
    node = wide.psi_deg[3], wide.theta_deg[3], wide.phi_deg[3]
    single = likelihood.likelihood_grid(**kw, step_deg=3.7, window_deg=[[v, v] for v in node])
    assert single.z.shape == (1, 1, 1)
    assert single.step_deg == pytest.approx(360.0 / 98)
    assert wide.step_deg == pytest.approx(360.0 / 98)


def test_phases_shifted_by_whole_cycles_give_the_same_attitude_until_the_limit() -> None:
    kw = {**_phases(), "window_deg": WINDOW, "step_deg": 2.0}
    ref = likelihood.ml_attitude(**kw).euler_gost_deg
    shifted_kw = {**kw, "phase_diffs": kw["phase_diffs"] + 2 * np.pi * 1e8}
    shifted = likelihood.ml_attitude(**shifted_kw).euler_gost_deg
    np.testing.assert_allclose(shifted, ref, atol=1e-6)
    with pytest.raises(InvalidInputError, match="phase_diffs at most 1e\\+12 rad"):
        likelihood.ml_attitude(**{**kw, "phase_diffs": kw["phase_diffs"] + 1e20})


def test_visibility_axis_refuses_more_lines_of_sight_than_its_limit_before_any_work() -> None:
    many = np.tile(LOS[:3], (visibility.MAX_SATELLITES // 3 + 1, 1))
    with pytest.raises(
        WorkLimitError, match=r"visible_los\) \+ len\(invisible_los\) = 2003 exceeds the limit of 2000"
    ):
        visibility.visibility_axis(many, -LOS[3:], method="centroid")


def test_attitude_dop_is_finite_or_refused() -> None:
    # baselines at the 1e-6 m limit: a DOP of order 1e6, finite; below it, refused before any work
    dop = geometry.attitude_dop(BASELINES * 1e-6, LOS, TRUTH)
    assert np.isfinite(dop) and dop == pytest.approx(geometry.attitude_dop(BASELINES, LOS, TRUTH) * 1e6)
    with pytest.raises(InvalidInputError, match="baselines"):
        geometry.attitude_dop(BASELINES * 1e-160, LOS, TRUTH)


# --- random hostile values (hypothesis) --------------------------------------------------------------------

HOSTILE_FLOATS = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True),
    st.sampled_from([0.0, -0.0, 1e-320, 1e-160, 1e160, 1e308, -1e308]),
)
HOSTILE_ARRAYS = st.one_of(
    hnp.arrays(
        st.sampled_from([np.float64, np.float32, np.int64, np.uint8, np.complex128, np.bool_]),
        hnp.array_shapes(min_dims=0, max_dims=3, min_side=0, max_side=4),
        elements=None,
    ),
    hnp.arrays(np.float64, hnp.array_shapes(min_dims=1, max_dims=3, max_side=6), elements=HOSTILE_FLOATS),
    st.sampled_from([None, "x", [], [[1.0, 2.0], [3.0]], object(), 1 + 2j, True, 10**30]),
)
ARGUMENTS = [(f, name) for f in FUNCTIONS for name, arg in f.args.items() if arg.kind in ("array", "scalar")]


@pytest.mark.slow
@settings(max_examples=200, deadline=None, derandomize=True, suppress_health_check=[HealthCheck.too_slow])
@given(case=st.sampled_from(ARGUMENTS), value=HOSTILE_ARRAYS)
def test_hostile_values_give_finite_output_or_a_gnssatt_error(case: tuple[Function, str], value: Any) -> None:
    # Any value in any argument: a gnssatt error (an InvalidInputError for the wrong kind of value, naming the
    # argument), or finite output; never another exception, a defect (InternalError) or a NaN.
    f, name = case
    kwargs = f.valid()
    kwargs[name] = value
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", NearDegenerateWarning)
        try:
            result = f.call(**kwargs)
        except InternalError:
            raise
        except InvalidTypeError as exc:
            assert name in str(exc)
            return
        except GnssattError:
            return
    assert all(np.all(np.isfinite(v)) for v in _leaves(result))
