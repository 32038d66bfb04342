"""Orbit determination of a small satellite from its GNSS receiver (Dzhepe Ali, chapter 1): the receiver's
own least-squares position/velocity fix, and the Kalman filter (inner loop in Rust) whose prediction is the
GLONASS ICD orbit model and whose corrections are either those fixes (loosely coupled) or between-satellite
first differences of pseudoranges and Doppler (tightly coupled).

State ``x = (x, y, z, vx, vy, vz)``: Earth-fixed axes, m and m/s (velocity relative to the rotating Earth).
Process noise: white acceleration of power spectral density ``accel_psd_m2_s3`` per axis. Conventions in
``docs/conventions.md`` ("Orbit determination").
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from gnssatt import _core
from gnssatt._arrays import finite_result, float_array, generator, instance, real_array, scalar, text
from gnssatt.errors import InvalidInputError, InvalidTypeError, WorkLimitError
from gnssatt.observations import SpaceborneMeasurements
from gnssatt.orbit import MIN_ORBIT_RADIUS_FRACTION, GlonassModel, glonass_propagate, rk4_steps

#: Most epochs of :func:`noisy_orbit` (a Python loop, about 0.1 ms per epoch).
MAX_EPOCHS = 1_000_000
#: Largest ``accel_psd_m2_s3`` of :func:`noisy_orbit` and :func:`orbit_filter`, m^2/s^3: a white
#: acceleration of 1 m/s^2 per sqrt(Hz), far above any orbit-model error; beyond, the filter's covariance
#: and the simulated noise leave float64 over long spans.
MAX_ACCEL_PSD_M2_S3 = 1.0
#: Largest entry of ``p0`` in :func:`orbit_filter`, m^2 and m^2/s^2: (1e8 m)^2, an initial position
#: uncertainty beyond the Moon's distance; larger ones overflow the innovation covariance.
MAX_P0 = 1e16
#: Largest initial radius ``|x0[:3]|``, m (beyond the Moon's distance the GLONASS model is meaningless).
MAX_ORBIT_RADIUS_M = 1e9

__all__ = [
    "MAX_ACCEL_PSD_M2_S3",
    "MAX_ORBIT_RADIUS_M",
    "MAX_P0",
    "OrbitFilterResult",
    "ReceiverFixes",
    "noisy_orbit",
    "orbit_filter",
    "receiver_fix",
    "white_acceleration_noise",
]


def white_acceleration_noise(accel_psd_m2_s3: float, dt_s: float) -> NDArray[np.float64]:
    """(6, 6) covariance over ``dt_s`` of white acceleration noise on a free particle:
    ``q [[dt^3/3 I, dt^2/2 I], [dt^2/2 I, dt I]]``.

    Parameters
    ----------
    accel_psd_m2_s3
        q, the power spectral density of the acceleration per axis, m^2/s^3, >= 0.
    dt_s
        The interval, s, >= 0.

    Returns
    -------
    numpy.ndarray
        (6, 6) covariance of ``(position, velocity)``, m^2, m^2/s and m^2/s^2.

    Raises
    ------
    InvalidInputError
        A negative, non-finite or non-real argument.
    ConvergenceError
        The covariance overflows (``q dt^3`` beyond float64).

    Examples
    --------
    >>> from gnssatt.orbit.determination import white_acceleration_noise
    >>> import numpy as np
    >>> q = white_acceleration_noise(3e-8, 10.0)
    >>> bool(np.allclose([q[0, 0], q[0, 3], q[3, 3]], [3e-8 * 1e3 / 3, 3e-8 * 1e2 / 2, 3e-8 * 10.0]))
    True
    """
    q = scalar("accel_psd_m2_s3", accel_psd_m2_s3, minimum=0.0)
    dt = np.float64(scalar("dt_s", dt_s, minimum=0.0))  # numpy floats overflow to inf, reported below
    i3 = np.eye(3)
    with np.errstate(over="ignore", invalid="ignore"):  # an overflow is reported below, by name
        out = q * np.block([[dt**3 / 3 * i3, dt**2 / 2 * i3], [dt**2 / 2 * i3, dt * i3]])
    return finite_result("the process noise covariance", out, f"accel_psd_m2_s3 = {q}, dt_s = {dt}")


def _initial_state(x0: ArrayLike, model: GlonassModel) -> NDArray[np.float64]:
    """``x0`` as a (6,) bound orbit: radius in [MIN_ORBIT_RADIUS_FRACTION x the model's equatorial radius,
    MAX_ORBIT_RADIUS_M], speed at most two
    escape speeds plus the axes' rotation (the bound of :func:`gnssatt.orbit.glonass_propagate`)."""
    x = float_array("x0", x0, ndim=1, shape="(6,)")
    if x.shape != (6,):
        raise InvalidInputError(f"expected x0 of shape (6,), got {x.shape}")
    with np.errstate(over="ignore"):
        r = float(np.linalg.norm(x[:3]))
        v = float(np.linalg.norm(x[3:]))
    r_min = MIN_ORBIT_RADIUS_FRACTION * model.equatorial_radius_m
    if not r_min <= r <= MAX_ORBIT_RADIUS_M:
        raise InvalidInputError(
            f"expected x0[:3] between {r_min:.6g} and {MAX_ORBIT_RADIUS_M:g} m from the Earth's "
            f"centre, got |x0[:3]| = {r:.6g} m"
        )
    v_max = 2.0 * np.sqrt(2.0 * abs(model.gm_m3_s2) / r) + abs(model.omega_rad_s) * r
    if not v <= v_max:
        raise InvalidInputError(
            f"expected x0[3:] a bound orbit's velocity, at most {v_max:.6g} m/s (two escape speeds plus the "
            f"axes' rotation) at |x0[:3]| = {r:.6g} m, got |x0[3:]| = {v:.6g} m/s"
        )
    return x


