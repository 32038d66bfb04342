"""The one intake of user arguments: arrays, real scalars and integers, checked before anything reaches Rust.

Every public function passes its arguments through these helpers, so that bad input always gets the same
kind of answer: :class:`~gnssatt.errors.InvalidTypeError` (a ``TypeError`` and a ``ValueError``) for a value
of the wrong kind (complex, object, boolean or text where real numbers are expected), and
:class:`~gnssatt.errors.InvalidInputError` for a wrong shape, a non-finite value or a value out of range. Each
message names the parameter, what was expected and what came.
"""

from __future__ import annotations

import math
import operator
import os
import re
import sys
from os import PathLike
from pathlib import Path
from types import UnionType
from typing import Any, TypeVar, overload

import numpy as np
from numpy.typing import NDArray

from gnssatt.errors import ConvergenceError, InvalidInputError, InvalidTypeError, WorkLimitError

__all__ = [
    "MAX_BATCH_ROWS",
    "MAX_BATCH_VALUES",
    "batch_limit",
    "checked_array",
    "choice",
    "finite_outputs",
    "finite_result",
    "flag",
    "float_array",
    "folder_path",
    "generator",
    "instance",
    "integer",
    "integer_array",
    "path_text",
    "plain_array",
    "readonly",
    "real_array",
    "rows",
    "sat_list",
    "scalar",
    "shaped",
    "text",
    "time_array",
    "unit_rows",
    "vector_array",
]

# The checked value keeps the type the caller names: the class given to ``instance``, the literal options
# given to ``choice``.
_T = TypeVar("_T")
_Choice = TypeVar("_Choice", bound=str)


#: Elements of one array argument (2^28: 2 GiB as float64), checked before the array is copied or scanned,
#: so that a zero-stride view such as ``numpy.broadcast_to(x, (2**40, 3))`` is refused at once instead of
#: allocating terabytes. The functions' own work limits (docs/limits.md) are far below it.
MAX_ELEMENTS = 2**28


def _unmasked(name: str, value: Any, *, nan_for_masked: bool = False) -> Any:
    """The data of a ``numpy.ma`` masked array with nothing masked (plain numpy would silently use the
    values under the mask); masked entries become NaN where NaN is documented input (``nan_for_masked``)
    and are refused otherwise. Any other value is returned unchanged."""
    # numpy >= 2 loads numpy.ma on first use of ``np.ma``, 30-50 ms of a command-line start; a masked array
    # can only exist once numpy.ma is loaded, so without it there is nothing to look for.
    if "numpy.ma" not in sys.modules or not isinstance(value, np.ma.MaskedArray):
        return value
    mask = np.ma.getmaskarray(value)
    if not mask.any():
        return np.ma.getdata(value)
    if nan_for_masked and value.dtype.kind in "iuf":
        return np.where(mask, np.nan, np.ma.getdata(value).astype(np.float64))
    bad = tuple(int(i) for i in np.argwhere(mask)[0]) if mask.ndim else ()
    raise InvalidInputError(
        f"expected {name} without masked values, got a numpy.ma masked array with a masked value at index "
        f"{bad}: fill it (numpy.ma.filled) or leave it out"
    )


def _size_limit(name: str, arr: np.ndarray) -> None:
    if arr.size > MAX_ELEMENTS:
        raise WorkLimitError(
            f"{name} has {arr.size} elements (shape {arr.shape}), more than the limit of {MAX_ELEMENTS}"
        )


#: Most rows (epochs, points, lines of sight) of one call of a vectorised transform or batch estimator that
#: has no limit of its own, counted from the shapes before anything is copied: 0.5-3 us a row on the loaded
#: 2-core build machine (``docs/limits.md``), so about 1-6 s; 10^7 rows took 5-60 s.
MAX_BATCH_ROWS = 2**21

#: Most values of one call of an element-wise numpy transform (``wrap_rad``, ``phase_diffs``, the troposphere
#: and its mapping functions, ``correlator_amplitude``), counted over all dimensions before anything is
#: copied: 24-70 ns and 24-48 bytes of temporaries a value (``docs/limits.md``), so under 2.5 s and 1.6 GB.
MAX_BATCH_VALUES = 2**25


