"""Ryzhkov and Holembiovskyi: eq. (1) pinned to scipy's ZYX, eq. (3) and its companion cosine, yaw against the
truth."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import gnssatt
from gnssatt import DegenerateGeometryError, NearDegenerateWarning


def paper_eq1(a0: np.ndarray, psi: float, theta: float, phi: float) -> np.ndarray:
    """Eq. (1) of the paper, written out row by row."""
    sps, cps, sth, cth, sph, cph = (
        np.sin(psi),
        np.cos(psi),
        np.sin(theta),
        np.cos(theta),
        np.sin(phi),
        np.cos(phi),
    )
    ax0, ay0, az0 = a0
    return np.array(
        [
            ax0 * cps * cth + ay0 * sps * cth - az0 * sth,
            ax0 * (-sps * cph + cps * sph * sth) + ay0 * (cps * cph + sps * sph * sth) + az0 * cth * sph,
            ax0 * (sps * sph + cps * cph * sth) + ay0 * (-cps * sph + sps * cph * sth) + az0 * cth * cph,
        ]
    )


def test_eq1_is_zyx_body_to_orbital_and_eq3_with_its_cosine(rng: np.random.Generator) -> None:
    for _ in range(200):
        psi, theta, phi = rng.uniform(-np.pi, np.pi), rng.uniform(-1.5, 1.5), rng.uniform(-np.pi, np.pi)
        a0 = rng.normal(size=3)
        a = paper_eq1(a0, psi, theta, phi)
        np.testing.assert_allclose(
            Rotation.from_euler("ZYX", [psi, theta, phi]).inv().apply(a0), a, atol=1e-12
        )
        mu1 = a[0] + a0[2] * np.sin(theta)
        mu2 = a[2] * np.sin(phi) - a[1] * np.cos(phi)
        d = a0[0] ** 2 + a0[1] ** 2
        sin_psi = (mu2 * a0[0] * np.cos(theta) + mu1 * a0[1]) / (np.cos(theta) * d)  # the paper's (3)
        cos_psi = (mu1 * a0[0] / np.cos(theta) - mu2 * a0[1]) / d  # the companion
        assert sin_psi == pytest.approx(np.sin(psi), abs=1e-9)
        assert cos_psi == pytest.approx(np.cos(psi), abs=1e-9)


def test_yaw_matches_truth_in_every_quadrant(rng: np.random.Generator) -> None:
    n = 400
    psi = rng.uniform(0.01, np.pi / 2 - 0.01, n) + np.pi / 2 * (np.arange(n) % 4) - np.pi
    theta, phi = rng.uniform(-1.4, 1.4, n), rng.uniform(-np.pi, np.pi, n)
    b_orb = rng.normal(size=(n, 3)) * 3e-5
    truth = Rotation.from_euler("ZYX", np.column_stack([psi, theta, phi]))
    b_body = truth.inv().apply(b_orb)
    res = gnssatt.yaw_from_magnetometer(b_body, b_orb, theta, phi)
    np.testing.assert_allclose(res.yaw_rad, psi, atol=1e-9)
    assert np.max((res.rotation * truth.inv()).magnitude()) < 1e-9
    one = gnssatt.yaw_from_magnetometer(
        b_body[0], b_orb[0], np.degrees(theta[0]), np.degrees(phi[0]), degrees=True
    )
    assert isinstance(one.yaw_rad, float) and one.yaw_rad == pytest.approx(psi[0], abs=1e-9)
    assert one.yaw_deg == pytest.approx(np.degrees(psi[0]), abs=1e-7)


def test_degenerate_and_near_degenerate() -> None:
    b = np.array([0.1, 0.2, 1.0])
    with pytest.raises(DegenerateGeometryError, match=r"cos\(pitch\)"):
        gnssatt.yaw_from_magnetometer(b, b, np.pi / 2, 0.0)
    with pytest.raises(DegenerateGeometryError, match="horizontal fraction"):
        gnssatt.yaw_from_magnetometer(b, [0.0, 0.0, 1.0], 0.1, 0.0)
    with pytest.raises(DegenerateGeometryError, match="b_body is zero"):
        gnssatt.yaw_from_magnetometer(np.zeros(3), b, 0.1, 0.0)
    with pytest.warns(NearDegenerateWarning, match="horizontal fraction"):
        gnssatt.yaw_from_magnetometer(b, [1e-3, 0.0, 1.0], 0.1, 0.0)
    with pytest.warns(NearDegenerateWarning, match=r"cos\(pitch\)"):
        gnssatt.yaw_from_magnetometer(b, b, np.pi / 2 - 1e-3, 0.0)
    with pytest.raises(gnssatt.InvalidInputError, match="one length"):
        gnssatt.yaw_from_magnetometer(np.ones((3, 3)), np.ones((3, 3)), np.zeros(2), 0.0)