def _accel_psd(value: float) -> float:
    return scalar("accel_psd_m2_s3", value, minimum=0.0, maximum=MAX_ACCEL_PSD_M2_S3, unit="m^2/s^3")


def noisy_orbit(
    x0: ArrayLike,
    times_s: ArrayLike,
    rng: int | np.random.Generator | None = None,
    *,
    accel_psd_m2_s3: float,
    step_s: float = 10.0,
    model: GlonassModel | None = None,
) -> NDArray[np.float64]:
    """A true trajectory for simulations: the ICD model between epochs plus the state noise of white
    acceleration (:func:`white_acceleration_noise`, the free-particle part of what the filter's Van Loan
    discretisation gives; the gravity-gradient correction is ``(n dt)^2 ~ 1e-4`` of it for 10 s in LEO).

    Parameters
    ----------
    x0
        (6,) initial state ``(r, v)``, ECEF, m and m/s, at ``times_s[0]``: a bound orbit.
    times_s
        (n_t,) epochs, s, strictly increasing, at least one.
    rng
        Draws the noise: an int, a Generator (advanced) or None (fresh entropy), as
        ``numpy.random.default_rng`` reads it.
    accel_psd_m2_s3
        Power spectral density of the white acceleration per axis, m^2/s^3 (0: the model's trajectory).
    step_s
        Longest RK4 step, s (default 10).
    model
        Propagation model (default: ICD PZ-90 constants, J2, no luni-solar term).

    Returns
    -------
    numpy.ndarray
        (n_t, 6) states at ``times_s``; the first is ``x0``.

    Raises
    ------
    InvalidInputError
        Bad shapes, types or values; times not strictly increasing; ``step_s`` <= 0; ``x0`` not a bound
        orbit (radius outside [``MIN_ORBIT_RADIUS_FRACTION`` of the model's equatorial radius,
        :data:`MAX_ORBIT_RADIUS_M`], speed above two escape speeds plus the axes' rotation);
        ``accel_psd_m2_s3`` above :data:`MAX_ACCEL_PSD_M2_S3`.
    WorkLimitError
        More than ``MAX_EPOCHS`` (1e6) epochs, or more than :data:`gnssatt.orbit.MAX_RK4_STEPS` (1e7) RK4
        steps over the whole span (checked before any work).
    ConvergenceError
        The propagation or the noise covariance overflowed.

    Examples
    --------
    >>> import numpy as np
    >>> from gnssatt.orbit.determination import noisy_orbit
    >>> x0 = np.array([7.0e6, 0.0, 0.0, 0.0, 7.5e3, 0.0])
    >>> truth = noisy_orbit(x0, np.arange(0.0, 60.0, 10.0), 1, accel_psd_m2_s3=1e-10)
    >>> truth.shape, bool(np.array_equal(truth[0], x0))
    ((6, 6), True)
    """
    if model is not None:
        instance("model", model, GlonassModel, "a GlonassModel")
    x = _initial_state(x0, model if model is not None else GlonassModel())
    t = float_array("times_s", times_s, ndim=1, shape="(n_t,)")
    if t.size == 0 or np.any(np.diff(t) <= 0):
        raise InvalidInputError("expected at least one epoch and strictly increasing times_s")
    if t.size > MAX_EPOCHS:
        raise WorkLimitError(f"noisy_orbit: times_s has {t.size} epochs, beyond the limit of {MAX_EPOCHS}")
    q = _accel_psd(accel_psd_m2_s3)
    step_s = scalar("step_s", step_s, minimum=0.0, strict=True)
    gen = generator("rng", rng)
    rk4_steps("noisy_orbit over times_s", np.diff(t), step_s)
    out = np.empty((t.size, 6))
    out[0] = x
    for k in range(1, t.size):
        dt = t[k] - t[k - 1]
        p = glonass_propagate(out[k - 1, :3], out[k - 1, 3:], dt, step_s=min(step_s, dt), model=model)
        out[k] = p.state + gen.multivariate_normal(np.zeros(6), white_acceleration_noise(q, dt))
    return out


