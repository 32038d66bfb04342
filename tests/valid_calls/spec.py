"""What a valid call is (:class:`Call`) and what its arguments mean to the tests (:class:`Arg`)."""

from __future__ import annotations

import importlib
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import Any

WORK_TINY_STEP = (1e-300, 1e-9)  # integration steps: 1e300 and 1e9+ steps per second of span


@dataclass(frozen=True)
class Arg:
    """What one argument means to the tests (every field optional: the defaults are "nothing special").

    Attributes
    ----------
    kind
        For the estimators' per-argument intake cases (``test_intake_estimators``): ``"array"``,
        ``"scalar"``, ``"integer"``, ``"choice"``, ``"flag"`` or ``"object"``, from which the categories of
        bad values follow; ``""``: not in those cases.
    shapes
        Wrong-shaped replacements that must be refused.
    out_of_range
        Finite values of the right kind that must be refused.
    optional
        None is valid (a default or "none given").
    limited
        An integer that sizes the work has a documented limit (an absurd one is a ``WorkLimitError``).
    label
        The name the message uses, where it differs (a field: ``"phases.los"``).
    count
        An integer that sizes work or memory: the hostile suite passes overflow-size counts.
    work
        Absurd values (tiny steps, huge spans) that must be refused before the work starts.
    nonfinite_ok
        NaN/inf is documented input (e.g. missing observations).
    free_text
        Any (short, printable) text is valid, such as a marker name: no invalid-name or empty-text mutants.
    complex_ok
        Complex values are documented input (e.g. correlator outputs).
    """

    kind: str = ""
    shapes: tuple[Any, ...] = ()
    out_of_range: tuple[Any, ...] = ()
    optional: bool = False
    limited: bool = True
    label: str | None = None
    count: bool = False
    work: tuple[Any, ...] = ()
    nonfinite_ok: bool = False
    free_text: bool = False
    complex_ok: bool = False


NO_ARG = Arg()


@dataclass(frozen=True)
class Call:
    """A valid call of one public function.

    Attributes
    ----------
    build
        Returns fresh valid keyword arguments; only these are mutated (others keep their defaults).
    args
        The arguments with a special meaning (:class:`Arg`); ``arg(name)`` gives :data:`NO_ARG` for the rest.
    nan_output
        Why the result may hold NaN (documented "not available" fields), or None: all outputs must be finite.
    nan_fields
        Result attributes documented as possibly non-finite (the rest is checked).
    function
        What is called, for the calls that are not a public function by that name (``OTHER_CALLS``:
        classes, methods, a second form of a function); None: ``resolve(name)``.
    """

    build: Callable[[], dict[str, Any]]
    args: Mapping[str, Arg] = field(default_factory=dict)
    nan_output: str | None = None
    nan_fields: frozenset[str] = frozenset()
    function: Callable[..., Any] | None = None

    def arg(self, name: str) -> Arg:
        return self.args.get(name, NO_ARG)


def resolve(qualified: str) -> Callable[..., Any]:
    """The public function named ``qualified`` (``module.attribute``)."""
    module, attr = qualified.rsplit(".", 1)
    return getattr(importlib.import_module(module), attr)
