"""The simulator's troposphere: Saastamoinen zenith delays of the standard atmosphere and Niell mapping,
against closed forms and the published values (Niell 1996, JGR 101(B2):3227)."""

from __future__ import annotations

import numpy as np
import pytest

from gnssatt.errors import InvalidInputError
from gnssatt.sim.atmosphere import niell_mapping, saastamoinen_zenith_m, troposphere_delay_m


def test_zenith_delays_of_the_standard_atmosphere() -> None:
    dry, wet = saastamoinen_zenith_m(np.radians(45.0), 0.0)
    # 45 degrees at sea level: cos(2 phi) = 0, 1013.25 hPa
    assert dry == pytest.approx(0.0022768 * 1013.25, abs=1e-12)
    assert 0.08 < wet < 0.2  # 70 % humidity at 15 C: about 0.12 m
    # above the tropopause no water vapour, and the pressure falls with a 6341.6 m scale height
    d30, w30 = saastamoinen_zenith_m(0.5, 30_000.0)
    d11, _ = saastamoinen_zenith_m(0.5, 11_000.0)
    gravity = (1 - 0.00266 * np.cos(1.0) - 0.00028 * 11) / (1 - 0.00266 * np.cos(1.0) - 0.00028 * 30)
    assert w30 == 0.0 and d30 == pytest.approx(d11 * np.exp(-19_000.0 / 6341.6) * gravity, rel=1e-12)


def test_niell_mapping() -> None:
    lat = np.radians(45.0)
    el = np.radians([90.0, 60.0, 30.0, 15.0, 5.0])
    dry, wet = niell_mapping(lat, 0.0, el)
    np.testing.assert_allclose([dry[0], wet[0]], 1.0, atol=1e-12)  # normalised at the zenith
    np.testing.assert_allclose(dry[:3], 1.0 / np.sin(el[:3]), rtol=5e-3)  # flat Earth above 30 degrees
    assert np.all(np.diff(dry) > 0) and np.all(np.diff(wet) > 0)
    assert 10.0 < dry[-1] < 10.4  # Niell's hydrostatic mapping near 10.15 at 5 degrees
    # the height correction raises the hydrostatic mapping at low elevation only (1 km: a few 1e-3)
    high, _ = niell_mapping(lat, 1000.0, el)
    assert high[0] == pytest.approx(1.0, abs=1e-12) and 0.0 < high[-1] - dry[-1] < 0.05
    below, _ = niell_mapping(lat, 0.0, -0.1)  # clamped at the horizon
    assert np.isfinite(below) and below == pytest.approx(niell_mapping(lat, 0.0, 0.0)[0])


def test_slant_delay_and_bad_input() -> None:
    zd, zw = saastamoinen_zenith_m(0.9, 150.0)
    assert troposphere_delay_m(0.9, 150.0, np.pi / 2) == pytest.approx(zd + zw)
    assert troposphere_delay_m(0.9, 150.0, np.radians([10.0, 20.0])).shape == (2,)
    with pytest.raises(InvalidInputError, match="height_m"):
        troposphere_delay_m(0.9, 2e5, 0.5)
    with pytest.raises(InvalidInputError, match="lat_rad"):
        saastamoinen_zenith_m(2.0, 0.0)
    with pytest.raises(InvalidInputError, match="elevation_rad"):
        niell_mapping(0.9, 0.0, np.nan)
