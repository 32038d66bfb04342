"""Reproductions of the source papers' experiments, run by ``gnssatt reproduce``.

Each experiment module defines ``EXPERIMENT``, an :class:`Experiment`; its ``run`` writes
``DIR/<name>.json`` (see :func:`gnssatt.experiments.report.write_report`) and its plots, prints a table, and
returns the JSON document.
"""

from __future__ import annotations

import importlib
from collections.abc import Callable
from concurrent.futures import Executor
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Protocol

from gnssatt.errors import UnknownNameError

__all__ = ["EXPERIMENTS", "Experiment", "RunExperiment", "get"]


class RunExperiment(Protocol):
    def __call__(
        self, *, runs: int, seed: int, out: Path, executor: Executor | None, progress: bool
    ) -> dict[str, Any]: ...


@dataclass(frozen=True)
class Experiment:
    """One paper experiment: ``runs`` Monte Carlo trials by default, ``quick_runs`` under ``--all``."""

    name: str
    summary: str
    run: RunExperiment | Callable[..., dict[str, Any]]
    default_runs: int
    quick_runs: int


# Module names under gnssatt.experiments, in the order `--list` shows them.
_MODULES = (
    "matrix_method",
    "ml_grid",
    "magnetometer_yaw",
    "orbit_filter",
    "gyro_gnss",
    "visibility_rotation",
    "recorded_methods",
)


def _load() -> dict[str, Experiment]:
    found = {}
    for module in _MODULES:
        exp: Experiment = importlib.import_module(f"gnssatt.experiments.{module}").EXPERIMENT
        found[exp.name] = exp
    return found


EXPERIMENTS: dict[str, Experiment] = _load()


def get(name: str) -> Experiment:
    """The experiment called ``name``; :class:`~gnssatt.errors.UnknownNameError` listing the known names
    otherwise.

    Parameters
    ----------
    name
        An experiment's name as ``gnssatt reproduce --list`` prints it, e.g. ``"matrix-method"``.

    Returns
    -------
    Experiment
        Its summary, ``run`` function and default and quick run counts.

    Raises
    ------
    UnknownNameError
        ``name`` is not an experiment; the message names the parameter and lists the known names (also a
        :class:`ValueError` and a :class:`KeyError`).

    Examples
    --------
    Every name of :data:`EXPERIMENTS` gives back its experiment; an unknown name lists the known ones:

    >>> from gnssatt.experiments import EXPERIMENTS, get
    >>> get("matrix-method").name
    'matrix-method'
    >>> all(get(name) is experiment for name, experiment in EXPERIMENTS.items())
    True
    >>> get("matrix method")  # doctest: +ELLIPSIS
    Traceback (most recent call last):
        ...
    gnssatt.errors.UnknownNameError: name: unknown experiment 'matrix method'; known: matrix-method, ...
    """
    try:
        return EXPERIMENTS[name]
    except KeyError:
        raise UnknownNameError(
            f"name: unknown experiment {name!r}; known: {', '.join(EXPERIMENTS)}"
        ) from None
