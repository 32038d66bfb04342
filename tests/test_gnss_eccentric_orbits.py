"""Galileo E18 (eccentricity 0.164) through the engine: a real navigation excerpt that holds it is used
whole, E18's positions agree with a Kepler propagation written here in numpy (Galileo OS SIS ICD 5.1.1,
Kepler's equation solved by scipy's brentq), and a single-point solution of ranges computed here uses it.

The excerpt (``tests/data/SEPT2650_E18_excerpt.21P``, provenance in ``tests/data/README.md``) holds every GPS
and Galileo record of 00:50-02:00 GPST of 2021-09-22. Every E14 and E18 record of that file and of the corpus
navigation files flags its signals out of service or in test (I/NAV health 130 or 390, F/NAV 16 or 48), so
the engine, by the ICD, does not use them for a solution; the solution test sets the health word of the
real record to 0, as a healthy broadcast would have it. E14 has no record in this file.
"""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np
from scipy.optimize import brentq

from gnssatt import _core
from gnssatt.rinex import read_nav
from gnssatt.rinex.nav import nav_input
from gnssatt.sim.atmosphere import troposphere_delay_m

EXCERPT = Path(__file__).resolve().parent / "data" / "SEPT2650_E18_excerpt.21P"
#: Galileo OS SIS ICD 5.1.1: mu (m^3/s^2), Earth rotation (rad/s); IS-GPS-200 for GPS.
MU = {"E": 3.986004418e14, "G": 3.986005e14}
OMEGA_E = 7.2921151467e-5
C = 299792458.0
WEEK_NS = 604_800 * 10**9
#: 2021-09-22 01:30:00 GPST, ns since the GPS epoch: 10 min after E18's last toe of the excerpt.
T_NS = 1316308800 * 10**9 + 600 * 10**9


def _records() -> dict[str, np.ndarray]:
    return nav_input(read_nav(EXCERPT)).kepler


def _row(k: dict[str, np.ndarray], i: int) -> dict[str, float]:
    return {key: v[i] for key, v in k.items() if key != "sat" and np.ndim(v) == 1}


def _kepler_ecef(r: dict[str, float], system: str, t_ns: int) -> tuple[np.ndarray, float]:
    """ECEF position (m) and clock with the relativistic term (s) of a Keplerian record at GPST t_ns."""
    mu = MU[system]
    tk = (t_ns - int(r["toe_gpst_ns"])) / 1e9
    a = r["sqrt_a"] ** 2
    n = np.sqrt(mu / a**3) + r["delta_n"]
    m = r["m0"] + n * tk
    e = r["e"]
    mr = (m + np.pi) % (2 * np.pi) - np.pi
    ea = brentq(lambda x: x - e * np.sin(x) - mr, -np.pi - 1, np.pi + 1, xtol=1e-15)
    nu = np.arctan2(np.sqrt(1 - e * e) * np.sin(ea), np.cos(ea) - e)
    phi = nu + r["omega"]
    u = phi + r["cus"] * np.sin(2 * phi) + r["cuc"] * np.cos(2 * phi)
    rad = a * (1 - e * np.cos(ea)) + r["crs"] * np.sin(2 * phi) + r["crc"] * np.cos(2 * phi)
    inc = r["i0"] + r["idot"] * tk + r["cis"] * np.sin(2 * phi) + r["cic"] * np.cos(2 * phi)
    toe_sow = (int(r["toe_gpst_ns"]) % WEEK_NS) / 1e9
    big = r["omega0"] + (r["omega_dot"] - OMEGA_E) * tk - OMEGA_E * toe_sow
    xp, yp = rad * np.cos(u), rad * np.sin(u)
    pos = np.array(
        [
            xp * np.cos(big) - yp * np.cos(inc) * np.sin(big),
            xp * np.sin(big) + yp * np.cos(inc) * np.cos(big),
            yp * np.sin(inc),
        ]
    )
    tc = (t_ns - int(r["toc_gpst_ns"])) / 1e9
    relativistic = -2 * np.sqrt(mu) / C**2 * e * r["sqrt_a"] * np.sin(ea)
    clock = r["af0"] + r["af1"] * tc + r["af2"] * tc**2 + relativistic
    return pos, clock


def _with_af(k: dict[str, np.ndarray], i: int) -> dict[str, float]:
    r = _row(k, i)
    r["af0"], r["af1"], r["af2"] = (float(x) for x in k["af"][i])
    return r


def _chosen(k: dict[str, np.ndarray], sat: str, t_ns: int) -> int:
    """The record the engine's rule picks (nearest toe; Galileo I/NAV before F/NAV at the same toe)."""
    rows = [int(i) for i in np.flatnonzero(k["sat"] == sat)]

    def fnav(i: int) -> bool:
        bits = k["data_source"][i]
        return bool(np.isfinite(bits) and int(bits) & 0x002 and not int(bits) & 0x005)

    return min(rows, key=lambda i: (abs(t_ns - int(k["toe_gpst_ns"][i])), fnav(i)))


def test_the_navigation_with_e18_is_used_whole() -> None:
    k = _records()
    e18 = k["sat"] == "E18"
    assert e18.sum() == 4 and np.all((k["e"][e18] > 0.16) & (k["e"][e18] < 0.17))
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no record skipped
        s = _core.gnss_satellite_states(
            nav_input(read_nav(EXCERPT)).navigation(), ["E18", "G06"], np.array([T_NS, T_NS])
        )
    # E18 out of service by its health word (I/NAV 130: E1-B and E5b HS = 1), G06 used
    assert s.valid.tolist() == [False, True]


