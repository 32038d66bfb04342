"""An independent integer least-squares search, and ill-conditioned cases to check ``lambda_ils`` against.

The reference minimises ``(a - z)' inv(Q) (a - z)`` over integer ``z`` with its own LLL reduction (on the
upper-triangular factor ``R`` of ``inv(Q) = R'R``, integer column operations tracked exactly in Python
integers) followed by a Schnorr-Euchner enumeration with a node budget. Nothing here comes from the
library's LAMBDA (which decorrelates ``Q`` with ``L'DL`` and searches on the conditional variances).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray
from scipy.linalg import cho_factor, cho_solve

LLL_DELTA = 0.99
Z_LIMIT = 2**40
GEOMETRIC_MEAN = 0.005  # cycles^2: conditional standard deviations of about 0.07 cycle


@dataclass(frozen=True)
class Case:
    """One problem: float ambiguities ``a`` (n,) and SPD covariance ``q`` (n, n), cycles and cycles^2."""

    seed: int
    n: int
    condition: float
    a: NDArray[np.float64]
    q: NDArray[np.float64]


def make_case(seed: int, n: int, condition: float) -> Case:
    """Random SPD ``q = U diag(s) U'`` (Haar ``U``; eigenvalues log-spaced over ``condition`` around a
    geometric mean of ``GEOMETRIC_MEAN`` cycles^2, so that the problem is ill-conditioned like the
    ambiguities of a short span, yet has a well-defined best integer) and ``a`` = integers in [-1e3, 1e3] +
    a draw from N(0, q)."""
    rng = np.random.default_rng(seed)
    u, r = np.linalg.qr(rng.normal(size=(n, n)))
    u *= np.sign(np.diag(r))
    half = 0.5 * np.log10(condition)
    s = GEOMETRIC_MEAN * np.logspace(half, -half, n)
    q = (u * s) @ u.T
    q = 0.5 * (q + q.T)
    a = rng.integers(-1000, 1001, size=n) + np.linalg.cholesky(q) @ rng.normal(size=n)
    return Case(seed, n, condition, a, q)


def squared_norm(a: NDArray[np.float64], q: NDArray[np.float64], z: NDArray[np.int64]) -> float:
    """``(a - z)' inv(q) (a - z)`` through a Cholesky solve of the original ``q``."""
    d = a - np.asarray(z, dtype=np.float64)
    return float(d @ cho_solve(cho_factor(q), d))


def _lll(
    r: NDArray[np.float64], y: NDArray[np.float64]
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.int64]] | None:
    """LLL-reduce the columns of upper-triangular ``r`` with Givens rotations (carried into ``y``); returns
    the reduced ``r``, rotated ``y`` and the unimodular integer ``Z`` with ``r_in Z = Q r_out``, or None if
    an entry of ``Z`` leaves ``Z_LIMIT`` (where int64 arithmetic would no longer be exact)."""
    n = r.shape[0]
    r = r.copy()
    y = y.copy()
    z = np.eye(n, dtype=np.int64)

    def reduce(i: int, k: int) -> bool:
        mu = np.rint(r[i, k] / r[i, i])
        if mu:
            if abs(mu) > Z_LIMIT:
                return False
            r[: i + 1, k] -= mu * r[: i + 1, i]
            z[:, k] -= np.int64(mu) * z[:, i]
            return bool(np.abs(z[:, k]).max() <= Z_LIMIT)
        return True

    k = 1
    while k < n:
        if not reduce(k - 1, k):
            return None
        if LLL_DELTA * r[k - 1, k - 1] ** 2 > r[k - 1, k] ** 2 + r[k, k] ** 2:
            r[:, [k - 1, k]] = r[:, [k, k - 1]]
            z[:, [k - 1, k]] = z[:, [k, k - 1]]
            a, b = r[k - 1, k - 1], r[k, k - 1]
            h = np.hypot(a, b)
            g = np.array([[a / h, b / h], [-b / h, a / h]])
            r[k - 1 : k + 1, k - 1 :] = g @ r[k - 1 : k + 1, k - 1 :]
            r[k, k - 1] = 0.0
            y[k - 1 : k + 1] = g @ y[k - 1 : k + 1]
            k = max(k - 1, 1)
        else:
            for i in range(k - 2, -1, -1):
                if not reduce(i, k):
                    return None
            k += 1
    return r, y, z


def _search(r: NDArray[np.float64], y: NDArray[np.float64], budget: int) -> NDArray[np.float64] | None:
    """Schnorr-Euchner enumeration of ``min ||y - r u||`` over integer ``u``; None when ``budget`` nodes do
    not suffice."""
    n = r.shape[0]
    u = np.zeros(n)
    c = np.zeros(n)
    step = np.zeros(n)
    partial = np.zeros(n + 1)  # partial[k]: squared distance of levels k..n-1
    best: NDArray[np.float64] | None = None
    radius = np.inf
    k = n - 1
    c[k] = y[k] / r[k, k]
    u[k] = np.round(c[k])
    step[k] = np.sign(c[k] - u[k]) or 1.0
    nodes = 0
    while True:
        nodes += 1
        if nodes > budget:
            return None
        d = partial[k + 1] + (r[k, k] * (c[k] - u[k])) ** 2
        if d < radius:
            if k == 0:
                best, radius = u.copy(), d
            else:
                partial[k] = d
                k -= 1
                c[k] = (y[k] - r[k, k + 1 :] @ u[k + 1 :]) / r[k, k]
                u[k] = np.round(c[k])
                step[k] = np.sign(c[k] - u[k]) or 1.0
                continue
        else:
            if k == n - 1:
                return best
            k += 1
        # next candidate at level k, zig-zagging around c[k]
        u[k] += step[k]
        step[k] = -step[k] - np.sign(step[k])


def reference_best(case: Case, budget: int = 200_000) -> NDArray[np.int64] | None:
    """The integer minimiser of ``case``, or None when the reference cannot certify it (budget spent, or
    its own reduction left the range where float64 is exact)."""
    w = np.linalg.inv(case.q)
    w = 0.5 * (w + w.T)
    r = np.linalg.cholesky(w).T  # w = r' r
    reduced = _lll(r, r @ case.a)
    if reduced is None:
        return None
    rr, yy, z = reduced
    u = _search(rr, yy, budget)
    if u is None:
        return None
    # exact in Python integers: Z u with |Z| <= 2^40 and |u| far below 2^53
    best = [sum(int(z[i, j]) * int(u[j]) for j in range(len(u))) for i in range(len(u))]
    if max(abs(v) for v in best) > 2**62:
        return None
    return np.array(best, dtype=np.int64)
