"""An independent integer least-squares solver, and the ill-conditioned problems to check LAMBDA against.

The solver minimises ``(a - z)' inv(Q) (a - z)`` over integer ``z`` for the m best ``z``: LLL reduction of the
upper-triangular factor ``R`` of ``inv(Q) = R'R`` (Lenstra, Lenstra & Lovasz 1982, Lovasz condition 0.99, with
Givens rotations; the integer column operations tracked exactly, refused past 2^40), then a Schnorr-Euchner
enumeration (Schnorr & Euchner 1994) of the reduced lattice with a shrinking radius and a node budget; the
squared norms are recomputed with scipy's Cholesky solve of the original ``Q``. Nothing here comes from the
library's LAMBDA, which decorrelates ``Q`` itself with ``L'DL`` and searches on the conditional variances
(the reduction of the dual lattice, in the opposite order). ``brute_force`` checks the solver where a box can
be listed.
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray
from scipy.linalg import cho_factor, cho_solve

LLL_DELTA = 0.99
Z_LIMIT = 2**40
GEOMETRIC_MEAN = 0.005  # cycles^2: conditional standard deviations of about 0.07 cycle


# ---------------------------------------------------------------- the covariances


def spectrum_covariance(rng: np.random.Generator, n: int, cond: float) -> NDArray[np.float64]:
    """``U diag(s) U.T``: random orthogonal U, s log-spaced from 1 to 1 / cond (condition number cond)."""
    u, _ = np.linalg.qr(rng.standard_normal((n, n)))
    s = np.logspace(0.0, -np.log10(cond), n)
    q = (u * s) @ u.T
    return (q + q.T) / 2


def geometry_covariance(rng: np.random.Generator, n: int, cond: float) -> NDArray[np.float64]:
    """The structure of GNSS float ambiguities: a few poorly determined directions (baseline and clock, from
    the code) over a well determined floor (the phase), ``H (H.T H)^-1 H.T + I / cond`` with H (n, 4)."""
    h = rng.standard_normal((n, min(4, n)))
    q = h @ np.linalg.solve(h.T @ h, h.T) + np.eye(n) / cond
    return (q + q.T) / 2


@dataclass(frozen=True)
class Case:
    """One problem: float ambiguities ``a`` (n,) and SPD covariance ``q`` (n, n), cycles and cycles^2, drawn
    around the integers ``truth``."""

    seed: int
    n: int
    condition: float
    a: NDArray[np.float64]
    q: NDArray[np.float64]
    truth: NDArray[np.int64]


def make_case(
    seed: int, n: int, condition: float, scale: float = GEOMETRIC_MEAN, centred: bool = True
) -> Case:
    """Random SPD ``q = U diag(s) U'`` (Haar ``U``; eigenvalues log-spaced over ``condition``) and ``a`` =
    integers in [-1e3, 1e3] + a draw from N(0, q).

    ``centred``: eigenvalues around a geometric mean of ``scale`` cycles^2 (conditional standard deviations
    of about 0.07 cycle at the default: ill-conditioned like the ambiguities of a short span, yet with a
    well-defined best integer); otherwise from ``scale`` down to ``scale / condition`` (issue 31's form,
    ``Q = (q * (0.05 * logspace(0, -log10(condition), n))) @ q.T``)."""
    rng = np.random.default_rng(seed)
    u, r = np.linalg.qr(rng.normal(size=(n, n)))
    u *= np.sign(np.diag(r))
    if centred:
        half = 0.5 * np.log10(condition)
        s = scale * np.logspace(half, -half, n)
    else:
        s = scale * np.logspace(0.0, -np.log10(condition), n)
    q = (u * s) @ u.T
    q = 0.5 * (q + q.T)
    truth = rng.integers(-1000, 1001, size=n)
    a = truth + np.linalg.cholesky(q) @ rng.normal(size=n)
    return Case(seed, n, condition, a, q, truth)


def squared_norm(a: NDArray[np.float64], q: NDArray[np.float64], z: NDArray[np.int64]) -> float:
    """``(a - z)' inv(q) (a - z)`` through a Cholesky solve of the original ``q``."""
    d = a - np.asarray(z, dtype=np.float64)
    return float(d @ cho_solve(cho_factor(q), d))


# ---------------------------------------------------------------- the solver


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


