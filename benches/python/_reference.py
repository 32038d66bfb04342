"""The RINEX readers of an earlier commit, loaded from git, for the scripts that compare the current readers
against them (``rinex_obs_equal.py``, ``rinex_nav_equal.py``, ``rinex_read_speed.py``), and the comparison
both equality scripts run (:func:`compare`).

The defaults are the last commits with the Python record loops (before each reader moved to the Rust core);
their modules import only ``gnssatt.rinex._fields`` names that still exist.
"""

from __future__ import annotations

import dataclasses
import random
import subprocess
import sys
import tempfile
import types
import warnings
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

from gnssatt.errors import RinexError
from gnssatt.rinex._fields import read_bytes

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


def outcome(reader: Callable[[Any], Any], path: Path) -> tuple[str, Any, list[str]]:
    """``("read", result, warnings)`` or ``("error", (message, line), warnings)`` of ``reader(path)``."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            result: Any = reader(path)
            kind = "read"
        except RinexError as exc:
            kind, result = "error", (str(exc), exc.line)
    return kind, result, [f"{w.category.__name__}: {w.message}" for w in caught]


def _same(a: Any, b: Any, where: str, out: list[str]) -> None:
    """Append to ``out`` where ``a`` and ``b`` differ (dataclasses and dicts field by field, arrays by
    bytes, dtype and shape, floats by bits)."""
    if dataclasses.is_dataclass(a) and dataclasses.is_dataclass(b):
        for f in dataclasses.fields(a):
            _same(getattr(a, f.name), getattr(b, f.name), f"{where}.{f.name}", out)
    elif isinstance(a, dict) and isinstance(b, dict):
        if list(a) != list(b):
            out.append(f"{where}: keys {list(a)} against {list(b)}")
        for k in a:
            if k in b:
                _same(a[k], b[k], f"{where}[{k!r}]", out)
    elif isinstance(a, np.ndarray) or isinstance(b, np.ndarray):
        a, b = np.asarray(a), np.asarray(b)
        if not (a.dtype == b.dtype and a.shape == b.shape and a.tobytes() == b.tobytes()):
            out.append(f"{where} differs")
    elif isinstance(a, float) and isinstance(b, float):
        if np.float64(a).tobytes() != np.float64(b).tobytes():
            out.append(f"{where} differs")
    elif type(a) is not type(b) or a != b:
        out.append(f"{where}: {a!r} against {b!r}")


def differences(new: Callable[[Any], Any], old: Callable[[Any], Any], path: Path) -> list[str]:
    """What differs between the readers ``new`` and ``old`` on ``path`` (empty: nothing)."""
    k_new, r_new, w_new = outcome(new, path)
    k_old, r_old, w_old = outcome(old, path)
    out: list[str] = []
    if k_new != k_old:
        shown_new = r_new if k_new == "error" else ""
        shown_old = r_old if k_old == "error" else ""
        return [f"new {k_new} {shown_new}, old {k_old} {shown_old}"]
    if k_new == "error":
        if r_new != r_old:
            out.append(f"error: new {r_new}, old {r_old}")
    else:
        _same(r_new, r_old, "result", out)
    if w_new != w_old:
        out.append(f"warnings: new {w_new}, old {w_old}")
    return out


def compare(
    files: list[Path],
    new: Callable[[Any], Any],
    old: Callable[[Any], Any],
    rev: str,
    mutants: int,
    rng: random.Random,
    mutate: Callable[[bytes, random.Random, int], bytes],
) -> int:
    """Prints, for every file and ``mutants`` mutants of it (``mutate(raw, rng, m)``), whether ``new`` and
    ``old`` agree, then a count; 1 on any difference, else 0 (the scripts' exit status)."""
    n_diff = n_mut = n_mut_err = 0
    for f in files:
        diff = differences(new, old, f)
        n_diff += bool(diff)
        print(f"{'DIFFERENT' if diff else 'same     '} {f}" + "".join(f"\n    {d}" for d in diff))
        if mutants:
            raw = read_bytes(str(f))
            with tempfile.TemporaryDirectory() as folder:
                for m in range(mutants):
                    p = Path(folder) / f"mutant{m}.rnx"
                    p.write_bytes(mutate(raw, rng, m))
                    diff = differences(new, old, p)
                    n_mut += 1
                    n_mut_err += outcome(new, p)[0] == "error"
                    if diff:
                        n_diff += 1
                        print(f"DIFFERENT mutant {m} of {f}" + "".join(f"\n    {d}" for d in diff))
    print(f"{len(files)} files, {n_mut} mutants ({n_mut_err} refused): {n_diff} different from {rev}")
    return 1 if n_diff else 0
