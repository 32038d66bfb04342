"""The multi-GNSS, multi-frequency simulator: files read back with every signal of every system, and a truth
that agrees with the navigation records (light time and Earth rotation recomputed here, independently of
the engine's ``gnss_transmit_states`` that the simulator uses; the records evaluated by the engine's
ephemerides, themselves checked against closed forms, Skydel truth and the prototype's frozen outputs in
tests/test_gnss_ephemeris.py and tests/test_gnss_prototype_reference.py), with the simulator's two-body
orbits, with the IS-GPS-200 Klobuchar closed form written here, and GLONASS records on the UTC grid of
broadcast files."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import numpy as np
import pytest

from gnssatt import _core
from gnssatt.errors import InvalidInputError
from gnssatt.gnss.session_input import session_input
from gnssatt.rinex import read_nav, read_obs
from gnssatt.rinex.nav import NavInput, gps_ns, nav_input
from gnssatt.rinex.signals import slot_frequency_hz
from gnssatt.rinex.writer import write_nav_from_constellation
from gnssatt.sim.rinex_scenario import (
    KLOBUCHAR,
    SIM_CODES,
    SimulatedGnss,
    gnss_constellation,
    simulate_gnss_rinex,
)

C = 299_792_458.0
OMEGA_E = 7.2921151467e-5  # IS-GPS-200 (the simulator's Earth)
T0 = np.datetime64("2024-03-01T10:00:00", "ns")
ANTENNAS = [[0.0, 0.0, 0.0], [1.5, 0.0, 0.0], [0.0, 0.0, 1.0], [1.0, 0.2, -0.8]]


def satellite_states(
    nav: NavInput, sats: list[str], t_ns: int, offset_s: float | np.ndarray = 0.0
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The engine's broadcast positions (ECEF of the instant), clocks and validity of ``sats`` at GPST
    ``t_ns`` + ``offset_s``."""
    n = len(sats)
    off = np.broadcast_to(np.asarray(offset_s, dtype=np.float64), (n,)).copy()
    t = np.full(n, t_ns, dtype=np.int64)
    s = _core.gnss_satellite_states(
        _core.Navigation(kepler=nav.kepler, glonass=nav.glonass), sats, t, offset_s=off
    )
    return s.position_m, s.clock_s, s.valid


def klobuchar_l1_s(
    a: Sequence[float], b: Sequence[float], lat: float, lon: float, az: float, el: float, t: float
) -> float:
    """IS-GPS-200 20.3.3.5.2.5 (figure 20-4) term by term: the L1 group delay, s; angles in radians."""
    e = el / np.pi
    psi = 0.0137 / (e + 0.11) - 0.022
    phi_i = min(max(lat / np.pi + psi * np.cos(az), -0.416), 0.416)
    lam_i = lon / np.pi + psi * np.sin(az) / np.cos(phi_i * np.pi)
    phi_m = phi_i + 0.064 * np.cos((lam_i - 1.617) * np.pi)
    local = (4.32e4 * lam_i + t) % 86400.0
    f = 1.0 + 16.0 * (0.53 - e) ** 3
    amp = max(sum(a[n] * phi_m**n for n in range(4)), 0.0)
    per = max(sum(b[n] * phi_m**n for n in range(4)), 72000.0)
    x = 2 * np.pi * (local - 50400.0) / per
    return f * (5e-9 + (amp * (1 - x**2 / 2 + x**4 / 24) if abs(x) < 1.57 else 0.0))


@pytest.fixture(scope="module")
def noiseless(tmp_path_factory: pytest.TempPathFactory) -> SimulatedGnss:
    return simulate_gnss_rinex(
        tmp_path_factory.mktemp("gnss"), ANTENNAS, [-40.0, 5.0, 3.0], n_epochs=4, rng=5,
        code_sigma_m=0.0, phase_sigma_m=0.0, doppler_sigma_hz=0.0, receiver_clock_s=[3e-4, -2e-4, 1e-5, 0.0],
        slips=[(2, 1, "G05", 1)], atmosphere=False,
    )  # fmt: skip


