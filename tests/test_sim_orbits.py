"""Kepler propagation and nominal constellations of gnssatt.sim, checked against independent computations."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.optimize import brentq

from gnssatt import constants, sim
from gnssatt.constants import GM_M3_S2, GPS_L1_HZ, SPEED_OF_LIGHT_M_S
from gnssatt.errors import ConvergenceError, InvalidInputError


def elements_from_state(r: np.ndarray, v: np.ndarray) -> dict[str, np.ndarray]:
    """Inclination, RAAN, argument of latitude and semi-major axis from ECI states (..., 3), written here."""
    h = np.cross(r, v)
    hn = np.linalg.norm(h, axis=-1)
    inc = np.arccos(h[..., 2] / hn)
    raan = np.arctan2(h[..., 0], -h[..., 1]) % (2 * np.pi)
    node = np.stack([np.cos(raan), np.sin(raan), np.zeros_like(raan)], axis=-1)
    rn = np.linalg.norm(r, axis=-1)
    cos_u = np.sum(node * r, axis=-1) / rn
    sin_u = np.sum(np.cross(node, r) * h, axis=-1) / (rn * hn)
    u = np.arctan2(sin_u, cos_u) % (2 * np.pi)
    energy = 0.5 * np.sum(v * v, axis=-1) - GM_M3_S2 / rn
    return {"inc": inc, "raan": raan, "u": u, "a": -GM_M3_S2 / (2 * energy)}


def test_solve_kepler_matches_brentq() -> None:
    rng = np.random.default_rng(7)
    m = rng.uniform(-20, 20, 300)
    e = rng.uniform(0, 0.99, 300)
    ea = sim.solve_kepler(m, e)
    for mi, ei, ei_sol in zip(m, e, ea, strict=True):
        ref = brentq(lambda x, mi=mi, ei=ei: x - ei * np.sin(x) - mi, mi - 1.0, mi + 1.0, xtol=1e-14)
        assert ei_sol == pytest.approx(ref, abs=1e-11)


def test_solve_kepler_rejects_hyperbolic_and_can_fail() -> None:
    with pytest.raises(InvalidInputError, match=r"eccentricity in \[0, 1\)"):
        sim.solve_kepler(1.0, 1.2)
    with pytest.raises(ConvergenceError):
        sim.solve_kepler(np.linspace(-3, 3, 50), 0.999999, max_iter=1)


def test_period_and_closure_eccentric() -> None:
    orbits = sim.KeplerOrbits(
        np.array([7.0e6, 2.6e7, 4.2e7]),
        np.array([0.0, 0.3, 0.7]),
        np.radians([51.6, 55.0, 63.4]),
        np.radians([10.0, 200.0, 300.0]),
        np.radians([0.0, 40.0, 270.0]),
        np.radians([5.0, 100.0, 350.0]),
    )
    expected = 2 * np.pi * np.sqrt(orbits.semi_major_axis_m**3 / GM_M3_S2)
    np.testing.assert_allclose(orbits.period_s, expected, rtol=1e-14)
    r0, v0 = orbits.state_eci(0.0)
    for k in range(3):
        r1, v1 = orbits.state_eci(orbits.period_s[k])
        np.testing.assert_allclose(r1[k], r0[k], atol=1e-5 * orbits.semi_major_axis_m[k])
        np.testing.assert_allclose(v1[k], v0[k], rtol=1e-6, atol=1e-6)
    # Energy and angular momentum are conserved; velocity is the time derivative of position.
    t = np.linspace(0, 20000, 9)
    r, v = orbits.state_eci(t)
    el = elements_from_state(r, v)
    np.testing.assert_allclose(el["a"], np.broadcast_to(orbits.semi_major_axis_m, el["a"].shape), rtol=1e-9)
    h = np.cross(r, v)
    np.testing.assert_allclose(h, np.broadcast_to(h[0], h.shape), rtol=1e-9)
    dt = 0.01
    rp, _ = orbits.state_eci(t + dt)
    rm, _ = orbits.state_eci(t - dt)
    np.testing.assert_allclose((rp - rm) / (2 * dt), v, rtol=1e-6, atol=1e-4)


def test_radius_follows_conic_equation() -> None:
    orbits = sim.KeplerOrbits([2.0e7], [0.5], [0.3], [0.2], [1.0], [0.0])
    t = np.linspace(0, orbits.period_s[0], 50)
    r, _ = orbits.state_eci(t)
    n = orbits.mean_motion_rad_s[0]
    ea = np.array([brentq(lambda x, m=n * ti: x - 0.5 * np.sin(x) - m, -1, 2 * np.pi + 1) for ti in t])
    np.testing.assert_allclose(np.linalg.norm(r, axis=-1)[:, 0], 2.0e7 * (1 - 0.5 * np.cos(ea)), rtol=1e-10)


def test_circular_orbit_radius_and_speed_constant() -> None:
    orbits = sim.KeplerOrbits.circular([7.0e6, 2.0e7], np.radians([98.0, 10.0]), [1.0, 2.0], [0.0, 3.0])
    r, v = orbits.state_eci(np.linspace(0, 30000, 31))
    radii = np.broadcast_to([7.0e6, 2.0e7], (31, 2))
    np.testing.assert_allclose(np.linalg.norm(r, axis=-1), radii, rtol=1e-12)
    np.testing.assert_allclose(
        np.linalg.norm(v, axis=-1), np.broadcast_to(np.sqrt(GM_M3_S2 / np.array([7.0e6, 2.0e7])), (31, 2))
    )
    np.testing.assert_allclose(np.sum(r * v, axis=-1), 0.0, atol=1e-3)


def test_kepler_orbits_shape_errors() -> None:
    with pytest.raises(InvalidInputError, match="common shape"):
        sim.KeplerOrbits([7e6, 8e6], [0.0, 0.0, 0.0], 0.0, 0.0, 0.0, 0.0)
    with pytest.raises(InvalidInputError, match="semi_major_axis_m > 0"):
        sim.KeplerOrbits([-1.0], [0.0], 0.0, 0.0, 0.0, 0.0)
    with pytest.raises(TypeError, match="numeric array"):
        sim.KeplerOrbits(["a"], [0.0], 0.0, 0.0, 0.0, 0.0)


def test_gps_nominal_slots_planes_inclination() -> None:
    gps = sim.gps_nominal()
    assert len(gps) == 24
    assert gps.ids[0] == "G01" and gps.ids[-1] == "G24"
    r, v = gps.state_eci(0.0)
    el = elements_from_state(r, v)
    np.testing.assert_allclose(np.degrees(el["inc"]), 55.0, atol=1e-9)
    np.testing.assert_allclose(el["a"], 26_559_700.0, rtol=1e-9)
    raans = np.round(np.degrees(el["raan"]), 3)
    planes, counts = np.unique(raans, return_counts=True)
    assert len(planes) == 6 and np.all(counts == 4)
    np.testing.assert_allclose(np.diff(planes), 60.0, atol=1e-6)
    # Spot checks of the SPS PS table: slot A1 and F4 at the epoch.
    a1, f4 = gps.slots.index("A1"), gps.slots.index("F4")
    assert np.degrees(el["raan"][a1]) == pytest.approx(272.847, abs=1e-6)
    assert np.degrees(el["u"][a1]) == pytest.approx(268.126, abs=1e-6)
    assert np.degrees(el["u"][f4]) == pytest.approx(135.346, abs=1e-6)
    # Half a sidereal day, within the tolerance of the nominal semi-major axis.
    assert gps.orbits.period_s[0] == pytest.approx(43082.0, abs=10.0)
    np.testing.assert_allclose(gps.wavelengths_m("L1"), SPEED_OF_LIGHT_M_S / GPS_L1_HZ)
    np.testing.assert_allclose(gps.wavelengths_m("L2"), 0.2442102, rtol=1e-6)


def test_gps_extra_slots() -> None:
    gps = sim.gps_nominal(extra_slots_deg=[(272.847, 100.0), (332.847, 20.0)])
    assert len(gps) == 26 and gps.ids[-1] == "G26" and gps.slots[-1] == ""
    with pytest.raises(InvalidInputError, match="extra_slots_deg"):
        sim.gps_nominal(extra_slots_deg=[(1.0, 2.0, 3.0)])


def test_glonass_nominal_geometry_and_channels() -> None:
    glo = sim.glonass_nominal(raan0_deg=10.0)
    assert len(glo) == 24 and glo.ids[0] == "R01"
    r, v = glo.state_eci(0.0)
    el = elements_from_state(r, v)
    np.testing.assert_allclose(np.degrees(el["inc"]), 64.8, atol=1e-9)
    np.testing.assert_allclose(el["a"], 25_510_000.0, rtol=1e-9)
    raan = np.degrees(el["raan"]).reshape(3, 8)
    np.testing.assert_allclose(raan, np.array([[10.0], [130.0], [250.0]]) * np.ones((1, 8)), atol=1e-9)
    u = np.degrees(el["u"]).reshape(3, 8)
    np.testing.assert_allclose(np.diff(u[0]) % 360, 45.0, atol=1e-9)
    np.testing.assert_allclose((u[1:, 0] - u[:-1, 0]) % 360, 15.0, atol=1e-9)
    # Period 11 h 15 min 44 s (ICD, draconic); the two-body period of the nominal axis is within a minute.
    assert glo.orbits.period_s[0] == pytest.approx(11 * 3600 + 15 * 60 + 44, abs=60)
    ch = glo.glonass_channels
    assert np.all((ch >= -7) & (ch <= 6))
    # Antipodal rule, from the geometry: satellites of one plane 180 deg apart share a channel, others do not.
    pos = r / np.linalg.norm(r, axis=-1, keepdims=True)
    for i in range(24):
        for j in range(i + 1, 24):
            same_plane = abs(raan.flat[i] - raan.flat[j]) < 1e-6
            antipodal = same_plane and np.dot(pos[i], pos[j]) < -0.999999
            assert (ch[i] == ch[j]) == antipodal, (glo.ids[i], glo.ids[j])
    f = glo.frequencies_hz["L1"]
    np.testing.assert_allclose(f, 1602e6 + 0.5625e6 * ch)
    np.testing.assert_allclose(glo.frequencies_hz["L2"], 1246e6 + 0.4375e6 * ch)
    np.testing.assert_allclose(glo.wavelengths_m("L1"), SPEED_OF_LIGHT_M_S / f)


def test_glonass_frequency_errors() -> None:
    assert constants.glonass_frequency_hz(-7) == pytest.approx(1598.0625e6)
    assert constants.glonass_frequency_hz(6, "L2") == pytest.approx(1248.625e6)
    with pytest.raises(InvalidInputError, match=r"-7\.\.6"):
        constants.glonass_frequency_hz(7)
    with pytest.raises(TypeError, match="integer"):
        constants.glonass_frequency_hz(0.5)
    with pytest.raises(InvalidInputError, match="band"):
        constants.glonass_frequency_hz(0, "L5")


def test_constellation_combine_select_and_shapes() -> None:
    both = sim.gps_nominal() + sim.glonass_nominal()
    assert len(both) == 48 and both.ids[24] == "R01"
    sub = both.select(["R05", "G03"])
    assert sub.ids == ("R05", "G03")
    assert sub.glonass_channels.tolist() == [1, 0]
    r, v = both.state_eci(np.array([0.0, 60.0, 120.0]))
    assert r.shape == v.shape == (3, 48, 3)
    r1, _ = both.state_eci(60.0)
    np.testing.assert_allclose(r[1], r1)
    r_ecef, _ = both.state_ecef(0.0)
    np.testing.assert_allclose(np.linalg.norm(r_ecef, axis=-1), np.linalg.norm(r[0], axis=-1))
    assert both.select(np.arange(48) < 5).ids == both.ids[:5]
    with pytest.raises(InvalidInputError, match="unknown"):
        both.select(["X01"])
    with pytest.raises(InvalidInputError, match="band"):
        both.wavelengths_m("L5")
    with pytest.raises(InvalidInputError, match=r"shape \(48,\)"):
        both.select(np.ones(3, dtype=bool))


def test_walker_pattern() -> None:
    w = sim.walker(24, 3, 1, inclination_deg=56.0, semi_major_axis_m=29_600e3, prefix="E")
    r, v = w.state_eci(0.0)
    el = elements_from_state(r, v)
    np.testing.assert_allclose(np.degrees(el["inc"]), 56.0)
    assert len(np.unique(np.round(np.degrees(el["raan"]), 6) % 360)) == 3
    assert w.ids[0] == "E01"
    with pytest.raises(InvalidInputError, match="multiple"):
        sim.walker(10, 3, 1, inclination_deg=56.0, semi_major_axis_m=29_600e3)
    with pytest.raises(TypeError, match="integer"):
        sim.walker(24.0, 3, 1, inclination_deg=56.0, semi_major_axis_m=29_600e3)  # type: ignore[arg-type]


def test_orbits_whose_mean_motion_overflows_are_refused_by_name() -> None:
    # issue 31: a = 1e-300 m makes a^3 zero and the mean motion infinite; the next call blamed
    # mean_anomaly_rad
    with pytest.raises(InvalidInputError, match=r"semi_major_axis_m.*mean motion inf"):
        sim.walker(6, 3, 1, inclination_deg=55.0, semi_major_axis_m=1e-300)
    with pytest.raises(InvalidInputError, match="semi_major_axis_m"):
        sim.KeplerOrbits.circular([7e6, 1e-120], 0.0, 0.0, 0.0)
    # a gravitational parameter so small that the mean motion underflows to zero (an infinite period)
    with pytest.raises(InvalidInputError, match=r"semi_major_axis_m.*gm_m3_s2"):
        sim.KeplerOrbits(
            np.array([1e15]), np.zeros(1), np.zeros(1), np.zeros(1), np.zeros(1), np.zeros(1), gm_m3_s2=5e-324
        )
    with pytest.raises(InvalidInputError, match="altitude_m"):
        sim.OrbitalReceiver(-constants.WGS84_A_M + 1e-9, inclination_deg=0.0, gm_m3_s2=1e300)
    # legitimate orbits are untouched
    assert np.isfinite(
        sim.walker(6, 3, 1, inclination_deg=55.0, semi_major_axis_m=7e6).orbits.mean_motion_rad_s
    ).all()
