"""The package imports downwards only, and no module takes another's private names (``docs/architecture.md``).

Every module of ``python/gnssatt`` is parsed with :mod:`ast` (imports inside functions and ``TYPE_CHECKING``
blocks included) and each import is checked against :data:`LAYERS`, the one table of the layout (the graph in
``docs/architecture.md`` is drawn from it by ``benches/python/import_graph.py``, and checked here to be
current).
"""

from __future__ import annotations

import ast
from collections.abc import Iterator
from pathlib import Path

import pytest

from gnssatt import _core

ROOT = Path(__file__).resolve().parents[1]
PACKAGE = ROOT / "python" / "gnssatt"
DOC = ROOT / "docs" / "architecture.md"

#: Layers, base first, each with its units: a unit is a top-level module or subpackage of gnssatt
#: (``__init__`` is the package's own lazy re-export table), or a module of a subpackage that lies in another
#: layer than its package (``orbit.determination``: the orbit estimator beside the orbit models). A module may
#: import its own unit or a lower layer.
LAYERS: tuple[tuple[str, tuple[str, ...]], ...] = (
    ("kernel", ("_core", "errors")),
    ("intake", ("_arrays", "constants")),
    ("base", ("frames", "rotation", "geometry", "observations", "data")),
    ("models", ("orbit", "magnetic")),
    ("io", ("rinex",)),
    ("estimators", ("attitude", "ambiguity", "orbit.determination", "gnss")),
    ("simulation", ("sim", "montecarlo")),
    ("plots", ("plots",)),
    ("experiments", ("experiments",)),
    ("command", ("cli",)),
    ("entry", ("__main__", "__init__")),
)

#: Units the simulator may not import although they lie below it: it must not borrow an estimator's model.
ESTIMATORS = dict(LAYERS)["estimators"]

#: Private modules of the base layer that every module may import: the designated shared internals.
SHARED_INTERNALS = ("_core", "_arrays")

#: Violations that need a function moved between modules: (importer, imported module or private name) -> what
#: to do. An entry that no longer occurs fails the test. Issue 19's entries are paid (the functions moved;
#: the old paths are gone, CHANGELOG.md).
KNOWN_DEBT: dict[tuple[str, str], str] = {}


def layer_of() -> dict[str, int]:
    """Unit -> layer index."""
    return {unit: i for i, (_, units) in enumerate(LAYERS) for unit in units}


def module_name(path: Path, package: Path = PACKAGE) -> str:
    parts = path.relative_to(package.parent).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def modules(package: Path = PACKAGE) -> dict[str, Path]:
    """Dotted name -> file of every module of the package (the compiled ``_core`` through its stub)."""
    found = {module_name(p, package): p for p in sorted(package.rglob("*.py"))}
    found[f"{package.name}._core"] = package / "_core.pyi"
    return found


def stub_only_names(stub: Path = PACKAGE / "_core.pyi") -> set[str]:
    """``gnssatt._core.NAME`` for each class the stub defines and the compiled module lacks: the TypedDicts of
    its dict arguments, named privately only because stubtest refuses a public stub name absent at runtime.
    They annotate the wrappers that build those dicts; no runtime name of another module is taken."""
    tree = ast.parse(stub.read_text(), filename=str(stub))
    names = {node.name for node in tree.body if isinstance(node, ast.ClassDef)}
    return {f"gnssatt._core.{name}" for name in names if not hasattr(_core, name)}


def unit(module: str) -> str:
    parts = module.split(".")
    if len(parts) > 2 and ".".join(parts[1:3]) in layer_of():
        return ".".join(parts[1:3])
    return parts[1] if len(parts) > 1 else "__init__"


def _is_private(part: str) -> bool:
    return part.startswith("_") and not part.startswith("__")


