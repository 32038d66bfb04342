"""Moving platforms of :mod:`gnssatt.sim.platforms`: trajectories against closed forms (circular turns,
coordinated bank, swell amplitudes), the attitude against an aerospace yaw-pitch-roll matrix built here
with scipy, antenna positions = position + R lever arm, the RINEX files read back by :mod:`gnssatt.rinex`
(epochs, satellites, outages, tree masks, loss-of-lock indicators, Doppler against the phase's rate), and
reproducibility from a seed."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from gnssatt import sim
from gnssatt.errors import InvalidInputError, WorkLimitError
from gnssatt.frames import dcm_ecef_from_enu, ecef_to_geodetic, geodetic_to_ecef
from gnssatt.rinex import read_obs
from gnssatt.sim import Blockage, Leg, NoiseProfile, Trajectory

#: ENU <- NED and FRD (forward, right, down) <- gnssatt body (X nose, Y up, Z right wing).
_ENU_FROM_NED = np.array([[0.0, 1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, -1.0]])
_FRD_FROM_BODY = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, -1.0, 0.0]])


def _aerospace_body_to_enu(
    heading_deg: np.ndarray, pitch_deg: np.ndarray, roll_deg: np.ndarray
) -> np.ndarray:
    """(n, 3, 3) body -> ENU from the aerospace yaw-pitch-roll (intrinsic z-y-x in NED, right wing down
    positive), independent of gnssatt's eq. (5) angles."""
    ned_from_frd = Rotation.from_euler(
        "ZYX", np.column_stack([heading_deg, pitch_deg, roll_deg]), degrees=True
    )
    return np.einsum("ij,tjk,kl->til", _ENU_FROM_NED, ned_from_frd.as_matrix(), _FRD_FROM_BODY)


def test_turn_is_a_circular_arc_of_radius_speed_over_rate() -> None:
    v, rate, h0 = 10.0, 9.0, 30.0
    traj = Trajectory((Leg(5.0, v), Leg(20.0, v, rate)), heading0_deg=h0)
    t = np.linspace(5.0, 25.0, 41)
    pos, eul = traj.at(t)
    h = np.radians(h0)
    start = 5.0 * v * np.array([np.sin(h), np.cos(h)])  # end of the straight leg
    radius = v / np.radians(rate)
    centre = start + radius * np.array([np.cos(h), -np.sin(h)])  # to the right of the track
    np.testing.assert_allclose(np.linalg.norm(pos[:, :2] - centre, axis=1), radius, rtol=1e-12)
    heading = -eul[:, 0]
    expected = (h0 + rate * (t - 5.0) + 180.0) % 360.0 - 180.0
    np.testing.assert_allclose(np.angle(np.exp(1j * np.radians(heading - expected))), 0.0, atol=1e-12)
    np.testing.assert_allclose(pos[:, 2], 0.0)


def test_climb_gives_the_flight_path_angle_and_a_coordinated_turn_its_bank() -> None:
    traj = Trajectory(
        (Leg(10.0, 60.0, 0.0, 4.0), Leg(10.0, 60.0, 3.0)), start_enu_m=(0.0, 0.0, 300.0), banked=True
    )
    pos, eul = traj.at([5.0, 15.0])
    assert pos[0, 2] == pytest.approx(300.0 + 20.0)
    assert eul[0, 1] == pytest.approx(np.degrees(np.arctan(4.0 / 60.0)))
    assert eul[0, 2] == pytest.approx(0.0)
    # standard-rate turn at 60 m/s: tan(bank) = 60 * 0.05235988 / 9.80665 = 0.3203533, whose arctangent
    # (its series to x^11) is 0.3100235 rad = 17.76303 deg
    assert eul[1, 2] == pytest.approx(17.76303, abs=1e-4)
    assert pos[1, 2] == pytest.approx(340.0)


