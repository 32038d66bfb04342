"""The Monte Carlo driver gives identical, ordered results whatever executes the trials."""

from __future__ import annotations

import functools
import multiprocessing
import subprocess
import sys
import textwrap
from concurrent.futures import ProcessPoolExecutor, ThreadPoolExecutor
from pathlib import Path

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


FORKED = textwrap.dedent(
    """
    import multiprocessing
    from concurrent.futures import ProcessPoolExecutor

    from gnssatt import montecarlo
    from tests.test_montecarlo import rust_parallel_trial

    import numpy as np

    parent = rust_parallel_trial(np.random.default_rng(0))  # the Rust pool runs in the parent first
    context = multiprocessing.get_context("fork")
    with ProcessPoolExecutor(2, mp_context=context) as pool:
        direct = pool.submit(rust_parallel_trial, np.random.default_rng(0)).result()
        runs = montecarlo.run(rust_parallel_trial, 4, seed=3, executor=pool, progress=False, chunksize=1)
    serial = montecarlo.run(
        rust_parallel_trial, 4, seed=3, executor=montecarlo.SerialExecutor(), progress=False
    )
    print("same" if direct == parent and runs == serial else f"differ {direct} {parent} {runs} {serial}")
    """
)


def rust_parallel_trial(rng: np.random.Generator) -> list[float]:
    """Two epochs of the ML series on the whole domain: rayon over the epochs, each search parallel too."""
    from gnssatt import ml_attitude_series
    from gnssatt.rotation import rotation_from_euler
    from gnssatt.sim import equilateral_triangle, random_los

    los = random_los(rng, 6, min_elevation_deg=15.0)
    baselines = equilateral_triangle(1.0, plane="xz")[1:]
    truth = rotation_from_euler(rng.uniform([-180.0, -60.0, -180.0], [180.0, 60.0, 180.0]))
    sd = -2 * np.pi / 0.19 * (truth.apply(baselines) @ los.T)
    series = ml_attitude_series(np.stack([sd, sd]), los, baselines, 0.19, step_deg=3.0)
    return [float(v) for v in series.euler_gost_deg.ravel()]


@pytest.mark.skipif(sys.platform != "linux", reason="fork start method")
def test_a_forked_pool_runs_rust_parallel_calls_after_the_parent_did() -> None:
    # In a child process of its own so that a hang (what a forked worker did on rayon's global pool) ends
    # in the timeout instead of stalling the suite; the timeout guards a hang and measures nothing.
    root = Path(__file__).resolve().parents[1]
    done = subprocess.run(
        [sys.executable, "-c", FORKED], capture_output=True, text=True, timeout=600, cwd=root, check=False
    )
    assert done.stdout.strip() == "same", (done.stdout, done.stderr)


@pytest.mark.skipif(
    sys.platform != "linux" or sys.version_info >= (3, 14), reason="the default start method is fork here"
)
def test_a_plain_process_pool_is_accepted() -> None:
    serial = montecarlo.run(draw, 4, seed=9, executor=montecarlo.SerialExecutor(), progress=False)
    with ProcessPoolExecutor(1) as pool:
        assert montecarlo.run(draw, 4, seed=9, executor=pool, progress=False) == serial


@pytest.mark.slow
def test_forkserver_pool_is_accepted() -> None:
    serial = montecarlo.run(draw, 4, seed=9, executor=montecarlo.SerialExecutor(), progress=False)
    with ProcessPoolExecutor(1, mp_context=multiprocessing.get_context("forkserver")) as pool:
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


class _CountingPool(ProcessPoolExecutor):
    """A process pool that counts the tasks submitted to it."""

    submitted = 0

    def submit(self, fn, /, *args, **kwargs):  # type: ignore[no-untyped-def, override]
        type(self).submitted += 1
        return super().submit(fn, *args, **kwargs)


def test_an_unpicklable_trial_is_refused_before_any_task_is_submitted() -> None:
    # issue 31: a bare PicklingError once the pool had started
    with pytest.raises(InvalidInputError, match=r"expected trial picklable.*lambda"):
        montecarlo.run(lambda rng: rng.random(), 3, seed=0, progress=False)
    with _CountingPool(1, mp_context=multiprocessing.get_context("spawn")) as pool:
        with pytest.raises(InvalidInputError, match="trial"):
            montecarlo.run(lambda rng: rng.random(), 3, seed=0, executor=pool, progress=False)
    assert _CountingPool.submitted == 0
    # executors that do not pickle take it
    assert (
        len(
            montecarlo.run(
                lambda rng: rng.random(), 3, seed=0, executor=montecarlo.SerialExecutor(), progress=False
            )
        )
        == 3
    )
