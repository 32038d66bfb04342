"""gnssatt.lambda_ils_batch: the answers of one lambda_ils call per problem, its limits checked before any
work, failures named by problem."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

import gnssatt
from gnssatt.ambiguity import BATCH_MAX_WORK
from gnssatt.errors import ConvergenceError, InvalidInputError, WorkLimitError


def _problems(rng: np.random.Generator, k: int, n: int) -> tuple[np.ndarray, np.ndarray]:
    h = rng.standard_normal((k, n, n))
    q = h @ h.transpose(0, 2, 1) * 0.05 / n + 0.002 * np.eye(n)
    a = rng.integers(-100, 100, (k, n)) + rng.normal(0, 0.3, (k, n))
    return a, q


@pytest.mark.parametrize("n", [1, 4, 12, 30])
def test_batch_equals_one_call_per_problem(n: int) -> None:
    rng = np.random.default_rng(n)
    a, q = _problems(rng, 25, n)
    for cov in (q, q[0]):
        out = gnssatt.lambda_ils_batch(a, cov, candidates=3)
        assert out.fixed.shape == (25, 3, n) and out.squared_norms.shape == (25, 3)
        assert out.nodes_visited.shape == (25,)
        for p in range(25):
            fixed, norms = gnssatt.lambda_ils(a[p], cov if cov.ndim == 2 else cov[p], candidates=3)
            np.testing.assert_array_equal(out.fixed[p], fixed)
            np.testing.assert_array_equal(out.squared_norms[p], norms)


def test_result_is_frozen_and_empty_batches_work() -> None:
    out = gnssatt.lambda_ils_batch(np.zeros((0, 3)), np.eye(3), candidates=2)
    assert out.fixed.shape == (0, 2, 3) and out.squared_norms.shape == (0, 2)
    with pytest.raises(dataclasses.FrozenInstanceError):
        out.fixed = out.fixed  # type: ignore[misc]


def test_bad_input_is_refused_with_its_name() -> None:
    a = np.zeros((4, 3))
    with pytest.raises(InvalidInputError, match="covariance"):
        gnssatt.lambda_ils_batch(a, np.eye(2))
    with pytest.raises(InvalidInputError, match="covariance"):
        gnssatt.lambda_ils_batch(a, np.broadcast_to(np.eye(3), (3, 3, 3)))
    with pytest.raises(InvalidInputError, match="float_ambiguities"):
        gnssatt.lambda_ils_batch(np.zeros(3), np.eye(3))
    with pytest.raises(InvalidInputError, match="float_ambiguities"):
        gnssatt.lambda_ils_batch([[np.nan, 0, 0]], np.eye(3))
    with pytest.raises(InvalidInputError, match="candidates"):
        gnssatt.lambda_ils_batch(a, np.eye(3), candidates=0)
    # problem 2 of 4 is not positive definite: the message names it
    q = np.broadcast_to(np.eye(3), (4, 3, 3)).copy()
    q[2] = [[1, 2, 0], [2, 1, 0], [0, 0, 1]]
    q[3] = q[2]
    with pytest.raises(InvalidInputError, match=r"problem 2: .*not positive definite"):
        gnssatt.lambda_ils_batch(a, q)


def test_work_limit_is_checked_before_any_work() -> None:
    n = 64
    k = BATCH_MAX_WORK // (n**3 + 1000) + 1
    a = np.broadcast_to(np.full(n, 0.2), (k, n))
    with pytest.raises(WorkLimitError, match=r"BATCH_MAX_WORK"):
        gnssatt.lambda_ils_batch(a, np.eye(n))
    # one problem fewer is within the limit (only counted here: solving it would take seconds)
    assert (k - 1) * (n**3 + 1000) <= BATCH_MAX_WORK


def test_a_refused_search_names_its_problem() -> None:
    # issue 31's second best at n = 45 exceeds the node budget: the batch says which problem it was
    rng = np.random.default_rng(45)
    n = 45
    u, _ = np.linalg.qr(rng.standard_normal((n, n)))
    q = (u * (0.05 * np.logspace(0, -6, n))) @ u.T
    q = (q + q.T) / 2
    a = rng.integers(-9, 9, (2, n)) + rng.standard_normal((2, n)) @ np.linalg.cholesky(q).T
    easy = gnssatt.lambda_ils_batch(a, q, candidates=1)
    assert np.all(easy.nodes_visited <= 4 * n)
    with pytest.raises(ConvergenceError, match="problem 0"):
        gnssatt.lambda_ils_batch(a[:1], q, candidates=2)