def test_swell_reaches_its_amplitudes_at_the_quarter_periods() -> None:
    traj = Trajectory(
        (Leg(100.0, 6.0),), roll_amplitude_deg=15.0, roll_period_s=8.0, pitch_amplitude_deg=10.0,
        pitch_period_s=6.0, heave_amplitude_m=1.5, heave_period_s=7.0,
    )  # fmt: skip
    pos, eul = traj.at([2.0, 6.0, 1.5, 1.75])
    assert eul[0, 2] == pytest.approx(15.0) and eul[1, 2] == pytest.approx(-15.0)
    assert eul[2, 1] == pytest.approx(10.0)
    assert pos[3, 2] == pytest.approx(1.5)
    dense = traj.at(np.linspace(0.0, 48.0, 48001))[1]
    assert np.max(np.abs(dense[:, 2])) == pytest.approx(15.0, abs=1e-5)


def test_attitude_matches_the_aerospace_yaw_pitch_roll_matrix() -> None:
    traj = Trajectory(
        (Leg(20.0, 8.0, 5.0, 1.0),), heading0_deg=-40.0, roll_amplitude_deg=12.0, roll_period_s=5.0,
        pitch_amplitude_deg=7.0, pitch_period_s=3.0,
    )  # fmt: skip
    _, eul = traj.at(np.linspace(0.0, 20.0, 57))
    heading, pitch, roll = -eul[:, 0], eul[:, 1], eul[:, 2]
    ours = sim.platforms.rotation_from_euler(eul).as_matrix()
    np.testing.assert_allclose(ours, _aerospace_body_to_enu(heading, pitch, roll), atol=1e-12)


def _profile(slip_rate_per_s: float = 0.0) -> NoiseProfile:
    return NoiseProfile("G", 1, (0.25, 0.25), (0.002, 0.002), 0.1, slip_rate_per_s)


def test_antenna_positions_are_the_position_plus_the_rotated_lever_arms(tmp_path: Path) -> None:
    run = sim.ship(tmp_path, n_antennas=3, duration_s=12.0, interval_s=0.5, rng=3)
    traj_origin = geodetic_to_ecef(50.0, 36.2, 0.0)
    r0 = dcm_ecef_from_enu(50.0, 36.2)
    ref = traj_origin + run.position_enu_m @ r0.T
    lever = np.array([[0.0, 8.0, 0.0], [4.0, 8.0, 0.0], [0.0, 8.0, 3.0]])
    body = _aerospace_body_to_enu(run.heading_deg, run.pitch_deg, run.roll_deg)
    for t in range(len(run.time)):
        lat, lon, _ = ecef_to_geodetic(ref[t])
        local = dcm_ecef_from_enu(float(lat), float(lon))
        np.testing.assert_allclose(run.antenna_ecef_m[t], ref[t] + (local @ body[t] @ lever.T).T, atol=1e-6)
        # the baselines are in ENU at antenna 0, whose vertical is 1e-6 rad from the reference point's
        # (its lever arm of a few metres over the Earth's radius): 1e-5 m on these baselines
        np.testing.assert_allclose(run.baselines_enu_m[t], (body[t] @ (lever[1:] - lever[0]).T).T, atol=1e-5)
        lat0, lon0, _ = ecef_to_geodetic(run.antenna_ecef_m[t, 0])
        local0 = dcm_ecef_from_enu(float(lat0), float(lon0))
        rel = run.antenna_ecef_m[t, 1:] - run.antenna_ecef_m[t, 0]
        np.testing.assert_allclose(run.baselines_enu_m[t], rel @ local0, atol=1e-9)
    assert np.max(np.abs(run.roll_deg)) == pytest.approx(15.0)
    assert run.rover_enu_m is not None and run.base_ecef_m is not None
    np.testing.assert_allclose(
        run.rover_enu_m[0, 0], -np.array([-300.0, -200.0, 2.0]) + [0, 0, 8.0], atol=0.05
    )