def batch_limit(limit: int, constant: str, unit: str, /, **arguments: tuple[Any, int]) -> None:
    """Refuses a batch call whose largest argument holds more than ``limit`` items, counted from the shapes
    alone, before anything is copied, converted or scanned: the one whole-call limit of the batch entry
    points (``docs/limits.md``). A zero-stride ``numpy.broadcast_to`` view of 10^7 rows costs nothing to pass
    and seconds per million rows to copy and compute.

    Parameters
    ----------
    limit
        The most items one call takes.
    constant
        The name of the module constant that holds ``limit`` (named in the message).
    unit
        What one item is, plural (``"epochs"``, ``"vectors"``), for the message.
    **arguments
        ``name=(value, item_ndim)``: an argument and the number of its trailing dimensions that make one
        item (1 for a (3,) vector in an (n, 3) batch, 0 for a scalar in an (n,) batch); the item count is the
        product of the other dimensions.

    Raises
    ------
    WorkLimitError
        The argument with the most items exceeds ``limit``: the message names it, the count and the limit.
    """
    counts = {}
    for name, (value, item_ndim) in arguments.items():
        shape = np.shape(plain_array(name, value))
        counts[name] = math.prod(shape[: max(len(shape) - item_ndim, 0)])
    name = max(counts, key=lambda n: counts[n])
    if counts[name] > limit:
        raise WorkLimitError(
            f"{name} asks for {counts[name]} {unit}, more than the limit of {limit} ({constant}) of one "
            f"call: split it into batches of at most {limit}"
        )


def plain_array(name: str, value: Any, *, nan_for_masked: bool = False) -> np.ndarray:
    """``numpy.asarray(value)`` for intakes that look at the dtype themselves (integer channels, NaN gaps),
    with the checks every intake shares: masked values refused (NaN with ``nan_for_masked``), at most
    :data:`MAX_ELEMENTS` elements, ragged sequences refused.

    Raises
    ------
    InvalidTypeError
        A ragged nested sequence.
    InvalidInputError
        A masked value (without ``nan_for_masked``); :class:`~gnssatt.errors.WorkLimitError` for more than
        :data:`MAX_ELEMENTS` elements.
    """
    try:
        arr = np.asarray(_unmasked(name, value, nan_for_masked=nan_for_masked))
    except (TypeError, ValueError) as exc:
        if isinstance(exc, InvalidInputError):
            raise
        raise InvalidTypeError(f"expected {name} as a numeric array, got {_describe(value)} ({exc})") from exc
    _size_limit(name, arr)
    return arr


def _describe(value: Any) -> str:
    if isinstance(value, np.ndarray):
        return f"an array of dtype {value.dtype}"
    return type(value).__name__


def _matches(got: tuple[int, ...], patterns: tuple[tuple[int | None, ...], ...]) -> bool:
    return any(
        len(p) == len(got) and all(d is None or d == n for d, n in zip(p, got, strict=True)) for p in patterns
    )


def float_array(
    name: str,
    value: Any,
    *,
    ndim: int | tuple[int, ...],
    shape: str,
    patterns: tuple[tuple[int | None, ...], ...] = (),
) -> NDArray[np.float64]:
    """``value`` as a C-contiguous float64 array with ``ndim`` dimensions (one of them, if a tuple) and, if
    ``patterns`` are given, a shape matching one of them (``None`` matches any length); the shape is checked
    before the value is copied or scanned.

    Real integer and floating input is converted; complex, boolean, object and text input is refused rather
    than silently converted (numpy would drop an imaginary part, or turn ``True`` into 1.0).

    Raises
    ------
    InvalidTypeError
        ``value`` is not an array of real numbers.
    InvalidInputError
        Wrong number of dimensions, or a non-finite value; ``shape`` is the expected shape as written in the
        message.
    """
    try:
        raw = np.asarray(_unmasked(name, value))
    except (TypeError, ValueError) as exc:  # ragged nested sequences
        raise InvalidTypeError(
            f"expected {name} as a numeric array of shape {shape}, got {_describe(value)} ({exc})"
        ) from exc
    if raw.dtype.kind not in "iuf":
        raise InvalidTypeError(
            f"expected {name} as a real numeric array of shape {shape}, got {_describe(raw)}"
        )
    _size_limit(name, raw)
    allowed = (ndim,) if isinstance(ndim, int) else ndim
    # the shape the conversion gives (numpy.ascontiguousarray makes a 0-d value one of shape (1,)), checked
    # before the copy: a zero-stride view of 10^7 rows cost seconds to convert
    converted = raw.shape if raw.ndim else (1,)
    if len(converted) not in allowed or (patterns and not _matches(converted, patterns)):
        raise InvalidInputError(f"expected {name} of shape {shape}, got {converted}")
    arr = np.ascontiguousarray(raw, dtype=np.float64)
    if not arr.flags.writeable:
        # a read-only input comes back as itself; scipy's Rotation.apply (and any in-place step) refuses it
        arr = arr.copy()
    if not np.all(np.isfinite(arr)):
        bad = tuple(int(i) for i in np.argwhere(~np.isfinite(arr))[0])
        raise InvalidInputError(f"{name} contains a non-finite value at index {bad}")
    return arr


