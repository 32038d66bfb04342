"""Pseudoranges and Doppler of a GNSS receiver on a small satellite (Dzhepe Ali, orbit determination).

Conventions of :mod:`gnssatt.sim`; everything here is Earth-fixed (ECEF = ECI turned by
``theta0 + OMEGA_E t``), velocities relative to the rotating Earth. Measurement model of satellite j at
epoch k:

- pseudorange ``P = rho + c b_k + isb_j + e``, ``rho = |r_sat - r_rx|`` the instantaneous geometric range (no
  light time, Sagnac, ionosphere or satellite clock: the filter models ranges the same way), ``isb_j`` the
  GPS-GLONASS inter-system bias (0 for GPS, ``isb_m`` for GLONASS), ``e ~ N(0, code_sigma_m^2)``;
- Doppler (RINEX sign, positive while approaching) ``D = -(d rho / dt + c d_k) / lambda_j + n``, ``lambda_j``
  the satellite's own carrier wavelength (GLONASS FDMA: per channel), ``n ~ N(0, doppler_sigma_hz^2)``;
- receiver clock: bias ``b`` (s) and drift ``d`` (s/s) as a random walk pair, per step ``dt``:
  ``b += d dt + w_b``, ``d += w_d``, ``w_b ~ N(0, q_bias dt)``, ``w_d ~ N(0, q_drift dt)``;
- visibility: within ``half_angle_deg`` of a zenith-pointing antenna (the receiver's radial direction) and not
  hidden by the Earth (sphere plus ``atmosphere_m``); ``outages`` windows keep only the ``max_sats``
  satellites nearest the boresight (e.g. an attitude manoeuvre or a blocked antenna), down to none.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.spatial.transform import Rotation

from gnssatt._arrays import (
    finite_result,
    float_array,
    generator,
    instance,
    integer,
    scalar,
    vector_array,
)
from gnssatt.constants import SPEED_OF_LIGHT_M_S
from gnssatt.errors import InvalidInputError, WorkLimitError
from gnssatt.observations import SYSTEM_INDEX, SpaceborneMeasurements
from gnssatt.orbit.constellation import Constellation
from gnssatt.orbit.masks import antenna_cone_mask, earth_occlusion_mask

__all__ = ["SpaceborneMeasurements", "simulate_spaceborne"]

#: Most ``outages`` windows of :func:`simulate_spaceborne` (each is a Python loop over its epochs).
MAX_OUTAGES = 10_000


def _outages(outages: Sequence[tuple[float, float, int]]) -> list[tuple[float, float, int]]:
    windows = list(instance("outages", outages, (Sequence,), "a sequence of (t_start_s, t_end_s, max_sats)"))
    if len(windows) > MAX_OUTAGES:
        raise WorkLimitError(f"{len(windows)} outages windows exceed the limit of {MAX_OUTAGES}")
    out = []
    for k, window in enumerate(windows):
        if not isinstance(window, Sequence | np.ndarray) or len(window) != 3:
            raise InvalidInputError(
                f"expected outages[{k}] as (t_start_s, t_end_s, max_sats), got {window!r}"
            )
        name = f"outages[{k}]"
        t0, t1 = scalar(f"{name}[0]", window[0]), scalar(f"{name}[1]", window[1])
        out.append((t0, t1, integer(f"{name}[2]", window[2], minimum=0)))
    return out


def _zenith_attitudes(r: NDArray[np.float64], v: NDArray[np.float64]) -> Rotation:
    """Body -> ECEF rotations with body z along the radius and body x along the velocity's horizontal part."""
    z = r / np.linalg.norm(r, axis=-1, keepdims=True)
    x = v - np.sum(v * z, axis=-1, keepdims=True) * z
    # No horizontal velocity (a vertical or resting receiver): any horizontal x will do, as only the
    # boresight z decides the visibility.
    other = np.where(np.abs(z[..., :1]) < 0.9, [[1.0, 0.0, 0.0]], [[0.0, 1.0, 0.0]])
    flat = np.linalg.norm(x, axis=-1, keepdims=True) <= 1e-9 * np.linalg.norm(v, axis=-1, keepdims=True)
    x = np.where(flat, np.cross(z, other), x)
    x /= np.linalg.norm(x, axis=-1, keepdims=True)
    return Rotation.from_matrix(np.stack([x, np.cross(z, x), z], axis=-1))


