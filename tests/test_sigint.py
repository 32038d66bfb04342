"""Ctrl-C (SIGINT) in the Monte Carlo driver (issue 31): the interrupt is honoured, checked by what it leaves
behind (a ``KeyboardInterrupt``, futures cancelled, worker processes gone), never by how long it took; the
latencies are measured by ``benches/python/sigint_latency.py``. The GNSS session's and the single-point
solver's polls of the core's flag are tested in Rust (``rust/core/tests/gnss_engine_interrupt.rs``).

The signal is sent to the main thread (``signal.pthread_kill``), as the kernel delivers a terminal's Ctrl-C,
from a helper thread once the trials are known to be running.
"""

from __future__ import annotations

import os
import signal
import threading
from collections.abc import Callable
from concurrent.futures import Executor, Future, ThreadPoolExecutor
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from gnssatt import montecarlo

STARTED = threading.Event()
RELEASE = threading.Event()


def _blocking_trial(rng: np.random.Generator) -> float:
    # the first trial to run blocks until the test releases it; the others are never reached
    STARTED.set()
    RELEASE.wait()
    return float(rng.random())


class _Recording(Executor):
    """A thread pool of one worker that keeps the futures it hands out."""

    def __init__(self) -> None:
        self.pool = ThreadPoolExecutor(1)
        self.futures: list[Future[Any]] = []

    def submit(self, fn: Callable[..., Any], /, *args: Any, **kwargs: Any) -> Future[Any]:
        future = self.pool.submit(fn, *args, **kwargs)
        self.futures.append(future)
        return future


def _interrupt_main_when(ready: Callable[[], bool]) -> threading.Thread:
    main = threading.main_thread().ident
    assert main is not None

    def watch() -> None:
        # no deadline asserted: the test fails by pytest's own timeout if the trials never start
        while not ready():
            threading.Event().wait(0.02)
        signal.pthread_kill(main, signal.SIGINT)

    thread = threading.Thread(target=watch, daemon=True)
    thread.start()
    return thread


@pytest.fixture
def sigint_handler() -> Any:
    # a runner started in the background inherits SIGINT ignored: install Python's own handler for the test
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    yield
    signal.signal(signal.SIGINT, previous)


def test_ctrl_c_cancels_the_chunks_not_started_on_a_callers_executor(sigint_handler: None) -> None:
    STARTED.clear()
    RELEASE.clear()
    executor = _Recording()
    watcher = _interrupt_main_when(STARTED.is_set)
    try:
        with pytest.raises(KeyboardInterrupt):
            montecarlo.run(_blocking_trial, 8, seed=1, executor=executor, progress=False, chunksize=1)
    finally:
        RELEASE.set()
        watcher.join()
    try:
        # one chunk was running on the one worker; the seven queued behind it were cancelled, none ran
        assert len(executor.futures) == 8
        assert sum(f.cancelled() for f in executor.futures) == 7
        assert not executor.futures[0].cancelled()
        # the caller's executor is the caller's: not shut down, it still takes work
        assert montecarlo.run(_plain_trial, 2, seed=1, executor=executor, progress=False) == [
            _plain_trial(g) for g in montecarlo.trial_generators(1, 2)
        ]
    finally:
        executor.pool.shutdown()


def _plain_trial(rng: np.random.Generator) -> float:
    return float(rng.random())


def _sleeping_trial(folder: str, rng: np.random.Generator) -> float:
    # runs in a worker process of the driver's own pool: says it started, then runs for an hour, the
    # chunk that would have held the driver's shutdown for that long
    Path(folder, f"started-{os.getpid()}").write_text("")
    threading.Event().wait(3600.0)
    return float(rng.random())


@pytest.mark.slow
def test_ctrl_c_to_the_main_process_alone_stops_the_drivers_own_pool(
    tmp_path: Path, sigint_handler: None
) -> None:
    # `kill -INT <pid>` reaches the main process only; its spawned workers run on. The driver terminates
    # them instead of waiting for their chunks.
    import functools

    trial = functools.partial(_sleeping_trial, str(tmp_path))
    watcher = _interrupt_main_when(lambda: any(tmp_path.glob("started-*")))
    with pytest.raises(KeyboardInterrupt):
        montecarlo.run(trial, 4, seed=1, progress=False)
    watcher.join()
    pids = [int(p.name.split("-")[1]) for p in tmp_path.glob("started-*")]
    assert pids
    for pid in pids:  # terminated and reaped by the driver: no such process any more
        with pytest.raises(ProcessLookupError):
            os.kill(pid, 0)