@pytest.mark.slow
def test_every_signal_of_every_system_found(noiseless: SimulatedGnss) -> None:
    s = noiseless
    assert {x[0] for x in s.sats} == set("GRECJ")
    obs = [read_obs(p) for p in s.obs_paths]
    si = session_input(obs, nav=read_nav(s.nav_path))
    assert si.sats == s.sats and len(si.time_gpst_ns) == 4 and si.epochs_dropped == (0, 0, 0, 0)
    for o in obs:
        for system, bands in SIM_CODES.items():
            want = tuple(f"C{b}/L{b}" if b else "" for b in bands)
            assert si.signal_codes[o.path][system] == want
    for k, sat in enumerate(s.sats):
        slots = [j for j, b in enumerate(SIM_CODES[sat[0]]) if b]
        for arr in (si.code_m, si.phase_cycles, si.doppler_hz, si.snr_dbhz):
            assert np.isfinite(arr[:, :, k, slots]).all(), sat
            assert np.isnan(arr[:, :, k, [j for j in range(3) if j not in slots]]).all()
    glo = [k for k, sat in enumerate(s.sats) if sat[0] == "R"]
    assert si.glonass_channel[glo].tolist() == [s.glonass_channels[s.sats[k]] for k in glo]
    np.testing.assert_allclose(si.approx_position_m, s.antenna_ecef_m[0], atol=1e-4)
    ni = nav_input(read_nav(s.nav_path))
    assert set(np.char.array(ni.kepler["sat"]).astype("U1").tolist()) == set("GECJ")
    assert ni.leap_seconds == 18 and ni.klobuchar is None


def test_slip_flagged_and_applied(noiseless: SimulatedGnss) -> None:
    s = noiseless
    si = session_input([read_obs(p) for p in s.obs_paths])
    k = s.sats.index("G05")
    (slip,) = s.slips
    assert slip[:4] == (2, 1, "G05", 1) and slip[4] != 0
    assert si.lli[1, :, k, 1].tolist() == [0, 0, 1, 0] and not si.lli[0].any()
    lam = C / 1227.60e6
    # noise-free: phase - code / lambda is the ambiguity, constant but for the slip (3.3 km of GPS
    # ranges fit in float64 to ~1e-8 cycles; the RINEX fields round to 1e-3)
    n = si.phase_cycles[1, :, k, 1] - si.code_m[1, :, k, 1] / lam
    np.testing.assert_allclose(np.diff(n), [0, slip[4], 0], atol=0.02)


def test_baselines_and_positions_agree(noiseless: SimulatedGnss) -> None:
    s = noiseless
    lat, lon = np.radians(50.0), np.radians(36.2)
    e = [-np.sin(lon), np.cos(lon), 0.0]
    nvec = [-np.sin(lat) * np.cos(lon), -np.sin(lat) * np.sin(lon), np.cos(lat)]
    u = [np.cos(lat) * np.cos(lon), np.cos(lat) * np.sin(lon), np.sin(lat)]
    enu = np.einsum(
        "ij,tai->taj", np.array([e, nvec, u]).T, s.antenna_ecef_m[:, 1:] - s.antenna_ecef_m[:, :1]
    )
    np.testing.assert_allclose(enu, s.baselines_enu_m, atol=1e-9)
    np.testing.assert_allclose(np.linalg.norm(s.baselines_enu_m[0, 0]), 1.5, atol=1e-12)


@pytest.mark.slow
def test_ranges_match_the_navigation_records(noiseless: SimulatedGnss) -> None:
    s = noiseless
    nav = nav_input(read_nav(s.nav_path))
    obs = [read_obs(p) for p in s.obs_paths]
    t_ns = int(gps_ns(s.time[:1])[0])
    worst = 0.0
    for i, o in enumerate(obs):
        rx = s.antenna_ecef_m[0, i]
        dt_rx = s.receiver_clock_s[i]
        for sat in s.sats:
            band = SIM_CODES[sat[0]][0]
            code = o.get(f"C{band}")[0, o.sats.index(sat)]
            # light time solved here by fixed point: tau = |Rz(-w tau) r_sat(T - dt_rx - tau) - rx| / c
            tau = 0.07
            for _ in range(10):
                p, clk, ok = satellite_states(nav, [sat], t_ns, -dt_rx - tau)
                a = OMEGA_E * tau
                rot = np.array([[np.cos(a), np.sin(a), 0.0], [-np.sin(a), np.cos(a), 0.0], [0.0, 0.0, 1.0]])
                tau = np.linalg.norm(rot @ p[0] - rx) / C
            assert ok[0]
            worst = max(worst, abs(code - (C * tau + C * (dt_rx - clk[0]))))
    assert worst < 1.5e-3  # the 14.3f field rounds to 0.5 mm


def test_kepler_records_reproduce_the_two_body_orbits(noiseless: SimulatedGnss) -> None:
    nav = nav_input(read_nav(noiseless.nav_path))
    orbits = gnss_constellation("GECJ")
    t = 600.0
    truth, _ = orbits.state_ecef(t)
    pos, _, ok = satellite_states(nav, list(orbits.ids), int(gps_ns(np.array([T0]))[0]), t)
    assert ok.all()
    err = np.linalg.norm(pos - truth, axis=1)
    assert err.max() < 1e-3, dict(zip(orbits.ids, err, strict=True))


