"""The Monte Carlo driver gives identical, ordered results whatever executes the trials."""

from __future__ import annotations

import functools
import multiprocessing
import sys
from concurrent.futures import ProcessPoolExecutor, ThreadPoolExecutor

import numpy as np
import pytest

from gnssatt import montecarlo
from gnssatt.errors import InvalidInputError, InvalidTypeError, WorkLimitError
from gnssatt.experiments import matrix_method


def draw(rng: np.random.Generator, *, size: int = 3) -> list[float]:
    return rng.standard_normal(size).tolist()


@pytest.mark.slow
def test_serial_threads_and_processes_agree() -> None:
    serial = montecarlo.run(draw, 37, seed=5, executor=montecarlo.SerialExecutor(), progress=False)
    with ThreadPoolExecutor(3) as pool:
        threads = montecarlo.run(draw, 37, seed=5, executor=pool, progress=False, chunksize=4)
    with ProcessPoolExecutor(2, mp_context=multiprocessing.get_context("spawn")) as pool:
        procs = montecarlo.run(draw, 37, seed=5, executor=pool, progress=False, chunksize=1)
    assert serial == threads == procs
    assert len(serial) == 37 and len({tuple(r) for r in serial}) == 37


def test_trial_generators_reproduce_one_trial() -> None:
    results = montecarlo.run(draw, 10, seed=11, executor=montecarlo.SerialExecutor(), progress=False)
    assert draw(montecarlo.trial_generators(11, 10)[7]) == results[7]
    other = montecarlo.run(draw, 10, seed=12, executor=montecarlo.SerialExecutor(), progress=False)
    assert other != results


@pytest.mark.slow
def test_dask_cluster_gives_identical_numbers() -> None:
    distributed = pytest.importorskip("distributed")
    trial = functools.partial(matrix_method.trial, sigma_m=0.004)
    serial = montecarlo.run(trial, 40, seed=3, executor=montecarlo.SerialExecutor(), progress=False)
    with (
        distributed.LocalCluster(
            n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None
        ) as cluster,
        distributed.Client(cluster) as client,
    ):
        on_dask = montecarlo.run(
            trial, 40, seed=3, executor=client.get_executor(), progress=False, chunksize=3
        )
    assert on_dask == serial


def test_trial_errors_propagate() -> None:
    def boom(rng: np.random.Generator) -> None:
        raise RuntimeError("trial failed")

    with pytest.raises(RuntimeError, match="trial failed"):
        montecarlo.run(boom, 3, seed=0, executor=montecarlo.SerialExecutor(), progress=False)


@pytest.mark.parametrize("n", [0, -1, 2.5, True])
def test_bad_trial_counts(n: object) -> None:
    with pytest.raises(InvalidInputError, match="n_trials"):
        montecarlo.run(draw, n, seed=0, progress=False)  # type: ignore[arg-type]


def test_fork_started_pool_is_refused_with_the_remedy() -> None:
    with ProcessPoolExecutor(1, mp_context=multiprocessing.get_context("fork")) as pool:
        with pytest.raises(InvalidInputError, match=r'fork.*get_context\("spawn"\)'):
            montecarlo.run(draw, 3, seed=0, executor=pool, progress=False)


@pytest.mark.skipif(
    sys.platform != "linux" or sys.version_info >= (3, 14), reason="the default start method is fork here"
)
def test_plain_process_pool_on_linux_is_refused() -> None:
    with ProcessPoolExecutor(1) as pool, pytest.raises(InvalidInputError, match="forkserver"):
        montecarlo.run(draw, 3, seed=0, executor=pool, progress=False)


class _ForeignContext:
    """A multiprocessing context look-alike that cannot tell its start method."""

    def __init__(self, inner: object) -> None:
        self._inner = inner

    def __getattr__(self, name: str) -> object:
        if name == "get_start_method":
            raise AttributeError(name)
        return getattr(self._inner, name)


@pytest.mark.slow
def test_forkserver_pool_and_unknown_context_are_accepted() -> None:
    serial = montecarlo.run(draw, 4, seed=9, executor=montecarlo.SerialExecutor(), progress=False)
    with ProcessPoolExecutor(1, mp_context=multiprocessing.get_context("forkserver")) as pool:
        assert montecarlo.run(draw, 4, seed=9, executor=pool, progress=False) == serial
    with ProcessPoolExecutor(1, mp_context=multiprocessing.get_context("spawn")) as pool:
        pool._mp_context = _ForeignContext(pool._mp_context)  # cannot say: nothing to conclude, not refused
        assert montecarlo.run(draw, 4, seed=9, executor=pool, progress=False) == serial


@pytest.mark.parametrize(
    ("kwargs", "error", "name"),
    [
        ({"seed": -1}, InvalidInputError, "seed"),
        ({"seed": 1.5}, InvalidTypeError, "seed"),
        ({"chunksize": 0}, InvalidInputError, "chunksize"),
        ({"chunksize": "4"}, InvalidTypeError, "chunksize"),
        ({"n_trials": montecarlo.MAX_TRIALS + 1}, WorkLimitError, "n_trials"),
        ({"executor": object()}, InvalidTypeError, "executor"),
        ({"trial": 3}, InvalidTypeError, "trial"),
    ],
)
def test_bad_arguments_name_the_parameter(kwargs: dict[str, object], error: type, name: str) -> None:
    args: dict[str, object] = {"trial": draw, "n_trials": 3, "seed": 0, "progress": False} | kwargs
    with pytest.raises(error, match=name):
        montecarlo.run(**args)  # type: ignore[arg-type]
