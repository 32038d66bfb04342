"""LAMBDA integer ambiguity resolution: decorrelation, exact integer least squares, success rates, validation.

Float ambiguities ``a`` are in cycles and their covariance ``Q`` in cycles². The decorrelating matrix ``Z`` is
unimodular and integer: the decorrelated ambiguities are ``Z.T @ a`` with covariance
``Z.T @ Q @ Z = L.T @ diag(D) @ L`` (``L`` unit lower triangular). Written from Teunissen (1995, J. Geodesy
70:65-82), de Jonge & Tiberius (1996, LGR-12) and Chang, Yang & Zhou (2005, J. Geodesy 79:552-565, MLAMBDA).

The fixed-failure-rate ratio test runs a seeded simulation on rayon's thread pool; set ``RAYON_NUM_THREADS``
before the first call to choose the thread count (results do not depend on it).

Guarantee: every integer vector returned is the exact integer least-squares (ILS) solution, or the call
raises :class:`~gnssatt.errors.ConvergenceError`; there is no silently wrong integer. ``Z`` is kept integer
and unimodular in checked integer arithmetic (entries up to 2^52), ``Z.T @ Q @ Z == L.T @ diag(D) @ L`` is
verified entry by entry to 64 n eps times the rounding scale ``|Z|.T |Q| |Z| + |L|.T D |L|``, and each
squared norm is recomputed from the original ``a`` and ``Q`` (Cholesky) and must agree with the search's to
``1e-6 (1 + norm)``; candidates within that of each other are ties, ordered by the recomputed norm. Returned
integers are bounded by :data:`MAX_ABS_AMBIGUITY` so that they are exact in int64 and float64.

Limits (each refused before any work with :class:`~gnssatt.errors.WorkLimitError`): n <= :data:`MAX_DIMENSION`
ambiguities, ``candidates <= MAX_CANDIDATES``, ``samples <= MAX_SAMPLES``. One search over n ambiguities
visits at most ``min(NODES_PER_AMBIGUITY * n, MAX_NODES)`` nodes (3.2e7, about 3 s, at n = 64) before
raising ``ConvergenceError``; the simulations of the fixed-failure-rate threshold share 1e9 nodes between
their samples; a :func:`lambda_ils_batch` call is bounded by :data:`BATCH_MAX_WORK` (before any work) and
:data:`BATCH_MAX_SEARCH_WORK` (while it runs), about 10 s of one core together.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, TypedDict

import numpy as np
from numpy.typing import ArrayLike, NDArray

from gnssatt import _core
from gnssatt._arrays import float_array, integer, scalar
from gnssatt.errors import ConvergenceError, InvalidInputError, WorkLimitError

__all__ = [
    "BATCH_MAX_SEARCH_WORK",
    "BATCH_MAX_WORK",
    "MAX_ABS_AMBIGUITY",
    "MAX_CANDIDATES",
    "MAX_DIMENSION",
    "MAX_NODES",
    "MAX_SAMPLES",
    "NODES_PER_AMBIGUITY",
    "IlsBatchResult",
    "PartialFixResult",
    "RatioTestResult",
    "bootstrap_success_rate",
    "lambda_decorrelate",
    "lambda_ils",
    "lambda_ils_batch",
    "partial_fix",
    "ratio_test",
    "ratio_threshold_fixed_failure_rate",
]


# The limits of the Rust core (gnssatt_core::lambda), read from it and checked here first so that the
# message names the Python parameter; tests/test_lambda_hostile.py serves each limit and refuses one more.
MAX_CANDIDATES: int = int(_core.LAMBDA_MAX_CANDIDATES)
"""Most ``candidates`` one :func:`lambda_ils` call may ask for (10,000)."""
MAX_SAMPLES: int = int(_core.LAMBDA_MAX_SAMPLES)
"""Most simulated ``samples`` of the fixed-failure-rate threshold (1,000,000)."""
MAX_DIMENSION: int = int(_core.LAMBDA_MAX_DIMENSION)
"""Most ambiguities n of one problem (256; answers are tested against an independent solver up to 64)."""
MAX_NODES: int = int(_core.LAMBDA_MAX_NODES)
"""Most nodes one integer search may visit before it raises ``ConvergenceError`` (1e8); a problem of n
ambiguities gets ``min(NODES_PER_AMBIGUITY * n, MAX_NODES)`` (3.2e7, about 3 s, at n = 64). The best
candidate of a float vector drawn from its covariance takes about 2n nodes; the second best (ratio test)
grows roughly binomially with n when the decorrelated variances are flat, and may reach the budget for
n >= 40."""
NODES_PER_AMBIGUITY: int = int(_core.LAMBDA_NODES_PER_AMBIGUITY)
"""Search nodes per ambiguity of a problem's budget (500,000: it reaches :data:`MAX_NODES` at n = 200)."""
BATCH_MAX_WORK: int = int(_core.LAMBDA_BATCH_MAX_WORK)
"""Most work units ``k * (n**3 + 1000)`` of the decorrelations of one :func:`lambda_ils_batch` call (2^31, at
most about 5 s of a core), checked before any work."""
BATCH_MAX_SEARCH_WORK: int = int(_core.LAMBDA_BATCH_MAX_SEARCH_WORK)
"""Most work units ``nodes * (n + 16)`` of all the searches of one :func:`lambda_ils_batch` call together
(2^31, about 5 s of a core: 3.8e7 nodes at n = 40), or one search's own budget where that is larger
(n >= 59)."""
MAX_ABS_AMBIGUITY: float = float(_core.LAMBDA_MAX_ABS_AMBIGUITY)
"""Largest magnitude of a float ambiguity and of any integer returned, cycles (4.5e15 < 2^53)."""
_MAX_SEED = 2**64 - 1