def scalar(
    name: str,
    value: Any,
    *,
    minimum: float | None = None,
    maximum: float | None = None,
    strict: bool = False,
    unit: str = "",
) -> float:
    """``value`` as a finite Python float within ``[minimum, maximum]`` (open bounds if ``strict``).

    Raises
    ------
    InvalidTypeError
        ``value`` is not a real number (``None``, text, complex, boolean, an array of size other than one).
    InvalidInputError
        ``value`` is not finite or lies outside the bounds.
    """
    value = _unmasked(name, value)
    if isinstance(value, np.ndarray) and value.shape == () and value.dtype.kind in "iuf":
        value = value.item()
    if isinstance(value, bool | np.bool_) or not isinstance(value, int | float | np.integer | np.floating):
        raise InvalidTypeError(f"expected {name} as a real number, got {_describe(value)}")
    try:
        x = float(value)
    except OverflowError:  # a Python int beyond float range (10**400) is as good as infinite
        raise InvalidInputError(
            f"expected a finite {name}, got an integer of {len(str(abs(int(value))))} digits"
        ) from None
    u = f" {unit}" if unit else ""
    if not math.isfinite(x):
        raise InvalidInputError(f"expected a finite {name}, got {x}")
    if minimum is not None and (x <= minimum if strict else x < minimum):
        raise InvalidInputError(f"expected {name} {'>' if strict else '>='} {minimum}{u}, got {x}{u}")
    if maximum is not None and (x >= maximum if strict else x > maximum):
        raise InvalidInputError(f"expected {name} {'<' if strict else '<='} {maximum}{u}, got {x}{u}")
    return x


def integer(name: str, value: Any, *, minimum: int | None = None, maximum: int | None = None) -> int:
    """``value`` as a Python int within ``[minimum, maximum]``.

    A ``maximum`` is how a documented work limit is enforced: the message gives the request and the limit.

    Raises
    ------
    InvalidTypeError
        ``value`` is not an integer (floats such as ``3.0`` are refused too: a count is never fractional).
    InvalidInputError
        ``value`` lies outside the bounds (:class:`~gnssatt.errors.WorkLimitError` above ``maximum``).
    """
    value = _unmasked(name, value)  # operator.index reads the data under a mask
    if isinstance(value, bool | np.bool_):
        raise InvalidTypeError(f"expected {name} as an integer, got {_describe(value)}")
    try:
        n = operator.index(value)
    except TypeError as exc:
        raise InvalidTypeError(f"expected {name} as an integer, got {_describe(value)}") from exc
    if minimum is not None and n < minimum:
        raise InvalidInputError(f"expected {name} >= {minimum}, got {n}")
    if maximum is not None and n > maximum:
        raise WorkLimitError(f"{name} = {n} exceeds the limit of {maximum}")
    return n


# --- exact shapes, unit rows, integer arrays, options, flags, objects, finite outputs (issue 15, part C) ---


def shaped(name: str, value: Any, shape: str, *patterns: tuple[int | None, ...]) -> NDArray[np.float64]:
    """:func:`float_array` whose shape matches one of ``patterns`` (``None`` matches any length), e.g.
    ``shaped("los", los, "(n, 3)", (None, 3))``; ``shape`` is the expected shape as written in the message.

    Raises
    ------
    InvalidTypeError, InvalidInputError
        As :func:`float_array`, and for a shape that matches no pattern.
    """
    return float_array(
        name, value, ndim=tuple(sorted({len(p) for p in patterns})), shape=shape, patterns=patterns
    )


