"""The one mechanism for public names renamed to the conventions of ``docs/conventions.md``, and the one
intake of random-number generators.

A renamed keyword or attribute keeps working for one release and says which name replaces it, with a
:class:`DeprecationWarning` (``docs/conventions.md``, "Renamed names").
"""

from __future__ import annotations

import functools
import warnings
from collections.abc import Callable
from typing import Any, TypeVar

import numpy as np

from gnssatt.errors import InvalidInputError, InvalidTypeError

__all__ = ["RNG_TYPES", "generator", "renamed"]

T = TypeVar("T")

#: What an ``rng=`` argument accepts (scipy's convention): an integer seed, a Generator or None (fresh
#: entropy). A ``numpy.random.SeedSequence`` is also taken, since ``default_rng`` takes it.
RNG_TYPES = "an int, a numpy.random.Generator, a numpy.random.SeedSequence or None"


def generator(name: str, value: Any) -> np.random.Generator:
    """``numpy.random.default_rng(value)`` for an ``rng=`` argument: a Generator is used as given (and
    advanced), an integer seeds a new one (the same integer, the same draws), None draws fresh entropy.

    Raises
    ------
    InvalidTypeError
        ``value`` of another kind (a float, a bool, the legacy ``RandomState``).
    InvalidInputError
        A negative integer seed (``default_rng`` refuses it).
    """
    if isinstance(value, bool) or not (
        value is None
        or isinstance(value, np.random.Generator | np.random.SeedSequence)
        or isinstance(value, int | np.integer)
    ):
        raise InvalidTypeError(f"expected {name} as {RNG_TYPES}, got {type(value).__name__}")
    if isinstance(value, int | np.integer) and value < 0:
        raise InvalidInputError(f"expected {name} as a non-negative integer seed, got {value}")
    return np.random.default_rng(value)


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
