"""A standard troposphere for simulated pseudoranges and phases: Saastamoinen zenith delays of a standard
atmosphere mapped to the elevation by Niell's functions (the model the observation engine corrects with,
``rust/core/src/gnss/atmosphere.rs``, so that simulated files carry the delay an engine expects).

- Standard atmosphere (as RTKLIB's): pressure ``1013.25 (1 - 2.2557e-5 h)^5.2568`` hPa, temperature
  ``15 - 6.5e-3 h`` deg C, relative humidity 0.7, up to the 11 km tropopause; above it an isothermal layer
  (pressure scale height 6341.6 m) and no water vapour. Heights below -500 m are taken as -500 m.
- Saastamoinen (1972) zenith delays: hydrostatic ``0.0022768 P / (1 - 0.00266 cos 2 phi - 0.00028 h_km)``,
  wet ``0.002277 (1255 / T + 0.05) e`` (m, P and e in hPa, T in K).
- Niell (1996, JGR 101(B2):3227, table 3) mapping functions: Marini's continued fraction with the
  coefficients interpolated linearly in latitude (constant beyond 15 and 75 degrees), the hydrostatic one
  with its height correction; the seasonal amplitude is left out (its yearly mean, zero, is used).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from gnssatt._arrays import MAX_BATCH_VALUES, batch_limit, float_array, scalar

__all__ = ["niell_mapping", "saastamoinen_zenith_m", "troposphere_delay_m"]

_LATITUDES_DEG = np.array([15.0, 30.0, 45.0, 60.0, 75.0])
#: Niell's table 3: hydrostatic averages a, b, c and wet a, b, c at the latitudes above.
_DRY = np.array(
    [
        [1.2769934e-3, 1.2683230e-3, 1.2465397e-3, 1.2196049e-3, 1.2045996e-3],
        [2.9153695e-3, 2.9152299e-3, 2.9288445e-3, 2.9022565e-3, 2.9024912e-3],
        [62.610505e-3, 62.837393e-3, 63.721774e-3, 63.824265e-3, 64.258455e-3],
    ]
)
_WET = np.array(
    [
        [5.8021897e-4, 5.6794847e-4, 5.8118019e-4, 5.9727542e-4, 6.1641693e-4],
        [1.4275268e-3, 1.5138625e-3, 1.4572752e-3, 1.5007428e-3, 1.7599082e-3],
        [4.3472961e-2, 4.6729510e-2, 4.3908931e-2, 4.4626982e-2, 5.4736038e-2],
    ]
)
#: Niell's height correction of the hydrostatic mapping: a, b, c (per km of height).
_HEIGHT = (2.53e-5, 5.49e-3, 1.14e-3)
#: Heights accepted, m (the standard atmosphere's range of use; the simulator's platforms).
HEIGHT_RANGE_M = (-1e4, 1e5)


def _marini(sin_el: NDArray[np.float64], a: float, b: float, c: float) -> NDArray[np.float64]:
    """Marini's continued fraction, 1 at the zenith."""
    return (1.0 + a / (1.0 + b / (1.0 + c))) / (sin_el + a / (sin_el + b / (sin_el + c)))


def saastamoinen_zenith_m(lat_rad: float, height_m: float) -> tuple[float, float]:
    """Hydrostatic and wet zenith delays of the standard atmosphere (module docstring), m.

    Raises
    ------
    InvalidTypeError, InvalidInputError
        ``lat_rad`` not a finite angle in [-pi/2, pi/2], ``height_m`` outside ``HEIGHT_RANGE_M``.
    """
    lat = scalar("lat_rad", lat_rad, minimum=-np.pi / 2, maximum=np.pi / 2)
    h = max(scalar("height_m", height_m, minimum=HEIGHT_RANGE_M[0], maximum=HEIGHT_RANGE_M[1]), -500.0)
    ht = min(h, 11_000.0)
    temp_k = 15.0 - 6.5e-3 * ht + 273.16
    pressure = 1013.25 * (1.0 - 2.2557e-5 * ht) ** 5.2568
    if h > 11_000.0:
        pressure *= np.exp(-(h - 11_000.0) / 6341.6)
    humidity = 0.0 if h > 11_000.0 else 0.7
    e = 6.108 * humidity * np.exp((17.15 * temp_k - 4684.0) / (temp_k - 38.45))
    dry = 0.0022768 * pressure / (1.0 - 0.00266 * np.cos(2.0 * lat) - 0.00028 * h / 1e3)
    wet = 0.002277 * (1255.0 / temp_k + 0.05) * e
    return float(dry), float(wet)


def niell_mapping(
    lat_rad: float, height_m: float, elevation_rad: ArrayLike
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Niell hydrostatic and wet mapping functions at ``elevation_rad`` (any shape, clamped to >= 0).

    Raises
    ------
    InvalidTypeError, InvalidInputError
        As :func:`saastamoinen_zenith_m`; ``elevation_rad`` not finite.
    WorkLimitError
        More than :data:`gnssatt._arrays.MAX_BATCH_VALUES` elevations, refused before they are copied.
    """
    batch_limit(MAX_BATCH_VALUES, "MAX_BATCH_VALUES", "elevations", elevation_rad=(elevation_rad, 0))
    lat = abs(np.degrees(scalar("lat_rad", lat_rad, minimum=-np.pi / 2, maximum=np.pi / 2)))
    h = scalar("height_m", height_m, minimum=HEIGHT_RANGE_M[0], maximum=HEIGHT_RANGE_M[1])
    el = float_array("elevation_rad", elevation_rad, ndim=(0, 1, 2, 3, 4), shape="(...)")
    s = np.sin(np.maximum(el, 0.0))
    dry_abc = [np.interp(lat, _LATITUDES_DEG, row) for row in _DRY]
    wet_abc = [np.interp(lat, _LATITUDES_DEG, row) for row in _WET]
    dry = _marini(s, *dry_abc) + h / 1e3 * (1.0 / np.maximum(s, 1e-3) - _marini(s, *_HEIGHT))
    return dry, _marini(s, *wet_abc)


def troposphere_delay_m(lat_rad: float, height_m: float, elevation_rad: ArrayLike) -> NDArray[np.float64]:
    """Slant tropospheric delay (zenith delays times mapping functions), m, shape of ``elevation_rad``.

    Raises
    ------
    InvalidTypeError, InvalidInputError
        As :func:`niell_mapping`.
    WorkLimitError
        As :func:`niell_mapping`.
    """
    batch_limit(MAX_BATCH_VALUES, "MAX_BATCH_VALUES", "elevations", elevation_rad=(elevation_rad, 0))
    zd, zw = saastamoinen_zenith_m(lat_rad, height_m)
    md, mw = niell_mapping(lat_rad, height_m, elevation_rad)
    return zd * md + zw * mw
