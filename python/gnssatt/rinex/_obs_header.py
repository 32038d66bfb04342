"""The header of a RINEX 2.xx or 3.xx/4.xx observation file: version, station, observation types, scale
factors, phase shifts and GLONASS channels, checked line by line (file, line, expected, got).

:func:`parse_header` reads the header lines only; the epochs after it are read by :mod:`._obs_body`.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from gnssatt.errors import RinexError
from gnssatt.rinex._fields import HEADER_LABELS, epoch_ns, integer, number

__all__ = ["ObsHeader", "parse_header", "used_code"]

_SYSTEMS = "GRESJCI"
_PRN = re.compile(r"[ 0]?[1-9]|[1-9]\d")


@dataclass
class ObsHeader:
    """What the header of an observation file says (the fields of :class:`~gnssatt.rinex.obs.RinexObs`
    that come from it, and the layout of the records).

    Attributes
    ----------
    version
        RINEX version (2.10, 3.04, ...).
    system
        The file's system letter (``"M"`` mixed).
    layout
        Per system letter, every observation code of its types line (each holds a field of a record).
    types
        Per system letter, the codes read (:func:`used_code`).
    unused
        ``"G X1"``: the codes read past.
    scale
        ``SYS / SCALE FACTOR``: system -> code (``"*"`` every code) -> factor.
    """

    version: float
    system: str
    marker: str = ""
    pos: NDArray[np.float64] = field(default_factory=lambda: np.zeros(3))
    delta: NDArray[np.float64] = field(default_factory=lambda: np.zeros(3))
    interval: float = float("nan")
    time_system: str = "GPS"
    layout: dict[str, tuple[str, ...]] = field(default_factory=dict)
    types: dict[str, tuple[str, ...]] = field(default_factory=dict)
    unused: tuple[str, ...] = ()
    glo: dict[str, int] = field(default_factory=dict)
    leap: int | None = None
    scale: dict[str, dict[str, int]] = field(default_factory=dict)
    phase_shift: dict[str, dict[str, tuple[float, tuple[str, ...]]]] = field(default_factory=dict)


_SAT_IDS: dict[tuple[str, str | None], str] = {}  # valid tokens seen: a few hundred at most


def _sat_id(path: str, lineno: int, token: str, default: str | None) -> str:
    """``"G03"`` from a satellite field (RINEX 2 allows a blank system letter, meaning the file's system)."""
    known = _SAT_IDS.get((token, default))
    if known is not None:
        return known
    letter = token[0:1]
    if letter == " " and default is not None:
        letter = default
    if len(token) < 3 or letter not in _SYSTEMS or not _PRN.fullmatch(token[1:3]):
        raise RinexError(path, lineno, f"expected a satellite id such as 'G03', got {token!r}")
    sat = _SAT_IDS[(token, default)] = f"{letter}{int(token[1:3]):02d}"
    return sat


def parse_header(path: str, lines: list[str]) -> tuple[ObsHeader, int]:
    """The header of ``lines`` (the file's lines from its first) and the index of the first body line.

    Raises
    ------
    RinexError
        A header line that breaks the RINEX rules, or no ``END OF HEADER``.
    """
    hdr = _first_line(path, lines)
    sysletter, version = hdr.system, hdr.version
    types = _TypeLines()
    last_known = 1
    for i in range(1, len(lines)):
        line = lines[i]
        label = line[60:80].strip()
        lineno = i + 1
        if label in HEADER_LABELS:
            last_known = lineno
        if label == "END OF HEADER":
            types.finish(path, lineno, hdr)
            return hdr, i + 1
        if label == "MARKER NAME":
            hdr.marker = line[0:60].strip()
        elif label == "APPROX POSITION XYZ":
            hdr.pos = _triple(path, lineno, line, "APPROX POSITION XYZ")
        elif label == "ANTENNA: DELTA H/E/N":
            hdr.delta = _triple(path, lineno, line, "ANTENNA: DELTA H/E/N")
        elif label == "INTERVAL":
            hdr.interval = _interval(path, lineno, line)
        elif label in ("TIME OF FIRST OBS", "TIME OF LAST OBS"):
            _check_time(path, lineno, line, label)
        if label == "TIME OF FIRST OBS":
            hdr.time_system = _time_system(line, sysletter, hdr.time_system)
        elif label == "# / TYPES OF OBSERV":
            types.add_v2(path, lineno, line, sysletter)
        elif label == "SYS / # / OBS TYPES":
            types.add_v3(path, lineno, line)
        elif label == "SYS / PHASE SHIFT" and version >= 3:
            types.phase_last = _phase_shift(path, lineno, line, hdr.phase_shift, types.phase_last)
        elif label == "SYS / SCALE FACTOR" and version >= 3:
            types.scale_last = _scale_factor(path, lineno, line, hdr.scale, types.scale_last, types.types3)
        elif label == "LEAP SECONDS":
            hdr.leap = integer(path, lineno, line[0:6], "LEAP SECONDS")
        elif label == "GLONASS SLOT / FRQ #":
            _glonass_slots(path, lineno, line, hdr.glo)
    raise RinexError(
        path,
        min(last_known + 1, len(lines)),
        "missing header line 'END OF HEADER': expected it here, after the last line with a known header "
        "label (file truncated in the header?)",
    )


def _first_line(path: str, lines: list[str]) -> ObsHeader:
    """The header begun from its ``RINEX VERSION / TYPE`` line: the version, an observation file, the
    file's system letter (blank: GPS)."""
    if not lines:
        raise RinexError(path, 1, "empty file: expected a RINEX VERSION / TYPE line")
    first = lines[0]
    if first[60:80].strip() != "RINEX VERSION / TYPE":
        raise RinexError(path, 1, f"expected 'RINEX VERSION / TYPE' in columns 61-80, got {first[60:80]!r}")
    version = number(path, 1, first[0:9], "the RINEX version")
    if not (2.0 <= version < 5.0):
        raise RinexError(path, 1, f"unknown RINEX version {version}: expected 2.xx, 3.xx or 4.xx")
    ftype = first[20:21]
    if ftype != "O":
        raise RinexError(path, 1, f"expected an observation file (type 'O' in column 21), got {ftype!r}")
    sysletter = first[40:41].strip() or "G"
    if sysletter not in _SYSTEMS + "M":
        raise RinexError(path, 1, f"expected a satellite system letter in column 41, got {sysletter!r}")
    return ObsHeader(version=version, system=sysletter)


@dataclass
class _TypeLines:
    """The observation types lines read so far (RINEX 2's ``# / TYPES OF OBSERV``, RINEX 3's ``SYS / # /
    OBS TYPES``, continuation lines included), and the last phase-shift and scale-factor lines (their
    continuation lines name no system)."""

    types2: list[str] = field(default_factory=list)
    n_types2: int = 0
    sys3: str = ""
    n3: int = 0
    types3: dict[str, list[str]] = field(default_factory=dict)
    announced: dict[str, tuple[int, int]] = field(default_factory=dict)  # system -> (count, its last line)
    scale_last: tuple[str, int, int] | None = None
    phase_last: tuple[str, str, int] | None = None

    def add_v2(self, path: str, lineno: int, line: str, sysletter: str) -> None:
        if line[0:6].strip():
            self.n_types2 = integer(path, lineno, line[0:6], "the number of observation types")
        self.types2 += _codes(path, lineno, line[6:60], self.types2, False)
        self.announced[sysletter] = (self.n_types2, lineno)
        if len(self.types2) > self.n_types2:
            raise RinexError(
                path, lineno, f"announced {self.n_types2} observation types, got {len(self.types2)}"
            )

    def add_v3(self, path: str, lineno: int, line: str) -> None:
        types3 = self.types3
        if line[0:1].strip():
            self.sys3 = line[0]
            if self.sys3 not in _SYSTEMS or self.sys3 in types3:
                raise RinexError(path, lineno, f"expected a new satellite system letter, got {self.sys3!r}")
            self.n3 = integer(path, lineno, line[3:6], "the number of observation types")
            types3[self.sys3] = []
        elif not self.sys3:
            raise RinexError(path, lineno, "continuation of 'SYS / # / OBS TYPES' without a system")
        sys3, n3 = self.sys3, self.n3
        types3[sys3] += _codes(path, lineno, line[7:58], types3[sys3], True)
        self.announced[sys3] = (n3, lineno)
        if len(types3[sys3]) > n3:
            raise RinexError(path, lineno, f"system {sys3}: announced {n3} types, got {len(types3[sys3])}")

    def finish(self, path: str, lineno: int, hdr: ObsHeader) -> None:
        """At ``END OF HEADER`` (line ``lineno``): ``hdr``'s layout, the codes read and read past; every
        system's announced count of types checked."""
        version = hdr.version
        if version < 3:
            if not self.types2:
                raise RinexError(path, lineno, "missing header line '# / TYPES OF OBSERV'")
            systems = "GRESJCI" if hdr.system == "M" else hdr.system
            hdr.layout = {s: tuple(self.types2) for s in systems}
        else:
            if not self.types3:
                raise RinexError(path, lineno, "missing header line 'SYS / # / OBS TYPES'")
            hdr.layout = {s: tuple(v) for s, v in self.types3.items()}
        v3 = version >= 3
        hdr.types = {s: tuple(c for c in v if used_code(c, v3)) for s, v in hdr.layout.items()}
        hdr.unused = tuple(
            sorted({f"{s} {c}" for s, v in hdr.layout.items() for c in v if not used_code(c, v3)})
        )
        for s, (count, at) in self.announced.items():
            got = self.types2 if version < 3 else self.types3[s]
            if len(got) != count:
                raise RinexError(path, at, f"system {s}: announced {count} observation types, got {len(got)}")


def _interval(path: str, lineno: int, line: str) -> float:
    """``INTERVAL``: a positive number of seconds."""
    interval = number(path, lineno, line[0:10], "INTERVAL")
    if interval <= 0.0:
        raise RinexError(
            path,
            lineno,
            f"expected INTERVAL as a positive number of seconds, got {line[0:10].strip()}",
        )
    return interval


def _check_time(path: str, lineno: int, line: str, label: str) -> None:
    """``TIME OF FIRST OBS`` / ``TIME OF LAST OBS``: 5I6,F13.7, a date and time that must exist; taken as
    words, as writers widen the seconds."""
    words = (line[0:60].split() + [""] * 6)[:6]
    y, mo, d, hh, mi = (integer(path, lineno, w, f"the date of {label}") for w in words[:5])
    epoch_ns(path, lineno, y, mo, d, hh, mi, number(path, lineno, words[5], f"the seconds of {label}"))


def _time_system(line: str, sysletter: str, default: str) -> str:
    """The time system of ``TIME OF FIRST OBS``, else that of the file's system, else ``default``."""
    # A3 in columns 49-51; some writers (gLAB) put it one column early, so take the word after the seconds
    # field
    ts = next((w for w in line[43:60].split() if w.isalpha()), "")
    if ts:
        return ts
    if sysletter in "RECJ":
        return {"R": "GLO", "E": "GAL", "C": "BDT", "J": "QZS"}[sysletter]
    return default


def _glonass_slots(path: str, lineno: int, line: str, glo: dict[str, int]) -> None:
    """A ``GLONASS SLOT / FRQ #`` line's satellites and channels into ``glo``."""
    body = line[4:60]
    # 8(A1,I2.2,1X,I2,1X) by the format; writers also omit the blank after a channel ("R11 -5R19
    # +3"), so the pairs are taken as tokens rather than by column
    rest = body
    for m in _GLO_PAIR.finditer(body):
        sat = _sat_id(path, lineno, m.group(1), "R")
        glo[sat] = integer(path, lineno, m.group(2).replace(" ", ""), "a GLONASS channel")
        rest = rest.replace(m.group(0), " " * len(m.group(0)), 1)
    if rest.strip():
        raise RinexError(
            path,
            lineno,
            f"expected GLONASS slot / channel pairs such as 'R01  1', got {body.strip()!r}",
        )


def _phase_shift(
    path: str,
    lineno: int,
    line: str,
    shifts: dict[str, dict[str, tuple[float, tuple[str, ...]]]],
    last: tuple[str, str, int] | None,
) -> tuple[str, str, int] | None:
    """One ``SYS / PHASE SHIFT`` line (A1,1X,A3,1X,F8.5,2X,I2.2,10(1X,A3); continuation lines
    18X,10(1X,A3)) into ``shifts[system][code] = (cycles, satellites)``; a blank correction (the reference
    signal of the band) is 0, no satellites means all. Returns (system, code, satellites still to come)."""
    if not line[0:14].strip():  # a continuation of the satellite list
        if last is None or last[2] <= 0:
            raise RinexError(
                path, lineno, "a 'SYS / PHASE SHIFT' continuation line without a list to continue"
            )
        system, code, left = last
        cycles, sats = shifts[system][code]
        more = tuple(_sat_id(path, lineno, t, system) for t in line[18:60].split())
        shifts[system][code] = (cycles, sats + more)
        return system, code, left - len(more)
    system, code = line[0], line[2:5].strip()
    if system not in _SYSTEMS or not code.startswith("L"):
        raise RinexError(
            path, lineno, f"expected a system letter and a phase code such as 'G L2X', got {line[0:5]!r}"
        )
    cycles = number(path, lineno, line[6:14], "the phase shift (cycles)") if line[6:14].strip() else 0.0
    count = integer(path, lineno, line[16:18], "the number of satellites") if line[16:18].strip() else 0
    sats = tuple(_sat_id(path, lineno, t, system) for t in line[18:60].split())
    shifts.setdefault(system, {})[code] = (cycles, sats)
    return system, code, count - len(sats)


def _scale_factor(
    path: str,
    lineno: int,
    line: str,
    scale: dict[str, dict[str, int]],
    last: tuple[str, int, int] | None,
    types3: dict[str, list[str]],
) -> tuple[str, int, int]:
    """One ``SYS / SCALE FACTOR`` line (A1,1X,I4,2X,I2,12(1X,A3); continuation lines 10X,12(1X,A3)) into
    ``scale[system]``, code -> factor (``"*"``: every code of the system); returns (system, factor, count)
    for a continuation line.

    RINEX 3: the stored observations are the values times the factor (1, 10, 100 or 1000), so a reader
    that ignores the record returns them that many times too large.
    """
    if line[0:1].strip():
        system = line[0]
        if system not in _SYSTEMS:
            raise RinexError(path, lineno, f"expected a satellite system letter in column 1, got {system!r}")
        factor = integer(path, lineno, line[2:6], "the scale factor")
        if factor not in (1, 10, 100, 1000):
            raise RinexError(path, lineno, f"expected a scale factor of 1, 10, 100 or 1000, got {factor}")
        text = line[8:10]
        count = integer(path, lineno, text, "the number of observation types") if text.strip() else 0
    elif last is not None:
        system, factor, count = last
    else:
        raise RinexError(path, lineno, "continuation of 'SYS / SCALE FACTOR' without a system")
    per_system = scale.setdefault(system, {})
    if count == 0:  # blank: every observation type of the system
        per_system["*"] = factor
    # a code the system's types line lacks has no values to scale (gLAB's example lists D1C, S2D, ...)
    per_system.update({c: factor for c in line[10:60].split() if c in types3.get(system, [])})
    return system, factor, count


#: One ``GLONASS SLOT / FRQ #`` pair: satellite (blank system letter allowed) and channel (sign may be apart).
_GLO_PAIR = re.compile(r"([R ][ \d]\d) *([+-]? *\d{1,2})(?!\d)")


def _triple(path: str, lineno: int, line: str, what: str) -> NDArray[np.float64]:
    """The three numbers of a 3F14.4 header line (columns 1-42).

    By the format each number fills 14 columns; writers that widen the fields (gLAB writes F15.4) shift
    them, so when the columns do not hold numbers the three blank-separated words of columns 1-60 are taken.
    """
    try:
        return np.array([number(path, lineno, line[k : k + 14], what) for k in (0, 14, 28)])
    except RinexError:
        words = line[0:60].split()
        if len(words) != 3:
            raise RinexError(
                path, lineno, f"expected three numbers for {what}, got {line[0:60].strip()!r}"
            ) from None
        return np.array([number(path, lineno, w, what) for w in words])


#: Observation codes read (type, band, RINEX 3 attribute): RINEX 2.11 Table A1 and RINEX 3.05 / 4.00
#: section 5.1 (types C L D S; RINEX 2 also P; bands 1-9; the attributes of the signal tables). A code
#: outside these (Septentrio's channel number ``X1``, a two-character code in a RINEX 3 file, an unknown
#: attribute, a receiver's own type) holds its 16 columns of every record, which are read past unparsed.
_V2_CODE = re.compile(r"[CPLDS][1-9]")
_V3_CODE = re.compile(r"[CLDS][1-9][PCDYMNABIQSLXWZE]")


def used_code(code: str, v3: bool) -> bool:
    """Whether ``code`` is an observation code the reader keeps (:data:`_V3_CODE`, :data:`_V2_CODE`)."""
    return bool((_V3_CODE if v3 else _V2_CODE).fullmatch(code))


def _codes(path: str, lineno: int, text: str, before: list[str], v3: bool) -> list[str]:
    """Observation codes of a types line (every one holds a field of the records). A code kept must be new
    in its system: a repeated one would overwrite data; codes read past may repeat."""
    codes = text.split()
    longest = 3 if v3 else 2
    for k, c in enumerate(codes):
        if not 2 <= len(c) <= longest or not c.isalnum():
            raise RinexError(
                path,
                lineno,
                f"expected observation codes of 2{'-3' if v3 else ''} letters and digits, got {c!r}",
            )
        if used_code(c, v3) and (c in before or c in codes[:k]):
            raise RinexError(path, lineno, f"expected distinct observation codes, got {c!r} twice")
    return codes
