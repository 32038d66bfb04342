"""Simulated antenna arrays written as RINEX 3 files with a known truth: a static or rotating platform at a
fixed point, nominal GPS, GLONASS, Galileo, BeiDou and QZSS orbits written as broadcast records, every
range computed from those records (light time, Earth rotation, satellite clocks), independent receiver
clocks in code and phase, white code, phase and Doppler noise, integer ambiguities with optional slips
(:func:`simulate_gnss_rinex`; :func:`simulate_rinex_array` is its GPS L1 form).

:func:`write_array_rinex` writes the far-field measurements of :func:`gnssatt.sim.simulate_array` (GPS L1,
the two-body orbits themselves, no light time) for tests of the phase-only estimators."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from os import PathLike
from pathlib import Path

import numpy as np
from numpy.typing import ArrayLike, NDArray

from gnssatt import _core, sim
from gnssatt._arrays import flag, folder_path, generator, instance, integer, sat_list, scalar, shaped
from gnssatt.errors import InvalidInputError, InvalidTypeError, WorkLimitError
from gnssatt.rinex.nav import nav_input
from gnssatt.rinex.writer import MAX_SPAN_S, write_nav_from_constellation, write_obs
from gnssatt.rotation import rotation_from_euler

__all__ = [
    "KLOBUCHAR",
    "SIM_CODES",
    "SimulatedGnss",
    "SimulatedRinex",
    "gnss_constellation",
    "simulate_gnss_rinex",
    "simulate_rinex_array",
    "write_array_rinex",
]

T0 = np.datetime64("2024-03-01T10:00:00", "ns")


@dataclass(frozen=True)
class SimulatedRinex:
    """Files and truth of :func:`simulate_rinex_array`.

    Attributes
    ----------
    obs_paths
        One RINEX 3 observation file per antenna, the reference antenna first.
    nav_path
        RINEX 3 GPS navigation file.
    time
        (n_ep,) GPST labels, ``datetime64[ns]``.
    euler_gost_deg
        (n_ep, 3) true eq. (5) angles ``(psi, theta, phi)`` (compass heading ``-psi``), degrees.
    baselines_enu_m
        (n_ep, n_ant - 1, 3) true baselines in East-North-Up, m.
    sats
        Satellites written.
    """

    obs_paths: tuple[Path, ...]
    nav_path: Path
    time: NDArray[np.datetime64]
    euler_gost_deg: NDArray[np.float64]
    baselines_enu_m: NDArray[np.float64]
    sats: tuple[str, ...]


#: Accepted magnitudes: antenna coordinates (m), angles (degrees), noise (m), times after T0 (s, ten
#: years), epoch spacing (s, a day) and number of epochs.
MAX_ANTENNA_M = 1e4
MAX_ANGLE_DEG = 3600.0
MAX_SIGMA_M = 1e3
MAX_START_S = 3.2e8
MAX_INTERVAL_S = 86400.0
MAX_EPOCHS = 100_000


def simulate_rinex_array(
    folder: str | PathLike[str],
    antennas_body_m: ArrayLike,
    euler_gost_deg: ArrayLike,
    *,
    interval_s: float = 1.0,
    rng: int | np.random.Generator | None = None,
    n_sats: int | None = None,
    code_sigma_m: float = 0.3,
    phase_sigma_m: float = 0.002,
    elevation_min_deg: float = 10.0,
    lat_deg: float = 50.0,
    lon_deg: float = 36.2,
    start_s: float = 0.0,
) -> SimulatedRinex:
    """Simulate a GPS L1 array and write its RINEX 3 files into ``folder``: :func:`simulate_gnss_rinex`
    with ``systems="G"``, ``frequencies=1``, no atmosphere, receiver clocks within 1e-7 s and the file
    names ``ant<i>.24o`` and ``sim.24n``.

    Parameters
    ----------
    folder
        Existing folder for the files ``ant<i>.24o`` and ``sim.24n``.
    antennas_body_m
        (n_ant, 3) antenna positions in the body frame of Bunyaeva et al. (X nose, Y up, Z right wing), the
        first the reference antenna, m.
    euler_gost_deg
        (n_ep, 3) eq. (5) angles per epoch, degrees (a rotating platform), or (3,) for a static one.
    interval_s
        Epoch spacing, s; the number of epochs is that of ``euler_gost_deg`` (static: 10).
    rng
        Seed or generator of the noise, ambiguities and clocks: an int (the former ``seed``, the same
        draws), a Generator (advanced) or None (fresh entropy).
    n_sats
        Keep only this many satellites (the highest at the first epoch); None keeps all above the mask.
    code_sigma_m, phase_sigma_m
        White noise standard deviations, m.
    elevation_min_deg
        Satellites below this elevation at any epoch are left out.
    lat_deg, lon_deg
        Position of the platform.
    start_s
        Time of the first epoch after the scenario epoch ``2024-03-01T10:00:00`` GPST, s (other
        satellite geometries).

    Raises
    ------
    InvalidTypeError
        An argument of the wrong kind (``folder`` not a path, arrays not real, counts not integers).
    InvalidInputError
        ``folder`` not an existing folder; ``antennas_body_m`` not (n_ant >= 2, 3) or beyond
        ``MAX_ANTENNA_M``; ``euler_gost_deg`` not (3,) or (n_ep >= 1, 3) within ``MAX_ANGLE_DEG``;
        ``interval_s`` not in ``[MIN_INTERVAL_S, MAX_INTERVAL_S]``; ``rng`` a negative integer; ``n_sats``
        below 1; noise levels negative or above ``MAX_SIGMA_M``; angles out of range; ``|start_s|`` above
        ``MAX_START_S``.
    WorkLimitError
        More than ``MAX_EPOCHS`` epochs.
    """
    eul = shaped("euler_gost_deg", euler_gost_deg, "(3,) or (n_ep >= 1, 3)", (3,), (None, 3))
    if eul.shape == (3,):
        eul = np.tile(eul, (10, 1))
    if eul.shape[0] < 1:
        raise InvalidInputError(f"expected euler_gost_deg of shape (3,) or (n_ep >= 1, 3), got {eul.shape}")
    if eul.shape[0] > MAX_EPOCHS:
        raise WorkLimitError(f"euler_gost_deg has {eul.shape[0]} epochs, above the limit of {MAX_EPOCHS}")
    gen = generator("rng", rng)
    ant = shaped("antennas_body_m", antennas_body_m, "(n_ant >= 2, 3)", (None, 3))
    s = simulate_gnss_rinex(
        folder, ant, eul, systems="G", frequencies=1, interval_s=interval_s, start_s=start_s, rng=gen,
        receiver_clock_s=gen.uniform(-1e-7, 1e-7, size=len(ant)), code_sigma_m=code_sigma_m,
        phase_sigma_m=phase_sigma_m, elevation_min_deg=elevation_min_deg, lat_deg=lat_deg, lon_deg=lon_deg,
        n_sats=n_sats, file_names=("ant{i}.24o", "sim.24n"), atmosphere=False,
    )  # fmt: skip
    return SimulatedRinex(s.obs_paths, s.nav_path, s.time, s.euler_gost_deg, s.baselines_enu_m, s.sats)


def write_array_rinex(
    folder: str | PathLike[str],
    measurements: sim.ArrayMeasurements,
    t_s: ArrayLike,
    constellation: sim.Constellation,
    sat_ids: Sequence[str],
    receiver: sim.GroundReceiver,
) -> tuple[tuple[Path, ...], Path]:
    """Write simulated array measurements as RINEX 3: ``ant<i>.24o`` per antenna (C1C, L1C, D1C of the
    satellites ``sat_ids``, the measurements' column order) and ``sim.24n``, GPS broadcast records of
    ``constellation`` that reproduce its orbits. ``t_s`` (n_ep,) are seconds after ``T0`` (GPST).

    Returns the observation paths (reference antenna first) and the navigation path.

    Raises
    ------
    InvalidTypeError
        ``folder`` not a path; ``measurements``, ``constellation`` or ``receiver`` not of their classes;
        ``sat_ids`` not a list of satellite ids; ``t_s`` not real.
    InvalidInputError
        ``folder`` not an existing folder; ``sat_ids`` or ``t_s`` not matching the measurements' satellites
        and epochs; ``t_s`` not finite or beyond ``MAX_START_S``.
    """
    folder = folder_path("folder", folder)
    measurements = instance("measurements", measurements, sim.ArrayMeasurements, "sim.ArrayMeasurements")
    constellation = instance("constellation", constellation, sim.Constellation, "a sim.Constellation")
    receiver = instance("receiver", receiver, sim.GroundReceiver, "a sim.GroundReceiver")
    n_ep, _, n_sat = measurements.pseudorange_m.shape
    sat_ids = sat_list("sat_ids", sat_ids)
    if len(sat_ids) != n_sat:
        raise InvalidInputError(
            f"expected {n_sat} sat_ids (the measurements' satellites), got {len(sat_ids)}"
        )
    t_s = shaped("t_s", t_s, f"({n_ep},)", (n_ep,))
    if np.any(np.abs(t_s) > MAX_START_S):
        raise InvalidInputError(f"expected |t_s| <= {MAX_START_S} s, got {np.max(np.abs(t_s))} s")
    nav = folder / "sim.24n"
    write_nav_from_constellation(nav, constellation, T0)
    times = T0 + (np.asarray(t_s, dtype=np.float64) * 1e9).astype("timedelta64[ns]")
    paths = []
    for i in range(measurements.pseudorange_m.shape[1]):
        p = folder / f"ant{i}.24o"
        obs = {
            "C1C": measurements.pseudorange_m[:, i],
            "L1C": measurements.carrier_phase_cycles[:, i],
            "D1C": measurements.doppler_hz[:, i],
        }
        write_obs(p, times, list(sat_ids), obs, approx_position_m=receiver.position_ecef_m)
        paths.append(p)
    return tuple(paths), nav


#: Observation codes the multi-GNSS simulation writes per system and slot (RINEX 3.04 band + attribute):
#: GPS L1 C/A, L2 P(Y) semi-codeless, L5 Q; GLONASS G1 C/A, G2 P (no G3: FDMA only); Galileo E1 C, E5b Q,
#: E5a Q; BeiDou B1I, B2I, B3I; QZSS L1 C/A, L2C (L), L5 Q.
SIM_CODES: dict[str, tuple[str | None, str | None, str | None]] = {
    "G": ("1C", "2W", "5Q"),
    "R": ("1C", "2P", None),
    "E": ("1C", "7Q", "5Q"),
    "C": ("2I", "7I", "6I"),
    "J": ("1C", "2L", "5Q"),
}
#: Broadcast Klobuchar coefficients the simulation writes and applies (alpha0..3 in s, s/sc, s/sc^2,
#: s/sc^3; beta0..3 in s, ...): typical GPS values of moderate solar activity, exact in the 12.4E field.
KLOBUCHAR = (1.1176e-08, 7.4506e-09, -5.9605e-08, -5.9605e-08, 9.0112e04, 0.0, -1.9661e05, -6.5536e04)
#: Largest receiver or satellite clock offset accepted, s; shortest epoch spacing (1 kHz), s; largest
#: platform height above or below the ellipsoid, m (aircraft and balloons; orbits are another simulator).
MAX_CLOCK_S = 1e-3
MIN_INTERVAL_S = 1e-3
MAX_HEIGHT_M = 1e5
_C = 299_792_458.0
#: Half-step of the central difference that gives the Doppler, s (its truncation error, rho''' h^2 / 6,
#: is below 1e-9 m/s).
DOPPLER_HALF_STEP_S = 0.05


@dataclass(frozen=True)
class SimulatedGnss:
    """Files and truth of :func:`simulate_gnss_rinex`.

    Attributes
    ----------
    obs_paths
        One RINEX 3.04 observation file per antenna (``gnss<i>.rnx``), the reference antenna first.
    nav_path
        Mixed RINEX 3.04 navigation file (``gnss_nav.rnx``) whose records gave every range.
    time
        (n_ep,) epoch labels (GPST), ``datetime64[ns]``; every receiver labels the same epochs.
    sats
        Satellites written (above the mask at every epoch at the reference antenna).
    euler_gost_deg
        (n_ep, 3) true eq. (5) angles ``(psi, theta, phi)`` of the platform (body -> ENU), degrees.
    baselines_enu_m
        (n_ep, n_ant - 1, 3) true baselines antenna i - antenna 0 in East-North-Up at antenna 0, m.
    antenna_ecef_m
        (n_ep, n_ant, 3) true antenna positions, ECEF, m (the header position is that of epoch 0).
    receiver_clock_s
        (n_ant,) receiver clock offsets: each receiver labels ``T`` the true instant ``T - clock``, s.
    satellite_clock_s
        (n_sat,) broadcast clock bias ``af0`` (GLONASS ``-tau_n``) written, s.
    glonass_channels
        GLONASS id -> FDMA channel (written as ``GLONASS SLOT / FRQ #`` and in the records).
    ambiguities
        (n_ant, n_sat, 3) integer phase ambiguities of the first epoch, cycles.
    slips
        The slips applied: (epoch, antenna, satellite, slot, jump in cycles).
    elevation_deg
        (n_ep, n_sat) elevation at the reference antenna, degrees.
    """

    obs_paths: tuple[Path, ...]
    nav_path: Path
    time: NDArray[np.datetime64]
    sats: tuple[str, ...]
    euler_gost_deg: NDArray[np.float64]
    baselines_enu_m: NDArray[np.float64]
    antenna_ecef_m: NDArray[np.float64]
    receiver_clock_s: NDArray[np.float64]
    satellite_clock_s: NDArray[np.float64]
    glonass_channels: dict[str, int]
    ambiguities: NDArray[np.int64]
    slips: tuple[tuple[int, int, str, int, int], ...]
    elevation_deg: NDArray[np.float64]


@dataclass(frozen=True)
class TransmitGeometry:
    """Satellites seen at receptions of shape ``S`` (then one satellite axis): transmit-time positions in
    the ECEF frame of reception (``S + (n_sat, 3)``, m), satellite clocks (s), elevations and azimuths
    (rad) at each receiver; NaN where no record is usable."""

    position_m: NDArray[np.float64]
    clock_s: NDArray[np.float64]
    elevation_rad: NDArray[np.float64]
    azimuth_rad: NDArray[np.float64]


#: Most evaluations (reception x satellite) per call of the engine, bounding the arrays of one call.
_CHUNK = 200_000


def transmit_geometry(
    nav: _core.Navigation, sats: list[str], t_rx_ns: NDArray[np.int64], receiver_m: NDArray[np.float64],
    receiver_clock_s: NDArray[np.float64],
) -> tuple[NDArray[np.bool_], TransmitGeometry]:  # fmt: skip
    """Every satellite of ``sats`` at every reception (labels ``t_rx_ns`` of shape ``S``, receivers
    ``S + (3,)`` ECEF m with clocks ``S`` s): the engine's light time and Earth rotation
    (``_core.gnss_transmit_states``), in chunks of at most ``_CHUNK`` evaluations. Shared by the
    simulators of :mod:`gnssatt.sim`, which check their inputs first."""
    shape = t_rx_ns.shape
    n_sat = len(sats)
    t = np.repeat(t_rx_ns.reshape(-1).astype(np.int64), n_sat)
    rx = np.repeat(np.asarray(receiver_m, dtype=np.float64).reshape(-1, 3), n_sat, axis=0)
    clk = np.repeat(np.asarray(receiver_clock_s, dtype=np.float64).reshape(-1), n_sat)
    ids = sats * int(np.prod(shape))
    parts = []
    for a in range(0, len(t), _CHUNK):
        z = slice(a, a + _CHUNK)
        parts.append(_core.gnss_transmit_states(nav, ids[z], t[z], rx[z], clk[z]))
    p, c, el, az, ok = (
        np.concatenate([getattr(q, k) for q in parts])
        for k in ("position_m", "clock_s", "elevation_rad", "azimuth_rad", "valid")
    )
    full = (*shape, n_sat)
    geometry = TransmitGeometry(p.reshape(*full, 3), c.reshape(full), el.reshape(full), az.reshape(full))
    return ok.reshape(full), geometry


# --- the measurement model both simulators write (simulate_gnss_rinex here, simulate_platform) -------------


def wavelengths_m(sats: list[str], channels: dict[str, int], n_freq: int) -> NDArray[np.float64]:
    """Carrier wavelengths (n_sat, 3) m of the simulated slots (``SIM_CODES``); NaN for a slot a satellite
    does not transmit or beyond the first ``n_freq``."""
    from gnssatt.rinex.signals import slot_frequency_hz

    lam = np.full((len(sats), 3), np.nan)
    for k, s in enumerate(sats):
        for slot in range(n_freq):
            if SIM_CODES[s[0]][slot] is not None:
                f = slot_frequency_hz(s[0], slot, channels.get(s))
                lam[k, slot] = _C / f if f else np.nan
    return lam


def ranges_and_rates(
    nav: _core.Navigation,
    sats: list[str],
    t_ns: NDArray[np.int64],
    receiver_m: NDArray[np.float64],
    receiver_clock_s: NDArray[np.float64],
) -> tuple[
    NDArray[np.bool_], TransmitGeometry, NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]
]:
    """Every satellite seen by every receiver at the labels ``t_ns`` (n_ep,) and half a Doppler step either
    side: receivers ``receiver_m`` (n_ep, n_rx, 3 instants, 3) ECEF m with clocks ``receiver_clock_s``
    (n_rx,) s. Returns the validity and geometry of :func:`transmit_geometry` (n_ep, n_rx, 3, n_sat), the
    geometric range (n_ep, n_rx, n_sat) m and the satellite clock s at the label, and the range rate less
    the satellite clock's drift (central difference), m/s."""
    h_ns = round(DOPPLER_HALF_STEP_S * 1e9)
    instants = receiver_m.shape[:3]
    t_rx = np.ascontiguousarray(np.broadcast_to(t_ns[:, None, None] + np.array([0, -h_ns, h_ns]), instants))
    clock = np.broadcast_to(receiver_clock_s[None, :, None], instants)
    valid, seen = transmit_geometry(nav, sats, t_rx, receiver_m, clock)
    rng_m = np.linalg.norm(seen.position_m - receiver_m[:, :, :, None, :], axis=-1)  # (n_ep, n_rx, 3, n_sat)
    rate = ((rng_m[:, :, 2] - _C * seen.clock_s[:, :, 2]) - (rng_m[:, :, 1] - _C * seen.clock_s[:, :, 1])) / (
        2 * DOPPLER_HALF_STEP_S
    )
    return valid, seen, rng_m[:, :, 0], seen.clock_s[:, :, 0], rate


def klobuchar_m(
    t_ns: NDArray[np.int64], lat_rad: float, lon_rad: float, elevation_rad: NDArray[np.float64],
    azimuth_rad: NDArray[np.float64], lam: NDArray[np.float64],
) -> NDArray[np.float64]:  # fmt: skip
    """Ionospheric group delay (n_ep, n_rx, n_sat, 3) m of each carrier (``KLOBUCHAR``, the coefficients
    the navigation file gives: exact in its 12.4E fields) at the elevations and azimuths (n_ep, n_rx,
    n_sat) rad; L1's frequency where a slot has no carrier."""
    freq = np.where(np.isfinite(lam), _C / lam, 1575.42e6)  # (n_sat, 3)
    shape = (*elevation_rad.shape, 3)
    el_b, az_b, f_b = (
        np.broadcast_to(x, shape).ravel() for x in (elevation_rad[..., None], azimuth_rad[..., None], freq)
    )
    t_b = np.broadcast_to(t_ns[:, None, None, None], shape).ravel().astype(np.int64)
    delay = _core.gnss_klobuchar_delay(np.asarray(KLOBUCHAR), t_b, lat_rad, lon_rad, az_b, el_b, f_b)
    return delay.reshape(shape)


def observables(
    gen: np.random.Generator, geometric_m: NDArray[np.float64], tropo_m: NDArray[np.float64],
    iono_m: NDArray[np.float64], lam: NDArray[np.float64], rate_m_s: NDArray[np.float64],
    code_sigma_m: float | NDArray[np.float64], phase_sigma_m: float | NDArray[np.float64],
    doppler_sigma_hz: float,
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:  # fmt: skip
    """Code (m), carrier phase (cycles, without its integer ambiguity) and Doppler (Hz), each (n_ep, n_rx,
    n_sat, 3), from the geometric terms (range plus clocks, n_ep, n_rx, n_sat) m, the troposphere (same
    shape) and the ionosphere (one per carrier) m: code delayed and phase advanced by the ionosphere, white
    noise drawn from ``gen`` in that order."""
    shape = iono_m.shape
    code = geometric_m[..., None] + tropo_m[..., None] + iono_m + code_sigma_m * gen.standard_normal(shape)
    phase_m = (
        geometric_m[..., None] + tropo_m[..., None] - iono_m + phase_sigma_m * gen.standard_normal(shape)
    )
    doppler = -rate_m_s[..., None] / lam + doppler_sigma_hz * gen.standard_normal(shape)
    return code, phase_m / lam, doppler


def write_receiver_obs(
    path: Path, times: NDArray[np.datetime64], sats: list[str], n_freq: int,
    observations: tuple[NDArray[np.float64], ...], lli: NDArray[np.float64],
    approx_position_m: NDArray[np.float64], marker_name: str, channels: dict[str, int],
) -> None:  # fmt: skip
    """One receiver's observation file: ``observations`` = (code, phase, Doppler, SNR), each (n_ep, n_sat,
    3), and the phases' loss-of-lock indicators ``lli`` (n_ep, n_sat, 3), as the ``SIM_CODES`` columns."""
    n_ep, n_sat = len(times), len(sats)
    obs: dict[str, NDArray[np.float64]] = {}
    flags: dict[str, NDArray[np.float64]] = {}
    for k, s in enumerate(sats):
        for slot, band in enumerate(SIM_CODES[s[0]][:n_freq]):
            if band is None:
                continue
            for kind, arr in zip("CLDS", observations, strict=True):
                col = obs.setdefault(kind + band, np.full((n_ep, n_sat), np.nan))
                col[:, k] = arr[:, k, slot]
            flags.setdefault("L" + band, np.zeros((n_ep, n_sat)))[:, k] = lli[:, k, slot]
    write_obs(
        path, times, sats, obs, approx_position_m=approx_position_m, marker_name=marker_name, lli=flags,
        glonass_channels=channels,
    )  # fmt: skip


def _slips(value: object) -> list[tuple[int, int, str, int]]:
    """``value`` as (epoch >= 0, antenna >= 0, satellite id, slot >= 0) tuples (ranges checked later)."""
    if isinstance(value, str) or not isinstance(value, Sequence):
        raise InvalidTypeError(
            f"expected slips as a sequence of (epoch, antenna, satellite, slot), got {type(value).__name__}"
        )
    out = []
    for k, slip in enumerate(value):
        if not (isinstance(slip, tuple | list) and len(slip) == 4 and isinstance(slip[2], str)):
            raise InvalidInputError(f"expected slips[{k}] as (epoch, antenna, satellite, slot), got {slip!r}")
        e, i, slot = (integer(f"slips[{k}]", x, minimum=0) for x in (slip[0], slip[1], slip[3]))
        out.append((e, i, slip[2], slot))
    return out


def gnss_constellation(systems: str = "GRECJ", *, lon_deg: float = 36.2) -> sim.Constellation:
    """Nominal orbits of the systems named: GPS (:func:`~gnssatt.sim.gps_nominal`), GLONASS
    (:func:`~gnssatt.sim.glonass_nominal`, FDMA channels per slot), Galileo (Walker 56: 24/3/1 at
    29,600 km, E01-E24), BeiDou MEO (Walker 55: 24/3/1 at 27,906 km, C19-C42; no GEO), QZSS (three
    circular geosynchronous orbits inclined 41 degrees on one figure-eight centred on ``lon_deg``, J01-J03).

    Raises
    ------
    InvalidInputError
        ``systems`` not distinct letters of ``"GRECJ"``.
    """
    letters = instance("systems", systems, str, "letters of 'GRECJ'")
    if not letters or any(c not in "GRECJ" for c in letters) or len(set(letters)) != len(letters):
        raise InvalidInputError(f"expected systems as distinct letters of 'GRECJ', got {systems!r}")
    lon = scalar("lon_deg", lon_deg, minimum=-360.0, maximum=360.0)
    parts = []
    for s in "GRECJ":
        if s not in letters:
            continue
        if s == "G":
            c = sim.gps_nominal()
        elif s == "R":
            c = sim.glonass_nominal()
        elif s == "E":
            c = sim.walker(24, 3, 1, inclination_deg=56.0, semi_major_axis_m=29_600_318.0, prefix="E")
        elif s == "C":
            w = sim.walker(24, 3, 1, inclination_deg=55.0, semi_major_axis_m=27_906_100.0, prefix="C")
            c = sim.Constellation(
                tuple(f"C{k + 19:02d}" for k in range(24)), w.orbits, w.frequencies_hz, w.slots,
                w.glonass_channels,
            )  # fmt: skip
        else:
            # the figure-eight of a geosynchronous orbit is centred on RAAN + u0 (ECEF at t = 0)
            raan = np.radians(lon + np.array([0.0, 120.0, 240.0]))
            orbits = sim.KeplerOrbits.circular(
                np.full(3, 42_164_200.0), np.full(3, np.radians(41.0)), raan, -raan + np.radians(lon)
            )
            c = sim.Constellation(
                ("J01", "J02", "J03"), orbits, {"L1": np.full(3, 1575.42e6)}, ("",) * 3, np.zeros(3, np.int64)
            )
        parts.append(sim.Constellation(c.ids, c.orbits, {}, c.slots, c.glonass_channels))
    out = parts[0]
    for p in parts[1:]:
        out = out + p
    return out


def _checked_attitudes(euler_gost_deg: ArrayLike, n_epochs: int) -> NDArray[np.float64]:
    """(n_epochs, 3) attitudes: one row repeated over ``n_epochs``, or one row per epoch (whose count
    then replaces ``n_epochs``)."""
    eul = shaped("euler_gost_deg", euler_gost_deg, "(3,) or (n_epochs, 3)", (3,), (None, 3))
    if eul.ndim == 2:
        n_epochs = eul.shape[0]
    n_epochs = integer("n_epochs", n_epochs, minimum=1)
    if n_epochs > MAX_EPOCHS:
        source = "n_epochs" if eul.ndim == 1 else "n_epochs (the rows of euler_gost_deg)"
        raise WorkLimitError(f"expected {source} <= {MAX_EPOCHS} (MAX_EPOCHS), got {n_epochs}")
    if eul.ndim == 1:
        eul = np.tile(eul, (n_epochs, 1))
    if np.any(np.abs(eul) > MAX_ANGLE_DEG):
        raise InvalidInputError(f"expected |euler_gost_deg| <= {MAX_ANGLE_DEG} degrees")
    return eul


def _check_file_names(file_names: object) -> None:
    if not (
        isinstance(file_names, tuple)
        and len(file_names) == 2
        and all(isinstance(x, str) and x and "/" not in x for x in file_names)
        and "{i}" in file_names[0]
    ):
        raise InvalidInputError(
            f"expected file_names as two file names, the first with '{{i}}', got {file_names!r}"
        )


def _receiver_clocks(
    gen: np.random.Generator, receiver_clock_s: ArrayLike | None, n_ant: int
) -> NDArray[np.float64]:
    """The antennas' receiver clocks, s: as given, or drawn uniform in +-1e-4 s."""
    if receiver_clock_s is None:
        # a shape tuple: with an untyped int size numpy's stubs pick the overload of a single float draw
        return gen.uniform(-1e-4, 1e-4, size=(n_ant,))
    dt_rx = shaped("receiver_clock_s", receiver_clock_s, f"({n_ant},)", (n_ant,))
    if np.any(np.abs(dt_rx) > MAX_CLOCK_S):
        raise InvalidInputError(f"expected |receiver_clock_s| <= {MAX_CLOCK_S} s")
    return dt_rx


def _kept_satellites(
    el: NDArray[np.float64], elevation_min_deg: float, n_sats: int | None
) -> NDArray[np.bool_]:
    """The satellites above the mask at every epoch (elevations ``el`` (n_ep, n_all), degrees); with
    ``n_sats``, the ``n_sats`` highest of them at the first epoch."""
    keep: NDArray[np.bool_] = np.all(el > elevation_min_deg, axis=0)
    if n_sats is not None:
        order = np.argsort(-np.where(keep, el[0], -90.0))
        keep = np.zeros_like(keep)
        keep[order[: min(n_sats, int(np.all(el > elevation_min_deg, axis=0).sum()))]] = True
    if not keep.any():
        raise InvalidInputError(f"no satellite above elevation_min_deg = {elevation_min_deg} at every epoch")
    return keep


def _applied_slips(
    gen: np.random.Generator,
    slip_list: list[tuple[int, int, str, int]],
    shape: tuple[int, int, int, int],
    sats: list[str],
    lam: NDArray[np.float64],
    n_freq: int,
) -> tuple[NDArray[np.int64], NDArray[np.float64], list[tuple[int, int, str, int, int]]]:
    """Cycle jumps (n_ep, n_ant, n_sat, 3) from each slip's epoch on, its loss-of-lock flags and the
    slips as applied (epoch, antenna, satellite, slot, cycles: 1 to 49 of a random sign)."""
    n_epochs, n_ant = shape[:2]
    jumps = np.zeros(shape, dtype=np.int64)
    lli = np.zeros(shape)
    applied = []
    for slip in slip_list:
        e, i, s, slot = slip
        if not (e < n_epochs and i < n_ant and s in sats and slot < n_freq) or np.isnan(
            lam[sats.index(s), slot]
        ):
            raise InvalidInputError(
                f"expected slips of a simulated epoch, antenna, satellite and slot, got {slip!r}"
            )
        size = int(gen.integers(1, 50)) * (1 if gen.random() < 0.5 else -1)
        jumps[e:, i, sats.index(s), slot] += size
        lli[e, i, sats.index(s), slot] = 1
        applied.append((int(e), int(i), str(s), int(slot), size))
    return jumps, lli, applied


def checked_antennas(antennas_body_m: ArrayLike, n_max: int, max_m: float) -> NDArray[np.float64]:
    """The (2..n_max, 3) body-frame antenna positions, m, each coordinate within ``max_m``; shared by
    :func:`simulate_gnss_rinex` and :func:`~gnssatt.sim.platforms.simulate_platform`."""
    ant = shaped("antennas_body_m", antennas_body_m, "(n_ant, 3)", (None, 3))
    if not 2 <= ant.shape[0] <= n_max or np.any(np.abs(ant) > max_m):
        raise InvalidInputError(
            f"expected antennas_body_m of shape (2..{n_max}, 3) within {max_m} m, got {ant.shape}"
        )
    return ant


def _check_span(n_epochs: int, interval_s: float) -> None:
    """Refuse a session longer than :data:`MAX_SPAN_S` (the navigation file's records cover it)."""
    if (n_epochs - 1) * interval_s > MAX_SPAN_S:
        raise WorkLimitError(
            f"expected n_epochs x interval_s <= {MAX_SPAN_S} s (MAX_SPAN_S), got {n_epochs} epochs every "
            f"{interval_s} s"
        )


def _checked_sigmas(code_sigma_m: float, phase_sigma_m: float, doppler_sigma_hz: float) -> dict[str, float]:
    """The noise sigmas of :func:`simulate_gnss_rinex` by parameter name, each within ``MAX_SIGMA_M``."""
    return {
        name: scalar(name, v, minimum=0.0, maximum=MAX_SIGMA_M, unit=unit)
        for name, v, unit in (
            ("code_sigma_m", code_sigma_m, "m"),
            ("phase_sigma_m", phase_sigma_m, "m"),
            ("doppler_sigma_hz", doppler_sigma_hz, "Hz"),
        )
    }


def _ground_atmosphere(
    atmosphere: bool, lat_deg: float, lon_deg: float, height_m: float, seen: TransmitGeometry,
    t_ns: NDArray[np.int64], lam: NDArray[np.float64],
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:  # fmt: skip
    """Tropospheric delay (epochs, antennas, satellites) and ionospheric group delay of each carrier
    (..., 3), m, at the site (the labels' receptions of ``seen``); zeros without ``atmosphere``."""
    from gnssatt.sim.atmosphere import troposphere_delay_m

    el_i, az_i = seen.elevation_rad[:, :, 0], seen.azimuth_rad[:, :, 0]
    iono: NDArray[np.float64] = np.zeros((*el_i.shape, 3))
    tropo: NDArray[np.float64] = np.zeros(el_i.shape)
    if atmosphere:
        lat, lon = np.radians(lat_deg), np.radians(lon_deg)
        tropo = troposphere_delay_m(lat, height_m, el_i)
        iono = klobuchar_m(t_ns, lat, lon, el_i, az_i, lam)
    return tropo, iono


def simulate_gnss_rinex(
    folder: str | PathLike[str],
    antennas_body_m: ArrayLike,
    euler_gost_deg: ArrayLike,
    *,
    systems: str = "GRECJ",
    frequencies: int = 3,
    n_epochs: int = 10,
    interval_s: float = 1.0,
    start_s: float = 0.0,
    rng: int | np.random.Generator | None = None,
    receiver_clock_s: ArrayLike | None = None,
    code_sigma_m: float = 0.3,
    phase_sigma_m: float = 0.002,
    doppler_sigma_hz: float = 0.05,
    elevation_min_deg: float = 10.0,
    slips: Sequence[tuple[int, int, str, int]] = (),
    lat_deg: float = 50.0,
    lon_deg: float = 36.2,
    height_m: float = 150.0,
    n_sats: int | None = None,
    file_names: tuple[str, str] = ("gnss{i}.rnx", "gnss_nav.rnx"),
    atmosphere: bool = True,
) -> SimulatedGnss:
    """Simulate a multi-GNSS, multi-frequency antenna array and write it as RINEX 3.04 with its truth.

    Orbits (:func:`gnss_constellation`) become broadcast records (mixed navigation file,
    :func:`~gnssatt.rinex.writer.write_nav_from_constellation`, random satellite clocks); every range is
    then computed from those records as read back (the engine's ``_core.gnss_transmit_states``: light time,
    Earth rotation during it, satellite clock), so that an engine that reads the files sees
    consistent data. For antenna i with receiver clock ``dt_i`` and satellite clock ``dt_s``, at label T
    (true reception ``T - dt_i``), slot wavelength ``lambda``:
    ``P = rho + c (dt_i - dt_s) + I + T + e_P``,
    ``L = (rho + c (dt_i - dt_s) - I + T) / lambda + N + e_L / lambda`` (cycles, RINEX sign),
    ``D = -d(rho - c dt_s)/dt / lambda + e_D`` (Hz; the atmosphere's rate, below 1 mm/s, left out), C/N0
    ``30 + 20 sin(el)`` dB-Hz, with the ionosphere ``I`` and troposphere ``T`` of ``atmosphere``; no group
    delays (TGD/BGD 0).
    Codes per system and slot: :data:`SIM_CODES`.

    Parameters
    ----------
    folder
        Existing folder for ``gnss<i>.rnx`` and ``gnss_nav.rnx``.
    antennas_body_m
        (n_ant, 3) antenna positions in the body frame (as :func:`simulate_rinex_array`), 2 to 16 antennas.
    euler_gost_deg
        (3,) platform attitude (static) or (n_epochs, 3) per epoch, eq. (5) angles, degrees.
    systems
        Letters of the systems, from ``"GRECJ"``.
    frequencies
        Slots written, 1 to 3 (GLONASS has two).
    n_epochs, interval_s, start_s
        Number of epochs (taken from ``euler_gost_deg`` when it has a row per epoch), their spacing (s, from
        ``MIN_INTERVAL_S`` to ``MAX_INTERVAL_S``; the session at most ``MAX_SPAN_S``) and the time of the
        first epoch after ``2024-03-01T10:00:00`` GPST (s, other satellite geometries; ``|start_s|`` up
        to ``MAX_START_S``).
    rng
        Seed or generator of the clocks, ambiguities, noise and slip sizes.
    receiver_clock_s
        (n_ant,) receiver clock offsets, s; uniform in +-1e-4 s by default.
    code_sigma_m, phase_sigma_m, doppler_sigma_hz
        White noise of code (m), phase (m) and Doppler (Hz).
    elevation_min_deg
        Satellites below it at any epoch (at the reference antenna) are left out.
    slips
        (epoch, antenna, satellite id, slot): the ambiguity of that phase jumps by a random nonzero
        integer from that epoch on and the loss-of-lock indicator is 1 there.
    lat_deg, lon_deg, height_m
        Geodetic position of the platform's reference point (degrees, degrees within +-360, m within
        +-``MAX_HEIGHT_M``).
    n_sats
        Keep only this many satellites (the highest at the first epoch); None keeps all above the mask.
    file_names
        Names of the observation files (``{i}`` the antenna) and of the navigation file.
    atmosphere
        Delay code and advance phase by the broadcast Klobuchar ionosphere of :data:`KLOBUCHAR` (written in
        the navigation header, scaled to each carrier) and delay both by the standard troposphere of
        :mod:`gnssatt.sim.atmosphere`, at each antenna's elevation and azimuth; False: vacuum.

    Raises
    ------
    InvalidTypeError
        An argument of the wrong kind.
    InvalidInputError
        ``folder`` not an existing folder; shapes or ranges of the arguments (each named); a slip of an
        epoch, antenna, satellite or slot not simulated; no satellite above the mask.
    WorkLimitError
        More than ``MAX_EPOCHS`` epochs, or a session longer than ``MAX_SPAN_S``.
    """
    from gnssatt.rinex.nav import gps_ns, read_nav

    folder = folder_path("folder", folder)
    ant = checked_antennas(antennas_body_m, 16, MAX_ANTENNA_M)
    n_ant = ant.shape[0]
    eul = _checked_attitudes(euler_gost_deg, n_epochs)
    n_epochs = eul.shape[0]
    n_freq = integer("frequencies", frequencies, minimum=1, maximum=3)
    interval_s = scalar("interval_s", interval_s, minimum=MIN_INTERVAL_S, maximum=MAX_INTERVAL_S, unit="s")
    start_s = scalar("start_s", start_s, minimum=-MAX_START_S, maximum=MAX_START_S, unit="s")
    lat_deg = scalar("lat_deg", lat_deg, minimum=-90.0, maximum=90.0)
    lon_deg = scalar("lon_deg", lon_deg, minimum=-360.0, maximum=360.0)
    height_m = scalar("height_m", height_m, minimum=-MAX_HEIGHT_M, maximum=MAX_HEIGHT_M, unit="m")
    _check_span(n_epochs, interval_s)
    if n_sats is not None:
        n_sats = integer("n_sats", n_sats, minimum=1)
    slip_list = _slips(slips)
    _check_file_names(file_names)
    gen = generator("rng", rng)
    dt_rx = _receiver_clocks(gen, receiver_clock_s, n_ant)
    sig = _checked_sigmas(code_sigma_m, phase_sigma_m, doppler_sigma_hz)
    elevation_min_deg = scalar("elevation_min_deg", elevation_min_deg, minimum=-90.0, maximum=90.0)
    rx = sim.GroundReceiver(lat_deg=lat_deg, lon_deg=lon_deg, height_m=height_m)
    allsats = gnss_constellation(systems, lon_deg=lon_deg)
    t_s = start_s + np.arange(n_epochs) * interval_s
    atmosphere = flag("atmosphere", atmosphere)
    sat_clk = gen.uniform(-1e-4, 1e-4, size=len(allsats))
    nav_path = folder / file_names[1]
    write_nav_from_constellation(
        nav_path, allsats, T0, start_s=start_s, span_s=float(t_s[-1] - t_s[0]) + 1.0, clock_bias_s=sat_clk,
        klobuchar=KLOBUCHAR if atmosphere else None,
    )  # fmt: skip
    nav = nav_input(read_nav(nav_path)).navigation()  # converted once for every chunk and call
    times = T0 + (t_s * 1e9).astype("timedelta64[ns]")
    t_ns = gps_ns(times)
    rot = rotation_from_euler(eul).as_matrix()  # (n_ep, 3, 3) body -> ENU
    enu2ecef = rx.dcm_ecef_from_enu
    pos = rx.position_ecef_m[None, None, :] + np.einsum("ij,tjk,ak->tai", enu2ecef, rot, ant)
    ids = list(allsats.ids)
    # geometry of every satellite at the reference antenna: visibility
    ok, at_ref = transmit_geometry(nav, ids, t_ns, pos[:, 0], np.full(n_epochs, dt_rx[0]))
    el = np.where(ok, np.degrees(at_ref.elevation_rad), -90.0)
    keep = _kept_satellites(el, elevation_min_deg, n_sats)
    sats = [s for s, k in zip(ids, keep, strict=True) if k]
    n_sat = len(sats)
    channels = {s: int(allsats.glonass_channels[ids.index(s)]) for s in sats if s[0] == "R"}
    lam = wavelengths_m(sats, channels, n_freq)
    # every antenna at the label and half a Doppler step either side
    rx_pos = np.broadcast_to(pos[:, :, None, :], (n_epochs, n_ant, 3, 3))
    _, seen, rho, clk, rate = ranges_and_rates(nav, sats, t_ns, rx_pos, dt_rx)
    tropo, iono = _ground_atmosphere(atmosphere, lat_deg, lon_deg, height_m, seen, t_ns, lam)
    amb = gen.integers(-1000, 1000, size=(n_ant, n_sat, 3))
    jumps, lli, applied = _applied_slips(gen, slip_list, (n_epochs, n_ant, n_sat, 3), sats, lam, n_freq)
    geo = rho + _C * (dt_rx[None, :, None] - clk)  # (n_ep, n_ant, n_sat)
    shape = (n_epochs, n_ant, n_sat, 3)
    code, phase, doppler = observables(
        gen, geo, tropo, iono, lam, rate, sig["code_sigma_m"], sig["phase_sigma_m"], sig["doppler_sigma_hz"]
    )
    phase = phase + amb + jumps
    snr = np.broadcast_to(30.0 + 20.0 * np.sin(np.radians(el[:, keep]))[:, None, :, None], shape)
    valid = np.isfinite(lam)[None, None]
    code, phase, doppler = (np.where(valid, x, np.nan) for x in (code, phase, doppler))
    paths = [folder / file_names[0].format(i=i) for i in range(n_ant)]
    for i, p in enumerate(paths):
        write_receiver_obs(
            p, times, sats, n_freq, tuple(x[:, i] for x in (code, phase, doppler, snr)), lli[:, i], pos[0, i],
            f"ANT{i}", channels,
        )  # fmt: skip
    rel = ant[1:] - ant[0]
    return SimulatedGnss(
        obs_paths=tuple(paths),
        nav_path=nav_path,
        time=times,
        sats=tuple(sats),
        euler_gost_deg=eul,
        baselines_enu_m=np.einsum("tij,aj->tai", rot, rel),
        antenna_ecef_m=pos,
        receiver_clock_s=dt_rx,
        satellite_clock_s=sat_clk[keep],
        glonass_channels=channels,
        ambiguities=amb.astype(np.int64),
        slips=tuple(applied),
        elevation_deg=el[:, keep],
    )
