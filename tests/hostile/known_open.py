"""Public functions whose hostile-input contract is not met yet, per test, with the reason.

Each entry turns that function's test into a strict xfail: while the contract fails the run stays green
and the gap stays listed here (and in docs/robustness.md); once the function is fixed the test passes,
``xfail_strict`` fails the run, and the entry must be deleted. Nothing is added here to hide a regression:
an entry needs an open issue behind it.
"""

from __future__ import annotations

import pytest

#: function -> reason, for tests/hostile/test_fixed_mutations.py
FIXED: dict[str, str] = {}

#: function -> reason, for tests/hostile/test_properties.py
HYPOTHESIS: dict[str, str] = {}


def params(names: list[str], known: dict[str, str]) -> list[object]:
    """``names`` as pytest parameters, the known-open ones marked as strict xfails."""
    return [
        pytest.param(n, marks=pytest.mark.xfail(strict=True, reason=known[n])) if n in known else n
        for n in names
    ]
