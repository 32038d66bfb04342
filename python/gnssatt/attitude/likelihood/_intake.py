"""Checks shared by the single-epoch and series estimators of :mod:`gnssatt.attitude.likelihood`: phases,
lines of sight, baselines, wavelengths, windows, steps, gaps (private to the package)."""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager

import numpy as np
from numpy.typing import ArrayLike, NDArray

from gnssatt._arrays import batch_limit, float_array, plain_array, scalar, shaped
from gnssatt.attitude.likelihood.model import (
    MAX_PHASE_RAD,
    MAX_STEP_DEG,
    MAX_WAVELENGTH_M,
    MIN_WAVELENGTH_M,
    WINDOW_LIMIT_DEG,
    AttitudePrior,
)
from gnssatt.errors import InvalidInputError
from gnssatt.geometry import MAX_BASELINE_M, MAX_BASELINES, MAX_SIGNALS, MIN_BASELINE_M, checked_baselines


def checked_inputs(
    phase_diffs: ArrayLike,
    los: ArrayLike,
    baselines: ArrayLike,
    wavelength: ArrayLike,
    *,
    n_baselines: int | None,
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    # from the shapes, before anything is copied: the kernel's work is cells x epochs x baselines x signals
    batch_limit(MAX_SIGNALS, "MAX_SIGNALS", "lines of sight (all epochs)", los=(los, 1))
    batch_limit(
        MAX_BASELINES * MAX_SIGNALS,
        "MAX_BASELINES x MAX_SIGNALS",
        "phase differences",
        phase_diffs=(phase_diffs, 0),
    )
    p = float_array("phase_diffs", phase_diffs, ndim=(2, 3), shape="(m, M) or (epochs, m, M)")
    if p.ndim == 2:
        p = p[None]
    ne, nb, m = p.shape
    if np.any(np.abs(p) > MAX_PHASE_RAD):
        k = tuple(int(i) for i in np.argwhere(np.abs(p) > MAX_PHASE_RAD)[0])
        raise InvalidInputError(
            f"expected phase_diffs at most {MAX_PHASE_RAD:g} rad in magnitude (remove whole cycles), got "
            f"{p[k]:.6g} at (epoch, baseline, satellite) {k}"
        )
    s = float_array("los", los, ndim=(2, 3), shape="(M, 3) or (epochs, M, 3)")
    if s.ndim == 2:
        s = np.broadcast_to(s, (ne, *s.shape))
    if s.shape != (ne, m, 3):
        raise InvalidInputError(
            f"expected los of shape ({m}, 3) or ({ne}, {m}, 3) to match phase_diffs {p.shape} "
            f"(epochs, m, M), got {s.shape}"
        )
    b = checked_baselines("baselines", baselines)
    if b.shape[0] != nb:
        raise InvalidInputError(f"expected baselines of shape ({nb}, 3) to match phase_diffs, got {b.shape}")
    if n_baselines is not None and nb < n_baselines:
        raise InvalidInputError(f"expected at least {n_baselines} baselines (m, 3), got {b.shape}")
    w = float_array("wavelength", wavelength, ndim=(0, 1, 2), shape="scalar, (M,) or (epochs, M)")
    try:
        w = np.broadcast_to(w, (ne, m))
    except ValueError as exc:
        raise InvalidInputError(f"expected wavelength as a scalar or of shape ({m},), got {w.shape}") from exc
    if np.any((w < MIN_WAVELENGTH_M) | (w > MAX_WAVELENGTH_M)):
        k = tuple(int(i) for i in np.argwhere((w < MIN_WAVELENGTH_M) | (w > MAX_WAVELENGTH_M))[0])
        raise InvalidInputError(
            f"expected wavelength in [{MIN_WAVELENGTH_M:g}, {MAX_WAVELENGTH_M:g}] m, got {w[k]:.6g} m at "
            f"(epoch, satellite) {k}"
        )
    return p, np.ascontiguousarray(s), np.ascontiguousarray(w), b


def window_rows(name: str, w: NDArray[np.float64], axes: tuple[str, ...]) -> None:
    """Window rows ``[lo, hi]`` in order and within +-WINDOW_LIMIT_DEG."""
    for (lo, hi), axis in zip(w, axes, strict=True):
        if not (-WINDOW_LIMIT_DEG <= lo <= hi <= WINDOW_LIMIT_DEG):
            raise InvalidInputError(
                f"expected {name} rows [lo, hi] with -{WINDOW_LIMIT_DEG:g} <= lo <= hi <= "
                f"{WINDOW_LIMIT_DEG:g} deg, got [{lo}, {hi}] for {axis}"
            )


def checked_window(window_deg: ArrayLike | AttitudePrior | None) -> list[list[float]] | None:
    if window_deg is None:
        return None
    if isinstance(window_deg, AttitudePrior):
        window_deg = window_deg.window_deg
    w = shaped("window_deg", window_deg, "(3, 2) ([lo, hi] of psi, theta, phi)", (3, 2))
    window_rows("window_deg", w, ("psi", "theta", "phi"))
    return [[float(v) for v in row] for row in np.radians(w)]


def checked_baseline_window(window_deg: ArrayLike | None) -> list[list[float]] | None:
    """The (2, 2) window of :func:`ml_baseline` (``[lo, hi]`` of psi and elevation, degrees) as the core's
    three rows in radians: the third, the roll about a single baseline, is not observable, so any."""
    if window_deg is None:
        return None
    w2 = shaped("window_deg", window_deg, "(2, 2) ([lo, hi] of psi, elevation)", (2, 2))
    window_rows("window_deg", w2, ("psi", "elevation"))
    return [[float(v) for v in row] for row in np.radians(np.vstack([w2, [[-1.0, 1.0]]]))]


@contextmanager
def named_lobe(b: NDArray[np.float64], length_name: str = "baselines") -> Iterator[None]:
    """Name ``baselines`` (``length_name``) and ``wavelength`` next to ``step_deg`` when the core finds the
    step coarser than the main lobe: the lobe's width lambda / (2 L) is set by the longest baseline and the
    wavelength, so any of the three can be the one to change."""
    try:
        yield
    except InvalidInputError as exc:
        if "main lobe" not in str(exc):
            raise
        longest = float(np.max(np.linalg.norm(b, axis=1)))
        what = "the longest of the baselines" if length_name == "baselines" else length_name
        raise InvalidInputError(
            f"{exc} (L = {longest:.6g} m, {what}; lambda from wavelength): choose a finer step_deg, a "
            f"shorter {length_name} or a longer wavelength"
        ) from exc


def checked_length(baseline_length_m: float) -> float:
    """The one baseline's length of :func:`ml_baseline` and :func:`ml_baseline_series`, metres."""
    return scalar(
        "baseline_length_m", baseline_length_m, minimum=MIN_BASELINE_M, maximum=MAX_BASELINE_M, unit="m"
    )


def direction_enu(heading_rad: ArrayLike, elevation_rad: ArrayLike) -> NDArray[np.float64]:
    """Unit vectors (..., 3) East-North-Up of compass headings and elevations, radians."""
    h, e = np.asarray(heading_rad, dtype=np.float64), np.asarray(elevation_rad, dtype=np.float64)
    return np.stack([np.sin(h) * np.cos(e), np.cos(h) * np.cos(e), np.sin(e)], axis=-1)


def checked_step(step_deg: float | None) -> float | None:
    if step_deg is None:
        return None
    step = scalar("step_deg", step_deg, minimum=0.0, strict=True, unit="deg")
    if step > MAX_STEP_DEG:
        raise InvalidInputError(f"expected step_deg <= {MAX_STEP_DEG:g} deg, got {step} deg")
    return float(np.radians(step))


def gapped(
    name: str, value: ArrayLike, *, ndim: int | tuple[int, ...], shape: str
) -> tuple[NDArray[np.float64], NDArray[np.bool_]]:
    """:func:`float_array` where NaN marks an absent value: (the values with NaN replaced by 0, the gaps)."""
    raw = value
    gaps: NDArray[np.bool_] | bool = False
    if isinstance(value, np.ndarray | list | tuple | float):
        # masked values are gaps too; the size is checked before np.isnan scans (or copies) the array
        raw = plain_array(name, value, nan_for_masked=True)
        if raw.dtype.kind == "f":
            gaps = np.isnan(raw)
            raw = np.where(gaps, 0.0, raw)
    arr = float_array(name, raw, ndim=ndim, shape=shape)
    return arr, np.broadcast_to(gaps, arr.shape)
