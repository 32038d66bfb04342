"""Visibility masks of gnssatt.sim: horizon, antenna cone and Earth occlusion against closed forms."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from gnssatt import sim
from gnssatt.constants import WGS84_A_M
from gnssatt.errors import InvalidInputError


def test_elevation_mask_overhead_and_below_horizon() -> None:
    t99, t101 = np.tan(np.radians(9.9)), np.tan(np.radians(10.1))
    los = np.array([[0, 0, 1.0], [1, 0, -0.1], [0, 1, t99], [0, 1, t101]])
    los /= np.linalg.norm(los, axis=1, keepdims=True)
    assert sim.elevation_mask(los).tolist() == [True, False, True, True]
    assert sim.elevation_mask(los, 10.0).tolist() == [True, False, False, True]
    with pytest.raises(InvalidInputError, match=r"mask_deg in \[-90, 90\]"):
        sim.elevation_mask(los, 95.0)


def test_elevation_mask_real_sky_counts() -> None:
    rx = sim.GroundReceiver(50.0, 36.2)
    geom = sim.line_of_sight(rx, sim.gps_nominal(), np.arange(0, 86400, 3600.0))
    n_vis = sim.elevation_mask(geom.los, 5.0).sum(axis=1)
    assert geom.los.shape[:2] == (*n_vis.shape, 24)
    assert n_vis.min() >= 4 and n_vis.max() <= 14


def test_antenna_cone_mask() -> None:
    up, horizon_ish, down = [0, 0, 1.0], [np.sin(np.radians(60)), 0, np.cos(np.radians(60))], [0, 0, -1.0]
    los = np.array([up, horizon_ish, down])
    ident = Rotation.identity()
    assert sim.antenna_cone_mask(los, ident).tolist() == [True, True, False]
    assert sim.antenna_cone_mask(los, ident, half_angle_deg=45.0).tolist() == [True, False, False]
    flipped = Rotation.from_euler("x", 180, degrees=True)  # body z points down
    assert sim.antenna_cone_mask(los, flipped).tolist() == [False, False, True]
    # Boresight along body x, attitude rotating body x onto reference z.
    pitch_up = Rotation.from_euler("y", -90, degrees=True)
    np.testing.assert_allclose(pitch_up.apply([1, 0, 0]), [0, 0, 1], atol=1e-15)
    assert sim.antenna_cone_mask(los, pitch_up, boresight_body=[1, 0, 0], half_angle_deg=10).tolist() == [
        True,
        False,
        False,
    ]
    with pytest.raises(InvalidInputError, match="non-zero boresight_body"):
        sim.antenna_cone_mask(los, ident, boresight_body=[0, 0, 0])
    with pytest.raises(InvalidInputError, match=r"half_angle_deg in \(0, 180\]"):
        sim.antenna_cone_mask(los, ident, half_angle_deg=200)


def test_earth_occlusion_closed_form() -> None:
    # Receiver at radius r1 on the x axis, satellite at radius r2 at central angle beta in the xy plane.
    # The segment grazes the sphere of radius R when beta = arccos(R / r1) + arccos(R / r2).
    r1, r2 = WGS84_A_M + 500e3, 26_560e3
    for atm in (0.0, 100e3):
        big_r = WGS84_A_M + atm
        beta_c = np.arccos(big_r / r1) + np.arccos(big_r / r2)
        beta = beta_c + np.array([-1e-4, 1e-4, -0.3, 0.3, np.pi - beta_c])
        sats = r2 * np.stack([np.cos(beta), np.sin(beta), np.zeros_like(beta)], axis=-1)
        vis = sim.earth_occlusion_mask([r1, 0, 0], sats, atmosphere_m=atm)
        assert vis.tolist() == [True, False, True, False, False]
    # The satellite straight overhead is visible; one directly behind the Earth is not.
    assert sim.earth_occlusion_mask([r1, 0, 0], [[r2, 0, 0], [-r2, 0, 0]]).tolist() == [True, False]


def test_earth_occlusion_batched_and_errors() -> None:
    rx = sim.OrbitalReceiver(500e3, 51.6)
    gps = sim.gps_nominal()
    geom = sim.line_of_sight(rx, gps, np.array([0.0, 600.0]))
    mask = sim.earth_occlusion_mask(geom.receiver_eci_m, geom.satellites_eci_m, atmosphere_m=50e3)
    assert mask.shape == (2, 24)
    # Every satellite above the local horizontal of the orbiting receiver is unobstructed.
    assert np.all(mask[sim.elevation_mask(geom.los, 0.0)])
    assert 0 < mask.sum() < 48
    with pytest.raises(InvalidInputError, match="expected receiver_m"):
        sim.earth_occlusion_mask(geom.receiver_eci_m[0], geom.satellites_eci_m)
    with pytest.raises(InvalidInputError, match="atmosphere_m >= 0"):
        sim.earth_occlusion_mask([7e6, 0, 0], [[3e7, 0, 0]], atmosphere_m=-1.0)