def imports(module: str, path: Path, known: set[str]) -> Iterator[tuple[str, int]]:
    """``(target, line)`` for every gnssatt import of ``module``: a target is a module, or ``module.name``
    for an imported name that is not a module (function-level imports and attribute chains included)."""
    if path.suffix == ".pyi":
        return
    tree = ast.parse(path.read_text(), filename=str(path))
    package = module if path.name == "__init__.py" else module.rpartition(".")[0]
    bound: dict[str, str] = {}  # local name -> gnssatt module it is bound to
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            for alias in node.names:
                if alias.name.split(".")[0] == "gnssatt":
                    yield alias.name, node.lineno
                    if alias.asname:
                        bound[alias.asname] = alias.name
                    else:
                        bound["gnssatt"] = "gnssatt"
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                anchor = package.split(".")[: len(package.split(".")) - node.level + 1]
                base = ".".join([*anchor, *([node.module] if node.module else [])])
            if base.split(".")[0] != "gnssatt":
                continue
            for alias in node.names:
                full = f"{base}.{alias.name}"
                if full in known:
                    yield full, node.lineno
                    bound[alias.asname or alias.name] = full
                else:
                    yield (full if _is_private(alias.name) else base), node.lineno
    for node in ast.walk(tree):
        # private attributes reached through a bound module: gnssatt.sim._util.x, wahba._vectors
        if isinstance(node, ast.Attribute) and not isinstance(getattr(node, "ctx", None), ast.Store):
            chain, value = [node.attr], node.value
            while isinstance(value, ast.Attribute):
                chain.insert(0, value.attr)
                value = value.value
            if not (isinstance(value, ast.Name) and value.id in bound and any(map(_is_private, chain))):
                continue
            target = bound[value.id]
            for part in chain:
                if f"{target}.{part}" in known:
                    target = f"{target}.{part}"
                elif _is_private(part):
                    yield f"{target}.{part}", node.lineno
                    break
                else:
                    break
            else:
                yield target, node.lineno


def edges(package: Path = PACKAGE) -> dict[tuple[str, str], int]:
    """(importer, target) -> first line, over the whole package."""
    known = set(modules(package))
    out: dict[tuple[str, str], int] = {}
    for module, path in modules(package).items():
        for target, line in imports(module, path, known):
            if target != module:
                out.setdefault((module, target), line)
    return out


def violation(importer: str, target: str, known: set[str]) -> str | None:
    """Why ``importer`` may not import ``target``, or None."""
    layers = layer_of()
    if target not in known:
        if target in stub_only_names():
            return None
        owner, _, name = target.rpartition(".")
        if owner in known and _is_private(name):
            return f"imports the private name {name} of {owner}"
        return f"imports {target}, no module of the package (an old path? see CHANGELOG.md)"
    parts = target.split(".")
    for i, part in enumerate(parts):
        owner = ".".join(parts[:i])
        if _is_private(part) and not (owner == "gnssatt" and part in SHARED_INTERNALS):
            if not importer.startswith(f"{owner}."):
                return f"imports {target}, private to {owner}"
    src, dst = unit(importer), unit(target)
    for u in (src, dst):
        if u not in layers:
            return f"unit {u} is in no layer of LAYERS"
    if src == dst:
        return None
    if src == "sim" and dst in ESTIMATORS:
        return f"the simulator imports the estimator {target}"
    if layers[dst] > layers[src]:
        return f"imports {target} of the higher layer {LAYERS[layers[dst]][0]}"
    if layers[dst] == layers[src]:
        return f"imports {target} of another unit of its layer ({LAYERS[layers[dst]][0]})"
    return None


def violations(package: Path = PACKAGE) -> dict[tuple[str, str], str]:
    known = set(modules(package))
    found = {}
    for (importer, target), line in edges(package).items():
        why = violation(importer, target, known)
        if why is not None:
            found[importer, target] = f"{importer} line {line}: {why}"
    return found


def test_every_module_lies_in_a_layer() -> None:
    layers = layer_of()
    assert sorted({unit(m) for m in modules()} - set(layers)) == []
    assert len(layers) == sum(len(units) for _, units in LAYERS)  # no unit in two layers