def _ready(value: Any, ndim: int) -> NDArray[np.float64] | None:
    """``value`` itself when it is already a C-contiguous float64 array of ``ndim`` dimensions, else None.

    The common case of a study calling :func:`lambda_ils` in a loop: the copy and the finiteness scan of
    :func:`~gnssatt._arrays.float_array` are skipped, because the Rust binding scans every value again
    (refusing a non-finite one with the same ``InvalidInputError`` and parameter name) and copies it.
    """
    if type(value) is np.ndarray and value.dtype == np.float64 and value.ndim == ndim:
        if value.flags.c_contiguous:
            return value
    return None


def _problem(float_ambiguities: Any, covariance: Any) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    a = _ready(float_ambiguities, 1)
    q = _ready(covariance, 2)
    if a is not None and q is not None and a.shape[0] == q.shape[0] == q.shape[1] and 0 < q.shape[0]:
        # NaN compares false: a non-finite or too large value takes the full intake below, which names it
        if q.shape[0] <= MAX_DIMENSION and float(np.abs(a).max()) < MAX_ABS_AMBIGUITY:
            return a, q
    a = float_array("float_ambiguities", float_ambiguities, ndim=1, shape="(n,)")
    big = np.abs(a) >= MAX_ABS_AMBIGUITY
    if np.any(big):
        i = int(np.argmax(big))
        raise InvalidInputError(
            f"float_ambiguities is out of range: |float_ambiguities[{i}]| = {abs(a[i]):.6g} cycles exceeds "
            f"(or equals) MAX_ABS_AMBIGUITY = {MAX_ABS_AMBIGUITY:.6g} cycles"
        )
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
    if q.shape[0] > MAX_DIMENSION:
        raise WorkLimitError(
            f"covariance of shape {q.shape} has {q.shape[0]} ambiguities, more than the limit of "
            f"{MAX_DIMENSION}"
        )
    return q


class _RatioSettings(TypedDict):
    """The ratio-test keywords of ``_core.lambda_ratio_test`` and ``_core.lambda_partial_fix``."""

    threshold: float | None
    failure_rate: float | None
    samples: int
    seed: int


