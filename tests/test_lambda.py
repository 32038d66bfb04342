"""LAMBDA integer ambiguity resolution (gnssatt.ambiguity), checked against independent computations:
brute-force enumeration, numpy factorisations, Monte Carlo, invariances, and RTKLIB's reference vectors."""

from __future__ import annotations

import itertools

import numpy as np
import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp
from scipy.stats import norm

import gnssatt
from gnssatt import InvalidInputError

# ---------------------------------------------------------------- independent references


def random_covariance(rng: np.random.Generator, n: int, scale: float = 0.3) -> np.ndarray:
    """Correlated covariance with eigenvalues spread over two decades, max ``scale``."""
    u, _ = np.linalg.qr(rng.standard_normal((n, n)))
    lam = scale * 10.0 ** rng.uniform(-2.0, 0.0, n)
    q = (u * lam) @ u.T
    return (q + q.T) / 2


def brute_force(a: np.ndarray, q: np.ndarray, m: int) -> tuple[np.ndarray, np.ndarray]:
    """The m best integer vectors by enumerating a box that provably contains them."""
    n = a.size
    qinv = np.linalg.inv(q)

    def norms(z: np.ndarray) -> np.ndarray:
        r = a - z
        return np.einsum("ki,ij,kj->k", r, qinv, r)

    r0 = np.round(a)
    seeds = r0 + np.array(list(itertools.product([-1.0, 0.0, 1.0], repeat=n)))
    chi2 = np.sort(norms(seeds))[m - 1]
    half = np.sqrt(chi2 * np.diag(q))
    axes = [np.arange(np.floor(a[i] - half[i]), np.ceil(a[i] + half[i]) + 1) for i in range(n)]
    grid = np.array(list(itertools.product(*axes)))
    s = norms(grid)
    order = np.argsort(s, kind="stable")[:m]
    return grid[order].astype(np.int64), s[order]


