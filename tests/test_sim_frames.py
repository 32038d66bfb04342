"""Frames, receivers and lines of sight of gnssatt.sim against independent formulas written here."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from gnssatt import sim
from gnssatt.constants import OMEGA_E_RAD_S, WGS84_A_M, WGS84_B_M, WGS84_E2
from gnssatt.errors import InvalidInputError

A, B = WGS84_A_M, WGS84_B_M


def bowring_inverse(r: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Geodetic latitude/longitude (deg) and height from ECEF by Bowring's (1976) closed form."""
    x, y, z = r[..., 0], r[..., 1], r[..., 2]
    p = np.hypot(x, y)
    ep2 = (A**2 - B**2) / B**2
    th = np.arctan2(z * A, p * B)
    lat = np.arctan2(z + ep2 * B * np.sin(th) ** 3, p - WGS84_E2 * A * np.cos(th) ** 3)
    n = A / np.sqrt(1 - WGS84_E2 * np.sin(lat) ** 2)
    h = p / np.cos(lat) - n
    return np.degrees(lat), np.degrees(np.arctan2(y, x)), h


def test_geodetic_known_points() -> None:
    np.testing.assert_allclose(sim.geodetic_to_ecef(0.0, 0.0, 0.0), [A, 0, 0], atol=1e-9)
    np.testing.assert_allclose(sim.geodetic_to_ecef(90.0, 0.0, 0.0), [0, 0, B], atol=1e-6)
    np.testing.assert_allclose(sim.geodetic_to_ecef(-90.0, 30.0, 100.0), [0, 0, -B - 100], atol=1e-6)
    np.testing.assert_allclose(sim.geodetic_to_ecef(0.0, 90.0, 500.0), [0, A + 500, 0], atol=1e-6)
    assert sim.geodetic_to_ecef(10.0, 20.0, 30.0).shape == (3,)


def test_one_geodetic_to_ecef_for_frames_sim_and_magnetic() -> None:
    from gnssatt import frames, magnetic

    assert magnetic.geodetic_to_ecef is frames.geodetic_to_ecef is sim.geodetic_to_ecef
    # closed forms on a (2, 2) grid (magnetic's former contract: any shape): equator at the prime meridian
    # (a, 0, 0), at 90 E (0, a, 0), the poles (0, 0, +-b), each raised by h along its normal
    lat, lon = np.array([[0.0, 0.0], [90.0, -90.0]]), np.array([[0.0, 90.0], [0.0, 45.0]])
    h = np.array([[0.0, 500.0], [100.0, 0.0]])
    want = np.array([[[A, 0, 0], [0, A + 500, 0]], [[0, 0, B + 100], [0, 0, -B]]])
    np.testing.assert_allclose(magnetic.geodetic_to_ecef(lat, lon, h), want, rtol=0, atol=1e-6)
    # frames' former lower bound of heights (100 km from the centre under the equator) for both
    np.testing.assert_allclose(magnetic.geodetic_to_ecef(0.0, 0.0, -A + 2e5), [2e5, 0, 0], atol=1e-6)


def test_geodetic_round_trip_independent_inverse() -> None:
    rng = np.random.default_rng(3)
    lat = rng.uniform(-89, 89, 200)
    lon = rng.uniform(-180, 180, 200)
    h = rng.uniform(-100, 2e6, 200)
    r = sim.geodetic_to_ecef(lat, lon, h)
    lat2, lon2, h2 = bowring_inverse(r)
    np.testing.assert_allclose(lat2, lat, atol=1e-9)
    np.testing.assert_allclose(lon2, lon, atol=1e-9)
    np.testing.assert_allclose(h2, h, atol=1e-3)
    lat3, lon3, h3 = sim.ecef_to_geodetic(r)
    np.testing.assert_allclose(lat3, lat, atol=1e-9)
    np.testing.assert_allclose(lon3, lon, atol=1e-9)
    np.testing.assert_allclose(h3, h, atol=1e-4)


@pytest.mark.parametrize(("lat", "lon"), [(0.0, 0.0), (50.0, 36.2), (-33.9, 151.2), (89.0, -120.0)])
def test_enu_basis(lat: float, lon: float) -> None:
    m = sim.dcm_ecef_from_enu(lat, lon)
    np.testing.assert_allclose(m.T @ m, np.eye(3), atol=1e-15)
    assert np.linalg.det(m) == pytest.approx(1.0)
    np.testing.assert_allclose(np.cross(m[:, 0], m[:, 1]), m[:, 2], atol=1e-15)
    # Up is the ellipsoid normal: finite difference of the surface point along height.
    d = sim.geodetic_to_ecef(lat, lon, 1.0) - sim.geodetic_to_ecef(lat, lon, 0.0)
    np.testing.assert_allclose(m[:, 2], d, atol=1e-9)
    # North is the direction of increasing latitude, East of increasing longitude.
    dn = sim.geodetic_to_ecef(lat + 1e-6, lon, 0.0) - sim.geodetic_to_ecef(lat - 1e-6, lon, 0.0)
    de = sim.geodetic_to_ecef(lat, lon + 1e-6, 0.0) - sim.geodetic_to_ecef(lat, lon - 1e-6, 0.0)
    np.testing.assert_allclose(m[:, 1], dn / np.linalg.norm(dn), atol=1e-7)
    np.testing.assert_allclose(m[:, 0], de / np.linalg.norm(de), atol=1e-7)


