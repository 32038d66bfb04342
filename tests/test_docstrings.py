"""Every public function documents itself in numpydoc sections with an example, and every example runs.

The public API is every name in ``gnssatt.__all__`` and the ``__all__`` of each module the API reference
lists (``docs/api/index.md``, the single source: a module added there is checked here). Each public function's
docstring is parsed with :class:`numpydoc.docscrape.FunctionDoc` and must have

- ``Parameters`` when the function takes parameters;
- ``Returns`` or ``Yields`` when its body returns or yields a value (an :mod:`ast` walk of its source; a
  compiled function always returns one);
- ``Raises`` when it takes parameters: every parameter passes through the intake (:mod:`gnssatt._arrays`),
  which raises :class:`gnssatt.errors.InvalidInputError` on a wrong type, shape or non-finite value;
- ``Examples``, which the second test runs as doctests.

Classes are documented by the examples of the functions that make them; exceptions and constants carry no
sections. Every public function has all its sections: a new one without them fails here.

The doctests run through :mod:`doctest` on the imported package rather than through
``pytest --doctest-modules python/gnssatt``: CI runs this suite a second time against the installed wheel
(``.ci/run``), where the source tree has no compiled ``_core``; importing the package by name checks the
examples against whichever build is installed.
"""

from __future__ import annotations

import ast
import doctest
import importlib
import inspect
import pkgutil
import re
import textwrap
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

import numpy as np
import numpydoc.docscrape as numpydoc_docscrape  # in the test extra: this module never skips
import pytest

import gnssatt

ROOT = Path(__file__).resolve().parents[1]
API_INDEX = ROOT / "docs" / "api" / "index.md"


def api_modules() -> list[str]:
    """The modules the API reference lists, read from its autosummary block."""
    text = API_INDEX.read_text(encoding="utf-8")
    block = text.split(".. autosummary::", 1)[1].split("```", 1)[0]
    return [line.strip() for line in block.splitlines() if line.strip().startswith("gnssatt")]


def public_functions() -> dict[str, Callable[..., Any]]:
    """Qualified name (where it is defined) -> public function, each object once."""
    found: dict[str, Callable[..., Any]] = {}
    for module_name in api_modules():
        module = importlib.import_module(module_name)
        for name in getattr(module, "__all__", ()):
            obj = getattr(module, name)
            if inspect.isclass(obj) or inspect.ismodule(obj) or not callable(obj):
                continue
            found.setdefault(f"{obj.__module__}.{obj.__qualname__}", obj)
    return found


FUNCTIONS = public_functions()


def _own_nodes(func: ast.AST) -> Iterator[ast.AST]:
    """The nodes of a function's body, not those of functions or lambdas defined inside it."""
    stack = list(ast.iter_child_nodes(func))
    while stack:
        node = stack.pop()
        yield node
        if not isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef | ast.Lambda | ast.ClassDef):
            stack.extend(ast.iter_child_nodes(node))


def returns_value(func: Callable[..., Any]) -> tuple[bool, bool]:
    """(returns a value, yields): from the source, or (True, False) for a compiled function."""
    try:
        source = textwrap.dedent(inspect.getsource(func))
    except (OSError, TypeError):
        return True, False
    tree = ast.parse(source).body[0]
    nodes = list(_own_nodes(tree))
    yields = any(isinstance(n, ast.Yield | ast.YieldFrom) for n in nodes)
    returns = any(
        isinstance(n, ast.Return)
        and n.value is not None
        and not (isinstance(n.value, ast.Constant) and n.value.value is None)
        for n in nodes
    )
    return returns, yields


def missing_sections(func: Callable[..., Any]) -> tuple[str, ...]:
    """The numpydoc sections ``func``'s docstring lacks, in numpydoc order."""
    doc = numpydoc_docscrape.FunctionDoc(func)
    try:
        params = list(inspect.signature(func).parameters)
    except (TypeError, ValueError):  # a compiled function without a text signature
        params = ["?"]
    returns, yields = returns_value(func)
    missing = []
    if params and not doc["Parameters"]:
        missing.append("Parameters")
    if yields and not doc["Yields"]:
        missing.append("Yields")
    elif returns and not doc["Returns"]:
        missing.append("Returns")
    if params and not doc["Raises"]:
        missing.append("Raises")
    if not doc["Examples"]:
        missing.append("Examples")
    return tuple(missing)


def test_public_api_is_found() -> None:
    # The walk finds what the reference lists: a broken parse of the index would check nothing.
    assert {"gnssatt", "gnssatt.frames", "gnssatt.sim"} <= set(api_modules())
    assert "gnssatt.frames.geodetic_to_ecef" in FUNCTIONS
    assert len(FUNCTIONS) > 60


def test_missing_sections_are_detected() -> None:
    def bare(x: float) -> float:
        """Twice ``x``."""
        return 2 * x

    assert missing_sections(bare) == ("Parameters", "Returns", "Raises", "Examples")


@pytest.mark.parametrize("name", sorted(FUNCTIONS))
def test_numpydoc_sections(name: str) -> None:
    missing = missing_sections(FUNCTIONS[name])
    assert not missing, f"{name}: docstring lacks {', '.join(missing)} (numpydoc sections)"


def package_modules() -> list[str]:
    """Every module of the installed package (``__main__`` modules run the command: left out)."""
    names = ["gnssatt"]
    for info in pkgutil.walk_packages(gnssatt.__path__, "gnssatt."):
        if not re.search(r"(^|\.)__main__$", info.name):
            names.append(info.name)
    return sorted(names)


#: Outputs are rounded in the examples themselves (``np.round``, format strings), so exact matching is stable
#: across platforms; whitespace and ``...`` give room for array layout and long reprs.
DOCTEST_FLAGS = doctest.NORMALIZE_WHITESPACE | doctest.ELLIPSIS


@pytest.mark.slow
@pytest.mark.parametrize("module_name", package_modules())
def test_examples_run(module_name: str) -> None:
    module = importlib.import_module(module_name)
    finder = doctest.DocTestFinder(exclude_empty=True)
    runner = doctest.DocTestRunner(optionflags=DOCTEST_FLAGS)
    printed: list[str] = []
    with np.printoptions(legacy=False):
        for test in finder.find(module, module_name, globs={"np": np}):
            runner.run(test, out=printed.append)
    assert runner.failures == 0, "".join(printed)
