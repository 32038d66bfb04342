"""RINEX 2.xx, 3.xx and 4.xx navigation files: broadcast ephemerides of GPS, Galileo, BeiDou, QZSS
(Keplerian) and GLONASS (state vectors). The file is parsed by the Rust core (``gnssatt_core::rinex::nav``);
this module opens and decompresses it and converts the records into the arrays below.

Times
-----
Every time is converted to GPST and kept as integer nanoseconds since the GPS epoch (1980-01-06 00:00:00
GPST), so that differences of large times stay exact. BDT = GPST - 14 s; GLONASS epochs (UTC) are shifted by
the GPS-UTC leap seconds (the header's ``LEAP SECONDS`` where given, else the table in this module).
"""

from __future__ import annotations

import functools
import operator
from collections.abc import Sequence
from dataclasses import dataclass, field
from os import PathLike
from typing import Any

import numpy as np
from numpy.typing import NDArray

from gnssatt import _core
from gnssatt._arrays import instance
from gnssatt.errors import InvalidInputError, InvalidTypeError
from gnssatt.rinex._fields import (
    HEADER_LABELS,
    Cursor,
    Skips,
    path_text,
    read_bytes,
    reading,
    time_labels,
)

__all__ = [
    "GPS_EPOCH",
    "GlonassEphemerides",
    "KeplerEphemerides",
    "NavInput",
    "RinexNav",
    "gps_ns",
    "nav_input",
    "read_nav",
]

#: The GPS epoch as datetime64[ns].
GPS_EPOCH = np.datetime64("1980-01-06T00:00:00", "ns")
_WEEK_NS = 604_800 * 1_000_000_000
_BDT_OFFSET_NS = 14 * 1_000_000_000
#: GPS - UTC leap seconds from the given UTC date on (IERS Bulletin C).
_LEAPS = (
    ("1999-01-01", 13),
    ("2006-01-01", 14),
    ("2009-01-01", 15),
    ("2012-07-01", 16),
    ("2015-07-01", 17),
    ("2017-01-01", 18),
)
#: Field names of the seven broadcast-orbit lines of a Keplerian record (IS-GPS-200 / RINEX 3 table A6).
KEPLER_FIELDS = (
    "iode", "crs", "delta_n", "m0",
    "cuc", "e", "cus", "sqrt_a",
    "toe_sow", "cic", "omega0", "cis",
    "i0", "crc", "omega", "omega_dot",
    "idot", "codes_l2", "week", "l2p_flag",
    "accuracy", "health", "tgd", "iodc_tgd2",
    "tx_time", "fit_interval",
)  # fmt: skip


def gps_ns(time: NDArray[np.datetime64]) -> NDArray[np.int64]:
    """Nanoseconds since the GPS epoch of GPST ``datetime64`` labels.

    Parameters
    ----------
    time
        Array (any shape) of ``datetime64`` labels in GPS time (no leap seconds applied), any unit.

    Returns
    -------
    numpy.ndarray
        int64 of the same shape: ns since 1980-01-06T00:00:00 GPST.

    Raises
    ------
    InvalidTypeError
        ``time`` is not of a datetime64 dtype.
    InvalidInputError
        ``time`` holds NaT or a label outside the years 1980 to 2199.

    Examples
    --------
    The GPS epoch is 0, and one week and one second later is ``(7 * 86400 + 1) * 1e9`` ns:

    >>> import numpy as np
    >>> from gnssatt.rinex.nav import gps_ns
    >>> gps_ns(np.array(["1980-01-06T00:00:00", "1980-01-13T00:00:01"], dtype="datetime64[s]")).tolist()
    [0, 604801000000000]
    """
    time = time_labels("time", time)
    return (time - GPS_EPOCH).astype(np.int64)


def leap_seconds(time_utc: np.datetime64) -> int:
    """GPS - UTC in seconds at a UTC date (1999 onwards)."""
    n = 13
    for day, value in _LEAPS:
        if np.datetime64(time_utc) >= np.datetime64(day):
            n = value
    return n