def test_eci_ecef_rotation() -> None:
    t = np.array([0.0, 3600.0, 86164.0905])
    theta = sim.earth_rotation_angle(t, theta0_rad=0.3)
    np.testing.assert_allclose(theta, 0.3 + OMEGA_E_RAD_S * t)
    m = sim.dcm_eci_from_ecef(t, 0.3)
    assert m.shape == (3, 3, 3)
    # ECEF x axis seen in ECI at angle theta east of ECI x.
    x_axis = np.stack([np.cos(theta), np.sin(theta), 0 * theta], -1)
    np.testing.assert_allclose(m[:, :, 0], x_axis, atol=1e-15)
    np.testing.assert_allclose(sim.dcm_ecef_from_eci(t, 0.3), np.swapaxes(m, 1, 2))
    rng = np.random.default_rng(0)
    r, v = rng.normal(size=(3, 5, 3)) * 1e7, rng.normal(size=(3, 5, 3)) * 1e3
    r2, v2 = sim.ecef_to_eci(*sim.eci_to_ecef(r, v, t, 0.3), t, 0.3)
    np.testing.assert_allclose(r2, r, rtol=1e-12)
    np.testing.assert_allclose(v2, v, rtol=1e-9, atol=1e-9)


def test_ground_receiver_state() -> None:
    rx = sim.GroundReceiver(45.0, 10.0, 300.0, theta0_rad=1.0)
    t = np.linspace(0, 600, 7)
    r, v = rx.state_eci(t)
    assert r.shape == v.shape == (7, 3)
    p = rx.position_ecef_m
    np.testing.assert_allclose(np.linalg.norm(v, axis=-1), OMEGA_E_RAD_S * np.hypot(p[0], p[1]), rtol=1e-12)
    rp, _ = rx.state_eci(t + 0.01)
    rm, _ = rx.state_eci(t - 0.01)
    np.testing.assert_allclose((rp - rm) / 0.02, v, rtol=1e-6)
    m = rx.dcm_eci_from_enu(t)
    np.testing.assert_allclose(m[:, :, 2], r / np.linalg.norm(r, axis=-1, keepdims=True), atol=4e-3)
    with pytest.raises(InvalidInputError, match=r"lat_deg in \[-90, 90\]"):
        sim.GroundReceiver(91.0, 0.0)
    with pytest.raises(TypeError, match="real number"):
        sim.GroundReceiver("north", 0.0)  # type: ignore[arg-type]


def test_orbital_frame_axes() -> None:
    rx = sim.OrbitalReceiver(altitude_m=550e3, inclination_deg=97.6, raan_deg=40.0, arg_latitude_deg=20.0)
    t = np.linspace(0, rx.period_s, 11)
    r, v = rx.state_eci(t)
    m = rx.dcm_eci_from_orbital(t)
    unit = np.linalg.norm
    np.testing.assert_allclose(m[..., 0], v / unit(v, axis=-1, keepdims=True), atol=1e-14)
    h = np.cross(r, v)
    np.testing.assert_allclose(m[..., 1], h / unit(h, axis=-1, keepdims=True), atol=1e-14)
    np.testing.assert_allclose(m[..., 2], r / unit(r, axis=-1, keepdims=True), atol=1e-14)
    np.testing.assert_allclose(np.linalg.det(m), 1.0)
    np.testing.assert_allclose(unit(r, axis=-1), WGS84_A_M + 550e3, rtol=1e-13)
    np.testing.assert_allclose(r[-1], r[0], atol=1e-3)
    assert rx.period_s == pytest.approx(2 * np.pi * np.sqrt((WGS84_A_M + 550e3) ** 3 / 3.986004418e14))
    rp, _ = rx.state_eci(t + 0.01)
    rm, _ = rx.state_eci(t - 0.01)
    np.testing.assert_allclose((rp - rm) / 0.02, v, rtol=1e-7)
    # Inclination and node from the state.
    hz = h[0] / unit(h[0])
    assert np.degrees(np.arccos(hz[2])) == pytest.approx(97.6)
    assert np.degrees(np.arctan2(hz[0], -hz[1])) % 360 == pytest.approx(40.0)
    # ECEF velocity is the ECI velocity minus the Earth's rotation.
    re, ve = rx.state_ecef(0.0)
    _, v_back = sim.ecef_to_eci(re, ve, 0.0)
    np.testing.assert_allclose(v_back, v[0], atol=1e-9)


