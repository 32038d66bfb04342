"""Simulated moving platforms written as RINEX 3.04 with their truth: a trajectory (position and body
attitude over time), an antenna array on it (body-frame lever arms), optionally a static base, satellites
blocked by the surroundings, a receiver noise profile, every range computed from the broadcast records
written (as :func:`~gnssatt.sim.rinex_scenario.simulate_gnss_rinex`: light time, Earth rotation,
satellite clocks, Klobuchar ionosphere and standard troposphere).

The general mechanism is :func:`simulate_platform` with a :class:`Trajectory` (legs of constant speed,
turn rate and climb rate, plus roll, pitch and heave oscillations, coordinated-turn bank), a
:class:`Blockage` (whole outages and tree-lined stretches) and a :class:`NoiseProfile`
(:data:`NOISE_PROFILES`: ``"gps_l1_ublox"``, ``"geodetic"``). The presets
:func:`~gnssatt.sim.platform_presets.car`, :func:`~gnssatt.sim.platform_presets.ship` and
:func:`~gnssatt.sim.platform_presets.aircraft` (:mod:`gnssatt.sim.platform_presets`) build on it.

Frames: ENU positions are in the tangent plane at the trajectory's origin (ECEF = origin + R0 ENU); the
attitude is body -> local ENU at the platform, eq. (5) angles ``euler_gost_deg`` of Bunyaeva et al. (body X
nose, Y up, Z right wing), so that compass ``heading_deg = -psi``, ``pitch_deg = theta`` (nose up
positive) and ``roll_deg = phi`` (right wing down positive). Antenna i is at ``position + R lever_i``.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from os import PathLike
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike, NDArray

from gnssatt._arrays import flag, folder_path, generator, instance, integer, scalar, shaped
from gnssatt.constants import SPEED_OF_LIGHT_M_S as _C
from gnssatt.errors import InvalidInputError, InvalidTypeError, WorkLimitError
from gnssatt.frames import ecef_to_geodetic, geodetic_to_ecef
from gnssatt.rinex.nav import nav_input
from gnssatt.rinex.writer import MAX_SPAN_S, write_nav_from_constellation
from gnssatt.rotation import rotation_from_euler
from gnssatt.sim.rinex_scenario import (
    DOPPLER_HALF_STEP_S,
    KLOBUCHAR,
    MIN_INTERVAL_S,
    T0,
    checked_antennas,
    gnss_constellation,
    klobuchar_m,
    observables,
    ranges_and_rates,
    transmit_geometry,
    wavelengths_m,
    write_receiver_obs,
)

if TYPE_CHECKING:
    from gnssatt import _core
    from gnssatt.orbit.constellation import Constellation

__all__ = [
    "MAX_PLATFORM_OBSERVATIONS",
    "NOISE_PROFILES",
    "Blockage",
    "Leg",
    "NoiseProfile",
    "SimulatedPlatform",
    "Trajectory",
    "simulate_platform",
]

#: Largest epochs x satellites of the systems simulated x receivers (antennas and base) of one call,
#: counted before any work. Measured on the shared 2-core machine at load 11: 15.7 s for the car preset
#: with every system, three antennas and a base over 60 s (601 x 99 x 4 = 238 000 counted), two thirds
#: of it writing the RINEX text; the limit is about a minute there and some 300 MB of arrays.
MAX_PLATFORM_OBSERVATIONS = 1_000_000
#: Largest number of legs of a trajectory and of outage or tree-lined windows (bounds the Python loops).
MAX_LEGS = 10_000
#: Largest speed (m/s), turn rate (deg/s), climb rate (m/s) and lever arm (m) accepted: a jet, a car
#: spinning, a fighter's climb, a ship's mast.
MAX_SPEED_M_S = 400.0
MAX_TURN_RATE_DEG_S = 360.0
MAX_CLIMB_RATE_M_S = 100.0
MAX_LEVER_ARM_M = 100.0
#: Standard gravity for the bank of a coordinated turn, m/s^2.
_G0 = 9.80665
#: Smallest elevation used in the elevation-dependent noise, degrees (the 1/sin term stays finite).
_NOISE_FLOOR_ELEVATION_DEG = 1.0


@dataclass(frozen=True)
class Leg:
    """One stretch of constant speed (m/s), turn rate (deg/s, compass sense: positive turns right) and
    climb rate (m/s) lasting ``duration_s``."""

    duration_s: float
    speed_m_s: float
    turn_rate_deg_s: float = 0.0
    climb_rate_m_s: float = 0.0

    def __post_init__(self) -> None:
        scalar("duration_s", self.duration_s, minimum=0.0, maximum=MAX_SPAN_S, unit="s")
        scalar("speed_m_s", self.speed_m_s, minimum=0.0, maximum=MAX_SPEED_M_S, unit="m/s")
        scalar(
            "turn_rate_deg_s", self.turn_rate_deg_s, minimum=-MAX_TURN_RATE_DEG_S,
            maximum=MAX_TURN_RATE_DEG_S, unit="deg/s",
        )  # fmt: skip
        scalar(
            "climb_rate_m_s", self.climb_rate_m_s, minimum=-MAX_CLIMB_RATE_M_S, maximum=MAX_CLIMB_RATE_M_S,
            unit="m/s",
        )  # fmt: skip


@dataclass(frozen=True)
class Trajectory:
    """A path of :class:`Leg` s from ``start_enu_m`` at ``heading0_deg``, with optional oscillations.

    Heading, position and height are closed forms of the legs (a turn is a circular arc of radius
    ``speed / turn rate``); after the last leg the motion continues as the last leg. Pitch is the flight-path
    angle ``atan(climb / speed)`` plus ``pitch_amplitude_deg sin(2 pi t / pitch_period_s)``; roll is the bank
    of a coordinated turn ``atan(speed omega / g)`` when ``banked`` plus ``roll_amplitude_deg
    sin(2 pi t / roll_period_s)``; the height gains ``heave_amplitude_m sin(2 pi t / heave_period_s)``.

    Attributes
    ----------
    legs
        The legs in order.
    heading0_deg
        Compass heading at t = 0, degrees.
    start_enu_m
        (3,) position at t = 0 in the tangent plane at the origin, m.
    lat_deg, lon_deg, height_m
        Geodetic origin of the tangent plane.
    roll_amplitude_deg, roll_period_s, pitch_amplitude_deg, pitch_period_s, heave_amplitude_m, heave_period_s
        Oscillations (a ship in a swell); zero amplitudes: none.
    banked
        Roll into turns as a coordinated turn (aircraft); False: no bank (car, ship).
    """

    legs: tuple[Leg, ...]
    heading0_deg: float = 0.0
    start_enu_m: tuple[float, float, float] = (0.0, 0.0, 0.0)
    lat_deg: float = 50.0
    lon_deg: float = 36.2
    height_m: float = 150.0
    roll_amplitude_deg: float = 0.0
    roll_period_s: float = 10.0
    pitch_amplitude_deg: float = 0.0
    pitch_period_s: float = 10.0
    heave_amplitude_m: float = 0.0
    heave_period_s: float = 10.0
    banked: bool = False

    def __post_init__(self) -> None:
        if not isinstance(self.legs, tuple) or not all(isinstance(x, Leg) for x in self.legs):
            raise InvalidTypeError(f"expected legs as a tuple of Leg, got {type(self.legs).__name__}")
        if not 1 <= len(self.legs) <= MAX_LEGS:
            raise InvalidInputError(f"expected 1 to {MAX_LEGS} legs, got {len(self.legs)}")
        scalar("heading0_deg", self.heading0_deg, minimum=-360.0, maximum=360.0)
        shaped("start_enu_m", self.start_enu_m, "(3,)", (3,))
        scalar("lat_deg", self.lat_deg, minimum=-90.0, maximum=90.0)
        scalar("lon_deg", self.lon_deg, minimum=-360.0, maximum=360.0)
        scalar("height_m", self.height_m, minimum=-1e4, maximum=1e5, unit="m")
        for name in ("roll_amplitude_deg", "pitch_amplitude_deg"):
            scalar(name, getattr(self, name), minimum=0.0, maximum=80.0)
        scalar("heave_amplitude_m", self.heave_amplitude_m, minimum=0.0, maximum=100.0, unit="m")
        for name in ("roll_period_s", "pitch_period_s", "heave_period_s"):
            scalar(name, getattr(self, name), minimum=0.1, maximum=1e4, unit="s")
        flag("banked", self.banked)

    def at(self, time_s: ArrayLike) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Position (n, 3) ENU in the origin's tangent plane (m) and eq. (5) angles (n, 3) (degrees) at
        ``time_s`` (n,) seconds after t = 0 (negative times continue the first leg backwards)."""
        t = np.atleast_1d(np.asarray(time_s, dtype=np.float64))
        if t.ndim != 1 or not np.all(np.isfinite(t)):
            raise InvalidInputError(f"expected time_s as finite (n,) seconds, got shape {t.shape}")
        starts = np.concatenate([[0.0], np.cumsum([leg.duration_s for leg in self.legs])[:-1]])
        # state at the start of each leg: heading (rad), east, north, up
        h, e, n, u = float(np.radians(self.heading0_deg)), *(float(x) for x in self.start_enu_m)
        state = []
        for leg in self.legs:
            state.append((h, e, n, u))
            h, e, n, u = (float(x) for x in _advance(leg, leg.duration_s, h, e, n, u))
        k = np.clip(np.searchsorted(starts, t, side="right") - 1, 0, len(self.legs) - 1)
        pos = np.empty((t.size, 3))
        heading = np.empty(t.size)
        pitch = np.empty(t.size)
        roll = np.zeros(t.size)
        for j in np.unique(k):
            leg, sel = self.legs[j], k == j
            hj, ej, nj, uj = _advance(leg, t[sel] - starts[j], *state[j])
            heading[sel], pos[sel, 0], pos[sel, 1], pos[sel, 2] = hj, ej, nj, uj
            pitch[sel] = np.degrees(np.arctan2(leg.climb_rate_m_s, leg.speed_m_s)) if leg.speed_m_s else 0.0
            if self.banked:
                roll[sel] = np.degrees(np.arctan(leg.speed_m_s * np.radians(leg.turn_rate_deg_s) / _G0))
        pitch = pitch + self.pitch_amplitude_deg * np.sin(2 * np.pi * t / self.pitch_period_s)
        roll = roll + self.roll_amplitude_deg * np.sin(2 * np.pi * t / self.roll_period_s)
        pos[:, 2] += self.heave_amplitude_m * np.sin(2 * np.pi * t / self.heave_period_s)
        psi = -np.degrees(np.angle(np.exp(1j * heading)))  # compass heading = -psi, wrapped to +-180
        return pos, np.column_stack([psi, pitch, roll])


