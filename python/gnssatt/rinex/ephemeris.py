"""Satellite positions and clocks from broadcast ephemerides; light time and Earth rotation.

- GPS, Galileo, QZSS, BeiDou MEO/IGSO: IS-GPS-200 (Table 20-IV) Keplerian model with harmonic corrections;
  BeiDou GEO (C01-C05, C59-C63): BDS-SIS-ICD 5.2.4.12 (extra rotation by -5 degrees about x).
  Clock: ``dt_sv = af0 + af1 (t - toc) + af2 (t - toc)^2 + F e sqrt(A) sin E`` (relativistic term,
  ``F = -2 sqrt(mu) / c^2``); the group delay ``T_GD`` is returned apart (:func:`satellite_states`):
  a single-frequency L1 user subtracts it, the L1/L2 ionosphere-free combination does not.
- GLONASS: ICD (ed. 5.1) A.3.1.2, fourth-order Runge-Kutta integration of the PZ-90 equations of motion
  (central term, J2, centrifugal and Coriolis terms, the broadcast luni-solar acceleration) in steps of
  at most 60 s by the Rust propagator of :mod:`gnssatt.orbit`;
  clock ``dt_sv = -tau_n + gamma_n (t - t_b)``; PZ-90 taken as WGS-84 (decimetre level).
- Positions are ECEF at the *transmission* time in the frame of that time; :func:`transmit_states` rotates
  them into the ECEF frame of the reception time (Sagnac) and iterates the light time.

Times are GPST nanoseconds since the GPS epoch (:func:`gnssatt.rinex.nav.gps_ns`) plus a float offset in
seconds, so that differences of large times stay exact.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from gnssatt import _core
from gnssatt._arrays import finite_outputs, float_array, instance, integer, scalar, shaped
from gnssatt.errors import InvalidInputError
from gnssatt.rinex._fields import sat_list
from gnssatt.rinex.nav import RinexNav

__all__ = ["satellite_states", "transmit_states"]

#: Largest time offset ``dt_s`` accepted, s: a week, far beyond any ephemeris validity.
MAX_OFFSET_S = 604800.0
#: Largest GPST nanosecond count accepted (2200-01-01, where datetime64[ns] labels end).
MAX_GPS_NS = 6_942_355_200 * 10**9
#: Largest receiver distance from the Earth's centre accepted, m (beyond the Moon).
MAX_RECEIVER_RADIUS_M = 1e9
#: Largest pseudorange accepted, m; largest receiver clock offset, s.
MAX_PSEUDORANGE_M = 1e9
MAX_RECEIVER_CLOCK_S = 1000.0

C = 299792458.0
OMEGA_E = 7.2921151467e-5
_MU = {"G": 3.986005e14, "J": 3.986005e14, "E": 3.986004418e14, "C": 3.986004418e14}
_OMEGA = {"G": 7.2921151467e-5, "J": 7.2921151467e-5, "E": 7.2921151467e-5, "C": 7.292115e-5}
_MAX_AGE_S = {"G": 4 * 3600.0, "J": 4 * 3600.0, "E": 4 * 3600.0, "C": 4 * 3600.0, "R": 1800.0 + 600.0}
_GLO_MU = 398600.4418e9
_GLO_J2 = 1.0826257e-3
_GLO_AE = 6378136.0
_GLO_OMEGA = 7.292115e-5


def _select(
    sat_ids: NDArray[np.str_], ref_ns: NDArray[np.int64], health: NDArray[np.float64], sat: str, t_ns: int
) -> int:
    rows = np.flatnonzero(sat_ids == sat)
    if rows.size == 0:
        return -1
    age = np.abs((t_ns - ref_ns[rows]).astype(np.float64)) * 1e-9 + 1e9 * (health[rows] != 0)
    best = int(np.argmin(age))
    if age[best] > _MAX_AGE_S.get(sat[0], 4 * 3600.0):
        return -1
    return int(rows[best])


def _kepler(
    nav: RinexNav, rows: NDArray[np.int64], sys: NDArray[np.str_], t_ns: int, dt_s: NDArray[np.float64]
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    k = nav.kepler
    f = {name: v[rows] for name, v in k.fields.items()}
    mu = np.array([_MU[s] for s in sys])
    om_e = np.array([_OMEGA[s] for s in sys])
    tk = (t_ns - k.toe_ns[rows]).astype(np.float64) * 1e-9 + dt_s
    a = f["sqrt_a"] ** 2
    n = np.sqrt(mu / a**3) + f["delta_n"]
    m = f["m0"] + n * tk
    e = f["e"]
    ea = m.copy()
    for _ in range(30):
        step = (ea - e * np.sin(ea) - m) / (1.0 - e * np.cos(ea))
        ea -= step
        if np.all(np.abs(step) < 1e-14):
            break
    nu = np.arctan2(np.sqrt(1.0 - e**2) * np.sin(ea), np.cos(ea) - e)
    phi = nu + f["omega"]
    s2, c2 = np.sin(2 * phi), np.cos(2 * phi)
    u = phi + f["cus"] * s2 + f["cuc"] * c2
    r = a * (1.0 - e * np.cos(ea)) + f["crs"] * s2 + f["crc"] * c2
    inc = f["i0"] + f["cis"] * s2 + f["cic"] * c2 + f["idot"] * tk
    xp, yp = r * np.cos(u), r * np.sin(u)
    prn = np.array([0] * len(rows))
    geo = np.zeros(len(rows), dtype=bool)
    for j, row in enumerate(rows):
        sid = str(k.sats[row])
        prn[j] = int(sid[1:])
        geo[j] = sid[0] == "C" and (prn[j] <= 5 or prn[j] >= 59)
    omega = np.where(
        geo,
        f["omega0"] + f["omega_dot"] * tk - om_e * f["toe_sow"],
        f["omega0"] + (f["omega_dot"] - om_e) * tk - om_e * f["toe_sow"],
    )
    co, so, ci, si = np.cos(omega), np.sin(omega), np.cos(inc), np.sin(inc)
    pos = np.stack([xp * co - yp * ci * so, xp * so + yp * ci * co, yp * si], axis=-1)
    if np.any(geo):
        g = np.flatnonzero(geo)
        x5 = np.radians(-5.0)
        rx = np.array([[1, 0, 0], [0, np.cos(x5), np.sin(x5)], [0, -np.sin(x5), np.cos(x5)]])
        for j in g:
            ang = om_e[j] * tk[j]
            rz = np.array([[np.cos(ang), np.sin(ang), 0], [-np.sin(ang), np.cos(ang), 0], [0, 0, 1]])
            pos[j] = rz @ rx @ pos[j]
    tc = (t_ns - k.toc_ns[rows]).astype(np.float64) * 1e-9 + dt_s
    af = k.af[rows]
    f_rel = -2.0 * np.sqrt(mu) / C**2
    clk = af[:, 0] + af[:, 1] * tc + af[:, 2] * tc**2 + f_rel * e * f["sqrt_a"] * np.sin(ea)
    return pos, clk, f["tgd"]


def _glonass(
    nav: RinexNav, rows: NDArray[np.int64], t_ns: int, dt_s: NDArray[np.float64]
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    g = nav.glonass
    tk = (t_ns - g.tb_ns[rows]).astype(np.float64) * 1e-9 + dt_s
    y = np.concatenate([g.position_m[rows], g.velocity_m_s[rows]], axis=1)
    acc = np.ascontiguousarray(g.acceleration_m_s2[rows], dtype=np.float64)
    model = {
        "gm_m3_s2": _GLO_MU,
        "j2": _GLO_J2,
        "equatorial_radius_m": _GLO_AE,
        "omega_rad_s": _GLO_OMEGA,
        "lunisolar_m_s2": [0.0, 0.0, 0.0],
    }
    y = _core.glonass_ephemeris_states(y, acc, tk, model, max_step_s=60.0)
    clk = g.clock_bias[rows] + g.gamma_n[rows] * tk
    return y[:, :3], clk, np.zeros(len(rows))


def satellite_states(
    nav: RinexNav, sats: list[str] | tuple[str, ...], t_ns: int, dt_s: ArrayLike = 0.0
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64], NDArray[np.bool_]]:
    """Broadcast positions and clocks of satellites at GPST ``t_ns * 1e-9 + dt_s`` (seconds since the GPS
    epoch), in the ECEF frame of that instant.

    Parameters
    ----------
    nav
        Ephemerides (:func:`gnssatt.rinex.read_nav`).
    sats
        (n,) satellite ids.
    t_ns
        GPST nanoseconds since the GPS epoch (integer).
    dt_s
        Offset in seconds, scalar or (n,) (e.g. minus the signal travel time).

    Returns
    -------
    position_m
        (n, 3) ECEF, m (NaN where no ephemeris is valid).
    clock_s
        (n,) satellite clock offset including the relativistic term, s.
    tgd_s
        (n,) broadcast group delay (GPS ``T_GD``, Galileo BGD E5a/E1, BeiDou ``T_GD1``), s; 0 for GLONASS.
    valid
        (n,) an ephemeris within its validity was found (healthy preferred).

    Raises
    ------
    InvalidTypeError
        ``nav`` is not a :class:`RinexNav`, ``sats`` not a list of satellite ids, ``t_ns`` not an integer,
        ``dt_s`` not real.
    InvalidInputError
        A malformed satellite id, ``t_ns`` outside ``[0, MAX_GPS_NS]``, ``dt_s`` not finite, of another
        length than ``sats`` or beyond ``MAX_OFFSET_S``.
    """
    nav = instance("nav", nav, RinexNav, "a RinexNav (from read_nav)")
    sats = sat_list("sats", sats)
    t_ns = _gps_time("t_ns", t_ns)
    _offset("dt_s", dt_s, len(sats))
    out = _satellite_states(nav, sats, t_ns, dt_s)
    finite_outputs("satellite_states", position_m=out[0][out[3]], clock_s=out[1][out[3]])
    return out


def _gps_time(name: str, value: object) -> int:
    t = integer(name, value, minimum=0)
    if t > MAX_GPS_NS:
        raise InvalidInputError(f"expected {name} <= {MAX_GPS_NS} (GPST ns of 2200-01-01), got {t}")
    return t


def _offset(name: str, value: ArrayLike, n: int) -> None:
    off = float_array(name, value, ndim=(0, 1), shape="() or (n,)")
    if off.ndim == 1 and off.shape[0] not in (1, n):
        raise InvalidInputError(
            f"expected {name} of shape (), (1,) or ({n},) (one per satellite), got {off.shape}"
        )
    if np.any(np.abs(off) > MAX_OFFSET_S):
        raise InvalidInputError(f"expected |{name}| <= {MAX_OFFSET_S} s, got {np.max(np.abs(off))} s")


def _satellite_states(
    nav: RinexNav, sats: list[str] | tuple[str, ...], t_ns: int, dt_s: ArrayLike = 0.0
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64], NDArray[np.bool_]]:
    n = len(sats)
    off = np.broadcast_to(np.asarray(dt_s, dtype=np.float64), (n,))
    pos = np.full((n, 3), np.nan)
    clk = np.full(n, np.nan)
    tgd = np.zeros(n)
    valid = np.zeros(n, dtype=bool)
    k, g = nav.kepler, nav.glonass
    k_rows, k_idx, g_rows, g_idx = [], [], [], []
    for j, sat in enumerate(sats):
        if sat[0] == "R":
            row = _select(g.sats, g.tb_ns, g.health, sat, t_ns)
            if row >= 0:
                g_rows.append(row)
                g_idx.append(j)
        elif sat[0] in "GECJ":
            row = _select(k.sats, k.toe_ns, k.fields["health"], sat, t_ns)
            if row >= 0:
                k_rows.append(row)
                k_idx.append(j)
    if k_rows:
        rows = np.array(k_rows)
        idx = np.array(k_idx)
        sysc = np.array([sats[j][0] for j in idx])
        pos[idx], clk[idx], tgd[idx] = _kepler(nav, rows, sysc, t_ns, off[idx])
        valid[idx] = True
    if g_rows:
        rows = np.array(g_rows)
        idx = np.array(g_idx)
        pos[idx], clk[idx], tgd[idx] = _glonass(nav, rows, t_ns, off[idx])
        valid[idx] = True
    return pos, clk, tgd, valid


def _sagnac(pos: NDArray[np.float64], tau: NDArray[np.float64]) -> NDArray[np.float64]:
    ang = OMEGA_E * tau
    c, s = np.cos(ang), np.sin(ang)
    return np.stack([c * pos[:, 0] + s * pos[:, 1], -s * pos[:, 0] + c * pos[:, 1], pos[:, 2]], axis=-1)


def transmit_states(
    nav: RinexNav,
    sats: list[str] | tuple[str, ...],
    t_rx_ns: int,
    receiver_ecef_m: ArrayLike,
    *,
    pseudorange_m: ArrayLike | None = None,
    receiver_clock_s: float = 0.0,
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64], NDArray[np.bool_]]:
    """Satellite positions at signal transmission, in the ECEF frame of reception (light time and Sagnac).

    With ``pseudorange_m`` the transmission time is ``t_rx - P / c - dt_sv`` (RTKLIB's approach: no
    receiver clock or position needed for the epoch); without, the geometric light time to
    ``receiver_ecef_m`` is iterated from the reception time ``t_rx - receiver_clock_s``.

    Returns
    -------
    position_m, clock_s, tgd_s, valid
        As :func:`satellite_states`; positions rotated by ``omega_E tau`` into the reception frame.

    Raises
    ------
    InvalidTypeError
        As :func:`satellite_states` for ``nav``, ``sats`` and ``t_rx_ns``; ``receiver_ecef_m``,
        ``pseudorange_m`` or ``receiver_clock_s`` not real.
    InvalidInputError
        ``t_rx_ns`` outside ``[0, MAX_GPS_NS]``; ``receiver_ecef_m`` not a finite (3,) vector within
        ``MAX_RECEIVER_RADIUS_M``; ``pseudorange_m`` not finite (n,) in ``[0, MAX_PSEUDORANGE_M]``;
        ``|receiver_clock_s|`` above ``MAX_RECEIVER_CLOCK_S``.
    """
    nav = instance("nav", nav, RinexNav, "a RinexNav (from read_nav)")
    sats = sat_list("sats", sats)
    t_rx_ns = _gps_time("t_rx_ns", t_rx_ns)
    rx = shaped("receiver_ecef_m", receiver_ecef_m, "(3,)", (3,))
    if np.linalg.norm(rx / MAX_RECEIVER_RADIUS_M) > 1.0:
        raise InvalidInputError(f"expected |receiver_ecef_m| <= {MAX_RECEIVER_RADIUS_M} m, got {rx.tolist()}")
    if pseudorange_m is not None:
        pr = shaped("pseudorange_m", pseudorange_m, f"({len(sats)},)", (len(sats),))
        if np.any((pr < 0.0) | (pr > MAX_PSEUDORANGE_M)):
            raise InvalidInputError(
                f"expected pseudorange_m in [0, {MAX_PSEUDORANGE_M}] m, got {pr.tolist()}"
            )
    receiver_clock_s = scalar(
        "receiver_clock_s",
        receiver_clock_s,
        minimum=-MAX_RECEIVER_CLOCK_S,
        maximum=MAX_RECEIVER_CLOCK_S,
        unit="s",
    )
    out = _transmit_states(
        nav, sats, t_rx_ns, rx, pseudorange_m=pseudorange_m, receiver_clock_s=receiver_clock_s
    )
    valid = out[3]
    finite_outputs("transmit_states", position_m=out[0][valid], clock_s=out[1][valid])
    return out


def _transmit_states(
    nav: RinexNav,
    sats: list[str] | tuple[str, ...],
    t_rx_ns: int,
    receiver_ecef_m: ArrayLike,
    *,
    pseudorange_m: ArrayLike | None = None,
    receiver_clock_s: float = 0.0,
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64], NDArray[np.bool_]]:
    rx = np.asarray(receiver_ecef_m, dtype=np.float64)
    n = len(sats)
    if pseudorange_m is not None:
        pr = np.asarray(pseudorange_m, dtype=np.float64)
        tau0 = np.where(np.isfinite(pr), pr, 0.0) / C
        _, clk, _, _ = _satellite_states(nav, sats, t_rx_ns, -tau0)
        pos, clk, tgd, valid = _satellite_states(nav, sats, t_rx_ns, -tau0 - np.nan_to_num(clk))
        valid &= np.isfinite(pr)
    else:
        tau = np.full(n, 0.075)
        for _ in range(3):
            pos, clk, tgd, valid = _satellite_states(nav, sats, t_rx_ns, -receiver_clock_s - tau)
            tau = np.linalg.norm(_sagnac(np.nan_to_num(pos), tau) - rx, axis=1) / C
    rho_tau = np.linalg.norm(np.nan_to_num(pos) - rx, axis=1) / C
    return _sagnac(pos, rho_tau), clk, tgd, valid