def test_line_of_sight_ground_against_enu_projection() -> None:
    gps = sim.gps_nominal()
    rx = sim.GroundReceiver(50.0, 36.2, 150.0, theta0_rad=0.7)
    t = np.array([0.0, 1800.0])
    geom = sim.line_of_sight(rx, gps, t)
    assert geom.los.shape == (2, 24, 3) and geom.range_m.shape == (2, 24) and geom.frame == "enu"
    np.testing.assert_allclose(np.linalg.norm(geom.los, axis=-1), 1.0)
    for k, tk in enumerate(t):
        r_sat, _ = gps.state_ecef(tk, theta0_rad=0.7)
        d = r_sat - rx.position_ecef_m
        rho = np.linalg.norm(d, axis=-1)
        np.testing.assert_allclose(geom.range_m[k], rho, rtol=1e-12)
        lat, lon = np.radians(50.0), np.radians(36.2)
        e = np.array([-np.sin(lon), np.cos(lon), 0])
        n = np.array([-np.sin(lat) * np.cos(lon), -np.sin(lat) * np.sin(lon), np.cos(lat)])
        u = np.array([np.cos(lat) * np.cos(lon), np.cos(lat) * np.sin(lon), np.sin(lat)])
        np.testing.assert_allclose(geom.los[k], (d / rho[:, None]) @ np.stack([e, n, u], 1), atol=1e-12)
    geom0 = sim.line_of_sight(rx, gps, 0.0)
    assert geom0.los.shape == (24, 3)
    np.testing.assert_allclose(geom0.los, geom.los[0])
    # Range rate is the time derivative of range.
    gp = sim.line_of_sight(rx, gps, t + 0.5)
    gm = sim.line_of_sight(rx, gps, t - 0.5)
    np.testing.assert_allclose(geom.range_rate_mps, gp.range_m - gm.range_m, atol=1e-3)
    assert np.max(np.abs(geom.range_rate_mps)) > 100.0


def test_line_of_sight_orbital_frame_and_range_rate() -> None:
    rx = sim.OrbitalReceiver(500e3, 51.6, 30.0, 10.0)
    both = sim.gps_nominal() + sim.glonass_nominal()
    geom = sim.line_of_sight(rx, both, 100.0)
    assert geom.frame == "orbital" and geom.los.shape == (48, 3)
    r_r, _ = rx.state_eci(100.0)
    r_s, _ = both.state_eci(100.0)
    g_eci = (r_s - r_r) / np.linalg.norm(r_s - r_r, axis=-1, keepdims=True)
    np.testing.assert_allclose(g_eci @ rx.dcm_eci_from_orbital(100.0), geom.los, atol=1e-12)
    gp, gm = sim.line_of_sight(rx, both, 100.1), sim.line_of_sight(rx, both, 99.9)
    np.testing.assert_allclose(geom.range_rate_mps, (gp.range_m - gm.range_m) / 0.2, atol=2e-3)


def test_elevation_azimuth_and_los_body() -> None:
    el, az = sim.elevation_azimuth(np.array([[0, 1.0, 0], [1.0, 0, 0], [0, 0, 1.0], [0, -1.0, -1.0]]))
    np.testing.assert_allclose(np.degrees(el), [0, 0, 90, -45], atol=1e-12)
    np.testing.assert_allclose(np.degrees(az[:2]), [0, 90], atol=1e-12)
    assert np.degrees(az[3]) == pytest.approx(180.0)
    rng = np.random.default_rng(5)
    los = sim.random_los(rng, 6)
    att = sim.random_attitude(rng)
    np.testing.assert_allclose(att.apply(sim.los_body(los, att)), los, atol=1e-14)
    atts = sim.random_attitude(rng, 2)
    los2 = np.stack([los, los[::-1]])
    body = sim.los_body(los2, atts)
    np.testing.assert_allclose(atts[1].apply(body[1]), los2[1], atol=1e-14)
    with pytest.raises(InvalidInputError, match="one per epoch"):
        sim.los_body(los2, sim.random_attitude(rng, 3))
    with pytest.raises(TypeError, match="scipy Rotation"):
        sim.los_body(los, np.eye(3))  # type: ignore[arg-type]


def test_geometry_from_los_and_select() -> None:
    g = sim.Geometry.from_los([[0, 0, 2.0], [1.0, 0, 0], [0, 1.0, 1.0]], range_m=[2e7, 2.1e7, 2.2e7])
    np.testing.assert_allclose(np.linalg.norm(g.los, axis=-1), 1.0)
    assert g.ids == ("S01", "S02", "S03") and g.range_rate_mps.shape == (3,)
    s = g.select(np.array([True, False, True]))
    assert s.ids == ("S01", "S03") and s.range_m.tolist() == [2e7, 2.2e7]
    with pytest.raises(InvalidInputError, match=r"shape \(3,\)"):
        g.select(np.array([True, False]))
    with pytest.raises(InvalidInputError, match="non-zero"):
        sim.Geometry.from_los([[0, 0, 0.0]])
    with pytest.raises(InvalidInputError, match=r"\(n_sat, 3\)"):
        sim.Geometry.from_los([0, 0, 1.0])
    with pytest.raises(TypeError, match="GroundReceiver or OrbitalReceiver"):
        sim.line_of_sight("here", sim.gps_nominal(), 0.0)  # type: ignore[arg-type]
    assert isinstance(Rotation.identity(), Rotation)
