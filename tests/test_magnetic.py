"""Dipole field models: eq. (2) derived from an inertial dipole; the tilted IGRF-14 dipole checked against
closed forms and (if installed) ppigrf at degree 1."""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest
from numpy.typing import NDArray

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


def _ppigrf_ecef(
    ppigrf: Any, r_m: float, colat_deg: float, lon_deg: float, year: float, degree: int
) -> NDArray[np.float64]:
    """ppigrf's geocentric components turned to ECEF here, with the spherical unit vectors written out."""
    br, bth, bph = (
        float(np.asarray(c).ravel()[0])
        for c in ppigrf.igrf_gc(r_m / 1e3, colat_deg, lon_deg, magnetic._datetime(year), max_degree=degree)
    )
    th, ph = np.radians(colat_deg), np.radians(lon_deg)
    e_r = np.array([np.sin(th) * np.cos(ph), np.sin(th) * np.sin(ph), np.cos(th)])
    e_th = np.array([np.cos(th) * np.cos(ph), np.cos(th) * np.sin(ph), -np.sin(th)])
    e_ph = np.array([-np.sin(ph), np.cos(ph), 0.0])
    return 1e-9 * (br * e_r + bth * e_th + bph * e_ph)


@pytest.mark.parametrize("z_m", [7e6, -7e6, 6.5e6, -2.0e7])
def test_igrf_is_finite_on_the_pole_axis_and_continuous_to_ppigrf_off_it(z_m: float) -> None:
    ppigrf = pytest.importorskip("ppigrf")
    # issue 31: NaN within about 1e-3 m of the axis before
    for offset in (0.0, 1e-300, 1e-9, 1e-3):
        on = magnetic.igrf_field_ecef([offset, 0.0, z_m], 2021.0)
        assert np.all(np.isfinite(on)), (offset, on)
    on = magnetic.igrf_field_ecef([0.0, 0.0, z_m], 2021.0)
    # ppigrf 1e-5 deg off the axis (1.2-3.5 m), at four longitudes: the field there differs from its value
    # on the axis by at most (n_max + 2) theta |B|, theta the angle off the axis (each degree-n term
    # varies over an angle of about 1 / n)
    theta_deg = 1e-5
    for lon in (0.0, 45.0, 90.0, 200.0):
        colat = theta_deg if z_m > 0 else 180.0 - theta_deg
        ref = _ppigrf_ecef(ppigrf, abs(z_m), colat, lon, 2021.0, 13)
        bound = 15 * np.radians(theta_deg) * np.linalg.norm(ref)
        assert np.linalg.norm(on - ref) < bound, (lon, on, ref)
        # and at that point the library gives ppigrf's value itself
        th, ph = np.radians(colat), np.radians(lon)
        point = abs(z_m) * np.array([np.sin(th) * np.cos(ph), np.sin(th) * np.sin(ph), np.cos(th)])
        np.testing.assert_allclose(magnetic.igrf_field_ecef(point, 2021.0), ref, rtol=1e-9, atol=1e-18)


@pytest.mark.parametrize("z_m", [7e6, -7e6])
def test_igrf_of_degree_one_on_the_axis_is_the_dipole_closed_form(z_m: float) -> None:
    pytest.importorskip("ppigrf")
    for year in (2016.0, 2021.0, 2025.0):
        # the closed form B = a^3 (3 (g . r^) r^ - g) / r^3 on the axis; the two interpolate the
        # coefficients in time differently, ~1e-5 relative (test_matches_ppigrf_at_degree_one)
        np.testing.assert_allclose(
            magnetic.igrf_field_ecef([0.0, 0.0, z_m], year, max_degree=1),
            magnetic.dipole_field_ecef([0.0, 0.0, z_m], year),
            rtol=1e-4,
            atol=1e-11,
        )
