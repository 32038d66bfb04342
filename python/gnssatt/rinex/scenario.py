"""Simulated antenna arrays written as RINEX 3 files with a known truth: a static or rotating platform at a
fixed point, the nominal GPS constellation (broadcast records that reproduce its orbits), independent
receiver clocks, white code and phase noise, constant integer ambiguities (no slips).

The simulator applies the receiver clock biases to the pseudoranges only (every receiver samples at the
true epoch), while the reader moves the phases by ``range rate x clock difference``: the biases are kept
below 1e-7 s so that this mismatch stays under 0.2 mm."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from os import PathLike
from pathlib import Path

import numpy as np
from numpy.typing import ArrayLike, NDArray

from gnssatt import sim
from gnssatt._arrays import instance, integer, scalar, shaped
from gnssatt.errors import InvalidInputError, WorkLimitError
from gnssatt.likelihood import rotation_from_euler
from gnssatt.rinex._fields import folder_path, sat_list
from gnssatt.rinex.writer import write_nav_from_constellation, write_obs

__all__ = ["SimulatedRinex", "simulate_rinex_array", "write_array_rinex"]

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
    euler_deg
        (n_ep, 3) true eq. (5) angles ``(psi, theta, phi)`` (compass heading ``-psi``), degrees.
    baselines_enu_m
        (n_ep, n_ant - 1, 3) true baselines in East-North-Up, m.
    sats
        Satellites written.
    """

    obs_paths: tuple[Path, ...]
    nav_path: Path
    time: NDArray[np.datetime64]
    euler_deg: NDArray[np.float64]
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
    euler_deg: ArrayLike,
    *,
    interval_s: float = 1.0,
    seed: int = 0,
    n_sats: int | None = None,
    code_sigma_m: float = 0.3,
    phase_sigma_m: float = 0.002,
    elevation_min_deg: float = 10.0,
    lat_deg: float = 50.0,
    lon_deg: float = 36.2,
    start_s: float = 0.0,
) -> SimulatedRinex:
    """Simulate an array and write its RINEX 3 files into ``folder``.

    Parameters
    ----------
    folder
        Existing folder for the files ``ant<i>.24o`` and ``sim.24n``.
    antennas_body_m
        (n_ant, 3) antenna positions in the body frame of seed 001 (X nose, Y up, Z right wing), the first
        the reference antenna, m.
    euler_deg
        (n_ep, 3) eq. (5) angles per epoch, degrees (a rotating platform), or (3,) for a static one.
    interval_s
        Epoch spacing, s; the number of epochs is that of ``euler_deg`` (static: 10).
    seed
        Seed of the noise, ambiguities and clocks.
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
        ``MAX_ANTENNA_M``; ``euler_deg`` not (3,) or (n_ep >= 1, 3) within ``MAX_ANGLE_DEG``; ``interval_s``
        not in ``(0, MAX_INTERVAL_S]``; ``seed`` negative; ``n_sats`` below 1; noise levels negative or
        above ``MAX_SIGMA_M``; angles out of range; ``|start_s|`` above ``MAX_START_S``.
    WorkLimitError
        More than ``MAX_EPOCHS`` epochs.
    """
    folder = folder_path("folder", folder)
    ant = shaped("antennas_body_m", antennas_body_m, "(n_ant >= 2, 3)", (None, 3))
    if ant.shape[0] < 2:
        raise InvalidInputError(f"expected antennas_body_m of shape (n_ant >= 2, 3), got {ant.shape}")
    if np.any(np.abs(ant) > MAX_ANTENNA_M):
        raise InvalidInputError(f"expected |antennas_body_m| <= {MAX_ANTENNA_M} m per coordinate")
    eul = shaped("euler_deg", euler_deg, "(3,) or (n_ep >= 1, 3)", (3,), (None, 3))
    if eul.shape == (3,):
        eul = np.tile(eul, (10, 1))
    if eul.shape[0] < 1:
        raise InvalidInputError(f"expected euler_deg of shape (3,) or (n_ep >= 1, 3), got {eul.shape}")
    if np.any(np.abs(eul) > MAX_ANGLE_DEG):
        raise InvalidInputError(f"expected |euler_deg| <= {MAX_ANGLE_DEG} degrees")
    if eul.shape[0] > MAX_EPOCHS:
        raise WorkLimitError(f"euler_deg has {eul.shape[0]} epochs, above the limit of {MAX_EPOCHS}")
    interval_s = scalar("interval_s", interval_s, minimum=0.0, maximum=MAX_INTERVAL_S, strict=True, unit="s")
    seed = integer("seed", seed, minimum=0)
    if n_sats is not None:
        n_sats = integer("n_sats", n_sats, minimum=1)
    code_sigma_m = scalar("code_sigma_m", code_sigma_m, minimum=0.0, maximum=MAX_SIGMA_M, unit="m")
    phase_sigma_m = scalar("phase_sigma_m", phase_sigma_m, minimum=0.0, maximum=MAX_SIGMA_M, unit="m")
    elevation_min_deg = scalar("elevation_min_deg", elevation_min_deg, minimum=-90.0, maximum=90.0)
    lat_deg = scalar("lat_deg", lat_deg, minimum=-90.0, maximum=90.0)
    lon_deg = scalar("lon_deg", lon_deg, minimum=-360.0, maximum=360.0)
    start_s = scalar("start_s", start_s, minimum=-MAX_START_S, maximum=MAX_START_S, unit="s")
    rng = np.random.default_rng(seed)
    rx = sim.GroundReceiver(lat_deg=lat_deg, lon_deg=lon_deg, height_m=150.0)
    gps = sim.gps_nominal()
    t = start_s + np.arange(len(eul)) * interval_s
    el = np.degrees(np.arcsin(sim.line_of_sight(rx, gps, t).los[..., 2]))
    keep = np.all(el > elevation_min_deg, axis=0)
    if n_sats is not None:
        order = np.argsort(-np.where(keep, el[0], -90.0))
        keep = np.zeros_like(keep)
        keep[order[:n_sats]] = True
    vis = gps.select(list(np.array(gps.ids)[keep]))
    geom = sim.line_of_sight(rx, vis, t)
    rot = rotation_from_euler(eul)
    meas = sim.simulate_array(
        geom,
        rot,
        ant,
        vis.wavelengths_m(),
        rng,
        code_sigma_m=code_sigma_m,
        phase_sigma_m=phase_sigma_m,
        clock_bias_s=rng.uniform(-1e-7, 1e-7, size=len(ant)),
    )
    paths, nav = write_array_rinex(folder, meas, t, gps, vis.ids, rx)
    rel = ant[1:] - ant[0]
    truth = np.einsum("tij,aj->tai", rot.as_matrix(), rel)
    times = T0 + (t * 1e9).astype("timedelta64[ns]")
    return SimulatedRinex(paths, nav, times, eul, truth, tuple(vis.ids))


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
