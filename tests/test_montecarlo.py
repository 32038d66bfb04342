"""The Monte Carlo driver gives identical, ordered results whatever executes the trials."""

from __future__ import annotations

import functools
from concurrent.futures import ProcessPoolExecutor, ThreadPoolExecutor

import numpy as np
import pytest

from gnssatt import montecarlo
from gnssatt.errors import InvalidInputError
from gnssatt.experiments import matrix_method


def draw(rng: np.random.Generator, *, size: int = 3) -> list[float]:
    return rng.standard_normal(size).tolist()


def test_serial_threads_and_processes_agree() -> None:
    serial = montecarlo.run(draw, 37, seed=5, executor=montecarlo.SerialExecutor(), progress=False)
    with ThreadPoolExecutor(3) as pool:
        threads = montecarlo.run(draw, 37, seed=5, executor=pool, progress=False, chunksize=4)
    with ProcessPoolExecutor(2) as pool:
        procs = montecarlo.run(draw, 37, seed=5, executor=pool, progress=False, chunksize=1)
    assert serial == threads == procs
    assert len(serial) == 37 and len({tuple(r) for r in serial}) == 37


def test_trial_generators_reproduce_one_trial() -> None:
    results = montecarlo.run(draw, 10, seed=11, executor=montecarlo.SerialExecutor(), progress=False)
    assert draw(montecarlo.trial_generators(11, 10)[7]) == results[7]
    other = montecarlo.run(draw, 10, seed=12, executor=montecarlo.SerialExecutor(), progress=False)
    assert other != results


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
