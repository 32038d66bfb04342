"""Belokonov et al.: antenna axis from GNSS visibility (eq. (5)) and the constrained estimators."""

from __future__ import annotations

import numpy as np
import pytest

from gnssatt import sim
from gnssatt.attitude.visibility import visibility_axis, visibility_sets
from gnssatt.errors import DegenerateGeometryError, InvalidInputError


@pytest.fixture(scope="module")
def scene() -> tuple[np.ndarray, list[tuple[np.ndarray, np.ndarray]]]:
    rng = np.random.default_rng(4)
    rx = sim.OrbitalReceiver(altitude_m=500e3, inclination_deg=51.6)
    constellation = sim.gps_nominal() + sim.glonass_nominal()
    n = 150
    axes = rng.normal(size=(n, 3))
    axes /= np.linalg.norm(axes, axis=1, keepdims=True)
    return axes, visibility_sets(rx, constellation, np.arange(n) * 37.0, axes)


def _errors_deg(axes: np.ndarray, sets: list, method: str) -> np.ndarray:
    est = np.array([visibility_axis(v, h, method=method) for v, h in sets])
    return np.degrees(np.arccos(np.clip(np.sum(est * axes, axis=1), -1.0, 1.0)))


def test_symmetric_geometry_gives_the_exact_axis() -> None:
    # Satellites symmetric about the axis z: eq. (5) and the polygon estimators return z exactly.
    az = np.radians(np.arange(0, 360, 45))
    ring = lambda el: np.c_[np.cos(el) * np.cos(az), np.cos(el) * np.sin(az), np.full(az.size, np.sin(el))]  # noqa: E731
    vis, inv = ring(np.radians(40.0)), ring(np.radians(-30.0))
    for method in ("paper", "margin", "centroid"):
        np.testing.assert_allclose(visibility_axis(vis, inv, method=method), [0, 0, 1], atol=1e-6)


@pytest.mark.slow
def test_noise_free_visibility_locates_the_axis(scene: tuple) -> None:
    axes, sets = scene
    paper, margin, centroid = (_errors_deg(axes, sets, m) for m in ("paper", "margin", "centroid"))
    rms = {
        k: float(np.sqrt(np.mean(e**2))) for k, e in (("paper", paper), ("margin", margin), ("c", centroid))
    }
    # The paper's "3 sigma = 15 deg" reading of eq. (5): about 10 deg RMS with 48 satellites at 500 km.
    assert 7.0 < rms["paper"] < 14.0
    # Both polygon estimators are measurably better; the centroid (posterior mean) is the best.
    assert rms["margin"] < 0.85 * rms["paper"]
    assert rms["c"] < 0.8 * rms["paper"]
    assert np.percentile(centroid, 95) < np.percentile(paper, 95)


@pytest.mark.slow
def test_polygon_estimators_satisfy_every_visibility_constraint(scene: tuple) -> None:
    _, sets = scene
    for vis, inv in sets[:40]:
        for method in ("margin", "centroid"):
            a = visibility_axis(vis, inv, method=method)
            assert np.all(vis @ a >= -1e-6) and np.all(inv @ a <= 1e-6)


def test_bad_input() -> None:
    vis = np.array([[0.0, 0.0, 1.0], [0.6, 0.0, 0.8], [0.0, 0.6, 0.8]])
    inv = np.array([[0.0, 0.0, -1.0], [-0.6, 0.0, -0.8]])
    with pytest.raises(InvalidInputError, match="every satellite is visible or none"):
        visibility_axis(vis, np.zeros((0, 3)))
    with pytest.raises(InvalidInputError, match="visible_los"):
        visibility_axis(np.zeros((0, 3)), inv)
    with pytest.raises(InvalidInputError, match="non-finite"):
        visibility_axis(np.where(vis == 0.6, np.nan, vis), inv)
    with pytest.raises(InvalidInputError, match=r"shape \(n, 3\)"):
        visibility_axis(vis[:, :2], inv)
    with pytest.raises(InvalidInputError, match="unit"):
        visibility_axis(2 * vis, inv)
    with pytest.raises(InvalidInputError, match="method"):
        visibility_axis(vis, inv, method="best")  # type: ignore[arg-type]
    flat = np.array([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [-1.0, 0.0, 0.0], [0.0, -1.0, 0.0]])
    with pytest.raises(DegenerateGeometryError, match="condition number"):
        visibility_axis(flat[:2], flat[2:])


def test_visibility_sets_bad_input() -> None:
    rx = sim.OrbitalReceiver(altitude_m=500e3, inclination_deg=51.6)
    gps = sim.gps_nominal()
    t = np.arange(3.0)
    axes = np.tile([0.0, 0.0, 1.0], (3, 1))
    with pytest.raises(InvalidInputError, match="row 1 is zero"):
        visibility_sets(rx, gps, t, axes * [[1], [0], [1]])
    with pytest.raises(InvalidInputError, match="non-finite"):
        visibility_sets(rx, gps, t, axes * [[1], [np.nan], [1]])
    with pytest.raises(InvalidInputError, match=r"shape \(3, 3\)"):
        visibility_sets(rx, gps, t, axes[:2])
    with pytest.raises(InvalidInputError, match="half_angle_deg"):
        visibility_sets(rx, gps, t, axes, half_angle_deg=0.0)
    with pytest.raises(InvalidInputError, match="half_angle_deg"):
        visibility_sets(rx, gps, t, axes, half_angle_deg=181.0)


def test_an_epoch_that_sees_every_satellite_or_none_is_refused() -> None:
    # A 180-deg cone sees every satellite above the limb, a 1-deg cone pointed at the nadir none.
    rx = sim.OrbitalReceiver(altitude_m=500e3, inclination_deg=51.6)
    gps = sim.gps_nominal()
    ((vis, inv),) = visibility_sets(rx, gps, [0.0], [[0.0, 0.0, 1.0]], half_angle_deg=180.0)
    assert len(inv) == 0 and len(vis) > 4
    with pytest.raises(InvalidInputError, match="every satellite is visible or none"):
        visibility_axis(vis, inv)
    ((vis, inv),) = visibility_sets(rx, gps, [0.0], [[0.0, 0.0, -1.0]], half_angle_deg=1.0)
    assert len(vis) == 0 and len(inv) > 4
    with pytest.raises(InvalidInputError, match="every satellite is visible or none"):
        visibility_axis(vis, inv)
