"""Property-based: hypothesis draws, for one argument at a time, arrays of nearby shapes and random dtypes
holding any floats (NaN, infinities, subnormals, 1e308), or junk scalars (None, text, huge integers,
complex). Derandomized with a bounded number of examples per function, so the run is deterministic."""

from __future__ import annotations

import inspect
from typing import Any

import numpy as np
import pytest
from hypothesis import HealthCheck, Phase, given, settings
from hypothesis import seed as hypothesis_seed
from hypothesis import strategies as st
from valid_calls import resolve

from . import harness
from . import inventory as inv
from . import mutations as mu
from . import outcomes as oc
from .conftest import report
from .worker import Job, Pool

EXAMPLES = 8


def drawn_job(name: str, data: st.DataObject) -> tuple[Job, str, Any]:
    entry = inv.ENTRIES[name]
    valid = entry.build()
    param = data.draw(st.sampled_from(sorted(valid)), label="param")
    value = data.draw(mu.hostile_value(valid[param]), label="value")
    none_ok = mu.none_ok(param, inspect.signature(resolve(name)).parameters[param].default)
    refuse = mu.must_refuse_drawn(
        value, mu.kind(valid[param]), nonfinite_ok=entry.arg(param).nonfinite_ok, none_ok=none_ok
    )
    if entry.arg(param).complex_ok and isinstance(value, np.ndarray) and value.dtype.kind == "c":
        # documented complex input: refusal only for what a real array would be refused for
        refuse = mu.must_refuse_drawn(
            value.real, mu.kind(valid[param]), nonfinite_ok=entry.arg(param).nonfinite_ok, none_ok=none_ok
        ) or not np.all(np.isfinite(value))
    job = Job(name, name, param, value=value, must_refuse=refuse)
    return job, param, value


def run_drawn(pool: Pool, name: str, examples: int, seed: int | None = None) -> list[harness.Record]:
    """``examples`` hypothesis draws for one function (no shrinking: every outcome is recorded instead);
    derandomized, or drawn from ``seed`` (the same seed, the same draws)."""
    records: list[harness.Record] = []

    @settings(
        max_examples=examples,
        derandomize=seed is None,
        database=None,
        deadline=None,
        phases=[Phase.generate],
        suppress_health_check=list(HealthCheck),
    )
    @given(st.data())
    def draw(data: st.DataObject) -> None:
        job, param, value = drawn_job(name, data)
        a = pool.run(job)
        label = f"{type(value).__name__} {getattr(value, 'dtype', '')} {getattr(value, 'shape', '')}".strip()
        records.append(
            harness.Record(harness.module_of(name), name, param, "hypothesis", label, a.outcome, a.detail)
        )

    if seed is not None:
        draw = hypothesis_seed(seed)(draw)
    draw()
    return records


# functions without arguments (gnssatt.data.geonet_dir) have nothing to draw
WITH_ARGUMENTS = sorted(n for n, e in inv.ENTRIES.items() if e.build())


@pytest.mark.slow
@pytest.mark.parametrize("name", WITH_ARGUMENTS)
def test_hypothesis_inputs_keep_the_contract(pool: Pool, name: str) -> None:
    records = run_drawn(pool, name, EXAMPLES)
    assert len(records) >= EXAMPLES // 2
    bad = [r.line() for r in records if r.outcome in oc.FAILURES]
    assert not bad, report(bad)