def unit_rows(name: str, value: Any, shape: str, *patterns: tuple[int | None, ...]) -> NDArray[np.float64]:
    """:func:`shaped` whose rows (last axis) are unit vectors to 1e-6, such as lines of sight.

    Raises
    ------
    InvalidTypeError, InvalidInputError
        As :func:`shaped`, and for a row whose norm differs from one (the message gives the row and its norm,
        computed without overflow).
    """
    a = shaped(name, value, shape, *patterns)
    big = np.max(np.abs(a), axis=-1, keepdims=True, initial=0.0)
    norm = big[..., 0] * np.linalg.norm(a / np.where(big > 0.0, big, 1.0), axis=-1)
    bad = np.abs(norm - 1.0) > 1e-6
    if np.any(bad):
        k = tuple(int(i) for i in np.argwhere(bad)[0])
        row = k[0] if len(k) == 1 else k
        raise InvalidInputError(f"expected unit lines of sight in {name}, row {row} has norm {norm[k]:.6g}")
    return a


def integer_array(name: str, value: Any, shape: str, *patterns: tuple[int | None, ...]) -> NDArray[np.int64]:
    """:func:`shaped` holding integers (of an integer dtype, or floats with integral values within +-2^53,
    where float64 still counts in ones), as int64: indices, arc ids, ambiguities.

    Raises
    ------
    InvalidTypeError, InvalidInputError
        As :func:`shaped`, and for a value that is not an integer (the message gives it and its index).
    """
    a = shaped(name, value, shape, *patterns)
    bad = (a != np.round(a)) | (np.abs(a) > 2.0**53)
    if np.any(bad):
        k = tuple(int(i) for i in np.argwhere(bad)[0])
        raise InvalidInputError(f"expected integers in {name}, got {a[k]} at index {k}")
    return a.astype(np.int64)


def choice(name: str, value: Any, options: tuple[_Choice, ...]) -> _Choice:
    """``value`` as one of the strings ``options`` (a method, a statistic, an Euler sequence ...).

    Raises
    ------
    InvalidTypeError
        ``value`` is not a string.
    InvalidInputError
        ``value`` is not one of ``options``.
    """
    listed = ", ".join(repr(o) for o in options)
    if not isinstance(value, str):
        raise InvalidTypeError(f"expected {name} as one of {listed}, got {_describe(value)}")
    if value not in options:
        raise InvalidInputError(f"expected {name} as one of {listed}, got {value!r}")
    return options[options.index(value)]  # the equal option itself, typed as one of the options


def flag(name: str, value: Any) -> bool:
    """``value`` as a bool; ``True``/``False`` (Python or numpy) only, since ``bool("no")`` is True.

    Raises
    ------
    InvalidTypeError
        ``value`` is not a boolean.
    """
    if not isinstance(value, bool | np.bool_):
        raise InvalidTypeError(f"expected {name} as True or False, got {_describe(value)}")
    return bool(value)


@overload
def instance(name: str, value: Any, cls: type[_T], what: str) -> _T: ...
@overload
def instance(name: str, value: Any, cls: UnionType | tuple[type, ...], what: str) -> Any: ...
def instance(name: str, value: Any, cls: type | UnionType | tuple[type, ...], what: str) -> Any:
    """``value`` itself if it is an instance of ``cls``; ``what`` says what is expected in the message.

    Raises
    ------
    InvalidTypeError
        ``value`` is not an instance of ``cls``.
    """
    if not isinstance(value, cls):
        raise InvalidTypeError(f"expected {name} as {what}, got {_describe(value)}")
    return value


def finite_result(what: str, value: _T, cause: str) -> _T:
    """``value`` unchanged if every entry is finite; otherwise a :class:`~gnssatt.errors.ConvergenceError`.

    The last guard of computations whose intermediates can overflow on finite but extreme input (fast
    rotation, huge velocities, huge noise levels): the caller gets an error that names the result and the
    inputs behind it (``cause``) rather than NaN or infinity.
    """
    arr = np.asarray(value)
    if arr.dtype.kind in "fc" and not np.all(np.isfinite(arr)):
        bad = tuple(int(i) for i in np.argwhere(~np.isfinite(arr))[0])
        raise ConvergenceError(f"{what} is not finite (at index {bad}); {cause}")
    return value


