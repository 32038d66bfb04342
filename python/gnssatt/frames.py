"""Reference frames: geodetic WGS-84, ECEF, ECI and local East-North-Up.

Conventions of :mod:`gnssatt.sim`
---------------------------------
- SI units and radians inside; public arguments in degrees carry ``_deg`` in their name.
- ECI: a J2000-like inertial frame without precession, nutation or polar motion.
- ECEF: ECI rotated about z by the Earth rotation angle ``theta(t) = theta0 + OMEGA_E t``
  (``OMEGA_E = 7.2921151467e-5 rad/s``, ``theta0`` a parameter, default 0), so that
  ``r_ecef = Rz(theta)^T r_eci``.
- ENU: East, North, Up at a geodetic WGS-84 point (latitude, longitude); ``dcm_ecef_from_enu`` has the
  E, N, U unit vectors (ECEF coordinates) as its columns.
- Matrices are named ``dcm_<to>_from_<from>``: ``v_to = dcm_to_from_from @ v_from``.
- ``t`` is in seconds from the scenario epoch; a scalar ``t`` gives unbatched results, an array of shape
  (n_t,) puts a leading epoch axis on every output.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from gnssatt._arrays import (
    MAX_BATCH_ROWS,
    batch_limit,
    checked_array,
    finite_result,
    scalar,
    time_array,
    vector_array,
)
from gnssatt.constants import OMEGA_E_RAD_S, WGS84_A_M, WGS84_E2
from gnssatt.errors import ConvergenceError, InvalidInputError

__all__ = [
    "dcm_ecef_from_eci",
    "dcm_ecef_from_enu",
    "dcm_eci_from_ecef",
    "earth_rotation_angle",
    "ecef_to_eci",
    "ecef_to_geodetic",
    "eci_to_ecef",
    "geodetic_to_ecef",
]

#: Closest distance to the Earth's centre accepted by :func:`ecef_to_geodetic`, m. Geodetic coordinates are
#: not unique within ``a e^2`` (about 42.7 km) of the centre (the evolute of the meridian ellipse), and the
#: fixed-point iteration needs some margin beyond it.
MIN_GEODETIC_RADIUS_M = 100e3
#: Geodetic height accepted by :func:`geodetic_to_ecef`, m: down to ``-MAX_DEPTH_M`` (about -6278 km, the
#: depth of ``MIN_GEODETIC_RADIUS_M`` under the equator; deeper points near the centre have no unique
#: geodetic coordinates).
MAX_DEPTH_M = WGS84_A_M - MIN_GEODETIC_RADIUS_M
#: Most fixed-point iterations of :func:`ecef_to_geodetic`: the error shrinks by about ``a e^2 / r`` per
#: iteration (0.43 at ``MIN_GEODETIC_RADIUS_M``, 0.007 at the surface), so 60 reach 1e-13 rad everywhere.
_GEODETIC_ITERATIONS = 60
#: Any number of dimensions (numpy's limit is 32).
_ANY_NDIM = tuple(range(33))


def earth_rotation_angle(t: ArrayLike, theta0_rad: float = 0.0) -> NDArray[np.float64]:
    """Earth rotation angle ``theta0 + OMEGA_E t`` in radians (not wrapped), shape of ``t``.

    Parameters
    ----------
    t
        Seconds from the epoch, shape () or (n_t,).
    theta0_rad
        Earth rotation angle at ``t = 0``, rad.

    Returns
    -------
    ndarray
        Angle in rad, shape of ``t``.

    Raises
    ------
    InvalidInputError
        A non-finite or non-numeric ``t`` or ``theta0_rad``, or ``t`` of more than one axis.

    Examples
    --------
    One sidereal day (86164.0905 s) turns the Earth by 2 pi:

    >>> from gnssatt.frames import earth_rotation_angle
    >>> round(float(earth_rotation_angle(86164.0905)), 4)
    6.2832
    """
    return scalar("theta0_rad", theta0_rad) + OMEGA_E_RAD_S * time_array(t)


def dcm_eci_from_ecef(t: ArrayLike, theta0_rad: float = 0.0) -> NDArray[np.float64]:
    """Rotation ECEF -> ECI at time ``t``: ``Rz(theta(t))``, shape (3, 3) or (n_t, 3, 3).

    Parameters
    ----------
    t
        Seconds from the epoch, shape () or (n_t,).
    theta0_rad
        Earth rotation angle at ``t = 0``, rad.

    Returns
    -------
    ndarray
        ``v_eci = dcm @ v_ecef``, shape (3, 3), or (n_t, 3, 3) for ``t`` of shape (n_t,).

    Raises
    ------
    InvalidInputError
        A non-finite or non-numeric ``t`` or ``theta0_rad``, or ``t`` of more than one axis.

    Examples
    --------
    A quarter of a sidereal day later the ECEF x axis points along ECI y:

    >>> import numpy as np
    >>> from gnssatt.frames import dcm_eci_from_ecef
    >>> np.round(dcm_eci_from_ecef(86164.0905 / 4) @ [1.0, 0.0, 0.0], 6) + 0.0
    array([0., 1., 0.])
    """
    return rot_z(earth_rotation_angle(t, theta0_rad))


def dcm_ecef_from_eci(t: ArrayLike, theta0_rad: float = 0.0) -> NDArray[np.float64]:
    """Rotation ECI -> ECEF at time ``t``: ``Rz(theta(t))^T``, shape (3, 3) or (n_t, 3, 3).

    Parameters
    ----------
    t
        Seconds from the epoch, shape () or (n_t,).
    theta0_rad
        Earth rotation angle at ``t = 0``, rad.

    Returns
    -------
    ndarray
        ``v_ecef = dcm @ v_eci``, the transpose of :func:`dcm_eci_from_ecef`, shape (3, 3) or (n_t, 3, 3).

    Raises
    ------
    InvalidInputError
        A non-finite or non-numeric ``t`` or ``theta0_rad``, or ``t`` of more than one axis.

    Examples
    --------
    >>> import numpy as np
    >>> from gnssatt.frames import dcm_ecef_from_eci
    >>> np.round(dcm_ecef_from_eci([0.0, 86164.0905 / 4]) @ [0.0, 1.0, 0.0], 6) + 0.0
    array([[0., 1., 0.],
           [1., 0., 0.]])
    """
    return np.swapaxes(dcm_eci_from_ecef(t, theta0_rad), -1, -2)


def _omega_cross(r: NDArray[np.float64]) -> NDArray[np.float64]:
    return OMEGA_E_RAD_S * np.stack([-r[..., 1], r[..., 0], np.zeros_like(r[..., 0])], axis=-1)


def _batch_dcm(dcm: NDArray[np.float64], v: NDArray[np.float64]) -> NDArray[np.float64]:
    # dcm (n_t, 3, 3) against v (n_t, ..., 3): insert axes so that n_t aligns with v's leading axis.
    if dcm.ndim == 3:
        if v.ndim < 2 or v.shape[0] != dcm.shape[0]:
            raise InvalidInputError(
                f"expected positions and velocities of shape ({dcm.shape[0]}, ..., 3) for t of shape "
                f"({dcm.shape[0]},), got {v.shape}"
            )
        dcm = dcm.reshape(dcm.shape[:1] + (1,) * (v.ndim - 2) + (3, 3))
    return matvec(dcm, v)


def _finite_state(
    what: str, r: NDArray[np.float64], v: NDArray[np.float64]
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    # a rotation of finite vectors near the float limit (1e308 m) overflows to inf: refuse, not return it
    cause = "position or velocity too large to rotate in float64"
    return finite_result(f"{what} position", r, cause), finite_result(f"{what} velocity", v, cause)


def _same_shape(
    name: str, v: NDArray[np.float64], ref_name: str, ref: NDArray[np.float64]
) -> NDArray[np.float64]:
    if v.shape != ref.shape:
        raise InvalidInputError(f"expected {name} of the shape of {ref_name}, {ref.shape}, got {v.shape}")
    return v


def eci_to_ecef(
    r_eci: ArrayLike, v_eci: ArrayLike, t: ArrayLike, theta0_rad: float = 0.0
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Position and velocity from ECI to ECEF (rotating frame: ``v_ecef = R^T (v_eci - omega x r_eci)``).

    Parameters
    ----------
    r_eci, v_eci
        (..., 3) position (m) and velocity (m/s) in ECI; with an array ``t`` of shape (n_t,), the leading
        axis must be the epoch axis (n_t, ..., 3).
    t
        Seconds from the epoch, () or (n_t,).
    theta0_rad
        Earth rotation angle at ``t = 0``.

    Returns
    -------
    r_ecef, v_ecef : ndarray
        Position (m) and velocity (m/s) in ECEF, shape of ``r_eci``.

    Raises
    ------
    InvalidInputError
        Shapes other than (..., 3), ``v_eci`` of another shape than ``r_eci``, a leading axis that does
        not match ``t``, non-finite values.
    ConvergenceError
        Vectors so large (near 1e308) that the rotated ones overflow float64.

    Examples
    --------
    At ``t = 0`` the frames coincide, and the ECEF velocity is the inertial one less ``omega x r``
    (7.292e-5 rad/s times 7000 km is 510.4 m/s):

    >>> import numpy as np
    >>> from gnssatt.frames import eci_to_ecef
    >>> r, v = eci_to_ecef([7000e3, 0.0, 0.0], [0.0, 7500.0, 0.0], 0.0)
    >>> np.round(v, 1) + 0.0
    array([   0. , 6989.6,    0. ])
    """
    r = vector_array("r_eci", r_eci, ndim=(1, 2, 3), shape="(..., 3)")
    v = _same_shape("v_eci", vector_array("v_eci", v_eci, ndim=(1, 2, 3), shape="(..., 3)"), "r_eci", r)
    m = dcm_ecef_from_eci(t, theta0_rad)
    with np.errstate(over="ignore", invalid="ignore"):  # an overflow is reported, as an error
        r_e, v_e = _batch_dcm(m, r), _batch_dcm(m, v - _omega_cross(r))
    return _finite_state("eci_to_ecef", r_e, v_e)