def _threshold(threshold: Any, failure_rate: Any, samples: Any, seed: Any) -> _RatioSettings:
    """The ratio-test settings, checked and named (the Rust core checks them again)."""
    if threshold is not None and failure_rate is not None:
        raise InvalidInputError(
            f"expected either threshold or failure_rate, got both ({threshold!r} and {failure_rate!r})"
        )
    return _RatioSettings(
        threshold=None if threshold is None else scalar("threshold", threshold, minimum=1.0),
        failure_rate=None
        if failure_rate is None
        else scalar("failure_rate", failure_rate, minimum=0.0, maximum=1.0, strict=True),
        samples=integer("samples", samples, minimum=1, maximum=MAX_SAMPLES),
        seed=integer("seed", seed, minimum=0, maximum=_MAX_SEED),
    )


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
        Number m of solutions wanted, 1 <= m <= :data:`MAX_CANDIDATES` (10,000).

    Returns
    -------
    fixed
        (m, n) int64 integer vectors, best first.
    squared_norms
        (m,) ``(a - z) @ inv(Q) @ (a - z)`` of each row recomputed from the original ``a`` and ``Q``,
        ascending.

    Notes
    -----
    Exact ILS or ``ConvergenceError``: see the module documentation for the checks behind the guarantee.
    Valid covariances of n <= 64 and condition number <= 1e8 are solved exactly (tested against an
    independent search); a refusal means the problem cannot be solved exactly in double precision.

    Raises
    ------
    InvalidInputError
        Wrong shapes, non-finite values, an asymmetric covariance or one not positive definite to working
        precision (the message gives the smallest pivot), ``candidates < 1``, ``|float_ambiguities| >=
        MAX_ABS_AMBIGUITY`` (checked here first, naming the parameter).
    InvalidTypeError
        ``candidates`` not an integer; arrays not real.
    WorkLimitError
        ``candidates > MAX_CANDIDATES`` or n > :data:`MAX_DIMENSION`.
    ConvergenceError
        The search exceeded :data:`MAX_NODES`, or an exactness check failed (the message gives the numbers).

    Examples
    --------
    Two independent ambiguities of variance 0.01 cycles²: the best vector rounds each, the second moves the
    one nearer to half a cycle; ``(0.1² + 0.05²) / 0.01 = 1.25`` and ``(0.9² + 0.05²) / 0.01 = 81.25``:

    >>> import numpy as np
    >>> from gnssatt import lambda_ils
    >>> fixed, squared_norms = lambda_ils([1.1, -2.05], np.diag([0.01, 0.01]))
    >>> fixed
    array([[ 1, -2],
           [ 2, -2]])
    >>> np.round(squared_norms, 6)
    array([ 1.25, 81.25])
    """
    a, q = _problem(float_ambiguities, covariance)
    m = integer("candidates", candidates, minimum=1, maximum=MAX_CANDIDATES)
    out = _core.lambda_ils(a, q, m)
    fixed, norms = out.fixed, out.squared_norms
    return fixed, norms


@dataclass(frozen=True)
class IlsBatchResult:
    """Outcome of :func:`lambda_ils_batch` for k problems of n ambiguities and m candidates.

    Attributes
    ----------
    fixed
        (k, m, n) int64: ``fixed[p, c]`` is the c-th best integer vector of problem p.
    squared_norms
        (k, m) ``(a - z) @ inv(Q) @ (a - z)`` of each candidate, recomputed from the original float vector and
        covariance, ascending per problem.
    nodes_visited
        (k,) uint64 search nodes of each problem.
    """

    fixed: NDArray[np.int64]
    squared_norms: NDArray[np.float64]
    nodes_visited: NDArray[np.uint64]


def lambda_ils_batch(
    float_ambiguities: ArrayLike, covariance: ArrayLike, *, candidates: int = 2
) -> IlsBatchResult:
    """:func:`lambda_ils` of many problems in one call, in parallel.

    Every problem is solved exactly as :func:`lambda_ils` solves it alone (same checks, search and node
    budget), so the answers do not depend on the batch's size, order or thread count; the intake is paid
    once per call instead of once per problem. Threads: rayon's pool (``RAYON_NUM_THREADS``); Ctrl-C stops
    the call within about 50 ms.

    Parameters
    ----------
    float_ambiguities
        (k, n) float ambiguities, one problem per row, cycles; k >= 0, 1 <= n <= :data:`MAX_DIMENSION`.
    covariance
        (n, n) covariance shared by every problem, or (k, n, n) one per problem, cycles².
    candidates
        Number m of solutions wanted per problem, 1 <= m <= :data:`MAX_CANDIDATES`.

    Returns
    -------
    IlsBatchResult
        ``fixed`` (k, m, n), ``squared_norms`` (k, m) and ``nodes_visited`` (k,).

    Raises
    ------
    InvalidInputError, InvalidTypeError
        As :func:`lambda_ils`; the message of a problem's own failure (not positive definite...) starts with
        ``problem p``, the lowest-numbered failing problem.
    WorkLimitError
        As :func:`lambda_ils`, and ``k * (n**3 + 1000) > BATCH_MAX_WORK`` (checked before any work).
    ConvergenceError
        As :func:`lambda_ils` for the lowest-numbered problem that fails, or the searches of the batch
        together passed :data:`BATCH_MAX_SEARCH_WORK` work units (``nodes * (n + 16)``).

    Examples
    --------
    The :func:`lambda_ils` example and its integer shift by (3, -1), sharing one covariance:

    >>> import numpy as np
    >>> from gnssatt import lambda_ils_batch
    >>> out = lambda_ils_batch([[1.1, -2.05], [4.1, -3.05]], np.diag([0.01, 0.01]), candidates=1)
    >>> out.fixed[:, 0]
    array([[ 1, -2],
           [ 4, -3]])
    >>> np.round(out.squared_norms, 6)
    array([[1.25],
           [1.25]])
    """
    a = float_array("float_ambiguities", float_ambiguities, ndim=2, shape="(k, n)")
    q = float_array("covariance", covariance, ndim=(2, 3), shape="(n, n) or (k, n, n)")
    k, n = a.shape
    if q.ndim == 2:
        q = q[np.newaxis]
    if q.shape[1:] != (n, n) or q.shape[0] not in (1, k) or n == 0:
        raise InvalidInputError(
            f"expected covariance of shape (n, n) or (k, n, n) with n >= 1 matching float_ambiguities of "
            f"shape (k, n) = {a.shape}, got {q.shape[1:] if q.shape[0] == 1 else q.shape}"
        )
    if n > MAX_DIMENSION:
        raise WorkLimitError(
            f"covariance of shape {q.shape[1:]} has {n} ambiguities, more than the limit of {MAX_DIMENSION}"
        )
    work = k * (n**3 + 1000)
    if work > BATCH_MAX_WORK:
        raise WorkLimitError(
            f"float_ambiguities of shape {a.shape} asks for {work} work units (k * (n**3 + 1000)), more than "
            f"the limit of {BATCH_MAX_WORK} (BATCH_MAX_WORK): split the batch"
        )
    big = np.abs(a) >= MAX_ABS_AMBIGUITY
    if np.any(big):
        p, i = (int(v) for v in np.argwhere(big)[0])
        raise InvalidInputError(
            f"float_ambiguities is out of range: |float_ambiguities[{p}, {i}]| = {abs(a[p, i]):.6g} cycles "
            f"exceeds (or equals) MAX_ABS_AMBIGUITY = {MAX_ABS_AMBIGUITY:.6g} cycles"
        )
    m = integer("candidates", candidates, minimum=1, maximum=MAX_CANDIDATES)
    out = _core.lambda_ils_batch(a, q, m)
    return IlsBatchResult(out.fixed, out.squared_norms, out.nodes_visited)


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

    Raises
    ------
    InvalidInputError
        As :func:`lambda_ils` for the covariance.
    ConvergenceError
        ``Z`` would need entries beyond 2^52, or the identity ``Z.T Q Z = L.T D L`` fails its check.

    Examples
    --------
    A strongly correlated pair (variances 1.0 and 0.9): the difference of the two ambiguities, the last
    column of ``Z``, has variance ``1.0 - 2 * 0.94 + 0.9 = 0.02``:

    >>> import numpy as np
    >>> from gnssatt import lambda_decorrelate
    >>> Q = np.array([[1.0, 0.94], [0.94, 0.9]])
    >>> Z, L, D = lambda_decorrelate(Q)
    >>> Z
    array([[-2,  1],
           [ 3, -1]])
    >>> np.round(D, 6)
    array([0.82, 0.02])
    """
    out = _core.lambda_decorrelate(_covariance(covariance))
    return out.z, out.l, out.d