@dataclass(frozen=True)
class KeplerEphemerides:
    """Keplerian broadcast ephemerides (one row per record) of GPS, Galileo, BeiDou or QZSS.

    Attributes
    ----------
    sats
        (n,) satellite ids.
    toc_ns
        (n,) time of clock, GPST ns since the GPS epoch.
    toe_ns
        (n,) time of ephemeris, GPST ns since the GPS epoch (from the week and seconds of week; BeiDou's
        BDT week and seconds converted).
    af
        (n, 3) clock bias (s), drift (s/s), drift rate (s/s^2).
    fields
        name -> (n,) array for every name of :data:`KEPLER_FIELDS` (as in the file, SI units and radians).
    """

    sats: NDArray[np.str_]
    toc_ns: NDArray[np.int64]
    toe_ns: NDArray[np.int64]
    af: NDArray[np.float64]
    fields: dict[str, NDArray[np.float64]]

    def __len__(self) -> int:
        return len(self.sats)


@dataclass(frozen=True)
class GlonassEphemerides:
    """GLONASS broadcast state vectors (PZ-90, treated as WGS-84).

    Attributes
    ----------
    sats
        (n,) satellite ids.
    tb_ns
        (n,) reference time, GPST ns since the GPS epoch.
    tau_n, gamma_n
        (n,) clock: ``dt_sv = -tau_n + gamma_n (t - tb)`` (RINEX stores ``-tau_n`` and ``+gamma_n``; these are
        the RINEX values ``clock_bias = -tau_n`` and ``gamma_n``).
    position_m, velocity_m_s, acceleration_m_s2
        (n, 3) state and luni-solar acceleration at ``tb``, ECEF.
    channel
        (n,) FDMA channel number.
    health
        (n,) health flag (0 healthy).
    """

    sats: NDArray[np.str_]
    tb_ns: NDArray[np.int64]
    clock_bias: NDArray[np.float64]
    gamma_n: NDArray[np.float64]
    position_m: NDArray[np.float64]
    velocity_m_s: NDArray[np.float64]
    acceleration_m_s2: NDArray[np.float64]
    channel: NDArray[np.int64]
    health: NDArray[np.float64]

    def __len__(self) -> int:
        return len(self.sats)


@dataclass(frozen=True)
class RinexNav:
    """Broadcast ephemerides of one or more navigation files.

    Attributes
    ----------
    path
        The file(s) read.
    kepler
        Keplerian ephemerides of every G, E, C, J satellite.
    glonass
        GLONASS state vectors.
    iono_alpha, iono_beta
        (4,) Klobuchar coefficients of the GPS header (NaN if absent).
    leap_seconds
        GPS - UTC leap seconds of the header's ``LEAP SECONDS`` line, or None.
    skipped
        Records not read, counted per ``"<type> <system> <message>"``: RINEX 4 ``"EPH G CNAV"``,
        ``"STO G LNAV"``, ``"EOP G CNAV"``, ``"ION E IFNV"`` ...; SBAS and NavIC records of every version as
        ``"EPH S SBAS"`` and ``"EPH I LNAV"``.
    """

    path: str
    kepler: KeplerEphemerides
    glonass: GlonassEphemerides
    iono_alpha: NDArray[np.float64]
    iono_beta: NDArray[np.float64]
    leap_seconds: int | None = None
    skipped: dict[str, int] = field(default_factory=dict)

    def __add__(self, other: RinexNav) -> RinexNav:
        k = {f: np.concatenate([self.kepler.fields[f], other.kepler.fields[f]]) for f in KEPLER_FIELDS}
        a, b = self.kepler, other.kepler
        g, h = self.glonass, other.glonass
        return RinexNav(
            path=f"{self.path}+{other.path}",
            kepler=KeplerEphemerides(
                np.concatenate([a.sats, b.sats]),
                np.concatenate([a.toc_ns, b.toc_ns]),
                np.concatenate([a.toe_ns, b.toe_ns]),
                np.concatenate([a.af, b.af]),
                k,
            ),
            glonass=GlonassEphemerides(
                *(np.concatenate([getattr(g, n), getattr(h, n)]) for n in g.__dataclass_fields__)
            ),
            iono_alpha=self.iono_alpha if np.all(np.isfinite(self.iono_alpha)) else other.iono_alpha,
            iono_beta=self.iono_beta if np.all(np.isfinite(self.iono_beta)) else other.iono_beta,
            leap_seconds=self.leap_seconds if self.leap_seconds is not None else other.leap_seconds,
            skipped={
                k: self.skipped.get(k, 0) + other.skipped.get(k, 0) for k in {**self.skipped, **other.skipped}
            },
        )


