"""The type stub of the native module declares exactly what the module exports."""

from __future__ import annotations

import ast
from pathlib import Path

import gnssatt
from gnssatt import _core


def test_stub_matches_native_module() -> None:
    stub = Path(gnssatt.__file__).with_name("_core.pyi")
    tree = ast.parse(stub.read_text())
    declared = {n.name for n in tree.body if isinstance(n, ast.FunctionDef)}
    # classes the module exports (TypedDicts are argument layouts, not exports)
    declared |= {
        n.name
        for n in tree.body
        if isinstance(n, ast.ClassDef) and not any(ast.unparse(b) == "TypedDict" for b in n.bases)
    }
    declared |= {
        n.target.id for n in tree.body if isinstance(n, ast.AnnAssign) and isinstance(n.target, ast.Name)
    }
    exported = {n for n in dir(_core) if not n.startswith("_")} | {"__version__"}
    assert declared == exported
