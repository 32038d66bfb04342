"""The GPS broadcast ionosphere (Klobuchar) model, IS-GPS-200 20.3.3.5.2.5, for single-frequency code.

Angles of the broadcast coefficients are in semicircles: ``alpha`` in s, s/sc, s/sc^2, s/sc^3 and ``beta``
in s, s/sc, ... as the navigation message (and RINEX ``ION ALPHA`` / ``ION BETA``, ``IONOSPHERIC CORR
GPSA`` / ``GPSB``) gives them. The model gives the L1 group delay; another carrier ``f`` scales it by
``(f_L1 / f)^2``.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from gnssatt.errors import InvalidInputError

__all__ = ["klobuchar_delay_m"]

C = 299792458.0
F_L1 = 1575.42e6


def klobuchar_delay_m(
    alpha: ArrayLike,
    beta: ArrayLike,
    lat_rad: float,
    lon_rad: float,
    azimuth_rad: ArrayLike,
    elevation_rad: ArrayLike,
    gps_time_s: ArrayLike,
    *,
    frequency_hz: ArrayLike = F_L1,
) -> NDArray[np.float64]:
    """Slant ionospheric group delay of the broadcast model, m (positive: code delayed).

    Parameters
    ----------
    alpha, beta
        (4,) broadcast coefficients (module docstring).
    lat_rad, lon_rad
        Geodetic latitude and longitude of the receiver, rad.
    azimuth_rad, elevation_rad
        Satellite azimuth (clockwise from North) and elevation, rad; arrays broadcast together.
    gps_time_s
        GPS time, s: seconds of week or of day (only the time of day enters).
    frequency_hz
        Carrier frequency of the code, Hz (default GPS L1).

    Raises
    ------
    InvalidInputError
        Coefficients not of shape (4,) or not finite.
    """
    a = np.asarray(alpha, dtype=np.float64)
    b = np.asarray(beta, dtype=np.float64)
    if a.shape != (4,) or b.shape != (4,) or not (np.all(np.isfinite(a)) and np.all(np.isfinite(b))):
        raise InvalidInputError(f"expected finite alpha and beta of shape (4,), got {a.shape} and {b.shape}")
    az = np.asarray(azimuth_rad, dtype=np.float64)
    el_sc = np.maximum(np.asarray(elevation_rad, dtype=np.float64), 0.0) / np.pi
    psi = 0.0137 / (el_sc + 0.11) - 0.022  # earth-centred angle, semicircles
    phi_i = np.clip(lat_rad / np.pi + psi * np.cos(az), -0.416, 0.416)
    lam_i = lon_rad / np.pi + psi * np.sin(az) / np.cos(phi_i * np.pi)
    phi_m = phi_i + 0.064 * np.cos((lam_i - 1.617) * np.pi)  # geomagnetic latitude, semicircles
    t = np.mod(4.32e4 * lam_i + np.asarray(gps_time_s, dtype=np.float64), 86400.0)
    amp = np.maximum(a[0] + phi_m * (a[1] + phi_m * (a[2] + phi_m * a[3])), 0.0)
    per = np.maximum(b[0] + phi_m * (b[1] + phi_m * (b[2] + phi_m * b[3])), 72000.0)
    x = 2.0 * np.pi * (t - 50400.0) / per
    f = 1.0 + 16.0 * (0.53 - el_sc) ** 3
    day = np.where(np.abs(x) < 1.57, amp * (1.0 - x**2 / 2.0 + x**4 / 24.0), 0.0)
    scale = (F_L1 / np.asarray(frequency_hz, dtype=np.float64)) ** 2
    return np.asarray(C * f * (5e-9 + day) * scale, dtype=np.float64)
