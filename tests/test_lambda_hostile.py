"""The hostile inputs of issue 15 that reach LAMBDA, the matrix method and the likelihood grid window: each
gets the documented exception class with a message naming the parameter, or a right answer; never a panic
(``InternalError``), an abort, a hang or a wrong integer."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import gnssatt
from gnssatt import _core, ambiguity
from gnssatt.errors import (
    ConvergenceError,
    DegenerateGeometryError,
    InvalidInputError,
    InvalidTypeError,
    WorkLimitError,
)

A3 = np.array([0.3, 0.2, 0.1])
Q3 = np.eye(3)


def spectrum_covariance(rng: np.random.Generator, n: int, cond: float) -> np.ndarray:
    u, _ = np.linalg.qr(rng.standard_normal((n, n)))
    q = (u * np.logspace(0.0, -np.log10(cond), n)) @ u.T
    return (q + q.T) / 2


# ---------------------------------------------------------------- tiny and subnormal covariances


@pytest.mark.parametrize("call", [gnssatt.ratio_test, gnssatt.lambda_ils, gnssatt.partial_fix])
def test_subnormal_covariance_is_not_positive_definite_to_working_precision(call) -> None:
    # used to panic with an index out of bounds in validation.rs
    with pytest.raises(InvalidInputError, match=r"covariance.*working precision.*1\.000e-320"):
        call([0.3], [[1e-320]])


def test_tiny_normal_covariance_of_one_ambiguity() -> None:
    # sigma 1e-150 cycles: a valid answer, with the norms of the closed form (a - z)^2 / q
    fixed, norms = gnssatt.lambda_ils([0.3], [[1e-300]], candidates=2)
    assert fixed.tolist() == [[0], [1]]
    np.testing.assert_allclose(norms, [0.09e300, 0.49e300], rtol=1e-12)
    r = gnssatt.ratio_test([0.3], [[1e-300]])
    assert r.accepted and r.fixed.tolist() == [0]


def test_norms_beyond_the_float_range_are_refused() -> None:
    # (0.4 + 4)^2 / 1e-307 overflows: the 20th candidate has no finite norm
    with pytest.raises(ConvergenceError, match="finite squared norm"):
        gnssatt.lambda_ils([0.4], [[1e-307]], candidates=20)


# ---------------------------------------------------------------- work limits, checked before allocating


@pytest.mark.parametrize("m", [10**11, 2**58, 10**6, ambiguity.MAX_CANDIDATES + 1])
def test_candidates_beyond_the_limit(m: int) -> None:
    # 10**11 aborted the interpreter (allocation failure), 2**58 panicked
    with pytest.raises(WorkLimitError, match=rf"candidates = {m} exceeds the limit of 10000"):
        gnssatt.lambda_ils(A3, Q3, candidates=m)


@pytest.mark.parametrize(
    ("m", "cls"),
    [(0, InvalidInputError), (-3, InvalidInputError), (2.0, InvalidTypeError), (True, InvalidTypeError)],
)
def test_bad_candidates_are_named(m: object, cls: type) -> None:
    with pytest.raises(cls, match="candidates"):
        gnssatt.lambda_ils(A3, Q3, candidates=m)


def test_the_candidate_limit_itself_is_served() -> None:
    fixed, norms = gnssatt.lambda_ils(A3, Q3 * 0.01, candidates=ambiguity.MAX_CANDIDATES)
    assert fixed.shape == (10_000, 3) and np.all(np.diff(norms) >= 0)
    assert len({tuple(v) for v in fixed}) == 10_000


@pytest.mark.parametrize(
    "call",
    [
        lambda s: gnssatt.ratio_threshold_fixed_failure_rate(Q3, 1e-3, samples=s),
        lambda s: gnssatt.ratio_test(A3, Q3, failure_rate=1e-3, samples=s),
        lambda s: gnssatt.partial_fix(A3, Q3, failure_rate=1e-3, samples=s),
    ],
)
def test_samples_beyond_the_limit(call) -> None:
    with pytest.raises(WorkLimitError, match=r"samples = 1000000000 exceeds the limit of 1000000"):
        call(10**9)
    with pytest.raises(InvalidTypeError, match="samples"):
        call(1e5)
    with pytest.raises(InvalidInputError, match="samples"):
        call(0)


@pytest.mark.slow
def test_dimension_beyond_the_limit() -> None:
    n = ambiguity.MAX_DIMENSION + 1
    with pytest.raises(WorkLimitError, match=r"covariance .* 257 ambiguities.*limit of 256"):
        gnssatt.lambda_ils(np.zeros(n), np.eye(n))
    # the core's own limit is the same: it serves n = 256 and refuses 257 by itself
    fixed, _ = gnssatt.lambda_ils(np.full(256, 0.1), np.eye(256) * 0.01, candidates=1)
    assert not fixed.any()
    with pytest.raises(WorkLimitError, match="257"):
        gnssatt._core.lambda_ils(np.zeros(257), np.eye(257), 1)


def test_the_core_checks_its_limits_itself() -> None:
    # the Python constants are the core's: one more than each is refused by the core too
    with pytest.raises(WorkLimitError, match="10001"):
        gnssatt._core.lambda_ils(A3, Q3, ambiguity.MAX_CANDIDATES + 1)
    with pytest.raises(WorkLimitError, match="1000001"):
        gnssatt._core.lambda_ffrt_threshold(Q3, 0.01, ambiguity.MAX_SAMPLES + 1, 0)


@pytest.mark.parametrize(
    ("kwargs", "name"),
    [
        ({"threshold": 0.5}, "threshold"),
        ({"threshold": float("nan")}, "threshold"),
        ({"threshold": "3"}, "threshold"),
        ({"failure_rate": 1.5}, "failure_rate"),
        ({"failure_rate": 0.0}, "failure_rate"),
        ({"seed": -1}, "seed"),
        ({"seed": 2**64}, "seed"),
        ({"threshold": 3.0, "failure_rate": 0.01}, "threshold or failure_rate"),
    ],
)
def test_bad_ratio_test_options_are_named(kwargs: dict, name: str) -> None:
    with pytest.raises(InvalidInputError, match=name):
        gnssatt.ratio_test(A3, Q3, **kwargs)


def test_bad_min_success_rate_is_named() -> None:
    with pytest.raises(InvalidInputError, match="min_success_rate"):
        gnssatt.partial_fix(A3, Q3, min_success_rate=2.0)


def test_float_ambiguity_beyond_exact_integers() -> None:
    with pytest.raises(InvalidInputError, match=r"float_ambiguities.*exceeds.*4\.5e\+?15"):
        gnssatt.lambda_ils([1e16, 0.0], np.eye(2))


# ---------------------------------------------------------------- no wrong integers


@pytest.mark.parametrize("n", [20, 40, 64])
def test_ill_conditioned_decorrelation_is_exact(n: int) -> None:
    # condition 1e4..1e8 used to saturate Z at +-2^63 and put NaN in L for n = 40..64
    rng = np.random.default_rng(n)
    for cond in (1e4, 1e6, 1e8):
        q = spectrum_covariance(rng, n, cond)
        z, lower, d = gnssatt.lambda_decorrelate(q)
        assert np.all(np.isfinite(lower)) and np.all(d > 0)
        assert np.abs(z).max() < 2**20
        zf = z.astype(float)
        assert round(abs(np.linalg.det(zf))) == 1
        qz = zf.T @ q @ zf
        np.testing.assert_allclose(lower.T @ np.diag(d) @ lower, qz, atol=1e-9 * np.abs(qz).max())


@pytest.mark.parametrize("n", [10, 20, 30])
def test_ratio_test_and_partial_fix_return_exact_integers(n: int) -> None:
    # used to accept integers of +-9.2e18 and fix them
    rng = np.random.default_rng(7 * n)
    for cond in (1e4, 1e6):
        q = spectrum_covariance(rng, n, cond) * 0.01
        a = rng.integers(-(10**6), 10**6, n) + np.linalg.cholesky(q) @ rng.standard_normal(n)
        r = gnssatt.ratio_test(a, q)
        fixed, norms = gnssatt.lambda_ils(a, q)
        assert np.array_equal(r.fixed, fixed[0]) and np.allclose(r.squared_norms, norms)
        res = a - fixed[0]
        np.testing.assert_allclose(norms[0], res @ np.linalg.solve(q, res), rtol=1e-8)
        assert np.abs(fixed).max() < 2 * 10**6
        p = gnssatt.partial_fix(a, q)
        assert np.abs(p.values).max(initial=0) < 1e15
        combos = p.combinations.astype(float)
        np.testing.assert_allclose(combos.T @ p.ambiguities, p.values, atol=1e-6)


# ---------------------------------------------------------------- matrix method and grid window


@pytest.mark.parametrize("method", ["svd", "ml", "closed_form", "paper"])
def test_matrix_attitude_with_tiny_baselines_does_not_panic(method: str) -> None:
    # used to panic on expect("condition checked"); the Python API refuses such baselines first (1e-6 m is
    # its documented minimum), so the core is called directly: it must answer or refuse, never panic
    with pytest.raises(InvalidInputError, match="baselines"):
        gnssatt.matrix_attitude(np.eye(3) * 1e-60, np.eye(3), np.zeros((3, 3)), method=method)
    try:
        out = _core.matrix_attitude(np.eye(3) * 1e-60, np.eye(3), np.zeros((3, 3)), method)
        dcm, rms = out.dcm_ref_from_body, out.residual_rms_m
    except DegenerateGeometryError as exc:
        assert "matrix" in str(exc)
    else:
        assert np.all(np.isfinite(dcm)) and np.isfinite(rms)


def test_matrix_attitude_is_scale_invariant() -> None:
    # the core's conditioning is scale-invariant: 1e-60 m baselines (below the Python API's minimum, so
    # through the core) give the attitude that 1 m baselines give
    rot = Rotation.from_euler("ZYX", [40.0, -10.0, 5.0], degrees=True)
    b = np.array([[1.0, 0.0, 0.0], [0.0, 1.2, 0.0], [0.1, 0.2, 0.9]])
    s = np.array([[0.3, 0.2, 1.0], [-0.7, 0.1, 0.5], [0.2, -0.8, 0.4]])
    s /= np.linalg.norm(s, axis=1, keepdims=True)
    for scale in (1.0, 1e-60):
        r = (b * scale) @ rot.as_matrix().T @ s.T
        dcm = _core.matrix_attitude(b * scale, s, r, "svd").dcm_ref_from_body
        assert np.allclose(dcm, rot.as_matrix(), atol=1e-9)


@pytest.mark.parametrize("limit", [1e20, -1e20, 3601.0])
def test_absurd_grid_window_is_named(limit: float) -> None:
    # 1e20 deg overflowed the i64 node index, then divided by zero
    b = np.array([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])
    s = np.array([[0.0, 0.0, 1.0], [0.6, 0.0, 0.8], [0.0, 0.6, 0.8]])
    window = [[min(0.0, limit), max(0.0, limit)], [0.0, 10.0], [0.0, 10.0]]
    with pytest.raises(InvalidInputError, match=r"window_deg.*3600.*psi") as info:
        gnssatt.ml_attitude(np.zeros((2, 3)), s, b, 0.19, step_deg=1.0, window_deg=window)
    assert "psi" in str(info.value)