def bootstrap_success_rate(covariance: ArrayLike) -> float:
    """Success rate of integer bootstrapping on the decorrelated ambiguities, a lower bound of the ILS one.

    ``prod_i (2 Phi(1 / (2 sqrt(D_i))) - 1)`` with ``D`` from :func:`lambda_decorrelate`
    (Teunissen 1998, J. Geodesy 72:606-612).

    Parameters
    ----------
    covariance
        (n, n) symmetric positive-definite covariance of the float ambiguities, cycles².

    Returns
    -------
    float
        Probability in [0, 1] that bootstrapping fixes the correct integers.

    Raises
    ------
    InvalidInputError
        As :func:`lambda_ils` for the covariance.
    ConvergenceError
        As :func:`lambda_decorrelate`.

    Examples
    --------
    Two independent ambiguities of standard deviation 0.1 cycles: ``(2 Phi(5) - 1)^2``:

    >>> import numpy as np
    >>> from gnssatt import bootstrap_success_rate
    >>> round(bootstrap_success_rate(np.diag([0.01, 0.01])), 7)
    0.9999989
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
        Simulated float vectors, at least ``1 / failure_rate`` and at most :data:`MAX_SAMPLES`.
    seed
        Seed of the simulation (one independent stream per sample), 0 <= seed < 2^64.

    Returns
    -------
    float
        The threshold ``c >= 1``.

    Raises
    ------
    InvalidInputError
        As :func:`lambda_ils` for the covariance; ``failure_rate`` not in (0, 1) (an
        :class:`~gnssatt.errors.InvalidTypeError` when it is not a real number, ``None`` included).
    WorkLimitError
        ``samples > MAX_SAMPLES``.
    ConvergenceError
        A simulated search exceeded its share of the 1e9 nodes of the whole simulation.

    Examples
    --------
    A 1 % failure rate for two independent ambiguities of standard deviation 0.32 cycles, from 10,000
    seeded samples (the same seed gives the same ``c``):

    >>> import numpy as np
    >>> from gnssatt import ratio_threshold_fixed_failure_rate
    >>> c = ratio_threshold_fixed_failure_rate(np.diag([0.1, 0.1]), 0.01, samples=10_000, seed=0)
    >>> round(c, 2)
    12.91
    """
    q = _covariance(covariance)
    rate = scalar("failure_rate", failure_rate, minimum=0.0, maximum=1.0, strict=True)
    checked = _threshold(None, rate, samples, seed)
    return _core.lambda_ffrt_threshold(q, rate, checked["samples"], checked["seed"])


