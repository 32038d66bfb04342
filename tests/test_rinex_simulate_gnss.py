"""The multi-GNSS, multi-frequency simulator: files read back with every signal of every system, and a truth
that agrees with the navigation records (light time and Earth rotation recomputed here, independently of
``transmit_states``) and with the simulator's two-body orbits."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from gnssatt.errors import InvalidInputError
from gnssatt.rinex import GlonassEphemerides, RinexNav, read_nav, read_obs, satellite_states
from gnssatt.rinex.nav import gps_ns
from gnssatt.rinex.scenario import SIM_CODES, SimulatedGnss, gnss_constellation, simulate_gnss_rinex
from gnssatt.rinex.session_input import nav_input, session_input
from gnssatt.rinex.signals import slot_frequency_hz
from gnssatt.rinex.writer import write_nav_from_constellation

C = 299_792_458.0
OMEGA_E = 7.2921151467e-5  # IS-GPS-200 (the simulator's Earth)
T0 = np.datetime64("2024-03-01T10:00:00", "ns")
ANTENNAS = [[0.0, 0.0, 0.0], [1.5, 0.0, 0.0], [0.0, 0.0, 1.0], [1.0, 0.2, -0.8]]


@pytest.fixture(scope="module")
def noiseless(tmp_path_factory: pytest.TempPathFactory) -> SimulatedGnss:
    return simulate_gnss_rinex(
        tmp_path_factory.mktemp("gnss"), ANTENNAS, [-40.0, 5.0, 3.0], n_epochs=4, rng=5,
        code_sigma_m=0.0, phase_sigma_m=0.0, doppler_sigma_hz=0.0, receiver_clock_s=[3e-4, -2e-4, 1e-5, 0.0],
        slips=[(2, 1, "G05", 1)],
    )  # fmt: skip


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


def test_ranges_match_the_navigation_records(noiseless: SimulatedGnss) -> None:
    s = noiseless
    nav = read_nav(s.nav_path)
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
                p, clk, _, ok = satellite_states(nav, [sat], t_ns, np.array([-dt_rx - tau]))
                a = OMEGA_E * tau
                rot = np.array([[np.cos(a), np.sin(a), 0.0], [-np.sin(a), np.cos(a), 0.0], [0.0, 0.0, 1.0]])
                tau = np.linalg.norm(rot @ p[0] - rx) / C
            assert ok[0]
            worst = max(worst, abs(code - (C * tau + C * (dt_rx - clk[0]))))
    assert worst < 1.5e-3  # the 14.3f field rounds to 0.5 mm


def test_kepler_records_reproduce_the_two_body_orbits(noiseless: SimulatedGnss) -> None:
    nav = read_nav(noiseless.nav_path)
    orbits = gnss_constellation("GECJ")
    t = 600.0
    truth, _ = orbits.state_ecef(t)
    pos, _, _, ok = satellite_states(nav, list(orbits.ids), int(gps_ns(np.array([T0]))[0]), t)
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


def test_neighbouring_glonass_records_agree(tmp_path: Path) -> None:
    # each GLONASS record continues the previous one, so the choice between two records (15 min from
    # both) does not move the satellite: without it the ICD's J2 would put them metres apart
    path = tmp_path / "glo.rnx"
    write_nav_from_constellation(path, gnss_constellation("R"), T0, span_s=3600.0)
    nav = read_nav(path)
    g = nav.glonass
    assert len(g) == 3 * 24

    def only(rows: np.ndarray) -> RinexNav:
        fields = {f: getattr(g, f)[rows] for f in g.__dataclass_fields__}
        return replace(nav, glonass=GlonassEphemerides(**fields))

    for sat in ("R01", "R13"):
        rows = np.flatnonzero(g.sats == sat)
        for k in range(2):
            mid = int(g.tb_ns[rows[k]]) + 900 * 10**9
            a = satellite_states(only(rows[k : k + 1]), [sat], mid)[0]
            b = satellite_states(only(rows[k + 1 : k + 2]), [sat], mid)[0]
            assert np.linalg.norm(a - b) < 2e-3
