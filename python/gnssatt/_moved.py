"""Old import paths of modules and names that moved (issue 19, ``docs/architecture.md``), kept working with a
:class:`DeprecationWarning` that names the new path.

One table, :data:`MOVED`, serves both kinds of old path:

- a module (``import gnssatt.tumble``, ``from gnssatt.sim import constants``): the meta-path finder of
  ``gnssatt/__init__.py`` (appended to :data:`sys.meta_path`, so asked only after the real files were not
  found) asks :func:`find_spec`, whose loader answers with the new module itself: old and new paths give
  the same object;
- a name a package used to re-export (``gnssatt.rinex.attitude_from_rinex``): the package's ``__getattr__``
  asks :func:`moved_attribute`.

Nothing imports this module until an old path or an unknown name is used, so that ``import gnssatt`` stays
as cheap as before (``benches/python/import_time.py``).
"""

from __future__ import annotations

import importlib
import os
import sys
import warnings
from importlib.abc import Loader
from importlib.machinery import ModuleSpec
from types import ModuleType
from typing import Any

#: Old dotted path -> new dotted path. A key names a module or, after its module, an attribute; so does
#: its value. docs/architecture.md shows the same table.
MOVED: dict[str, str] = {
    "gnssatt.matrix_method": "gnssatt.attitude.matrix_method",
    "gnssatt.likelihood": "gnssatt.attitude.likelihood",
    "gnssatt.vector_attitude": "gnssatt.attitude.wahba",
    "gnssatt.magnetometer": "gnssatt.attitude.magnetometer",
    "gnssatt.gyro_gnss": "gnssatt.attitude.gyro_gnss",
    "gnssatt.phase_attitude": "gnssatt.attitude.phase_attitude",
    "gnssatt.visibility": "gnssatt.attitude.visibility",
    "gnssatt.tumble": "gnssatt.attitude.dynamics",
    "gnssatt.sim.constants": "gnssatt.constants",
    "gnssatt.sim.frames": "gnssatt.frames",
    "gnssatt.sim.kepler": "gnssatt.orbit.kepler",
    "gnssatt.sim.constellation": "gnssatt.orbit.constellation",
    "gnssatt.sim.receivers": "gnssatt.orbit.receivers",
    "gnssatt.sim.geometry": "gnssatt.orbit.line_of_sight",
    "gnssatt.sim.visibility": "gnssatt.orbit.masks",
    "gnssatt.rinex.attitude": "gnssatt.gnss.attitude",
    "gnssatt.rinex.session_input": "gnssatt.gnss.session_input",
    "gnssatt.rinex.scenario": "gnssatt.sim.rinex_scenario",
    "gnssatt.rinex.attitude_from_rinex": "gnssatt.gnss.attitude.attitude_from_rinex",
    "gnssatt.rinex.AttitudeSeries": "gnssatt.gnss.attitude.AttitudeSeries",
}


_IMPORTLIB = os.path.dirname(importlib.__file__)
_PACKAGE = os.path.dirname(__file__)


def _warn(old: str, new: str) -> None:
    # Blame the first frame outside the import machinery and this package (whose own modules never use an
    # old path, tests/test_import_layers.py): the user's import line or attribute access.
    level, frame = 2, sys._getframe(1)
    while frame is not None and frame.f_code.co_filename.startswith(
        ("<frozen importlib", _IMPORTLIB, _PACKAGE)
    ):
        # warnings itself skips importlib's _bootstrap frames when it counts the stack level
        internal = "importlib" in frame.f_code.co_filename and "_bootstrap" in frame.f_code.co_filename
        level, frame = level + (not internal), frame.f_back  # type: ignore[assignment]
    warnings.warn(f"{old} moved to {new}; import it from there", DeprecationWarning, stacklevel=level)


def _resolve(path: str) -> Any:
    """The module or module attribute a dotted ``path`` names."""
    if path in sys.modules:
        return sys.modules[path]
    try:
        return importlib.import_module(path)
    except ModuleNotFoundError as exc:
        module, _, name = path.rpartition(".")
        if exc.name != path:
            raise
        return getattr(importlib.import_module(module), name)


class _Loader(Loader):
    """Loads an old module path as the new module object (no second copy, no re-execution)."""

    def __init__(self, old: str, new: str) -> None:
        self.old, self.new = old, new

    def create_module(self, spec: ModuleSpec) -> ModuleType:
        module = _resolve(self.new)
        if not isinstance(module, ModuleType):  # an attribute key: served by moved_attribute only
            raise ImportError(f"{self.old} moved to {self.new}, which is not a module", name=self.old)
        _warn(self.old, self.new)
        self._spec = module.__spec__
        return module

    def exec_module(self, module: ModuleType) -> None:
        # The import system has just set the new module's __spec__ to the old path's; give it back.
        module.__spec__ = self._spec


def find_spec(fullname: str) -> ModuleSpec | None:
    """The spec that loads an old module path of :data:`MOVED` as its new module, or None (the finder that
    ``gnssatt/__init__.py`` appends to :data:`sys.meta_path` asks this)."""
    new = MOVED.get(fullname)
    return None if new is None else ModuleSpec(fullname, _Loader(fullname, new))


def moved_attribute(module: str, name: str) -> Any:
    """``module.name`` from its new home, with a warning; :class:`AttributeError` if it never moved.

    For a package's ``__getattr__``: ``def __getattr__(name): return moved_attribute(__name__, name)``. The
    value is then cached on the package (``from package import name`` looks it up twice), so that, as for a
    moved module, the warning comes once.
    """
    old = f"{module}.{name}"
    new = MOVED.get(old)
    if new is None:
        raise AttributeError(f"module {module!r} has no attribute {name!r}")
    value = _resolve(new)
    _warn(old, new)
    setattr(sys.modules[module], name, value)
    return value