def finite_outputs(what: str, **outputs: Any) -> None:
    """The counterpart of the intake on the way out: every output of ``what`` finite, or
    :class:`~gnssatt.errors.ConvergenceError` naming the output and its first non-finite entry.

    Raises
    ------
    ConvergenceError
        An output holds NaN or infinity although every input was finite.
    """
    for name, value in outputs.items():
        arr = np.asarray(value, dtype=np.float64)
        if not np.all(np.isfinite(arr)):
            k = tuple(int(i) for i in np.argwhere(~np.isfinite(arr))[0]) if arr.ndim else ()
            raise ConvergenceError(
                f"{what} gave a non-finite {name} from finite input: {arr[k]} at index {k} of shape "
                f"{arr.shape}"
            )


# Intake of times, 3-vectors and typed arguments of the models and the simulator (once gnssatt.sim._util).


def checked_array(name: str, value: Any, *, ndim: tuple[int, ...], shape: str) -> NDArray[np.float64]:
    """Like :func:`gnssatt._arrays.float_array`, but 0-d input stays 0-d."""
    allowed = (*ndim, 1) if 0 in ndim else ndim
    arr = float_array(name, value, ndim=allowed, shape=shape)
    if np.ndim(value) == 0:
        return arr.reshape(())
    if arr.ndim not in ndim:
        raise InvalidInputError(f"expected {name} of shape {shape}, got {arr.shape}")
    return arr


def time_array(t: Any) -> NDArray[np.float64]:
    """``t`` (seconds from the scenario epoch) as a float64 array of shape () or (n_t,)."""
    return checked_array("t", t, ndim=(0, 1), shape="() or (n_t,)")


def real_array(name: str, value: Any) -> NDArray[np.float64]:
    """``value`` as a float64 array of real numbers that may hold NaN (where a value is unknown or not
    measured); complex, boolean, object, text and ragged input is refused as in ``float_array``."""
    try:
        arr = np.asarray(_unmasked(name, value, nan_for_masked=True))
    except ValueError as exc:  # ragged nested sequences
        raise InvalidTypeError(f"expected {name} as a real numeric array, got {exc}") from exc
    if arr.dtype.kind not in "iuf":
        raise InvalidTypeError(f"expected {name} as a real numeric array, got dtype {arr.dtype}")
    _size_limit(name, arr)
    return arr.astype(np.float64)


def vector_array(
    name: str, value: Any, *, ndim: int | tuple[int, ...], shape: str, nonzero: bool = False
) -> NDArray[np.float64]:
    """Like :func:`gnssatt._arrays.float_array` for arrays of 3-vectors: the last axis must have length 3
    and, with ``nonzero``, no vector may be zero (a direction is to be taken from it)."""
    arr = float_array(name, value, ndim=ndim, shape=shape)
    if arr.shape[-1:] != (3,):
        raise InvalidInputError(f"expected {name} of shape {shape}, got {arr.shape}")
    if nonzero and arr.size:
        with np.errstate(over="ignore"):  # only zero matters here
            norm = np.linalg.norm(arr, axis=-1)
        if np.any(norm == 0.0):
            bad = tuple(int(i) for i in np.argwhere(norm == 0.0)[0])
            raise InvalidInputError(f"expected non-zero vectors in {name}, got a zero vector at index {bad}")
    return arr


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
    value = _unmasked(name, value)  # .item() reads the data under a mask
    if isinstance(value, np.ndarray) and value.shape == () and value.dtype.kind in "iu":
        value = value.item()  # a 0-d integer array is an integer seed, as default_rng takes it
    if isinstance(value, bool) or not (
        value is None
        or isinstance(value, np.random.Generator | np.random.SeedSequence)
        or isinstance(value, int | np.integer)
    ):
        raise InvalidTypeError(f"expected {name} as {RNG_TYPES}, got {type(value).__name__}")
    if isinstance(value, int | np.integer) and value < 0:
        raise InvalidInputError(f"expected {name} as a non-negative integer seed, got {value}")
    return np.random.default_rng(value)


