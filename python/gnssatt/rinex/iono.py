"""The GPS broadcast ionosphere (Klobuchar) model, IS-GPS-200 20.3.3.5.2.5, for single-frequency code.

Angles of the broadcast coefficients are in semicircles: ``alpha`` in s, s/sc, s/sc^2, s/sc^3 and ``beta``
in s, s/sc, ... as the navigation message (and RINEX ``ION ALPHA`` / ``ION BETA``, ``IONOSPHERIC CORR
GPSA`` / ``GPSB``) gives them. The model gives the L1 group delay; another carrier ``f`` scales it by
``(f_L1 / f)^2``.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from gnssatt._arrays import finite_outputs, float_array, scalar, shaped
from gnssatt.errors import InvalidInputError

__all__ = ["klobuchar_delay_m"]

C = 299792458.0
F_L1 = 1575.42e6
#: Largest magnitude of a broadcast coefficient accepted (alpha in s/sc^k, beta in s/sc^k).
MAX_COEFFICIENT = 1e9
#: Carrier frequencies accepted, Hz; largest |GPS time| accepted, s; largest |azimuth|, rad.
FREQUENCY_RANGE_HZ = (1e6, 1e11)
MAX_GPS_TIME_S = 1e10
MAX_AZIMUTH_RAD = 4.0 * np.pi


def _broadcast(
    shape: tuple[int, ...], names: list[str], name: str, arr: NDArray[np.float64]
) -> tuple[int, ...]:
    try:
        return np.broadcast_shapes(shape, arr.shape)
    except ValueError:
        raise InvalidInputError(
            f"expected {name} and {', '.join(names)} broadcasting together, got {arr.shape} against {shape}"
        ) from None


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
    InvalidTypeError
        An argument that is not real.
    InvalidInputError
        Coefficients not finite of shape (4,) or beyond ``MAX_COEFFICIENT``; ``lat_rad`` outside
        [-pi/2, pi/2], ``lon_rad`` outside [-2 pi, 2 pi]; ``azimuth_rad``, ``elevation_rad``, ``gps_time_s``
        and ``frequency_hz`` not finite or not broadcasting together; elevations outside [-pi/2, pi/2],
        ``|azimuth_rad|`` above ``MAX_AZIMUTH_RAD``, ``|gps_time_s|`` above ``MAX_GPS_TIME_S``, frequencies
        outside ``FREQUENCY_RANGE_HZ``.
    """
    a = shaped("alpha", alpha, "(4,)", (4,))
    b = shaped("beta", beta, "(4,)", (4,))
    for name, c in (("alpha", a), ("beta", b)):
        if np.any(np.abs(c) > MAX_COEFFICIENT):
            raise InvalidInputError(f"expected |{name}| <= {MAX_COEFFICIENT}, got {c.tolist()}")
    lat_rad = scalar("lat_rad", lat_rad, minimum=-np.pi / 2, maximum=np.pi / 2, unit="rad")
    lon_rad = scalar("lon_rad", lon_rad, minimum=-2 * np.pi, maximum=2 * np.pi, unit="rad")
    ranges = {
        "azimuth_rad": (-MAX_AZIMUTH_RAD, MAX_AZIMUTH_RAD),
        "elevation_rad": (-np.pi / 2, np.pi / 2),
        "gps_time_s": (-MAX_GPS_TIME_S, MAX_GPS_TIME_S),
        "frequency_hz": FREQUENCY_RANGE_HZ,
    }
    given = {
        "azimuth_rad": azimuth_rad,
        "elevation_rad": elevation_rad,
        "gps_time_s": gps_time_s,
        "frequency_hz": frequency_hz,
    }
    shape: tuple[int, ...] = ()
    arrays = {}
    for name, value in given.items():
        arr = float_array(name, value, ndim=tuple(range(33)), shape="broadcasting together")
        arr = arr.reshape(np.shape(value))  # float_array gives 0-d input one dimension
        lo, hi = ranges[name]
        if np.any((arr < lo) | (arr > hi)):
            raise InvalidInputError(f"expected {name} in [{lo:.6g}, {hi:.6g}], got a value outside")
        shape = _broadcast(shape, list(arrays), name, arr)
        arrays[name] = arr
    out = _klobuchar_delay_m(a, b, lat_rad, lon_rad, *arrays.values())
    finite_outputs("klobuchar_delay_m", delay_m=out)
    return out


def _klobuchar_delay_m(
    a: NDArray[np.float64],
    b: NDArray[np.float64],
    lat_rad: float,
    lon_rad: float,
    azimuth_rad: ArrayLike,
    elevation_rad: ArrayLike,
    gps_time_s: ArrayLike,
    frequency_hz: ArrayLike,
) -> NDArray[np.float64]:
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