@dataclass(frozen=True)
class RatioTestResult:
    """Outcome of :func:`ratio_test`.

    Attributes
    ----------
    accepted
        ``ratio >= threshold``.
    ratio
        Second-best over best squared norm; ``inf`` (and ``accepted``) when the best squared norm is 0, i.e.
        the float vector is an integer vector to double precision.
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
    samples, seed
        Simulated float vectors and seed of that simulation, as in
        :func:`ratio_threshold_fixed_failure_rate`; unused with a fixed ``threshold``.

    Returns
    -------
    RatioTestResult
        Acceptance, ratio, threshold used, the best integer vector and the two best squared norms.

    Raises
    ------
    InvalidInputError
        As :func:`lambda_ils`; both ``threshold`` and ``failure_rate`` given; threshold < 1; failure rate
        outside (0, 1); fewer than ``1 / failure_rate`` samples.
    WorkLimitError, ConvergenceError
        As :func:`lambda_ils` and :func:`ratio_threshold_fixed_failure_rate`; the two candidates are exact
        or the call raises. ``ConvergenceError`` also when both squared norms underflow to 0 (the ratio
        would be 0/0).

    Examples
    --------
    The ratio of the two best squared norms of the :func:`lambda_ils` example, ``81.25 / 1.25 = 65``, passes
    the default threshold 3:

    >>> import numpy as np
    >>> from gnssatt import ratio_test
    >>> result = ratio_test([1.1, -2.05], np.diag([0.01, 0.01]))
    >>> bool(result.accepted), round(result.ratio, 6), result.fixed
    (True, 65.0, array([ 1, -2]))
    """
    a, q = _problem(float_ambiguities, covariance)
    out = _core.lambda_ratio_test(a, q, **_threshold(threshold, failure_rate, samples, seed))
    accepted, ratio, c, fixed, norms = out.accepted, out.ratio, out.threshold, out.fixed, out.squared_norms
    _defined_ratio("ratio_test", ratio, norms)
    return RatioTestResult(bool(accepted), ratio, c, fixed, norms)


