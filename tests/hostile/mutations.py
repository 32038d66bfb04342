"""Hostile replacements for one argument: the fixed categories of issue 15, and hypothesis strategies.

A :class:`Mutant` says whether the contract requires a refusal (``must_refuse``: a value of the wrong
kind, a non-finite value where finite ones are documented, an absurd amount of work); otherwise a call may
also succeed, as long as its results are finite.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp
from scipy.spatial.transform import Rotation

CATEGORIES = (
    "shape",
    "complex",
    "bool",
    "object",
    "str",
    "none",
    "nan",
    "+inf",
    "-inf",
    "huge",
    "tiny",
    "negative",
    "zero",
    "count",
    "work",
)

COUNTS = {"2**31": 2**31, "10**11": 10**11, "2**58": 2**58, "2**63": 2**63}
MISSING_PATH = "/nonexistent-gnssatt-hostile/dir/file.24o"


@dataclass(frozen=True)
class Mutant:
    category: str
    label: str
    value: Any
    must_refuse: bool


def kind(value: Any) -> str:
    """The harness's reading of a valid argument: numeric, bool, text, path, datetime, sequence, mapping or
    object (anything else: Rotation, Generator, dataclasses of the library, callables)."""
    if isinstance(value, bool | np.bool_):
        return "bool"
    if isinstance(value, str):
        return "text"
    if isinstance(value, os.PathLike):
        return "path"
    if isinstance(value, int | float | np.integer | np.floating):
        return "numeric"
    if isinstance(value, np.ndarray):
        if value.dtype.kind in "iuf":
            return "numeric"
        return "datetime" if value.dtype.kind == "M" else "object"
    if isinstance(value, tuple | list):
        try:
            arr = np.asarray(value)
        except ValueError:
            return "sequence"
        return "numeric" if arr.dtype.kind in "iuf" and arr.size else "sequence"
    if isinstance(value, dict):
        return "mapping"
    return "object"


def _poke(arr: np.ndarray, x: Any) -> np.ndarray:
    """A copy of ``arr`` (float or complex) with its middle element replaced by ``x``."""
    out = arr.astype(
        np.result_type(arr, type(x)) if not isinstance(x, np.datetime64) else arr.dtype, copy=True
    )
    if out.size:
        out.flat[out.size // 2] = x
    return out


def _numeric(value: Any, counts: bool, nonfinite_ok: bool) -> list[Mutant]:
    scalar = np.ndim(value) == 0
    a = np.asarray(value, dtype=np.float64)
    out: list[Mutant] = []

    def add(cat: str, label: str, v: Any, refuse: bool = False) -> None:
        out.append(Mutant(cat, label, v, refuse))

    if scalar:
        x = float(a)
        add("shape", "array(3)", np.full(3, x))
        add("shape", "empty", np.array([]))
        add("complex", "x+0.5j", complex(x, 0.5), True)
        add("bool", "True", True, True)
        add("object", "object()", object(), True)
        add("str", "'abc'", "abc", True)
        for cat, v in (("nan", np.nan), ("+inf", np.inf), ("-inf", -np.inf)):
            add(cat, cat, v, not nonfinite_ok)
        for v in (1e300, 1e20):
            add("huge", repr(v), v)
        for v in (1e-300, 5e-324):
            add("tiny", repr(v), v)
        add("negative", "-|x|", -abs(x) if x else -1.0)
        add("negative", "-1", -1)
        add("zero", "0", 0)
        add("zero", "0.0", 0.0)
    else:
        add("shape", "extra-dim", np.stack([a, a]))
        add("shape", "empty", a[:0])
        if a.ndim >= 1:
            add("shape", "missing-dim", a[0])
            add("shape", "wrong-inner+1", np.concatenate([a, a[..., :1]], axis=-1))
            if a.shape[-1] > 1:
                add("shape", "wrong-inner-1", a[..., :-1])
        add("complex", "complex128", a + 0.5j, True)
        add("bool", "bool array", np.ones(a.shape, dtype=bool), True)
        add("object", "object array", a.astype(object), True)
        add("str", "str array", a.astype(str), True)
        for cat, v in (("nan", np.nan), ("+inf", np.inf), ("-inf", -np.inf)):
            add(cat, f"{cat} at middle", _poke(a, v), not nonfinite_ok)
        add("huge", "x*1e20", a * 1e20 + (a == 0) * 1e20)
        add("huge", "1e300 at middle", _poke(a, 1e300))
        add("tiny", "x*1e-300", a * 1e-300)
        add("tiny", "5e-324 at middle", _poke(a, 5e-324))
        add("negative", "-|x|", -np.abs(a) - (a == 0))
        add("zero", "zeros", np.zeros_like(a))
    if counts:
        for label, c in COUNTS.items():
            add("count", label, c)
    return out


def _other(value: Any, k: str, free_text: bool = False) -> list[Mutant]:
    """Values of the wrong kind for a non-numeric argument; each must be refused."""
    out = [
        Mutant("bool", "True", True, True),
        Mutant("object", "object()", object(), True),
        Mutant("zero", "0", 0, True),
        Mutant("complex", "1+1j", 1 + 1j, True),
    ]
    if k == "text" and free_text:  # any text is valid (a marker name)
        pass
    elif k == "text":
        out.append(Mutant("str", "'not-a-valid-name'", "not-a-valid-name", True))
        out.append(Mutant("shape", "''", "", True))
    elif k == "path":  # any relative name is a valid path; an empty one is not
        out.append(Mutant("str", "''", "", True))
    else:
        out.append(Mutant("str", "'abc'", "abc", True))
    if k == "path":
        out.append(Mutant("str", "missing path", MISSING_PATH, True))
        if Path(value).is_dir():  # a folder argument gets a file, a file argument a folder
            out.append(Mutant("shape", "a file", __file__, True))
        else:
            out.append(Mutant("shape", "a folder", str(Path(value).parent), True))
    if k == "datetime":
        a = np.asarray(value)
        out.append(Mutant("nan", "NaT at middle", _poke(a, np.datetime64("NaT")), True))
        out.append(Mutant("shape", "empty", a[:0], False))
        out.append(Mutant("shape", "extra-dim", np.stack([a, a]), False))
    if k == "sequence":
        out.append(Mutant("shape", "empty", type(value)(), False))
        out.append(Mutant("shape", "nested", [value], False))
    if k == "mapping":
        out.append(Mutant("shape", "empty", {}, False))
    if isinstance(value, Rotation) and value.single:
        out.append(Mutant("shape", "5 rotations", Rotation.identity(5), False))
    return out


def mutants(
    value: Any,
    *,
    counts: bool,
    work: tuple[Any, ...],
    nonfinite_ok: bool,
    none_ok: bool,
    free_text: bool = False,
) -> list[Mutant]:
    """Every fixed mutation of one valid argument ``value``, in a fixed order."""
    k = kind(value)
    if k == "numeric":
        out = _numeric(value, counts, nonfinite_ok)
    elif k == "bool":
        out = [Mutant("object", "object()", object(), True), Mutant("str", "'abc'", "abc", True)]
    else:
        out = _other(value, k, free_text)
    if not none_ok:
        out.append(Mutant("none", "None", None, True))
    out.extend(Mutant("work", repr(w), w, True) for w in work)
    return out


def none_ok(param: str, default: Any) -> bool:
    """Whether None is valid input: a parameter defaulting to None, and every ``rng`` (None draws fresh
    entropy, docs/conventions.md "Randomness", also where ``rng`` comes before a required argument)."""
    return default is None or param == "rng"


def must_refuse_drawn(value: Any, valid_kind: str, *, nonfinite_ok: bool, none_ok: bool) -> bool:
    """Whether the contract requires refusing a value drawn by hypothesis for an argument whose valid
    value is of kind ``valid_kind``."""
    if value is None:
        return not none_ok
    if valid_kind == "bool":
        return False
    wrong_kind = isinstance(value, complex | bool | np.bool_) or (
        isinstance(value, np.ndarray) and value.dtype.kind in "cbOUS"
    )
    if valid_kind == "numeric":
        if isinstance(value, str) or wrong_kind:
            return True
        arr = np.asarray(value)
        return arr.dtype.kind in "fc" and not nonfinite_ok and not np.all(np.isfinite(arr))
    return wrong_kind or isinstance(value, int | float | np.ndarray)


_FLOATS = st.floats(allow_nan=True, allow_infinity=True, allow_subnormal=True, width=64)
_JUNK = st.one_of(
    st.none(),
    st.booleans(),
    st.integers(min_value=-(2**70), max_value=2**70),
    _FLOATS,
    st.complex_numbers(allow_nan=True, allow_infinity=True),
    st.text(max_size=4),
)


@st.composite
def hostile_value(draw: st.DrawFn, valid: Any) -> Any:
    """A hostile replacement for ``valid``: an array of a nearby shape with any float values (NaN,
    infinities, subnormals, 1e308), of a random dtype, or a junk scalar."""
    if kind(valid) != "numeric":
        return draw(_JUNK)
    shape = np.shape(valid)
    near = st.lists(st.integers(0, 5), min_size=max(len(shape) - 1, 0), max_size=len(shape) + 1).map(tuple)
    new_shape = draw(st.one_of(st.just(shape), near))
    dtype = draw(st.sampled_from(["float64", "float64", "float64", "int64", "complex128", "bool", "float32"]))
    if dtype == "int64":
        elements: Any = st.integers(-(2**63), 2**63 - 1)
    elif dtype == "bool":
        elements = st.booleans()
    elif dtype == "complex128":
        elements = st.complex_numbers(allow_nan=True, allow_infinity=True)
    else:
        elements = st.floats(allow_nan=True, allow_infinity=True, width=32 if dtype == "float32" else 64)
    if draw(st.integers(0, 4)) == 0:
        return draw(_JUNK)
    if draw(st.booleans()) and new_shape == shape and dtype == "float64":
        # the valid array with a few elements replaced keeps the call meaningful
        arr = np.array(valid, dtype=np.float64, copy=True)
        n = arr.size
        if n:
            for _ in range(draw(st.integers(1, 3))):
                arr.flat[draw(st.integers(0, n - 1))] = draw(_FLOATS)
        return arr if np.ndim(valid) else float(arr)
    return draw(hnp.arrays(dtype, new_shape, elements=elements))
