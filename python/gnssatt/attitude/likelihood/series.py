"""The series estimators of :mod:`gnssatt.attitude.likelihood`: one search per epoch, in parallel in the
core, tracked in a window after the first (:func:`ml_attitude_series`, :func:`ml_baseline_series`), within
the whole-call work limit :data:`MAX_SERIES_WORK`."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.spatial.transform import Rotation

from gnssatt import _core
from gnssatt._arrays import plain_array, scalar
from gnssatt.attitude.likelihood._intake import (
    checked_length,
    checked_step,
    direction_enu,
    gapped,
    named_lobe,
)
from gnssatt.attitude.likelihood.model import (
    MAX_PHASE_RAD,
    MAX_WAVELENGTH_M,
    MIN_WAVELENGTH_M,
)
from gnssatt.errors import InvalidInputError, WorkLimitError
from gnssatt.geometry import checked_baselines
from gnssatt.rotation import rotation_from_euler


@dataclass(frozen=True)
class LikelihoodAttitudeSeries:
    """Per-epoch attitudes from :func:`ml_attitude_series`.

    Attributes
    ----------
    rotation
        (n_ep,) body -> East-North-Up rotations (the convention of :class:`LikelihoodAttitude`); the identity
        where ``solved`` is False.
    euler_gost_deg
        (n_ep, 3) (psi, theta, phi) of eq. (5), degrees, refined as :func:`ml_attitude` with its defaults;
        NaN where ``solved`` is False.
    z_max
        (n_ep,) the ambiguity function at each epoch's grid maximum; NaN where ``solved`` is False.
    solved
        (n_ep,) False where the epoch has fewer than 3 signals present at every rover antenna.
    """

    rotation: Rotation
    euler_gost_deg: NDArray[np.float64]
    z_max: NDArray[np.float64]
    solved: NDArray[np.bool_]


@dataclass(frozen=True)
class BaselineSeries:
    """Per-epoch baseline directions from :func:`ml_baseline_series`.

    Attributes
    ----------
    heading_deg
        (n_ep,) compass heading of the baseline (clockwise from North towards East), degrees in [0, 360).
    elevation_deg
        (n_ep,) elevation above the horizontal plane, degrees.
    direction_enu
        (n_ep, 3) unit vectors along the baseline, East-North-Up.
    z_max, solved
        As in :class:`LikelihoodAttitudeSeries`; every angle and vector is NaN where ``solved`` is False.
    """

    heading_deg: NDArray[np.float64]
    elevation_deg: NDArray[np.float64]
    direction_enu: NDArray[np.float64]
    z_max: NDArray[np.float64]
    solved: NDArray[np.bool_]


#: Most work one :func:`ml_attitude_series` or :func:`ml_baseline_series` call accepts, in kernel terms
#: (epochs x grid cells searched x signals x rovers; ``docs/limits.md``), read from the core.
MAX_SERIES_WORK: float = _core.LIKELIHOOD_MAX_SERIES_WORK


def _check_series_work(
    sd_phase: ArrayLike,
    wavelength: ArrayLike,
    step: float | None,
    window_deg: float | None,
    longest: float,
    *,
    two_dimensional: bool,
) -> None:
    """Refuses a series call whose shapes alone ask for more than :data:`MAX_SERIES_WORK`, before the
    measurements are copied or scanned: every epoch counted solved with all its signals at the longest
    valid wavelength given (the coarsest default step, so no more than the core's own per-epoch count)."""
    shape = np.shape(plain_array("sd_phase", sd_phase, nan_for_masked=True))
    if len(shape) != (2 if two_dimensional else 3):
        return  # the intake names the shape
    n_ep, n_rover, n_sig = (shape[0], 1, shape[1]) if two_dimensional else shape
    w = plain_array("wavelength", wavelength, nan_for_masked=True)
    if w.dtype.kind not in "fiu" or w.size == 0:
        return
    # a reduction, not a mask: nothing of the wavelengths' size is allocated; a longer wavelength than
    # any epoch's smallest only lowers the count
    longest_wavelength = min(float(np.fmax.reduce(w, axis=None)), MAX_WAVELENGTH_M)
    if not longest_wavelength >= MIN_WAVELENGTH_M:
        return  # the intake names the wavelengths
    window = None
    if window_deg is not None:
        window = float(np.radians(scalar("window_deg", window_deg, minimum=0.0, maximum=360.0, strict=True)))
    work = _core.ml_series_work(
        n_ep,
        n_rover,
        n_sig,
        step_rad=step,
        wavelength_m=longest_wavelength,
        longest_baseline_m=longest,
        window_rad=window,
        two_dimensional=two_dimensional,
    )
    if work > MAX_SERIES_WORK:
        raise WorkLimitError(
            f"sd_phase asks for {work:.4g} kernel terms ({n_ep} epochs x grid cells searched x {n_sig} "
            f"signals x {n_rover} rovers), more than the limit of {MAX_SERIES_WORK:.4g} (MAX_SERIES_WORK): "
            "split the epochs into batches, search in a window (window_deg) or with a coarser step_deg"
        )


def _series_intake(
    sd_phase: ArrayLike, los: ArrayLike, wavelength: ArrayLike, mask: ArrayLike | None, n_rover: int
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """Checked (n_ep, n_rover, n_sig) phases with NaN where absent, (n_ep, n_sig, 3) lines of sight and
    (n_ep, n_sig) wavelengths, finite wherever a signal is present at every rover."""
    p, absent = gapped("sd_phase", sd_phase, ndim=3, shape="(n_ep, n_rover, n_sig)")
    ne, nr, m = p.shape
    if ne == 0:
        raise InvalidInputError(f"expected sd_phase with at least one epoch, got shape {p.shape}")
    if nr != n_rover:
        raise InvalidInputError(
            f"expected sd_phase of shape (n_ep, {n_rover}, n_sig) to match the baselines, got {p.shape}"
        )
    if mask is not None:
        mk = np.asarray(mask)
        if mk.dtype != np.bool_ or mk.shape != p.shape:
            raise InvalidInputError(
                f"expected mask as a boolean array of shape {p.shape} (True where a signal is present), got "
                f"{mk.dtype} of shape {mk.shape}"
            )
        absent = absent | ~mk
    used = ~np.any(absent, axis=1)  # (n_ep, n_sig): a signal some rover lacks is left out of its epoch
    big = (np.abs(p) > MAX_PHASE_RAD) & ~absent
    if np.any(big):
        k = tuple(int(i) for i in np.argwhere(big)[0])
        raise InvalidInputError(
            f"expected sd_phase at most {MAX_PHASE_RAD:g} rad in magnitude (remove whole cycles), got "
            f"{p[k]:.6g} at (epoch, rover, signal) {k}"
        )
    s, s_gaps = gapped("los", los, ndim=(2, 3), shape="(n_sig, 3) or (n_ep, n_sig, 3)")
    if s.shape not in ((m, 3), (ne, m, 3)):
        raise InvalidInputError(
            f"expected los of shape ({m}, 3) or ({ne}, {m}, 3) to match sd_phase {p.shape}, got {s.shape}"
        )
    s, s_gaps = np.broadcast_to(s, (ne, m, 3)), np.broadcast_to(s_gaps, (ne, m, 3))
    w, w_gaps = gapped("wavelength", wavelength, ndim=(0, 1, 2), shape="scalar, (n_sig,) or (n_ep, n_sig)")
    try:
        w, w_gaps = np.broadcast_to(w, (ne, m)), np.broadcast_to(w_gaps, (ne, m))
    except ValueError as exc:
        raise InvalidInputError(
            f"expected wavelength as a scalar or of shape ({m},) or ({ne}, {m}), got {w.shape}"
        ) from exc
    for name, bad in (("los", np.any(s_gaps, axis=2) & used), ("wavelength", w_gaps & used)):
        if np.any(bad):
            k = tuple(int(i) for i in np.argwhere(bad)[0])
            raise InvalidInputError(
                f"{name} is NaN at (epoch, signal) {k}, where the signal is present at every rover (NaN "
                "is accepted only for absent signals)"
            )
    out = (w < MIN_WAVELENGTH_M) | (w > MAX_WAVELENGTH_M)
    if np.any(out & used):
        k = tuple(int(i) for i in np.argwhere(out & used)[0])
        raise InvalidInputError(
            f"expected wavelength in [{MIN_WAVELENGTH_M:g}, {MAX_WAVELENGTH_M:g}] m, got {w[k]:.6g} m at "
            f"(epoch, signal) {k}"
        )
    # Signals left out carry placeholders the core never reads as measurements.
    p = np.where(absent, np.nan, p)
    s = np.where(used[..., None], s, np.array([0.0, 0.0, 1.0]))
    w = np.where(used, w, 1.0)
    return p, np.ascontiguousarray(s), np.ascontiguousarray(w)


def _series_window(
    window_deg: float | None,
    step_deg: float | None,
    w: NDArray[np.float64],
    used: NDArray[np.bool_],
    longest: float,
) -> float | None:
    """The window half-width in radians, refused when finer than the step of some epoch (it could hold no
    grid node): ``step_deg``, or eq. (15)'s ``lambda_min / (10 L_max)`` of the epoch's signals."""
    if window_deg is None:
        return None
    half = scalar("window_deg", window_deg, minimum=0.0, maximum=360.0, strict=True, unit="deg")
    if step_deg is not None:
        step = float(step_deg)
    else:
        lam = np.min(np.where(used, w, np.inf), axis=1)
        lam = lam[np.isfinite(lam)]
        step = float(np.degrees(np.max(lam) / (10.0 * longest))) if lam.size else 0.0
    if half < step:
        raise InvalidInputError(
            f"expected window_deg of at least the grid step ({step:.6g} deg), got {half} deg: a narrower "
            "window can hold no grid node"
        )
    return float(np.radians(half))


def ml_attitude_series(
    sd_phase: ArrayLike,
    los: ArrayLike,
    baselines: ArrayLike,
    wavelength: ArrayLike,
    *,
    mask: ArrayLike | None = None,
    step_deg: float | None = None,
    window_deg: float | None = None,
) -> LikelihoodAttitudeSeries:
    """Maximum-likelihood attitude of every epoch of a batch, in one call (GIL released; Ctrl-C stops it).

    Each epoch gives what :func:`ml_attitude` gives for that epoch alone with the default statistic, search
    and refinement (its own oscillator phases; the exact branch-and-bound where it is faster than the
    exhaustive pass), bit for bit. Without a window the epochs run in parallel; with one each epoch searches
    ``+- window_deg`` on every angle around the previous epoch's solution (the whole domain at the first
    epoch and after an unsolved one). The work is one grid search per epoch, each within the limits of
    :func:`ml_attitude`.

    Parameters
    ----------
    sd_phase
        (n_ep, n_rover, n_sig) radians: phase at rover antenna ``i`` minus the reference antenna for signal
        ``k`` (sign, wrapping and oscillator phases as in :func:`ml_attitude`); NaN where a rover lacks the
        signal. A signal some rover lacks is left out of its epoch.
    los
        (n_sig, 3) or (n_ep, n_sig, 3) unit lines of sight in East-North-Up; NaN allowed where the signal is
        left out.
    baselines
        (n_rover, 3) rover antenna positions relative to the reference antenna, body frame, metres;
        n_rover >= 2, not collinear.
    wavelength
        Metres: a scalar, (n_sig,) per signal (GLONASS FDMA) or (n_ep, n_sig); NaN allowed where the signal
        is left out.
    mask
        ``None`` or a boolean (n_ep, n_rover, n_sig) array, True where the signal is present (combined with
        the NaNs of ``sd_phase``).
    step_deg
        As in :func:`ml_attitude` (``None``: eq. (15) per epoch, from the wavelengths of its signals).
    window_deg
        ``None`` (every epoch searches the whole domain) or the half-width in degrees, in (0, 360] and at
        least the grid step, of the window around the previous epoch's solution.

    Returns
    -------
    LikelihoodAttitudeSeries
        Per epoch: the body -> ENU rotation, the eq. (5) angles (deg, NaN where unsolved), ``z_max`` and
        whether the epoch was solved.

    Raises
    ------
    InvalidInputError
        As :func:`ml_attitude`; a ``mask`` of the wrong kind or shape, NaN lines of sight or wavelengths of
        a signal used, no epoch, a window finer than the step.
    WorkLimitError
        More than :data:`MAX_SERIES_WORK` kernel terms (epochs x grid cells searched x signals x rovers,
        ``docs/limits.md``), counted before the measurements are copied.
    DegenerateGeometryError
        Collinear baselines.

    Examples
    --------
    Two epochs of the :func:`ml_attitude` example, the second turned by 2 deg in psi:

    >>> import numpy as np
    >>> from gnssatt.rotation import rotation_from_euler
    >>> from gnssatt.sim import equilateral_triangle, random_los
    >>> los = random_los(1, 6, min_elevation_deg=15.0)  # (6, 3) unit vectors, ENU
    >>> baselines = equilateral_triangle(1.0, plane="xz")[1:]  # (2, 3) m, body
    >>> true = rotation_from_euler([30.0, 10.0, -5.0])  # psi, theta, phi in deg
    >>> phase_diffs = -2 * np.pi / 0.19 * (true.apply(baselines) @ los.T)  # (2, 6) rad, RINEX sign
    >>> from gnssatt import ml_attitude_series
    >>> second = rotation_from_euler([32.0, 10.0, -5.0])
    >>> sd_phase = np.stack([phase_diffs, -2 * np.pi / 0.19 * (second.apply(baselines) @ los.T)])
    >>> series = ml_attitude_series(sd_phase, los, baselines, 0.19)
    >>> np.round(series.euler_gost_deg, 6) + 0.0
    array([[30., 10., -5.],
           [32., 10., -5.]])
    """
    b = checked_baselines("baselines", baselines)
    if b.shape[0] < 2:
        raise InvalidInputError(f"expected at least 2 baselines (n_rover, 3), got {b.shape}")
    step = checked_step(step_deg)
    longest = float(np.max(np.linalg.norm(b, axis=1)))
    _check_series_work(sd_phase, wavelength, step, window_deg, longest, two_dimensional=False)
    p, s, w = _series_intake(sd_phase, los, wavelength, mask, b.shape[0])
    used = ~np.any(np.isnan(p), axis=1)
    window = _series_window(window_deg, step_deg, w, used, longest)
    with named_lobe(b):
        series = _core.ml_attitude_series(p, s, w, b, step_rad=step, window_rad=window)
    euler, z, solved = series.euler_gost_rad, series.z_max, series.solved
    euler_deg = np.degrees(euler)
    matrices = rotation_from_euler(np.where(solved[:, None], euler_deg, 0.0)).as_matrix()
    return LikelihoodAttitudeSeries(
        rotation=Rotation.from_matrix(np.where(solved[:, None, None], matrices, np.eye(3))),
        euler_gost_deg=euler_deg,
        z_max=z,
        solved=solved,
    )


def ml_baseline_series(
    sd_phase: ArrayLike,
    los: ArrayLike,
    baseline_length_m: float,
    wavelength: ArrayLike,
    *,
    mask: ArrayLike | None = None,
    step_deg: float | None = None,
    window_deg: float | None = None,
) -> BaselineSeries:
    """Heading and elevation of one baseline at every epoch of a batch, in one call (as
    :func:`ml_baseline` epoch by epoch, with its defaults; windows and parallelism as in
    :func:`ml_attitude_series`, the window on heading and elevation).

    Parameters
    ----------
    sd_phase
        (n_ep, n_sig) radians, phase at antenna 1 minus antenna 0; NaN where absent.
    los, wavelength, step_deg, window_deg
        As in :func:`ml_attitude_series`.
    baseline_length_m
        As in :func:`ml_baseline`.
    mask
        ``None`` or a boolean (n_ep, n_sig) array, True where the signal is present.

    Returns
    -------
    BaselineSeries
        Per epoch: compass heading and elevation (deg, NaN where unsolved), the unit direction in ENU,
        ``z_max`` and whether the epoch was solved.

    Raises
    ------
    InvalidInputError
        As :func:`ml_attitude_series`.
    WorkLimitError
        As :func:`ml_attitude_series`.

    Examples
    --------
    The first baseline of the :func:`ml_attitude_series` example: heading ``-psi``, elevation ``theta``:

    >>> import numpy as np
    >>> from gnssatt.rotation import rotation_from_euler
    >>> from gnssatt.sim import equilateral_triangle, random_los
    >>> los = random_los(1, 6, min_elevation_deg=15.0)  # (6, 3) unit vectors, ENU
    >>> baselines = equilateral_triangle(1.0, plane="xz")[1:]  # (2, 3) m, body
    >>> true = rotation_from_euler([30.0, 10.0, -5.0])  # psi, theta, phi in deg
    >>> phase_diffs = -2 * np.pi / 0.19 * (true.apply(baselines) @ los.T)  # (2, 6) rad, RINEX sign
    >>> from gnssatt import ml_baseline_series
    >>> second = rotation_from_euler([32.0, 10.0, -5.0])
    >>> sd_phase = np.stack([phase_diffs[0], -2 * np.pi / 0.19 * (second.apply(baselines[0]) @ los.T)])
    >>> series = ml_baseline_series(sd_phase, los, 1.0, 0.19)
    >>> np.round(series.heading_deg, 6), np.round(series.elevation_deg, 6)
    (array([330., 328.]), array([10., 10.]))
    """
    length = checked_length(baseline_length_m)
    step = checked_step(step_deg)
    _check_series_work(sd_phase, wavelength, step, window_deg, length, two_dimensional=True)
    p, gaps = gapped("sd_phase", sd_phase, ndim=2, shape="(n_ep, n_sig)")
    p = np.where(gaps, np.nan, p)[:, None, :]
    if mask is not None:
        mk = np.asarray(mask)
        mask = mk[:, None, :] if mk.ndim == 2 else mk  # a wrong shape is named by the intake
    p, s, w = _series_intake(p, los, wavelength, mask, 1)
    used = ~np.isnan(p[:, 0, :])
    window = _series_window(window_deg, step_deg, w, used, length)
    with named_lobe(np.array([[length, 0.0, 0.0]]), "baseline_length_m"):
        series = _core.ml_baseline_series(p, s, w, length, step_rad=step, window_rad=window)
    direction, z, solved = series.direction_rad, series.z_max, series.solved
    heading, elevation = direction[:, 0], direction[:, 1]
    return BaselineSeries(
        heading_deg=np.degrees(heading) % 360.0,  # an angle just under 2 pi can round to 360 deg
        elevation_deg=np.degrees(elevation),
        direction_enu=direction_enu(heading, elevation),
        z_max=z,
        solved=solved,
    )
