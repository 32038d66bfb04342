"""Every argument of every public function, replaced by each fixed hostile value of issue 15 (wrong shape,
complex, bool, object, text, None, NaN, +-inf, 1e300, 1e-300, subnormal, negative, zero, overflow-size
counts, absurd work), and by the widened categories (memory layouts, dtypes, lists, masked arrays, overflow,
signed zero, NaN at either end, zero-stride views of 2^40 rows, 0-d forms, junk text and paths, seeds,
rotations of NaN, broken executors): the answer is a finite result or a refusal of the right class naming
the argument; the valid value in another form (layout, list, 0-d) must be accepted."""

from __future__ import annotations

import pytest

from . import harness
from . import inventory as inv
from .conftest import report
from .worker import Pool


@pytest.mark.slow
@pytest.mark.parametrize("name", sorted(inv.ENTRIES))
def test_fixed_mutations_keep_the_contract(pool: Pool, name: str) -> None:
    records = harness.run_fixed(pool, [name])
    # every function with an argument gets mutants (a function without arguments has nothing to mutate)
    assert records or not inv.ENTRIES[name].build(), "no mutation generated"
    bad = [r.line() for r in harness.failures(records)]
    assert not bad, report(bad)
