"""The RINEX readers of an earlier commit, loaded from git, for the scripts that compare the current readers
against them (``rinex_obs_equal.py``, ``rinex_nav_equal.py``, ``rinex_read_speed.py``).

The defaults are the last commits with the Python record loops (before each reader moved to the Rust core);
their modules import only ``gnssatt.rinex._fields`` names that still exist.
"""

from __future__ import annotations

import subprocess
import sys
import types
from collections.abc import Callable
from pathlib import Path
from typing import Any

#: The last commit whose ``python/gnssatt/rinex/obs.py`` walks the epochs in Python.
PYTHON_READER_REV = "99e2fa6"
#: The last commit whose ``python/gnssatt/rinex/nav.py`` walks the records in Python.
PYTHON_NAV_REV = "11cca68"

_ROOT = Path(__file__).resolve().parents[2]


def _module(rev: str, name: str) -> types.ModuleType:
    """``python/gnssatt/rinex/{name}.py`` at git revision ``rev``, as a module of its own."""
    path = f"python/gnssatt/rinex/{name}.py"
    source = subprocess.run(
        ["git", "show", f"{rev}:{path}"], cwd=_ROOT, check=True, capture_output=True, text=True
    ).stdout
    module = types.ModuleType(f"gnssatt.rinex._{name}_reference")
    module.__file__ = f"{rev}:{path}"
    sys.modules[module.__name__] = module  # dataclasses look their module up
    exec(compile(source, module.__file__, "exec"), module.__dict__)
    return module


def reference_reader(rev: str = PYTHON_READER_REV) -> Callable[[Any], Any]:
    """``read_obs`` of ``python/gnssatt/rinex/obs.py`` at git revision ``rev``."""
    return _module(rev, "obs").read_obs  # type: ignore[no-any-return]


def reference_nav_reader(rev: str = PYTHON_NAV_REV) -> Callable[[Any], Any]:
    """``read_nav`` of ``python/gnssatt/rinex/nav.py`` at git revision ``rev``."""
    return _module(rev, "nav").read_nav  # type: ignore[no-any-return]