@dataclass(frozen=True)
class ReceiverFixes:
    """The receiver's own single-epoch solutions.

    Attributes
    ----------
    times_s
        (n_t,) epochs.
    position_m, velocity_m_s
        (n_t, 3) ECEF fix (NaN where ``valid`` is false).
    covariance
        (n_t, 6, 6) covariance of ``(position, velocity)`` from the least-squares normal matrices (position
        and velocity solved apart: no cross-covariance).
    valid
        (n_t,) a fix exists (>= 3 + number of systems satellites for the position, >= 4 for the velocity).
    """

    times_s: NDArray[np.float64]
    position_m: NDArray[np.float64]
    velocity_m_s: NDArray[np.float64]
    covariance: NDArray[np.float64]
    valid: NDArray[np.bool_]

    def __post_init__(self) -> None:
        # Also an input of orbit_filter: shapes and types checked; values are finite where valid.
        t = float_array("times_s", self.times_s, ndim=1, shape="(n_t,)")
        n_t = t.size
        valid = np.asarray(self.valid)
        if valid.dtype != bool or valid.shape != (n_t,):
            raise InvalidInputError(
                f"expected valid as booleans of shape ({n_t},), got {valid.dtype} {valid.shape}"
            )
        for name, shape in (
            ("position_m", (n_t, 3)),
            ("velocity_m_s", (n_t, 3)),
            ("covariance", (n_t, 6, 6)),
        ):
            arr = real_array(name, getattr(self, name))
            if arr.shape != shape:
                raise InvalidInputError(f"expected {name} of shape {shape}, got {arr.shape}")
            if not np.all(np.isfinite(arr[valid])):
                raise InvalidInputError(f"{name} contains a non-finite value where valid")


def _fix_epoch(
    meas: SpaceborneMeasurements, k: int, start: NDArray[np.float64]
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]] | None:
    vis = meas.visible[k]
    systems = np.unique(meas.system[vis])
    n = int(vis.sum())
    if n < 3 + systems.size or n < 4:
        return None
    sp, sv = meas.sat_position_m[k, vis], meas.sat_velocity_m_s[k, vis]
    pr = meas.pseudorange_m[k, vis]
    cols = (meas.system[vis][:, None] == systems[None, :]).astype(float)  # one clock per system
    x = np.concatenate([start, np.zeros(systems.size)])
    for _ in range(10):
        d = sp - x[:3]
        rho = np.linalg.norm(d, axis=1)
        a = np.hstack([-d / rho[:, None], cols])
        dx = np.linalg.lstsq(a, pr - rho - cols @ x[3:], rcond=None)[0]
        x += dx
        if np.linalg.norm(dx[:3]) < 1e-4:
            break
    d = sp - x[:3]
    u = d / np.linalg.norm(d, axis=1)[:, None]
    cov_p = meas.code_sigma_m**2 * np.linalg.inv(a.T @ a)[:3, :3]
    # Range rates -lambda D = u . (v_sat - v) + c drift: linear in (v, c drift).
    lam = meas.wavelength_m[vis]
    rate = -lam * meas.doppler_hz[k, vis]
    b = np.hstack([-u, np.ones((n, 1))])
    w = 1.0 / (lam * meas.doppler_sigma_hz) ** 2
    nb = b.T @ (b * w[:, None])
    y = np.linalg.solve(nb, b.T @ (w * (rate - np.sum(u * sv, axis=1))))
    cov = np.zeros((6, 6))
    cov[:3, :3] = cov_p
    cov[3:, 3:] = np.linalg.inv(nb)[:3, :3]
    return x[:3], y[:3], cov