def _search(
    r: NDArray[np.float64], y: NDArray[np.float64], m: int, budget: int
) -> tuple[list[tuple[float, NDArray[np.float64]]] | None, int]:
    """Schnorr-Euchner enumeration of the m integer ``u`` minimising ``||y - r u||``: (the m best as (squared
    distance, u), ascending; None when ``budget`` nodes do not suffice) and the nodes visited (integer
    values tried at any level)."""
    n = r.shape[0]
    u = np.zeros(n)
    c = np.zeros(n)
    step = np.zeros(n)
    partial = np.zeros(n + 1)  # partial[k]: squared distance of levels k..n-1
    best: list[tuple[float, NDArray[np.float64]]] = []
    radius = np.inf
    k = n - 1
    c[k] = y[k] / r[k, k]
    u[k] = np.round(c[k])
    step[k] = np.sign(c[k] - u[k]) or 1.0
    nodes = 0
    while True:
        nodes += 1
        if nodes > budget:
            return None, nodes - 1
        d = partial[k + 1] + (r[k, k] * (c[k] - u[k])) ** 2
        if d < radius:
            if k == 0:
                best.append((d, u.copy()))
                best.sort(key=lambda t: t[0])
                del best[m:]
                if len(best) == m:
                    radius = best[-1][0]
            else:
                partial[k] = d
                k -= 1
                c[k] = (y[k] - r[k, k + 1 :] @ u[k + 1 :]) / r[k, k]
                u[k] = np.round(c[k])
                step[k] = np.sign(c[k] - u[k]) or 1.0
                continue
        else:
            if k == n - 1:
                return best, nodes
            k += 1
        # next candidate at level k, zig-zagging around c[k]
        u[k] += step[k]
        step[k] = -step[k] - np.sign(step[k])


@dataclass(frozen=True)
class Solution:
    """The reference's answer: ``fixed`` (m, n) best first, their ``squared_norms`` (m,) from scipy, and the
    ``nodes`` its enumeration visited."""

    fixed: NDArray[np.int64]
    squared_norms: NDArray[np.float64]
    nodes: int


def reference_ils(
    a: NDArray[np.float64], q: NDArray[np.float64], m: int = 1, budget: int = 200_000
) -> Solution | None:
    """The m best integer vectors of ``(a, q)``, or None when the reference cannot certify them (its node
    budget spent, or its reduction left the range where float64 is exact)."""
    offset = np.round(a)
    w = np.linalg.inv(q)
    w = 0.5 * (w + w.T)
    r = np.linalg.cholesky(w).T  # w = r' r
    reduced = _lll(r, r @ (a - offset))
    if reduced is None:
        return None
    rr, yy, z = reduced
    found, nodes = _search(rr, yy, m, budget)
    if found is None or len(found) < m:
        return None
    fixed = []
    for _, u in found:
        # exact in Python integers: Z u with |Z| <= 2^40 and |u| far below 2^53
        v = [int(offset[i]) + sum(int(z[i, j]) * int(u[j]) for j in range(len(u))) for i in range(len(u))]
        if max(abs(x) for x in v) > 2**62:
            return None
        fixed.append(v)
    fz = np.array(fixed, dtype=np.int64)
    norms = np.array([squared_norm(a, q, row) for row in fz])
    order = np.argsort(norms, kind="stable")
    return Solution(fz[order], norms[order], nodes)


def reference_best(case: Case, budget: int = 200_000) -> NDArray[np.int64] | None:
    """The integer minimiser of ``case``, or None when the reference cannot certify it."""
    sol = reference_ils(case.a, case.q, 1, budget)
    return None if sol is None else sol.fixed[0]


def brute_force(
    a: NDArray[np.float64], q: NDArray[np.float64], m: int
) -> tuple[NDArray[np.int64], NDArray[np.float64]]:
    """The m best integer vectors of a box that provably holds them (small n only): the m-th best norm among
    the rounded vector and its neighbours within one bounds the ellipsoid, which lies in the box
    ``|a_i - z_i| <= sqrt(chi2 Q_ii)``."""
    qinv = np.linalg.inv(q)
    r0 = np.round(a)
    seeds = r0 + np.array(list(itertools.product([-1.0, 0.0, 1.0], repeat=a.size)))
    res = a - seeds
    chi2 = np.sort(np.einsum("ki,ij,kj->k", res, qinv, res))[m - 1]
    half = np.sqrt(chi2 * np.diag(q))
    ranges = [range(int(np.floor(x - h)), int(np.ceil(x + h)) + 1) for x, h in zip(a, half, strict=True)]
    cand = np.array(list(itertools.product(*ranges)), dtype=float)
    res = a - cand
    norms = np.einsum("ki,ij,kj->k", res, qinv, res)
    order = np.argsort(norms, kind="stable")[:m]
    return cand[order].astype(np.int64), norms[order]
