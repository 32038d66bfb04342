"""Monte Carlo driver: independent, reproducible trials on any :class:`concurrent.futures.Executor`.

Each trial gets its own :class:`numpy.random.Generator` from ``SeedSequence(seed).spawn(n_trials)``, so a
trial's random stream depends only on ``seed`` and its index: results are identical serially, in a process
pool, or on a Dask cluster (``client.get_executor()``), whatever the number of workers.

Any process pool works, forking ones included (a plain ``ProcessPoolExecutor()`` forks on Linux before
Python 3.14): the Rust core's thread pool belongs to the process that built it, and a forked worker builds
its own on its first parallel call.
"""

from __future__ import annotations

import multiprocessing
import os
import pickle
from collections.abc import Callable
from concurrent.futures import Executor, Future, ProcessPoolExecutor, as_completed
from typing import Any, TypeVar

import numpy as np
from tqdm.auto import tqdm

from gnssatt._arrays import flag, integer
from gnssatt.errors import InvalidInputError, InvalidTypeError

__all__ = ["MAX_TRIALS", "SerialExecutor", "run", "trial_generators"]

#: Most trials one :func:`run` takes: the results are held in one list, and each trial has its own seed.
MAX_TRIALS = 100_000_000

T = TypeVar("T")


class SerialExecutor(Executor):
    """An executor that runs each task in the calling process at submission (debugging, profiling)."""

    def submit(self, fn: Callable[..., T], /, *args: Any, **kwargs: Any) -> Future[T]:
        """Run ``fn(*args, **kwargs)`` now; the returned future holds its result or its exception."""
        future: Future[T] = Future()
        try:
            future.set_result(fn(*args, **kwargs))
        except BaseException as exc:
            future.set_exception(exc)
        return future


def trial_generators(seed: int, n_trials: int) -> list[np.random.Generator]:
    """The generators :func:`run` hands to its trials, in trial order, for reproducing one trial alone.

    Parameters
    ----------
    seed
        Root seed, an integer >= 0, as given to :func:`run`.
    n_trials
        Number of trials, 1 to :data:`MAX_TRIALS`.

    Returns
    -------
    list of numpy.random.Generator
        Generator ``i`` from the ``i``-th child of ``numpy.random.SeedSequence(seed)``.

    Raises
    ------
    InvalidInputError
        ``seed`` negative, ``n_trials`` below 1, either not an integer
        (:class:`~gnssatt.errors.InvalidTypeError`).
    WorkLimitError
        ``n_trials`` above :data:`MAX_TRIALS`.

    Examples
    --------
    Trial 2 of a run, drawn again alone:

    >>> from gnssatt.montecarlo import SerialExecutor, run, trial_generators
    >>> draws = run(lambda rng: int(rng.integers(1000)), 3, seed=7, executor=SerialExecutor(), progress=False)
    >>> draws[2] == int(trial_generators(7, 3)[2].integers(1000))
    True
    """
    seed = integer("seed", seed, minimum=0)
    n_trials = integer("n_trials", n_trials, minimum=1, maximum=MAX_TRIALS)
    return [np.random.default_rng(s) for s in np.random.SeedSequence(seed).spawn(n_trials)]


def _run_chunk(trial: Callable[[np.random.Generator], T], seed: int, trials: range) -> list[T]:
    # SeedSequence(seed, spawn_key=(i,)) is the i-th child of SeedSequence(seed).spawn(...), made here so
    # that no list of n_trials seeds is built or pickled
    return [trial(np.random.default_rng(np.random.SeedSequence(seed, spawn_key=(i,)))) for i in trials]


def _cancel(futures: dict[Future[Any], int]) -> int:
    """Cancels the futures that have not started; returns how many were cancelled."""
    return sum(future.cancel() for future in futures)


