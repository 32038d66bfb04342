"""Yaw from a magnetometer when an Earth sensor gives pitch and roll: eq. (3) of Ryzhkov and Holembiovskyi,
with the quadrant resolved by atan2 (the paper gives only ``sin psi``).

Angles are those of docs/conventions.md, Ryzhkov-Holembiovskyi row: ``Rotation.from_euler("ZYX", [psi, theta,
phi])`` maps body to orbital coordinates (eq. (1) writes its transpose with passive matrices).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.spatial.transform import Rotation

from gnssatt import _core
from gnssatt._arrays import batch_limit, finite_outputs, flag, float_array
from gnssatt.attitude.wahba import checked_vectors, warn_small
from gnssatt.errors import InvalidInputError

__all__ = ["MAX_YAW_EPOCHS", "YawResult", "yaw_from_magnetometer"]

#: Most epochs of one :func:`yaw_from_magnetometer` call, counted from the shapes before anything is copied:
#: 40-50 us an epoch on the loaded 2-core build machine (``docs/limits.md``), about 12 s at the limit.
MAX_YAW_EPOCHS = 2**18

#: Warn when ``|cos(pitch)|`` is below this (eq. (3) divides by it).
COS_PITCH_WARN = 1e-2
#: Warn when ``sqrt(a_x0^2 + a_y0^2) / |a_orb|`` is below this (near-polar orbits at u = 90, 270 deg).
HORIZONTAL_WARN = 1e-2


@dataclass(frozen=True)
class YawResult:
    """Yaw from :func:`yaw_from_magnetometer`.

    Attributes
    ----------
    yaw_rad
        psi in radians, (-pi, pi]; float or (epochs,).
    rotation
        Body -> orbital rotation ``ZYX(yaw, pitch, roll)`` with the given pitch and roll.
    cos_pitch
        ``|cos(theta)|``, which eq. (3) divides by.
    horizontal_fraction
        ``sqrt(a_x0^2 + a_y0^2) / |a_orb|``, the part of the reference field that fixes yaw; the yaw
        error from magnetometer errors grows like its reciprocal.
    """

    yaw_rad: float | NDArray[np.float64]
    rotation: Rotation
    cos_pitch: float | NDArray[np.float64]
    horizontal_fraction: float | NDArray[np.float64]

    @property
    def yaw_deg(self) -> float | NDArray[np.float64]:
        """Yaw in degrees."""
        return np.degrees(self.yaw_rad)


def yaw_from_magnetometer(
    b_body: ArrayLike, b_orbital: ArrayLike, pitch: ArrayLike, roll: ArrayLike, *, degrees: bool = False
) -> YawResult:
    """Yaw psi from the magnetometer reading, the model field in the orbital frame, pitch and roll (eq. 3).

    ``psi = atan2(mu2 a_x0 + (mu1 / cos theta) a_y0, (mu1 / cos theta) a_x0 - mu2 a_y0)`` with
    ``mu1 = a_x + a_z0 sin theta``, ``mu2 = a_z sin phi - a_y cos phi``; the first argument over
    ``a_x0^2 + a_y0^2`` is the paper's ``sin psi``, the second its companion ``cos psi``. The field's scale
    (``M_E / r^3``) cancels, but both fields must be in the same unit.

    Parameters
    ----------
    b_body
        (3,) or (epochs, 3) measured field ``[a_x, a_y, a_z]`` in body axes.
    b_orbital
        (3,) or (epochs, 3) model field ``[a_x0, a_y0, a_z0]`` in the orbital frame (x along-track,
        y orbit normal, z radial), e.g. from :func:`gnssatt.magnetic.dipole_orbital`.
    pitch, roll
        theta and phi (scalars or (epochs,)), radians, or degrees with ``degrees=True``.
    degrees
        Whether pitch and roll are in degrees. ``yaw_rad`` is always radians (``yaw_deg`` for degrees).

    Returns
    -------
    YawResult
        ``yaw_rad`` (float, or (epochs,) for batch input), the body -> orbital ``rotation``, ``|cos(pitch)|``
        and the horizontal fraction of the reference field.

    Raises
    ------
    InvalidInputError
        Wrong shapes or non-finite values; ``b_body`` and ``b_orbital`` whose magnitudes differ by more
        than 1e12 (not in the same unit) (:class:`~gnssatt.errors.InvalidTypeError` for values that are
        not real numbers, a ``degrees`` that is not a bool).
    DegenerateGeometryError
        ``cos(pitch)`` = 0, a vanishing horizontal field ``a_x0^2 + a_y0^2``, or a zero field; the message
        names the quantity and the epoch.
    WorkLimitError
        More than :data:`MAX_YAW_EPOCHS` epochs, refused before they are copied.

    Warns
    -----
    NearDegenerateWarning
        ``|cos(pitch)|`` below :data:`COS_PITCH_WARN` or the horizontal fraction below
        :data:`HORIZONTAL_WARN`.

    Examples
    --------
    The field a noise-free magnetometer reads at yaw 50, pitch 4, roll -3 deg gives back the yaw; the
    horizontal fraction is ``sqrt(20^2 + 5^2) / sqrt(20^2 + 5^2 + 40^2) = sqrt(425 / 2025)``:

    >>> import numpy as np
    >>> from scipy.spatial.transform import Rotation
    >>> from gnssatt.attitude.magnetometer import yaw_from_magnetometer
    >>> b_orbital = np.array([20.0, -5.0, 40.0])  # uT, orbital frame
    >>> true = Rotation.from_euler("ZYX", [50.0, 4.0, -3.0], degrees=True)  # body -> orbital
    >>> b_body = true.inv().apply(b_orbital)  # uT, body frame
    >>> result = yaw_from_magnetometer(b_body, b_orbital, 4.0, -3.0, degrees=True)
    >>> round(float(result.yaw_deg), 6)
    50.0
    >>> round(result.horizontal_fraction, 6), round(float(np.sqrt(425 / 2025)), 6)
    (0.458123, 0.458123)
    """
    bb, bo, p, r, single = _checked_readings(b_body, b_orbital, pitch, roll, degrees)
    n = _n_epochs(bb, bo, p, r)
    vec = _common_scale(bb, bo, n)
    ang = [np.ascontiguousarray(np.broadcast_to(a, (n,))) for a in (p, r)]
    out = _core.yaw_batch(*vec, *ang)
    yaw, cos_pitch, horizontal = out.yaw_rad, out.cos_pitch, out.horizontal_fraction
    finite_outputs("yaw_from_magnetometer", yaw=yaw, cos_pitch=cos_pitch, horizontal_fraction=horizontal)
    # here, not in a helper: the warnings name the caller's line (stacklevel)
    warn_small(cos_pitch, COS_PITCH_WARN, "|cos(pitch)|")
    warn_small(horizontal, HORIZONTAL_WARN, "the horizontal fraction sqrt(a_x0^2 + a_y0^2)/|a_orb|")
    rotation = Rotation.from_euler("ZYX", np.column_stack([yaw, ang[0], ang[1]]))
    if single:
        return YawResult(float(yaw[0]), rotation[0], float(cos_pitch[0]), float(horizontal[0]))
    return YawResult(yaw, rotation, cos_pitch, horizontal)


def _checked_readings(
    b_body: ArrayLike, b_orbital: ArrayLike, pitch: ArrayLike, roll: ArrayLike, degrees: bool
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64], NDArray[np.float64], bool]:
    """The fields and angles (rad) of :func:`yaw_from_magnetometer`, checked, and whether all four are
    of a single epoch (the result then scalar)."""
    batch_limit(
        MAX_YAW_EPOCHS,
        "MAX_YAW_EPOCHS",
        "epochs",
        b_body=(b_body, 1),
        b_orbital=(b_orbital, 1),
        pitch=(pitch, 0),
        roll=(roll, 0),
    )
    bb = checked_vectors("b_body", b_body)
    bo = checked_vectors("b_orbital", b_orbital)
    p = float_array("pitch", pitch, ndim=(0, 1), shape="() or (epochs,)")
    r = float_array("roll", roll, ndim=(0, 1), shape="() or (epochs,)")
    # float_array makes scalars (1,): decide single-epoch output from the arguments themselves.
    single = bb.ndim == 1 and bo.ndim == 1 and np.ndim(pitch) == 0 and np.ndim(roll) == 0
    if flag("degrees", degrees):
        p, r = np.radians(p), np.radians(r)
    return bb, bo, p, r, single


def _n_epochs(
    bb: NDArray[np.float64], bo: NDArray[np.float64], p: NDArray[np.float64], r: NDArray[np.float64]
) -> int:
    """The number of epochs the fields and angles broadcast to (at least one)."""
    try:
        epochs = np.broadcast_shapes(bb.shape[:-1], bo.shape[:-1], p.shape, r.shape)
    except ValueError:
        raise InvalidInputError(
            f"expected b_body, b_orbital (epochs, 3) and pitch, roll (epochs,) of one length, got "
            f"{bb.shape}, {bo.shape}, {p.shape}, {r.shape}"
        ) from None
    n = epochs[0] if epochs else 1
    if n == 0:
        # numpy broadcasts a single epoch against an empty batch to nothing; that is a mismatch here
        raise InvalidInputError(
            f"expected b_body, b_orbital, pitch and roll with at least one epoch, got shapes {bb.shape}, "
            f"{bo.shape}, {p.shape}, {r.shape}"
        )
    return n


def _common_scale(bb: NDArray[np.float64], bo: NDArray[np.float64], n: int) -> list[NDArray[np.float64]]:
    """Both fields (n, 3) divided by one scale per epoch, refused where one vanishes next to the other."""
    vec = [np.broadcast_to(v, (n, 3)) for v in (bb, bo)]
    raw = vec
    # One scale per epoch for both fields (eq. (3) adds a_x to a_z0 sin theta): the norms the core forms
    # then neither overflow nor underflow, and the yaw is unchanged.
    scale = np.maximum(np.max(np.abs(vec[0]), axis=1), np.max(np.abs(vec[1]), axis=1))[:, None]
    vec = [np.ascontiguousarray(v / np.where(scale > 0.0, scale, 1.0)) for v in vec]
    # a field that vanishes next to the other (different units, or a wild reading) is not a zero field
    peak = [np.max(np.abs(v), axis=1) for v in raw]
    with np.errstate(over="ignore", divide="ignore", invalid="ignore"):
        ratio = np.minimum(*peak) / np.maximum(*peak)
    lost = np.flatnonzero((np.minimum(*peak) > 0.0) & (ratio < 1e-12))
    if lost.size:
        k = int(lost[0])
        raise InvalidInputError(
            f"expected b_body and b_orbital in the same unit, got largest components {peak[0][k]:.3g} and "
            f"{peak[1][k]:.3g} at epoch {k}, differing by more than 1e12"
        )
    return vec
