"""Geomagnetic field models for attitude determination (numpy).

* :func:`dipole_orbital`: the axial dipole in the orbital frame of a circular orbit, eq. (2) of Ryzhkov and
  Holembiovskyi.
* :func:`dipole_field_ecef`, :func:`dipole_field_eci`, :func:`dipole_field_ned`: the centred *tilted*
  dipole of the IGRF-14 degree-1 Gauss coefficients (with their secular variation).
* :func:`igrf_field_ecef`: the full IGRF-14 (degree 13) through the optional package ``ppigrf``
  (``pip install gnssatt[igrf]``), for judging how far the dipole is from the real field.

Units: tesla, metres, radians unless a name ends in ``_deg``. Frames: docs/conventions.md (orbital frame
x along-track, y orbit normal, z radial).

IGRF-14 degree-1 coefficients (nT) used here, read from the coefficient file ``IGRF14.shc`` distributed with
ppigrf 2.1.0, which gives the IAGA V-MOD release (Alken et al., IGRF-14, doi:10.5281/zenodo.14012302):

==========  =========  ========  ========
epoch       g10        g11       h11
==========  =========  ========  ========
2015.0      -29441.46  -1501.77  4795.99
2020.0      -29403.41  -1451.37  4653.35
2025.0      -29350.0   -1410.3   4545.5
SV 2025-30  +12.6/yr   +10.0/yr  -21.5/yr
==========  =========  ========  ========

(The 2025-2030 secular variation is the file's 2030 column minus its 2025 column over 5 years.) These are
not checked here against the NOAA/BGS coefficient table itself; a test compares the dipole with ppigrf at
degree 1.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from gnssatt import constants as _constants
from gnssatt._arrays import batch_limit, checked_array, integer, plain_array, scalar, vector_array
from gnssatt.errors import InvalidInputError, WorkLimitError

# One geodetic -> ECEF conversion, in the base layer.
from gnssatt.frames import geodetic_to_ecef as geodetic_to_ecef

__all__ = [
    "EARTH_DIPOLE_T_M3",
    "IGRF_COEFFICIENTS",
    "IGRF_REFERENCE_RADIUS_M",
    "MAX_DIPOLE_POINTS",
    "MAX_IGRF_TERMS",
    "dcm_ned_from_ecef",
    "dipole_coefficients",
    "dipole_field_ecef",
    "dipole_field_eci",
    "dipole_field_ned",
    "dipole_orbital",
    "igrf_field_ecef",
]

#: IGRF reference radius a (m).
IGRF_REFERENCE_RADIUS_M = 6_371_200.0
#: WGS-84 semi-major axis (m) and flattening.
WGS84_A_M = _constants.WGS84_A_M
WGS84_F = _constants.WGS84_F
_E2 = WGS84_F * (2.0 - WGS84_F)

# Degree-1 Gauss coefficients (g10, g11, h11) in nT at the IGRF-14 epochs, and the 2025-2030 SV in nT/yr.
_EPOCHS = np.array([2015.0, 2020.0, 2025.0])
_GAUSS_NT = np.array(
    [[-29441.46, -1501.77, 4795.99], [-29403.41, -1451.37, 4653.35], [-29350.0, -1410.3, 4545.5]]
)
_SV_NT_PER_YEAR = np.array([12.6, 10.0, -21.5])
_LAST_YEAR = 2030.0
#: Closest distance to the Earth's centre at which the field functions evaluate the dipole, m: the models
#: describe the field outside the core (radius about 3485 km), and ``1 / r^3`` must stay finite.
MIN_RADIUS_M = 1.0e6
# Any number of dimensions (numpy's limit is 64; 32 is far more than any broadcast here needs).
_ANY_NDIM = tuple(range(33))
#: Largest radius accepted, m (far beyond the magnetopause, some 6e7 m; ``r^3`` stays well inside float64).
MAX_RADIUS_M = 1.0e12

#: Spherical-harmonic terms ppigrf evaluates at each point of :func:`igrf_field_ecef` (g and h of degrees 1
#: to 13, whatever ``max_degree``): 13 x 15.
IGRF_COEFFICIENTS = 195
#: Most points x :data:`IGRF_COEFFICIENTS` one :func:`igrf_field_ecef` call evaluates: 2.5e7 (128,000
#: points), measured at 70 us a point on the loaded 2-core build machine: about 9 s.
MAX_IGRF_TERMS = 25_000_000
#: Most points of one dipole-field call (:func:`dipole_field_ecef`, :func:`dipole_field_eci`,
#: :func:`dipole_field_ned`, :func:`dipole_orbital`), counted from the shapes before anything is copied:
#: 1-7 us a point on the loaded 2-core build machine (``docs/limits.md``), about 7 s at most.
MAX_DIPOLE_POINTS = 2**20
#: Points per ppigrf call (about 80 MB of its matrices).
_IGRF_CHUNK = 8192

#: Earth's dipole strength ``M_E = mu0 m / (4 pi) = a^3 sqrt(g10^2 + g11^2 + h11^2)`` at 2025.0 from the
#: IGRF-14 coefficients above, in T m^3 (about 7.70e15; the dipole moment m is 7.70e22 A m^2). This is the
#: ``M_E`` of eq. (2): ``|B| = M_E / r^3`` on the magnetic equator.
EARTH_DIPOLE_T_M3 = float(IGRF_REFERENCE_RADIUS_M**3 * np.linalg.norm(_GAUSS_NT[2]) * 1e-9)


def dipole_orbital(
    u: ArrayLike, inclination: float, radius: ArrayLike, *, strength: float = EARTH_DIPOLE_T_M3
) -> NDArray[np.float64]:
    """Axial dipole field in the orbital frame of a circular orbit, eq. (2) of Ryzhkov and Holembiovskyi.

    ``a_orb = (M_E / r^3) [cos u sin i, cos i, -2 sin u sin i]`` for the dipole ``-M_E z_eci`` (north
    geomagnetic pole at the geographic north pole), axes x along-track, y orbit normal (``r x v``),
    z radial (zenith). Derived from ``B = (3 (m . r_hat) r_hat - m) / r^3`` in ``tests/test_magnetic.py``.

    Parameters
    ----------
    u
        Argument of latitude, radians; any shape.
    inclination
        Orbit inclination i, radians.
    radius
        Orbit radius r from the Earth's centre, metres; broadcast against ``u``.
    strength
        ``M_E`` in T m^3 (:data:`EARTH_DIPOLE_T_M3` by default).

    Returns
    -------
    ndarray
        (..., 3) field in tesla, ``...`` the broadcast shape of ``u`` and ``radius``.

    Raises
    ------
    InvalidInputError
        Non-finite or non-real input, ``radius`` outside [``MIN_RADIUS_M``, ``MAX_RADIUS_M``] (1e6 to
        1e12 m), ``inclination`` outside [0, pi], a negative ``strength`` or above 1e30 T m^3, shapes that
        do not broadcast.

    Examples
    --------
    On a polar orbit (``i = 90`` deg) the field at the equator (``u = 0``) points along-track, to the north,
    and over the pole (``u = 90`` deg) it points down with twice that strength:

    >>> import numpy as np
    >>> from gnssatt.magnetic import EARTH_DIPOLE_T_M3, dipole_orbital
    >>> field = dipole_orbital([0.0, np.pi / 2], np.pi / 2, 7e6)  # (2, 3) T
    >>> np.round(field / (EARTH_DIPOLE_T_M3 / 7e6**3), 6) + 0.0
    array([[ 1.,  0.,  0.],
           [ 0.,  0., -2.]])
    """
    batch_limit(MAX_DIPOLE_POINTS, "MAX_DIPOLE_POINTS", "points", u=(u, 0), radius=(radius, 0))
    u = checked_array("u", u, ndim=_ANY_NDIM, shape="(...)")
    r = _radii("radius", checked_array("radius", radius, ndim=_ANY_NDIM, shape="(...)"))
    inclination = scalar("inclination", inclination, minimum=0.0, maximum=np.pi, unit="rad")
    strength = scalar("strength", strength, minimum=0.0, maximum=1e30, unit="T m^3")
    si, ci = np.sin(inclination), np.cos(inclination)
    scale = strength / r**3
    try:
        u, scale = np.broadcast_arrays(u, scale)
    except ValueError as exc:
        raise InvalidInputError(
            f"expected u and radius of broadcastable shapes, got {u.shape}, {r.shape}"
        ) from exc
    # typed here: numpy types broadcast_arrays' results as Any
    field: NDArray[np.float64] = scale[..., None] * np.stack(
        [np.cos(u) * si, np.full_like(u, ci), -2.0 * np.sin(u) * si], axis=-1
    )
    return field


def dipole_coefficients(decimal_year: float) -> NDArray[np.float64]:
    """IGRF-14 ``(g10, g11, h11)`` in nT at ``decimal_year`` (2015.0 to 2030.0): linear between the
    5-yearly models, the secular variation after 2025.0.

    Parameters
    ----------
    decimal_year
        Epoch as a decimal year, in [2015.0, 2030.0].

    Returns
    -------
    numpy.ndarray
        (3,) ``(g10, g11, h11)``, nT.

    Raises
    ------
    InvalidInputError
        A year outside [2015.0, 2030.0] or not finite (:class:`~gnssatt.errors.InvalidTypeError` for a value
        that is not a real number).

    Examples
    --------
    The table at 2020.0, the midpoint of 2020 and 2025 at 2022.5, and two years of secular variation after
    2025.0 (``-29350.0 + 2 * 12.6 = -29324.8`` ...):

    >>> import numpy as np
    >>> from gnssatt.magnetic import dipole_coefficients
    >>> dipole_coefficients(2020.0).tolist()
    [-29403.41, -1451.37, 4653.35]
    >>> np.round(dipole_coefficients(2022.5), 6).tolist()
    [-29376.705, -1430.835, 4599.425]
    >>> np.round(dipole_coefficients(2027.0), 6).tolist()
    [-29324.8, -1390.3, 4502.5]
    """
    t = scalar("decimal_year", decimal_year)
    if not _EPOCHS[0] <= t <= _LAST_YEAR:
        raise InvalidInputError(
            f"expected decimal_year, a decimal year in [2015.0, 2030.0] (IGRF-14), got {t}"
        )
    if t >= _EPOCHS[-1]:
        extrapolated: NDArray[np.float64] = _GAUSS_NT[-1] + (t - _EPOCHS[-1]) * _SV_NT_PER_YEAR
        return extrapolated
    return np.array([np.interp(t, _EPOCHS, _GAUSS_NT[:, k]) for k in range(3)])


def _radii(name: str, r: NDArray[np.float64]) -> NDArray[np.float64]:
    if r.size and (r.min() < MIN_RADIUS_M or r.max() > MAX_RADIUS_M):
        raise InvalidInputError(
            f"expected {name} in [{MIN_RADIUS_M}, {MAX_RADIUS_M}] m from the Earth's centre, got "
            f"[{r.min()}, {r.max()}]"
        )
    return r


def _geodetic(
    lat_deg: ArrayLike, lon_deg: ArrayLike, *height_m: ArrayLike
) -> tuple[NDArray[np.float64], ...]:
    """Checked latitudes (rad, in [-pi/2, pi/2]), longitudes (rad) and heights (m), broadcast together."""
    lat = checked_array("lat_deg", lat_deg, ndim=_ANY_NDIM, shape="(...)")
    if lat.size and np.max(np.abs(lat)) > 90.0:
        raise InvalidInputError(f"expected lat_deg in [-90, 90], got {lat.flat[np.argmax(np.abs(lat))]}")
    lon = checked_array("lon_deg", lon_deg, ndim=_ANY_NDIM, shape="(...)")
    arrays = [np.radians(lat), np.radians(lon)]
    for value in height_m:  # one height or none
        h = checked_array("height_m", value, ndim=_ANY_NDIM, shape="(...)")
        if h.size and (h.min() < MIN_RADIUS_M - WGS84_A_M or h.max() > MAX_RADIUS_M):
            raise InvalidInputError(
                f"expected height_m in [{MIN_RADIUS_M - WGS84_A_M}, {MAX_RADIUS_M}] m, "
                f"got [{h.min()}, {h.max()}]"
            )
        arrays.append(h)
    try:
        return tuple(np.broadcast_arrays(*arrays))
    except ValueError as exc:
        shapes = [a.shape for a in arrays]
        raise InvalidInputError(
            f"expected lat_deg, lon_deg, height_m of broadcastable shapes, got {shapes}"
        ) from exc


def dcm_ned_from_ecef(lat_deg: ArrayLike, lon_deg: ArrayLike) -> NDArray[np.float64]:
    """(..., 3, 3) matrix taking ECEF coordinates to geodetic north-east-down at the given point.

    Parameters
    ----------
    lat_deg, lon_deg
        WGS-84 geodetic latitude and longitude, degrees, any shapes that broadcast together.

    Returns
    -------
    numpy.ndarray
        (..., 3, 3) rotation matrices ECEF -> NED; rows are the north, east and down unit vectors in ECEF.

    Raises
    ------
    InvalidInputError
        Non-finite or non-real input, latitudes outside [-90, 90], shapes that do not broadcast.

    Examples
    --------
    At latitude 0, longitude 0 north is ECEF +z, east +y and down -x:

    >>> import numpy as np
    >>> from gnssatt.magnetic import dcm_ned_from_ecef
    >>> np.round(dcm_ned_from_ecef(0.0, 0.0), 12) + 0.0
    array([[ 0.,  0.,  1.],
           [ 0.,  1.,  0.],
           [-1.,  0.,  0.]])
    """
    lat, lon = _geodetic(lat_deg, lon_deg)
    sl, cl, so, co = np.sin(lat), np.cos(lat), np.sin(lon), np.cos(lon)
    zero = np.zeros_like(sl * so)
    rows = [
        np.stack([-sl * co, -sl * so, cl + zero], axis=-1),
        np.stack([-so + zero, co + zero, zero], axis=-1),
        np.stack([-cl * co, -cl * so, -sl + zero], axis=-1),
    ]
    return np.stack(rows, axis=-2)


def dipole_field_ecef(position_ecef_m: ArrayLike, decimal_year: float) -> NDArray[np.float64]:
    """Centred tilted dipole of IGRF-14 degree 1 at ECEF positions, ECEF components, tesla.

    The degree-1 potential ``V = a^3 (g . r) / r^3`` with ``g = [g11, h11, g10]`` is that of a dipole,
    ``B = -grad V = a^3 (3 (g . r_hat) r_hat - g) / r^3``.

    Parameters
    ----------
    position_ecef_m
        (..., 3) positions in metres, ``MIN_RADIUS_M`` to ``MAX_RADIUS_M`` (1e6 to 1e12 m) from the centre.
    decimal_year
        Epoch, 2015.0 to 2030.0.

    Returns
    -------
    numpy.ndarray
        (..., 3) field, ECEF components, tesla.

    Raises
    ------
    InvalidInputError
        Wrong shape, non-finite or non-real input, a position outside that radius range, a year outside
        the model.

    Examples
    --------
    At the reference radius on the dipole's axis (along ``g``) the field is ``2 g``; on its equator
    (normal to ``g``) it is ``-g``:

    >>> import numpy as np
    >>> from gnssatt.magnetic import IGRF_REFERENCE_RADIUS_M, dipole_coefficients, dipole_field_ecef
    >>> g10, g11, h11 = dipole_coefficients(2025.0)
    >>> g = np.array([g11, h11, g10]) * 1e-9  # T
    >>> axis = g / np.linalg.norm(g)
    >>> np.round(dipole_field_ecef(IGRF_REFERENCE_RADIUS_M * axis, 2025.0) / g, 9)
    array([2., 2., 2.])
    >>> normal = np.cross(axis, [0.0, 0.0, 1.0])
    >>> normal /= np.linalg.norm(normal)
    >>> np.round(dipole_field_ecef(IGRF_REFERENCE_RADIUS_M * normal, 2025.0) / g, 9)
    array([-1., -1., -1.])
    """
    r = _positions("position_ecef_m", position_ecef_m)
    g10, g11, h11 = dipole_coefficients(decimal_year) * 1e-9
    g = np.array([g11, h11, g10])
    norm = np.linalg.norm(r, axis=-1, keepdims=True)
    rh = r / norm
    # typed here: numpy types np.linalg.norm over an axis as Any
    field: NDArray[np.float64] = IGRF_REFERENCE_RADIUS_M**3 * (3.0 * (rh @ g)[..., None] * rh - g) / norm**3
    return field


def _positions(name: str, value: ArrayLike) -> NDArray[np.float64]:
    batch_limit(MAX_DIPOLE_POINTS, "MAX_DIPOLE_POINTS", "points", **{name: (value, 1)})
    r = vector_array(name, value, ndim=_ANY_NDIM[1:], shape="(..., 3)")
    with np.errstate(over="ignore"):  # a radius beyond float64 is refused as out of range
        _radii(name, np.linalg.norm(r, axis=-1))
    return r


def dipole_field_eci(
    position_eci_m: ArrayLike, decimal_year: float, earth_rotation_angle_rad: ArrayLike
) -> NDArray[np.float64]:
    """:func:`dipole_field_ecef` for ECI positions: ECEF is ECI turned about z by the Earth rotation angle
    (docs/conventions.md), so ``B_eci = R_z(theta) B_ecef(R_z(-theta) r_eci)``. Tesla, (..., 3).

    ``earth_rotation_angle_rad`` broadcasts against the leading shape of ``position_eci_m``; errors as
    :func:`dipole_field_ecef`.

    Parameters
    ----------
    position_eci_m
        (..., 3) ECI positions, m, ``MIN_RADIUS_M`` to ``MAX_RADIUS_M`` (1e6 to 1e12 m) from the centre.
    decimal_year
        Epoch, 2015.0 to 2030.0.
    earth_rotation_angle_rad
        Earth rotation angle ``theta``, rad: () or broadcastable to the leading shape of ``position_eci_m``.

    Returns
    -------
    numpy.ndarray
        (..., 3) field, ECI components, tesla (the broadcast leading shape).

    Raises
    ------
    InvalidInputError
        As :func:`dipole_field_ecef`; an ``earth_rotation_angle_rad`` that does not broadcast or is not
        finite.

    Examples
    --------
    With the Earth turned by 90 deg, ECI +y is ECEF +x, and the ECEF field there, ``(bx, by, bz)``, appears
    in ECI as ``(-by, bx, bz)``:

    >>> import numpy as np
    >>> from gnssatt.magnetic import dipole_field_ecef, dipole_field_eci
    >>> np.round(dipole_field_ecef([7e6, 0.0, 0.0], 2025.0) * 1e9, 3)  # nT
    array([-2126.724, -3427.293, 22129.811])
    >>> np.round(dipole_field_eci([0.0, 7e6, 0.0], 2025.0, np.pi / 2) * 1e9, 3)  # nT
    array([ 3427.293, -2126.724, 22129.811])
    """
    r = _positions("position_eci_m", position_eci_m)
    th = checked_array("earth_rotation_angle_rad", earth_rotation_angle_rad, ndim=_ANY_NDIM, shape="(...)")
    try:
        lead = np.broadcast_shapes(r.shape[:-1], th.shape)
    except ValueError as exc:
        raise InvalidInputError(
            f"expected earth_rotation_angle_rad broadcastable to {r.shape[:-1]}, got {th.shape}"
        ) from exc
    # one position at several angles, or several positions at one angle
    r, th = np.broadcast_to(r, (*lead, 3)), np.broadcast_to(th, lead)
    c, s = np.cos(th), np.sin(th)
    r_ecef = np.stack([c * r[..., 0] + s * r[..., 1], -s * r[..., 0] + c * r[..., 1], r[..., 2]], axis=-1)
    b = dipole_field_ecef(r_ecef, decimal_year)
    return np.stack([c * b[..., 0] - s * b[..., 1], s * b[..., 0] + c * b[..., 1], b[..., 2]], axis=-1)


def dipole_field_ned(
    lat_deg: ArrayLike, lon_deg: ArrayLike, height_m: ArrayLike, decimal_year: float
) -> NDArray[np.float64]:
    """Centred tilted dipole of IGRF-14 degree 1 in geodetic north-east-down, tesla.

    Parameters
    ----------
    lat_deg, lon_deg
        WGS-84 geodetic latitude and longitude, degrees (broadcast together).
    height_m
        Height above the WGS-84 ellipsoid, metres.
    decimal_year
        Epoch, 2015.0 to 2030.0.

    Returns
    -------
    ndarray
        (..., 3) ``[north, east, down]`` in tesla.

    Raises
    ------
    InvalidInputError
        Non-finite or non-real input, latitudes outside [-90, 90], heights that bring the point nearer the
        centre than ``MIN_RADIUS_M`` or beyond ``MAX_RADIUS_M``, shapes that do not broadcast, a year outside
        the model.

    Examples
    --------
    The NED components are the ECEF field turned, so the strength is the same; in the northern hemisphere
    the field dips downwards:

    >>> import numpy as np
    >>> from gnssatt.magnetic import dipole_field_ecef, dipole_field_ned, geodetic_to_ecef
    >>> ned = dipole_field_ned(45.0, 0.0, 0.0, 2025.0)  # (3,) T
    >>> ecef = dipole_field_ecef(geodetic_to_ecef(45.0, 0.0, 0.0), 2025.0)
    >>> bool(np.isclose(np.linalg.norm(ned), np.linalg.norm(ecef), rtol=1e-12, atol=0.0)), bool(ned[2] > 0)
    (True, True)
    """
    batch_limit(
        MAX_DIPOLE_POINTS,
        "MAX_DIPOLE_POINTS",
        "points",
        lat_deg=(lat_deg, 0),
        lon_deg=(lon_deg, 0),
        height_m=(height_m, 0),
    )
    # checked here first, under this function's names and its own bound on heights (the dipole needs
    # MIN_RADIUS_M from the centre), before frames' conversion checks them again
    _geodetic(lat_deg, lon_deg, height_m)
    b = dipole_field_ecef(geodetic_to_ecef(lat_deg, lon_deg, height_m), decimal_year)
    # typed here: numpy types einsum's result as Any
    ned: NDArray[np.float64] = np.einsum("...ij,...j->...i", dcm_ned_from_ecef(lat_deg, lon_deg), b)
    return ned


def _datetime(decimal_year: float):  # type: ignore[no-untyped-def]
    import datetime

    year = int(decimal_year)
    days = 366 if (year % 4 == 0 and year % 100 != 0) or year % 400 == 0 else 365
    return datetime.datetime(year, 1, 1) + datetime.timedelta(days=(decimal_year - year) * days)


def igrf_field_ecef(
    position_ecef_m: ArrayLike, decimal_year: float, *, max_degree: int = 13
) -> NDArray[np.float64]:
    """Full IGRF-14 (to ``max_degree``) at ECEF positions, ECEF components, tesla, through ``ppigrf``.

    Needs the optional dependency ``ppigrf`` (``pip install gnssatt[igrf]``), which carries the IGRF-14
    coefficient file and works offline.

    Parameters
    ----------
    position_ecef_m
        (..., 3) positions in metres, ``MIN_RADIUS_M`` to ``MAX_RADIUS_M`` (1e6 to 1e12 m) from the centre.
    decimal_year
        Epoch, 1900.0 to 2030.0.
    max_degree
        Highest degree of the expansion, 1 to 13.

    Returns
    -------
    numpy.ndarray
        (..., 3) field, ECEF components, tesla.

    Raises
    ------
    ImportError
        ppigrf is not installed.
    InvalidInputError
        As :func:`dipole_field_ecef`; ``max_degree`` outside 1..13.
    WorkLimitError
        More than :data:`MAX_IGRF_TERMS` points x :data:`IGRF_COEFFICIENTS`, refused before any is computed.

    Examples
    --------
    Cut at degree 1 the IGRF is the centred tilted dipole of :func:`dipole_field_ecef`:

    >>> import numpy as np
    >>> from gnssatt.magnetic import dipole_field_ecef, geodetic_to_ecef, igrf_field_ecef
    >>> position = geodetic_to_ecef(45.0, 10.0, 500e3)  # (3,) m
    >>> np.round(igrf_field_ecef(position, 2025.0, max_degree=1) / dipole_field_ecef(position, 2025.0), 6)
    array([1., 1., 1.])
    """
    _igrf_work_limit(position_ecef_m)
    r = _positions("position_ecef_m", position_ecef_m)
    year = scalar("decimal_year", decimal_year, minimum=1900.0, maximum=_LAST_YEAR)
    max_degree = integer("max_degree", max_degree, minimum=1)
    if max_degree > 13:
        raise InvalidInputError(f"expected max_degree in 1..13 (IGRF-14), got {max_degree}")
    try:  # here, so that a missing ppigrf is said before any work; _igrf_spherical uses it
        import ppigrf  # noqa: F401
    except ImportError as exc:
        raise ImportError(
            "igrf_field_ecef needs the optional package ppigrf: pip install gnssatt[igrf]"
        ) from exc
    rn = np.linalg.norm(r, axis=-1)
    rho = np.hypot(r[..., 0], r[..., 1])
    # arctan2 keeps the colatitude's precision near the axis, where arccos(z / r) rounds to 0 or 180 deg
    colat = np.degrees(np.arctan2(rho, r[..., 2]))
    lon = np.degrees(np.arctan2(r[..., 1], r[..., 0]))
    date = _datetime(year)
    field = _ecef_from_spherical(_igrf_spherical(rn, colat, lon, date, max_degree), colat, lon)
    axis = rho <= _AXIS_SIN_COLAT * rn
    if np.any(axis):
        field[axis] = _axis_field(rn[axis], r[..., 2][axis] > 0.0, date, max_degree)
    return field


def _igrf_work_limit(position_ecef_m: ArrayLike) -> None:
    """Refuse more points than :data:`MAX_IGRF_TERMS` allows, before any of them is checked or evaluated."""
    shape = np.shape(plain_array("position_ecef_m", position_ecef_m))
    n_points = int(np.prod(shape[:-1])) if shape else 1
    if n_points * IGRF_COEFFICIENTS > MAX_IGRF_TERMS:
        raise WorkLimitError(
            f"position_ecef_m asks for {n_points} points x {IGRF_COEFFICIENTS} coefficients = "
            f"{n_points * IGRF_COEFFICIENTS} terms (ppigrf evaluates every degree to 13 whatever "
            "max_degree), "
            f"more than the limit of {MAX_IGRF_TERMS} (MAX_IGRF_TERMS): split the positions into batches"
        )


def _igrf_spherical(
    rn: NDArray[np.float64],
    colat: NDArray[np.float64],
    lon: NDArray[np.float64],
    date: object,
    max_degree: int,
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """ppigrf's radial, southward and eastward components (nT) at radii ``rn`` (m), colatitudes and
    longitudes (deg); NaN or infinite on the z axis, where :func:`_axis_field` replaces them."""
    import ppigrf

    br, bth, bph = np.empty_like(rn), np.empty_like(rn), np.empty_like(rn)
    flat = [a.reshape(-1) for a in (rn, colat, lon, br, bth, bph)]
    # In chunks: ppigrf holds about 10 kB of matrices per point, and Python's signal handlers (Ctrl-C)
    # run between chunks.
    for k in range(0, flat[0].size, _IGRF_CHUNK):
        part = slice(k, k + _IGRF_CHUNK)
        with np.errstate(invalid="ignore", divide="ignore"):  # on the axis: replaced by the caller
            out = ppigrf.igrf_gc(
                flat[0][part] / 1e3, flat[1][part], flat[2][part], date, max_degree=max_degree
            )
        for target, c in zip(flat[3:], out, strict=True):
            target[part] = np.asarray(c)[0]
    return br, bth, bph


def _ecef_from_spherical(
    b_nt: tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]],
    colat: NDArray[np.float64],
    lon: NDArray[np.float64],
) -> NDArray[np.float64]:
    """Radial, southward and eastward components (nT) at colatitudes and longitudes (deg) as ECEF
    vectors, tesla."""
    br, bth, bph = b_nt
    th, ph = np.radians(colat), np.radians(lon)
    e_r = np.stack([np.sin(th) * np.cos(ph), np.sin(th) * np.sin(ph), np.cos(th)], axis=-1)
    e_th = np.stack([np.cos(th) * np.cos(ph), np.cos(th) * np.sin(ph), -np.sin(th)], axis=-1)
    e_ph = np.stack([-np.sin(ph), np.cos(ph), np.zeros_like(ph)], axis=-1)
    # typed here: ppigrf is untyped, so its components are Any
    field: NDArray[np.float64] = 1e-9 * (br[..., None] * e_r + bth[..., None] * e_th + bph[..., None] * e_ph)
    return field


#: Points closer to the z axis than this fraction of their radius take the field on the axis itself
#: (:func:`_axis_field`): there ppigrf divides by ``sin(colatitude)`` (NaN at 0), and the field differs
#: from its value on the axis by about ``n_max`` times this fraction (1e-11 relative), far below the
#: model's own error.
_AXIS_SIN_COLAT = 1e-12


def _axis_field(
    rn: NDArray[np.float64], north: NDArray[np.bool_], date: object, max_degree: int
) -> NDArray[np.float64]:
    """The IGRF on the z axis, ECEF, tesla, from ppigrf's radial and southward components at the pole.

    On the axis only the zonal terms (m = 0) give a field along it and the m = 1 terms the field across it;
    ppigrf's radial and colatitude components are finite there (only its eastward one divides by
    ``sin(colatitude)``). At colatitude 0 the southward unit vector is ``(cos lon, sin lon, 0)``, so the
    southward component at longitudes 0 and 90 deg is the field's x and y component; at colatitude 180 deg
    it is ``-(cos lon, sin lon, 0)`` and the radial unit vector ``-z``.
    """
    import ppigrf

    colat = np.where(north, 0.0, 180.0)
    sign = np.where(north, 1.0, -1.0)
    out = np.empty((rn.size, 3))
    for k, lon in enumerate((0.0, 90.0)):
        with np.errstate(invalid="ignore", divide="ignore"):  # the eastward component, unused
            components = ppigrf.igrf_gc(rn / 1e3, colat, lon, date, max_degree=max_degree)
        br, bth = (np.asarray(c)[0] for c in components[:2])
        out[:, k] = sign * bth
    out[:, 2] = sign * br
    return 1e-9 * out