def ltdl_numpy(q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``Q = L^T diag(d) L`` from numpy's Cholesky of the reversed matrix."""
    c = np.linalg.cholesky(q[::-1, ::-1])
    u = c[::-1, ::-1]  # upper triangular, Q = U U^T
    diag = np.diag(u)
    return (u / diag).T, diag**2


def geometry_covariance(sats: int, freqs: int, epochs: int = 5, interval_s: float = 2.0) -> np.ndarray:
    """Float DD ambiguity covariance (cycles²), short static baseline: phase 3 mm, code 0.3 m at zenith."""
    lams = [0.19029367, 0.24421021, 0.25482805][:freqs]
    m = sats - 1
    nn = m * freqs
    normal = np.zeros((3 + nn, 3 + nn))
    j = np.arange(sats)
    for e in range(epochs):
        t = e * interval_s
        az = 2.399963 * j + 1e-4 * t
        el = np.radians(15 + 70 * ((0.618034 * j) % 1.0)) + np.where(j % 2 == 0, 1, -1) * 5e-5 * t
        u = np.column_stack([np.cos(el) * np.sin(az), np.cos(el) * np.cos(az), np.sin(el)])
        r = int(np.argmax(el))
        oth = j[j != r]
        g = u[oth] - u[r]

        def dd_cov(sigma: float, oth: np.ndarray = oth, r: int = r, el: np.ndarray = el) -> np.ndarray:
            var = 2 * (sigma / np.sin(el)) ** 2
            return var[r] + np.diag(var[oth])

        for f, lam in enumerate(lams):
            a = np.zeros((m, 3 + nn))
            a[:, :3] = g / lam
            a[:, 3 + f * m : 3 + (f + 1) * m] = np.eye(m)
            normal += a.T @ np.linalg.solve(dd_cov(0.003) / lam**2, a)
            c = np.zeros((m, 3 + nn))
            c[:, :3] = g
            normal += c.T @ np.linalg.solve(dd_cov(0.3), c)
    q = np.linalg.inv(normal)[3:, 3:]
    return (q + q.T) / 2


# ---------------------------------------------------------------- exact search


@pytest.mark.parametrize("n", [1, 2, 3, 4, 5])
def test_matches_brute_force(n: int) -> None:
    rng = np.random.default_rng(100 + n)
    for _ in range(60):
        q = random_covariance(rng, n)
        a = rng.uniform(-20, 20, n)
        fixed, norms = gnssatt.lambda_ils(a, q, candidates=2)
        want_z, want_s = brute_force(a, q, 2)
        assert fixed.shape == (2, n) and fixed.dtype == np.int64
        np.testing.assert_allclose(norms, want_s, rtol=1e-9, atol=1e-12)
        gap = want_s[1] - want_s[0]
        np.testing.assert_array_equal(fixed[0], want_z[0])
        if gap > 1e-9 * (1 + want_s[0]):  # exact ties leave the order free
            np.testing.assert_array_equal(fixed[1], want_z[1])


def test_more_candidates_match_brute_force() -> None:
    rng = np.random.default_rng(7)
    for n in (2, 3, 4):
        for _ in range(20):
            q = random_covariance(rng, n)
            a = rng.uniform(-5, 5, n)
            _, norms = gnssatt.lambda_ils(a, q, candidates=6)
            _, want = brute_force(a, q, 6)
            np.testing.assert_allclose(norms, want, rtol=1e-9, atol=1e-12)


def test_classic_example() -> None:
    # de Jonge & Tiberius (1996), the 3-D example of the LAMBDA papers: fixed solution (5, 3, 4).
    q = np.array([[6.290, 5.978, 0.544], [5.978, 6.292, 2.340], [0.544, 2.340, 6.288]])
    fixed, norms = gnssatt.lambda_ils([5.45, 3.10, 2.97], q)
    np.testing.assert_array_equal(fixed[0], [5, 3, 4])
    want_z, want_s = brute_force(np.array([5.45, 3.10, 2.97]), q, 2)
    np.testing.assert_array_equal(fixed, want_z)
    np.testing.assert_allclose(norms, want_s, rtol=1e-10)


def test_rtklib_vectors() -> None:
    # RTKLIB test/utest/t_lambda.c utest1 (BSD-2-Clause, (c) 2007-2013 T. Takasu).
    a = np.array([1585184.171, -6716599.430, 3915742.905, 7627233.455, 9565990.879, 989457273.200])
    q = np.full((6, 6), 0.112202)
    q[:, 5] = q[5, :] = 0.103473
    np.fill_diagonal(q, 0.227134)
    q[5, 5] = 0.434339
    fixed, norms = gnssatt.lambda_ils(a, q)
    np.testing.assert_array_equal(fixed[0], [1585184, -6716599, 3915743, 7627234, 9565991, 989457273])
    np.testing.assert_array_equal(fixed[1], [1585184, -6716600, 3915743, 7627233, 9565991, 989457273])
    np.testing.assert_allclose(norms, [3.507984, 3.708456], atol=1e-4)


def test_sixty_ambiguities_from_a_realistic_geometry() -> None:
    q = geometry_covariance(31, 2)
    assert q.shape == (60, 60)
    rng = np.random.default_rng(60)
    truth = rng.integers(-1000, 1000, 60)
    a = truth + np.linalg.cholesky(q) @ rng.standard_normal(60)
    fixed, norms = gnssatt.lambda_ils(a, q, candidates=3)
    assert fixed.shape == (3, 60) and np.all(np.diff(norms) >= 0)
    r = a - fixed
    np.testing.assert_allclose(np.einsum("ki,ij,kj->k", r, np.linalg.inv(q), r), norms, rtol=1e-6)
    # A strong model: the best solution is the truth.
    assert gnssatt.bootstrap_success_rate(q) > 0.99
    np.testing.assert_array_equal(fixed[0], truth)


# ---------------------------------------------------------------- invariances (hypothesis)

floats = hnp.arrays(np.float64, 4, elements=st.floats(-50, 50, allow_nan=False))
shifts = hnp.arrays(np.int64, 4, elements=st.integers(-(10**6), 10**6))


@pytest.mark.slow
@settings(max_examples=60, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), a=floats, shift=shifts)
@example(seed=0, a=np.array([-0.5, 0.0, 0.0, 0.0]), shift=np.array([1, 1, 1, 1]))
def test_integer_shift_shifts_the_solution(seed: int, a: np.ndarray, shift: np.ndarray) -> None:
    q = random_covariance(np.random.default_rng(seed), 4)
    fixed, norms = gnssatt.lambda_ils(a, q)
    moved, moved_norms = gnssatt.lambda_ils(a + shift, q)
    np.testing.assert_allclose(moved_norms, norms, rtol=1e-7, atol=1e-9)
    # An exact tie (e.g. a = (-0.5, 0, 0, 0)) has two equally good integer vectors; either may come first.
    if norms[1] - norms[0] > 1e-6 * (1 + norms[0]):
        np.testing.assert_array_equal(moved[0], fixed[0] + shift)
    else:
        assert any(np.array_equal(m, fixed[0] + shift) for m in moved[:2])