def receiver_fix(measurements: SpaceborneMeasurements) -> ReceiverFixes:
    """Single-epoch least-squares fixes (Gauss-Newton for position + one clock per system, linear least
    squares for velocity + clock drift from Doppler); none where too few satellites are tracked, or where
    the satellites' geometry does not fix the solution (e.g. all in one line).

    Parameters
    ----------
    measurements
        Pseudoranges and Doppler of every epoch (:func:`gnssatt.sim.simulate_spaceborne` or the same layout
        from a real receiver).

    Returns
    -------
    ReceiverFixes
        Position, velocity and their covariance per epoch, ``valid`` where a fix exists.

    Raises
    ------
    InvalidInputError
        ``measurements`` is not :class:`~gnssatt.sim.SpaceborneMeasurements` (an
        :class:`~gnssatt.errors.InvalidTypeError`).

    Examples
    --------
    Six epochs of a 500 km orbit tracking the nominal GPS constellation fix within a few metres:

    >>> import numpy as np
    >>> from gnssatt import sim
    >>> leo = sim.OrbitalReceiver(altitude_m=500e3, inclination_deg=97.0)
    >>> t = np.arange(0.0, 60.0, 10.0)
    >>> r, v = leo.state_ecef(t)
    >>> meas = sim.simulate_spaceborne(r, v, t, sim.gps_nominal(), np.random.default_rng(1))
    >>> from gnssatt.orbit.determination import receiver_fix
    >>> fix = receiver_fix(meas)
    >>> bool(fix.valid.all()), bool(np.linalg.norm(fix.position_m - r, axis=1).max() < 10.0)
    (True, True)
    """
    m = instance("measurements", measurements, SpaceborneMeasurements, "SpaceborneMeasurements")
    n_t = m.times_s.size
    pos = np.full((n_t, 3), np.nan)
    vel = np.full((n_t, 3), np.nan)
    cov = np.full((n_t, 6, 6), np.nan)
    valid = np.zeros(n_t, dtype=bool)
    start = np.zeros(3)
    for k in range(n_t):
        try:
            fix = _fix_epoch(m, k, start)
        except np.linalg.LinAlgError:  # the satellites' geometry fixes no solution at this epoch
            fix = None
        if fix is not None and all(np.all(np.isfinite(f)) for f in fix):
            pos[k], vel[k], cov[k] = fix
            valid[k] = True
            start = pos[k]
    return ReceiverFixes(m.times_s, pos, vel, cov, valid)


@dataclass(frozen=True)
class OrbitFilterResult:
    """Filter output after each epoch's update.

    Attributes
    ----------
    times_s
        (n_t,) epochs.
    states
        (n_t, 6) estimates ``(r, v)``, ECEF, m and m/s.
    covariances
        (n_t, 6, 6) their covariances.
    nis
        (n_t,) normalised innovation squared of the epoch's update (NaN where no update).
    nis_dof
        (n_t,) its degrees of freedom (number of scalar measurements; 0 where no update).
    coupling
        ``"loose"`` or ``"tight"``.
    """

    times_s: NDArray[np.float64]
    states: NDArray[np.float64]
    covariances: NDArray[np.float64]
    nis: NDArray[np.float64]
    nis_dof: NDArray[np.int64]
    coupling: str

    def nees(self, truth: ArrayLike) -> NDArray[np.float64]:
        """(n_t,) normalised estimation error squared ``e^T P^-1 e`` against true states (n_t, 6).

        Raises
        ------
        InvalidInputError
            ``truth`` of the wrong shape, non-finite or non-real.
        """
        x = float_array("truth", truth, ndim=2, shape="(n_t, 6)")
        if x.shape != self.states.shape:
            raise InvalidInputError(f"expected truth of shape {self.states.shape}, got {x.shape}")
        e = self.states - x
        with np.errstate(over="ignore", invalid="ignore"):  # an overflow is reported below, by name
            out = np.einsum("ki,ki->k", e, np.linalg.solve(self.covariances, e[..., None])[..., 0])
        return finite_result("the NEES", out, "truth is too far from the estimates for float64")

    def sigma(self) -> NDArray[np.float64]:
        """(n_t, 6) standard deviations of the state."""
        sigma: NDArray[np.float64] = np.sqrt(np.einsum("kii->ki", self.covariances))  # einsum is typed Any
        return sigma


