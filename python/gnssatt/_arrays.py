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
from typing import Any

import numpy as np
from numpy.typing import NDArray

from gnssatt.errors import ConvergenceError, InvalidInputError, InvalidTypeError, WorkLimitError

__all__ = ["finite_result", "float_array", "integer", "scalar"]


def _describe(value: Any) -> str:
    if isinstance(value, np.ndarray):
        return f"an array of dtype {value.dtype}"
    return type(value).__name__


def float_array(name: str, value: Any, *, ndim: int | tuple[int, ...], shape: str) -> NDArray[np.float64]:
    """``value`` as a C-contiguous float64 array with ``ndim`` dimensions (one of them, if a tuple).

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
        raw = np.asarray(value)
    except (TypeError, ValueError) as exc:  # ragged nested sequences
        raise InvalidTypeError(
            f"expected {name} as a numeric array of shape {shape}, got {_describe(value)} ({exc})"
        ) from exc
    if raw.dtype.kind not in "iuf":
        raise InvalidTypeError(
            f"expected {name} as a real numeric array of shape {shape}, got {_describe(raw)}"
        )
    arr = np.ascontiguousarray(raw, dtype=np.float64)
    allowed = (ndim,) if isinstance(ndim, int) else ndim
    if arr.ndim not in allowed:
        raise InvalidInputError(f"expected {name} of shape {shape}, got {arr.shape}")
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
    if isinstance(value, np.ndarray) and value.shape == () and value.dtype.kind in "iuf":
        value = value.item()
    if isinstance(value, bool | np.bool_) or not isinstance(value, int | float | np.integer | np.floating):
        raise InvalidTypeError(f"expected {name} as a real number, got {_describe(value)}")
    x = float(value)
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


def finite_result(what: str, value: Any, cause: str) -> Any:
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