def unimodular(rng: np.random.Generator, n: int) -> np.ndarray:
    t = np.eye(n, dtype=np.int64)
    for _ in range(2 * n):
        i, j = rng.choice(n, 2, replace=False)
        t[:, j] += rng.choice([-2, -1, 1, 2]) * t[:, i]
    return t[:, rng.permutation(n)]


@pytest.mark.slow
@settings(max_examples=60, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), a=floats)
def test_unimodular_transform_transforms_the_solution(seed: int, a: np.ndarray) -> None:
    rng = np.random.default_rng(seed)
    q = random_covariance(rng, 4)
    t = unimodular(rng, 4)
    assert round(abs(np.linalg.det(t))) == 1
    fixed, norms = gnssatt.lambda_ils(a, q)
    moved, moved_norms = gnssatt.lambda_ils(t.T @ a, t.T @ q @ t)
    np.testing.assert_allclose(moved_norms, norms, rtol=1e-6, atol=1e-9)
    if norms[1] - norms[0] > 1e-6 * (1 + norms[0]):
        np.testing.assert_array_equal(moved[0], t.T @ fixed[0])


# ---------------------------------------------------------------- decorrelation


@pytest.mark.parametrize("n", [1, 3, 6, 12, 20])
def test_decorrelation_is_unimodular_and_factorises(n: int) -> None:
    q = geometry_covariance(n + 1, 1) if n <= 10 else geometry_covariance(n // 2 + 1, 2)
    z, lower, d = gnssatt.lambda_decorrelate(q)
    assert z.dtype == np.int64 and z.shape == (n, n)
    assert round(abs(np.linalg.det(z))) == 1
    assert np.allclose(np.linalg.inv(z), np.round(np.linalg.inv(z)), atol=1e-6)  # integer inverse
    qz = z.T @ q @ z
    np.testing.assert_allclose(lower.T @ np.diag(d) @ lower, qz, atol=1e-9 * np.abs(qz).max())
    assert np.all(np.abs(np.tril(lower, -1)) <= 0.5 + 1e-9)
    l_np, d_np = ltdl_numpy(qz)
    np.testing.assert_allclose(d, d_np, rtol=1e-6)
    np.testing.assert_allclose(lower, l_np, atol=1e-6)
    # It decorrelates: the spread of conditional variances and the correlations shrink.
    _, d0 = ltdl_numpy(q)
    assert d.max() / d.min() <= d0.max() / d0.min() * (1 + 1e-9)
    corr = lambda m: np.abs(m / np.sqrt(np.outer(np.diag(m), np.diag(m))) - np.eye(n)).max()  # noqa: E731
    assert corr(qz) <= corr(q) + 1e-12


# ---------------------------------------------------------------- success rate


def test_success_rate_one_ambiguity_is_rounding() -> None:
    sigma = 0.21
    assert gnssatt.bootstrap_success_rate([[sigma**2]]) == pytest.approx(2 * norm.cdf(0.5 / sigma) - 1, 1e-14)


@pytest.mark.slow
def test_success_rate_matches_monte_carlo_bootstrapping() -> None:
    q = geometry_covariance(8, 1, epochs=2)  # a weak model: P = 0.81
    n = q.shape[0]
    p = gnssatt.bootstrap_success_rate(q)
    z, _, _ = gnssatt.lambda_decorrelate(q)
    qz = z.T @ q @ z
    rng = np.random.default_rng(2024)
    trials = 100_000
    e = rng.standard_normal((trials, n)) @ np.linalg.cholesky(qz).T  # decorrelated float errors, truth 0
    fixed = np.zeros_like(e)
    for i in range(n - 1, -1, -1):  # bootstrapping: last first, each conditioned on those fixed
        if i == n - 1:
            cond = e[:, i]
        else:
            gain = np.linalg.solve(qz[i + 1 :, i + 1 :], qz[i + 1 :, i])
            cond = e[:, i] - (e[:, i + 1 :] - fixed[:, i + 1 :]) @ gain
        fixed[:, i] = np.round(cond)
    p_mc = np.mean(np.all(fixed == 0, axis=1))
    sigma = np.sqrt(p * (1 - p) / trials)
    assert 0.3 < p < 0.98
    assert abs(p_mc - p) < 4.5 * sigma, (p, p_mc, sigma)
    # ILS does at least as well as bootstrapping (Teunissen 1999).
    ils_ok = sum(np.all(gnssatt.lambda_ils(a, qz, candidates=1)[0][0] == 0) for a in e[:3000])
    assert ils_ok / 3000 > p - 4.5 * np.sqrt(p * (1 - p) / 3000)


# ---------------------------------------------------------------- validation


def test_ratio_test_fixed_threshold() -> None:
    q = np.diag([0.01, 0.02, 0.015])
    r = gnssatt.ratio_test([3.05, -2.02, 7.01], q, threshold=3.0)
    assert r.accepted and r.threshold == 3.0
    np.testing.assert_array_equal(r.fixed, [3, -2, 7])
    assert r.ratio == pytest.approx(r.squared_norms[1] / r.squared_norms[0])
    assert not gnssatt.ratio_test([3.49, -2.02, 7.01], q).accepted  # default threshold 3
    assert gnssatt.ratio_test([3.0, -2.0, 7.0], q).ratio == np.inf


@pytest.mark.slow
def test_fixed_failure_rate_threshold() -> None:
    weak = geometry_covariance(8, 1, epochs=2)  # bootstrapped failure rate 0.19
    c = gnssatt.ratio_threshold_fixed_failure_rate(weak, 0.01, samples=20_000, seed=3)
    assert c > 1.0
    assert c == gnssatt.ratio_threshold_fixed_failure_rate(weak, 0.01, samples=20_000, seed=3)
    r = gnssatt.ratio_test(np.zeros(7) + 0.1, weak, failure_rate=0.01, samples=20_000, seed=3)
    assert r.threshold == c
    # Independent check: with c, wrong fixes are accepted at about the target rate or less.
    rng = np.random.default_rng(9)
    draws = rng.standard_normal((4000, 7)) @ np.linalg.cholesky(weak).T
    bad = 0
    for a in draws:
        fixed, s = gnssatt.lambda_ils(a, weak)
        bad += bool(np.any(fixed[0] != 0) and s[1] / s[0] >= c)
    assert bad / 4000 < 0.01 + 4.5 * np.sqrt(0.01 * 0.99 / 4000)
    # A strong model needs no threshold: every fix is acceptable.
    strong = geometry_covariance(11, 1)  # bootstrapped failure rate 5e-10
    assert gnssatt.ratio_threshold_fixed_failure_rate(strong, 1e-3, samples=1000) == 1.0


def test_partial_fix_conditions_the_float_solution() -> None:
    rng = np.random.default_rng(5)
    q = geometry_covariance(8, 1)  # bootstrapped success rate 0.994 < 0.999
    n = q.shape[0]
    a = rng.integers(-50, 50, n) + np.linalg.cholesky(q) @ rng.standard_normal(n)
    res = gnssatt.partial_fix(a, q, min_success_rate=0.999, threshold=2.0)
    k = res.fixed_count
    assert 0 < k < n, k
    zk = res.combinations
    assert zk.shape == (n, k) and res.values.shape == (k,) and res.success_rate >= 0.999
    z, _, _ = gnssatt.lambda_decorrelate(q)
    np.testing.assert_array_equal(zk, z[:, n - k :])
    # Independent conditioning: a - Q Zk (Zk^T Q Zk)^-1 (Zk^T a - values).
    s = zk.T @ q @ zk
    gain = q @ zk @ np.linalg.inv(s)
    np.testing.assert_allclose(res.ambiguities, a - gain @ (zk.T @ a - res.values), atol=1e-8)
    np.testing.assert_allclose(res.covariance, q - gain @ zk.T @ q, atol=1e-10)
    np.testing.assert_allclose(zk.T @ res.ambiguities, res.values, atol=1e-8)
    # The fixed subset is the ILS solution of the subset's problem, and it passed its ratio test.
    sub, norms = gnssatt.lambda_ils(zk.T @ a, s)
    np.testing.assert_array_equal(sub[0], res.values)
    assert norms[1] / norms[0] == pytest.approx(res.ratio) and res.ratio >= 2.0


def test_partial_fix_full_and_none() -> None:
    q = np.diag([0.001, 0.003, 0.002])
    full = gnssatt.partial_fix([1.01, 2.0, -3.02], q, threshold=3.0)
    assert full.fixed_count == 3
    np.testing.assert_array_equal(full.ambiguities, [1.0, 2.0, -3.0])
    assert not full.covariance.any()
    none = gnssatt.partial_fix([1.5, 2.5, -3.5], np.eye(3) * 4.0, min_success_rate=0.5)
    assert none.fixed_count == 0 and np.isnan(none.ratio)
    np.testing.assert_array_equal(none.ambiguities, [1.5, 2.5, -3.5])


# ---------------------------------------------------------------- bad input


@pytest.mark.parametrize(
    ("a", "q", "match"),
    [
        ([1.0, 2.0], [[1.0, 0.5], [0.4, 1.0]], "not symmetric"),
        ([1.0, 2.0], [[1.0, 2.0], [2.0, 1.0]], "not positive definite"),
        ([1.0, 2.0], [[1.0, 0.0], [0.0, 0.0]], "not positive definite"),
        ([1.0, 2.0, 3.0], np.eye(2), r"float_ambiguities of shape \(2,\).*got \(3,\)"),
        ([1.0, 2.0], np.ones((2, 3)), r"covariance of shape \(n, n\).*got \(2, 3\)"),
        ([], np.zeros((0, 0)), r"n >= 1, got \(0, 0\)"),
        ([1.0, np.nan], np.eye(2), "float_ambiguities contains a non-finite value"),
        ([1.0, 2.0], [[1.0, np.inf], [0.0, 1.0]], "covariance contains a non-finite value"),
        ([1e17, 2.0], np.eye(2), "exceeds"),
    ],
)
def test_bad_input_is_named(a: object, q: object, match: str) -> None:
    with pytest.raises(InvalidInputError, match=match):
        gnssatt.lambda_ils(a, q)


def test_bad_options_are_named() -> None:
    q = np.eye(2) * 0.01
    with pytest.raises(InvalidInputError, match="candidates"):
        gnssatt.lambda_ils([0.1, 0.2], q, candidates=0)
    with pytest.raises(InvalidInputError, match="got both"):
        gnssatt.ratio_test([0.1, 0.2], q, threshold=2.0, failure_rate=0.01)
    with pytest.raises(InvalidInputError, match="threshold >= 1"):
        gnssatt.ratio_test([0.1, 0.2], q, threshold=0.5)
    with pytest.raises(InvalidInputError, match="failure_rate"):
        gnssatt.ratio_test([0.1, 0.2], q, failure_rate=1.5)
    with pytest.raises(InvalidInputError, match="samples"):
        gnssatt.ratio_test([0.1, 0.2], q, failure_rate=1e-3, samples=10)
    with pytest.raises(InvalidInputError, match="min_success_rate"):
        gnssatt.partial_fix([0.1, 0.2], q, min_success_rate=2.0)
    with pytest.raises(InvalidInputError, match="not positive definite"):
        gnssatt.bootstrap_success_rate([[1.0, 2.0], [2.0, 1.0]])
    with pytest.raises(InvalidInputError, match="not symmetric"):
        gnssatt.lambda_decorrelate([[1.0, 0.5], [0.0, 1.0]])