def read_nav(path: str | PathLike[str] | Sequence[str | PathLike[str]] | RinexNav) -> RinexNav:
    """Read a RINEX 2.xx (GPS ``N``, GLONASS ``G``, Galileo ``E``, SBAS ``H``), 3.xx or 4.xx (any system)
    navigation file, or several merged into one.

    The reader follows the rule of ``docs/robustness.md`` ("Real files"): malformed records are refused,
    a valid file is read whole, records it cannot use are skipped with one
    :class:`~gnssatt.errors.RecordsSkippedWarning` per kind. SBAS and NavIC (IRNSS) records are counted in
    :attr:`RinexNav.skipped` (``"EPH S SBAS"``, ``"EPH I LNAV"``, as RINEX 4 names them). A Keplerian record
    whose perigee a (1 - e) is below the Earth's equatorial radius is not an orbit and is skipped; any
    eccentricity in [0, 1) is otherwise kept (Galileo E14 and E18, e 0.16-0.17, are real orbits). A file
    cut inside its last record gives the records before it; a file without a final line end after a
    complete record is read whole. RINEX 4 files: the ephemeris messages the engine uses are read
    (``EPH`` records of GPS/QZSS ``LNAV``, Galileo ``INAV``/``FNAV``, BeiDou ``D1``/``D2``, GLONASS
    ``FDMA``) and the Klobuchar coefficients of the first GPS ``ION ... LNAV`` record (RINEX 4 moved them out
    of the header); every other record (``CNAV``, ``CNV1-3``, ``STO``, ``EOP``, other ``ION``) is skipped and
    counted in :attr:`RinexNav.skipped`. Records are kept in file order, repeated ones included: navigation
    files are grouped by satellite, not sorted in time, and merged files carry one record per message type
    (Galileo I/NAV and F/NAV share a time of clock).

    Parameters
    ----------
    path
        The navigation file (str or ``os.PathLike``), or a list or tuple of them, read in order and merged
        (:meth:`RinexNav.__add__`: records of every file, the first file's header values where it has them);
        a :class:`RinexNav` already read is returned as it is, so that every function taking navigation data
        takes any of these through this one reader. Hatanaka- and gzip/Z/zip/bz2-compressed files are read
        with the optional ``hatanaka`` package (``pip install gnssatt[hatanaka]``).

    Returns
    -------
    RinexNav
        Keplerian ephemerides (G, E, C, J), GLONASS state vectors, the GPS Klobuchar coefficients, the
        leap seconds of the header and the RINEX 4 records skipped.

    Warns
    -----
    RecordsSkippedWarning
        One per kind: records of messages not used (counted in ``skipped``), records that are not an orbit,
        the last record of a file cut inside it.

    Raises
    ------
    RinexError
        Unknown version or file type, a missing ``END OF HEADER``, a record with fewer lines than its system
        has (except the last, cut by the end of the file), a line cut inside a field (except the last line
        of a file without a final line end), a Keplerian record with sqrt(A) <= 0 or an eccentricity outside
        [0, 1), a malformed or non-finite number,
        a date or time that does not exist, a week, time of week or GLONASS channel that is not a whole
        number in its range; the message names the file and line. Every other failure while reading becomes
        a ``RinexError`` naming the line being read. ``InvalidTypeError`` if ``path`` is not a str,
        ``os.PathLike``, list or tuple of them or a :class:`RinexNav`; ``InvalidInputError`` if a name is
        empty or the list is.

    Examples
    --------
    A file written from the nominal GPS orbits (:func:`~gnssatt.rinex.writer.write_nav_from_constellation`)
    reads back with their elements: semi-major axis 26 559.7 km, inclination 55 deg, circular, one record per
    hour for each satellite:

    >>> import tempfile
    >>> from pathlib import Path
    >>> import numpy as np
    >>> from gnssatt.orbit.constellation import gps_nominal
    >>> from gnssatt.rinex import read_nav, write_nav_from_constellation
    >>> gps = gps_nominal().select(["G01", "G02"])
    >>> with tempfile.TemporaryDirectory() as folder:
    ...     path = Path(folder) / "sim.nav"
    ...     epoch = np.datetime64("2024-03-01T00:00:00")  # GPST
    ...     toe_ns = write_nav_from_constellation(path, gps, epoch, span_s=3600.0)
    ...     nav = read_nav(path)
    >>> nav.kepler.sats.tolist(), nav.leap_seconds
    (['G01', 'G01', 'G02', 'G02'], 18)
    >>> fields = nav.kepler.fields
    >>> np.round(fields["sqrt_a"] ** 2 / 1e3, 3), np.round(np.degrees(fields["i0"]), 9), fields["e"]
    (array([26559.7, 26559.7, 26559.7, 26559.7]), array([55., 55., 55., 55.]), array([0., 0., 0., 0.]))
    >>> (np.diff(nav.kepler.toe_ns[:2]) / 1e9).tolist(), bool(nav.kepler.toe_ns[0] == toe_ns[0])
    ([3600.0], True)
    """
    return navigation(path, "path")


