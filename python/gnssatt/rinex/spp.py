"""Single-point positioning from pseudoranges: each receiver's position and clock, epoch by epoch.

Model: ``P_k = |r_k(t_tx) - x| + c (dt_r - dt_k) + T_k + e``, satellite positions at transmission in the
ECEF frame of reception (:func:`gnssatt.rinex.ephemeris.transmit_states`), one receiver clock per
satellite system (inter-system biases absorbed), troposphere ``2.3 m exp(-h / 8.5 km) / sin(el)``.
Ionosphere: removed by the L1/L2 (band 1 / band 2) ionosphere-free combination where both codes exist,
otherwise corrected with the broadcast Klobuchar model of the navigation header where it has one
(:func:`~gnssatt.rinex.iono.klobuchar_delay_m`, scaled to each system's band-1 carrier; GLONASS on G1 of
channel 0), else left in (metres; the position is used only for lines of sight and clocks). Single-frequency
code: the broadcast group delay is applied (``dt_k - T_GD``).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from gnssatt._arrays import finite_outputs, flag, instance, integer, scalar, shaped
from gnssatt.errors import InvalidInputError, RinexError
from gnssatt.rinex.ephemeris import C, _transmit_states
from gnssatt.rinex.iono import _klobuchar_delay_m
from gnssatt.rinex.nav import RinexNav, gps_ns
from gnssatt.rinex.obs import RinexObs
from gnssatt.sim.frames import dcm_ecef_from_enu, ecef_to_geodetic

__all__ = ["PointSolution", "code_observations", "elevation_azimuth_ecef", "single_point_positions"]

_F1 = {"G": 1575.42e6, "J": 1575.42e6, "E": 1575.42e6, "C": 1561.098e6, "R": 1602.0e6}
_F2 = {"G": 1227.60e6, "J": 1227.60e6, "E": 1176.45e6, "C": 1207.14e6}
_BAND2 = {"G": 2, "J": 2, "E": 5, "C": 7, "R": 2}


@dataclass(frozen=True)
class PointSolution:
    """Per-epoch single-point solutions.

    Attributes
    ----------
    time
        (n_epochs,) epoch labels of the file, ``datetime64[ns]`` GPST.
    position_ecef_m
        (n_epochs, 3) receiver position, ECEF, m (NaN where unsolved).
    clock_s
        (n_epochs,) receiver clock offset of the first system present (GPS where present), s:
        the true reception time is ``time - clock_s``.
    n_sats
        (n_epochs,) satellites used.
    residual_rms_m
        (n_epochs,) RMS of the pseudorange residuals, m.
    """

    time: NDArray[np.datetime64]
    position_ecef_m: NDArray[np.float64]
    clock_s: NDArray[np.float64]
    n_sats: NDArray[np.int64]
    residual_rms_m: NDArray[np.float64]

    @property
    def valid(self) -> NDArray[np.bool_]:
        """(n_epochs,) epochs with a solution."""
        return np.isfinite(self.clock_s)


#: Largest coordinate accepted for receivers and satellites, m; most iterations of the position solver.
MAX_COORDINATE_M = 1e10
MAX_ITERATIONS = 1000
#: Smallest receiver distance from the Earth's centre accepted, m.
MIN_RECEIVER_RADIUS_M = 1e5


def elevation_azimuth_ecef(
    receiver_ecef_m: NDArray[np.float64], sat_ecef_m: NDArray[np.float64]
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """Elevation (rad), azimuth (rad, clockwise from North) and unit ENU line of sight (n, 3) receiver ->
    satellites.

    Raises
    ------
    InvalidTypeError
        An argument that is not a real array.
    InvalidInputError
        ``receiver_ecef_m`` not a finite (3,), ``sat_ecef_m`` not a finite (n, 3), coordinates beyond
        ``MAX_COORDINATE_M``, a receiver within ``MIN_RECEIVER_RADIUS_M`` of the Earth's centre, or a
        satellite at the receiver (no line of sight).
    """
    rx = shaped("receiver_ecef_m", receiver_ecef_m, "(3,)", (3,))
    sat = shaped("sat_ecef_m", sat_ecef_m, "(n, 3)", (None, 3))
    for name, a in (("receiver_ecef_m", rx), ("sat_ecef_m", sat)):
        if np.any(np.abs(a) > MAX_COORDINATE_M):
            raise InvalidInputError(f"expected |{name}| <= {MAX_COORDINATE_M} m per coordinate")
    if np.linalg.norm(rx) < MIN_RECEIVER_RADIUS_M:
        raise InvalidInputError(
            f"expected receiver_ecef_m at least {MIN_RECEIVER_RADIUS_M} m from the Earth's centre (geodetic "
            f"coordinates are not unique near it), got {rx.tolist()}"
        )
    dist = np.linalg.norm(sat - rx, axis=-1)
    if np.any(dist < 1e-3):
        raise InvalidInputError(
            f"expected sat_ecef_m away from receiver_ecef_m, row {int(np.argmin(dist))} is at the receiver"
        )
    out = _elevation_azimuth_ecef(rx, sat)
    finite_outputs("elevation_azimuth_ecef", elevation_rad=out[0], azimuth_rad=out[1], los_enu=out[2])
    return out


def _elevation_azimuth_ecef(
    receiver_ecef_m: NDArray[np.float64], sat_ecef_m: NDArray[np.float64]
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    lat, lon, _ = ecef_to_geodetic(receiver_ecef_m)
    d = sat_ecef_m - receiver_ecef_m
    los = d / np.linalg.norm(d, axis=-1, keepdims=True)
    enu = los @ dcm_ecef_from_enu(float(lat), float(lon))
    return np.arcsin(np.clip(enu[:, 2], -1, 1)), np.arctan2(enu[:, 0], enu[:, 1]) % (2 * np.pi), enu


def code_observations(obs: RinexObs) -> tuple[NDArray[np.float64], NDArray[np.bool_]]:
    """(n_epochs, n_sats) pseudoranges for positioning, m, and whether each is ionosphere-free.

    Raises
    ------
    InvalidTypeError
        ``obs`` is not a :class:`RinexObs`.
    """
    obs = instance("obs", obs, RinexObs, "a RinexObs (from read_obs)")
    out = np.full(obs.data.shape[:2], np.nan)
    iono_free = np.zeros(obs.data.shape[:2], dtype=bool)
    for system in sorted({s[0] for s in obs.sats}):
        cols = np.array([k for k, s in enumerate(obs.sats) if s[0] == system])
        c1 = obs.code_for(system, "C", 1)
        if c1 is None:
            continue
        p1 = obs.get(c1)[:, cols]
        c2 = obs.code_for(system, "C", _BAND2.get(system, 2))
        if c2 is not None and system in _F2:
            p2 = obs.get(c2)[:, cols]
            g = (_F1[system] / _F2[system]) ** 2  # system in _F2, so in _F1
            p_if = (g * p1 - p2) / (g - 1.0)
            both = np.isfinite(p_if)
            out[:, cols] = np.where(both, p_if, p1)
            iono_free[:, cols] = both
        else:
            out[:, cols] = p1
    return out, iono_free


def single_point_positions(
    obs: RinexObs,
    nav: RinexNav,
    *,
    elevation_mask_deg: float = 10.0,
    max_iter: int = 10,
    ionosphere: bool = True,
) -> PointSolution:
    """Position and clock of the receiver at every epoch from its pseudoranges (module docstring).

    ``ionosphere=False`` leaves the single-frequency ionospheric delay in (no Klobuchar correction).

    Raises
    ------
    InvalidTypeError
        ``obs`` not a :class:`RinexObs`, ``nav`` not a :class:`RinexNav`, ``elevation_mask_deg`` not real,
        ``max_iter`` not an integer, ``ionosphere`` not a bool.
    InvalidInputError
        ``elevation_mask_deg`` outside [-90, 90], ``max_iter`` below 1.
    WorkLimitError
        ``max_iter`` above ``MAX_ITERATIONS``.
    RinexError
        No epoch could be solved (fewer than 4 + systems - 1 satellites with ephemerides everywhere).
    """
    obs = instance("obs", obs, RinexObs, "a RinexObs (from read_obs)")
    nav = instance("nav", nav, RinexNav, "a RinexNav (from read_nav)")
    elevation_mask_deg = scalar("elevation_mask_deg", elevation_mask_deg, minimum=-90.0, maximum=90.0)
    max_iter = integer("max_iter", max_iter, minimum=1, maximum=MAX_ITERATIONS)
    ionosphere = flag("ionosphere", ionosphere)
    pr, iono_free = code_observations(obs)
    t_ns = gps_ns(obs.time)
    n_ep = len(obs.time)
    pos_out = np.full((n_ep, 3), np.nan)
    clk_out = np.full(n_ep, np.nan)
    nsat_out = np.zeros(n_ep, dtype=np.int64)
    rms_out = np.full(n_ep, np.nan)
    x0 = obs.approx_position_m.copy() if np.linalg.norm(obs.approx_position_m) > 6e6 else np.zeros(3)
    mask = np.radians(elevation_mask_deg)
    klob = ionosphere and bool(np.all(np.isfinite(nav.iono_alpha)) and np.all(np.isfinite(nav.iono_beta)))
    week_ns = 604_800 * 1_000_000_000
    for e in range(n_ep):
        have = np.flatnonzero(np.isfinite(pr[e]))
        sats = [obs.sats[k] for k in have]
        if len(sats) < 4:
            continue
        p = pr[e, have]
        sp, sclk, tgd, valid = _transmit_states(nav, sats, int(t_ns[e]), x0, pseudorange_m=p)
        if valid.sum() < 4:
            continue
        sp, sclk, tgd, p = sp[valid], sclk[valid], tgd[valid], p[valid]
        sysc = np.array([s[0] for s in np.array(sats)[valid]])
        sclk = np.where(iono_free[e, have][valid], sclk, sclk - tgd)
        single_freq = ~iono_free[e, have][valid]
        systems = sorted(set(sysc), key=lambda s: (s != "G", s))
        x = np.concatenate([x0, np.zeros(len(systems))])
        use = np.ones(len(p), dtype=bool)
        for it in range(max_iter):
            d = sp - x[:3]
            rho = np.linalg.norm(d, axis=1)
            if np.linalg.norm(x[:3]) > 6e6:
                el, az, _ = _elevation_azimuth_ecef(x[:3], sp)
                lat, lon, h = ecef_to_geodetic(x[:3])
                delay = 2.3 * np.exp(-max(float(h), 0.0) / 8500.0) / np.maximum(np.sin(el), 0.05)
                if klob:
                    freq = np.array([_F1.get(c, _F1["G"]) for c in sysc])
                    iono = _klobuchar_delay_m(
                        nav.iono_alpha,
                        nav.iono_beta,
                        float(np.radians(lat)),
                        float(np.radians(lon)),
                        az,
                        el,
                        (int(t_ns[e]) % week_ns) * 1e-9,
                        freq,
                    )
                    delay = delay + np.where(single_freq, iono, 0.0)
                use = el >= mask if it > 0 else np.ones(len(p), dtype=bool)
            else:
                delay = np.zeros(len(p))
            clk_cols = np.array([systems.index(s) for s in sysc])
            model = rho + x[3 + clk_cols] - C * sclk + delay
            h_mat = np.zeros((len(p), 3 + len(systems)))
            h_mat[:, :3] = -d / rho[:, None]
            h_mat[np.arange(len(p)), 3 + clk_cols] = 1.0
            a, b = h_mat[use], (p - model)[use]
            if len(b) < 3 + len(systems):
                x[:] = np.nan
                break
            dx = np.linalg.lstsq(a, b, rcond=None)[0]
            x = x + dx
            if np.linalg.norm(dx[:3]) < 1e-4:
                break
        if not np.all(np.isfinite(x)):
            continue
        res = (p - (np.linalg.norm(sp - x[:3], axis=1) + x[3 + clk_cols] - C * sclk + delay))[use]
        pos_out[e] = x[:3]
        clk_out[e] = x[3] / C
        nsat_out[e] = int(use.sum())
        rms_out[e] = float(np.sqrt(np.mean(res**2)))
        x0 = x[:3].copy()
    if not np.any(np.isfinite(clk_out)):
        raise RinexError(
            obs.path, None, "no epoch has 4 or more satellites with pseudoranges and ephemerides"
        )
    return PointSolution(obs.time, pos_out, clk_out, nsat_out, rms_out)
