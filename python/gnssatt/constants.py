"""Physical and signal constants of the scenario simulator.

Conventions of :mod:`gnssatt.sim`: SI units (m, s, Hz) and radians inside; arguments in degrees carry
``_deg`` in their name.

Sources: WGS-84 (NIMA TR8350.2, 3rd ed.): ``a``, ``1/f``, ``GM``, ``omega_E``; IS-GPS-200 for the GPS
carriers (10.23 MHz x 154 and x 120) and the speed of light; GLONASS ICD (ed. 5.1, 2008) for the FDMA plan
``f_L1 = 1602 MHz + k 0.5625 MHz``, ``f_L2 = 1246 MHz + k 0.4375 MHz``, channel ``k`` in -7..+6.
"""

from __future__ import annotations

import sys

import numpy as np
from numpy.typing import ArrayLike, NDArray

from gnssatt.errors import InvalidInputError, InvalidTypeError, WorkLimitError

__all__ = [
    "GLONASS_CHANNELS",
    "GLONASS_L1_BASE_HZ",
    "GLONASS_L1_STEP_HZ",
    "GLONASS_L2_BASE_HZ",
    "GLONASS_L2_STEP_HZ",
    "GM_M3_S2",
    "GPS_L1_HZ",
    "GPS_L1_WAVELENGTH_M",
    "GPS_L2_HZ",
    "GPS_L2_WAVELENGTH_M",
    "OMEGA_E_RAD_S",
    "SPEED_OF_LIGHT_M_S",
    "WGS84_A_M",
    "WGS84_B_M",
    "WGS84_E2",
    "WGS84_F",
    "glonass_frequency_hz",
    "glonass_wavelength_m",
]

#: WGS-84 semi-major axis, m.
WGS84_A_M = 6378137.0
#: WGS-84 flattening.
WGS84_F = 1.0 / 298.257223563
#: WGS-84 semi-minor axis, m.
WGS84_B_M = WGS84_A_M * (1.0 - WGS84_F)
#: WGS-84 first eccentricity squared.
WGS84_E2 = WGS84_F * (2.0 - WGS84_F)
#: Earth's gravitational parameter (WGS-84, including the atmosphere), m^3/s^2.
GM_M3_S2 = 3.986004418e14
#: Earth's rotation rate (WGS-84), rad/s.
OMEGA_E_RAD_S = 7.2921151467e-5
#: Speed of light in vacuum, m/s.
SPEED_OF_LIGHT_M_S = 299792458.0

#: GPS L1 carrier, Hz (154 x 10.23 MHz).
GPS_L1_HZ = 1575.42e6
#: GPS L2 carrier, Hz (120 x 10.23 MHz).
GPS_L2_HZ = 1227.60e6
#: GPS L1 wavelength, m (about 0.1903 m).
GPS_L1_WAVELENGTH_M = SPEED_OF_LIGHT_M_S / GPS_L1_HZ
#: GPS L2 wavelength, m (about 0.2442 m).
GPS_L2_WAVELENGTH_M = SPEED_OF_LIGHT_M_S / GPS_L2_HZ

#: GLONASS FDMA channel numbers in use since 2005.
GLONASS_CHANNELS = tuple(range(-7, 7))
GLONASS_L1_BASE_HZ = 1602.0e6
GLONASS_L1_STEP_HZ = 0.5625e6
GLONASS_L2_BASE_HZ = 1246.0e6
GLONASS_L2_STEP_HZ = 0.4375e6


_MAX_ELEMENTS = 2**28  # gnssatt._arrays.MAX_ELEMENTS


def _channels(k: ArrayLike) -> NDArray[np.int64]:
    # the shared intake's checks (gnssatt._arrays, same layer, not importable from here): masked values
    # refused, the size checked before anything is copied (a zero-stride view of 2^40 channels)
    # a masked array exists only once numpy.ma is loaded: without it, nothing to look for (and np.ma would
    # load it, 30-50 ms of a command-line start)
    if "numpy.ma" in sys.modules and isinstance(k, np.ma.MaskedArray):
        if np.ma.getmaskarray(k).any():
            raise InvalidInputError("expected k without masked values, got a numpy.ma array with some masked")
        k = np.ma.getdata(k)
    try:
        arr = np.asarray(k)
    except ValueError as exc:  # ragged nested sequences
        raise InvalidTypeError(f"expected k as integer GLONASS channel numbers, got {exc}") from exc
    if arr.size > _MAX_ELEMENTS:
        raise WorkLimitError(f"k has {arr.size} elements, more than the limit of {_MAX_ELEMENTS}")
    if arr.dtype.kind not in "iu" and not (arr.dtype.kind == "f" and np.all(arr == np.round(arr))):
        raise InvalidTypeError(
            f"expected k as integer GLONASS channel numbers, got dtype {arr.dtype} {arr.tolist()}"[:200]
        )
    arr = arr.astype(np.int64)
    if np.any((arr < -7) | (arr > 6)):
        raise InvalidInputError(
            f"expected k as GLONASS channel numbers in -7..6, got {np.unique(arr).tolist()}"[:200]
        )
    return arr


def glonass_frequency_hz(k: ArrayLike, band: str = "L1") -> NDArray[np.float64]:
    """GLONASS FDMA carrier frequency of channel ``k``.

    Parameters
    ----------
    k
        Channel number(s), integers in -7..6, any shape.
    band
        ``"L1"`` (1602 MHz + 0.5625 MHz k) or ``"L2"`` (1246 MHz + 0.4375 MHz k).

    Returns
    -------
    ndarray
        Frequencies in Hz, same shape as ``k``.

    Raises
    ------
    InvalidInputError
        A channel outside -7..6 or not an integer, or a band other than ``"L1"``/``"L2"``.

    Examples
    --------
    >>> from gnssatt.constants import glonass_frequency_hz
    >>> glonass_frequency_hz([-7, 0, 6]) / 1e6
    array([1598.0625, 1602.    , 1605.375 ])
    """
    ch = _channels(k)
    if band == "L1":
        return np.asarray(GLONASS_L1_BASE_HZ + ch * GLONASS_L1_STEP_HZ, dtype=np.float64)
    if band == "L2":
        return np.asarray(GLONASS_L2_BASE_HZ + ch * GLONASS_L2_STEP_HZ, dtype=np.float64)
    if isinstance(band, str):
        raise InvalidInputError(f"expected band 'L1' or 'L2', got {band!r}")
    raise InvalidTypeError(f"expected band as a str 'L1' or 'L2', got {type(band).__name__}")


def glonass_wavelength_m(k: ArrayLike, band: str = "L1") -> NDArray[np.float64]:
    """GLONASS carrier wavelength of channel ``k`` in metres (``c / glonass_frequency_hz(k, band)``).

    Parameters
    ----------
    k
        Channel number(s), integers in -7..6, any shape.
    band
        ``"L1"`` or ``"L2"``.

    Returns
    -------
    ndarray
        Wavelengths in m, same shape as ``k``.

    Raises
    ------
    InvalidInputError
        As :func:`glonass_frequency_hz`.

    Examples
    --------
    Channel 0 on L1: 299792458 m/s / 1602 MHz:

    >>> from gnssatt.constants import glonass_wavelength_m
    >>> round(float(glonass_wavelength_m(0)), 5)
    0.18714
    """
    return SPEED_OF_LIGHT_M_S / glonass_frequency_hz(k, band)