def test_car_files_read_back_with_outages_tree_masks_and_slips(tmp_path: Path) -> None:
    run = sim.car(tmp_path, n_antennas=2, duration_s=40.0, interval_s=0.5, noise=_profile(0.02), rng=4)
    n_ep = len(run.time)
    assert n_ep == 81 and run.outage_ends_s == (25.0, 34.0)
    base = read_obs(run.base_path) if run.base_path else None
    assert base is not None and len(base.time) == n_ep  # the base sees the open sky
    outage = ((run.time_s >= 22.0) & (run.time_s < 25.0)) | ((run.time_s >= 32.0) & (run.time_s < 34.0))
    trees = (run.time_s >= 8.0) & (run.time_s < 18.0)
    for i, path in enumerate(run.obs_paths):
        obs = read_obs(path)
        # no epoch is written while every satellite is hidden
        np.testing.assert_array_equal(obs.time, run.time[~outage])
        assert set(obs.sats) <= set(run.sats)
        j = obs.codes.index("L1C")
        seen = np.zeros((n_ep, len(run.sats)), dtype=bool)
        rows = np.flatnonzero(~outage)
        for k, s in enumerate(obs.sats):
            seen[rows, run.sats.index(s)] = np.isfinite(obs.data[:, k, j])
        np.testing.assert_array_equal(seen, run.visible[:, i])
        # the tree mask: 15 degrees along the road, 45 across, 10 degrees elsewhere
        el = run.elevation_deg[:, i]
        assert not np.any(seen & (el < 10.0))
        assert not np.any(seen[trees] & (el[trees] < 15.0))
        assert np.all(seen[~trees & ~outage] | (el[~trees & ~outage] <= 10.0))
        assert seen[trees].sum() < seen[~trees & ~outage].mean(axis=0).sum() * trees.sum()
        # a loss-of-lock indicator at every injected slip of this antenna
        for e, r, s, _, jump in run.slips:
            if r == i:
                assert jump != 0
                k = obs.sats.index(s)
                assert obs.lli[np.flatnonzero(obs.time == run.time[e])[0], k, j] & 1
    assert any(r < len(run.obs_paths) for _, r, *_ in run.slips)


def test_doppler_of_a_moving_antenna_is_the_rate_of_its_phase(tmp_path: Path) -> None:
    # open sky, no slips: the mean Doppler over 0.1 s equals minus the phase's rate (to its noise: 0.1 Hz
    # Doppler, 3 mm / 0.19 m per 0.1 s = 0.2 Hz of phase rate, and the rate's change, below 0.01 Hz)
    traj = Trajectory((Leg(10.0, 30.0, 6.0),))
    run = sim.simulate_platform(
        tmp_path, traj, [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]], duration_s=1.0, interval_s=0.1,
        noise=_profile(), base_offset_enu_m=None, rng=5,
    )  # fmt: skip
    obs = read_obs(run.obs_paths[1])
    lc, dc = obs.codes.index("L1C"), obs.codes.index("D1C")
    rate = -np.diff(obs.data[:, :, lc], axis=0) / 0.1
    mean_doppler = 0.5 * (obs.data[1:, :, dc] + obs.data[:-1, :, dc])
    ok = np.isfinite(rate)
    assert ok.sum() > 40
    np.testing.assert_allclose(mean_doppler[ok], rate[ok], atol=1.5)  # 30 m/s would be ~150 Hz
    assert np.std(mean_doppler[ok] - rate[ok]) < 0.4


def test_geodetic_profile_writes_every_system_and_three_frequencies(tmp_path: Path) -> None:
    run = sim.aircraft(tmp_path, n_antennas=2, duration_s=1.0, interval_s=0.5, noise="geodetic", rng=6)
    obs = read_obs(run.obs_paths[0])
    assert {s[0] for s in obs.sats} == set("GRECJ")
    assert {"L1C", "L2W", "L5Q", "L7Q", "L6I"} <= set(obs.codes)
    assert run.heading_deg[0] == pytest.approx(-110.0)


def test_same_seed_same_files_other_seed_other_files(tmp_path: Path) -> None:
    texts = []
    for k, seed in enumerate((7, 7, 8)):
        folder = tmp_path / str(k)
        folder.mkdir()
        run = sim.car(folder, duration_s=2.0, interval_s=0.5, rng=np.random.default_rng(seed))
        texts.append([p.read_text() for p in (*run.obs_paths, run.nav_path)])
    assert texts[0] == texts[1]
    assert texts[0][0] != texts[2][0]