def test_doppler_is_the_range_rate(noiseless: SimulatedGnss) -> None:
    s = noiseless
    o = read_obs(s.obs_paths[2])
    for sat in ("G10", "R02", "E02", "C20", "J01"):
        if sat not in s.sats:
            continue
        k = o.sats.index(sat)
        band = SIM_CODES[sat[0]][0]
        code = o.get(f"C{band}")[:, k]
        ch = s.glonass_channels.get(sat)
        lam = C / slot_frequency_hz(sat[0], 0, ch)  # type: ignore[operator]
        rate = (code[2] - code[0]) / 2.0  # central difference over 1 s epochs
        assert o.get(f"D{band}")[1, k] * -lam == pytest.approx(rate, abs=2e-3)


def test_seeded_and_checked(tmp_path: Path) -> None:
    kw = {"n_epochs": 2, "systems": "GE", "frequencies": 2}
    a = simulate_gnss_rinex(tmp_path / ".", ANTENNAS[:2], [0.0, 0.0, 0.0], rng=3, **kw)  # type: ignore[arg-type]
    text = a.obs_paths[1].read_text()
    b = simulate_gnss_rinex(tmp_path, ANTENNAS[:2], [0.0, 0.0, 0.0], rng=np.random.default_rng(3), **kw)  # type: ignore[arg-type]
    assert b.obs_paths[1].read_text() == text
    assert "C5Q" not in text and "L7Q" in text  # two slots: E1, E5b
    with pytest.raises(InvalidInputError, match="slip"):
        simulate_gnss_rinex(tmp_path, ANTENNAS[:2], [0.0, 0.0, 0.0], slips=[(0, 0, "G99", 0)], **kw)  # type: ignore[arg-type]
    with pytest.raises(InvalidInputError, match="systems"):
        simulate_gnss_rinex(tmp_path, ANTENNAS[:2], [0.0, 0.0, 0.0], systems="GX")
    with pytest.raises(InvalidInputError, match="antennas_body_m"):
        simulate_gnss_rinex(tmp_path, ANTENNAS[:1], [0.0, 0.0, 0.0])


def test_glonass_records_on_the_utc_quarter_hours(tmp_path: Path) -> None:
    # Broadcast t_b is a 15-minute index of the day in UTC(SU) = UTC + 3 h, and files have records at 15
    # and 45 minutes past each UTC hour; T0 is 10:00:00 GPST = 09:59:42 UTC, so the hour from it is covered
    # by 09:45, 10:15, 10:45 and 11:15 UTC (every instant within 15 minutes of one).
    path = tmp_path / "glo.rnx"
    first = write_nav_from_constellation(path, gnss_constellation("R"), T0, span_s=3600.0)
    labels = sorted({line[4:23] for line in path.read_text().splitlines() if line.startswith("R01 ")})
    assert labels == [
        "2024 03 01 09 45 00",
        "2024 03 01 10 15 00",
        "2024 03 01 10 45 00",
        "2024 03 01 11 15 00",
    ]
    g = nav_input(read_nav(path)).glonass
    assert len(g["sat"]) == 4 * 24
    # the reader turns the UTC labels back into GPST: t_b = label + 18 s
    t0 = int(gps_ns(np.array([T0]))[0])
    assert sorted(set(g["tb_gpst_ns"].tolist())) == [t0 + (k * 1800 - 882) * 10**9 for k in range(4)]
    assert (first == t0 - 882 * 10**9).all()


def test_neighbouring_glonass_records_agree(tmp_path: Path) -> None:
    # each GLONASS record continues the previous one by the ICD's equations of motion, so the choice
    # between two records (15 min from both) does not move the satellite: without it the ICD's J2 would
    # put them metres apart
    path = tmp_path / "glo.rnx"
    write_nav_from_constellation(path, gnss_constellation("R"), T0, span_s=3600.0)
    g = nav_input(read_nav(path)).glonass
    for sat in ("R01", "R13"):
        rows = np.flatnonzero(g["sat"] == sat)
        for k in range(3):
            mid = int(g["tb_gpst_ns"][rows[k]]) + 900 * 10**9
            a, b = (
                _core.gnss_satellite_states(
                    _core.Navigation(glonass={f: v[r : r + 1] for f, v in g.items()}), [sat], np.array([mid])
                ).position_m[0]
                for r in rows[k : k + 2]
            )
            assert np.linalg.norm(a - b) < 2e-3


