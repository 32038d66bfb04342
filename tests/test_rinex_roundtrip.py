"""Round trip: simulated 2- and 3-antenna data written as RINEX 3 (observations) and GPS navigation files
whose broadcast records reproduce the simulator's orbits, read back and processed: the true baseline
direction / attitude comes out."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from gnssatt import _core, sim
from gnssatt.cli import main
from gnssatt.gnss.attitude import attitude_from_rinex
from gnssatt.rinex import gps_ns, read_nav, read_obs
from gnssatt.rinex.nav import nav_input
from gnssatt.rotation import rotation_from_euler
from gnssatt.sim.rinex_scenario import write_array_rinex

T0 = np.datetime64("2024-03-01T10:00:00", "ns")
EULER = [-40.0, 5.0, 3.0]  # psi (compass heading 40), theta, phi of Bunyaeva et al.


def _scenario(tmp_path: Path, antennas: np.ndarray, n_ep: int = 12) -> tuple[list[Path], Path]:
    rx = sim.GroundReceiver(lat_deg=50.0, lon_deg=36.2, height_m=150.0)
    gps = sim.gps_nominal()
    t = np.arange(n_ep) * 10.0
    el = np.degrees(np.arcsin(sim.line_of_sight(rx, gps, t).los[..., 2]))
    vis = gps.select(list(np.array(gps.ids)[np.all(el > 5.0, axis=0)]))
    geom = sim.line_of_sight(rx, vis, t)
    meas = sim.simulate_array(
        geom, rotation_from_euler(EULER), antennas, vis.wavelengths_m(), np.random.default_rng(7),
        code_sigma_m=0.3, phase_sigma_rad=0.03, clock_bias_s=np.linspace(0.0, 3e-7, len(antennas)),
    )  # fmt: skip
    paths, nav = write_array_rinex(tmp_path, meas, t, gps, vis.ids, rx)
    return list(paths), nav


def test_written_files_read_back(tmp_path: Path) -> None:
    paths, nav_path = _scenario(tmp_path, np.array([[0.0, 0, 0], [1.2, 0, 0]]), n_ep=2)
    obs = read_obs(paths[0])
    assert obs.version == pytest.approx(3.04) and obs.codes == ("C1C", "L1C", "D1C")
    assert obs.code_for("G", "L", 1) == "L1C"
    nav = nav_input(read_nav(nav_path))
    gps = sim.gps_nominal()
    n = len(gps.ids)
    t = np.full(n, int(gps_ns(np.array([T0]))[0]), dtype=np.int64)
    states = _core.gnss_satellite_states(
        _core.Navigation(kepler=nav.kepler, glonass=nav.glonass), list(gps.ids), t, offset_s=np.full(n, 60.0)
    )
    pos, clk, valid = states.position_m, states.clock_s, states.valid
    truth, _ = gps.state_ecef(60.0)
    assert valid.all() and np.all(np.abs(clk) < 1e-15)
    assert np.max(np.linalg.norm(pos - truth, axis=1)) < 1e-3  # broadcast model reproduces two-body orbits


@pytest.mark.slow
def test_two_antennas_baseline_direction(tmp_path: Path) -> None:
    paths, nav = _scenario(tmp_path, np.array([[0.0, 0, 0], [1.2, 0, 0]]))
    res = attitude_from_rinex(paths, nav, method="ml", elevation_mask_deg=5.0)
    assert res.mode == "baseline" and res.solved.all() and set(res.method) == {"ml"}
    np.testing.assert_allclose(res.angles_deg[:, 0], 40.0, atol=1.0)  # azimuth of the nose baseline
    np.testing.assert_allclose(res.angles_deg[:, 1], 5.0, atol=1.0)
    lam = attitude_from_rinex(paths, nav, method="lambda", elevation_mask_deg=5.0)
    assert lam.fixed.all() and set(lam.method) == {"lambda"}
    assert lam.baseline_length_m == pytest.approx(1.2, abs=0.02)
    np.testing.assert_allclose(lam.angles_deg, res.angles_deg, atol=1.0)


@pytest.mark.slow
def test_three_antennas_attitude_and_cli(tmp_path: Path) -> None:
    ant = sim.equilateral_triangle(1.0, plane="xz")
    paths, nav = _scenario(tmp_path, ant, n_ep=4)
    res = attitude_from_rinex(paths, nav, ant[1:], elevation_mask_deg=5.0)
    assert res.mode == "attitude" and res.solved.all()
    np.testing.assert_allclose(res.angles_deg, np.tile([40.0, 5.0, 3.0], (4, 1)), atol=1.0)
    base = tmp_path / "baselines.txt"
    np.savetxt(base, ant[1:])
    out = tmp_path / "results.csv"
    argv = [
        "attitude",
        "--nav",
        str(nav),
        "--baselines",
        str(base),
        "--out",
        str(out),
        "--elevation-mask",
        "5",
    ]
    for p in paths:
        argv += ["--obs", str(p)]
    assert main(argv) == 0
    lines = out.read_text().splitlines()
    head = lines[0].split(",")
    assert head[:8] == "time_gpst,heading_deg,pitch_deg,roll_deg,method,fixed,state,satellites".split(",")
    # one set of baseline columns per rover, then the sigma of each angle (docs/conventions.md)
    assert head[8:18] == [
        *("east_m", "north_m", "up_m", "length_m", "east_m_2", "north_m_2", "up_m_2", "length_m_2"),
        *("heading_sigma_deg", "pitch_sigma_deg"),
    ]
    assert lines[1].startswith("2024-03-01T10:00:00.000,")
    assert out.with_suffix(".png").is_file()
