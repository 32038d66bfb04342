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
    # widened sweep (issue 15 follow-up): what real callers and fuzzers pass that the above misses
    "layout",
    "dtype",
    "list",
    "masked",
    "overflow",
    "signed-zero",
    "nan-position",
    "huge-size",
    "0-d",
    "text-junk",
    "rng",
    "rotation",
    "executor",
)

#: Rows of a zero-stride view for the "huge-size" category: 2^40 rows cost no memory as a view, and 8 TiB
#: or more as a copy, so an intake that copies before checking the size fails at once (MemoryError)
#: instead of slowly exhausting the machine.
HUGE_ROWS = 2**40

COUNTS = {"2**31": 2**31, "10**11": 10**11, "2**58": 2**58, "2**63": 2**63}
MISSING_PATH = "/nonexistent-gnssatt-hostile/dir/file.24o"


@dataclass(frozen=True)
class Mutant:
    """One hostile value. ``must_accept``: the value is the valid one in another form (another memory
    layout, a list, a 0-d array): refusing it is a failure too. ``propagates``: the value is user code
    that raises this exception class, which must come out of the call unchanged."""

    category: str
    label: str
    value: Any
    must_refuse: bool
    must_accept: bool = False
    propagates: str = ""


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


class _NoFutureExecutor:
    """An executor whose ``submit`` returns None instead of a Future (a broken duck type)."""

    def submit(self, fn: Any, *args: Any, **kwargs: Any) -> None:
        return None


class ExecutorDown(RuntimeError):
    """Raised by :class:`_RaisingExecutor`: user code's own error, to come out of the call unchanged."""


class _RaisingExecutor:
    """An executor whose ``submit`` raises (a cluster that went away)."""

    def submit(self, fn: Any, *args: Any, **kwargs: Any) -> None:
        raise ExecutorDown("executor is down")


def _readonly(a: np.ndarray) -> np.ndarray:
    out = a.copy()
    out.flags.writeable = False
    return out