def ecef_to_eci(
    r_ecef: ArrayLike, v_ecef: ArrayLike, t: ArrayLike, theta0_rad: float = 0.0
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Position and velocity from ECEF to ECI (``v_eci = R v_ecef + omega x r_eci``); shapes as
    :func:`eci_to_ecef`.

    Parameters
    ----------
    r_ecef, v_ecef
        (..., 3) position (m) and velocity (m/s) in ECEF; with an array ``t`` of shape (n_t,), the leading
        axis is the epoch axis (n_t, ..., 3), or a single (3,) pair is broadcast to every epoch.
    t
        Seconds from the epoch, () or (n_t,).
    theta0_rad
        Earth rotation angle at ``t = 0``.

    Returns
    -------
    r_eci, v_eci : ndarray
        Position (m) and velocity (m/s) in ECI, shape (..., 3) (or (n_t, 3) for a (3,) input).

    Raises
    ------
    InvalidInputError
        As :func:`eci_to_ecef`.

    Examples
    --------
    A point at rest on the equator moves at ``omega r`` (465.1 m/s at 6378 km) in ECI:

    >>> import numpy as np
    >>> from gnssatt.frames import ecef_to_eci
    >>> r, v = ecef_to_eci([6378137.0, 0.0, 0.0], [0.0, 0.0, 0.0], 0.0)
    >>> np.round(v, 1) + 0.0
    array([  0. , 465.1,   0. ])
    """
    r = vector_array("r_ecef", r_ecef, ndim=(1, 2, 3), shape="(..., 3)")
    v = _same_shape("v_ecef", vector_array("v_ecef", v_ecef, ndim=(1, 2, 3), shape="(..., 3)"), "r_ecef", r)
    m = dcm_eci_from_ecef(t, theta0_rad)
    if m.ndim == 3 and r.ndim == 1:
        r = np.broadcast_to(r, (m.shape[0], 3))
        v = np.broadcast_to(v, (m.shape[0], 3))
    with np.errstate(over="ignore", invalid="ignore"):  # an overflow is reported, as an error
        r_i = _batch_dcm(m, r)
        v_i = _batch_dcm(m, v) + _omega_cross(r_i)
    return _finite_state("ecef_to_eci", r_i, v_i)


def geodetic_to_ecef(lat_deg: ArrayLike, lon_deg: ArrayLike, height_m: ArrayLike) -> NDArray[np.float64]:
    """ECEF position (m) of geodetic WGS-84 coordinates; inputs of any shapes that broadcast together,
    output shape (..., 3).

    ``N = a / sqrt(1 - e^2 sin^2 lat)``, ``x = (N + h) cos lat cos lon``, ``y = (N + h) cos lat sin lon``,
    ``z = (N (1 - e^2) + h) sin lat``.

    The one implementation: ``gnssatt.magnetic.geodetic_to_ecef`` and ``gnssatt.sim.geodetic_to_ecef`` are
    this function.

    Parameters
    ----------
    lat_deg, lon_deg
        Geodetic latitude in [-90, 90] and longitude, degrees.
    height_m
        Height above the ellipsoid, m, in [``-MAX_DEPTH_M``, 1e12].

    Returns
    -------
    ndarray
        ECEF position, m, shape ``broadcast(lat_deg, lon_deg, height_m).shape + (3,)``.

    Raises
    ------
    InvalidInputError
        Latitudes outside [-90, 90] deg, heights below ``-MAX_DEPTH_M`` (-6278 km) or above 1e12 m,
        non-finite values, shapes that do not broadcast (:class:`~gnssatt.errors.InvalidTypeError` for values
        that are not real numbers).

    Examples
    --------
    The pole lies at the semi-minor axis ``b = a (1 - f)`` = 6356752.314 m:

    >>> import numpy as np
    >>> from gnssatt.frames import geodetic_to_ecef
    >>> np.round(geodetic_to_ecef([0.0, 90.0], 0.0, 0.0), 3) + 0.0
    array([[6378137.   ,       0.   ,       0.   ],
           [      0.   ,       0.   , 6356752.314]])
    """
    lat_d = _latitudes("lat_deg", checked_array("lat_deg", lat_deg, ndim=_ANY_NDIM, shape="(...)"))
    lon = np.radians(checked_array("lon_deg", lon_deg, ndim=_ANY_NDIM, shape="(...)"))
    h = checked_array("height_m", height_m, ndim=_ANY_NDIM, shape="(...)")
    if h.size and (h.min() < -MAX_DEPTH_M or h.max() > 1e12):
        raise InvalidInputError(f"expected height_m in [{-MAX_DEPTH_M}, 1e12] m, got [{h.min()}, {h.max()}]")
    try:
        np.broadcast_shapes(lat_d.shape, lon.shape, h.shape)
    except ValueError as exc:
        raise InvalidInputError(
            f"expected lat_deg, lon_deg and height_m of shapes that broadcast together, got {lat_d.shape}, "
            f"{lon.shape}, {h.shape}"
        ) from exc
    lat = np.radians(lat_d)
    n = WGS84_A_M / np.sqrt(1.0 - WGS84_E2 * np.sin(lat) ** 2)
    return np.stack(
        np.broadcast_arrays(
            (n + h) * np.cos(lat) * np.cos(lon),
            (n + h) * np.cos(lat) * np.sin(lon),
            (n * (1.0 - WGS84_E2) + h) * np.sin(lat),
        ),
        axis=-1,
    )


def _latitudes(name: str, lat_deg: NDArray[np.float64]) -> NDArray[np.float64]:
    if lat_deg.size and np.max(np.abs(lat_deg)) > 90.0:
        raise InvalidInputError(
            f"expected {name} in [-90, 90] deg, got {lat_deg.flat[np.argmax(np.abs(lat_deg))]}"
        )
    return lat_deg


def ecef_to_geodetic(r_ecef: ArrayLike) -> tuple[NDArray[Any], NDArray[Any], NDArray[Any]]:
    """Geodetic WGS-84 latitude (deg), longitude (deg) and height (m) of ECEF positions (..., 3).

    Fixed-point iteration on the latitude, until it changes by less than 1e-13 rad (4 iterations at the
    surface, about 40 at 100 km from the centre).

    Parameters
    ----------
    r_ecef
        ECEF positions, m, shape (3,) or (n, 3).

    Returns
    -------
    lat_deg, lon_deg, height_m : ndarray
        Geodetic latitude and longitude (deg) and height above the ellipsoid (m), shape () or (n,).

    Raises
    ------
    InvalidInputError
        A position within ``MIN_GEODETIC_RADIUS_M`` (100 km) of the Earth's centre, where geodetic
        coordinates are not unique, or a non-finite one.
    ConvergenceError
        The iteration did not converge or produced a non-finite value (not expected outside that sphere).

    Examples
    --------
    100 m above the equator at 90 deg East:

    >>> from gnssatt.frames import ecef_to_geodetic
    >>> lat, lon, h = ecef_to_geodetic([0.0, 6378137.0 + 100.0, 0.0])
    >>> print(f"{float(lat):.6f} {float(lon):.6f} {float(h):.3f}")
    0.000000 90.000000 100.000
    """
    batch_limit(MAX_BATCH_ROWS, "MAX_BATCH_ROWS", "positions", r_ecef=(r_ecef, 1))
    r = vector_array("r_ecef", r_ecef, ndim=(1, 2), shape="(3,) or (n, 3)")
    radius = np.linalg.norm(r, axis=-1)
    if radius.size and radius.min() < MIN_GEODETIC_RADIUS_M:
        raise InvalidInputError(
            f"expected r_ecef at least {MIN_GEODETIC_RADIUS_M} m from the Earth's centre (geodetic "
            f"coordinates are not unique near it), got a position {radius.min()} m from it"
        )
    x, y, z = r[..., 0], r[..., 1], r[..., 2]
    p = np.hypot(x, y)
    lon = np.arctan2(y, x)
    lat = np.arctan2(z, p * (1.0 - WGS84_E2))
    for _ in range(_GEODETIC_ITERATIONS):
        n = _prime_vertical(lat)
        new = np.arctan2(z, p * (1.0 - WGS84_E2 * n / (n + _height(lat, p, z))))
        change = np.max(np.abs(new - lat), initial=0.0)
        lat = new
        if change < 1e-13:  # a few ulp of pi/2: rounding keeps the last digits moving
            break
    else:
        raise ConvergenceError(f"ecef_to_geodetic: the latitude still changed by {change} rad")
    h = finite_result("the geodetic height", _height(lat, p, z), f"r_ecef of shape {r.shape}")
    return np.degrees(lat), np.degrees(lon), h


def _prime_vertical(lat: NDArray[np.float64]) -> NDArray[np.float64]:
    return WGS84_A_M / np.sqrt(1.0 - WGS84_E2 * np.sin(lat) ** 2)


def _height(lat: NDArray[np.float64], p: NDArray[np.float64], z: NDArray[np.float64]) -> NDArray[np.float64]:
    # h from the horizontal distance near the equator, from z near the poles (each formula divides by a
    # cosine or sine that vanishes in the other region; only the well-conditioned one is evaluated).
    n = _prime_vertical(lat)
    equatorial = np.abs(lat) < np.pi / 4
    safe_cos = np.where(equatorial, np.cos(lat), 1.0)
    safe_sin = np.where(equatorial, 1.0, np.sin(lat))
    return np.where(equatorial, p / safe_cos - n, z / safe_sin - n * (1.0 - WGS84_E2))


def dcm_ecef_from_enu(lat_deg: float, lon_deg: float) -> NDArray[np.float64]:
    """Rotation ENU -> ECEF at a geodetic point: columns are the E, N, U unit vectors, shape (3, 3).

    Parameters
    ----------
    lat_deg, lon_deg
        Geodetic latitude and longitude of the point, deg.

    Returns
    -------
    ndarray
        ``v_ecef = dcm @ v_enu``, shape (3, 3).

    Raises
    ------
    InvalidInputError
        ``lat_deg`` outside [-90, 90], non-finite or non-numeric arguments.

    Examples
    --------
    At latitude 0, longitude 0, East is ECEF y, North is z and Up is x:

    >>> import numpy as np
    >>> from gnssatt.frames import dcm_ecef_from_enu
    >>> np.round(dcm_ecef_from_enu(0.0, 0.0), 6) + 0.0
    array([[0., 0., 1.],
           [1., 0., 0.],
           [0., 1., 0.]])
    """
    lat = np.radians(scalar("lat_deg", lat_deg, minimum=-90.0, maximum=90.0, unit="deg"))
    lon = np.radians(scalar("lon_deg", lon_deg))
    sl, cl, so, co = np.sin(lat), np.cos(lat), np.sin(lon), np.cos(lon)
    east = [-so, co, 0.0]
    north = [-sl * co, -sl * so, cl]
    up = [cl * co, cl * so, sl]
    dcm: NDArray[np.float64] = np.array([east, north, up]).T  # numpy types an array from lists as Any
    return dcm


# Elementary rotations and batched products shared by the frames and the orbit models.


def matvec(m: NDArray[np.float64], v: NDArray[np.float64]) -> NDArray[np.float64]:
    """``m @ v`` over the last axes with broadcasting: m (..., 3, 3), v (..., 3) -> (..., 3)."""
    out: NDArray[np.float64] = np.einsum("...ij,...j->...i", m, v)  # numpy types einsum's result as Any
    return out


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
