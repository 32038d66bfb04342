"""Dipole field models: eq. (2) derived from an inertial dipole; the tilted IGRF-14 dipole checked against
closed forms and (if installed) ppigrf at degree 1."""

from __future__ import annotations

import numpy as np
import pytest

from gnssatt import InvalidInputError, magnetic


def test_eq2_follows_from_an_axial_dipole_in_inertial_coordinates(rng: np.random.Generator) -> None:
    m_e = magnetic.EARTH_DIPOLE_T_M3
    for _ in range(100):
        inc, raan, u = rng.uniform(0, np.pi), rng.uniform(0, 2 * np.pi), rng.uniform(0, 2 * np.pi, 8)
        r = rng.uniform(6.6e6, 8e6)
        c, s = np.cos, np.sin
        r_hat = np.stack(
            [
                c(raan) * c(u) - s(raan) * s(u) * c(inc),
                s(raan) * c(u) + c(raan) * s(u) * c(inc),
                s(u) * s(inc),
            ],
            -1,
        )
        v_hat = np.stack(
            [
                -c(raan) * s(u) - s(raan) * c(u) * c(inc),
                -s(raan) * s(u) + c(raan) * c(u) * c(inc),
                c(u) * s(inc),
            ],
            -1,
        )
        n_hat = np.cross(r_hat, v_hat)  # orbit normal r x v
        m = np.array([0.0, 0.0, -m_e])  # axial dipole, moment towards geographic south
        b_eci = (
            3 * (r_hat @ m)[:, None] * r_hat - m
        ) / r**3  # B = (mu0/4pi)(3 (m.r) r - m)/r^3, M_E = mu0 m/4pi
        b_orb = np.stack(
            [np.sum(b_eci * e, -1) for e in (v_hat, n_hat, r_hat)], -1
        )  # x along, y normal, z radial
        np.testing.assert_allclose(magnetic.dipole_orbital(u, inc, r), b_orb, rtol=1e-12, atol=1e-20)


def test_tilted_dipole_magnitude_and_pole() -> None:
    g10, g11, h11 = magnetic.dipole_coefficients(2025.0)
    axis = -np.array([g11, h11, g10]) / np.linalg.norm([g11, h11, g10])  # north geomagnetic pole direction
    b0 = np.linalg.norm([g10, g11, h11]) * 1e-9
    a = magnetic.IGRF_REFERENCE_RADIUS_M
    rng = np.random.default_rng(3)
    pos = rng.normal(size=(50, 3))
    pos *= rng.uniform(6.4e6, 4e7, (50, 1)) / np.linalg.norm(pos, axis=1, keepdims=True)
    r = np.linalg.norm(pos, axis=1)
    sin_mlat = pos @ axis / r
    expected = b0 * (a / r) ** 3 * np.sqrt(1 + 3 * sin_mlat**2)
    np.testing.assert_allclose(
        np.linalg.norm(magnetic.dipole_field_ecef(pos, 2025.0), axis=1), expected, rtol=1e-12
    )
    # At the geomagnetic north pole the field points straight down (radially inward).
    pole = 7e6 * axis
    b = magnetic.dipole_field_ecef(pole, 2025.0)
    np.testing.assert_allclose(b / np.linalg.norm(b), -axis, atol=1e-14)
    # NED at the surface point on the dipole axis: the field leans from geodetic down by exactly the
    # difference between geodetic and geocentric latitude.
    lat_c = np.arcsin(axis[2])
    lon = np.degrees(np.arctan2(axis[1], axis[0]))
    lat_d = np.arctan(np.tan(lat_c) / (1 - magnetic._E2))
    ned = magnetic.dipole_field_ned(np.degrees(lat_d), lon, 0.0, 2025.0)
    assert ned[2] > 0 and abs(ned[1]) < 1e-12 * ned[2]
    assert np.hypot(ned[0], ned[1]) / np.linalg.norm(ned) == pytest.approx(np.sin(lat_d - lat_c), rel=1e-9)
    # Eq. (2)'s strength is this dipole's: |B| on the magnetic equator at r is M_E / r^3.
    assert magnetic.EARTH_DIPOLE_T_M3 == pytest.approx(b0 * a**3, rel=1e-12)


def test_eci_form_and_bad_input() -> None:
    pos = np.array([[7e6, 1e6, -2e6]])
    theta = 0.7
    c, s = np.cos(theta), np.sin(theta)
    rz = np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])
    np.testing.assert_allclose(
        magnetic.dipole_field_eci(pos, 2024.3, theta),
        magnetic.dipole_field_ecef(pos @ rz, 2024.3) @ rz.T,
        rtol=1e-12,
    )
    with pytest.raises(InvalidInputError, match="decimal year"):
        magnetic.dipole_coefficients(2031.0)
    np.testing.assert_allclose(magnetic.dipole_coefficients(2027.5), [-29318.5, -1385.3, 4491.75])


@pytest.mark.slow
def test_matches_ppigrf_at_degree_one() -> None:
    ppigrf = pytest.importorskip("ppigrf")
    rng = np.random.default_rng(4)
    lat, lon, h = rng.uniform(-89, 89, 20), rng.uniform(-180, 180, 20), rng.uniform(0, 1e6, 20)
    for year in (2016.0, 2020.0, 2025.0, 2028.0):
        ours = magnetic.dipole_field_ned(lat, lon, h, year) * 1e9
        be, bn, bu = (
            np.asarray(x)[0] for x in ppigrf.igrf(lon, lat, h / 1e3, magnetic._datetime(year), max_degree=1)
        )
        # ppigrf interpolates in datetime and converts geodetic coordinates its own way: ~1e-5 relative.
        np.testing.assert_allclose(ours, np.stack([bn, be, -bu], -1), rtol=1e-5, atol=0.05)  # nT
        pos = magnetic.geodetic_to_ecef(lat, lon, h)
        np.testing.assert_allclose(
            magnetic.igrf_field_ecef(pos, year, max_degree=1),
            magnetic.dipole_field_ecef(pos, year),
            rtol=1e-5,
            atol=5e-11,
        )


def test_the_former_latitude_longitude_keywords_are_gone() -> None:
    # lat_deg / lon_deg as everywhere else in the package (CHANGELOG.md: the old names were removed)
    with pytest.raises(TypeError, match="latitude_deg"):
        magnetic.dcm_ned_from_ecef(latitude_deg=30.0, longitude_deg=-60.0)  # type: ignore[call-arg]