def test_e18_positions_match_a_numpy_kepler_propagation() -> None:
    k = _records()
    k["health"] = np.where(k["sat"] == "E18", 0.0, k["health"])
    nav = _core.Navigation(kepler=k)
    for dt_s in (-3000, 0, 1800, 7200):
        t = T_NS + dt_s * 10**9
        i = _chosen(k, "E18", t)
        want, clock = _kepler_ecef(_with_af(k, i), "E", t)
        s = _core.gnss_satellite_states(nav, ["E18"], np.array([t]))
        assert s.valid[0]
        # float64 rounding of a 2.8e7 m vector: micrometres
        np.testing.assert_allclose(s.position_m[0], want, rtol=0, atol=1e-5)
        assert abs(s.clock_s[0] - clock) < 1e-15
        # the orbit is eccentric here: the radius is not the semi-major axis
        assert abs(np.linalg.norm(want) - k["sqrt_a"][i] ** 2) > 1e5


def _transmit(r: dict[str, float], system: str, t_rx: int, x: np.ndarray) -> tuple[np.ndarray, float]:
    """Satellite position at transmission in the ECEF frame of reception (light time iterated, Earth
    rotation during it) and its clock, s."""
    tau = 0.075
    for _ in range(10):
        p, clk = _kepler_ecef(r, system, t_rx - round(tau * 1e9))
        th = OMEGA_E * tau
        p = np.array([np.cos(th) * p[0] + np.sin(th) * p[1], -np.sin(th) * p[0] + np.cos(th) * p[1], p[2]])
        tau = np.linalg.norm(p - x) / C
    return p, clk


def test_a_single_point_solution_uses_e18() -> None:
    k = _records()
    k["health"] = np.where(k["sat"] == "E18", 0.0, k["health"])
    # a receiver on the ground below E18, so that E18 stands near the zenith
    e18 = _kepler_ecef(_with_af(k, _chosen(k, "E18", T_NS)), "E", T_NS)[0]
    lat, lon, h = np.arcsin(e18[2] / np.linalg.norm(e18)), np.arctan2(e18[1], e18[0]), 0.0
    x = 6_371_000.0 * np.array([np.cos(lat) * np.cos(lon), np.cos(lat) * np.sin(lon), np.sin(lat)])
    # geodetic latitude of x on WGS-84, for the troposphere model
    f = 1 / 298.257223563
    e2 = f * (2 - f)
    p = np.hypot(x[0], x[1])
    glat = np.arctan2(x[2], p * (1 - e2))
    for _ in range(10):
        n = 6378137.0 / np.sqrt(1 - e2 * np.sin(glat) ** 2)
        h = p / np.cos(glat) - n
        glat = np.arctan2(x[2], p * (1 - e2 * n / (n + h)))
    up = np.array([np.cos(glat) * np.cos(lon), np.cos(glat) * np.sin(lon), np.sin(glat)])
    dt_rx = 1e-4
    sats, code = [], []
    for sat in dict.fromkeys(k["sat"].tolist()):
        i = _chosen(k, sat, T_NS)
        r = _with_af(k, i)
        if k["health"][i] != 0:
            continue
        # the label is receiver time: true reception = label - receiver clock
        pos, clk = _transmit(r, sat[0], T_NS - round(dt_rx * 1e9), x)
        el = np.arcsin(np.dot(pos - x, up) / np.linalg.norm(pos - x))
        if el < np.radians(15):
            continue
        # the group delay the ICDs add to the broadcast clock for the first frequency: GPS L1 -TGD, Galileo
        # E1 with the I/NAV record -BGD(E1, E5b)
        tgd = k["tgd_s"][i][0] if sat[0] == "G" else k["tgd_s"][i][1]
        rho = np.linalg.norm(pos - x)
        tropo = float(np.ravel(troposphere_delay_m(float(glat), float(h), el))[0])
        code.append(rho + C * (dt_rx - (clk - tgd)) + tropo)
        sats.append(sat)
    assert "E18" in sats and len(sats) >= 8, sats
    arr = np.full((1, len(sats), 3), np.nan)
    arr[0, :, 0] = code
    args = (np.array([T_NS]), sats, np.full(len(sats), 99, dtype=np.int64))
    sp = _core.gnss_single_point(_core.Navigation(kepler=k), *args, arr, systems="GE")
    assert sp.satellites[0] == len(sats)
    assert sp.satellites_per_system[0].tolist() == [
        sum(s[0] == "G" for s in sats),
        0,
        sum(s[0] == "E" for s in sats),
        0,
        0,
    ]
    # measured 0.3 mm: the engine's Niell mapping has the seasonal term, the simulator's the annual mean
    assert np.linalg.norm(sp.position_m[0] - x) < 0.01, np.linalg.norm(sp.position_m[0] - x)
    # E18's range moved by 30 m moves the solution: it is used, not merely counted
    arr[0, sats.index("E18"), 0] += 30.0
    moved = _core.gnss_single_point(_core.Navigation(kepler=k), *args, arr, systems="GE").position_m[0]
    assert np.linalg.norm(moved - x) > 1.0
