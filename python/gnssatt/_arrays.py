"""Intake of array arguments: dtype, dimensions and a readable message, before anything reaches Rust."""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from gnssatt.errors import InvalidInputError


def float_array(name: str, value: Any, *, ndim: int | tuple[int, ...], shape: str) -> NDArray[np.float64]:
    """``value`` as a C-contiguous float64 array with ``ndim`` dimensions (one of them, if a tuple).

    Raises :class:`TypeError` for non-numeric input, :class:`InvalidInputError` for a wrong number of
    dimensions or a non-finite value; ``shape`` is the expected shape as written in the message.
    """
    try:
        arr = np.ascontiguousarray(value, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise TypeError(
            f"expected {name} as a numeric array of shape {shape}, got {type(value).__name__}"
        ) from exc
    allowed = (ndim,) if isinstance(ndim, int) else ndim
    if arr.ndim not in allowed:
        raise InvalidInputError(f"expected {name} of shape {shape}, got {arr.shape}")
    if not np.all(np.isfinite(arr)):
        bad = tuple(int(i) for i in np.argwhere(~np.isfinite(arr))[0])
        raise InvalidInputError(f"{name} contains a non-finite value at index {bad}")
    return arr
