"""The inventory covers every public function, and each valid example call succeeds with finite results
(the harness's own test: a mutation of a call that already failed would prove nothing)."""

from __future__ import annotations

import pytest

from . import inventory as inv
from . import outcomes as oc
from .worker import Job, Pool


def test_every_public_function_has_an_entry() -> None:
    public = set(inv.public_functions())
    missing = sorted(public - set(inv.ENTRIES))
    stale = sorted(set(inv.ENTRIES) - public)
    assert not missing, f"public functions without a valid example in tests/hostile/inventory.py: {missing}"
    assert not stale, f"inventory entries for functions that are not public (any more): {stale}"


@pytest.mark.parametrize("name", sorted(inv.ENTRIES))
def test_valid_call_succeeds(pool: Pool, name: str) -> None:
    answer = pool.run(Job(name, name))
    assert answer.outcome == oc.ACCEPTED, f"{name}: {answer.outcome}: {answer.detail}"
