"""The last line of defence at the Rust boundary: a Rust panic becomes :class:`~gnssatt.errors.InternalError`.

pyo3 turns a panic into ``pyo3_runtime.PanicException``, which derives from :class:`BaseException`, so an
``except Exception`` in user code misses it and Monte Carlo workers die. The core is written not to panic on
any input; this wrapper, installed by ``gnssatt._core``'s own module initialisation (so before any module can
take a name from it), makes sure that a defect that still panics surfaces as an ordinary ``GnssattError``.
"""

from __future__ import annotations

import functools
from collections.abc import Callable
from types import ModuleType
from typing import Any

from gnssatt.errors import InternalError

_MARK = "__gnssatt_guarded__"


def _is_panic(exc: BaseException) -> bool:
    # PanicException is not importable by name; it is the one BaseException pyo3 defines in pyo3_runtime.
    cls = type(exc)
    return cls.__name__ == "PanicException" and cls.__module__ == "pyo3_runtime"


def _guarded(func: Callable[..., Any]) -> Callable[..., Any]:
    @functools.wraps(func)
    def call(*args: Any, **kwargs: Any) -> Any:
        try:
            return func(*args, **kwargs)
        except BaseException as exc:
            if _is_panic(exc):
                raise InternalError(
                    f"{func.__name__}: Rust core defect ({exc}); please report it with its input"
                ) from exc
            raise

    setattr(call, _MARK, True)
    return call


def install(module: ModuleType) -> None:
    """Replace every builtin function of ``module`` by a guarded wrapper (idempotent)."""
    for name, value in list(vars(module).items()):
        if (
            callable(value)
            and type(value).__name__ == "builtin_function_or_method"
            and not name.startswith("__")
        ):
            if not getattr(value, _MARK, False):
                setattr(module, name, _guarded(value))