def _advance(
    leg: Leg, dt: ArrayLike, h: float, e: float, n: float, u: float
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """Heading (rad) and E, N, U (m) ``dt`` seconds into ``leg`` from heading ``h`` at ``(e, n, u)``: a
    straight line, or the circular arc of radius ``v / omega`` (``d(E, N)/dt = v (sin h, cos h)``)."""
    t = np.asarray(dt, dtype=np.float64)
    v, w = leg.speed_m_s, np.radians(leg.turn_rate_deg_s)
    h1 = h + w * t
    if w == 0.0:
        de, dn = v * t * np.sin(h), v * t * np.cos(h)
    else:
        de, dn = (v / w) * (np.cos(h) - np.cos(h1)), (v / w) * (np.sin(h1) - np.sin(h))
    return h1 + 0.0 * t, e + de, n + dn, u + leg.climb_rate_m_s * t


@dataclass(frozen=True)
class Blockage:
    """What the surroundings of the platform hide from its antennas (never from a static base).

    Attributes
    ----------
    outages_s
        ``(start, end)`` windows (s after the first epoch) in which every satellite is hidden (a bridge, a
        tunnel); an epoch at ``start <= t < end`` has no observation.
    tree_lined_s
        ``(start, end)`` windows of a road lined with trees: a satellite is hidden below the elevation mask
        ``along_deg + (across_deg - along_deg) |sin(azimuth - heading)|`` (low across the road, high
        beside it).
    along_deg, across_deg
        The tree mask along and across the direction of travel, degrees.
    """

    outages_s: tuple[tuple[float, float], ...] = ()
    tree_lined_s: tuple[tuple[float, float], ...] = ()
    along_deg: float = 15.0
    across_deg: float = 45.0

    def __post_init__(self) -> None:
        for name in ("outages_s", "tree_lined_s"):
            windows = getattr(self, name)
            if isinstance(windows, tuple) and not windows:
                continue
            w = shaped(name, windows, "(n_windows, 2) (start_s, end_s)", (None, 2))
            if len(w) > MAX_LEGS:
                raise InvalidInputError(f"expected {name} with at most {MAX_LEGS} windows, got {len(w)}")
            if np.any(w[:, 1] < w[:, 0]):
                raise InvalidInputError(f"expected {name} windows with start_s <= end_s, got {w.tolist()}")
        scalar("along_deg", self.along_deg, minimum=-90.0, maximum=90.0)
        scalar("across_deg", self.across_deg, minimum=-90.0, maximum=90.0)

    def hidden(
        self, t_s: NDArray[np.float64], heading_deg: NDArray[np.float64], el_deg: NDArray[np.float64],
        az_deg: NDArray[np.float64],
    ) -> NDArray[np.bool_]:  # fmt: skip
        """(n_ep, n_sat) True where hidden, at epochs ``t_s`` (n_ep,), platform heading (n_ep,) and the
        satellites' elevation and azimuth (n_ep, n_sat), degrees."""
        out = np.zeros(el_deg.shape, dtype=bool)
        for a, b in self.outages_s:
            out |= ((t_s >= a) & (t_s < b))[:, None]
        trees = np.zeros(t_s.shape, dtype=bool)
        for a, b in self.tree_lined_s:
            trees |= (t_s >= a) & (t_s < b)
        mask = self.along_deg + (self.across_deg - self.along_deg) * np.abs(
            np.sin(np.radians(az_deg - heading_deg[:, None]))
        )
        return out | (trees[:, None] & (el_deg < mask))


@dataclass(frozen=True)
class NoiseProfile:
    """A receiver's signals and noise.

    Code and phase noise are white with the elevation-dependent standard deviation of RTKLIB's model,
    ``sqrt(a^2 + b^2 / sin^2(el))`` (``(a, b)`` in m); Doppler noise white. A cycle slip hits each tracked
    satellite of a receiver at a rate ``slip_rate_per_s`` (a Poisson process sampled per epoch): every
    phase of that satellite jumps by a nonzero integer (1 to 50 cycles) and its loss-of-lock indicator is 1.

    Attributes
    ----------
    systems, frequencies
        Systems (letters of ``"GRECJ"``) and frequency slots (1 to 3) written.
    code_sigma_m, phase_sigma_m
        ``(a, b)`` of the elevation model, m.
    doppler_sigma_hz
        Doppler noise, Hz.
    slip_rate_per_s
        Cycle slips per tracked satellite per second.
    """

    systems: str
    frequencies: int
    code_sigma_m: tuple[float, float]
    phase_sigma_m: tuple[float, float]
    doppler_sigma_hz: float
    slip_rate_per_s: float

    def __post_init__(self) -> None:
        if not isinstance(self.systems, str):
            raise InvalidTypeError(f"expected systems as text, got {type(self.systems).__name__}")
        if not (self.systems and set(self.systems) <= set("GRECJ")):
            raise InvalidInputError(f"expected systems as letters of 'GRECJ', got {self.systems!r}")
        integer("frequencies", self.frequencies, minimum=1, maximum=3)
        for name in ("code_sigma_m", "phase_sigma_m"):
            ab = shaped(name, getattr(self, name), "(2,) (a, b) in m", (2,))
            if np.any(ab < 0.0) or np.any(ab > 1e3):
                raise InvalidInputError(f"expected {name} within [0, 1e3] m, got {ab.tolist()}")
        scalar("doppler_sigma_hz", self.doppler_sigma_hz, minimum=0.0, maximum=1e3, unit="Hz")
        scalar("slip_rate_per_s", self.slip_rate_per_s, minimum=0.0, maximum=1e3, unit="1/s")

    def sigma_m(self, ab: tuple[float, float], el_deg: NDArray[np.float64]) -> NDArray[np.float64]:
        """The elevation model ``sqrt(a^2 + b^2 / sin^2(el))`` of ``ab`` at ``el_deg``, m."""
        s = np.sin(np.radians(np.maximum(el_deg, _NOISE_FLOOR_ELEVATION_DEG)))
        return np.sqrt(ab[0] ** 2 + (ab[1] / s) ** 2)


#: ``gps_l1_ublox``: GPS L1 C/A of a low-cost receiver with a patch antenna (u-blox M8T class): code 0.35 m
#: at zenith, 1 m at 15 degrees; phase 2.8 mm at zenith, 8 mm at 15 degrees; Doppler 0.1 Hz; a slip per
#: satellite every 10 minutes on average. ``geodetic``: every system and three frequencies of a geodetic
#: receiver: code 0.14 m / 0.4 m, phase 1.4 mm / 4 mm, Doppler 0.03 Hz, a slip per satellite per hour.
NOISE_PROFILES: dict[str, NoiseProfile] = {
    "gps_l1_ublox": NoiseProfile("G", 1, (0.25, 0.25), (0.002, 0.002), 0.1, 1 / 600),
    "geodetic": NoiseProfile("GRECJ", 3, (0.1, 0.1), (0.001, 0.001), 0.03, 1 / 3600),
}


@dataclass(frozen=True)
class SimulatedPlatform:
    """Files and truth of :func:`simulate_platform`.

    Attributes
    ----------
    obs_paths
        RINEX 3.04 observation file of each antenna (``ant<i>.rnx``), antenna 0 (the moving base) first.
    base_path
        Observation file of the static base (``base.rnx``), or None.
    nav_path
        Mixed navigation file (``nav.rnx``) whose records gave every range.
    time
        (n_ep,) GPST epoch labels, ``datetime64[ns]``; t = 0 of the trajectory is the first.
    time_s
        (n_ep,) seconds after the first epoch.
    sats
        Satellites written (above the elevation mask at the base or antenna 0 at some epoch).
    position_enu_m
        (n_ep, 3) the platform's reference point in the tangent plane at the trajectory's origin, m.
    euler_gost_deg
        (n_ep, 3) eq. (5) angles body -> local ENU, degrees.
    heading_deg, pitch_deg, roll_deg
        (n_ep,) compass heading (-psi, in [-180, 180)), pitch (theta) and roll (phi), degrees.
    antenna_ecef_m
        (n_ep, n_ant, 3) true antenna positions, ECEF, m.
    base_ecef_m
        (3,) the static base, ECEF, m (its header position), or None.
    baselines_enu_m
        (n_ep, n_ant - 1, 3) antenna i - antenna 0 in ENU at antenna 0, m.
    rover_enu_m
        (n_ep, n_ant, 3) antenna i - base in ENU at the base, m (None without a base).
    visible
        (n_ep, n_rx, n_sat) True where the receiver (antennas, then the base) observed the satellite.
    slips
        Slips applied within arcs: (epoch, receiver, satellite, slot, jump in cycles); a receiver's LLI is 1
        there and also at the first epoch of every new arc (after the satellite was hidden).
    outage_ends_s
        End of each whole outage (s after the first epoch), for the time to re-fix.
    elevation_deg
        (n_ep, n_rx, n_sat) elevation at each receiver, degrees.
    """

    obs_paths: tuple[Path, ...]
    base_path: Path | None
    nav_path: Path
    time: NDArray[np.datetime64]
    time_s: NDArray[np.float64]
    sats: tuple[str, ...]
    position_enu_m: NDArray[np.float64]
    euler_gost_deg: NDArray[np.float64]
    heading_deg: NDArray[np.float64]
    pitch_deg: NDArray[np.float64]
    roll_deg: NDArray[np.float64]
    antenna_ecef_m: NDArray[np.float64]
    base_ecef_m: NDArray[np.float64] | None
    baselines_enu_m: NDArray[np.float64]
    rover_enu_m: NDArray[np.float64] | None
    visible: NDArray[np.bool_]
    slips: tuple[tuple[int, int, str, int, int], ...]
    outage_ends_s: tuple[float, ...]
    elevation_deg: NDArray[np.float64] = field(repr=False)


def _dcm_ecef_from_enu(lat_deg: NDArray[np.float64], lon_deg: NDArray[np.float64]) -> NDArray[np.float64]:
    """(..., 3, 3) ENU -> ECEF rotations (columns E, N, U) at geodetic points."""
    la, lo = np.radians(lat_deg), np.radians(lon_deg)
    sl, cl, sp, cp = np.sin(lo), np.cos(lo), np.sin(la), np.cos(la)
    z = np.zeros_like(la)
    east = np.stack([-sl, cl, z], axis=-1)
    north = np.stack([-sp * cl, -sp * sl, cp], axis=-1)
    up = np.stack([cp * cl, cp * sl, sp], axis=-1)
    return np.stack([east, north, up], axis=-1)


def _antennas_ecef(
    traj: Trajectory, t_s: NDArray[np.float64], lever_m: NDArray[np.float64]
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """ECEF (n, n_ant, 3) of every antenna at ``t_s``: the reference point (origin + R0 ENU) plus the lever
    arms turned body -> local ENU -> ECEF; also the ENU positions, the angles and the local ENU -> ECEF."""
    enu, eul = traj.at(t_s)
    r0 = _dcm_ecef_from_enu(np.asarray(traj.lat_deg), np.asarray(traj.lon_deg))
    origin = geodetic_to_ecef(traj.lat_deg, traj.lon_deg, traj.height_m)
    ref = origin + enu @ r0.T
    lat, lon, _ = ecef_to_geodetic(ref)
    local = _dcm_ecef_from_enu(np.asarray(lat, dtype=np.float64), np.asarray(lon, dtype=np.float64))
    body = rotation_from_euler(eul).as_matrix()  # (n, 3, 3) body -> local ENU
    ant = ref[:, None, :] + np.einsum("tij,tjk,ak->tai", local, body, lever_m)
    return ant, enu, eul, local


def _checked_noise(noise: str | NoiseProfile) -> NoiseProfile:
    """``noise`` as a profile: a :class:`NoiseProfile`, or the name of one of :data:`NOISE_PROFILES`."""
    if isinstance(noise, str):
        if noise not in NOISE_PROFILES:
            raise InvalidInputError(f"expected noise as one of {sorted(NOISE_PROFILES)}, got {noise!r}")
        noise = NOISE_PROFILES[noise]
    return instance("noise", noise, NoiseProfile, "a NoiseProfile or a profile name")


def _receiver_positions(
    traj: Trajectory,
    t_rel: NDArray[np.float64],
    lever: NDArray[np.float64],
    base_off: NDArray[np.float64] | None,
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64], NDArray[np.float64] | None]:
    """ECEF positions (n_ep, n_rx, 3 instants, 3) of the antennas, then the base, at the label and half a
    Doppler step either side; the platform's ENU positions and Euler angles at the labels; the base."""
    n_ant = lever.shape[0]
    n_rx = n_ant + (base_off is not None)
    h = DOPPLER_HALF_STEP_S
    pos = np.empty((t_rel.size, n_rx, 3, 3))
    for j, dt in enumerate((0.0, -h, h)):
        ant, enu_j, eul_j, _ = _antennas_ecef(traj, t_rel + dt, lever)
        pos[:, :n_ant, j] = ant
        if j == 0:
            enu, eul = enu_j, eul_j
    base_ecef = None
    if base_off is not None:
        r0 = _dcm_ecef_from_enu(np.asarray(traj.lat_deg), np.asarray(traj.lon_deg))
        base_ecef = geodetic_to_ecef(traj.lat_deg, traj.lon_deg, traj.height_m) + r0 @ base_off
        pos[:, n_ant] = base_ecef
    return pos, enu, eul, base_ecef


def _atmosphere_delays(
    atmosphere: bool,
    pos: NDArray[np.float64],
    el_deg: NDArray[np.float64],
    az_deg: NDArray[np.float64],
    t_ns: NDArray[np.int64],
    lam: NDArray[np.float64],
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Klobuchar ionosphere (n_ep, n_rx, n_sat, 3 slots) and troposphere (n_ep, n_rx, n_sat) delays, m;
    zero without ``atmosphere``."""
    from gnssatt.sim.atmosphere import troposphere_delay_m

    n_ep, n_rx, n_sat = el_deg.shape
    iono: NDArray[np.float64] = np.zeros((n_ep, n_rx, n_sat, 3))
    tropo: NDArray[np.float64] = np.zeros((n_ep, n_rx, n_sat))
    if atmosphere:
        lat, lon, hgt = ecef_to_geodetic(pos[:, :, 0].reshape(-1, 3))
        lat_r, lon_r = np.radians(np.asarray(lat)), np.radians(np.asarray(lon))
        el_r = np.radians(np.maximum(el_deg, 0.0)).reshape(-1, n_sat)
        hgt = np.asarray(hgt).reshape(-1)
        # the troposphere's zenith delay depends on each receiver's height (an aircraft's changes)
        tropo = np.stack(
            [troposphere_delay_m(float(lat_r[q]), float(hgt[q]), el_r[q]) for q in range(el_r.shape[0])]
        ).reshape(n_ep, n_rx, n_sat)
        # the receiver's latitude and longitude vary little over a session: those of the first epoch
        el_r3 = np.radians(np.maximum(el_deg, 0.0))
        iono = klobuchar_m(t_ns, float(lat_r[0]), float(lon_r[0]), el_r3, np.radians(az_deg), lam)
    return iono, tropo


def _carrier_cycles(
    gen: np.random.Generator,
    visible: NDArray[np.bool_],
    prof: NoiseProfile,
    interval_s: float,
    lam: NDArray[np.float64],
    sats: list[str],
    n_freq: int,
) -> tuple[NDArray[np.int64], NDArray[np.bool_], list[tuple[int, int, str, int, int]]]:
    """Integer cycles (n_ep, n_rx, n_sat, 3) on the phases: a draw per arc, slips within arcs at the
    profile's rate; the loss-of-lock flags; the slips applied as (epoch, receiver, satellite, slot,
    cycles)."""
    shape = (*visible.shape, 3)
    n_rx, n_sat = visible.shape[1:]
    amb = gen.integers(-1000, 1000, size=(n_rx, n_sat, 3))
    new_arc = visible.copy()
    new_arc[1:] &= ~visible[:-1]
    new_arc[0] = False
    slip_event = visible & ~new_arc & (gen.random(visible.shape) < prof.slip_rate_per_s * interval_s)
    slip_event[0] = False
    size = gen.integers(1, 51, size=shape) * np.where(gen.random(shape) < 0.5, 1, -1)
    arc_jump = gen.integers(-1000, 1000, size=shape)
    jumps = np.where(slip_event[..., None], size, 0) + np.where(new_arc[..., None], arc_jump, 0)
    n_cycles = amb[None] + np.cumsum(jumps, axis=0)
    lli = (slip_event | new_arc)[..., None] & np.ones(3, dtype=bool)
    applied = [
        (int(e), int(r), sats[int(s)], slot, int(size[e, r, s, slot]))
        for e, r, s in zip(*np.nonzero(slip_event), strict=True)
        for slot in range(n_freq)
        if np.isfinite(lam[s, slot])
    ]
    return n_cycles, lli, applied


def _truth_baselines(
    ant_ecef: NDArray[np.float64], base_ecef: NDArray[np.float64] | None
) -> tuple[NDArray[np.float64], NDArray[np.float64] | None]:
    """Baselines from antenna 0 in the local ENU of antenna 0 (n_ep, n_ant - 1, 3) and, with a base, the
    antennas' positions in the base's ENU (n_ep, n_ant, 3), m."""
    local = _dcm_ecef_from_enu(
        *(np.asarray(x, dtype=np.float64) for x in ecef_to_geodetic(ant_ecef[:, 0])[:2])
    )
    baselines = np.einsum("tji,taj->tai", local, ant_ecef[:, 1:] - ant_ecef[:, :1])
    rover = None
    if base_ecef is not None:
        lat_b, lon_b, _ = ecef_to_geodetic(base_ecef)
        rb = _dcm_ecef_from_enu(np.asarray(lat_b, dtype=np.float64), np.asarray(lon_b, dtype=np.float64))
        rover = (ant_ecef - base_ecef) @ rb
    return baselines, rover


def _checked_base_offset(base_offset_enu_m: ArrayLike | None) -> NDArray[np.float64] | None:
    """The static base's (3,) East-North-Up offset, m, or None for no base."""
    if base_offset_enu_m is None:
        return None
    base_off = shaped("base_offset_enu_m", base_offset_enu_m, "(3,)", (3,))
    if np.any(np.abs(base_off) > 1e6):
        raise InvalidInputError(f"expected |base_offset_enu_m| <= 1e6 m, got {base_off}")
    return base_off


def _check_observation_count(n_ep: int, n_sats: int, n_rx: int) -> None:
    """Refuse a session of more than :data:`MAX_PLATFORM_OBSERVATIONS` before anything is simulated."""
    if n_ep * n_sats * n_rx > MAX_PLATFORM_OBSERVATIONS:
        raise WorkLimitError(
            f"expected epochs x satellites x receivers <= {MAX_PLATFORM_OBSERVATIONS} "
            f"(MAX_PLATFORM_OBSERVATIONS), got {n_ep} x {n_sats} x {n_rx}: shorten duration_s or "
            f"lengthen interval_s"
        )


def _satellites_in_view(
    nav: _core.Navigation, allsats: Constellation, t_ns: NDArray[np.int64], ref_ecef_m: NDArray[np.float64],
    ref_clock_s: float, elevation_min_deg: float,
) -> tuple[list[str], dict[str, int]]:  # fmt: skip
    """The satellites above the mask at the reference receiver (ECEF positions per epoch, clock offset)
    at some epoch, in the constellation's order, and the GLONASS ones' channels."""
    ids = list(allsats.ids)
    ok, at_ref = transmit_geometry(nav, ids, t_ns, ref_ecef_m, np.full(len(t_ns), ref_clock_s))
    el_ref = np.where(ok, np.degrees(at_ref.elevation_rad), -90.0)
    keep = np.any(el_ref > elevation_min_deg, axis=0)
    if not keep.any():
        raise InvalidInputError(f"no satellite above elevation_min_deg = {elevation_min_deg}")
    sats = [s for s, k in zip(ids, keep, strict=True) if k]
    channels = {s: int(allsats.glonass_channels[ids.index(s)]) for s in sats if s[0] == "R"}
    return sats, channels


def _unblocked(
    visible: NDArray[np.bool_], block: Blockage, t_rel: NDArray[np.float64], heading: NDArray[np.float64],
    el_deg: NDArray[np.float64], az_deg: NDArray[np.float64], n_ant: int,
) -> NDArray[np.bool_]:  # fmt: skip
    """``visible`` (epochs, receivers, satellites) less what the blockage hides from each antenna (the
    base, after them, sees past it)."""
    for i in range(n_ant):
        visible[:, i] &= ~block.hidden(t_rel, heading, el_deg[:, i], az_deg[:, i])
    return visible


def simulate_platform(
    folder: str | PathLike[str],
    trajectory: Trajectory,
    antennas_body_m: ArrayLike,
    *,
    duration_s: float,
    interval_s: float,
    noise: str | NoiseProfile = "gps_l1_ublox",
    blockage: Blockage | None = None,
    base_offset_enu_m: ArrayLike | None = None,
    elevation_min_deg: float = 10.0,
    start_s: float = 0.0,
    atmosphere: bool = True,
    rng: int | np.random.Generator | None = None,
) -> SimulatedPlatform:
    """Simulate an antenna array on a moving platform (and a static base) and write it as RINEX 3.04.

    Every receiver (antennas, then the base) observes each satellite of ``sats`` while it is above
    ``elevation_min_deg`` at that receiver and not hidden by ``blockage`` (antennas only); a satellite
    seen again after a gap starts a new arc (a new integer ambiguity, LLI 1). Observations at label T,
    with the steered receiver clock ``dt_r`` (uniform in +-1e-7 s, as a low-cost receiver's time tags, so
    that the antenna's motion during it, below 1e-5 m at 100 m/s, is left out) follow the model of
    :func:`~gnssatt.sim.rinex_scenario.simulate_gnss_rinex`, with the noise of ``noise`` at each
    receiver's elevation and the Doppler of the moving antenna (central difference of the range over
    +-0.05 s of its trajectory). C/N0 is ``30 + 20 sin(el)`` dB-Hz.

    Parameters
    ----------
    folder
        Existing folder for ``ant<i>.rnx``, ``base.rnx`` and ``nav.rnx``.
    trajectory
        The platform's motion.
    antennas_body_m
        (n_ant, 3) lever arms in the body frame (X nose, Y up, Z right wing), 2 to 8 antennas, each within
        ``MAX_LEVER_ARM_M``, m; antenna 0 is the moving base of the array.
    duration_s, interval_s
        Session length and epoch spacing, s (``floor(duration / interval) + 1`` epochs).
    noise
        A :class:`NoiseProfile` or the name of one of :data:`NOISE_PROFILES`.
    blockage
        What hides satellites from the antennas; None: open sky.
    base_offset_enu_m
        (3,) static base relative to the trajectory's origin, ENU in its tangent plane, m (hundreds of
        metres: near; kilometres: far); None (default): no base, a moving-base set-up only.
    elevation_min_deg
        Elevation mask of every receiver, degrees.
    start_s
        First epoch after ``2024-03-01T10:00:00`` GPST, s (other satellite geometries).
    atmosphere
        Klobuchar ionosphere and standard troposphere (at each receiver's height) as
        :func:`~gnssatt.sim.rinex_scenario.simulate_gnss_rinex`; False: vacuum.
    rng
        Seed or generator of the clocks, ambiguities, noise and slips.

    Returns
    -------
    SimulatedPlatform
        The files and the truth.

    Raises
    ------
    InvalidTypeError
        An argument of the wrong kind.
    InvalidInputError
        ``folder`` not an existing folder; shapes or ranges of the arguments (each named); no satellite
        above the mask.
    WorkLimitError
        Epochs x satellites x receivers above ``MAX_PLATFORM_OBSERVATIONS``, or a session longer than
        ``MAX_SPAN_S``.

    Examples
    --------
    Two antennas 2 m apart along the nose of a platform driving north at 5 m/s, no base:

    >>> import tempfile
    >>> import numpy as np
    >>> from gnssatt import sim
    >>> traj = sim.Trajectory((sim.Leg(10.0, 5.0),), heading0_deg=0.0)
    >>> with tempfile.TemporaryDirectory() as folder:
    ...     run = sim.simulate_platform(
    ...         folder, traj, [[0.0, 0.0, 0.0], [2.0, 0.0, 0.0]], duration_s=2.0, interval_s=1.0,
    ...         base_offset_enu_m=None, rng=1,
    ...     )
    >>> run.base_path is None, run.position_enu_m[:, 1].tolist()
    (True, [0.0, 5.0, 10.0])
    >>> bool(np.allclose(run.baselines_enu_m[:, 0], [0.0, 2.0, 0.0]))
    True
    """
    from gnssatt.rinex.nav import gps_ns, read_nav

    folder = folder_path("folder", folder)
    traj = instance("trajectory", trajectory, Trajectory, "a Trajectory")
    lever = checked_antennas(antennas_body_m, 8, MAX_LEVER_ARM_M)
    duration_s = scalar("duration_s", duration_s, minimum=0.0, maximum=MAX_SPAN_S, unit="s")
    interval_s = scalar("interval_s", interval_s, minimum=MIN_INTERVAL_S, maximum=MAX_SPAN_S, unit="s")
    prof = _checked_noise(noise)
    n_freq = integer("noise.frequencies", prof.frequencies, minimum=1, maximum=3)
    block = Blockage() if blockage is None else instance("blockage", blockage, Blockage, "a Blockage")
    base_off = _checked_base_offset(base_offset_enu_m)
    elevation_min_deg = scalar("elevation_min_deg", elevation_min_deg, minimum=-90.0, maximum=90.0)
    start_s = scalar("start_s", start_s, minimum=-3.2e8, maximum=3.2e8, unit="s")
    atmosphere = flag("atmosphere", atmosphere)
    gen = generator("rng", rng)

    n_ep = int(np.floor(duration_s / interval_s + 1e-9)) + 1
    allsats = gnss_constellation(prof.systems, lon_deg=traj.lon_deg)
    n_ant = lever.shape[0]
    n_rx = n_ant + (base_off is not None)
    _check_observation_count(n_ep, len(allsats), n_rx)
    t_rel: NDArray[np.float64] = np.arange(n_ep, dtype=np.float64) * interval_s
    t_s = start_s + t_rel
    dt_rx = gen.uniform(-1e-7, 1e-7, size=(n_rx,))
    sat_clk = gen.uniform(-1e-4, 1e-4, size=len(allsats))
    nav_path = folder / "nav.rnx"
    write_nav_from_constellation(
        nav_path, allsats, T0, start_s=start_s, span_s=float(t_rel[-1]) + 1.0, clock_bias_s=sat_clk,
        klobuchar=KLOBUCHAR if atmosphere else None,
    )  # fmt: skip
    nav = nav_input(read_nav(nav_path)).navigation()
    times = T0 + (t_s * 1e9).astype("timedelta64[ns]")
    t_ns = gps_ns(times)

    pos, enu, eul, base_ecef = _receiver_positions(traj, t_rel, lever, base_off)
    heading = -eul[:, 0]

    # which satellites to write: above the mask at the base (or antenna 0) at some epoch
    ref = n_ant if base_off is not None else 0
    sats, channels = _satellites_in_view(
        nav, allsats, t_ns, pos[:, ref, 0], float(dt_rx[ref]), elevation_min_deg
    )
    lam = wavelengths_m(sats, channels, n_freq)
    valid, seen, rho, clk, rate = ranges_and_rates(nav, sats, t_ns, pos, dt_rx)
    el_deg = np.where(valid[:, :, 0], np.degrees(seen.elevation_rad[:, :, 0]), -90.0)
    az_deg = np.degrees(seen.azimuth_rad[:, :, 0])
    visible = _unblocked(el_deg > elevation_min_deg, block, t_rel, heading, el_deg, az_deg, n_ant)

    iono, tropo = _atmosphere_delays(atmosphere, pos, el_deg, az_deg, t_ns, lam)
    n_cycles, lli, applied = _carrier_cycles(gen, visible, prof, interval_s, lam, sats, n_freq)

    geo = rho + _C * (dt_rx[None, :, None] - clk)
    sig_code = prof.sigma_m(prof.code_sigma_m, el_deg)[..., None]
    sig_phase = prof.sigma_m(prof.phase_sigma_m, el_deg)[..., None]
    code, phase, doppler = observables(
        gen, geo, tropo, iono, lam, rate, sig_code, sig_phase, prof.doppler_sigma_hz
    )
    phase = phase + n_cycles
    snr = np.broadcast_to((30.0 + 20.0 * np.sin(np.radians(np.maximum(el_deg, 0.0))))[..., None], phase.shape)
    ok4 = (visible & valid[:, :, 0])[..., None] & np.isfinite(lam)[None, None]
    code, phase, doppler, snr = (np.where(ok4, x, np.nan) for x in (code, phase, doppler, snr))

    paths = [folder / ("base.rnx" if r == n_ant else f"ant{r}.rnx") for r in range(n_rx)]
    lli_written = np.where(ok4, lli, 0)
    for r, p in enumerate(paths):
        write_receiver_obs(
            p, times, sats, n_freq, tuple(x[:, r] for x in (code, phase, doppler, snr)), lli_written[:, r],
            pos[0, r, 0], "BASE" if r == n_ant else f"ANT{r}", channels,
        )  # fmt: skip

    ant_ecef = pos[:, :n_ant, 0]
    baselines, rover = _truth_baselines(ant_ecef, base_ecef)
    return SimulatedPlatform(
        obs_paths=tuple(paths[:n_ant]),
        base_path=paths[n_ant] if base_off is not None else None,
        nav_path=nav_path,
        time=times,
        time_s=t_rel,
        sats=tuple(sats),
        position_enu_m=enu,
        euler_gost_deg=eul,
        heading_deg=np.where(heading >= 180.0, heading - 360.0, heading),
        pitch_deg=eul[:, 1].copy(),
        roll_deg=eul[:, 2].copy(),
        antenna_ecef_m=ant_ecef,
        base_ecef_m=base_ecef,
        baselines_enu_m=baselines,
        rover_enu_m=rover,
        visible=visible & valid[:, :, 0],
        slips=tuple(applied),
        outage_ends_s=tuple(float(b) for _, b in block.outages_s),
        elevation_deg=el_deg,
    )
