"""The observation reader of an earlier commit, loaded from git, for the scripts that compare the current
reader against it (``rinex_obs_equal.py``, ``rinex_read_speed.py``).

The default is the last commit with the Python epoch loop (before the reader moved to the Rust core); its
``obs.py`` imports only ``gnssatt.rinex._fields`` names that still exist.
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

_ROOT = Path(__file__).resolve().parents[2]


def reference_reader(rev: str = PYTHON_READER_REV) -> Callable[[Any], Any]:
    """``read_obs`` of ``python/gnssatt/rinex/obs.py`` at git revision ``rev``."""
    source = subprocess.run(
        ["git", "show", f"{rev}:python/gnssatt/rinex/obs.py"],
        cwd=_ROOT,
        check=True,
        capture_output=True,
        text=True,
    ).stdout
    module = types.ModuleType("gnssatt.rinex._obs_reference")
    module.__file__ = f"{rev}:python/gnssatt/rinex/obs.py"
    sys.modules[module.__name__] = module  # dataclasses look their module up
    exec(compile(source, module.__file__, "exec"), module.__dict__)
    return module.read_obs  # type: ignore[no-any-return]
