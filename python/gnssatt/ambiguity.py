"""LAMBDA integer ambiguity resolution: decorrelation, exact integer least squares, success rates, validation.

Float ambiguities ``a`` are in cycles and their covariance ``Q`` in cycles². The decorrelating matrix ``Z`` is
unimodular and integer: the decorrelated ambiguities are ``Z.T @ a`` with covariance
``Z.T @ Q @ Z = L.T @ diag(D) @ L`` (``L`` unit lower triangular). Written from Teunissen (1995, J. Geodesy
70:65-82), de Jonge & Tiberius (1996, LGR-12) and Chang, Yang & Zhou (2005, J. Geodesy 79:552-565, MLAMBDA).

The fixed-failure-rate ratio test runs a seeded simulation on rayon's thread pool; set ``RAYON_NUM_THREADS``
before the first call to choose the thread count (results do not depend on it).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from gnssatt import _core
from gnssatt._arrays import float_array
from gnssatt.errors import InvalidInputError

__all__ = [
    "PartialFixResult",
    "RatioTestResult",
    "bootstrap_success_rate",
    "lambda_decorrelate",
    "lambda_ils",
    "partial_fix",
    "ratio_test",
    "ratio_threshold_fixed_failure_rate",
]


def _problem(float_ambiguities: Any, covariance: Any) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    a = float_array("float_ambiguities", float_ambiguities, ndim=1, shape="(n,)")
    q = _covariance(covariance)
    if a.shape[0] != q.shape[0]:
        raise InvalidInputError(
            f"expected float_ambiguities of shape ({q.shape[0]},) to match a covariance of shape "
            f"{q.shape}, got {a.shape}"
        )
    return a, q


def _covariance(covariance: Any) -> NDArray[np.float64]:
    q = float_array("covariance", covariance, ndim=2, shape="(n, n)")
    if q.shape[0] != q.shape[1] or q.shape[0] == 0:
        raise InvalidInputError(f"expected covariance of shape (n, n) with n >= 1, got {q.shape}")
    return q


def _count(name: str, value: int, minimum: int) -> int:
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < minimum:
        raise InvalidInputError(f"expected {name} as an integer >= {minimum}, got {value!r}")
    return int(value)


def lambda_ils(
    float_ambiguities: ArrayLike, covariance: ArrayLike, *, candidates: int = 2
) -> tuple[NDArray[np.int64], NDArray[np.float64]]:
    """The ``candidates`` best integer least-squares solutions, by LAMBDA.

    Parameters
    ----------
    float_ambiguities
        (n,) float ambiguities ``a``, cycles; n >= 1 (tested up to 64).
    covariance
        (n, n) symmetric positive-definite covariance ``Q`` of ``a``, cycles².
    candidates
        Number m >= 1 of solutions wanted.

    Returns
    -------
    fixed
        (m, n) int64 integer vectors, best first.
    squared_norms
        (m,) ``(a - z) @ inv(Q) @ (a - z)`` of each row, ascending.

    Raises
    ------
    InvalidInputError
        Wrong shapes, non-finite values, an asymmetric or non-positive-definite covariance (the message
        says which), ``candidates < 1``.
    ConvergenceError
        The search exceeded its node cap (2e8 nodes), which only a badly conditioned problem does.
    """
    a, q = _problem(float_ambiguities, covariance)
    fixed, norms, _ = _core.lambda_ils(a, q, _count("candidates", candidates, 1))
    return fixed, norms


def lambda_decorrelate(
    covariance: ArrayLike,
) -> tuple[NDArray[np.int64], NDArray[np.float64], NDArray[np.float64]]:
    """The decorrelating transformation of LAMBDA.

    Parameters
    ----------
    covariance
        (n, n) symmetric positive-definite covariance ``Q`` of the float ambiguities, cycles².

    Returns
    -------
    Z
        (n, n) int64 unimodular matrix (``|det Z| = 1``); decorrelated ambiguities are ``Z.T @ a``.
    L
        (n, n) unit lower-triangular factor, ``|L[i, j]| <= 1/2`` below the diagonal.
    D
        (n,) conditional variances, cycles²: ``Z.T @ Q @ Z == L.T @ np.diag(D) @ L``; ``D[-1]`` is the
        variance of the last decorrelated ambiguity, ``D[i]`` that of ambiguity i given those after it.
    """
    return _core.lambda_decorrelate(_covariance(covariance))


def bootstrap_success_rate(covariance: ArrayLike) -> float:
    """Success rate of integer bootstrapping on the decorrelated ambiguities, a lower bound of the ILS one.

    ``prod_i (2 Phi(1 / (2 sqrt(D_i))) - 1)`` with ``D`` from :func:`lambda_decorrelate`
    (Teunissen 1998, J. Geodesy 72:606-612).

    Parameters
    ----------
    covariance
        (n, n) symmetric positive-definite covariance of the float ambiguities, cycles².
    """
    return _core.lambda_bootstrap_success_rate(_covariance(covariance))


def ratio_threshold_fixed_failure_rate(
    covariance: ArrayLike, failure_rate: float = 1e-3, *, samples: int = 100_000, seed: int = 0
) -> float:
    """The ratio-test threshold ``c`` that keeps the probability of accepting a wrong fix at ``failure_rate``.

    Computed by a seeded simulation of ``a ~ N(z, Q)`` (the way the published look-up tables were made:
    Teunissen & Verhagen 2009, Survey Review 41:138-151; Verhagen & Teunissen 2013, GPS Solutions
    17:535-548): ``c`` is just above the ``floor(failure_rate * samples) + 1``-th largest ratio among wrong
    fixes, and 1 when the bootstrapped failure rate is already at most ``failure_rate``. Use
    ``samples >= 100 / failure_rate`` for a stable ``c``.

    Parameters
    ----------
    covariance
        (n, n) covariance of the float ambiguities, cycles².
    failure_rate
        Tolerated probability of accepting a wrong integer vector, in (0, 1).
    samples
        Simulated float vectors, at least ``1 / failure_rate``.
    seed
        Seed of the simulation (one independent stream per sample).
    """
    q = _covariance(covariance)
    return _core.lambda_ffrt_threshold(
        q, float(failure_rate), _count("samples", samples, 1), _count("seed", seed, 0)
    )


@dataclass(frozen=True)
class RatioTestResult:
    """Outcome of :func:`ratio_test`.

    Attributes
    ----------
    accepted
        ``ratio >= threshold``.
    ratio
        Second-best over best squared norm (``inf`` when the float vector is an integer vector).
    threshold
        The threshold used (given, or computed for the fixed failure rate).
    fixed
        (n,) int64 best integer vector, accepted or not.
    squared_norms
        (2,) the two best squared norms.
    """

    accepted: bool
    ratio: float
    threshold: float
    fixed: NDArray[np.int64]
    squared_norms: NDArray[np.float64]


def ratio_test(
    float_ambiguities: ArrayLike,
    covariance: ArrayLike,
    *,
    threshold: float | None = None,
    failure_rate: float | None = None,
    samples: int = 100_000,
    seed: int = 0,
) -> RatioTestResult:
    """Ratio test of the ILS solution: accept when ``||a - z2||² / ||a - z1||² >= threshold``.

    Parameters
    ----------
    float_ambiguities, covariance
        (n,) float ambiguities (cycles) and their (n, n) covariance (cycles²).
    threshold
        Fixed threshold ``c >= 1``; default 3 (RTKLIB's) when ``failure_rate`` is not given.
    failure_rate
        Instead of ``threshold``: choose ``c`` for this fixed failure rate, see
        :func:`ratio_threshold_fixed_failure_rate` (``samples`` and ``seed`` apply).

    Raises
    ------
    InvalidInputError
        As :func:`lambda_ils`; both ``threshold`` and ``failure_rate`` given; threshold < 1; failure rate
        outside (0, 1); fewer than ``1 / failure_rate`` samples.
    """
    a, q = _problem(float_ambiguities, covariance)
    accepted, ratio, c, fixed, norms = _core.lambda_ratio_test(
        a, q, threshold, failure_rate, _count("samples", samples, 1), _count("seed", seed, 0)
    )
    return RatioTestResult(bool(accepted), ratio, c, fixed, norms)


@dataclass(frozen=True)
class PartialFixResult:
    """Outcome of :func:`partial_fix`.

    Attributes
    ----------
    fixed_count
        Number k of integer combinations fixed: 0 (nothing passed) to n (full fix).
    combinations
        (n, k) int64: the fixed combinations ``combinations.T @ a`` (the last k columns of ``Z``).
    values
        (k,) int64 integers those combinations are fixed to.
    ratio, threshold
        Ratio statistic of the fixed subset and the threshold it passed (NaN when k = 0).
    success_rate
        Bootstrapped success rate of the fixed subset (1 when k = 0).
    ambiguities
        (n,) float ambiguities conditioned on the fixed combinations, cycles; the integer solution when
        k = n, the input when k = 0.
    covariance
        (n, n) their covariance, cycles²; zero when k = n.
    """

    fixed_count: int
    combinations: NDArray[np.int64]
    values: NDArray[np.int64]
    ratio: float
    threshold: float
    success_rate: float
    ambiguities: NDArray[np.float64]
    covariance: NDArray[np.float64]


def partial_fix(
    float_ambiguities: ArrayLike,
    covariance: ArrayLike,
    *,
    min_success_rate: float = 0.0,
    threshold: float | None = None,
    failure_rate: float | None = None,
    samples: int = 100_000,
    seed: int = 0,
) -> PartialFixResult:
    """Partial ambiguity resolution: fix the largest subset of decorrelated ambiguities that passes.

    Subsets are the last k decorrelated ambiguities for k = n, n-1, ..., 1 (dropping the least precise end
    of the conditional-variance order first, Teunissen, Joosten & Tiberius 1999); the first whose
    bootstrapped success rate is at least ``min_success_rate`` and whose ratio test passes is fixed, and
    the float solution is conditioned on it.

    Parameters
    ----------
    float_ambiguities, covariance
        (n,) float ambiguities (cycles) and their (n, n) covariance (cycles²).
    min_success_rate
        In [0, 1]; e.g. 0.999.
    threshold, failure_rate, samples, seed
        The ratio test applied to each subset, as in :func:`ratio_test`.
    """
    a, q = _problem(float_ambiguities, covariance)
    k, combos, values, ratio, c, sr, amb, cov = _core.lambda_partial_fix(
        a,
        q,
        threshold,
        failure_rate,
        _count("samples", samples, 1),
        _count("seed", seed, 0),
        float(min_success_rate),
    )
    return PartialFixResult(int(k), combos, values, ratio, c, sr, amb, cov)
