"""RINEX 2.xx and 3.xx navigation files: broadcast ephemerides of GPS, Galileo, BeiDou, QZSS (Keplerian)
and GLONASS (state vectors).

Times
-----
Every time is converted to GPST and kept as integer nanoseconds since the GPS epoch (1980-01-06 00:00:00
GPST), so that differences of large times stay exact. BDT = GPST - 14 s; GLONASS epochs (UTC) are shifted by
the GPS-UTC leap seconds (the header's ``LEAP SECONDS`` where given, else the table in this module).
"""

from __future__ import annotations

from dataclasses import dataclass
from os import PathLike

import numpy as np
from numpy.typing import NDArray

from gnssatt.errors import RinexError
from gnssatt.rinex.obs import _epoch_ns, _float, _int, _read_lines

__all__ = ["GPS_EPOCH", "GlonassEphemerides", "KeplerEphemerides", "RinexNav", "gps_ns", "read_nav"]

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
    """Nanoseconds since the GPS epoch of GPST ``datetime64`` labels."""
    return (np.asarray(time, dtype="datetime64[ns]") - GPS_EPOCH).astype(np.int64)


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
    """

    path: str
    kepler: KeplerEphemerides
    glonass: GlonassEphemerides
    iono_alpha: NDArray[np.float64]
    iono_beta: NDArray[np.float64]

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
        )


def _values(path: str, lineno: int, line: str, start: int, count: int) -> list[float]:
    out = []
    for k in range(count):
        text = line[start + 19 * k : start + 19 * (k + 1)]
        out.append(_float(path, lineno, text, f"broadcast field {k + 1}") if text.strip() else 0.0)
    return out


def read_nav(path: str | PathLike[str]) -> RinexNav:
    """Read a RINEX 2.xx (GPS ``N`` or GLONASS ``G``) or 3.xx (any system) navigation file.

    SBAS, IRNSS and RINEX 4 message records are not read (RINEX 4 files are refused).

    Raises
    ------
    RinexError
        Unknown version or file type, a missing ``END OF HEADER``, a truncated record, a malformed number;
        the message names the file and line.
    """
    p, lines = _read_lines(path)
    if not lines or lines[0][60:80].strip() != "RINEX VERSION / TYPE":
        raise RinexError(p, 1, "expected 'RINEX VERSION / TYPE' in columns 61-80")
    version = _float(p, 1, lines[0][0:9], "the RINEX version")
    if not (2.0 <= version < 4.0):
        raise RinexError(p, 1, f"unknown navigation file version {version}: expected 2.xx or 3.xx")
    ftype = lines[0][20:21]
    if version < 3 and ftype not in "NG":
        raise RinexError(p, 1, f"expected a GPS ('N') or GLONASS ('G') navigation file, got type {ftype!r}")
    if version >= 3 and ftype != "N":
        raise RinexError(p, 1, f"expected a navigation file (type 'N'), got {ftype!r}")
    v2_system = "R" if (version < 3 and ftype == "G") else "G"
    if version >= 3:
        v2_system = lines[0][40:41].strip() or "G"
    alpha = np.full(4, np.nan)
    beta = np.full(4, np.nan)
    leaps: int | None = None
    body = None
    for i, line in enumerate(lines[1:], start=1):
        label = line[60:80].strip()
        if label == "END OF HEADER":
            body = i + 1
            break
        if label == "ION ALPHA":
            alpha = np.array(
                [_float(p, i + 1, line[2 + 12 * k : 14 + 12 * k], "ION ALPHA") for k in range(4)]
            )
        elif label == "ION BETA":
            beta = np.array([_float(p, i + 1, line[2 + 12 * k : 14 + 12 * k], "ION BETA") for k in range(4)])
        elif label == "IONOSPHERIC CORR" and line[0:4] in ("GPSA", "GPSB"):
            vals = np.array(
                [_float(p, i + 1, line[5 + 12 * k : 17 + 12 * k], "IONOSPHERIC CORR") for k in range(4)]
            )
            if line[3] == "A":
                alpha = vals
            else:
                beta = vals
        elif label == "LEAP SECONDS":
            leaps = _int(p, i + 1, line[0:6], "LEAP SECONDS")
    if body is None:
        raise RinexError(p, len(lines), "missing header line 'END OF HEADER'")
    v3 = version >= 3
    start = 4 if v3 else 3
    kep_rows: list[list[float]] = []
    kep_sats: list[str] = []
    kep_epoch: list[tuple[int, int, int, int, int, float]] = []
    glo_rows: list[list[float]] = []
    glo_sats: list[str] = []
    glo_epoch: list[tuple[int, int, int, int, int, float]] = []
    i = body
    n = len(lines)
    while i < n:
        line = lines[i]
        if not line.strip():
            i += 1
            continue
        lineno = i + 1
        if v3:
            sysc = line[0]
            prn = _int(p, lineno, line[1:3], "the satellite number")
            date = line[3:23].split()
        else:
            sysc = v2_system
            prn = _int(p, lineno, line[0:2], "the satellite number")
            date = line[2:22].split()
        if sysc in "GECJI":
            n_lines = 8
        elif sysc == "R":
            n_lines = 5 if version >= 3.05 else 4
        elif sysc == "S":
            n_lines = 4
        else:
            raise RinexError(p, lineno, f"unknown satellite system {sysc!r} in a navigation record")
        if i + n_lines > n:
            raise RinexError(p, n, f"file truncated inside the record that starts at line {lineno}")
        if len(date) != 6:
            raise RinexError(p, lineno, f"expected an epoch 'yy mm dd hh mm ss', got {' '.join(date)!r}")
        y, mo, d, hh, mi = (_int(p, lineno, x, "the epoch") for x in date[:5])
        sec = _float(p, lineno, date[5], "the epoch seconds")
        if not v3:
            y += 1900 if y >= 80 else 2000
        head = _values(p, lineno, line, 23 if v3 else 22, 3)
        orbit: list[float] = []
        for q in range(1, n_lines):
            orbit += _values(p, lineno + q, lines[i + q], start, 4)
        sat = f"{sysc}{prn:02d}"
        if sysc in "GECJ":
            kep_rows.append(head + orbit[:26])
            kep_sats.append(sat)
            kep_epoch.append((y, mo, d, hh, mi, sec))
        elif sysc == "R":
            glo_rows.append(head + orbit[:12])
            glo_sats.append(sat)
            glo_epoch.append((y, mo, d, hh, mi, sec))
        i += n_lines

    def epochs_ns(ep: list[tuple[int, int, int, int, int, float]]) -> NDArray[np.int64]:
        if not ep:
            return np.zeros(0, dtype=np.int64)
        a = np.array([e[:5] for e in ep], dtype=np.int64)
        s = np.array([e[5] for e in ep])
        sod = (a[:, 3] * 3600 + a[:, 4] * 60) * 1_000_000_000 + np.round(s * 1e9).astype(np.int64)
        return gps_ns(_epoch_ns(a[:, 0], a[:, 1], a[:, 2], sod))

    kr = np.array(kep_rows, dtype=np.float64).reshape(-1, 29)
    ks = np.array(kep_sats, dtype="U3")
    toc = epochs_ns(kep_epoch)
    fields = {name: kr[:, 3 + k] for k, name in enumerate(KEPLER_FIELDS)}
    is_bds = np.char.startswith(ks, "C")
    week = fields["week"] + np.where(is_bds, 1356, 0)
    toe = (week.astype(np.int64) * _WEEK_NS) + np.round(fields["toe_sow"] * 1e9).astype(np.int64)
    toe = np.where(is_bds, toe + _BDT_OFFSET_NS, toe)
    toc = np.where(is_bds, toc + _BDT_OFFSET_NS, toc)
    kepler = KeplerEphemerides(ks, toc, toe, kr[:, :3].copy(), fields)

    gr = np.array(glo_rows, dtype=np.float64).reshape(-1, 15)
    tb = epochs_ns(glo_epoch)
    if len(tb):
        first_utc = GPS_EPOCH + np.timedelta64(int(tb[0]), "ns")
        tb = tb + 1_000_000_000 * (leaps if leaps is not None else leap_seconds(first_utc))
    km = 1000.0
    glonass = GlonassEphemerides(
        sats=np.array(glo_sats, dtype="U3"),
        tb_ns=tb,
        clock_bias=gr[:, 0],
        gamma_n=gr[:, 1],
        position_m=gr[:, [3, 7, 11]] * km,
        velocity_m_s=gr[:, [4, 8, 12]] * km,
        acceleration_m_s2=gr[:, [5, 9, 13]] * km,
        channel=np.round(gr[:, 10]).astype(np.int64),
        health=gr[:, 6],
    )
    return RinexNav(path=p, kepler=kepler, glonass=glonass, iono_alpha=alpha, iono_beta=beta)
