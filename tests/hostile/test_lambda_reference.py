"""LAMBDA right or refusing: ``lambda_ils``'s best integer vector against an independent search
(``references/lambda_reference.py``: LLL + Schnorr-Euchner, brute-force checked by
``tests/test_lambda_reference.py``) on ill-conditioned SPD covariances
up to n = 64 and condition 1e10, fixed seeds."""

from __future__ import annotations

import numpy as np
import pytest
from references import lambda_reference as ref

from . import outcomes as oc
from .worker import Job, Pool

# (n, condition): one seed each here (the reference's LLL costs up to 10 s at n = 64 on a loaded machine);
# benches/python/hostile_inputs.py --lambda-cases N draws more.
SIZES = [(8, 1e4), (16, 1e6), (24, 1e8), (32, 1e5), (40, 1e7), (64, 1e8), (48, 1e10), (64, 1e10)]
CASES = [(1000 * n + 1, n, c) for n, c in SIZES]  # seeds whose reference search fits its budget
# |f - f_ref| tolerance, relative: squared norms from two Cholesky solves of a Q of condition c agree to
# about c * n * eps (1e10 * 64 * 2.2e-16 = 1.4e-4 at the largest case); 10x that leaves a margin.
ABS_TOL = 1e-6


def rel_tol(case: ref.Case) -> float:
    return 10.0 * float(np.linalg.cond(case.q)) * case.a.size * float(np.finfo(float).eps)


def judge(pool: Pool, case: ref.Case) -> tuple[str, str]:
    """Outcome of ``lambda_ils`` on ``case``: ``refused-ok`` (ConvergenceError/WorkLimitError),
    ``accepted-finite`` (the reference's minimum, its squared norm right), or a failure; ``skip`` where the
    reference exhausts its budget."""
    best = ref.reference_best(case)
    if best is None:
        return "skip", "reference budget exhausted"
    job = Job(
        "gnssatt.lambda_ils",
        kwargs={"float_ambiguities": case.a, "covariance": case.q, "candidates": 2},
        want_result=True,
    )
    a = pool.run(job)
    if a.outcome != oc.ACCEPTED:
        if a.outcome == oc.REFUSED and a.detail.startswith(("ConvergenceError", "WorkLimitError")):
            return oc.REFUSED, a.detail
        return (a.outcome if a.outcome != oc.REFUSED else oc.LAMBDA_WRONG), a.detail
    fixed, norms = a.result
    f_ref = ref.squared_norm(case.a, case.q, best)
    f = ref.squared_norm(case.a, case.q, fixed[0])
    if f > f_ref * (1 + rel_tol(case)) + ABS_TOL:
        return oc.LAMBDA_WRONG, f"best has squared norm {f:.6g}, the reference found {f_ref:.6g}"
    if abs(norms[0] - f) > rel_tol(case) * f + ABS_TOL:
        return oc.LAMBDA_WRONG, f"reported squared norm {norms[0]:.6g}, recomputed {f:.6g}"
    return oc.ACCEPTED, ""


@pytest.mark.slow
@pytest.mark.parametrize(("seed", "n", "condition"), CASES)
def test_lambda_ils_finds_the_best_integer_or_refuses(
    pool: Pool, seed: int, n: int, condition: float
) -> None:
    outcome, detail = judge(pool, ref.make_case(seed, n, condition))
    if outcome == "skip":
        pytest.skip(detail)
    assert outcome in (oc.ACCEPTED, oc.REFUSED), (
        f"n={n} condition={condition:.0e} seed={seed}: {outcome}: {detail}"
    )
