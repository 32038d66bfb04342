"""The one mechanism for public names renamed to the conventions of ``docs/conventions.md`` (the one
``rng=`` intake is :func:`gnssatt._arrays.generator`).

A renamed keyword or attribute keeps working for one release and says which name replaces it, with a
:class:`DeprecationWarning` (``docs/conventions.md``, "Renamed names").
"""

from __future__ import annotations

import functools
import warnings
from collections.abc import Callable
from typing import Any, TypeVar

from gnssatt.errors import InvalidInputError

__all__ = ["renamed"]

T = TypeVar("T")


def _warn(owner: str, old: str, new: str) -> None:
    warnings.warn(
        f"{owner}: {old!r} is deprecated, use {new!r} (the old name is removed in the next release)",
        DeprecationWarning,
        stacklevel=3,
    )


def renamed(**old_to_new: str) -> Callable[[T], T]:
    """Decorator keeping renamed names working for one release: ``@renamed(old="new")``.

    On a function: the keyword ``old=`` is passed on as ``new=`` (a :class:`DeprecationWarning` naming
    ``new``; both given is an :class:`~gnssatt.errors.InvalidInputError`). On a class: the same for the
    keywords of its constructor, and a read-only attribute ``old`` returning ``new`` (with the warning).
    """

    def wrap_call(func: Callable[..., Any], owner: str) -> Callable[..., Any]:
        @functools.wraps(func)
        def call(*args: Any, **kwargs: Any) -> Any:
            for old, new in old_to_new.items():
                if old in kwargs:
                    if new in kwargs:
                        raise InvalidInputError(f"{owner}: got both {old!r} and its new name {new!r}")
                    _warn(owner, old, new)
                    kwargs[new] = kwargs.pop(old)
            return func(*args, **kwargs)

        return call

    def alias(old: str, new: str, owner: str) -> property:
        def get(self: Any) -> Any:
            _warn(owner, old, new)
            return getattr(self, new)

        return property(get, doc=f"Deprecated name of :attr:`{new}`.")

    def decorate(obj: T) -> T:
        if isinstance(obj, type):
            obj.__init__ = wrap_call(obj.__init__, obj.__name__)  # type: ignore[misc]
            for old, new in old_to_new.items():
                setattr(obj, old, alias(old, new, obj.__name__))
            return obj
        return wrap_call(obj, getattr(obj, "__qualname__", repr(obj)))  # type: ignore[arg-type, return-value]

    return decorate
