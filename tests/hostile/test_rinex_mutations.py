"""Mutated RINEX files (``rinex_mutations``, fixed seed): readers refuse what must be refused with a
RinexError naming the file, and nothing crashes."""

from __future__ import annotations

import pytest

from . import outcomes as oc
from . import rinex_mutations as rm
from . import scenario
from .conftest import report
from .worker import Job, Pool

RANDOM_PER_FILE = 4
SEED = 15


def run_mutant(pool: Pool, m: rm.FileMutant, index: int) -> tuple[str, str]:
    path = scenario.folder() / f"mutant-{index}-{m.source}"
    path.write_bytes(m.text)
    a = pool.run(
        Job(
            m.reader, kwargs={"path": path}, names=(path.name,), must_refuse=m.must_refuse, nan_output_ok=True
        )
    )
    # missing observations and absent header fields are NaN by design: finiteness is checked through the
    # field edits instead (a non-finite value must be refused)
    return a.outcome, a.detail


def mutants() -> list[rm.FileMutant]:
    s = scenario.rinex_array()
    return rm.file_mutants(rm.default_sources(s.obs_paths[0], s.nav_path), RANDOM_PER_FILE, SEED)


@pytest.mark.slow
@pytest.mark.parametrize("category", ["field-edit", "truncate", "byte-flip"])
def test_mutated_rinex_files(pool: Pool, category: str) -> None:
    bad = []
    for i, m in enumerate(mutants()):
        if m.category != category:
            continue
        outcome, detail = run_mutant(pool, m, i)
        if outcome in oc.FAILURES:
            bad.append(f"{m.reader} {m.source} {m.category} ({m.label}): {outcome}: {detail}")
    assert not bad, report(bad)
