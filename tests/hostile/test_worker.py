"""The harness's own check: a worker killed by a signal is an ``abort``, one that does not answer a
``hang``, a Python exception outside the contract a ``wrong-exception``, and the pool goes on after each."""

from __future__ import annotations

import pytest

from . import outcomes as oc
from .worker import Job, Pool


@pytest.mark.slow
def test_pool_reports_abort_hang_and_recovers() -> None:
    pool = Pool(hang_s=5.0, prewarm=False)
    try:
        answers = [
            pool.run(Job("os.abort", kwargs={})),
            pool.run(Job("signal.pause", kwargs={})),
            pool.run(Job("math.factorial", kwargs={}, names=("x",))),
            pool.run(Job("gnssatt.triad", "gnssatt.triad")),
        ]
        got = [(a.outcome, a.detail, round(a.seconds, 2)) for a in answers]
        assert [a.outcome for a in answers] == [oc.ABORT, oc.HANG, oc.WRONG, oc.ACCEPTED], got
        assert "SIGABRT" in answers[0].detail
        assert pool.restarts == 2
    finally:
        pool.close()
