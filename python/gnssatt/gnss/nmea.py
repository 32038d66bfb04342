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
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from gnssatt._arrays import path_text
from gnssatt.errors import InvalidInputError, InvalidTypeError
from gnssatt.gnss.attitude import AttitudeSeries
from gnssatt.rinex.nav import leap_seconds

__all__ = ["nmea_sentences", "write_nmea"]


def _checksum(body: str) -> str:
    """Two-digit upper-case hexadecimal XOR of the characters of ``body`` (between ``$`` and ``*``).

    Parameters
    ----------
    body
        The sentence without ``$``, ``*``, checksum and line end; ASCII.

    Returns
    -------
    str
        The checksum, e.g. ``"2C"``.

    Raises
    ------
    UnicodeEncodeError
        ``body`` not ASCII.

    Examples
    --------
    A Hemisphere VS100 compass's sentence as logged on NOAA's R/V Ronald H. Brown:

    >>> from gnssatt.gnss.nmea import _checksum
    >>> _checksum("GPHDT,74.20,T")
    '34'
    """
    return f"{reduce(lambda a, c: a ^ c, body.encode('ascii'), 0):02X}"


def _sentence(body: str) -> str:
    return f"${body}*{_checksum(body)}"


def _angle(value: float) -> str:
    return "" if not np.isfinite(value) else f"{value:.3f}"


def _hdt_sentence(heading_deg: float) -> str:
    """``$GNHDT,<heading>,T*hh``: true heading, degrees clockwise from true North, in [0, 360).

    Parameters
    ----------
    heading_deg
        True heading, degrees (taken modulo 360).

    Returns
    -------
    str
        The sentence without its line end.

    Raises
    ------
    TypeError, ValueError
        ``heading_deg`` not a number.

    Examples
    --------
    >>> from gnssatt.gnss.nmea import _hdt_sentence
    >>> _hdt_sentence(-0.5)
    '$GNHDT,359.500,T*21'
    """
    return _sentence(f"GNHDT,{_angle(float(heading_deg) % 360.0)},T")