def orbit_filter(
    data: SpaceborneMeasurements | ReceiverFixes,
    x0: ArrayLike,
    p0: ArrayLike,
    *,
    coupling: str = "tight",
    accel_psd_m2_s3: float = 1e-8,
    step_s: float = 10.0,
    use_doppler: bool = True,
    model: GlonassModel | None = None,
) -> OrbitFilterResult:
    """Run the orbit-determination Kalman filter (Rust inner loop) over all epochs.

    Parameters
    ----------
    data
        Pseudoranges and Doppler (:func:`gnssatt.sim.simulate_spaceborne` or the same layout from a real
        receiver), or precomputed fixes (:func:`receiver_fix`, loosely coupled only). With measurements
        and ``coupling="loose"`` the fixes are computed here.
    x0, p0
        (6,) initial state at ``times_s[0]`` and its (6, 6) covariance.
    coupling
        ``"tight"``: first differences, between tracked satellites of the same system, of pseudoranges and
        of range rates ``-lambda_j D_j`` (the receiver clock bias, drift and inter-system bias cancel; the
        differences' noise covariance ``D R D^T`` has the shared reference satellite's variance off the
        diagonal). Updates need two tracked satellites of one system. ``"loose"``: the fixes with their
        covariance; needs a fix.
    accel_psd_m2_s3
        Power spectral density of the white acceleration process noise per axis, m^2/s^3.
    step_s
        Longest RK4 step of the prediction, s.
    use_doppler
        Tightly coupled: include the Doppler differences.
    model
        Prediction model (default: ICD PZ-90 constants, J2, no luni-solar term).

    Returns
    -------
    OrbitFilterResult
        The state and covariance after each epoch's update, with its normalised innovation squared.

    Raises
    ------
    InvalidInputError
        Bad shapes or values, non-finite tracked measurements, non-increasing times, or no usable
        measurement in any epoch; ``x0`` not a bound orbit (as :func:`noisy_orbit`); ``p0`` not symmetric
        positive semi-definite or with an entry above :data:`MAX_P0`; ``accel_psd_m2_s3`` above
        :data:`MAX_ACCEL_PSD_M2_S3`.
    WorkLimitError
        More than :data:`gnssatt.orbit.MAX_RK4_STEPS` (1e7) prediction steps over the whole span (checked
        before any work).

    Examples
    --------
    Started 75 m and 0.7 m/s off the truth, the tightly coupled filter is within 10 m after the first epoch:

    >>> import numpy as np
    >>> from gnssatt import sim
    >>> leo = sim.OrbitalReceiver(altitude_m=500e3, inclination_deg=97.0)
    >>> t = np.arange(0.0, 60.0, 10.0)
    >>> r, v = leo.state_ecef(t)
    >>> meas = sim.simulate_spaceborne(r, v, t, sim.gps_nominal(), np.random.default_rng(1))
    >>> from gnssatt.orbit.determination import orbit_filter
    >>> x0 = np.concatenate([r[0], v[0]]) + [50.0, -50.0, 30.0, 0.5, -0.5, 0.2]
    >>> res = orbit_filter(meas, x0, np.diag([1e4, 1e4, 1e4, 1.0, 1.0, 1.0]))
    >>> res.coupling, bool(np.linalg.norm(res.states[:, :3] - r, axis=1).max() < 10.0)
    ('tight', True)
    """
    m = instance("model", model if model is not None else GlonassModel(), GlonassModel, "a GlonassModel")
    x = _initial_state(x0, m)
    p = _initial_covariance(p0)
    psd = _accel_psd(accel_psd_m2_s3)
    h = scalar("step_s", step_s, minimum=0.0, strict=True)
    _check_coupling(coupling, use_doppler)
    fixes = _loose_fixes(data, coupling, h)
    if fixes is not None:
        return _filter_result(fixes.times_s, _loose_filter(fixes, x, p, m, psd, h), coupling)
    assert isinstance(data, SpaceborneMeasurements)
    return _filter_result(data.times_s, _tight_filter(data, x, p, m, psd, h, use_doppler), coupling)