@pytest.mark.slow
def test_atmosphere_delays_code_and_advances_phase(tmp_path: Path) -> None:
    kw = {
        "n_epochs": 1, "rng": 9, "code_sigma_m": 0.0, "phase_sigma_m": 0.0, "receiver_clock_s": [1e-5, 0.0],
        "systems": "GR",
    }  # fmt: skip
    vac = simulate_gnss_rinex(tmp_path / ".", ANTENNAS[:2], [0.0, 0.0, 0.0], atmosphere=False, **kw)  # type: ignore[arg-type]
    air_dir = tmp_path / "air"
    air_dir.mkdir()
    air = simulate_gnss_rinex(air_dir, ANTENNAS[:2], [0.0, 0.0, 0.0], **kw)  # type: ignore[arg-type]
    assert air.sats == vac.sats
    nav = nav_input(read_nav(air.nav_path))
    assert nav.klobuchar is not None
    np.testing.assert_array_equal(nav.klobuchar, KLOBUCHAR)
    a, v = read_obs(air.obs_paths[1]), read_obs(vac.obs_paths[1])
    rx = air.antenna_ecef_m[0, 1]
    lat, lon = np.radians(50.0), np.radians(36.2)
    east = np.array([-np.sin(lon), np.cos(lon), 0.0])
    north = np.array([-np.sin(lat) * np.cos(lon), -np.sin(lat) * np.sin(lon), np.cos(lat)])
    up = np.cross(east, north)
    t = int(gps_ns(air.time[:1])[0])
    for sat in air.sats:
        k = a.sats.index(sat)
        for slot, band in enumerate(SIM_CODES[sat[0]][:2]):
            f = slot_frequency_hz(sat[0], slot, air.glonass_channels.get(sat))
            lam = C / f  # type: ignore[operator]
            d_code = a.get(f"C{band}")[0, k] - v.get(f"C{band}")[0, k]  # I + T
            d_phase = (a.get(f"L{band}")[0, k] - v.get(f"L{band}")[0, k]) * lam  # T - I
            iono, tropo = (d_code - d_phase) / 2, (d_code + d_phase) / 2
            p = satellite_states(nav, [sat], t, -0.075)[0][0]  # direction: light time irrelevant
            los = (p - rx) / np.linalg.norm(p - rx)
            el, az = np.arcsin(los @ up), np.arctan2(los @ east, los @ north)
            want = (
                C
                * klobuchar_l1_s(KLOBUCHAR[:4], KLOBUCHAR[4:], lat, lon, az, el, t * 1e-9)
                * (1575.42e6 / f) ** 2  # type: ignore[operator]
            )
            assert iono == pytest.approx(float(want), abs=2e-3)  # the 14.3f fields round to 0.5 mm
            # the troposphere: about 2.4 m at the zenith, growing as 1 / sin(el)
            assert tropo == pytest.approx(2.38 / np.sin(el), rel=0.05)


def test_engine_code_solution_recovers_the_antennas(tmp_path: Path) -> None:
    # The engine's single-point solution (Rust ephemerides, Klobuchar, Saastamoinen + Niell) on the
    # simulated files: noise-free code gives the true antenna positions and receiver clocks. Measured on
    # the ephem branch's binding: <= 1.4 mm for G, R, E, C and GRECJ (6-10 m with atmosphere=False).
    s = simulate_gnss_rinex(
        tmp_path, ANTENNAS[:2], [-40.0, 5.0, 3.0], n_epochs=2, rng=2, code_sigma_m=0.0, phase_sigma_m=0.0,
        receiver_clock_s=[3e-4, -2e-4], elevation_min_deg=5.0,
    )  # fmt: skip
    nav = read_nav(s.nav_path)
    si = session_input([read_obs(p) for p in s.obs_paths], nav=nav)
    ni = nav_input(nav)
    for r in range(2):
        sp = _core.gnss_single_point(
            ni.navigation(), si.time_gpst_ns, list(si.sats),
            si.glonass_channel, np.ascontiguousarray(si.code_m[r]), approx_position_m=si.approx_position_m[r],
            systems="GRECJ", frequencies=1, elevation_mask_deg=5.0,
        )  # fmt: skip
        assert (sp.satellites == len(s.sats)).all()
        np.testing.assert_allclose(sp.position_m, s.antenna_ecef_m[:, r], atol=5e-3)
        np.testing.assert_allclose(sp.clock_s, s.receiver_clock_s[r], atol=1e-10)  # every system's clock