def test_bad_input_and_work_limit(tmp_path: Path) -> None:
    traj = Trajectory((Leg(1.0, 1.0),))
    with pytest.raises(InvalidInputError, match="antennas_body_m"):
        sim.simulate_platform(tmp_path, traj, [[0.0, 0.0, 0.0]], duration_s=1.0, interval_s=1.0)
    with pytest.raises(InvalidInputError, match="noise"):
        sim.simulate_platform(tmp_path, traj, np.eye(2, 3), duration_s=1.0, interval_s=1.0, noise="rtk")
    with pytest.raises(WorkLimitError, match="MAX_PLATFORM_OBSERVATIONS"):
        sim.simulate_platform(tmp_path, traj, np.eye(2, 3), duration_s=86400.0, interval_s=0.01)
    with pytest.raises(InvalidInputError, match="speed_m_s"):
        Trajectory((Leg(1.0, 1e4),))
    with pytest.raises(InvalidInputError, match="outages_s"):
        Blockage(outages_s=((5.0, 1.0),))
    with pytest.raises(InvalidInputError, match="systems"):
        NoiseProfile("GX", 1, (0.2, 0.2), (0.002, 0.002), 0.1, 0.0)
    with pytest.raises(InvalidInputError, match="phase_sigma_m"):
        NoiseProfile("G", 1, (0.2, 0.2), (-0.002, 0.002), 0.1, 0.0)
    with pytest.raises(InvalidInputError, match="n_antennas"):
        sim.car(tmp_path, n_antennas=4, duration_s=1.0)


@pytest.fixture(scope="module")
def rc():  # type: ignore[no-untyped-def]
    """``benches/python/rtklib_compare.py`` as a module (its platform metrics)."""
    import importlib.util
    import sys

    script = Path(__file__).resolve().parents[1] / "benches" / "python" / "rtklib_compare.py"
    spec = importlib.util.spec_from_file_location("rtklib_compare_platforms", script)
    assert spec is not None and spec.loader is not None
    mod = importlib.util.module_from_spec(spec)
    sys.modules["rtklib_compare_platforms"] = mod  # dataclasses look their module up
    spec.loader.exec_module(mod)
    yield mod
    del sys.modules["rtklib_compare_platforms"]


def test_platform_metrics_of_a_hand_made_run(rc) -> None:  # type: ignore[no-untyped-def]
    # ten epochs at 1 s, truth 1 m north; an outage ends at 5 s; solved at 1-8, fixed at 2, 3, 6, 7
    time_s = 1000.0 + np.arange(10.0)
    truth = np.tile([0.0, 1.0, 0.0], (10, 1))
    t = time_s[1:9]
    enu = np.tile([0.0, 1.0, 0.0], (8, 1))
    enu[5] = [0.1, 1.0, 0.0]  # epoch 6: 0.1 m east, heading 5.711 deg (atan 0.1), a wrong fix at 5 cm
    enu[0] = [1.0, 0.0, 0.0]  # epoch 1, float: 90 deg off
    fixed = np.isin(np.arange(1, 9), [2, 3, 6, 7])
    sol = rc.Solutions(t, enu, fixed, "test")
    m = rc.platform_metrics(sol, time_s, truth, [1005.0], 0.05)
    assert m["fix_rate"] == 0.4 and m["fixed"] == 4 and m["solved"] == 8
    assert m["wrong_fixes"] == 1
    assert m["first_fix_s"] == 2.0 and m["refix_s"] == 1.0 and m["refix_missed"] == 0
    assert m["heading_rms_fixed_deg"] == pytest.approx(np.sqrt(np.degrees(np.arctan(0.1)) ** 2 / 4))
    assert m["heading_rms_all_deg"] == pytest.approx(np.sqrt((np.degrees(np.arctan(0.1)) ** 2 + 90.0**2) / 8))
    never = rc.platform_metrics(sol, time_s, truth, [1008.5], 0.05)
    assert never["refix_s"] is None and never["refix_missed"] == 1
    # the pair of two base -> antenna solutions: the common epochs, fixed where both are
    a = rc.Solutions(t[:4], np.zeros((4, 3)), np.array([True, True, False, True]), "pos")
    b = rc.Solutions(t[1:], np.ones((7, 3)), np.ones(7, dtype=bool), "pos")
    pair = rc.pair_solutions(a, b)
    np.testing.assert_array_equal(pair.time_s, t[1:4])
    np.testing.assert_array_equal(pair.fixed, [True, False, True])
    np.testing.assert_array_equal(pair.enu_m, np.ones((3, 3)))
