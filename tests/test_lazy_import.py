"""``import gnssatt`` stays light (PEP 562 lazy submodules and re-exports) yet offers every public name."""

from __future__ import annotations

import ast
import importlib
import subprocess
import sys
from pathlib import Path

import pytest

import gnssatt

HEAVY = ("scipy.stats", "matplotlib", "gnssatt.sim", "gnssatt.attitude", "gnssatt.orbit")


def test_import_does_not_load_heavy_modules() -> None:
    # A fresh interpreter: this test process has long since imported everything.
    code = f"import sys, gnssatt; print(','.join(m for m in {HEAVY!r} if m in sys.modules))"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == ""


def test_every_public_name_resolves_and_is_listed() -> None:
    for name in gnssatt.__all__:
        assert getattr(gnssatt, name) is not None, name
    assert set(gnssatt.__all__) <= set(dir(gnssatt))
    assert gnssatt.matrix_attitude is gnssatt.attitude.matrix_method.matrix_attitude  # type: ignore[attr-defined]


def test_unknown_attribute_raises_attribute_error() -> None:
    with pytest.raises(AttributeError, match="no_such_name"):
        gnssatt.no_such_name  # type: ignore[attr-defined]  # noqa: B018


def test_type_checking_block_matches_the_lazy_table() -> None:
    # Type checkers read the TYPE_CHECKING imports, the interpreter the lazy table: they must agree.
    tree = ast.parse(Path(gnssatt.__file__).read_text())
    block = next(n for n in tree.body if isinstance(n, ast.If) and ast.unparse(n.test) == "TYPE_CHECKING")
    static: dict[str, str] = {}
    for node in block.body:
        assert isinstance(node, ast.ImportFrom) and node.module is not None
        for alias in node.names:
            static[alias.asname or alias.name] = node.module
    lazy = {name: f"gnssatt.{module}" for name, module in gnssatt._EXPORTS.items()}
    lazy |= dict.fromkeys(gnssatt._SUBMODULES, "gnssatt")
    assert static == lazy
    assert set(gnssatt.__all__) == set(lazy) | {"__version__"}


@pytest.mark.parametrize(
    "old", ["gnssatt.tumble", "gnssatt.matrix_method", "gnssatt.sim.frames", "gnssatt.rinex.attitude"]
)
def test_old_module_paths_are_gone(old: str) -> None:
    # 0.1.0 was never released: the paths that moved before it (CHANGELOG.md) do not import
    with pytest.raises(ModuleNotFoundError, match=old.replace(".", r"\.")):
        importlib.import_module(old)


@pytest.mark.parametrize(
    ("package", "name"), [("gnssatt", "tumble"), ("gnssatt.rinex", "attitude_from_rinex")]
)
def test_old_names_are_gone(package: str, name: str) -> None:
    with pytest.raises(AttributeError, match=name):
        getattr(importlib.import_module(package), name)