def navigation(value: object, name: str) -> RinexNav:
    """:func:`read_nav` of the argument ``name`` of a caller (``nav`` of the engine's entry points): a
    refusal names that argument."""
    if isinstance(value, RinexNav):
        return value
    if isinstance(value, str | PathLike):
        return _read_one(path_text(value, name))
    if not isinstance(value, list | tuple):
        raise InvalidTypeError(
            f"expected {name} as a str or os.PathLike (a navigation file), a list of them or a RinexNav, got "
            f"{type(value).__name__}"
        )
    if not value:
        raise InvalidInputError(f"expected at least one navigation file in {name}, got none")
    navs = [_read_one(path_text(p, f"{name}[{i}]")) for i, p in enumerate(value)]
    return functools.reduce(operator.add, navs)


def _read_one(p: str) -> RinexNav:
    """One navigation file, its name checked."""
    with reading(p) as cursor:
        skips = Skips(p)
        nav = _read_nav(p, read_bytes(p), cursor, skips)
    for key, count in sorted(nav.skipped.items(), key=lambda kv: -kv[1]):
        skips.add(_UNUSED_MESSAGES, f"{key} x{count}", count)
    skips.warn()
    return nav


#: Kinds of what :func:`read_nav` skips, for its warnings.
_UNUSED_MESSAGES = "records skipped, of messages gnssatt does not use (counted in RinexNav.skipped)"
_NOT_AN_ORBIT = (
    "Keplerian records skipped: not an orbit (perigee a (1 - e) below the Earth's equatorial radius)"
)
_CUT_RECORD = "record left out: the file ends inside it (the records before it are read)"


