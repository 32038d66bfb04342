"""Monte Carlo driver: independent, reproducible trials on any :class:`concurrent.futures.Executor`.

Each trial gets its own :class:`numpy.random.Generator` from ``SeedSequence(seed).spawn(n_trials)``, so a
trial's random stream depends only on ``seed`` and its index: results are identical serially, in a process
pool, or on a Dask cluster (``client.get_executor()``), whatever the number of workers.
"""

from __future__ import annotations

import multiprocessing
import os
from collections.abc import Callable, Sequence
from concurrent.futures import Executor, Future, ProcessPoolExecutor, as_completed
from typing import Any, TypeVar

import numpy as np
from tqdm.auto import tqdm

from gnssatt.errors import InvalidInputError

__all__ = ["SerialExecutor", "run", "trial_generators"]

T = TypeVar("T")


class SerialExecutor(Executor):
    """An executor that runs each task in the calling process at submission (debugging, profiling)."""

    def submit(self, fn: Callable[..., T], /, *args: Any, **kwargs: Any) -> Future[T]:
        future: Future[T] = Future()
        try:
            future.set_result(fn(*args, **kwargs))
        except BaseException as exc:
            future.set_exception(exc)
        return future


def trial_generators(seed: int, n_trials: int) -> list[np.random.Generator]:
    """The generators :func:`run` hands to trials ``0 .. n_trials-1``, for reproducing one trial alone."""
    return [np.random.default_rng(s) for s in np.random.SeedSequence(seed).spawn(n_trials)]


def _run_chunk(trial: Callable[[np.random.Generator], T], seeds: Sequence[np.random.SeedSequence]) -> list[T]:
    return [trial(np.random.default_rng(s)) for s in seeds]


def run(
    trial: Callable[[np.random.Generator], T],
    n_trials: int,
    *,
    seed: int,
    executor: Executor | None = None,
    progress: bool = True,
    chunksize: int | None = None,
) -> list[T]:
    """Run ``trial(rng)`` ``n_trials`` times and return the results in trial order.

    Parameters
    ----------
    trial
        A picklable callable (a module-level function or a :func:`functools.partial` of one) taking a
        :class:`numpy.random.Generator` and returning a picklable result.
    n_trials
        Number of trials, >= 1.
    seed
        Root seed; trial ``i`` uses the ``i``-th child of ``numpy.random.SeedSequence(seed)``.
    executor
        Any :class:`concurrent.futures.Executor`: a ``ProcessPoolExecutor``, a Dask
        ``distributed.Client(...).get_executor()``, or :class:`SerialExecutor`. Default: a process pool
        with one worker per CPU (``os.cpu_count()``), created and shut down here; it uses the ``spawn``
        start method so that worker processes never inherit the parent's native thread pools.
    progress
        Show a tqdm progress bar of completed trials.
    chunksize
        Trials per submitted task (default: about 64 tasks in all), to amortise the per-task overhead.
    """
    if isinstance(n_trials, bool) or not isinstance(n_trials, int | np.integer) or n_trials < 1:
        raise InvalidInputError(f"expected n_trials as an integer >= 1, got {n_trials!r}")
    if chunksize is None:
        chunksize = max(1, -(-n_trials // 64))
    elif chunksize < 1:
        raise InvalidInputError(f"expected chunksize >= 1, got {chunksize}")
    seeds = np.random.SeedSequence(seed).spawn(n_trials)
    chunks = [seeds[i : i + chunksize] for i in range(0, n_trials, chunksize)]
    owned = executor is None
    if executor is None:
        executor = ProcessPoolExecutor(os.cpu_count(), mp_context=multiprocessing.get_context("spawn"))
    try:
        futures = {executor.submit(_run_chunk, trial, chunk): k for k, chunk in enumerate(chunks)}
        results: list[list[T] | None] = [None] * len(chunks)
        with tqdm(total=n_trials, disable=not progress, unit="trial") as bar:
            for future in as_completed(futures):
                k = futures[future]
                results[k] = future.result()
                bar.update(len(chunks[k]))
    finally:
        if owned:
            executor.shutdown(cancel_futures=True)
    return [r for chunk in results for r in chunk]  # type: ignore[union-attr]
