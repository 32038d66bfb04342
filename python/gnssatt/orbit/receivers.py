"""Receivers (vehicles) whose antenna arrays the simulator observes: static on the ground, or on a circular
low Earth orbit.

Conventions of :mod:`gnssatt.sim`: SI units and radians inside (arguments in degrees end in ``_deg``);
``t`` in seconds from the scenario epoch; scalar ``t`` -> unbatched outputs, ``t`` of shape (n_t,) -> a
leading epoch axis. Frames as in :mod:`gnssatt.frames`.

Each receiver has a *reference frame* in which attitudes are expressed (``rotation.apply(v_body)`` gives
reference coordinates):

- :class:`GroundReceiver`: local-level ENU (East, North, Up) at its geodetic point.
- :class:`OrbitalReceiver`: the orbital frame of its circular orbit: x along-track (velocity direction),
  y along the orbit normal (angular momentum ``r x v``), z radial (zenith, away from the Earth); right-handed
  since ``x cross y = z``.

Both provide ``state_eci(t)``, ``state_ecef(t)`` and ``dcm_eci_from_reference(t)``, which the geometry
functions use.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from gnssatt._arrays import scalar, time_array
from gnssatt.constants import GM_M3_S2, WGS84_A_M
from gnssatt.errors import InvalidInputError
from gnssatt.frames import (
    MAX_DEPTH_M,
    dcm_ecef_from_enu,
    dcm_eci_from_ecef,
    ecef_to_eci,
    eci_to_ecef,
    geodetic_to_ecef,
    rot_x,
    rot_z,
)
from gnssatt.orbit.kepler import check_orbital_motion

__all__ = ["GroundReceiver", "OrbitalReceiver", "Receiver"]

#: Largest orbit radius of an :class:`OrbitalReceiver`, m (beyond it ``r^3`` overflows the mean motion).
MAX_ORBIT_RADIUS_M = 1e15


@dataclass(frozen=True)
class GroundReceiver:
    """A static receiver on the rotating Earth; reference frame ENU.

    Attributes
    ----------
    lat_deg, lon_deg
        Geodetic WGS-84 latitude and longitude, degrees.
    height_m
        Height above the WGS-84 ellipsoid, m, in [-6e6, 1e12] (see :func:`~gnssatt.sim.geodetic_to_ecef`).
    theta0_rad
        Earth rotation angle at ``t = 0`` (ECEF = ECI rotated by ``theta0 + OMEGA_E t``).
    """

    lat_deg: float
    lon_deg: float
    height_m: float = 0.0
    theta0_rad: float = 0.0

    frame = "enu"

    def __post_init__(self) -> None:
        lat = scalar("lat_deg", self.lat_deg)
        if abs(lat) > 90.0:
            raise InvalidInputError(f"expected lat_deg in [-90, 90], got {lat}")
        for name in ("lon_deg", "height_m", "theta0_rad"):
            object.__setattr__(self, name, scalar(name, getattr(self, name)))
        object.__setattr__(self, "lat_deg", lat)
        scalar("height_m", self.height_m, minimum=-MAX_DEPTH_M, maximum=1e12, unit="m")

    @property
    def position_ecef_m(self) -> NDArray[np.float64]:
        """(3,) ECEF position, m."""
        return geodetic_to_ecef(self.lat_deg, self.lon_deg, self.height_m)

    @property
    def dcm_ecef_from_enu(self) -> NDArray[np.float64]:
        """(3, 3) rotation ENU -> ECEF (columns E, N, U)."""
        return dcm_ecef_from_enu(self.lat_deg, self.lon_deg)

    def state_ecef(self, t: ArrayLike) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """ECEF position (m) and velocity (zero), (3,) or (n_t, 3)."""
        tt = time_array(t)
        r = np.broadcast_to(self.position_ecef_m, (*tt.shape, 3)).copy()
        return r, np.zeros_like(r)

    def state_eci(self, t: ArrayLike) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """ECI position (m) and velocity (m/s, ``omega x r``), (3,) or (n_t, 3)."""
        r, v = self.state_ecef(t)
        return ecef_to_eci(r, v, t, self.theta0_rad)

    def dcm_eci_from_enu(self, t: ArrayLike) -> NDArray[np.float64]:
        """Rotation ENU -> ECI at ``t``, (3, 3) or (n_t, 3, 3)."""
        return dcm_eci_from_ecef(t, self.theta0_rad) @ self.dcm_ecef_from_enu

    def dcm_eci_from_reference(self, t: ArrayLike) -> NDArray[np.float64]:
        """Rotation reference frame (ENU) -> ECI at ``t``, (3, 3) or (n_t, 3, 3)."""
        return self.dcm_eci_from_enu(t)


@dataclass(frozen=True)
class OrbitalReceiver:
    """A receiver on a circular two-body orbit; reference frame the orbital frame.

    Attributes
    ----------
    altitude_m
        Orbit radius minus the WGS-84 equatorial radius (6378137 m), m; the radius must lie in
        (0, ``MAX_ORBIT_RADIUS_M``].
    inclination_deg, raan_deg
        Inclination and right ascension of the ascending node (ECI), degrees.
    arg_latitude_deg
        Argument of latitude ``u`` (angle from the ascending node along the orbit) at ``t = 0``, degrees.
    theta0_rad
        Earth rotation angle at ``t = 0``, used for the ECEF outputs only.
    gm_m3_s2
        Gravitational parameter, m^3/s^2.
    """

    altitude_m: float
    inclination_deg: float
    raan_deg: float = 0.0
    arg_latitude_deg: float = 0.0
    theta0_rad: float = 0.0
    gm_m3_s2: float = GM_M3_S2

    frame = "orbital"

    def __post_init__(self) -> None:
        scalar("altitude_m", self.altitude_m, minimum=-WGS84_A_M, strict=True)
        scalar("altitude_m", self.altitude_m, maximum=MAX_ORBIT_RADIUS_M - WGS84_A_M, unit="m")
        scalar("gm_m3_s2", self.gm_m3_s2, minimum=0.0, strict=True)
        names = ("altitude_m", "inclination_deg", "raan_deg", "arg_latitude_deg", "theta0_rad", "gm_m3_s2")
        for name in names:
            object.__setattr__(self, name, scalar(name, getattr(self, name)))
        check_orbital_motion("altitude_m", np.array([self.radius_m]), self.gm_m3_s2)

    @property
    def radius_m(self) -> float:
        """Orbit radius, m."""
        return WGS84_A_M + self.altitude_m

    @property
    def mean_motion_rad_s(self) -> float:
        """Orbital rate ``sqrt(GM / r^3)``, rad/s."""
        return float(np.sqrt(self.gm_m3_s2 / self.radius_m**3))

    @property
    def period_s(self) -> float:
        """Orbital period, s."""
        return 2.0 * np.pi / self.mean_motion_rad_s

    def arg_latitude_rad(self, t: ArrayLike) -> NDArray[np.float64]:
        """Argument of latitude ``u(t) = u0 + n t``, rad (not wrapped), shape of ``t``."""
        return float(np.radians(self.arg_latitude_deg)) + self.mean_motion_rad_s * time_array(t)

    def dcm_eci_from_orbital(self, t: ArrayLike) -> NDArray[np.float64]:
        """Rotation orbital frame -> ECI at ``t``, (3, 3) or (n_t, 3, 3).

        Columns: along-track ``Rz(RAAN) Rx(i) [-sin u, cos u, 0]``, orbit normal ``Rz(RAAN) Rx(i) [0, 0, 1]``,
        radial ``Rz(RAAN) Rx(i) [cos u, sin u, 0]``.
        """
        u = self.arg_latitude_rad(t)
        q = rot_z(np.radians(self.raan_deg)) @ rot_x(np.radians(self.inclination_deg))
        c, s = np.cos(u), np.sin(u)
        z = np.zeros_like(u)
        in_plane = np.stack(
            [np.stack([-s, z, c], -1), np.stack([c, z, s], -1), np.stack([z, np.ones_like(u), z], -1)], -2
        )
        dcm: NDArray[np.float64] = q @ in_plane
        return dcm

    def dcm_eci_from_reference(self, t: ArrayLike) -> NDArray[np.float64]:
        """Rotation reference frame (orbital) -> ECI at ``t``, (3, 3) or (n_t, 3, 3)."""
        return self.dcm_eci_from_orbital(t)

    def state_eci(self, t: ArrayLike) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """ECI position (m) and velocity (m/s), (3,) or (n_t, 3)."""
        m = self.dcm_eci_from_orbital(t)
        r = self.radius_m * m[..., :, 2]
        v = self.radius_m * self.mean_motion_rad_s * m[..., :, 0]
        return r, v

    def state_ecef(self, t: ArrayLike) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """ECEF position (m) and velocity relative to the rotating Earth (m/s), (3,) or (n_t, 3)."""
        r, v = self.state_eci(t)
        return eci_to_ecef(r, v, t, self.theta0_rad)


Receiver = GroundReceiver | OrbitalReceiver