def _read_nav(p: str, raw: bytes, cursor: Cursor, skips: Skips) -> RinexNav:
    """The records of the decompressed file ``raw``, parsed by the Rust core (``gnssatt_core::rinex::nav``:
    the header values, the record walk and every check of a field), as the arrays of :class:`RinexNav`
    in GPST."""
    r = _core.rinex_nav_records(p, raw, sorted(HEADER_LABELS))
    for kind, record in r.skips:
        skips.add(_CUT_RECORD if kind == "cut" else _NOT_AN_ORBIT, record)
    skipped = dict(r.unused)
    leaps = r.leap_seconds
    cursor.line = r.lines

    def epochs_ns(ep: NDArray[np.int64]) -> NDArray[np.int64]:
        return gps_ns(ep.astype("datetime64[ns]"))

    kr = r.kepler_values
    ks = np.array(r.kepler_sats, dtype="U3")
    toc = epochs_ns(r.kepler_toc_ns)
    fields = {name: kr[:, 3 + k] for k, name in enumerate(KEPLER_FIELDS)}
    is_bds = ks.astype("U1") == "C"  # not numpy.char: its first use imports it (start-up)
    week = fields["week"] + np.where(is_bds, 1356, 0)
    toe = (week.astype(np.int64) * _WEEK_NS) + np.round(fields["toe_sow"] * 1e9).astype(np.int64)
    toe = np.where(is_bds, toe + _BDT_OFFSET_NS, toe)
    toc = np.where(is_bds, toc + _BDT_OFFSET_NS, toc)
    kepler = KeplerEphemerides(ks, toc, toe, kr[:, :3].copy(), fields)

    gr = r.glonass_values
    tb = epochs_ns(r.glonass_tb_ns)
    if len(tb):
        first_utc = GPS_EPOCH + np.timedelta64(int(tb[0]), "ns")
        tb = tb + 1_000_000_000 * (leaps if leaps is not None else leap_seconds(first_utc))
    km = 1000.0
    glonass = GlonassEphemerides(
        sats=np.array(r.glonass_sats, dtype="U3"),
        tb_ns=tb,
        clock_bias=gr[:, 0],
        gamma_n=gr[:, 1],
        position_m=gr[:, [3, 7, 11]] * km,
        velocity_m_s=gr[:, [4, 8, 12]] * km,
        acceleration_m_s2=gr[:, [5, 9, 13]] * km,
        channel=np.round(gr[:, 10]).astype(np.int64),
        health=gr[:, 6],
    )
    return RinexNav(
        path=p,
        kepler=kepler,
        glonass=glonass,
        iono_alpha=r.iono_alpha,
        iono_beta=r.iono_beta,
        leap_seconds=leaps,
        skipped=skipped,
    )


@dataclass(frozen=True)
class NavInput:
    """Broadcast records as arrays, one per field of the core's ``KeplerRecord`` / ``GlonassRecord``.

    Attributes
    ----------
    kepler
        ``"sat"`` (n,) str; ``"toc_gpst_ns"``, ``"toe_gpst_ns"`` (n,) int64; ``"af"`` (n, 3); ``"tgd_s"``
        (n, 2); ``"crs"``, ``"delta_n"``, ``"m0"``, ``"cuc"``, ``"e"``, ``"cus"``, ``"sqrt_a"``, ``"cic"``,
        ``"omega0"``, ``"cis"``, ``"i0"``, ``"crc"``, ``"omega"``, ``"omega_dot"``, ``"idot"``,
        ``"health"`` (raw word), ``"iode"``, ``"accuracy_m"``, ``"fit_interval_h"``, ``"data_source"``
        (n,) float64 (SI units and radians as in the file; see ``navdata.rs`` for each system's meaning).
    glonass
        ``"sat"`` (m,) str; ``"tb_gpst_ns"`` (m,) int64; ``"clock_bias_s"`` (-tau_n), ``"gamma_n"``,
        ``"health"`` (m,) float64; ``"position_m"``, ``"velocity_m_s"``, ``"acceleration_m_s2"`` (m, 3)
        float64 (PZ-90 ECEF); ``"channel"`` (m,) int64.
    klobuchar
        (8,) GPS alpha0..3, beta0..3, or None where the header gives none.
    leap_seconds
        GPS - UTC from the header, or None.

    The engine's bindings take these records converted once, as :meth:`navigation`.
    """

    kepler: dict[str, NDArray[Any]]
    glonass: dict[str, NDArray[Any]]
    klobuchar: NDArray[np.float64] | None
    leap_seconds: int | None

    def navigation(self) -> _core.Navigation:
        """These records converted into the core's navigation data, the argument of every GNSS binding
        (``_core.gnss_run``, ``GnssEngine``, ``gnss_satellite_states``, ``gnss_transmit_states``,
        ``gnss_single_point``): made once per file, not on every call.

        Returns
        -------
        gnssatt._core.Navigation
            Frozen; its ``kepler_records`` and ``glonass_records`` count the records.

        Raises
        ------
        InvalidInputError
            A column is missing or of another shape or type than the attributes above say, a satellite id
            is malformed or of the other table's systems, or a GLONASS channel is outside -7..13.
        """
        return _core.Navigation(
            kepler=self.kepler, glonass=self.glonass, klobuchar=self.klobuchar, leap_seconds=self.leap_seconds
        )


