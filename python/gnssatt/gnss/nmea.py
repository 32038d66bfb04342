"""NMEA 0183 heading sentences of an :class:`~gnssatt.gnss.attitude.AttitudeSeries`, for chart plotters and
autopilots (``gnssatt attitude --nmea FILE``).

Per solved epoch, two sentences, each ``$<body>*<checksum>`` and CR LF, the checksum the two-digit
upper-case hexadecimal XOR of every character between ``$`` and ``*`` (NMEA 0183):

- ``$GNHDT,<heading>,T``: true heading, degrees clockwise from true North (the standard HDT sentence; talker
  ``GN``, several systems).
- ``$PSAT,HPR,<hhmmss.ss>,<heading>,<pitch>,<roll>,N``: heading, pitch and roll, degrees, at UTC time of
  day; the proprietary sentence of Hemisphere GNSS compasses (its last field ``N`` for a GNSS-derived
  attitude, ``G`` for a gyro). Roll is empty with two antennas (a baseline has no roll), and pitch is the
  baseline's elevation there.

Heading is ``heading_deg`` (attitude mode) or ``azimuth_deg`` (baseline mode, the direction of the first
rover from the reference antenna), pitch ``pitch_deg`` or ``elevation_deg``; angles carry three decimals.
UTC is GPST minus the leap seconds (GPS - UTC) at the epoch. Unsolved epochs (NaN heading) get no sentence;
float epochs do: the fix state is the CSV's ``state`` column (``docs/conventions.md``).
"""

from __future__ import annotations

from functools import reduce
from os import PathLike
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from gnssatt.rinex.nav import leap_seconds

if TYPE_CHECKING:
    from gnssatt.gnss.attitude import AttitudeSeries

__all__ = ["checksum", "hdt_sentence", "hpr_sentence", "nmea_sentences", "utc_from_gpst", "write_nmea"]


def checksum(body: str) -> str:
    """Two-digit upper-case hexadecimal XOR of the characters of ``body`` (between ``$`` and ``*``).

    Parameters
    ----------
    body
        The sentence without ``$``, ``*``, checksum and line end; ASCII.

    Returns
    -------
    str
        The checksum, e.g. ``"2C"``.
    """
    return f"{reduce(lambda a, c: a ^ c, body.encode('ascii'), 0):02X}"


def _sentence(body: str) -> str:
    return f"${body}*{checksum(body)}"


def _angle(value: float) -> str:
    return "" if not np.isfinite(value) else f"{value:.3f}"


def hdt_sentence(heading_deg: float) -> str:
    """``$GNHDT,<heading>,T*hh``: true heading, degrees clockwise from true North, in [0, 360).

    Parameters
    ----------
    heading_deg
        True heading, degrees (taken modulo 360).

    Returns
    -------
    str
        The sentence without its line end.
    """
    return _sentence(f"GNHDT,{_angle(float(heading_deg) % 360.0)},T")


def hpr_sentence(time_utc: np.datetime64, heading_deg: float, pitch_deg: float, roll_deg: float) -> str:
    """``$PSAT,HPR,<hhmmss.ss>,<heading>,<pitch>,<roll>,N*hh`` (Hemisphere GNSS; module docstring).

    Parameters
    ----------
    time_utc
        UTC instant; its time of day, rounded to 0.01 s, is written.
    heading_deg, pitch_deg, roll_deg
        Degrees; heading taken modulo 360, a NaN field written empty.

    Returns
    -------
    str
        The sentence without its line end.
    """
    cs = int(np.rint((time_utc - time_utc.astype("datetime64[D]")) / np.timedelta64(10, "ms")))
    cs %= 8_640_000
    hh, rest = divmod(cs, 360_000)
    mm, rest = divmod(rest, 6_000)
    ss, frac = divmod(rest, 100)
    hms = f"{hh:02d}{mm:02d}{ss:02d}.{frac:02d}"
    heading = float(heading_deg) % 360.0 if np.isfinite(heading_deg) else float("nan")
    return _sentence(f"PSAT,HPR,{hms},{_angle(heading)},{_angle(pitch_deg)},{_angle(roll_deg)},N")


def utc_from_gpst(time_gpst: NDArray[np.datetime64]) -> NDArray[np.datetime64]:
    """UTC labels of GPST instants: GPST minus the leap seconds (GPS - UTC) in force then.

    Parameters
    ----------
    time_gpst
        (n,) GPST ``datetime64``.

    Returns
    -------
    numpy.ndarray
        (n,) UTC ``datetime64[ns]``.
    """
    t = np.asarray(time_gpst, dtype="datetime64[ns]")
    # A leap second takes effect at a UTC date: the table is looked up at GPST minus its value there.
    leaps = np.array([leap_seconds(x - np.timedelta64(leap_seconds(x), "s")) for x in t], dtype=np.int64)
    utc: NDArray[np.datetime64] = t - leaps.astype("timedelta64[s]")
    return utc


def nmea_sentences(series: AttitudeSeries) -> list[str]:
    """The HDT and HPR sentences of every solved epoch of ``series``, in time order.

    Parameters
    ----------
    series
        Results of :func:`~gnssatt.gnss.attitude.attitude_from_rinex`.

    Returns
    -------
    list of str
        Two sentences per epoch with a finite heading (no line ends).
    """
    utc = utc_from_gpst(series.time)
    angles = series.angles_deg
    out: list[str] = []
    for k in range(len(series.time)):
        heading, pitch = float(angles[k, 0]), float(angles[k, 1])
        if not np.isfinite(heading):
            continue
        roll = float(angles[k, 2]) if angles.shape[1] > 2 else float("nan")
        out.append(hdt_sentence(heading))
        out.append(hpr_sentence(utc[k], heading, pitch, roll))
    return out


def write_nmea(path: str | PathLike[str], series: AttitudeSeries) -> int:
    """Write :func:`nmea_sentences` of ``series`` to ``path``, CR LF after each.

    Parameters
    ----------
    path
        File to write (replaced).
    series
        Results of :func:`~gnssatt.gnss.attitude.attitude_from_rinex`.

    Returns
    -------
    int
        Epochs written.

    Raises
    ------
    OSError
        When ``path`` cannot be written.
    """
    lines = nmea_sentences(series)
    with open(path, "w", encoding="ascii", newline="") as f:
        f.writelines(line + "\r\n" for line in lines)
    return len(lines) // 2