def _hpr_sentence(time_utc: np.datetime64, heading_deg: float, pitch_deg: float, roll_deg: float) -> str:
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

    Raises
    ------
    TypeError, ValueError
        ``time_utc`` not a ``datetime64`` or an angle not a number.

    Examples
    --------
    Two antennas (no roll):

    >>> import numpy as np
    >>> from gnssatt.gnss.nmea import _hpr_sentence
    >>> _hpr_sentence(np.datetime64("2024-03-01T09:59:42.25"), 12.5, -1.25, float("nan"))
    '$PSAT,HPR,095942.25,12.500,-1.250,,N*25'
    """
    cs = int(np.rint((time_utc - time_utc.astype("datetime64[D]")) / np.timedelta64(10, "ms")))
    cs %= 8_640_000
    hh, rest = divmod(cs, 360_000)
    mm, rest = divmod(rest, 6_000)
    ss, frac = divmod(rest, 100)
    hms = f"{hh:02d}{mm:02d}{ss:02d}.{frac:02d}"
    heading = float(heading_deg) % 360.0 if np.isfinite(heading_deg) else float("nan")
    return _sentence(f"PSAT,HPR,{hms},{_angle(heading)},{_angle(pitch_deg)},{_angle(roll_deg)},N")


def _utc_from_gpst(time_gpst: NDArray[np.datetime64]) -> NDArray[np.datetime64]:
    """UTC labels of GPST instants: GPST minus the leap seconds (GPS - UTC) in force then.

    Parameters
    ----------
    time_gpst
        (n,) GPST ``datetime64``.

    Returns
    -------
    numpy.ndarray
        (n,) UTC ``datetime64[ns]``.

    Raises
    ------
    ValueError
        ``time_gpst`` not convertible to ``datetime64``.

    Examples
    --------
    GPS - UTC became 18 s at 2017-01-01T00:00:00 UTC:

    >>> import numpy as np
    >>> from gnssatt.gnss.nmea import _utc_from_gpst
    >>> utc = _utc_from_gpst(np.array(["2017-01-01T00:00:16", "2017-01-01T00:00:18"], "datetime64[ns]"))
    >>> [str(t) for t in utc.astype("datetime64[s]")]
    ['2016-12-31T23:59:59', '2017-01-01T00:00:00']
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

    Raises
    ------
    InvalidTypeError
        ``series`` not an :class:`~gnssatt.gnss.attitude.AttitudeSeries`.

    Examples
    --------
    Three epochs of a simulated 1 m triangle at heading 330, pitch 10, roll -5 deg (as
    :func:`~gnssatt.gnss.attitude.attitude_from_rinex`'s example); 2024-03-01 10:00:00 GPST is 09:59:42 UTC:

    >>> import tempfile
    >>> from gnssatt.gnss.attitude import attitude_from_rinex
    >>> from gnssatt.gnss.nmea import nmea_sentences
    >>> from gnssatt.sim import equilateral_triangle
    >>> from gnssatt.sim.rinex_scenario import simulate_gnss_rinex
    >>> antennas = equilateral_triangle(1.0, plane="xz")
    >>> quiet = {"phase_sigma_m": 1e-5, "code_sigma_m": 0.01, "atmosphere": False}
    >>> with tempfile.TemporaryDirectory() as folder:
    ...     sim = simulate_gnss_rinex(folder, antennas, [30.0, 10.0, -5.0], systems="GE", frequencies=2,
    ...                               n_epochs=3, rng=0, **quiet)
    ...     series = attitude_from_rinex(list(sim.obs_paths), sim.nav_path, antennas[1:] - antennas[0])
    >>> lines = nmea_sentences(series)
    >>> len(lines), lines[0][:6], round(float(lines[0].split(",")[1]), 1), lines[1][:19]
    (6, '$GNHDT', 330.0, '$PSAT,HPR,095942.00')
    """
    if not isinstance(series, AttitudeSeries):
        raise InvalidTypeError(f"expected series as an AttitudeSeries, got {type(series).__name__}")
    utc = _utc_from_gpst(series.time)
    angles = series.angles_deg
    out: list[str] = []
    for k in range(len(series.time)):
        heading, pitch = float(angles[k, 0]), float(angles[k, 1])
        if not np.isfinite(heading):
            continue
        roll = float(angles[k, 2]) if angles.shape[1] > 2 else float("nan")
        out.append(_hdt_sentence(heading))
        out.append(_hpr_sentence(utc[k], heading, pitch, roll))
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
    InvalidTypeError
        ``path`` not a str or os.PathLike, ``series`` not an :class:`~gnssatt.gnss.attitude.AttitudeSeries`.
    InvalidInputError
        ``path`` empty, a folder, or in a folder that does not exist.
    OSError
        When ``path`` cannot be written otherwise (permissions, a full disk).

    Examples
    --------
    >>> import tempfile
    >>> from pathlib import Path
    >>> from gnssatt.gnss.attitude import attitude_from_rinex
    >>> from gnssatt.gnss.nmea import write_nmea
    >>> from gnssatt.sim import equilateral_triangle
    >>> from gnssatt.sim.rinex_scenario import simulate_gnss_rinex
    >>> antennas = equilateral_triangle(1.0, plane="xz")
    >>> with tempfile.TemporaryDirectory() as folder:
    ...     sim = simulate_gnss_rinex(folder, antennas, [30.0, 10.0, -5.0], systems="GE", frequencies=2,
    ...                               n_epochs=3, rng=0, atmosphere=False)
    ...     series = attitude_from_rinex(list(sim.obs_paths), sim.nav_path, antennas[1:] - antennas[0])
    ...     write_nmea(Path(folder) / "heading.nmea", series)
    3
    """
    target = Path(path_text(path, "path"))
    if target.is_dir():
        raise InvalidInputError(f"expected path as a file name, got the folder {str(target)!r}")
    if not target.parent.is_dir():
        raise InvalidInputError(f"expected path in an existing folder, got {str(target)!r}")
    lines = nmea_sentences(series)
    with open(target, "w", encoding="ascii", newline="") as f:
        f.writelines(line + "\r\n" for line in lines)
    return len(lines) // 2