_KEPLER_SAME = (
    "crs", "delta_n", "m0", "cuc", "e", "cus", "sqrt_a", "cic", "omega0", "cis", "i0", "crc", "omega",
    "omega_dot", "idot", "health", "iode",
)  # fmt: skip


def nav_input(nav: RinexNav) -> NavInput:
    """The records of ``nav`` as the arrays of :class:`NavInput`.

    Per system (RINEX 3 navigation layout): ``tgd_s`` is GPS/QZSS ``[TGD, NaN]``, Galileo
    ``[BGD E5a/E1, BGD E5b/E1]``, BeiDou ``[TGD1, TGD2]``; ``data_source`` the Galileo data-source word
    (NaN for other systems); ``fit_interval_h`` the GPS fit interval (hours), 0 (the system default) for
    QZSS, whose files give a flag there, and NaN for Galileo and BeiDou, which have none; ``health`` the raw
    word (QZSS's L1C/A health bit 0 and BeiDou's SatH1 included: the ephemeris interprets it).

    Raises
    ------
    InvalidTypeError
        ``nav`` is not a :class:`~gnssatt.rinex.nav.RinexNav`.
    """
    nav = instance("nav", nav, RinexNav, "a RinexNav (from read_nav)")
    k = nav.kepler
    f = k.fields
    system = np.array([s[0] for s in k.sats.tolist()], dtype="U1")
    gps_like = (system == "G") | (system == "J")
    kepler: dict[str, NDArray[Any]] = {
        "sat": np.asarray(k.sats, dtype="U3"),
        "toc_gpst_ns": np.ascontiguousarray(k.toc_ns, dtype=np.int64),
        "toe_gpst_ns": np.ascontiguousarray(k.toe_ns, dtype=np.int64),
        "af": np.ascontiguousarray(k.af, dtype=np.float64).reshape(-1, 3),
    }
    for name in _KEPLER_SAME:
        kepler[name] = np.ascontiguousarray(f[name], dtype=np.float64)
    kepler["tgd_s"] = np.ascontiguousarray(
        np.stack([f["tgd"], np.where(gps_like, np.nan, f["iodc_tgd2"])], axis=-1).reshape(-1, 2)
    )
    kepler["accuracy_m"] = np.ascontiguousarray(f["accuracy"], dtype=np.float64)
    kepler["fit_interval_h"] = np.where(
        system == "G", f["fit_interval"], np.where(system == "J", 0.0, np.nan)
    )
    kepler["data_source"] = np.where(system == "E", f["codes_l2"], np.nan)
    g = nav.glonass
    glonass: dict[str, NDArray[Any]] = {
        "sat": np.asarray(g.sats, dtype="U3"),
        "tb_gpst_ns": np.ascontiguousarray(g.tb_ns, dtype=np.int64),
        "clock_bias_s": np.ascontiguousarray(g.clock_bias, dtype=np.float64),
        "gamma_n": np.ascontiguousarray(g.gamma_n, dtype=np.float64),
        "position_m": np.ascontiguousarray(g.position_m, dtype=np.float64).reshape(-1, 3),
        "velocity_m_s": np.ascontiguousarray(g.velocity_m_s, dtype=np.float64).reshape(-1, 3),
        "acceleration_m_s2": np.ascontiguousarray(g.acceleration_m_s2, dtype=np.float64).reshape(-1, 3),
        "channel": np.ascontiguousarray(g.channel, dtype=np.int64),
        "health": np.ascontiguousarray(g.health, dtype=np.float64),
    }
    coeffs = np.concatenate([nav.iono_alpha, nav.iono_beta]).astype(np.float64)
    return NavInput(
        kepler=kepler,
        glonass=glonass,
        klobuchar=coeffs if np.all(np.isfinite(coeffs)) else None,
        leap_seconds=nav.leap_seconds,
    )
