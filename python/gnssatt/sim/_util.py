"""Small shared helpers of :mod:`gnssatt.sim` (and the orbit and attitude models next to it): intake of times,
3-vectors and typed arguments, batched matrix products, phase wrapping."""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from gnssatt import _renamed
from gnssatt._arrays import float_array
from gnssatt.errors import InvalidInputError, InvalidTypeError


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
        arr = np.array(value)
    except ValueError as exc:  # ragged nested sequences
        raise InvalidTypeError(f"expected {name} as a real numeric array, got {exc}") from exc
    if arr.dtype.kind not in "iuf":
        raise InvalidTypeError(f"expected {name} as a real numeric array, got dtype {arr.dtype}")
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


def instance(name: str, value: Any, cls: type | tuple[type, ...], what: str) -> Any:
    """``value`` if it is an instance of ``cls``, else :class:`~gnssatt.errors.InvalidTypeError`."""
    if not isinstance(value, cls):
        raise InvalidTypeError(f"expected {name} as {what}, got {type(value).__name__}")
    return value


def generator(name: str, value: Any) -> np.random.Generator:
    """The Generator of an ``rng=`` argument (int, Generator or None): :func:`gnssatt._renamed.generator`."""
    return _renamed.generator(name, value)


def text(name: str, value: Any, choices: tuple[str, ...] | None = None) -> str:
    """``value`` if it is a ``str`` (one of ``choices`` where given)."""
    instance(name, value, str, "a str")
    if choices is not None and value not in choices:
        raise InvalidInputError(f"expected {name} one of {list(choices)}, got {value!r}")
    return value


def matvec(m: NDArray[np.float64], v: NDArray[np.float64]) -> NDArray[np.float64]:
    """``m @ v`` over the last axes with broadcasting: m (..., 3, 3), v (..., 3) -> (..., 3)."""
    return np.einsum("...ij,...j->...i", m, v)


def rot_x(angle: NDArray[np.float64] | float) -> NDArray[np.float64]:
    """Active rotation matrices about x by ``angle`` (rad), shape (..., 3, 3)."""
    c, s = np.cos(angle), np.sin(angle)
    o, z = np.ones_like(c), np.zeros_like(c)
    return np.stack([np.stack([o, z, z], -1), np.stack([z, c, -s], -1), np.stack([z, s, c], -1)], -2)


def rot_z(angle: NDArray[np.float64] | float) -> NDArray[np.float64]:
    """Active rotation matrices about z by ``angle`` (rad), shape (..., 3, 3)."""
    c, s = np.cos(angle), np.sin(angle)
    o, z = np.ones_like(c), np.zeros_like(c)
    return np.stack([np.stack([c, -s, z], -1), np.stack([s, c, z], -1), np.stack([z, z, o], -1)], -2)


def wrap_rad(x: Any) -> NDArray[np.float64]:
    """Angles (rad, any shape, finite) wrapped to [-pi, pi)."""
    arr = checked_array("x", x, ndim=tuple(range(33)), shape="(...)")
    return (arr + np.pi) % (2.0 * np.pi) - np.pi


def readonly(*arrays: NDArray[Any] | None) -> None:
    """Mark arrays read-only (results held by frozen dataclasses)."""
    for a in arrays:
        if isinstance(a, np.ndarray):
            a.flags.writeable = False