@pytest.mark.slow
def test_imports_go_downwards_and_take_no_private_names() -> None:
    found = violations()
    new = sorted(why for key, why in found.items() if key not in KNOWN_DEBT)
    assert new == []
    fixed = sorted(f"{a} -> {b}" for a, b in KNOWN_DEBT if (a, b) not in found)
    assert fixed == [], "debt paid: delete these entries from KNOWN_DEBT"


@pytest.mark.slow
@pytest.mark.parametrize(
    ("importer", "target", "expected"),
    [
        ("gnssatt.frames", "gnssatt.sim.arrays", "higher layer simulation"),
        ("gnssatt.attitude.gyro_gnss", "gnssatt.sim", "higher layer simulation"),
        ("gnssatt.sim.spaceborne", "gnssatt.orbit.determination", "the simulator imports the estimator"),
        ("gnssatt.orbit.kepler", "gnssatt.orbit.determination", "higher layer estimators"),
        ("gnssatt.attitude.likelihood", "gnssatt.ambiguity", "another unit of its layer"),
        ("gnssatt.rinex.nav", "gnssatt.gnss.attitude", "higher layer estimators"),
        ("gnssatt.plots", "gnssatt.attitude.wahba._vectors", "private name _vectors"),
        ("gnssatt.sim.rinex_scenario", "gnssatt.rinex._fields", "private to gnssatt.rinex"),
        ("gnssatt.orbit", "gnssatt.tumble", "no module of the package"),
        ("gnssatt.plots", "gnssatt.rinex.AttitudeSeries", "no module of the package"),
    ],
)
def test_the_rules_catch_each_kind_of_violation(importer: str, target: str, expected: str) -> None:
    why = violation(importer, target, set(modules()))
    assert why is not None and expected in why


@pytest.mark.parametrize(
    ("importer", "target"),
    [
        ("gnssatt.rinex.nav", "gnssatt.rinex._fields"),  # a private module of its own package
        ("gnssatt.sim.measurements", "gnssatt._arrays"),  # a designated shared internal
        ("gnssatt.experiments.gyro_gnss", "gnssatt.sim"),  # the top uses the simulator
        ("gnssatt.sim.spaceborne", "gnssatt.orbit.constellation"),  # the simulator builds on the models
        ("gnssatt.attitude.dynamics", "gnssatt._core._TumbleModelArgs"),  # a stub-only annotation
    ],
)
def test_the_rules_allow_what_the_layout_allows(importer: str, target: str) -> None:
    assert violation(importer, target, set(modules())) is None


def test_the_walk_sees_function_level_imports_and_attribute_chains(tmp_path: Path) -> None:
    pkg = tmp_path / "gnssatt"
    (pkg / "sim").mkdir(parents=True)
    for name in ("__init__.py", "_core.pyi", "frames.py", "sim/__init__.py", "sim/_util.py"):
        (pkg / name).write_text("")
    (pkg / "frames.py").write_text(
        "import gnssatt.sim as s\n\ndef f():\n    from gnssatt.sim import _util\n    return s._hidden\n"
    )
    found = violations(pkg)
    assert set(found) == {
        ("gnssatt.frames", "gnssatt.sim"),
        ("gnssatt.frames", "gnssatt.sim._util"),
        ("gnssatt.frames", "gnssatt.sim._hidden"),
    }


@pytest.mark.slow
def test_the_architecture_page_shows_the_current_graph() -> None:
    import sys

    sys.path.insert(0, str(ROOT / "benches" / "python"))
    try:
        from import_graph import BEGIN, END, mermaid
    finally:
        sys.path.pop(0)
    text = DOC.read_text()
    shown = text[text.index(BEGIN) + len(BEGIN) : text.index(END)]
    assert shown.strip() == mermaid().strip(), "run python benches/python/import_graph.py --write"