def _stop_workers(pool: ProcessPoolExecutor) -> None:
    """Terminates the worker processes of ``pool`` (SIGTERM) and waits for them: the pool is then broken,
    and its shutdown returns without waiting for chunks that would run for minutes. Python 3.14 has
    ``ProcessPoolExecutor.terminate_workers``; before it the processes are only reachable here."""
    workers = list((getattr(pool, "_processes", None) or {}).values())
    for process in workers:
        process.terminate()
    for process in workers:
        process.join()


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
        Any :class:`concurrent.futures.Executor`: a ``ProcessPoolExecutor`` (any start method), a Dask
        ``distributed.Client(...).get_executor()``, or :class:`SerialExecutor`. Default: a process pool
        with one worker per CPU (``os.cpu_count()``), created and shut down here, started with ``spawn``
        (workers that import only what the trial needs, on every platform alike).
    progress
        Show a tqdm progress bar of completed trials.
    chunksize
        Trials per submitted task (default: about 64 tasks in all), to amortise the per-task overhead.

    Returns
    -------
    list
        ``trial``'s result for each trial, in trial order (whatever order the executor finished them in).

    Raises
    ------
    InvalidInputError
        ``n_trials`` or ``chunksize`` below 1 or not integers, ``seed`` negative or not an integer, ``trial``
        not callable, ``progress`` not a bool (:class:`~gnssatt.errors.InvalidTypeError`), ``executor``
        without ``submit`` or whose ``submit`` returns something other than a
        :class:`concurrent.futures.Future`; a ``trial`` that cannot be pickled when it runs in a process
        pool (the default, or a ``ProcessPoolExecutor``), refused before the pool starts.
    WorkLimitError
        ``n_trials`` above :data:`MAX_TRIALS`.
    KeyboardInterrupt
        Ctrl-C (SIGINT) while the trials run: the chunks that have not started are cancelled, on any
        executor; the pool this function created has its workers terminated, whether or not they saw the
        signal, and is shut down before the interrupt comes out. A caller's executor is not shut down.
    Exception
        Whatever ``trial`` or ``executor.submit`` raises comes out unchanged (user code's own error; the
        chunks not started are cancelled, the pool this function created is shut down first).

    Examples
    --------
    The same seed gives the same draws, trial by trial, on any executor:

    >>> from gnssatt.montecarlo import SerialExecutor, run
    >>> def draw(rng):
    ...     return int(rng.integers(1000))
    >>> first = run(draw, 4, seed=3, executor=SerialExecutor(), progress=False)
    >>> first == run(draw, 4, seed=3, executor=SerialExecutor(), progress=False, chunksize=3)
    True
    >>> len(first)
    4
    """
    n_trials, seed, progress, chunks = _checked_run(trial, n_trials, seed, progress, executor, chunksize)
    owned = executor is None
    executor = _own_pool() if executor is None else executor
    futures: dict[Future[list[T]], int] = {}
    try:
        _submit(executor, trial, seed, chunks, futures)
        results = _collect(futures, chunks, n_trials, progress)
    except BaseException as exc:
        _stop(exc, executor, owned, futures)
        raise
    finally:
        if owned:
            executor.shutdown(cancel_futures=True)
    return [r for chunk in results for r in chunk]


def _own_pool() -> ProcessPoolExecutor:
    """The pool :func:`run` starts when given none: a process per CPU, started with ``spawn`` (workers that
    import only what the trial needs, on every platform alike)."""
    return ProcessPoolExecutor(os.cpu_count(), mp_context=multiprocessing.get_context("spawn"))


def _checked_run(
    trial: Callable[[np.random.Generator], T], n_trials: int, seed: int, progress: bool,
    executor: Executor | None, chunksize: int | None,
) -> tuple[int, int, bool, list[range]]:  # fmt: skip
    """The checked arguments of :func:`run` and its chunks of trials (64 by default), before any pool
    starts."""
    n_trials = integer("n_trials", n_trials, minimum=1, maximum=MAX_TRIALS)
    seed = integer("seed", seed, minimum=0)
    progress = flag("progress", progress)
    if not callable(trial):
        raise InvalidTypeError(
            f"expected trial as a callable taking a numpy Generator, got {type(trial).__name__}"
        )
    if executor is None or isinstance(executor, ProcessPoolExecutor):
        # a process pool pickles the trial with each task: an unpicklable one (a lambda, a local
        # function) failed only after the pool had started, as a bare PicklingError
        try:
            pickle.dumps(trial)
        except Exception as exc:
            raise InvalidInputError(
                f"expected trial picklable for a process pool (a module-level function or a "
                f"functools.partial of one), got {trial!r}: {exc}; or pass executor=SerialExecutor()"
            ) from exc
    if executor is not None and not callable(getattr(executor, "submit", None)):
        raise InvalidTypeError(
            f"expected executor as a concurrent.futures.Executor (with submit), got {type(executor).__name__}"
        )
    if chunksize is None:
        chunksize = max(1, -(-n_trials // 64))
    else:
        chunksize = integer("chunksize", chunksize, minimum=1)
    chunks = [range(i, min(i + chunksize, n_trials)) for i in range(0, n_trials, chunksize)]
    return n_trials, seed, progress, chunks


def _submit(
    executor: Executor, trial: Callable[[np.random.Generator], T], seed: int, chunks: list[range],
    futures: dict[Future[list[T]], int],
) -> None:  # fmt: skip
    """Submit every chunk, each future into ``futures`` as it is made (so that a failure part way cancels
    the ones submitted)."""
    for k, chunk in enumerate(chunks):
        future = executor.submit(_run_chunk, trial, seed, chunk)
        # as_completed needs concurrent.futures.Future; a duck-typed executor that returns something
        # else failed inside it with an AttributeError on a private field
        if not isinstance(future, Future):
            raise InvalidTypeError(
                f"expected executor.submit to return a concurrent.futures.Future, got {type(future).__name__}"
            )
        futures[future] = k


def _collect(
    futures: dict[Future[list[T]], int], chunks: list[range], n_trials: int, progress: bool
) -> list[list[T]]:
    """The chunks' results in chunk order, as they complete (the progress bar counts trials)."""
    results: list[list[T] | None] = [None] * len(chunks)
    with tqdm(total=n_trials, disable=not progress, unit="trial") as bar:
        for future in as_completed(futures):
            k = futures[future]
            results[k] = future.result()
            bar.update(len(chunks[k]))
    return results  # type: ignore[return-value]


def _stop(exc: BaseException, executor: Executor, owned: bool, futures: dict[Future[Any], int]) -> None:
    """After ``exc`` in :func:`run`: nothing more of the caller's executor starts; this function's own pool
    stops its workers at once on Ctrl-C."""
    if not owned:
        _cancel(futures)  # nothing more starts; the caller's executor stays the caller's
    elif isinstance(exc, KeyboardInterrupt):
        # Ctrl-C: this function's own pool stops at once. Its workers may not have seen the signal (a
        # terminal sends it to the whole group, `kill -INT` to this process alone), and a shutdown that
        # waits for their running chunks took minutes. The pool's own thread then fails the pending
        # chunks (a cancel from here races with it), and the shutdown in run's finally returns at once.
        assert isinstance(executor, ProcessPoolExecutor)
        _stop_workers(executor)