def _widened_numeric(value: Any, nonfinite_ok: bool) -> list[Mutant]:
    """Memory layouts, dtypes, lists, masked arrays, overflow, signed zero, NaN at the ends, zero-stride
    views of absurd size and 0-d forms of a numeric argument."""
    orig = np.asarray(value)
    a = np.asarray(value, dtype=np.float64)
    out: list[Mutant] = []

    def add(cat: str, label: str, v: Any, refuse: bool = False, accept: bool = False) -> None:
        out.append(Mutant(cat, label, v, refuse, accept))

    if np.ndim(value) == 0:
        x = float(a)
        add("0-d", "0-d array", np.array(value), accept=True)
        add("0-d", "numpy scalar", orig[()], accept=True)
        add("0-d", "[x]", [value])
        add("dtype", "float32 scalar", np.float32(x))
        with np.errstate(over="ignore"):  # 7e6 m is inf in float16: a hostile value like any other
            add("dtype", "float16 scalar", np.float16(x))
        add("dtype", "Fraction", __import__("fractions").Fraction(1, 3))
        add("dtype", "Decimal", __import__("decimal").Decimal("1.5"))
        add("overflow", "10**400", 10**400)
        add("overflow", "-10**400", -(10**400))
        add("overflow", "max float", float(np.finfo(np.float64).max))
        add("overflow", "-max float", -float(np.finfo(np.float64).max))
        add("signed-zero", "-0.0", -0.0)
        add("masked", "np.ma.masked", np.ma.masked, True)
        add("masked", "masked 0-d", np.ma.masked_array(x, mask=True), not nonfinite_ok)
        return out

    # the valid array in other forms: these must be accepted like the original (a valid list of tuples,
    # such as (t0, t1, count) outages, is not the same as an array of floats, which may be refused)
    same = isinstance(value, np.ndarray)
    if a.ndim >= 2:
        add("layout", "Fortran order", np.asfortranarray(orig), accept=same)
    add("layout", "non-contiguous", np.repeat(orig, 2, axis=-1)[..., ::2], accept=same)
    add("layout", "read-only", _readonly(orig), accept=same)
    add("layout", "big-endian", orig.astype(orig.dtype.newbyteorder(">")), accept=same)
    add("list", "nested list", orig.tolist(), accept=same)
    add("masked", "nothing masked", np.ma.masked_array(orig), accept=same)
    if a.size:
        mask = np.zeros(a.shape, dtype=bool)
        mask.flat[a.size // 2] = True
        # a masked element holds garbage: using it silently is wrong, NaN in its place only where NaN is
        # documented input
        garbage = a.copy()
        garbage.flat[a.size // 2] = 12345.0
        add("masked", "middle masked", np.ma.masked_array(garbage, mask=mask), not nonfinite_ok)
        mixed = a.tolist()
        flat: Any = mixed
        while isinstance(flat[0], list):
            flat = flat[0]
        flat_str = [*flat]
        flat_str[0] = "1.0"
        add("list", "text in list", _replace_first_row(mixed, flat_str), True)
        flat_none = [*flat]
        flat_none[0] = None
        add("list", "None in list", _replace_first_row(mixed, flat_none), True)
        ragged = [*mixed, mixed[0]] if a.ndim == 1 else [*mixed[:-1], mixed[-1][:-1]]
        add("list", "ragged", ragged if a.ndim > 1 else [mixed, mixed[:-1]], True)
        add("list", "10**400 in list", _replace_first_row(mixed, [10**400, *flat[1:]]), True)
        for cat, label, pos in (("nan-position", "first", 0), ("nan-position", "last", a.size - 1)):
            b = a.copy()
            b.flat[pos] = np.nan
            add(cat, f"NaN at {label}", b, not nonfinite_ok)
        add("overflow", "max float", np.full(a.shape, np.finfo(np.float64).max))
        add(
            "overflow", "alternating +-1e308", np.where(np.arange(a.size) % 2, 1e308, -1e308).reshape(a.shape)
        )
        add("signed-zero", "-0.0", np.full(a.shape, -0.0))
        add("0-d", "0-d array", np.array(a.flat[0]))
        add("0-d", "Python float", float(a.flat[0]))
        rows = orig[:1] if a.ndim >= 1 else orig
        add(
            "huge-size",
            f"{HUGE_ROWS} rows (zero-stride view)",
            np.broadcast_to(rows, (HUGE_ROWS, *a.shape[1:])),
            True,
        )
    for dt in ("float32", "float16", "int8", "uint64", "longdouble"):
        with np.errstate(all="ignore"):
            add("dtype", dt, a.astype(dt))
    add("complex", "complex64", a.astype(np.complex64) + np.complex64(0.5j), True)
    add("dtype", "datetime64", np.zeros(a.shape, dtype="datetime64[s]"), True)
    add("dtype", "timedelta64", np.zeros(a.shape, dtype="timedelta64[s]"), True)
    add("dtype", "bytes", a.astype("S8"), True)
    return out


def _replace_first_row(nested: list[Any], row: list[Any]) -> list[Any]:
    """``nested`` (a list of numbers, or of lists) with its first innermost row replaced by ``row``."""
    if not nested or not isinstance(nested[0], list):
        return row
    return [_replace_first_row(nested[0], row), *nested[1:]]


def _widened_other(value: Any, k: str, param: str, free_text: bool) -> list[Mutant]:
    out: list[Mutant] = []
    if k == "bool":
        out.append(Mutant("0-d", "numpy bool", np.True_, False, True))
    if k == "text":
        out.append(Mutant("text-junk", "bytes", value.encode(), True))
        out.append(Mutant("text-junk", "NUL inside", value + "\x00x", not free_text))
        out.append(Mutant("text-junk", "100000 characters", "x" * 100_000, not free_text))
    if k == "path":
        out.append(Mutant("text-junk", "bytes path", os.fsencode(str(value)), True))
        out.append(Mutant("text-junk", "NUL in path", str(value) + "\x00x", True))
        out.append(Mutant("text-junk", "name of 5000 characters", "x" * 5000, True))
        out.append(Mutant("text-junk", "/dev/null", "/dev/null", False))  # a reader refuses, a writer may
    if isinstance(value, Rotation):
        n = 1 if value.single else len(value)
        quat = np.tile([np.nan, 0.0, 0.0, 1.0], (n, 1))
        try:
            bad = Rotation.from_quat(quat[0] if value.single else quat)
        except ValueError:
            bad = None
        if bad is not None:
            out.append(Mutant("rotation", "NaN quaternion", bad, True))
    if param in ("rng", "seed"):
        for label, v, refuse in (
            ("2**128", 2**128, False),
            ("-1", -1, True),
            ("1.5", 1.5, True),
            ("uint64 max", np.uint64(2**64 - 1), False),
            ("RandomState", np.random.RandomState(0), param == "rng"),
            ("SeedSequence", np.random.SeedSequence(3), False),
        ):
            out.append(Mutant("rng", label, v, refuse))
    if param == "executor":
        out.append(Mutant("executor", "submit returns None", _NoFutureExecutor(), True))
        out.append(
            Mutant("executor", "submit raises", _RaisingExecutor(), True, propagates=ExecutorDown.__name__)
        )
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
    param: str = "",
    counts: bool,
    work: tuple[Any, ...],
    nonfinite_ok: bool,
    none_ok: bool,
    free_text: bool = False,
) -> list[Mutant]:
    """Every fixed mutation of one valid argument ``value``, in a fixed order."""
    k = kind(value)
    if k == "numeric":
        out = _numeric(value, counts, nonfinite_ok) + _widened_numeric(value, nonfinite_ok)
        if param in ("rng", "seed"):
            out += _widened_other(value, k, param, free_text)
    elif k == "bool":
        out = [Mutant("object", "object()", object(), True), Mutant("str", "'abc'", "abc", True)]
        out += _widened_other(value, k, param, free_text)
    else:
        out = _other(value, k, free_text) + _widened_other(value, k, param, free_text)
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
        if isinstance(value, np.ma.MaskedArray) and np.ma.getmaskarray(value).any():
            return not nonfinite_ok  # a masked value used as if it were data
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
    dtype = draw(
        st.sampled_from(
            [
                "float64",
                "float64",
                "float64",
                "int64",
                "complex128",
                "bool",
                "float32",
                "float16",
                "int8",
                "uint64",
            ]
        )
    )
    if dtype == "int64":
        elements: Any = st.integers(-(2**63), 2**63 - 1)
    elif dtype == "bool":
        elements = st.booleans()
    elif dtype == "complex128":
        elements = st.complex_numbers(allow_nan=True, allow_infinity=True)
    else:
        width = {"float32": 32, "float16": 16}.get(dtype, 64)
        elements = st.floats(allow_nan=True, allow_infinity=True, width=width)
    if dtype == "int8":
        elements = st.integers(-128, 127)
    elif dtype == "uint64":
        elements = st.integers(0, 2**64 - 1)
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
    return _relayout(draw, draw(hnp.arrays(dtype, new_shape, elements=elements)))


def _relayout(draw: st.DrawFn, arr: np.ndarray) -> Any:
    """The drawn array as such, or in a form that survives the pickle to the worker: Fortran order,
    big-endian, a masked array with one element masked, a nested list."""
    form = draw(st.sampled_from(["as-is", "as-is", "fortran", "big-endian", "masked", "list"]))
    if form == "fortran":
        return np.asfortranarray(arr)
    if form == "big-endian":
        return arr.astype(arr.dtype.newbyteorder(">"))
    if form == "masked" and arr.size:
        mask = np.zeros(arr.shape, dtype=bool)
        mask.flat[draw(st.integers(0, arr.size - 1))] = True
        return np.ma.masked_array(arr, mask=mask)
    if form == "list":
        return arr.tolist()
    return arr
