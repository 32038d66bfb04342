"""Enumerating hostile calls and recording their outcomes: shared by the tests and the counting script."""

from __future__ import annotations

from collections import Counter
from collections.abc import Iterable, Iterator
from dataclasses import dataclass

import numpy as np

from . import inventory as inv
from . import outcomes as oc
from .worker import Job, Pool, fixed_mutants


@dataclass(frozen=True)
class Record:
    """One hostile call: where (module, function, parameter), what (category, label) and what happened."""

    module: str
    function: str
    param: str
    category: str
    label: str
    outcome: str
    detail: str = ""

    @property
    def failed(self) -> bool:
        return self.outcome in oc.FAILURES

    def line(self) -> str:
        return f"{self.function}  {self.param}  {self.category} ({self.label}): {self.outcome}: {self.detail}"


def module_of(function: str) -> str:
    return function.rsplit(".", 1)[0]


def fixed_jobs(entry_name: str) -> Iterator[tuple[Job, str, str, str]]:
    """(job, parameter, category, label) for every fixed mutant of every argument of one entry."""
    entry = inv.ENTRIES[entry_name]
    for param in entry.build():
        seen: Counter[str] = Counter()
        for m in fixed_mutants(entry_name, param):
            index = seen[m.category]
            seen[m.category] += 1
            job = Job(entry_name, entry_name, param, (m.category, index))
            yield job, param, m.category, m.label


def run_fixed(pool: Pool, entry_names: Iterable[str]) -> list[Record]:
    records = []
    for name in entry_names:
        for job, param, category, label in fixed_jobs(name):
            a = pool.run(job)
            records.append(Record(module_of(name), name, param, category, label, a.outcome, a.detail))
    return records


#: Leading axes of the batch-size dimension: a zero-stride view costs nothing to pass, so a call must answer
#: within the hang limit (a result, or a refusal such as WorkLimitError) at any of them.
BATCH_ROWS = (10**6, 10**7)


def batch_params(entry_name: str) -> list[str]:
    """The arguments of an entry that are numeric arrays with a leading axis (the candidates for a batch)."""
    out = []
    for param, value in inv.ENTRIES[entry_name].build().items():
        if isinstance(value, np.ndarray) and value.ndim >= 1 and value.size and value.dtype.kind in "fiu":
            out.append(param)
    return out


def run_batch(
    pool: Pool, entry_names: Iterable[str], rows: Iterable[int] = BATCH_ROWS, only: str | None = None
) -> list[Record]:
    """Each batch candidate (or the one named ``only``) of each entry broadcast to each axis of ``rows``."""
    records = []
    for name in entry_names:
        for param in batch_params(name) if only is None else [only]:
            for n in rows:
                a = pool.run(Job(name, name, param, batch_rows=n))
                records.append(
                    Record(module_of(name), name, param, "batch-size", f"{n} rows", a.outcome, a.detail)
                )
    return records


def failures(records: Iterable[Record]) -> list[Record]:
    return [r for r in records if r.failed]
