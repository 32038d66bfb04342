"""Pseudoranges and Doppler of a GNSS receiver on a small satellite (seed 003, orbit determination).

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
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.spatial.transform import Rotation

from gnssatt._arrays import float_array, scalar
from gnssatt.errors import InvalidInputError
from gnssatt.sim.constants import SPEED_OF_LIGHT_M_S
from gnssatt.sim.constellation import Constellation
from gnssatt.sim.visibility import antenna_cone_mask, earth_occlusion_mask

__all__ = ["SpaceborneMeasurements", "simulate_spaceborne"]

#: System index of each satellite id prefix (the filters difference within a system only).
SYSTEM_INDEX = {"G": 0, "R": 1}


@dataclass(frozen=True)
class SpaceborneMeasurements:
    """Measurements of a spaceborne receiver and the truth behind them.

    Attributes
    ----------
    times_s
        (n_t,) epochs, s.
    ids
        (n_sat,) satellite ids (``G..`` GPS, ``R..`` GLONASS).
    system
        (n_sat,) uint32 system index (0 GPS, 1 GLONASS).
    wavelength_m
        (n_sat,) L1 carrier wavelengths, m.
    sat_position_m, sat_velocity_m_s
        (n_t, n_sat, 3) satellite states, ECEF.
    pseudorange_m, doppler_hz
        (n_t, n_sat) measurements (NaN where not visible).
    visible
        (n_t, n_sat) tracked.
    code_sigma_m, doppler_sigma_hz
        Noise standard deviations used.
    clock_bias_s, clock_drift
        (n_t,) truth: receiver clock bias (s) and drift (s/s).
    isb_m
        Truth: GLONASS minus GPS inter-system bias, m.
    """

    times_s: NDArray[np.float64]
    ids: tuple[str, ...]
    system: NDArray[np.uint32]
    wavelength_m: NDArray[np.float64]
    sat_position_m: NDArray[np.float64]
    sat_velocity_m_s: NDArray[np.float64]
    pseudorange_m: NDArray[np.float64]
    doppler_hz: NDArray[np.float64]
    visible: NDArray[np.bool_]
    code_sigma_m: float
    doppler_sigma_hz: float
    clock_bias_s: NDArray[np.float64]
    clock_drift: NDArray[np.float64]
    isb_m: float

    def select_systems(self, prefixes: str) -> SpaceborneMeasurements:
        """Only the satellites whose id starts with one of ``prefixes`` (e.g. ``"G"`` or ``"GR"``)."""
        keep = np.array([i[0] in prefixes for i in self.ids], dtype=bool)
        if not keep.any():
            raise InvalidInputError(
                f"expected systems among {sorted({i[0] for i in self.ids})}, got {prefixes!r}"
            )
        return SpaceborneMeasurements(
            self.times_s,
            tuple(i for i, k in zip(self.ids, keep, strict=True) if k),
            self.system[keep],
            self.wavelength_m[keep],
            self.sat_position_m[:, keep],
            self.sat_velocity_m_s[:, keep],
            self.pseudorange_m[:, keep],
            self.doppler_hz[:, keep],
            self.visible[:, keep],
            self.code_sigma_m,
            self.doppler_sigma_hz,
            self.clock_bias_s,
            self.clock_drift,
            self.isb_m,
        )


def _zenith_attitudes(r: NDArray[np.float64], v: NDArray[np.float64]) -> Rotation:
    """Body -> ECEF rotations with body z along the radius and body x along the velocity's horizontal part."""
    z = r / np.linalg.norm(r, axis=-1, keepdims=True)
    x = v - np.sum(v * z, axis=-1, keepdims=True) * z
    x /= np.linalg.norm(x, axis=-1, keepdims=True)
    return Rotation.from_matrix(np.stack([x, np.cross(z, x), z], axis=-1))