def text(name: str, value: Any, choices: tuple[str, ...] | None = None) -> str:
    """``value`` if it is a ``str`` (one of ``choices`` where given)."""
    checked = instance(name, value, str, "a str")
    if choices is not None and checked not in choices:
        raise InvalidInputError(f"expected {name} one of {list(choices)}, got {checked!r}")
    return checked


def readonly(*arrays: NDArray[Any] | None) -> None:
    """Mark arrays read-only (results held by frozen dataclasses)."""
    for a in arrays:
        if isinstance(a, np.ndarray):
            a.flags.writeable = False


def rows(name: str, value: Any, shape: tuple[int, ...], *, integers: bool = False) -> int:
    """Checks a field of a result type that is also an input: its shape (``()`` stands for any (n,)), a
    finite real array, or integers; returns its first dimension."""
    if integers:
        arr = np.asarray(value)
        if arr.size and arr.dtype.kind not in "iu":
            raise InvalidTypeError(f"expected {name} as integers, got dtype {arr.dtype}")
    else:
        arr = float_array(name, value, ndim=max(len(shape), 1), shape=str(shape or "(n,)"))
    if (shape and arr.shape != shape) or (not shape and arr.ndim != 1):
        raise InvalidInputError(f"expected {name} of shape {shape or '(n,)'}, got {arr.shape}")
    return int(arr.shape[0])


#: A satellite id: system letter and a two-digit PRN from 01.
_SAT_ID = re.compile(r"[GRECJSI](?:0[1-9]|[1-9]\d)")


#: POSIX limits of a path and of one of its names, bytes (Linux and macOS file systems).
_PATH_MAX = 4095
_NAME_MAX = 255


def path_text(path: object, name: str = "path") -> str:
    """The file name as text; a value that is not a path is refused (``Path(3)`` would read a descriptor),
    and so is an empty name."""
    if not isinstance(path, str | PathLike):
        raise InvalidTypeError(f"expected {name} as a str or os.PathLike, got {type(path).__name__}")
    text = str(path)
    if not text:
        raise InvalidInputError(f"expected {name} as a file name, got an empty one")
    # what open() and os.stat() refuse with a bare ValueError or OSError (ENAMETOOLONG): refused here, by name
    if "\x00" in text:
        raise InvalidInputError(f"expected {name} as a file name without NUL characters, got {text[:80]!r}")
    encoded = os.fsencode(text)
    longest = max(len(part) for part in encoded.split(b"/"))
    if len(encoded) > _PATH_MAX or longest > _NAME_MAX:
        raise InvalidInputError(
            f"expected {name} of at most {_PATH_MAX} bytes with names of at most {_NAME_MAX} bytes (the "
            f"POSIX limits), got {len(encoded)} bytes with a name of {longest}: {text[:80]!r}..."
        )
    return text


def folder_path(name: str, value: object) -> Path:
    """An existing folder given as a str or os.PathLike (an empty name is refused, not read as ``.``).

    Raises
    ------
    InvalidTypeError
        ``value`` is not a str or os.PathLike.
    InvalidInputError
        ``value`` is empty or not an existing folder.
    """
    p = Path(path_text(value, name))
    if not p.is_dir():
        raise InvalidInputError(f"expected {name} as an existing folder, got {str(p)!r}")
    return p


def sat_list(name: str, value: object) -> list[str]:
    """Satellite ids (a list, tuple or 1-d array of texts such as ``"G01"``) as a list of str.

    Raises
    ------
    InvalidTypeError
        ``value`` is not a sequence of texts (a single text too: ``"G01"`` would be three satellites).
    InvalidInputError
        No entry, or an entry that is not a satellite id (system letter GRECJSI and a two-digit PRN from 01).
    """
    if isinstance(value, np.ndarray) and value.ndim == 1 and value.dtype.kind == "U":
        value = [str(v) for v in value]
    if not isinstance(value, list | tuple) or not all(isinstance(v, str) for v in value):
        raise InvalidTypeError(
            f"expected {name} as a list of satellite ids such as 'G01', got {type(value).__name__}"
        )
    if not value:
        raise InvalidInputError(f"expected at least one satellite id in {name}, got none")
    for i, v in enumerate(value):
        if not _SAT_ID.fullmatch(v):
            raise InvalidInputError(f"expected satellite ids such as 'G01' in {name}, got {v!r} at index {i}")
    return list(value)
