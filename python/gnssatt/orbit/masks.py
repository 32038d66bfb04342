"""Visibility masks: elevation mask, antenna cone about a body-frame boresight, Earth occlusion.

Conventions of :mod:`gnssatt.sim`: SI units and radians inside, arguments in degrees end in ``_deg``.
Every mask is a boolean array, true where the satellite is usable, with the leading shape of the lines of
sight ((n_sat,) or (n_t, n_sat)); combine masks with ``&``.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.spatial.transform import Rotation

from gnssatt._arrays import MAX_BATCH_ROWS, batch_limit, float_array, scalar, vector_array
from gnssatt.constants import WGS84_A_M
from gnssatt.errors import InvalidInputError
from gnssatt.orbit.line_of_sight import los_body

__all__ = ["antenna_cone_mask", "earth_occlusion_mask", "elevation_mask"]


def elevation_mask(los_ref: ArrayLike, mask_deg: float = 0.0) -> NDArray[np.bool_]:
    """True where the elevation above the local horizontal is at least ``mask_deg``.

    Parameters
    ----------
    los_ref
        (..., 3) unit lines of sight in a frame whose z axis is the local vertical (ENU or orbital).
    mask_deg
        Elevation mask, degrees, in [-90, 90].

    Returns
    -------
    numpy.ndarray
        Boolean, the leading shape of ``los_ref``.

    Raises
    ------
    InvalidInputError
        Wrong shapes, non-finite values, a zero vector, ``mask_deg`` outside [-90, 90]
        (:class:`~gnssatt.errors.InvalidTypeError` for values that are not real numbers).

    Examples
    --------
    >>> import numpy as np
    >>> from gnssatt.orbit.masks import elevation_mask
    >>> el = np.radians([10.0, 30.0])
    >>> los = np.column_stack([np.zeros(2), np.cos(el), np.sin(el)])  # (2, 3) ENU, due North
    >>> elevation_mask(los, 15.0)
    array([False,  True])
    """
    batch_limit(MAX_BATCH_ROWS, "MAX_BATCH_ROWS", "lines of sight", los_ref=(los_ref, 1))
    g = vector_array("los_ref", los_ref, ndim=(1, 2, 3), shape="(..., 3)", nonzero=True)
    m = scalar("mask_deg", mask_deg)
    if abs(m) > 90:
        raise InvalidInputError(f"expected mask_deg in [-90, 90], got {m}")
    # typed here: numpy types np.linalg.norm over an axis as Any
    above: NDArray[np.bool_] = g[..., 2] / np.linalg.norm(g, axis=-1) >= np.sin(np.radians(m))
    return above


def antenna_cone_mask(
    los_ref: ArrayLike,
    attitude: Rotation,
    boresight_body: ArrayLike = (0.0, 0.0, 1.0),
    half_angle_deg: float = 90.0,
) -> NDArray[np.bool_]:
    """True where the satellite lies within ``half_angle_deg`` of the antenna boresight.

    Parameters
    ----------
    los_ref
        (n_sat, 3) or (n_t, n_sat, 3) unit lines of sight in the reference frame.
    attitude
        Body -> reference rotation (one, or one per epoch).
    boresight_body
        (3,) antenna boresight in the body frame (normalised here).
    half_angle_deg
        Cone half-angle, degrees, in (0, 180]; 90 is a hemispherical antenna (strictly above its horizon
        plane counts; a satellite exactly in that plane is visible).

    Returns
    -------
    numpy.ndarray
        Boolean, (n_sat,) or (n_t, n_sat).

    Raises
    ------
    InvalidInputError
        Wrong shapes, non-finite values, a zero boresight, ``half_angle_deg`` outside (0, 180], a number of
        rotations other than one or n_t (:class:`~gnssatt.errors.InvalidTypeError` for an ``attitude`` that
        is not a scipy ``Rotation``).

    Examples
    --------
    A body pitched 90 deg about Y points its +z boresight at reference +x: a 30 deg cone holds a satellite on
    +x, not one at the zenith:

    >>> import numpy as np
    >>> from scipy.spatial.transform import Rotation
    >>> from gnssatt.orbit.masks import antenna_cone_mask
    >>> attitude = Rotation.from_euler("y", 90.0, degrees=True)  # body -> reference
    >>> antenna_cone_mask(np.array([[0.0, 0.0, 1.0], [1.0, 0.0, 0.0]]), attitude, half_angle_deg=30.0)
    array([False,  True])
    """
    batch_limit(MAX_BATCH_ROWS, "MAX_BATCH_ROWS", "lines of sight", los_ref=(los_ref, 1))
    b = float_array("boresight_body", boresight_body, ndim=1, shape="(3,)")
    if b.shape != (3,) or np.linalg.norm(b) < 1e-12:
        raise InvalidInputError(f"expected a non-zero boresight_body of shape (3,), got {b.tolist()}")
    h = scalar("half_angle_deg", half_angle_deg, minimum=0.0, strict=True)
    if h > 180:
        raise InvalidInputError(f"expected half_angle_deg in (0, 180], got {h}")
    vector_array("los_ref", los_ref, ndim=(2, 3), shape="(n_sat, 3) or (n_t, n_sat, 3)", nonzero=True)
    g_body = los_body(los_ref, attitude)
    cos_angle = g_body @ (b / np.linalg.norm(b)) / np.linalg.norm(g_body, axis=-1)
    # typed here: numpy types np.linalg.norm over an axis as Any
    inside: NDArray[np.bool_] = cos_angle >= np.cos(np.radians(h)) - 1e-12
    return inside


def earth_occlusion_mask(
    receiver_m: ArrayLike, satellites_m: ArrayLike, *, atmosphere_m: float = 0.0, radius_m: float = WGS84_A_M
) -> NDArray[np.bool_]:
    """True where the segment receiver -> satellite misses the sphere of radius ``radius_m + atmosphere_m``.

    The Earth is a sphere centred at the origin (default radius: the WGS-84 equatorial radius, which
    slightly over-occludes near the poles). The segment's closest point to the centre is
    ``r + s d`` with ``d = r_sat - r``, ``s = clip(-r . d / |d|^2, 0, 1)``.

    Parameters
    ----------
    receiver_m
        (3,) or (n_t, 3) receiver position, any Earth-centred frame (ECI or ECEF), m.
    satellites_m
        (n_sat, 3) or (n_t, n_sat, 3) satellite positions in the same frame, m.
    atmosphere_m
        Height of the grazing layer to exclude (e.g. 100e3 for tropo/ionospheric grazing), m, >= 0.
    radius_m
        Radius of the Earth sphere, m.

    Returns
    -------
    numpy.ndarray
        Boolean, (n_sat,) or (n_t, n_sat).

    Raises
    ------
    InvalidInputError
        Shapes that do not pair up as above, non-finite values, ``radius_m <= 0``, ``atmosphere_m < 0``
        (:class:`~gnssatt.errors.InvalidTypeError` for values that are not real numbers).

    Examples
    --------
    A segment parallel to Y at ``x = 6450`` km passes 71.9 km above the 6378.137 km sphere: clear, but
    inside a 100 km grazing layer; a satellite at the mirror point through the centre is hidden:

    >>> from gnssatt.orbit.masks import earth_occlusion_mask
    >>> receiver = [6.45e6, -1e7, 0.0]  # m
    >>> earth_occlusion_mask(receiver, [[6.45e6, 1e7, 0.0], [-6.45e6, 1e7, 0.0]])
    array([ True, False])
    >>> earth_occlusion_mask(receiver, [[6.45e6, 1e7, 0.0]], atmosphere_m=100e3)
    array([False])
    """
    batch_limit(
        MAX_BATCH_ROWS,
        "MAX_BATCH_ROWS",
        "positions",
        receiver_m=(receiver_m, 1),
        satellites_m=(satellites_m, 1),
    )
    r = float_array("receiver_m", receiver_m, ndim=(1, 2), shape="(3,) or (n_t, 3)")
    s = float_array("satellites_m", satellites_m, ndim=(2, 3), shape="(n_sat, 3) or (n_t, n_sat, 3)")
    if r.shape[-1] != 3 or s.shape[-1] != 3 or r.ndim + 1 != s.ndim:
        raise InvalidInputError(
            f"expected receiver_m (3,) with satellites_m (n_sat, 3), or (n_t, 3) with (n_t, n_sat, 3), "
            f"got {r.shape} and {s.shape}"
        )
    big_r = scalar("radius_m", radius_m, minimum=0.0, strict=True) + scalar(
        "atmosphere_m", atmosphere_m, minimum=0.0
    )
    r = r[..., None, :]
    d = s - r
    dd = np.sum(d * d, axis=-1)
    frac = np.clip(-np.sum(r * d, axis=-1) / np.where(dd > 0, dd, 1.0), 0.0, 1.0)
    closest = r + frac[..., None] * d
    # typed here: numpy types np.linalg.norm over an axis as Any
    clear: NDArray[np.bool_] = np.linalg.norm(closest, axis=-1) > big_r
    return clear