def simulate_spaceborne(
    receiver_position_m: ArrayLike,
    receiver_velocity_m_s: ArrayLike,
    times_s: ArrayLike,
    constellation: Constellation,
    rng: np.random.Generator,
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
        (n_t, 3) true receiver states, ECEF (m, m/s relative to the Earth).
    times_s
        (n_t,) strictly increasing epochs, s from the scenario epoch (the constellation's ``t``).
    constellation
        GNSS satellites (ids starting with ``G`` or ``R``).
    rng
        The only source of randomness (drawn: clock noise, code noise, Doppler noise).
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
        ``(t_start_s, t_end_s, max_sats)`` windows (inclusive) that keep at most ``max_sats`` satellites.
    """
    r = float_array("receiver_position_m", receiver_position_m, ndim=2, shape="(n_t, 3)")
    v = float_array("receiver_velocity_m_s", receiver_velocity_m_s, ndim=2, shape="(n_t, 3)")
    t = float_array("times_s", times_s, ndim=1, shape="(n_t,)")
    if r.shape != (t.size, 3) or v.shape != r.shape:
        raise InvalidInputError(
            f"expected receiver states of shape ({t.size}, 3) (one per epoch), got {r.shape} and {v.shape}"
        )
    if t.size == 0 or np.any(np.diff(t) <= 0):
        raise InvalidInputError("expected at least one epoch and strictly increasing times_s")
    if not isinstance(constellation, Constellation):
        raise TypeError(f"expected a gnssatt.sim Constellation, got {type(constellation).__name__}")
    if not isinstance(rng, np.random.Generator):
        raise TypeError(f"expected rng as a numpy.random.Generator, got {type(rng).__name__}")
    unknown = sorted({i[0] for i in constellation.ids} - set(SYSTEM_INDEX))
    if unknown:
        raise InvalidInputError(f"expected GPS (G) or GLONASS (R) satellites, got systems {unknown}")
    sig_c = scalar("code_sigma_m", code_sigma_m, minimum=0.0, strict=True)
    sig_d = scalar("doppler_sigma_hz", doppler_sigma_hz, minimum=0.0, strict=True)
    q_b = scalar("q_bias_s2_s", q_bias_s2_s, minimum=0.0)
    q_d = scalar("q_drift_1_s", q_drift_1_s, minimum=0.0)
    isb = scalar("isb_m", isb_m)

    sat_r, sat_v = constellation.state_ecef(t, theta0_rad)  # (n_t, n_sat, 3)
    d = sat_r - r[:, None, :]
    rho = np.linalg.norm(d, axis=-1)
    los = d / rho[..., None]
    rate = np.sum(los * (sat_v - v[:, None, :]), axis=-1)
    visible = antenna_cone_mask(los, _zenith_attitudes(r, v), (0.0, 0.0, 1.0), half_angle_deg)
    visible &= earth_occlusion_mask(r, sat_r, atmosphere_m=atmosphere_m)
    cos_boresight = np.sum(los * (r / np.linalg.norm(r, axis=-1, keepdims=True))[:, None, :], axis=-1)
    for k, window in enumerate(outages):
        if len(window) != 3:
            raise InvalidInputError(
                f"expected outages[{k}] as (t_start_s, t_end_s, max_sats), got {window!r}"
            )
        t0, t1, n_max = float(window[0]), float(window[1]), int(window[2])
        for i in np.flatnonzero((t >= t0) & (t <= t1)):
            order = np.argsort(-np.where(visible[i], cos_boresight[i], -np.inf), kind="stable")
            visible[i, order[n_max:]] = False

    dt = np.diff(t, prepend=t[0])
    bias = np.empty(t.size)
    drift = np.empty(t.size)
    bias[0], drift[0] = scalar("clock_bias0_s", clock_bias0_s), scalar("clock_drift0", clock_drift0)
    noise = rng.standard_normal((t.size, 2))
    for k in range(1, t.size):
        bias[k] = bias[k - 1] + drift[k - 1] * dt[k] + np.sqrt(q_b * dt[k]) * noise[k, 0]
        drift[k] = drift[k - 1] + np.sqrt(q_d * dt[k]) * noise[k, 1]

    system = np.array([SYSTEM_INDEX[i[0]] for i in constellation.ids], dtype=np.uint32)
    lam = constellation.wavelengths_m("L1")
    c = SPEED_OF_LIGHT_M_S
    pr = rho + c * bias[:, None] + isb * (system == 1) + sig_c * rng.standard_normal(rho.shape)
    dop = -(rate + c * drift[:, None]) / lam + sig_d * rng.standard_normal(rho.shape)
    pr[~visible] = np.nan
    dop[~visible] = np.nan
    return SpaceborneMeasurements(
        t, constellation.ids, system, lam, sat_r, sat_v, pr, dop, visible, sig_c, sig_d, bias, drift, isb
    )