def _filter_result(t: ArrayLike, out: _core.OrbitFilterRun, coupling: str) -> OrbitFilterResult:
    states, covs, nis, dof = out.states, out.covariances, out.nis, out.dof
    return OrbitFilterResult(np.asarray(t), states, covs, nis, dof.astype(np.int64), coupling)


def _initial_covariance(p0: ArrayLike) -> NDArray[np.float64]:
    """The (6, 6) initial covariance of :func:`orbit_filter`: bounded, symmetric, positive semi-definite."""
    p = float_array("p0", p0, ndim=2, shape="(6, 6)")
    if p.shape != (6, 6):
        raise InvalidInputError(f"expected p0 of shape (6, 6), got {p.shape}")
    if np.max(np.abs(p)) > MAX_P0:
        raise InvalidInputError(
            f"expected p0 entries at most MAX_P0 = {MAX_P0:g} in magnitude, got {np.max(np.abs(p)):.6g}"
        )
    if np.max(np.abs(p - p.T)) > 1e-9 * np.max(np.abs(p)):
        raise InvalidInputError(f"expected p0 symmetric, got an asymmetry of {np.max(np.abs(p - p.T)):.3e}")
    smallest = float(np.linalg.eigvalsh(p)[0])
    if smallest < -1e-9 * np.max(np.abs(p)):
        raise InvalidInputError(f"expected p0 positive semi-definite, got an eigenvalue of {smallest:.3e}")
    return p


def _check_coupling(coupling: str, use_doppler: bool) -> None:
    text("coupling", coupling)
    if coupling not in ("loose", "tight"):
        raise InvalidInputError(f"expected coupling 'loose' or 'tight', got {coupling!r}")
    if not isinstance(use_doppler, bool | np.bool_):
        raise InvalidTypeError(f"expected use_doppler as a bool, got {type(use_doppler).__name__}")


def _loose_fixes(
    data: SpaceborneMeasurements | ReceiverFixes, coupling: str, step_s: float
) -> ReceiverFixes | None:
    """The receiver fixes the loosely coupled filter takes (given, or made from the measurements), None for
    the tightly coupled one; the data's epochs checked against the work limit of RK4 steps."""
    instance("data", data, SpaceborneMeasurements | ReceiverFixes, "SpaceborneMeasurements or ReceiverFixes")
    t_all = float_array("data.times_s", data.times_s, ndim=1, shape="(n_t,)")
    rk4_steps("orbit_filter over data.times_s", np.diff(t_all), step_s)
    if isinstance(data, ReceiverFixes):
        if coupling != "loose":
            raise InvalidInputError("receiver fixes can only drive the loosely coupled filter")
        return data
    return receiver_fix(data) if coupling == "loose" else None


def _loose_filter(
    fixes: ReceiverFixes,
    x: NDArray[np.float64],
    p: NDArray[np.float64],
    m: GlonassModel,
    psd: float,
    h: float,
) -> _core.OrbitFilterRun:
    """The core's loosely coupled filter over ``fixes``."""
    return _core.orbit_filter_loose(
        fixes.times_s,
        x,
        p,
        np.ascontiguousarray(fixes.position_m),
        np.ascontiguousarray(fixes.velocity_m_s),
        np.ascontiguousarray(fixes.covariance),
        np.ascontiguousarray(fixes.valid, dtype=bool),
        model=m._kwargs(),
        accel_psd_m2_s3=psd,
        step_s=h,
    )


def _tight_filter(
    d: SpaceborneMeasurements, x: NDArray[np.float64], p: NDArray[np.float64], m: GlonassModel, psd: float,
    h: float, use_doppler: bool,
) -> _core.OrbitFilterRun:  # fmt: skip
    """The core's tightly coupled filter over the measurements ``d`` (Dopplers unweighted without
    ``use_doppler``)."""
    return _core.orbit_filter_tight(
        d.times_s,
        x,
        p,
        np.ascontiguousarray(d.sat_position_m),
        np.ascontiguousarray(d.sat_velocity_m_s),
        np.ascontiguousarray(d.pseudorange_m),
        np.ascontiguousarray(d.doppler_hz),
        np.ascontiguousarray(d.visible, dtype=bool),
        np.ascontiguousarray(d.wavelength_m),
        np.ascontiguousarray(d.system, dtype=np.uint32),
        code_sigma_m=float(d.code_sigma_m),
        doppler_sigma_hz=float(d.doppler_sigma_hz) if use_doppler else 0.0,
        model=m._kwargs(),
        accel_psd_m2_s3=psd,
        step_s=h,
    )
