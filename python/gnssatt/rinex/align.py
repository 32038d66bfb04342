"""Receivers with independent clocks: common epochs, common satellites, clocks, satellite geometry and
cycle slips, ready for between-receiver differences.

Each receiver's clock comes from its own pseudoranges (:func:`~gnssatt.rinex.spp.single_point_positions`):
its observations at label ``t`` were taken at the true GPST ``t - dt_i``. Satellite positions are computed
for every receiver at its own transmission times, so the ranges modelled for a receiver refer to the
instant it really sampled. :meth:`Aligned.phase_at_common_time` moves the phases to one instant (the
reference receiver's) with the range rate, which is what the single-epoch grid estimators need.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from gnssatt._arrays import instance, integer, scalar
from gnssatt.errors import InvalidInputError, InvalidTypeError, RinexError
from gnssatt.rinex._fields import sat_id
from gnssatt.rinex.ephemeris import C, _satellite_states, _transmit_states
from gnssatt.rinex.nav import RinexNav, gps_ns
from gnssatt.rinex.obs import RinexObs
from gnssatt.rinex.spp import PointSolution, code_observations, single_point_positions
from gnssatt.sim.frames import dcm_ecef_from_enu, ecef_to_geodetic

__all__ = ["Aligned", "align_receivers", "carrier_frequency_hz"]

_FREQ = {
    ("G", 1): 1575.42e6, ("G", 2): 1227.60e6, ("G", 5): 1176.45e6,
    ("J", 1): 1575.42e6, ("J", 2): 1227.60e6, ("J", 5): 1176.45e6,
    ("E", 1): 1575.42e6, ("E", 5): 1176.45e6, ("E", 7): 1207.14e6, ("E", 8): 1191.795e6, ("E", 6): 1278.75e6,
    ("C", 1): 1575.42e6, ("C", 2): 1561.098e6, ("C", 7): 1207.14e6, ("C", 6): 1268.52e6, ("C", 5): 1176.45e6,
}  # fmt: skip


#: GLONASS FDMA frequency channels (ICD: -7 to +6; +7 to +13 in older almanacs).
GLONASS_CHANNELS = (-7, 13)


def carrier_frequency_hz(sat: str, band: int, glonass_channel: int | None = None) -> float:
    """Carrier frequency of a satellite's band, Hz (GLONASS FDMA from its channel).

    Raises
    ------
    InvalidTypeError
        ``sat`` not text, ``band`` or ``glonass_channel`` not an integer.
    InvalidInputError
        ``sat`` not a satellite id; ``band`` not a band of that system (GLONASS: 1 or 2); a GLONASS
        satellite without ``glonass_channel``, or a channel outside ``GLONASS_CHANNELS``.
    """
    sat = sat_id("sat", sat)
    band = integer("band", band)
    if glonass_channel is not None:
        glonass_channel = integer("glonass_channel", glonass_channel, minimum=GLONASS_CHANNELS[0])
        if glonass_channel > GLONASS_CHANNELS[1]:
            raise InvalidInputError(
                f"expected glonass_channel <= {GLONASS_CHANNELS[1]}, got {glonass_channel}"
            )
    if sat[0] == "R":
        if glonass_channel is None:
            raise InvalidInputError(f"expected glonass_channel for the GLONASS satellite {sat}, got None")
        if band not in (1, 2):
            raise InvalidInputError(f"expected band 1 or 2 for the GLONASS satellite {sat}, got {band}")
    elif (sat[0], band) not in _FREQ:
        known = sorted(b for sy, b in _FREQ if sy == sat[0])
        raise InvalidInputError(f"expected band among {known} for {sat}, got {band}")
    return _carrier_frequency_hz(sat, band, glonass_channel)


def _carrier_frequency_hz(sat: str, band: int, glonass_channel: int | None = None) -> float:
    if sat[0] == "R":
        if glonass_channel is None:
            raise RinexError("", None, f"no FDMA channel known for GLONASS satellite {sat}")
        return {1: 1602.0e6 + 0.5625e6 * glonass_channel, 2: 1246.0e6 + 0.4375e6 * glonass_channel}[band]
    try:
        return _FREQ[(sat[0], band)]
    except KeyError:
        raise RinexError("", None, f"no carrier frequency for system {sat[0]} band {band}") from None


@dataclass(frozen=True)
class Aligned:
    """Observations of n_rx receivers on their common epochs and satellites.

    Attributes
    ----------
    paths
        The observation files, reference receiver first.
    time
        (n_ep,) epoch labels of the reference receiver, ``datetime64[ns]`` GPST.
    sats
        (n_sat,) satellite ids.
    wavelength_m
        (n_sat,) wavelength of the band used, m.
    phase_cycles
        (n_rx, n_ep, n_sat) carrier phase, cycles, RINEX sign, NaN where absent.
    code_m
        (n_rx, n_ep, n_sat) pseudorange on the same band, m.
    slip
        (n_rx, n_ep, n_sat) a new phase arc starts here (loss-of-lock flag, phase/code jump, gap, or the
        ionosphere-free-geometry (L1 - L2 phase) jump where a second band exists).
    clock_s
        (n_rx, n_ep) receiver clocks from single-point positioning, s (true time = label - clock).
    position_ecef_m
        (n_rx, 3) mean single-point position of each receiver, ECEF, m.
    sat_ecef_m
        (n_rx, n_ep, n_sat, 3) satellite at each receiver's transmission time, ECEF of reception, m.
    range_rate_m_s
        (n_ep, n_sat) range rate seen from the reference receiver, m/s.
    los_enu
        (n_ep, n_sat, 3) unit lines of sight at the reference receiver, East-North-Up.
    elevation_rad
        (n_ep, n_sat) elevations at the reference receiver.
    epoch_position_ecef_m
        (n_rx, n_ep, 3) single-point position of each receiver at each epoch, ECEF, m (NaN where unsolved);
        what a moving platform's processing uses instead of ``position_ecef_m``.
    """

    paths: tuple[str, ...]
    time: NDArray[np.datetime64]
    sats: tuple[str, ...]
    wavelength_m: NDArray[np.float64]
    phase_cycles: NDArray[np.float64]
    code_m: NDArray[np.float64]
    slip: NDArray[np.bool_]
    clock_s: NDArray[np.float64]
    position_ecef_m: NDArray[np.float64]
    sat_ecef_m: NDArray[np.float64]
    range_rate_m_s: NDArray[np.float64]
    los_enu: NDArray[np.float64]
    elevation_rad: NDArray[np.float64]
    epoch_position_ecef_m: NDArray[np.float64] | None = None

    @property
    def usable(self) -> NDArray[np.bool_]:
        """(n_ep, n_sat) phase present at every receiver and the satellite's ephemeris valid."""
        return np.all(np.isfinite(self.phase_cycles), axis=0) & np.all(
            np.isfinite(self.sat_ecef_m[..., 0]), axis=0
        )

    def phase_at_common_time(self) -> NDArray[np.float64]:
        """(n_rx, n_ep, n_sat) phases moved to the reference receiver's sampling instant, cycles:
        ``phi_i - rho_dot (t_i - t_0) / lambda`` with ``t_i = label_i - dt_i`` (the common ``f dt`` term
        is left: it is one nuisance phase per receiver and epoch)."""
        shift = -(self.clock_s - self.clock_s[:1])  # true-time offset of receiver i from the reference
        return self.phase_cycles - self.range_rate_m_s[None] * shift[..., None] / self.wavelength_m

    def single_differences_rad(self, *, wrapped: bool = True) -> NDArray[np.float64]:
        """(n_rx - 1, n_ep, n_sat) carrier phase at receiver i minus the reference receiver, rad, at a
        common instant (:meth:`phase_at_common_time`), RINEX sign, wrapped to [-pi, pi) by default."""
        ph = self.phase_at_common_time()
        sd = 2.0 * np.pi * (ph[1:] - ph[:1])
        return (sd + np.pi) % (2.0 * np.pi) - np.pi if wrapped else sd


