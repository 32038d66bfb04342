"""The public API of gnssatt, discovered from the modules' ``__all__``, and for each function a valid call.

Each entry is the function's :class:`valid_calls.Call` (the table the intake tests share): the keyword
arguments of one call that must succeed (``test_inventory`` checks that it does: the harness's own test),
which the hostile harness then replaces one argument at a time, and per argument (:class:`valid_calls.Arg`)
which are work counts, which values are absurd amounts of work that must be refused quickly, and where
non-finite values are part of the documented input; per call, which outputs may be non-finite.

Excluded modules (``EXCLUDED``): ``gnssatt.cli`` (driven through subprocesses by the CLI cases),
``gnssatt.plots`` (draws files from results of the functions here) and ``gnssatt.experiments`` (the papers'
reproductions, reached through ``gnssatt reproduce``).
"""

from __future__ import annotations

import importlib
import inspect
import pkgutil
from collections.abc import Callable
from typing import Any

from valid_calls import CALLS, Call

import gnssatt

# Searched first, so that a function re-exported in several places is known by its most public name.
PREFERRED = (
    "gnssatt",
    "gnssatt.magnetic",
    "gnssatt.sim",
    "gnssatt.orbit",
    "gnssatt.orbit.determination",
    "gnssatt.attitude.dynamics",
    "gnssatt.rinex",
    "gnssatt.montecarlo",
    "gnssatt.attitude.visibility",
    "gnssatt.rotation",
    "gnssatt.geometry",
)
EXCLUDED = ("gnssatt.cli", "gnssatt.plots", "gnssatt.experiments")

#: The valid call of every public function (one table, ``valid_calls.CALLS``).
ENTRIES: dict[str, Call] = CALLS


def public_modules() -> list[str]:
    """Every importable gnssatt module without an underscore in its path, outside ``EXCLUDED``,
    ``PREFERRED`` first."""
    found = [m.name for m in pkgutil.walk_packages(gnssatt.__path__, "gnssatt.")]
    rest = sorted(
        m
        for m in found
        if not any(part.startswith("_") for part in m.split("."))
        and not any(m == x or m.startswith(x + ".") for x in EXCLUDED)
        and m not in PREFERRED
    )
    return [*PREFERRED, *rest]


def public_functions() -> dict[str, Callable[..., Any]]:
    """Qualified name -> function, for every function in a public module's ``__all__`` (or, without one,
    every public name it defines); a function exported in several places is named once, where first
    found in :func:`public_modules` order."""
    seen: dict[int, str] = {}
    out: dict[str, Callable[..., Any]] = {}
    for name in public_modules():
        mod = importlib.import_module(name)
        names = getattr(mod, "__all__", None)
        if names is None:
            names = [
                n
                for n, v in vars(mod).items()
                if not n.startswith("_") and getattr(v, "__module__", "") == name
            ]
        for attr in names:
            obj = getattr(mod, attr)
            if inspect.isroutine(obj) and id(obj) not in seen:
                seen[id(obj)] = f"{name}.{attr}"
                out[f"{name}.{attr}"] = obj
    return out
