"""Scenario of the gyro + multi-antenna GNSS filter (Dzhepe Ali): true angular motion, gyro output,
carrier-phase first differences between the master and slave antennas, and the receiver's own attitude
solutions.

Conventions (``docs/conventions.md``, "Gyro + GNSS filter"):

- Attitude is a scipy ``Rotation`` body -> ECI; the body rate ``omega`` is relative to ECI, body axes, rad/s.
- Motion: orbital-frame hold plus small oscillations,
  ``R_eci_from_body(t) = R_eci_from_orbital(t) exp([a(t) x])`` with ``a_j(t) = A_j sin(2 pi t / T_j + p_j)``.
  Then ``omega = exp(-[a x]) (0, n, 0) + J_r(a) da/dt``, with ``J_r`` the right Jacobian of SO(3) and ``n``
  the orbital rate (the orbital frame turns about its y axis).
- Gyro: ``omega_meas[k] = C mean_rate[k] - drift[k] - w[k]`` where ``mean_rate[k]`` is the constant rate that
  takes ``R(t_k)`` to ``R(t_{k+1})`` (an integrating gyro's angle increment over the interval divided by it),
  ``C = exp(-[mu x])`` the misalignment of the gyro triad (body -> gyro axes), ``w[k] ~ N(0, arw^2 / dt)``,
  ``drift[k+1] = drift[k] + N(0, rrw^2 dt)``.
- Phase first difference of slave antenna ``i`` minus the master for satellite ``k``, cycles:
  ``-los_k . (R (b_i + db_i)) / lambda_k + N_ik + e``: one receiver, one oscillator for every antenna, so no
  oscillator or clock term; ``db_i`` optional baseline errors (truth only).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, cast

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.spatial.transform import Rotation

from gnssatt._arrays import (
    MAX_BATCH_ROWS,
    batch_limit,
    finite_result,
    float_array,
    generator,
    instance,
    integer,
    scalar,
    vector_array,
)
from gnssatt._arrays import rows as _rows
from gnssatt.errors import DegenerateGeometryError, InvalidInputError
from gnssatt.geometry import MAX_BASELINES
from gnssatt.observations import AttitudeFixes, PhaseObservations
from gnssatt.orbit.constellation import Constellation
from gnssatt.orbit.masks import earth_occlusion_mask
from gnssatt.orbit.receivers import OrbitalReceiver

__all__ = [
    "AttitudeFixes",
    "GyroOutput",
    "PhaseObservations",
    "attitude_fixes",
    "gyro_output",
    "orbital_hold_motion",
    "phase_observations",
    "right_jacobian",
]

#: Longest baseline accepted, m (antenna arrays span metres; 1e7 m keeps every product finite).
MAX_BASELINE_M = 1.0e7
#: Phase noise standard deviations accepted by :func:`attitude_fixes`, cycles: from far below any
#: receiver's noise to far above a wrapped phase's range (keeps ``sigma^2`` and its inverse finite).
SIGMA_RANGE_CYCLES = (1e-12, 1e3)
#: Largest rotation-vector norm and oscillation amplitude accepted, rad: beyond 1e12 rad an angle has no
#: significant digits left modulo 2 pi.
MAX_ANGLE_RAD = 1.0e12


def _skew(v: NDArray[np.float64]) -> NDArray[np.float64]:
    z = np.zeros(v.shape[:-1])
    x, y, w = v[..., 0], v[..., 1], v[..., 2]
    return np.stack([np.stack([z, -w, y], -1), np.stack([w, z, -x], -1), np.stack([-y, x, z], -1)], -2)


def right_jacobian(a: ArrayLike) -> NDArray[np.float64]:
    """Right Jacobian of SO(3), (..., 3, 3): ``exp(-[a x]) d/dt exp([a x]) = [(J_r(a) da/dt) x]``.

    Raises
    ------
    InvalidInputError
        ``a`` not of shape (..., 3) with finite components within +-``MAX_ANGLE_RAD``
        (:class:`~gnssatt.errors.WorkLimitError` for more than :data:`gnssatt._arrays.MAX_BATCH_ROWS`
        rotation vectors, refused before they are copied).
    """
    batch_limit(MAX_BATCH_ROWS, "MAX_BATCH_ROWS", "rotation vectors", a=(a, 1))
    v = vector_array("a", a, ndim=(1, 2, 3), shape="(..., 3)")
    if v.size and np.max(np.abs(v)) > MAX_ANGLE_RAD:
        raise InvalidInputError(
            f"expected a with components within +-{MAX_ANGLE_RAD} rad, got {np.max(np.abs(v))}"
        )
    th = np.linalg.norm(v, axis=-1)[..., None, None]
    k = _skew(v)
    small = th < 1e-6
    ths = np.where(small, 1.0, th)
    c1 = np.where(small, 0.5 - th**2 / 24.0, (1.0 - np.cos(ths)) / ths**2)
    c2 = np.where(small, 1.0 / 6.0 - th**2 / 120.0, (ths - np.sin(ths)) / ths**3)
    jac: NDArray[np.float64] = np.eye(3) - c1 * k + c2 * (k @ k)  # numpy types np.where's result as Any
    return jac


def orbital_hold_motion(
    receiver: OrbitalReceiver,
    t: ArrayLike,
    amplitude_rad: ArrayLike = (0.0, 0.0, 0.0),
    period_s: ArrayLike = (300.0, 300.0, 300.0),
    phase_rad: ArrayLike = (0.0, 0.0, 0.0),
) -> tuple[Rotation, NDArray[np.float64]]:
    """True attitude (body -> ECI) and body rate (rad/s, body axes) at ``t`` for the orbital-frame hold of
    ``receiver``'s circular orbit plus oscillations ``a_j = A_j sin(2 pi t / T_j + p_j)`` about body axes.

    Raises
    ------
    InvalidInputError
        Wrong shapes or non-finite values; ``period_s`` below 1e-3 s; ``amplitude_rad`` beyond +-pi
        (:class:`~gnssatt.errors.InvalidTypeError` for values of the wrong kind).
    WorkLimitError
        More than :data:`gnssatt._arrays.MAX_BATCH_ROWS` times, refused before they are copied.
    ConvergenceError
        A non-finite body rate.
    """
    instance("receiver", receiver, OrbitalReceiver, "a gnssatt.sim OrbitalReceiver")
    batch_limit(MAX_BATCH_ROWS, "MAX_BATCH_ROWS", "times", t=(t, 0))
    tt = float_array("t", t, ndim=1, shape="(n_t,)")
    amp = float_array("amplitude_rad", amplitude_rad, ndim=1, shape="(3,)")
    per = float_array("period_s", period_s, ndim=1, shape="(3,)")
    ph = float_array("phase_rad", phase_rad, ndim=1, shape="(3,)")
    if amp.shape != (3,) or per.shape != (3,) or ph.shape != (3,) or np.any(per <= 0):
        raise InvalidInputError("expected amplitude_rad, period_s (> 0) and phase_rad of shape (3,)")
    if np.max(np.abs(amp)) > np.pi:
        raise InvalidInputError(
            f"expected amplitude_rad within +-pi (an oscillation of the attitude), got {amp}"
        )
    if np.min(per) < 1e-3:
        raise InvalidInputError(
            f"expected period_s of at least 1e-3 s (an attitude oscillation, not a vibration), got {per}"
        )
    w = 2.0 * np.pi / per
    a = amp * np.sin(w * tt[:, None] + ph)
    a_dot = amp * w * np.cos(w * tt[:, None] + ph)
    osc = Rotation.from_rotvec(a)
    orbital = Rotation.from_matrix(receiver.dcm_eci_from_orbital(tt))
    omega_orb = np.array([0.0, receiver.mean_motion_rad_s, 0.0])
    rate = osc.inv().apply(omega_orb) + np.einsum("kij,kj->ki", right_jacobian(a), a_dot)
    finite_result("the body rate", rate, f"amplitude_rad {amp} over period_s {per}")
    return orbital * osc, rate


@dataclass(frozen=True)
class GyroOutput:
    """Gyro samples: ``rates[k]`` (gyro axes, rad/s) holds over ``[t[k], t[k+1]]``; ``drift`` the truth."""

    t: NDArray[np.float64]
    rates: NDArray[np.float64]
    drift: NDArray[np.float64]

    def __post_init__(self) -> None:
        n = _rows("t", self.t, ())
        _rows("rates", self.rates, (n, 3))
        _rows("drift", self.drift, (n, 3))


def gyro_output(
    t: ArrayLike,
    attitude: Rotation,
    rng: int | np.random.Generator | None = None,
    *,
    drift_rad_s: ArrayLike,
    arw: float,
    rrw: float = 0.0,
    misalignment_rad: ArrayLike = (0.0, 0.0, 0.0),
) -> GyroOutput:
    """Gyro output for the true attitude ``attitude`` (body -> ECI) at the sample times ``t``.

    ``drift_rad_s`` is the initial drift (3,), ``arw`` the angle random walk (rad/s/sqrt(Hz)), ``rrw`` the
    drift random walk (rad/s^2/sqrt(Hz)), ``misalignment_rad`` the rotation vector ``mu`` of the gyro triad.
    The last sample repeats the previous rate (it holds over no interval).

    Raises
    ------
    InvalidInputError
        Bad shapes, types or values (fewer than 2 or non-increasing time stamps, negative noise levels).
    ConvergenceError
        Time stamps so close, or noise levels so large, that the rates overflow.
    """
    tt = float_array("t", t, ndim=1, shape="(n_t,)")
    if len(tt) < 2 or np.any(np.diff(tt) <= 0):
        raise InvalidInputError("expected at least 2 strictly increasing gyro time stamps t")
    _per_epoch("attitude", attitude, len(tt))
    rng = generator("rng", rng)
    arw = scalar("arw", arw, minimum=0.0)
    rrw = scalar("rrw", rrw, minimum=0.0)
    b0 = vector_array("drift_rad_s", drift_rad_s, ndim=1, shape="(3,)")
    mu = vector_array("misalignment_rad", misalignment_rad, ndim=1, shape="(3,)")
    dt = np.diff(tt)
    mean_rate = (attitude[:-1].inv() * attitude[1:]).as_rotvec() / dt[:, None]
    mean_rate = np.vstack([mean_rate, mean_rate[-1:]])
    dt = np.append(dt, dt[-1])
    steps = rng.standard_normal((len(tt), 3)) * rrw * np.sqrt(dt)[:, None]
    drift = b0 + np.vstack([np.zeros((1, 3)), np.cumsum(steps[:-1], axis=0)])
    with np.errstate(over="ignore", invalid="ignore"):  # an overflow is reported below, by name
        noise = rng.standard_normal((len(tt), 3)) * arw / np.sqrt(dt)[:, None]
        measured = Rotation.from_rotvec(-mu).apply(mean_rate) - drift - noise
    cause = f"time steps down to {dt.min()} s with arw = {arw}, rrw = {rrw}"
    return GyroOutput(
        tt, finite_result("the gyro output", measured, cause), finite_result("the drift", drift, cause)
    )


def _baselines(value: ArrayLike) -> NDArray[np.float64]:
    # counted from the shape before the copy: 10^7 rows of baselines took over 10 s to be scanned
    batch_limit(MAX_BASELINES, "MAX_BASELINES", "baselines", baselines_m=(value, 1))
    b = vector_array("baselines_m", value, ndim=2, shape="(m, 3)", nonzero=True)
    norm = np.linalg.norm(b, axis=1)
    if len(b) == 0 or norm.max() > MAX_BASELINE_M:
        raise InvalidInputError(
            f"expected baselines_m of shape (m >= 1, 3), each at most {MAX_BASELINE_M} m, got shape {b.shape}"
            + (f", longest {norm.max()} m" if len(b) else "")
        )
    return b


def _per_epoch(name: str, attitude: Any, n: int) -> Rotation:
    instance(name, attitude, Rotation, "a scipy Rotation")
    if attitude.single or len(attitude) != n:
        got = "a single rotation" if attitude.single else f"{len(attitude)} rotations"
        raise InvalidInputError(f"expected {name} as {n} rotations (one per epoch), got {got}")
    return attitude


def _visible(
    receiver: OrbitalReceiver,
    gnss: Constellation,
    t: NDArray[np.float64],
    attitude: Rotation,
    half_angle_deg: float,
    atmosphere_m: float,
) -> tuple[NDArray[np.float64], NDArray[np.bool_]]:
    r_r, _ = receiver.state_eci(t)
    r_s, _ = gnss.state_eci(t)
    d = r_s - r_r[:, None, :]
    los = d / np.linalg.norm(d, axis=-1, keepdims=True)
    boresight = attitude.apply([0.0, 0.0, 1.0])
    up = np.einsum("kj,kij->ki", boresight, los) >= np.cos(np.radians(half_angle_deg))
    return los, up & earth_occlusion_mask(r_r, r_s, atmosphere_m=atmosphere_m)


def phase_observations(
    receiver: OrbitalReceiver,
    gnss: Constellation,
    t: ArrayLike,
    attitude: Rotation,
    baselines_m: ArrayLike,
    rng: int | np.random.Generator | None = None,
    *,
    phase_sigma_cycles: float,
    baseline_errors_m: ArrayLike | None = None,
    half_angle_deg: float = 80.0,
    atmosphere_m: float = 100e3,
    max_satellites: int | None = None,
    new_arcs_after: ArrayLike = (),
    slips: ArrayLike = (),
) -> PhaseObservations:
    """Simulated first differences at epochs ``t`` for the true attitude ``attitude`` (body -> ECI, one per
    epoch) of an array whose antenna boresight is body +z (cone of ``half_angle_deg``), Earth occlusion with
    ``atmosphere_m`` of grazing layer. ``max_satellites`` keeps the satellites of lowest index among those
    visible. Every satellite starts a new arc (new track id, new random integers) after each time in
    ``new_arcs_after`` (e.g. the end of a phase outage). ``slips`` rows ``(time, satellite index, cycles)``
    add a jump to every baseline of that satellite from that time on, keeping the track id.

    Raises
    ------
    InvalidInputError
        Bad types, shapes or values: ``half_angle_deg`` outside (0, 180], negative ``atmosphere_m`` or
        ``phase_sigma_cycles``, ``phase_sigma_cycles`` above 1e3 (``SIGMA_RANGE_CYCLES``),
        ``max_satellites`` < 0, ``slips`` not ``(time, satellite index in range,
        integer cycles)`` rows.
    WorkLimitError
        More than :data:`gnssatt.geometry.MAX_BASELINES` rows of ``baselines_m``, refused before the copy.
    """
    instance("receiver", receiver, OrbitalReceiver, "a gnssatt.sim OrbitalReceiver")
    instance("gnss", gnss, Constellation, "a gnssatt.sim Constellation")
    tt = float_array("t", t, ndim=1, shape="(n_e,)")
    _per_epoch("attitude", attitude, len(tt))
    rng = generator("rng", rng)
    b = _baselines(baselines_m)
    db = (
        np.zeros_like(b)
        if baseline_errors_m is None
        else float_array("baseline_errors_m", baseline_errors_m, ndim=2, shape="(m, 3)")
    )
    if db.shape != b.shape:
        raise InvalidInputError(f"expected baseline_errors_m of shape {b.shape}, got {db.shape}")
    sigma = scalar("phase_sigma_cycles", phase_sigma_cycles, minimum=0.0)
    # zero is valid here (noise-free phases); the upper bound keeps the noise finite, as in attitude_fixes
    sigma = scalar("phase_sigma_cycles", sigma, maximum=SIGMA_RANGE_CYCLES[1])
    half = scalar("half_angle_deg", half_angle_deg, minimum=0.0, strict=True, unit="deg")
    scalar("half_angle_deg", half, maximum=180.0, unit="deg")
    arcs_after = float_array("new_arcs_after", new_arcs_after, ndim=1, shape="(k,)")
    slip_rows = _slips(slips, len(gnss))
    los, vis = _visible(receiver, gnss, tt, attitude, half, atmosphere_m)
    if max_satellites is not None:
        vis &= np.cumsum(vis, axis=1) <= integer("max_satellites", max_satellites, minimum=0)
    lam = gnss.wavelengths_m("L1")
    arcs = np.searchsorted(np.sort(arcs_after), tt, side="left")
    k_idx, s_idx = np.nonzero(vis)
    arc = arcs[k_idx]
    track = s_idx * 1000 + arc
    uniq, inverse = np.unique(track, return_inverse=True)
    ints = rng.integers(-50, 51, size=(len(uniq), len(b)))
    amb = ints[inverse]
    for ts, sat, cycles in slip_rows:
        amb[(s_idx == int(sat)) & (tt[k_idx] >= ts)] += int(cycles)
    rows_los = los[k_idx, s_idx]
    los_body = attitude[k_idx].inv().apply(rows_los)
    geom = -(los_body @ (b + db).T) / lam[s_idx, None]
    phase = geom + amb + sigma * rng.standard_normal(geom.shape)
    return PhaseObservations(
        tt,
        k_idx.astype(np.int64),
        track.astype(np.int64),
        rows_los,
        lam[s_idx],
        phase,
        amb.astype(np.int64),
        s_idx.astype(np.int64),
    )


def _slips(slips: ArrayLike, n_sat: int) -> NDArray[np.float64]:
    """``slips`` as (k, 3) rows ``(time, satellite index, cycles)`` (a single row may be given flat)."""
    rows = float_array("slips", slips, ndim=(1, 2), shape="(k, 3)")
    if rows.size == 0:
        return np.zeros((0, 3))
    if rows.shape == (3,):
        rows = rows[None, :]
    if rows.ndim != 2 or rows.shape[1] != 3:
        raise InvalidInputError(f"expected slips of shape (k, 3), got {rows.shape}")
    sat, cycles = rows[:, 1], rows[:, 2]
    if np.any(sat != np.round(sat)) or sat.min() < 0 or sat.max() >= n_sat:
        raise InvalidInputError(
            f"expected slips' satellite indices as integers in [0, {n_sat}), got {sat.tolist()}"
        )
    if np.any(cycles != np.round(cycles)) or np.abs(cycles).max() > 2**31:
        raise InvalidInputError(f"expected slips' cycles as integers within +-2^31, got {cycles.tolist()}")
    return rows


def attitude_fixes(
    phases: PhaseObservations,
    attitude: Rotation,
    baselines_m: ArrayLike,
    rng: int | np.random.Generator | None = None,
    *,
    phase_sigma_cycles: float,
    min_satellites: int = 3,
) -> AttitudeFixes:
    """The receiver's own attitude solution at each epoch of ``phases`` with at least ``min_satellites``
    satellites, drawn from the least-squares error of the first differences with their integers resolved:
    covariance ``(sum_k,i H_ki^T H_ki / sigma^2)^-1``, ``H_ki = ((R^T los_k) x b_i)^T / lambda_k``. Three
    satellites is what a single-epoch solution (e.g. :func:`gnssatt.matrix_attitude`) needs.
    :func:`gnssatt.phase_attitude_fixes` solves the phases themselves instead.

    Raises
    ------
    InvalidInputError
        Bad types, shapes or values (``min_satellites`` < 1, ``phase_sigma_cycles`` <= 0).
    WorkLimitError
        More than :data:`gnssatt.geometry.MAX_BASELINES` rows of ``baselines_m``, refused before the copy.
    DegenerateGeometryError
        An epoch whose lines of sight and baselines do not fix all three attitude angles.
    """
    instance("phases", phases, PhaseObservations, "gnssatt.sim PhaseObservations")
    _per_epoch("attitude", attitude, len(phases.epoch_t))
    rng = generator("rng", rng)
    b = _baselines(baselines_m)
    sigma = scalar("phase_sigma_cycles", phase_sigma_cycles, minimum=0.0, strict=True)
    sigma = scalar("phase_sigma_cycles", sigma, minimum=SIGMA_RANGE_CYCLES[0], maximum=SIGMA_RANGE_CYCLES[1])
    count = phases.n_visible()
    keep = np.nonzero(count >= integer("min_satellites", min_satellites, minimum=1))[0]
    s_body = attitude[phases.epoch].inv().apply(phases.los)
    h = np.cross(s_body[:, None, :], b[None]) / phases.wavelength[:, None, None]  # (rows, m, 3)
    info = np.zeros((len(phases.epoch_t), 3, 3))  # per unit variance: cov = sigma^2 info^-1
    np.add.at(info, phases.epoch, np.einsum("rim,rin->rmn", h, h))
    try:
        np.linalg.cholesky(info[keep])
        # numpy types inv of a float64 array as floating[Any]; it is float64
        cov = cast(NDArray[np.float64], sigma**2 * np.linalg.inv(info[keep]))
        root = np.linalg.cholesky(cov)
    except np.linalg.LinAlgError as exc:
        bad = [int(k) for k in keep if np.linalg.matrix_rank(info[k]) < 3][:5]
        raise DegenerateGeometryError(
            f"the lines of sight and baselines_m do not fix the attitude at epochs {bad}; "
            f"raise min_satellites (now {min_satellites}) or add baselines"
        ) from exc
    eta = np.einsum("kij,kj->ki", root, rng.standard_normal((len(keep), 3)))
    return AttitudeFixes(phases.epoch_t[keep], attitude[keep] * Rotation.from_rotvec(eta), cov)