def _match(ref: NDArray[np.int64], other: NDArray[np.int64], tol_ns: int) -> NDArray[np.int64]:
    j = np.clip(np.searchsorted(other, ref), 1, max(len(other) - 1, 1))
    j0 = np.clip(j - 1, 0, len(other) - 1)
    j1 = np.clip(j, 0, len(other) - 1)
    best = np.where(np.abs(other[j0] - ref) <= np.abs(other[j1] - ref), j0, j1)
    return np.where(np.abs(other[best] - ref) <= tol_ns, best, -1)


#: Largest epoch-matching tolerance accepted, s.
MAX_TOLERANCE_S = 3600.0


def _observation_list(name: str, value: object) -> list[RinexObs]:
    if isinstance(value, RinexObs) or not isinstance(value, list | tuple):
        raise InvalidTypeError(
            f"expected {name} as a list of RinexObs (from read_obs), got {type(value).__name__}"
        )
    for i, o in enumerate(value):
        if not isinstance(o, RinexObs):
            raise InvalidTypeError(
                f"expected {name} as a list of RinexObs, got {type(o).__name__} at index {i}"
            )
    if len(value) < 2:
        raise InvalidInputError(f"expected two or more {name} (receivers), got {len(value)}")
    return list(value)


def align_receivers(
    observations: Sequence[RinexObs],
    nav: RinexNav,
    *,
    band: int = 1,
    systems: str = "GREJC",
    tolerance_s: float = 0.5,
    elevation_mask_deg: float = 10.0,
    slip_code_threshold_m: float = 10.0,
    slip_geometry_free_m: float = 0.05,
    solutions: Sequence[PointSolution] | None = None,
) -> Aligned:
    """Bring receivers onto common epochs and satellites (module docstring).

    Parameters
    ----------
    observations
        Two or more observation files, the reference receiver first.
    nav
        Broadcast ephemerides covering the observations.
    band
        Carrier band (1: GPS L1 / GLONASS G1 / Galileo E1 ...).
    systems
        Satellite systems to use.
    tolerance_s
        Largest difference of epoch labels that still counts as the same epoch, s.
    elevation_mask_deg
        Satellites below this elevation at the reference receiver are dropped (NaN) at that epoch.
    slip_code_threshold_m, slip_geometry_free_m
        Phase/code consistency: a jump of ``lambda phi - P`` between epochs beyond the first threshold, or
        of the two-band phase difference ``lambda_1 phi_1 - lambda_2 phi_2`` beyond the second, flags a slip.
    solutions
        Single-point solutions of the receivers, if already computed.

    Raises
    ------
    InvalidTypeError
        ``observations`` not a list of :class:`RinexObs`, ``nav`` not a :class:`RinexNav`, ``solutions``
        not a list of :class:`PointSolution`, another argument of the wrong kind.
    InvalidInputError
        Fewer than two observations; ``band`` outside 1 to 9; ``systems`` empty or with letters other than
        GREJC; ``tolerance_s`` not in ``(0, MAX_TOLERANCE_S]``; ``elevation_mask_deg`` outside [-90, 90];
        slip thresholds not positive and finite; ``solutions`` not one per observation.
    RinexError
        No common epochs, no common satellites (naming the files).
    """
    observations = _observation_list("observations", observations)
    nav = instance("nav", nav, RinexNav, "a RinexNav (from read_nav)")
    band = integer("band", band, minimum=1)
    if band > 9:
        raise InvalidInputError(f"expected band <= 9 (a RINEX band digit), got {band}")
    systems = instance("systems", systems, str, "system letters such as 'GE'")
    if not systems or any(ch not in "GREJC" for ch in systems):
        raise InvalidInputError(f"expected systems as letters among 'GREJC', got {systems!r}")
    tolerance_s = scalar("tolerance_s", tolerance_s, minimum=0.0, strict=True, unit="s")
    if tolerance_s > MAX_TOLERANCE_S:
        raise InvalidInputError(f"expected tolerance_s <= {MAX_TOLERANCE_S} s, got {tolerance_s} s")
    elevation_mask_deg = scalar("elevation_mask_deg", elevation_mask_deg, minimum=-90.0, maximum=90.0)
    slip_code_threshold_m = scalar("slip_code_threshold_m", slip_code_threshold_m, minimum=0.0, strict=True)
    slip_geometry_free_m = scalar("slip_geometry_free_m", slip_geometry_free_m, minimum=0.0, strict=True)
    if solutions is not None:
        if not isinstance(solutions, list | tuple) or not all(
            isinstance(x, PointSolution) for x in solutions
        ):
            raise InvalidTypeError(
                f"expected solutions as a list of PointSolution, got {type(solutions).__name__}"
            )
        if len(solutions) != len(observations):
            raise InvalidInputError(
                f"expected one solution per observation ({len(observations)}), got {len(solutions)} solutions"
            )
    paths = tuple(o.path for o in observations)
    sols = (
        list(solutions) if solutions is not None else [single_point_positions(o, nav) for o in observations]
    )
    t_ref = gps_ns(observations[0].time)
    idx = [np.arange(len(t_ref))]
    for o in observations[1:]:
        idx.append(_match(t_ref, gps_ns(o.time), int(tolerance_s * 1e9)))
    common = np.all(np.stack(idx) >= 0, axis=0)
    if not np.any(common):
        raise RinexError(" and ".join(paths), None, f"no common epochs (labels within {tolerance_s} s)")
    idx = [i[common] for i in idx]
    per_rx = []
    for o in observations:
        have = {
            s
            for s in o.sats
            if s[0] in systems
            and o.code_for(s[0], "L", band) is not None
            and o.code_for(s[0], "C", band) is not None
        }
        per_rx.append(have)
    sats = tuple(sorted(set.intersection(*per_rx)))
    if not sats:
        raise RinexError(" and ".join(paths), None, f"no common satellites with band-{band} phase and code")
    channels: dict[str, int] = {}
    for o in observations:
        channels.update(o.glonass_channels)
    for s, ch in zip(nav.glonass.sats, nav.glonass.channel, strict=True):
        channels.setdefault(str(s), int(ch))
    lam = np.array([C / _carrier_frequency_hz(s, band, channels.get(s)) for s in sats])
    n_rx, n_ep, n_sat = len(observations), int(common.sum()), len(sats)
    phase = np.full((n_rx, n_ep, n_sat), np.nan)
    code = np.full((n_rx, n_ep, n_sat), np.nan)
    slip = np.zeros((n_rx, n_ep, n_sat), dtype=bool)
    clock = np.zeros((n_rx, n_ep))
    pos = np.zeros((n_rx, 3))
    traj = np.full((n_rx, n_ep, 3), np.nan)
    sat_pos = np.full((n_rx, n_ep, n_sat, 3), np.nan)
    for r, (o, sol, ix) in enumerate(zip(observations, sols, idx, strict=True)):
        cols = o.sat_index(sats)
        for k, s in enumerate(sats):
            lcode, ccode = o.code_for(s[0], "L", band), o.code_for(s[0], "C", band)
            assert lcode is not None and ccode is not None
            phase[r, :, k] = o.get(lcode)[ix, cols[k]]
            code[r, :, k] = o.get(ccode)[ix, cols[k]]
            slip[r, :, k] = (o.get_lli(lcode)[ix, cols[k]] & 1) == 1
            b2 = {1: 2, 2: 1}.get(band, 1) if s[0] in "GRJ" else None
            l2 = o.code_for(s[0], "L", b2) if b2 is not None else None
            if l2 is not None:
                lam2 = (
                    C / _carrier_frequency_hz(s, b2, channels.get(s))
                    if (s[0] != "R" or s in channels)
                    else None
                )
                if lam2 is not None:
                    gf = lam[k] * phase[r, :, k] - lam2 * o.get(l2)[ix, cols[k]]
                    slip[r, 1:, k] |= np.abs(np.diff(gf)) > slip_geometry_free_m
        mp = lam * phase[r] - code[r]
        jump = np.diff(mp, axis=0)
        jump = jump - np.nanmedian(jump, axis=1, keepdims=True)  # receiver clock steps move every satellite
        slip[r, 1:] |= np.abs(jump) > slip_code_threshold_m
        gap = np.isfinite(phase[r, 1:]) & ~np.isfinite(phase[r, :-1])
        slip[r, 1:] |= gap
        slip[r, 0] |= np.isfinite(phase[r, 0])
        clock[r] = sol.clock_s[ix]
        pos[r] = np.nanmean(sol.position_ecef_m[ix], axis=0)
        traj[r] = sol.position_ecef_m[ix]
        t_ns = gps_ns(o.time)[ix]
        pr_all, _ = code_observations(o)
        for e in range(n_ep):
            pr = pr_all[ix[e], cols]
            sp, _, _, valid = _transmit_states(nav, list(sats), int(t_ns[e]), pos[r], pseudorange_m=pr)
            if not np.isfinite(clock[r, e]):
                valid[:] = False
            sat_pos[r, e] = np.where(valid[:, None], sp, np.nan)
    ok = np.all(np.isfinite(clock), axis=0)
    if not np.any(ok):
        raise RinexError(
            " and ".join(paths), None, "no common epoch where every receiver has a clock solution"
        )
    lat, lon, _ = ecef_to_geodetic(pos[0])
    d = sat_pos[0] - pos[0]
    rng = np.linalg.norm(d, axis=-1, keepdims=True)
    los_enu = (d / rng) @ dcm_ecef_from_enu(float(lat), float(lon))
    elev = np.arcsin(np.clip(los_enu[..., 2], -1.0, 1.0))
    # range rate at the reference receiver from the ephemeris (1 s central difference)
    rate = np.full((n_ep, n_sat), np.nan)
    t0 = gps_ns(observations[0].time)[idx[0]]
    for e in range(n_ep):
        p1, _, _, _ = _satellite_states(nav, list(sats), int(t0[e]), 0.5)
        p0, _, _, _ = _satellite_states(nav, list(sats), int(t0[e]), -0.5)
        u = d[e] / rng[e]
        rate[e] = np.sum((p1 - p0) * u, axis=1)  # a static receiver: ECEF satellite velocity along the line
    low = ~(elev >= np.radians(elevation_mask_deg)) | ~ok[:, None]
    phase[:, low] = np.nan
    code[:, low] = np.nan
    # a satellite reappearing after the mask or a gap starts a new arc
    back = np.isfinite(phase[:, 1:]) & ~np.isfinite(phase[:, :-1])
    slip[:, 1:] |= back
    return Aligned(
        paths=paths,
        time=observations[0].time[idx[0]],
        sats=sats,
        wavelength_m=lam,
        phase_cycles=phase,
        code_m=code,
        slip=slip,
        clock_s=clock,
        position_ecef_m=pos,
        sat_ecef_m=sat_pos,
        range_rate_m_s=rate,
        los_enu=los_enu,
        elevation_rad=elev,
        epoch_position_ecef_m=traj,
    )