def _checked_receiver(
    receiver_position_m: ArrayLike, receiver_velocity_m_s: ArrayLike, times_s: ArrayLike
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """The receiver's (n_t, 3) ECEF positions (m) and velocities (m/s) and its (n_t,) increasing times (s)."""
    r = vector_array("receiver_position_m", receiver_position_m, ndim=2, shape="(n_t, 3)", nonzero=True)
    v = vector_array("receiver_velocity_m_s", receiver_velocity_m_s, ndim=2, shape="(n_t, 3)")
    with np.errstate(over="ignore"):  # a norm beyond float64 is refused as out of range
        radius, speed = np.linalg.norm(r, axis=1), np.linalg.norm(v, axis=1)
    if r.size and (radius.min() < 1e5 or radius.max() > 1e12):
        raise InvalidInputError(
            f"expected receiver_position_m 1e5 to 1e12 m from the Earth's centre, got [{radius.min()}, "
            f"{radius.max()}] m"
        )
    if v.size and speed.max() > SPEED_OF_LIGHT_M_S:
        raise InvalidInputError(
            f"expected receiver_velocity_m_s below the speed of light, got {speed.max()} m/s"
        )
    t = float_array("times_s", times_s, ndim=1, shape="(n_t,)")
    if r.shape != (t.size, 3) or v.shape != r.shape:
        raise InvalidInputError(
            f"expected receiver_position_m and receiver_velocity_m_s of shape ({t.size}, 3) (one per epoch "
            f"of times_s), got {r.shape} and {v.shape}"
        )
    if t.size == 0 or np.any(np.diff(t) <= 0):
        raise InvalidInputError("expected at least one epoch and strictly increasing times_s")
    return r, v, t


def _visibility(
    los: NDArray[np.float64], r: NDArray[np.float64], v: NDArray[np.float64], sat_r: NDArray[np.float64],
    t: NDArray[np.float64], windows: list[tuple[float, float, int]], half_angle_deg: float,
    atmosphere_m: float,
) -> NDArray[np.bool_]:  # fmt: skip
    """(n_t, n_sat) satellites inside the zenith antenna's cone and not behind the Earth; in each outage
    window only the ``n_max`` nearest the boresight."""
    visible: NDArray[np.bool_] = antenna_cone_mask(
        los, _zenith_attitudes(r, v), (0.0, 0.0, 1.0), half_angle_deg
    )
    visible &= earth_occlusion_mask(r, sat_r, atmosphere_m=atmosphere_m)
    cos_boresight = np.sum(los * (r / np.linalg.norm(r, axis=-1, keepdims=True))[:, None, :], axis=-1)
    for t0, t1, n_max in windows:
        for i in np.flatnonzero((t >= t0) & (t <= t1)):
            order = np.argsort(-np.where(visible[i], cos_boresight[i], -np.inf), kind="stable")
            visible[i, order[n_max:]] = False
    return visible


def _receiver_clock(
    rng: np.random.Generator, t: NDArray[np.float64], clock_bias0_s: float, clock_drift0: float, q_b: float,
    q_d: float,
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:  # fmt: skip
    """The receiver clock's bias (s) and drift at each epoch: random walks from the initial values."""
    dt = np.diff(t, prepend=t[0])
    bias0, drift0 = scalar("clock_bias0_s", clock_bias0_s), scalar("clock_drift0", clock_drift0)
    noise = rng.standard_normal((t.size, 2))
    # The random walks b[k] = b[k-1] + d[k-1] dt[k] + w_b[k], d[k] = d[k-1] + w_d[k] as cumulative sums
    # (dt[0] = 0: the first epoch carries the initial values).
    drift = drift0 + np.cumsum(np.sqrt(q_d * dt) * noise[:, 1])
    bias = bias0 + np.cumsum(np.r_[0.0, drift[:-1]] * dt + np.sqrt(q_b * dt) * noise[:, 0])
    return bias, drift


def simulate_spaceborne(
    receiver_position_m: ArrayLike,
    receiver_velocity_m_s: ArrayLike,
    times_s: ArrayLike,
    constellation: Constellation,
    rng: int | np.random.Generator | None = None,
    *,
    theta0_rad: float = 0.0,
    half_angle_deg: float = 85.0,
    atmosphere_m: float = 50_000.0,
    code_sigma_m: float = 1.0,
    doppler_sigma_hz: float = 0.2,
    clock_bias0_s: float = 1e-4,
    clock_drift0: float = 1e-8,
    q_bias_s2_s: float = 1e-20,
    q_drift_1_s: float = 1e-20,
    isb_m: float = 20.0,
    outages: Sequence[tuple[float, float, int]] = (),
) -> SpaceborneMeasurements:
    """Simulate pseudoranges and Doppler of a zenith-pointing receiver along a given trajectory.

    Parameters
    ----------
    receiver_position_m, receiver_velocity_m_s
        (n_t, 3) true receiver states, ECEF (m, m/s relative to the Earth): positions 1e5 to 1e12 m from
        the centre, speeds below the speed of light.
    times_s
        (n_t,) strictly increasing epochs, s from the scenario epoch (the constellation's ``t``).
    constellation
        GNSS satellites (ids starting with ``G`` or ``R``).
    rng
        The only source of randomness (drawn: clock noise, code noise, Doppler noise):
        ``np.random.default_rng(rng)``, an int seed (reproducible), a ``numpy.random.Generator``
        (used and advanced) or None (fresh entropy).
    theta0_rad
        Earth rotation angle at ``t = 0``.
    half_angle_deg
        Antenna cone half-angle about the zenith, degrees.
    atmosphere_m
        Grazing height added to the Earth's radius for occlusion, m.
    code_sigma_m, doppler_sigma_hz
        White noise standard deviations (pseudorange m, Doppler Hz).
    clock_bias0_s, clock_drift0
        Receiver clock bias (s) and drift (s/s) at the first epoch.
    q_bias_s2_s, q_drift_1_s
        Random-walk intensities of bias (s^2/s) and drift (1/s).
    isb_m
        GLONASS minus GPS inter-system bias, m.
    outages
        ``(t_start_s, t_end_s, max_sats)`` windows (inclusive) that keep at most ``max_sats`` satellites;
        at most ``MAX_OUTAGES`` (10,000) windows.

    Returns
    -------
    SpaceborneMeasurements
        Per epoch and satellite: pseudoranges (m), Doppler (Hz), visibility, the satellites' ECEF states and
        wavelengths, with the true clock bias and drift and the noise levels used.

    Raises
    ------
    InvalidInputError
        Bad types, shapes or values (an :class:`~gnssatt.errors.InvalidTypeError` for wrong types), a
        receiver at the Earth's centre or at a satellite.
    ConvergenceError
        Finite but extreme noise levels or clock parameters overflowed a measurement.

    Examples
    --------
    Without clock random walk and with negligible code noise, a visible GPS pseudorange exceeds the geometric
    range by ``c dt``: ``c * 1e-4 s = 29979.246`` m at the first epoch, and 10 s of a 1e-8 drift later
    ``c * (1e-4 + 1e-7) = 30009.225`` m:

    >>> import numpy as np
    >>> from gnssatt.orbit import CircularOrbit
    >>> from gnssatt.orbit.constellation import gps_nominal
    >>> from gnssatt.sim.spaceborne import simulate_spaceborne
    >>> t = np.array([0.0, 10.0])  # s
    >>> r, v = CircularOrbit(6_878_137.0, np.radians(51.6), 0.0, 0.0).state_ecef(t)  # (2, 3) m, m/s
    >>> quiet = {"code_sigma_m": 1e-6, "q_bias_s2_s": 0.0, "q_drift_1_s": 0.0}
    >>> s = simulate_spaceborne(r, v, t, gps_nominal(), rng=1, clock_bias0_s=1e-4, clock_drift0=1e-8, **quiet)
    >>> rho = np.linalg.norm(s.sat_position_m - r[:, None, :], axis=-1)  # (2, 24) m
    >>> excess = np.where(s.visible, s.pseudorange_m - rho, np.nan)
    >>> [sorted(set(np.round(row[s.visible[k]], 3).tolist())) for k, row in enumerate(excess)]
    [[29979.246], [30009.225]]
    """
    r, v, t = _checked_receiver(receiver_position_m, receiver_velocity_m_s, times_s)
    instance("constellation", constellation, Constellation, "a gnssatt.sim Constellation")
    rng = generator("rng", rng)
    unknown = sorted({i[0] for i in constellation.ids} - set(SYSTEM_INDEX))
    if unknown:
        raise InvalidInputError(f"expected GPS (G) or GLONASS (R) satellites, got systems {unknown}")
    sig_c = scalar("code_sigma_m", code_sigma_m, minimum=0.0, strict=True)
    sig_d = scalar("doppler_sigma_hz", doppler_sigma_hz, minimum=0.0, strict=True)
    q_b = scalar("q_bias_s2_s", q_bias_s2_s, minimum=0.0)
    q_d = scalar("q_drift_1_s", q_drift_1_s, minimum=0.0)
    isb = scalar("isb_m", isb_m)
    windows = _outages(outages)

    sat_r, sat_v = constellation.state_ecef(t, theta0_rad)  # (n_t, n_sat, 3)
    d = sat_r - r[:, None, :]
    rho = np.linalg.norm(d, axis=-1)
    if np.any(rho == 0.0):
        raise InvalidInputError(
            "receiver_position_m coincides with a satellite: the line of sight is undefined"
        )
    los = d / rho[..., None]
    rate = np.sum(los * (sat_v - v[:, None, :]), axis=-1)
    visible = _visibility(los, r, v, sat_r, t, windows, half_angle_deg, atmosphere_m)
    bias, drift = _receiver_clock(rng, t, clock_bias0_s, clock_drift0, q_b, q_d)

    system = np.array([SYSTEM_INDEX[i[0]] for i in constellation.ids], dtype=np.uint32)
    lam = constellation.wavelengths_m("L1")
    c = SPEED_OF_LIGHT_M_S
    pr = rho + c * bias[:, None] + isb * (system == 1) + sig_c * rng.standard_normal(rho.shape)
    dop = -(rate + c * drift[:, None]) / lam + sig_d * rng.standard_normal(rho.shape)
    cause = "the noise levels or clock parameters are too large for float64"
    for what, value in (("pseudorange", pr), ("Doppler", dop), ("clock bias", bias), ("clock drift", drift)):
        finite_result(f"the simulated {what}", value, cause)
    pr[~visible] = np.nan
    dop[~visible] = np.nan
    return SpaceborneMeasurements(
        t, constellation.ids, system, lam, sat_r, sat_v, pr, dop, visible, sig_c, sig_d, bias, drift, isb
    )
