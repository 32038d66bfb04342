"""Orbit models of Dzhepe Ali: the GLONASS ICD Earth-fixed equations of motion (RK4, with the state-transition
matrix), the circular Keplerian reference orbit, and TLE input through the ``sgp4`` package.

Frames and units (``docs/conventions.md``, "Orbit determination"): states are ``(x, y, z, vx, vy, vz)`` in
Earth-fixed axes (ECEF; the GLONASS ICD's PZ-90, taken equal to WGS-84 here), metres and metres per second,
velocities relative to the rotating Earth. ``ECEF = Rz(theta) ECI`` with ``theta = theta0 + omega_E t``.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike, NDArray

from gnssatt import _core
from gnssatt import constants as _constants
from gnssatt._arrays import checked_array, finite_result, float_array, instance, scalar, vector_array
from gnssatt.errors import InvalidInputError, InvalidTypeError, WorkLimitError

__all__ = [
    "CircularOrbit",
    "GlonassModel",
    "PropagatedState",
    "glonass_propagate",
    "gmst_rad",
    "teme_to_ecef",
    "tle_states",
]

#: Earth rotation rate of the GLONASS CDMA ICD (2016) and WGS-84, rad/s.
OMEGA_E_RAD_S = _constants.OMEGA_E_RAD_S
#: Most RK4 steps of one :func:`glonass_propagate` call (and of all the steps of one
#: :func:`gnssatt.orbit.determination.noisy_orbit` or :func:`gnssatt.orbit.determination.orbit_filter`
#: call): the core's limit, about 58 days in 1 s steps, some 8 s of work.
MAX_RK4_STEPS = int(_core.ORBIT_MAX_RK4_STEPS)
#: Closest distance to the Earth's centre of a propagated position, as a fraction of the model's equatorial
#: radius (0.99: below the surface, the polar radius being 0.9966 of it, the model no longer describes the
#: motion): the core's bound, checked here so that the message names the caller's argument.
MIN_ORBIT_RADIUS_FRACTION = float(_core.ORBIT_MIN_RADIUS_FRACTION)
#: Julian dates accepted by :func:`gmst_rad` (4713 BC to AD 22666): the IAU-82 polynomial is cubic in the
#: centuries from J2000 and meaningless far outside.
JULIAN_DATE_RANGE = (0.0, 1.0e7)


@dataclass(frozen=True)
class GlonassModel:
    """Constants of the GLONASS ICD model (PZ-90 values of the ICD, 2016 edition, appendix J).

    Attributes
    ----------
    gm_m3_s2
        Earth's gravitational parameter, m^3/s^2.
    j2
        Second zonal harmonic; 0 leaves only the central field.
    equatorial_radius_m
        Radius that scales J2, m.
    omega_rad_s
        Rotation rate of the Earth-fixed axes, rad/s; 0 turns the equations into inertial ones.
    lunisolar_m_s2
        (3,) constant perturbing acceleration in Earth-fixed axes (the broadcast luni-solar term), m/s^2.
    """

    gm_m3_s2: float = 398600.4418e9
    j2: float = 1082625.75e-9
    equatorial_radius_m: float = 6378136.0
    omega_rad_s: float = OMEGA_E_RAD_S
    lunisolar_m_s2: tuple[float, float, float] = field(default=(0.0, 0.0, 0.0))

    def __post_init__(self) -> None:
        for name in ("gm_m3_s2", "j2", "equatorial_radius_m", "omega_rad_s"):
            object.__setattr__(self, name, scalar(name, getattr(self, name)))
        acc = _vec3("lunisolar_m_s2", self.lunisolar_m_s2)
        object.__setattr__(self, "lunisolar_m_s2", tuple(float(a) for a in acc))
        if self.gm_m3_s2 <= 0 or self.equatorial_radius_m <= 0:
            raise InvalidInputError(
                f"expected gm_m3_s2 > 0 and equatorial_radius_m > 0, got {self.gm_m3_s2}, "
                f"{self.equatorial_radius_m}"
            )

    def _kwargs(self) -> _core._GlonassModelArgs:
        return {
            "gm_m3_s2": self.gm_m3_s2,
            "j2": self.j2,
            "equatorial_radius_m": self.equatorial_radius_m,
            "omega_rad_s": self.omega_rad_s,
            "lunisolar_m_s2": self.lunisolar_m_s2,
        }


@dataclass(frozen=True)
class PropagatedState:
    """State after :func:`glonass_propagate`.

    Attributes
    ----------
    position_m, velocity_m_s
        (3,) Earth-fixed position (m) and velocity relative to the rotating Earth (m/s).
    stm
        (6, 6) state-transition matrix ``d(r, v)(t + duration) / d(r, v)(t)`` from the variational equations.
    """

    position_m: NDArray[np.float64]
    velocity_m_s: NDArray[np.float64]
    stm: NDArray[np.float64]

    @property
    def state(self) -> NDArray[np.float64]:
        """(6,) ``(position, velocity)``."""
        return np.concatenate([self.position_m, self.velocity_m_s])


def _vec3(name: str, value: ArrayLike) -> NDArray[np.float64]:
    return vector_array(name, value, ndim=1, shape="(3,)")


def rk4_steps(what: str, durations_s: NDArray[np.float64], step_s: float) -> int:
    """Number of RK4 steps ``sum ceil(duration / step)`` of a propagation, checked against
    ``MAX_RK4_STEPS`` before any work; ``what`` names the call and the span's parameter in the
    :class:`~gnssatt.errors.WorkLimitError`."""
    n = float(np.sum(np.ceil(np.maximum(durations_s, 0.0) / step_s)))
    if n > MAX_RK4_STEPS:
        raise WorkLimitError(
            f"{what} ({float(np.sum(durations_s)):.6g} s) in steps of step_s = {step_s} s needs {n:.3g} RK4 "
            f"steps, beyond the limit of {MAX_RK4_STEPS}; use a longer step_s or a shorter span"
        )
    return int(n)


def _orbit_position(position_m: ArrayLike, equatorial_radius_m: float) -> NDArray[np.float64]:
    """The (3,) position of :func:`glonass_propagate`, m, refused inside the Earth (the model's
    :data:`MIN_ORBIT_RADIUS_FRACTION` of its equatorial radius)."""
    r = _vec3("position_m", position_m)
    r_min = MIN_ORBIT_RADIUS_FRACTION * equatorial_radius_m
    if not np.linalg.norm(r) >= r_min:
        raise InvalidInputError(
            f"expected position_m at least {r_min:.6g} m away from the Earth's centre ("
            f"{MIN_ORBIT_RADIUS_FRACTION} of the model's equatorial radius), got |r| = "
            f"{np.linalg.norm(r):.6g} m"
        )
    return r


def _duration_and_step(duration_s: float, step_s: float) -> tuple[float, float]:
    """The duration and step of :func:`glonass_propagate`, s: a step no longer than a positive duration, and
    no more steps than the work limit (the core reports the other cases)."""
    d = scalar("duration_s", duration_s)
    h = scalar("step_s", step_s)
    if 0 < d < h:
        raise InvalidInputError(
            f"expected step_s in (0, duration_s], no longer than the duration, got step_s = {h:g} s "
            f"and duration_s = {d:g} s"
        )
    if d > 0 and 0 < h <= d:  # the core reports the other cases
        rk4_steps("glonass_propagate over duration_s", np.array([d]), h)
    return d, h


def glonass_propagate(
    position_m: ArrayLike,
    velocity_m_s: ArrayLike,
    duration_s: float,
    *,
    step_s: float = 10.0,
    lunisolar_m_s2: ArrayLike | None = None,
    model: GlonassModel | None = None,
) -> PropagatedState:
    """Propagate a state forward with the GLONASS ICD equations of motion by 4th-order Runge-Kutta.

    The Earth-fixed equations (GLONASS ICD ed. 5.1, 2008, A.3.1.2; CDMA ICD 2016, J.2): central gravity,
    J2, centrifugal ``omega^2 (x, y)`` and Coriolis ``2 omega (vy, -vx)`` terms and a constant luni-solar
    acceleration, integrated in ``ceil(duration / step)`` equal steps together with the variational
    equations ``dPhi/dt = F(x) Phi``.

    Parameters
    ----------
    position_m, velocity_m_s
        (3,) Earth-fixed position (m) and velocity relative to the rotating Earth (m/s).
    duration_s
        Propagation time, s, >= 0. Only forward propagation: a negative duration is an error (to go
        backwards, e.g. from a broadcast reference time, use :mod:`gnssatt.rinex`'s ephemeris functions).
    step_s
        Longest RK4 step, s, in (0, duration_s] (any positive step when ``duration_s`` is 0).
    lunisolar_m_s2
        (3,) constant acceleration in Earth-fixed axes, m/s^2; overrides ``model.lunisolar_m_s2``.
    model
        The constants (default :class:`GlonassModel`, the ICD's PZ-90 values).

    Returns
    -------
    PropagatedState

    Raises
    ------
    InvalidInputError
        Non-finite or wrongly shaped state, a position nearer the Earth's centre than
        ``MIN_ORBIT_RADIUS_FRACTION`` (0.99) of the model's equatorial radius, negative duration,
        step <= 0 or longer than the duration.
    WorkLimitError
        More than ``MAX_RK4_STEPS`` (1e7) steps.
    ConvergenceError
        The integration overflowed (absurd velocities or model constants: the state left float64).

    Examples
    --------
    Central gravity alone in inertial axes (``j2 = 0``, ``omega_rad_s = 0``): a circular orbit of 25 500 km
    turns by 90 deg in a quarter of its period ``2 pi sqrt(r^3 / GM)``, and the state-transition matrix of
    this Hamiltonian flow preserves phase-space volume (determinant 1):

    >>> import numpy as np
    >>> from gnssatt.orbit import GlonassModel, glonass_propagate
    >>> gm, r = 398600.4418e9, 25_500e3  # m^3/s^2, m
    >>> quarter = 0.5 * np.pi * np.sqrt(r**3 / gm)  # s
    >>> model = GlonassModel(j2=0.0, omega_rad_s=0.0)
    >>> v = np.sqrt(gm / r)  # m/s, circular
    >>> state = glonass_propagate([r, 0.0, 0.0], [0.0, v, 0.0], quarter, step_s=50.0, model=model)
    >>> np.round(state.position_m / 1e3, 3) + 0.0  # km
    array([    0., 25500.,     0.])
    >>> round(float(np.linalg.det(state.stm)), 6)
    1.0
    """
    m = instance("model", model if model is not None else GlonassModel(), GlonassModel, "a GlonassModel")
    if lunisolar_m_s2 is not None:
        acc = _vec3("lunisolar_m_s2", lunisolar_m_s2)
        m = GlonassModel(m.gm_m3_s2, m.j2, m.equatorial_radius_m, m.omega_rad_s, tuple(acc))
    r = _orbit_position(position_m, m.equatorial_radius_m)
    state = np.concatenate([r, _vec3("velocity_m_s", velocity_m_s)])
    d, h = _duration_and_step(duration_s, step_s)
    out = _core.glonass_propagate(state, d, m._kwargs(), step_s=h)
    x, phi = out.state, out.stm
    cause = f"position {r.tolist()} m, velocity {state[3:].tolist()} m/s over {d} s"
    finite_result("the propagated state", x, cause)
    finite_result("the state-transition matrix", phi, cause)
    return PropagatedState(x[:3].copy(), x[3:].copy(), phi)


@dataclass(frozen=True)
class CircularOrbit:
    """A circular Keplerian orbit (the seed's reference orbit), mapped orbital -> ECI -> ECEF.

    Attributes
    ----------
    radius_m
        Orbit radius, m.
    inclination_rad, raan_rad
        Inclination and right ascension of the ascending node in ECI, rad.
    arg_latitude0_rad
        Argument of latitude at ``t = 0``, rad.
    gm_m3_s2
        Gravitational parameter (default WGS-84), m^3/s^2.

    Raises
    ------
    InvalidInputError
        Non-finite or non-real elements, a radius outside [``MIN_ORBIT_RADIUS_FRACTION`` x the WGS-84
        equatorial radius, 1e12] m, a non-positive ``gm_m3_s2``.
    """

    radius_m: float
    inclination_rad: float
    raan_rad: float
    arg_latitude0_rad: float
    gm_m3_s2: float = _constants.GM_M3_S2

    def __post_init__(self) -> None:
        for name in ("inclination_rad", "raan_rad", "arg_latitude0_rad"):
            object.__setattr__(self, name, scalar(name, getattr(self, name)))
        r_min = MIN_ORBIT_RADIUS_FRACTION * _constants.WGS84_A_M
        r = scalar("radius_m", self.radius_m, minimum=r_min, unit="m")
        object.__setattr__(self, "radius_m", scalar("radius_m", r, maximum=1e12, unit="m"))
        object.__setattr__(self, "gm_m3_s2", scalar("gm_m3_s2", self.gm_m3_s2, minimum=0.0, strict=True))

    @property
    def period_s(self) -> float:
        """``2 pi sqrt(r^3 / GM)``, s."""
        return float(2.0 * np.pi * np.sqrt(self.radius_m**3 / self.gm_m3_s2))

    def state_ecef(
        self, times_s: ArrayLike, *, theta0_rad: float = 0.0, omega_rad_s: float = OMEGA_E_RAD_S
    ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """(n, 3) ECEF positions (m) and velocities relative to the Earth (m/s) at ``times_s`` (n,), s.

        The orbital frame (x along-track, y orbit normal, z radial) is rotated into ECI by
        ``Rz(raan) Rx(i) Rz(u)`` and ECI into ECEF by ``Rz(-(theta0 + omega t))``.
        """
        t = float_array("times_s", times_s, ndim=1, shape="(n,)")
        elements = [
            getattr(self, k)
            for k in ("radius_m", "inclination_rad", "raan_rad", "arg_latitude0_rad", "gm_m3_s2")
        ]
        out = _core.circular_orbit_ecef(
            elements,
            t,
            theta0_rad=scalar("theta0_rad", theta0_rad),
            omega_rad_s=scalar("omega_rad_s", omega_rad_s),
        )
        return out.position_m, out.velocity_m_s


def gmst_rad(jd_ut1: ArrayLike) -> NDArray[np.float64]:
    """Greenwich mean sidereal time (IAU-82, Vallado's ``gstime``) of UT1 Julian dates, rad in [0, 2 pi).

    Parameters
    ----------
    jd_ut1
        () or (n,) Julian dates in UT1, days, within ``JULIAN_DATE_RANGE``.

    Returns
    -------
    numpy.ndarray
        GMST, rad in [0, 2 pi), of the shape of ``jd_ut1``.

    Raises
    ------
    InvalidInputError
        Julian dates outside ``JULIAN_DATE_RANGE`` ([0, 1e7]), non-finite or non-real.

    Examples
    --------
    At J2000.0 (JD 2451545.0, ``T = 0``) the polynomial leaves its constant term, 67310.54841 s of
    sidereal time, i.e. ``67310.54841 / 240 = 280.460618`` deg:

    >>> import numpy as np
    >>> from gnssatt.orbit import gmst_rad
    >>> round(float(np.degrees(gmst_rad(2451545.0))), 6)
    280.460618
    """
    jd = checked_array("jd_ut1", jd_ut1, ndim=(0, 1), shape="() or (n,)")
    lo, hi = JULIAN_DATE_RANGE
    if jd.size and (jd.min() < lo or jd.max() > hi):
        raise InvalidInputError(
            f"expected jd_ut1 in [{lo}, {hi}] (Julian dates), got [{jd.min()}, {jd.max()}]"
        )
    t = (jd - 2451545.0) / 36525.0
    sec = 67310.54841 + (876600.0 * 3600.0 + 8640184.812866) * t + 0.093104 * t**2 - 6.2e-6 * t**3
    return np.remainder(np.radians(sec / 240.0), 2.0 * np.pi)


def teme_to_ecef(
    r_teme_m: ArrayLike, v_teme_m_s: ArrayLike, jd_ut1: ArrayLike
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """TEME (the SGP4 output frame) to Earth-fixed axes by the GMST rotation.

    ``r = Rz(-gmst) r_teme``, ``v = Rz(-gmst) v_teme - omega_E x r``. Polar motion is neglected (the result is
    the pseudo-Earth-fixed frame; polar motion moves a LEO position by up to about 15 m) and so is the
    length-of-day change of ``omega_E``.

    Parameters
    ----------
    r_teme_m, v_teme_m_s
        (n, 3) or (3,) TEME position (m) and velocity (m/s).
    jd_ut1
        () or (n,) Julian dates in UT1.

    Returns
    -------
    position_m, velocity_m_s
        (n, 3) or (3,) Earth-fixed position (m) and velocity relative to the rotating Earth (m/s).

    Raises
    ------
    InvalidInputError
        Wrong shapes, ``r_teme_m`` and ``v_teme_m_s`` of different shapes, a ``jd_ut1`` that is not one date
        per position, non-finite values or Julian dates outside ``JULIAN_DATE_RANGE``
        (:class:`~gnssatt.errors.InvalidTypeError` for values that are not real numbers).
    ConvergenceError
        Vectors so large (near 1e308) that the rotated ones overflow float64.

    Examples
    --------
    A point that turns with the Earth (``v_teme = omega_E x r_teme``) is at rest in Earth-fixed axes; the
    rotation about Z keeps the radius and the Z component:

    >>> import numpy as np
    >>> from gnssatt.constants import OMEGA_E_RAD_S
    >>> from gnssatt.orbit import teme_to_ecef
    >>> r_teme = np.array([7000e3, 1000e3, 2000e3])  # m
    >>> v_teme = np.cross([0.0, 0.0, OMEGA_E_RAD_S], r_teme)  # m/s
    >>> r, v = teme_to_ecef(r_teme, v_teme, 2451545.0)
    >>> np.round(v, 9) + 0.0
    array([0., 0., 0.])
    >>> round(float(np.linalg.norm(r) - np.linalg.norm(r_teme)), 6) + 0.0, float(r[2])
    (0.0, 2000000.0)
    """
    r = vector_array("r_teme_m", r_teme_m, ndim=(1, 2), shape="(n, 3)")
    v = vector_array("v_teme_m_s", v_teme_m_s, ndim=(1, 2), shape="(n, 3)")
    if v.shape != r.shape:
        raise InvalidInputError(
            f"expected r_teme_m and v_teme_m_s of one shape (n, 3), got {r.shape}, {v.shape}"
        )
    g = gmst_rad(jd_ut1)
    if g.ndim == 1 and g.shape != r.shape[:1]:
        raise InvalidInputError(
            f"expected jd_ut1 of shape () or ({r.shape[0]},) (one per position), got {g.shape}"
        )
    c, s, z, o = np.cos(g), np.sin(g), np.zeros_like(g), np.ones_like(g)
    ecef_from_teme = np.stack(
        [np.stack([c, s, z], -1), np.stack([-s, c, z], -1), np.stack([z, z, o], -1)], -2
    )
    # finite vectors near the float limit (1e308 m) overflow when rotated: refuse rather than return inf
    with np.errstate(over="ignore", invalid="ignore"):
        re = np.einsum("...ij,...j->...i", ecef_from_teme, r)
        ve = np.einsum("...ij,...j->...i", ecef_from_teme, v)
        ve = ve - np.cross([0.0, 0.0, OMEGA_E_RAD_S], re)
    cause = "r_teme_m or v_teme_m_s too large to rotate in float64"
    return finite_result("teme_to_ecef position", re, cause), finite_result(
        "teme_to_ecef velocity", ve, cause
    )


def _julian_dates(times: ArrayLike) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    t = np.asarray(times)
    if t.dtype.kind != "M":
        raise InvalidTypeError(f"expected times as numpy datetime64 (UTC), got dtype {t.dtype}")
    if t.ndim > 1:
        raise InvalidInputError(f"expected times of shape () or (n,), got {t.shape}")
    if np.any(np.isnat(t)):
        raise InvalidInputError("times contains NaT")
    ns = t.astype("datetime64[ns]").astype(np.int64)
    days = ns // 86_400_000_000_000
    frac = (ns - days * 86_400_000_000_000) / 86_400e9
    return np.atleast_1d(2440587.5 + days.astype(np.float64)), np.atleast_1d(frac)


def tle_states(
    line1: str, line2: str, times: ArrayLike, *, dut1_s: float = 0.0
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Earth-fixed states of a satellite from its two-line elements (SGP4 through the ``sgp4`` package).

    Parameters
    ----------
    line1, line2
        The TLE lines.
    times
        (n,) or () numpy ``datetime64`` instants, UTC.
    dut1_s
        UT1 - UTC, s, for the Earth rotation (neglecting it, ``|dUT1|`` < 0.9 s, turns a LEO position by up to
        about 0.4 km along the equator).

    Returns
    -------
    position_m, velocity_m_s
        (n, 3) Earth-fixed (pseudo-Earth-fixed: polar motion neglected, see :func:`teme_to_ecef`).

    Raises
    ------
    ImportError
        ``sgp4`` is not installed (``pip install gnssatt[tle]``).
    InvalidInputError
        ``line1``/``line2`` not TLE lines (starting with ``"1 "``/``"2 "``, at least 68 characters),
        an unparsable TLE, or SGP4 reports an error (e.g. decayed orbit) at some time.
    ConvergenceError
        SGP4 returns a non-finite state for the elements.

    Examples
    --------
    Satellite 00005 (Vanguard 1) of the SGP4 verification set, 360 min after its epoch, where Vallado et
    al. (2006) give the TEME position ``(-7154.031, -3783.177, -3536.194)`` km: the Earth-fixed position
    keeps its Z component and its radius (8831.606 km):

    >>> import numpy as np
    >>> from gnssatt.orbit import tle_states
    >>> line1 = "1 00005U 58002B   00179.78495062  .00000023  00000-0  28098-4 0  4753"
    >>> line2 = "2 00005  34.2682 348.7242 1859667 331.7664  19.3264 10.82419157413667"
    >>> t = np.datetime64("2000-06-27T18:50:19.733568") + np.timedelta64(360, "m")  # UTC
    >>> r, v = tle_states(line1, line2, np.array([t]))
    >>> round(float(r[0, 2]) / 1e3, 3), round(float(np.linalg.norm(r[0])) / 1e3, 3)  # km
    (-3536.194, 8831.606)
    """
    instance("line1", line1, str, "a str")
    instance("line2", line2, str, "a str")
    jd, fr = _julian_dates(times)
    for name, line, digit in (("line1", line1, "1"), ("line2", line2, "2")):
        if not line.startswith(digit + " ") or len(line.rstrip()) < 68:
            raise InvalidInputError(
                f"expected {name} as TLE line {digit}: starting with '{digit} ' and at least 68 characters "
                f"long, got {line[:80]!r}"
            )
    d = scalar("dut1_s", dut1_s, minimum=-1.0, maximum=1.0, unit="s")  # |UT1 - UTC| < 0.9 s by definition
    try:
        from sgp4.api import Satrec
    except ImportError as exc:  # pragma: no cover - depends on the environment
        raise ImportError("tle_states needs the sgp4 package: pip install 'gnssatt[tle]'") from exc
    try:
        sat = Satrec.twoline2rv(line1, line2)
    except (ValueError, IndexError) as exc:
        raise InvalidInputError(f"could not parse the TLE line1, line2: {exc}") from exc
    err, r_km, v_km_s = sat.sgp4_array(jd, fr)
    if np.any(err != 0):
        k = int(np.flatnonzero(err)[0])
        raise InvalidInputError(
            f"SGP4 error code {int(err[k])} at time index {k} for the elements of line1, line2 (see "
            "sgp4.api.SGP4_ERRORS)"
        )
    finite_result("the SGP4 state", r_km, "the elements of line1, line2")
    finite_result("the SGP4 velocity", v_km_s, "the elements of line1, line2")
    return teme_to_ecef(r_km * 1e3, v_km_s * 1e3, jd + (fr + d / 86400.0))
