"""Old import paths (issue 19's moves, ``gnssatt._moved.MOVED``) warn, name the new path and give the very
object the new path gives; the old files are gone and ``docs/architecture.md`` lists the same table."""

from __future__ import annotations

import importlib
import subprocess
import sys
import warnings
from pathlib import Path

import pytest

import gnssatt
from gnssatt._moved import MOVED

PACKAGE = Path(gnssatt.__file__).parent
DOC = Path(__file__).resolve().parents[1] / "docs" / "architecture.md"


def _new_object(new: str) -> object:
    try:
        return importlib.import_module(new)
    except ModuleNotFoundError:
        module, _, name = new.rpartition(".")
        return getattr(importlib.import_module(module), name)


def _forget(old: str) -> None:
    """Drop what an earlier use of ``old`` cached (the alias in sys.modules, the attribute on its parent)."""
    sys.modules.pop(old, None)
    parent, _, name = old.rpartition(".")
    if name in vars(importlib.import_module(parent)):
        delattr(sys.modules[parent], name)


@pytest.mark.parametrize(("old", "new"), sorted(MOVED.items()))
def test_the_old_path_warns_and_gives_the_same_object(old: str, new: str) -> None:
    expected = _new_object(new)
    _forget(old)
    parent, _, name = old.rpartition(".")
    scope: dict[str, object] = {}
    with pytest.warns(DeprecationWarning, match=f"{old} moved to {new}") as record:
        exec(f"from {parent} import {name} as found", scope)
    assert scope["found"] is expected
    assert len(record) == 1  # `from package import name` looks the name up twice; one warning


def test_the_warning_points_at_the_importing_line() -> None:
    _forget("gnssatt.tumble")
    with warnings.catch_warnings(record=True) as record:
        warnings.simplefilter("always")
        import gnssatt.tumble  # noqa: F401
    assert [(w.category, w.filename) for w in record] == [(DeprecationWarning, __file__)]


def test_a_moved_module_keeps_its_own_identity() -> None:
    _forget("gnssatt.sim.frames")
    with pytest.warns(DeprecationWarning):
        old = importlib.import_module("gnssatt.sim.frames")
    assert old.__spec__ is not None
    assert old.__name__ == old.__spec__.name == "gnssatt.frames"  # the finder gave __spec__ back


def test_import_gnssatt_does_not_load_the_table() -> None:
    code = "import sys, gnssatt; print('gnssatt._moved' in sys.modules)"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "False"


def test_the_new_paths_do_not_warn() -> None:
    # A fresh interpreter, warnings as errors: the package itself never goes through an old path.
    modules = [new for new in MOVED.values() if isinstance(_new_object(new), type(gnssatt))]
    code = "import importlib, warnings; warnings.simplefilter('error')\n"
    code += f"for m in {modules!r}: importlib.import_module(m)"
    subprocess.run([sys.executable, "-c", code], check=True)


def test_old_files_are_gone_and_unknown_names_still_fail() -> None:
    for old in MOVED:
        relative = Path(*old.split(".")[1:])
        assert not (PACKAGE / relative).with_suffix(".py").exists(), old
        assert not (PACKAGE / relative / "__init__.py").exists(), old
    with pytest.raises(AttributeError, match="no_such_name"):
        gnssatt.rinex.no_such_name  # noqa: B018
    with pytest.raises(ModuleNotFoundError):
        importlib.import_module("gnssatt.sim.no_such_module")


def test_the_architecture_page_lists_every_moved_module() -> None:
    text = DOC.read_text()
    for old, new in MOVED.items():
        if isinstance(_new_object(new), type(gnssatt)):
            assert f"| `{old}` | `{new}` |" in text, old
