"""Outcome of one hostile call, and which outcomes break the contract of ``docs/robustness.md``."""

from __future__ import annotations

import dataclasses
from typing import Any

import numpy as np
from scipy.spatial.transform import Rotation

from gnssatt.errors import ConvergenceError, InternalError, InvalidInputError

ACCEPTED = "accepted-finite"
REFUSED = "refused-ok"
UNNAMED = "refused-unnamed"
WRONG = "wrong-exception"
PANIC = "panic"
ABORT = "abort"
HANG = "hang"
SILENT_NAN = "silent-nan"
ACCEPTED_INVALID = "accepted-invalid"  # input the contract says must be refused (complex, NaN, ...) was used
LAMBDA_WRONG = "lambda-wrong"
REFUSED_VALID = "refused-valid"  # the valid value in another form (layout, list, 0-d) was refused
HARNESS = (
    "harness-error"  # the harness itself failed (e.g. a value that cannot be sent): counted, to be fixed
)

ORDER = (
    ACCEPTED,
    REFUSED,
    UNNAMED,
    WRONG,
    PANIC,
    ABORT,
    HANG,
    SILENT_NAN,
    ACCEPTED_INVALID,
    LAMBDA_WRONG,
    REFUSED_VALID,
    HARNESS,
)
FAILURES = frozenset(ORDER) - {ACCEPTED, REFUSED}


def is_panic(exc: BaseException) -> bool:
    """A Rust panic: the library's InternalError, or pyo3's PanicException (a BaseException subclass)."""
    return isinstance(exc, InternalError) or type(exc).__name__ == "PanicException"


def classify_exception(exc: BaseException, names: tuple[str, ...]) -> str:
    """``names``: the words an input error's message must contain one of (the parameter, or a file's
    path); empty where any message will do."""
    if is_panic(exc):
        return PANIC
    if isinstance(exc, ConvergenceError):
        return REFUSED
    if isinstance(exc, InvalidInputError):
        text = str(exc)
        return REFUSED if not names or any(n in text for n in names) else UNNAMED
    return WRONG  # including a GnssattError that is neither an input error nor a refusal to answer


def nonfinite_path(
    value: Any, depth: int = 0, seen: set[int] | None = None, skip: frozenset[str] = frozenset()
) -> str | None:
    """Where in a result a NaN or infinity sits ("" for the value itself), or None if all is finite.

    Walks arrays, floats, tuples/lists/dicts, dataclasses, Rotations and gnssatt objects' attributes;
    top-level attributes named in ``skip`` are documented as possibly non-finite and not looked at."""
    seen = set() if seen is None else seen
    if depth > 5 or id(value) in seen:
        return None
    seen.add(id(value))
    if isinstance(value, bool | int | str | bytes | type(None)):
        return None
    if isinstance(value, float | complex | np.floating | np.complexfloating):
        return None if np.isfinite(value) else ""
    if isinstance(value, np.ndarray):
        if value.dtype.kind in "fc":
            return None if np.all(np.isfinite(value)) else ""
        if value.dtype.kind == "O":
            for i, v in enumerate(value.flat):
                p = nonfinite_path(v, depth + 1, seen)
                if p is not None:
                    return f"[{i}]{p}"
        return None
    if isinstance(value, Rotation):
        return None if np.all(np.isfinite(value.as_quat())) else ".as_quat()"
    if isinstance(value, dict):
        items: Any = value.items()
    elif isinstance(value, list | tuple):
        items = enumerate(value)
    elif dataclasses.is_dataclass(value):
        items = ((f.name, getattr(value, f.name)) for f in dataclasses.fields(value))
    elif type(value).__module__.startswith("gnssatt") and hasattr(value, "__dict__"):
        items = vars(value).items()
    else:
        return None
    for key, v in items:
        if depth == 0 and key in skip:
            continue
        p = nonfinite_path(v, depth + 1, seen)
        if p is not None:
            return f"[{key!r}]{p}" if not isinstance(key, str) else f".{key}{p}"
    return None


def classify_result(
    result: Any, *, must_refuse: bool, nan_output_ok: bool, nan_fields: frozenset[str] = frozenset()
) -> tuple[str, str]:
    """(outcome, detail) of a call that returned ``result``; ``nan_fields``: result attributes documented
    as possibly non-finite."""
    if must_refuse:
        return ACCEPTED_INVALID, f"returned {type(result).__name__}"
    if not nan_output_ok:
        where = nonfinite_path(result, skip=nan_fields)
        if where is not None:
            return SILENT_NAN, f"non-finite at result{where}"
    return ACCEPTED, ""


def describe(exc: BaseException) -> str:
    text = str(exc).splitlines()[0] if str(exc) else ""
    return f"{type(exc).__name__}: {text[:160]}"