def _defined_ratio(what: str, ratio: float, norms: Any) -> None:
    """Refuse a 0/0 ratio (both squared norms underflow to 0): it cannot be answered in double precision."""
    if np.isnan(ratio):
        raise ConvergenceError(
            f"{what}: the ratio of the squared norms {np.asarray(norms).tolist()} is 0/0: the "
            "float_ambiguities are too close to integers for the covariance to tell the candidates apart "
            "in double precision"
        )


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
        Ratio statistic of the fixed subset and the threshold it passed; both NaN ("not available") when
        k = 0, and ``ratio`` is ``inf`` when the subset's float values are integers to double precision.
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

    Returns
    -------
    PartialFixResult
        The number of fixed decorrelated ambiguities, their integer combinations and values, the ratio and
        threshold of the subset fixed, its bootstrapped success rate, and the float ambiguities and covariance
        conditioned on it.

    Raises
    ------
    InvalidInputError, WorkLimitError, ConvergenceError
        As :func:`ratio_test`; the norms of each subset are recomputed from ``Z_k.T @ a`` and
        ``Z_k.T @ Q @ Z_k`` and checked, and the fixed values are exact integers within
        :data:`MAX_ABS_AMBIGUITY`, or the call raises.

    Examples
    --------
    Three correlated ambiguities whose full set fails the ratio test (ratio 1.41 < 3); the two most precise
    decorrelated ambiguities pass it and are fixed:

    >>> import numpy as np
    >>> from gnssatt import partial_fix
    >>> Q = np.array([[6.29, 5.978, 0.544], [5.978, 6.292, 2.340], [0.544, 2.340, 6.288]])
    >>> result = partial_fix([5.45, 3.10, 2.97], Q)
    >>> result.fixed_count, round(result.ratio, 2), result.values
    (2, 3.49, array([10,  2]))
    """
    a, q = _problem(float_ambiguities, covariance)
    settings = _threshold(threshold, failure_rate, samples, seed)
    rate = scalar("min_success_rate", min_success_rate, minimum=0.0, maximum=1.0)
    out = _core.lambda_partial_fix(a, q, **settings, min_success_rate=rate)
    k, combos, values, ratio = out.fixed_count, out.combinations, out.values, out.ratio
    c, sr, amb, cov = out.threshold, out.success_rate, out.ambiguities, out.covariance
    if int(k) > 0:
        _defined_ratio("partial_fix", ratio, [ratio])
    return PartialFixResult(int(k), combos, values, ratio, c, sr, amb, cov)
