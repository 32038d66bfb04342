"""The broadcast (Klobuchar) ionosphere of the engine (``_core.gnss_klobuchar_delay``) against published
values and the model's closed-form limits. Its effect on single-frequency single-point positioning of the
GEONET data: tests/test_gnss_ephemeris.py (test_single_point_matches_geonet_header)."""

from __future__ import annotations

import numpy as np
import pytest

from gnssatt import _core

WEEK_NS = 604_800 * 10**9


def klobuchar_delay_m(
    alpha: tuple[float, ...], beta: tuple[float, ...], lat: float, lon: float, az: float, el: float,
    tow: float, frequency_hz: float = 1575.42e6, week: int = 1042,
) -> float:  # fmt: skip
    """One evaluation at GPS week ``week``, ``tow`` s (only the time of day enters)."""
    t = np.array([week * WEEK_NS + round(tow * 1e9)], dtype=np.int64)
    coefficients = np.array([*alpha, *beta], dtype=np.float64)
    one = np.ones(1)
    return float(
        _core.gnss_klobuchar_delay(coefficients, t, lat, lon, one * az, one * el, one * frequency_hz)[0]
    )


@pytest.mark.parametrize(
    ("alpha", "beta", "lat", "lon", "az", "el", "tow", "expected"),
    [
        # Klobuchar's worked example (Parkinson & Spilker, GPS: Theory and Applications I, ch. 12):
        # 40 N 100 W, azimuth 210, elevation 20, 2000-01-01 20:45 (GPS week 1042, 593100 s) -> 23.784 m,
        # as pinned by libswiftnav (swift-nav/libswiftnav-legacy tests/check_ionosphere.c) and Orekit
        (
            (0.3820e-7, 0.1490e-7, -0.1790e-6, 0.0),
            (0.1430e6, 0.0, -0.3280e6, 0.1130e6),
            40.0, 260.0, 210.0, 20.0, 593100.0, 23.784,
        ),
        # libswiftnav's second vector: real broadcast coefficients, 35.3 S 149.1 E, week 1875 479820 s
        (
            (0.1583e-7, -0.7451e-8, -0.5960e-7, 0.1192e-6),
            (0.1290e6, -0.2130e6, 0.6554e5, 0.3277e6),
            -35.3, 149.1, 0.0, 15.0, 479820.0, 7.202,
        ),
    ],
)  # fmt: skip
def test_klobuchar_published_values(alpha, beta, lat, lon, az, el, tow, expected) -> None:  # type: ignore[no-untyped-def]
    d = klobuchar_delay_m(alpha, beta, np.radians(lat), np.radians(lon), np.radians(az), np.radians(el), tow)
    assert float(d) == pytest.approx(expected, abs=1e-3)  # the references print 1 mm


def test_klobuchar_night_floor_and_frequency_scaling() -> None:
    a, b = (1e-8, 0.0, 0.0, 0.0), (72000.0, 0.0, 0.0, 0.0)
    # at the zenith the slant factor is 1 + 16 (0.53 - 0.5)^3; at night only the 5 ns floor remains
    night = klobuchar_delay_m(a, b, 0.0, 0.0, 0.0, np.pi / 2, 0.0)
    assert float(night) == pytest.approx(299792458.0 * 5e-9 * (1 + 16 * 0.03**3), rel=1e-12)
    l2 = klobuchar_delay_m(a, b, 0.0, 0.0, 0.0, np.pi / 2, 0.0, frequency_hz=1227.60e6)
    assert float(l2 / night) == pytest.approx((1575.42 / 1227.60) ** 2, rel=1e-12)
