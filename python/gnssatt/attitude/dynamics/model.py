"""The tumbling-spacecraft model of Belokonov et al.: its parameters (:class:`TumbleModel`), frames and
the limits of its integration (the propagation is :mod:`~gnssatt.attitude.dynamics.propagation`)."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from gnssatt import _core
from gnssatt import constants as _constants
from gnssatt._arrays import (
    scalar,
    vector_array,
)
from gnssatt.errors import InvalidInputError, InvalidTypeError

GM_M3_S2 = _constants.GM_M3_S2
EARTH_RADIUS_M = _constants.WGS84_A_M
# Library orbital (x along, y normal, z radial) from the paper's (X0 radial, Y0 along, Z0 normal).
DCM_ORBITAL_FROM_ORB0 = np.array([[0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]])
MAX_RATE_RAD_S = math.radians(3.0)
#: Most RK4 steps of one propagation call, all initial states together (the core's limit, about 10 s of
#: one core); a fit's population (``popsize * 6`` states) counts once per generation.
MAX_RK4_STEPS = int(_core.DYNAMICS_MAX_RK4_STEPS)
#: Largest rotation per RK4 step, ``|omega| h`` in rad, at the initial rates: RK4 on a rotation loses
#: stability near 2.8 rad per step and accuracy long before (this bound keeps the angle error per step
#: below about 1e-2 rad); beyond it the integration is refused rather than left to produce NaN.
MAX_ROTATION_PER_STEP_RAD = float(_core.DYNAMICS_MAX_ROTATION_PER_STEP_RAD)
#: Most output times of one :func:`propagate` call, counted from the shape of ``t`` before it is copied:
#: 25 us a time (the rotations and axes of each state; ``docs/limits.md``) makes about 6.6 s.
#: :func:`propagate_axes` (0.1 us a time) is bounded by the core's output limit.
MAX_PROPAGATE_TIMES = 2**18


@dataclass(frozen=True)
class TumbleModel:
    """Parameters of eqs. (3)-(4); SI units.

    The default is an assumed 3U-class nanosatellite (the paper does not list its parameters) on a
    circular 500 km orbit: principal moments (0.035, 0.008, 0.030) kg m^2 with the antenna axis ``Yc``
    the axis of least inertia, drag coefficient 2.2, area 0.03 m^2, density 5e-13 kg/m^3, centre of
    pressure 2 cm behind the centre of mass along ``Yc``.

    Attributes
    ----------
    inertia_kg_m2
        Principal moments ``(Ix, Iy, Iz)``, kg m^2. Gravity gradient depends only on the ratios
        ``Ix/Iz``, ``Iy/Iz`` (the paper's dimensionless coefficients); the scale matters for drag.
    orbital_rate_rad_s
        Orbital rate ``w0 = sqrt(mu / r^3)``, rad/s; the gravity-gradient coefficient is ``3 w0^2``.
    gravity_gradient
        Whether the gravity-gradient torque acts (the orbital frame turns at ``w0`` regardless).
    density_kg_m3, drag_coefficient, area_m2
        Drag ``F = -0.5 rho Cd S |V| V`` (constant area).
    cp_offset_m
        Centre of pressure minus centre of mass, body axes, m.
    speed_m_s
        Orbital speed, m/s (the atmosphere is taken at rest).
    """

    orbital_rate_rad_s: float
    speed_m_s: float
    inertia_kg_m2: tuple[float, float, float] = (0.035, 0.008, 0.030)
    gravity_gradient: bool = True
    density_kg_m3: float = 5e-13
    drag_coefficient: float = 2.2
    area_m2: float = 0.03
    cp_offset_m: tuple[float, float, float] = (0.0, -0.02, 0.0)

    def __post_init__(self) -> None:
        for name in ("orbital_rate_rad_s", "speed_m_s", "density_kg_m3", "drag_coefficient", "area_m2"):
            object.__setattr__(self, name, scalar(name, getattr(self, name), minimum=0.0))
        inertia = vector_array("inertia_kg_m2", self.inertia_kg_m2, ndim=1, shape="(3,)")
        ix, iy, iz = inertia
        tol = 1e-12 * (ix + iy + iz)  # the core's tolerance: a thin plate has ix + iy = iz to rounding
        if inertia.min() <= 0 or ix + iy < iz - tol or iy + iz < ix - tol or iz + ix < iy - tol:
            raise InvalidInputError(
                f"expected inertia_kg_m2 as positive principal moments obeying the triangle inequality, "
                f"got {inertia.tolist()}"
            )
        cp = vector_array("cp_offset_m", self.cp_offset_m, ndim=1, shape="(3,)")
        if not isinstance(self.gravity_gradient, bool | np.bool_):
            raise InvalidTypeError(
                f"expected gravity_gradient as a bool, got {type(self.gravity_gradient).__name__}"
            )
        object.__setattr__(self, "inertia_kg_m2", tuple(float(v) for v in inertia))
        object.__setattr__(self, "cp_offset_m", tuple(float(v) for v in cp))

    @classmethod
    def circular(cls, altitude_m: float = 500e3, **kwargs: Any) -> TumbleModel:
        """The model on a circular orbit of ``altitude_m`` above a 6378137 m sphere (altitude in
        (-6378137, 1e12] m)."""
        r = EARTH_RADIUS_M + scalar("altitude_m", altitude_m, maximum=1e12, unit="m")
        if not r > 0:
            raise InvalidInputError(f"expected altitude_m above -6378137 m, got {altitude_m}")
        return cls(orbital_rate_rad_s=math.sqrt(GM_M3_S2 / r**3), speed_m_s=math.sqrt(GM_M3_S2 / r), **kwargs)

    def _kwargs(self) -> _core._TumbleModelArgs:
        return {
            "inertia_kg_m2": self.inertia_kg_m2,
            "orbital_rate_rad_s": float(self.orbital_rate_rad_s),
            "gravity_gradient": bool(self.gravity_gradient),
            "density_kg_m3": float(self.density_kg_m3),
            "drag_coefficient": float(self.drag_coefficient),
            "area_m2": float(self.area_m2),
            "cp_offset_m": self.cp_offset_m,
            "speed_m_s": float(self.speed_m_s),
        }
