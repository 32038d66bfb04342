"""RINEX 2.xx and 3.xx/4.xx observation files: a lean reader (numpy fixed-width parsing).

The epoch headers are walked in Python; the observation records of the whole file are gathered into one
byte buffer and converted in a few vectorised numpy calls (``S14 -> float64``), which is where readers that
convert field by field spend their time (``benches/python/rinex_read.py`` measures it against georinex).

Conventions
-----------
- Times are the epoch labels as written, as ``datetime64[ns]`` in the file's time system
  (``RinexObs.time_system``, ``"GPS"`` unless the header says otherwise); gnssatt computes in GPST.
- Observation codes are kept as the file writes them: RINEX 2 ``"L1"``, ``"C1"``, ``"P2"``; RINEX 3
  ``"L1C"``, ``"C1C"``, ``"D1C"``, ``"S1C"``. :meth:`RinexObs.code_for` picks the code of a kind and band for
  a system in a version-independent way.
- Carrier phase in cycles with the RINEX sign (grows with range), pseudorange in metres, Doppler in Hz
  (positive while the satellite approaches), signal strength as written (dB-Hz in RINEX 3).
- Loss-of-lock indicator ``lli`` (bit 0: lost lock, cycle slip possible) and signal strength ``ssi`` as
  ``uint8`` digits, 0 where blank.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from os import PathLike

import numpy as np
from numpy.typing import NDArray

from gnssatt.errors import RinexError
from gnssatt.rinex._fields import (
    HEADER_LABELS,
    Cursor,
    Skips,
    epoch_ns,
    integer,
    number,
    path_text,
    read_lines,
    reading,
)

__all__ = ["MAX_CELLS", "RinexObs", "read_obs"]

#: Most epochs x satellites x codes :func:`read_obs` holds in its dense arrays (8 GiB of float64 values and
#: 2 GiB of indicators): a day at 1 Hz of 120 satellites with 40 codes is 4.1e8; a hostile file scattering
#: one record per epoch over every satellite id could otherwise ask for hundreds of GiB.
MAX_CELLS = 2**30

_CODE_PRIORITY = "CPWYXSLQIDBZMNA"


@dataclass(frozen=True)
class RinexObs:
    """Contents of one observation file.

    Attributes
    ----------
    path
        The file read.
    version
        RINEX version (2.10, 3.04, ...).
    marker_name
        MARKER NAME (may be empty).
    approx_position_m
        (3,) APPROX POSITION XYZ, ECEF, m (zeros if the header gives none).
    antenna_delta_hen_m
        (3,) ANTENNA: DELTA H/E/N, m.
    time_system
        ``"GPS"``, ``"GLO"``, ``"GAL"``, ``"BDT"`` ... (RINEX 2 files of GPS or mixed type: ``"GPS"``).
    interval_s
        INTERVAL, s, or NaN.
    obs_types
        Observation codes per system letter.
    time
        (n_epochs,) epoch labels, ``datetime64[ns]``.
    epoch_flag
        (n_epochs,) 0 OK, 1 power failure before this epoch.
    clock_offset_s
        (n_epochs,) receiver clock offset reported in the file, s, NaN where absent.
    sats
        Satellite ids (``"G03"``), sorted.
    codes
        Observation codes: the union over systems, in the order of the last axis of :attr:`data`.
    data
        (n_epochs, n_sats, n_codes) float64, NaN where not observed.
    lli, ssi
        (n_epochs, n_sats, n_codes) uint8 loss-of-lock indicators and signal-strength digits.
    glonass_channels
        GLONASS FDMA channel per satellite from ``GLONASS SLOT / FRQ #`` (RINEX 3.02+), else empty.
    leap_seconds
        GPS - UTC leap seconds of the header's ``LEAP SECONDS`` line, or None.
    phase_shift_cycles
        RINEX 3.01+ ``SYS / PHASE SHIFT``: system -> phase code -> (correction, satellites), the correction
        in cycles that the writer has already applied to align the code's phases with the reference signal
        of its band (0 for the reference itself), for the satellites listed (all where none); empty where
        the header has none. The phases in :attr:`data` are as written: the reader applies nothing.
    unused_codes
        ``"G X1"``: observation codes of the header that the reader reads past (their values are not
        parsed, :attr:`codes` omits them): a receiver's channel number, a two-character code in a RINEX 3
        file, an unknown attribute or type.
    """

    path: str
    version: float
    marker_name: str
    approx_position_m: NDArray[np.float64]
    antenna_delta_hen_m: NDArray[np.float64]
    time_system: str
    interval_s: float
    obs_types: dict[str, tuple[str, ...]]
    time: NDArray[np.datetime64]
    epoch_flag: NDArray[np.uint8]
    clock_offset_s: NDArray[np.float64]
    sats: tuple[str, ...]
    codes: tuple[str, ...]
    data: NDArray[np.float64]
    lli: NDArray[np.uint8]
    ssi: NDArray[np.uint8]
    glonass_channels: dict[str, int] = field(default_factory=dict)
    leap_seconds: int | None = None
    phase_shift_cycles: dict[str, dict[str, tuple[float, tuple[str, ...]]]] = field(default_factory=dict)
    unused_codes: tuple[str, ...] = ()

    def get(self, code: str) -> NDArray[np.float64]:
        """(n_epochs, n_sats) values of one observation code (NaN where absent)."""
        if code not in self.codes:
            raise RinexError(
                self.path, None, f"no observation code {code!r}; the file has {list(self.codes)}"
            )
        return self.data[:, :, self.codes.index(code)]

    def get_lli(self, code: str) -> NDArray[np.uint8]:
        """(n_epochs, n_sats) loss-of-lock indicators of one observation code."""
        if code not in self.codes:
            raise RinexError(
                self.path, None, f"no observation code {code!r}; the file has {list(self.codes)}"
            )
        return self.lli[:, :, self.codes.index(code)]

    def code_for(self, system: str, kind: str, band: int | str) -> str | None:
        """The observation code of ``kind`` (``"C"`` code, ``"L"`` phase, ``"D"`` Doppler, ``"S"``
        strength) on ``band`` (1, 2, 5, ...) for ``system`` (``"G"``, ``"R"``, ...), or None.

        RINEX 2: ``C1`` before ``P1`` on band 1, ``P2`` before ``C2`` on band 2. RINEX 3: the first
        attribute present in the order C, P, W, Y, X, S, L, Q, I, D, B, Z, M, N, A.
        """
        types = self.obs_types.get(system, ())
        band = str(band)
        if self.version < 3:
            order = [f"{kind}{band}"]
            if kind == "C":
                order = ["C1", "P1"] if band == "1" else [f"P{band}", f"C{band}"]
            return next((c for c in order if c in types), None)
        present = [c for c in types if c[0] == kind and c[1] == band]
        present.sort(key=lambda c: _CODE_PRIORITY.find(c[2]) if c[2] in _CODE_PRIORITY else 99)
        return present[0] if present else None

    def sat_index(self, sats: list[str] | tuple[str, ...]) -> NDArray[np.int64]:
        """Indices into :attr:`sats` of the given ids."""
        lookup = {s: i for i, s in enumerate(self.sats)}
        return np.array([lookup[s] for s in sats], dtype=np.int64)


_SYSTEMS = "GRESJCI"
_PRN = re.compile(r"[ 0]?[1-9]|[1-9]\d")
#: Characters of an F14.3 observation: digits, sign, point, leading blanks.
_OBS_CHARS = np.zeros(256, dtype=bool)
_OBS_CHARS[[ord(c) for c in "0123456789+-. "]] = True
_OBS_NUMBER = re.compile(r" *[+-]?(?:\d+\.?\d*|\.\d+)")
#: A continuation of a RINEX 2 satellite list (an observation line always holds a decimal point).
_SAT_LIST = re.compile(r" {32}(?:[A-Z ][ \d]\d)+ *")
_FLAG_NAMES = "0 (OK), 1 (power failure), 2-5 (events followed by special records) or 6 (cycle slip records)"


#: The start of an epoch line (RINEX 3: ``>``; RINEX 2: a two-digit-year label, flag and count), to tell a
#: file cut inside its last epoch from an epoch that announces more records than follow it.
_NEXT_EPOCH = {
    True: re.compile(">"),
    False: re.compile(r" [ \d]\d [ \d]\d [ \d]\d [ \d]\d [ \d]\d [ \d]\d\.\d{7}  [0-6][ \d]{2}\d"),
}

#: Header records that change the layout or scaling of the observation records after them.
_LAYOUT_LABELS = frozenset({"SYS / # / OBS TYPES", "# / TYPES OF OBSERV", "SYS / SCALE FACTOR"})

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


def _blank(line: str, spans: tuple[tuple[int, int], ...]) -> bool:
    return all(not line[a:b].strip() for a, b in spans)


#: Epoch-line layout (0-based slices): year, month, day, hour, minute, second; separators; flag; count;
#: clock offset; the shortest valid line.
_EPOCH_V3 = (((2, 6), (7, 9), (10, 12), (13, 15), (16, 18), (18, 29)), ((1, 2), (6, 7), (9, 10), (12, 13),
             (15, 16), (29, 31)), 31, (32, 35), (41, 56), 35)  # fmt: skip
_EPOCH_V2 = (((1, 3), (4, 6), (7, 9), (10, 12), (13, 15), (15, 26)), ((0, 1), (3, 4), (6, 7), (9, 10),
             (12, 13), (26, 28)), 28, (29, 32), (68, 80), 32)  # fmt: skip


def _epoch_line(path: str, lineno: int, line: str, v3: bool) -> tuple[int, int, int | None, float]:
    """Flag, count, label (ns since 1970, None for an event epoch without a time) and clock offset (s, NaN
    if blank) of an epoch line."""
    dates, seps, flag_col, (n0, n1), (c0, c1), shortest = _EPOCH_V3 if v3 else _EPOCH_V2
    if len(line) < shortest:
        raise RinexError(
            path, lineno, f"epoch line cut short: expected at least {shortest} columns, got {len(line)}"
        )
    flag_text = line[flag_col]
    if flag_text not in "0123456":
        raise RinexError(path, lineno, f"unknown epoch flag {flag_text!r}: expected {_FLAG_NAMES}")
    flag = int(flag_text)
    n = integer(path, lineno, line[n0:n1], "the number of satellites (or special records)")
    if n < 0:
        raise RinexError(path, lineno, f"expected a number of satellites >= 0, got {n}")
    # RINEX 3/4: the offset (F15.12, columns 42-56) ends the line; take all after the count so that a
    # writer one column off (gLAB writes the count as I2) cannot cut the sign from the number
    clk_text = line[n1:] if v3 else line[c0:c1]
    clk = number(path, lineno, clk_text, "the receiver clock offset") if clk_text.strip() else float("nan")
    date_area = line[dates[0][0] : dates[-1][1]]
    if 2 <= flag <= 5 and not date_area.strip():
        return flag, n, None, clk  # an event whose time is not significant
    if not _blank(line, seps):
        raise RinexError(path, lineno, f"expected an epoch 'yyyy mm dd hh mm ss.sssssss', got {date_area!r}")
    y, mo, d, hh, mi = (integer(path, lineno, line[a:b], "the epoch") for a, b in dates[:5])
    sec = number(path, lineno, line[dates[5][0] : dates[5][1]], "the epoch seconds")
    if not v3:
        if not 0 <= y <= 99:
            raise RinexError(path, lineno, f"expected a two-digit year, got {y}")
        y += 1900 if y >= 80 else 2000
    return flag, n, epoch_ns(path, lineno, y, mo, d, hh, mi, sec), clk


def _check_fields(path: str, lineno: int, text: str, n_fields: int, what: str) -> None:
    """Refuse a record line that ends inside a number (a cut field) or holds more fields than announced.

    Observations are F14.3 right-justified in 16 columns (then the LLI and signal-strength digits), so a
    line whose blanks at the end were stripped still ends at column 14, 15 or 16 of a field.
    """
    content = text.rstrip(" ")
    if len(content) > 16 * n_fields:
        raise RinexError(
            path, lineno, f"{what}: more than the {n_fields} observation fields the header announces"
        )
    cut = len(content) % 16
    if 1 <= cut <= 13:
        field = len(content) // 16 + 1
        raise RinexError(
            path, lineno, f"{what}: the line ends inside observation field {field} (a field cut short)"
        )


def _convert(
    path: str, texts: list[str], n_fields: int, keep: NDArray[np.int64], line_of: NDArray[np.int64]
) -> tuple[NDArray[np.float64], NDArray[np.uint8], NDArray[np.uint8]]:
    """Values, LLI and signal-strength digits of the fields ``keep`` of records (one text of ``16 n_fields``
    columns each), checked as a whole; ``line_of[r, k]`` is the line of kept field ``k`` of record ``r``,
    to name the first bad one. The other fields (codes read past) are not looked at."""
    n_rec = len(texts)
    raw = np.frombuffer("".join(texts).encode("ascii", errors="replace"), dtype=np.uint8)
    raw = raw.reshape(n_rec, n_fields, 16)
    if len(keep) < n_fields:
        raw = raw[:, keep, :]
    n_types = len(keep)
    num = np.ascontiguousarray(raw[:, :, :14])
    space = num == 32
    blank = space.all(axis=2)
    # a number is right-justified with no blank inside: no blank follows a non-blank
    shaped = _OBS_CHARS[num].all(axis=2) & ~np.any(space[:, :, 1:] & ~space[:, :, :-1], axis=2)
    digits = raw[:, :, 14:16]
    is_digit = (digits >= 48) & (digits <= 57)
    bad = (~blank & ~shaped) | ~np.all(is_digit | (digits == 32), axis=2)
    strings = num.view("S14").reshape(n_rec, n_types).copy()
    strings[blank | bad] = b"nan"
    try:
        values = strings.astype(np.float64)
    except ValueError:  # "1-2", "1.2.3": the right characters in a wrong order
        for r, k in np.argwhere(~blank & ~bad):
            bad[r, k] = not _OBS_NUMBER.fullmatch(strings[r, k].decode())
        strings[bad] = b"nan"
        values = strings.astype(np.float64)
    if bad.any():
        r, k = min(np.argwhere(bad), key=lambda rk: (line_of[rk[0], rk[1]], rk[1]))
        text = raw[r, k].tobytes().decode("ascii", errors="replace")
        raise RinexError(
            path,
            int(line_of[r, k]),
            f"expected a number (F14.3) with blank or digit indicators in observation field {keep[k] + 1}, "
            f"got {text!r}",
        )
    flags = np.where(is_digit, digits - 48, 0).astype(np.uint8)
    return values, flags[:, :, 0], flags[:, :, 1]


def _parse_header(path: str, lines: list[str]) -> tuple[dict[str, object], int]:
    """Header dict and the index of the first body line."""
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
    hdr: dict[str, object] = {
        "version": version,
        "system": sysletter,
        "marker": "",
        "pos": np.zeros(3),
        "delta": np.zeros(3),
        "interval": float("nan"),
        "time_system": "GPS",
        "types": {},
        "glo": {},
        "leap": None,
    }
    scale: dict[str, dict[str, int]] = {}
    scale_last: tuple[str, int, int] | None = None
    hdr["scale"] = scale
    hdr["phase_shift"] = {}
    phase_last: tuple[str, str, int] | None = None
    types2: list[str] = []
    n_types2 = 0
    sys3 = ""
    types3: dict[str, list[str]] = {}
    announced: dict[str, tuple[int, int]] = {}  # system -> (count, line of its last types line)
    last_known = 1
    for i in range(1, len(lines)):
        line = lines[i]
        label = line[60:80].strip()
        lineno = i + 1
        if label in HEADER_LABELS:
            last_known = lineno
        if label == "END OF HEADER":
            if version < 3:
                if not types2:
                    raise RinexError(path, lineno, "missing header line '# / TYPES OF OBSERV'")
                systems = "GRESJCI" if sysletter == "M" else sysletter
                hdr["layout"] = {s: tuple(types2) for s in systems}
            else:
                if not types3:
                    raise RinexError(path, lineno, "missing header line 'SYS / # / OBS TYPES'")
                hdr["layout"] = {s: tuple(v) for s, v in types3.items()}
            layout: dict[str, tuple[str, ...]] = hdr["layout"]  # type: ignore[assignment]
            hdr["types"] = {s: tuple(c for c in v if _used(c, version >= 3)) for s, v in layout.items()}
            unused = sorted({f"{s} {c}" for s, v in layout.items() for c in v if not _used(c, version >= 3)})
            if unused:
                hdr["unused"] = unused
            for s, (count, at) in announced.items():
                got = types2 if version < 3 else types3[s]
                if len(got) != count:
                    raise RinexError(
                        path, at, f"system {s}: announced {count} observation types, got {len(got)}"
                    )
            return hdr, i + 1
        if label == "MARKER NAME":
            hdr["marker"] = line[0:60].strip()
        elif label == "APPROX POSITION XYZ":
            hdr["pos"] = _triple(path, lineno, line, "APPROX POSITION XYZ")
        elif label == "ANTENNA: DELTA H/E/N":
            hdr["delta"] = _triple(path, lineno, line, "ANTENNA: DELTA H/E/N")
        elif label == "INTERVAL":
            interval = number(path, lineno, line[0:10], "INTERVAL")
            if interval <= 0.0:
                raise RinexError(
                    path,
                    lineno,
                    f"expected INTERVAL as a positive number of seconds, got {line[0:10].strip()}",
                )
            hdr["interval"] = interval
        elif label in ("TIME OF FIRST OBS", "TIME OF LAST OBS"):
            # 5I6,F13.7: a date and time that must exist; taken as words, as writers widen the seconds
            words = (line[0:60].split() + [""] * 6)[:6]
            y, mo, d, hh, mi = (integer(path, lineno, w, f"the date of {label}") for w in words[:5])
            epoch_ns(
                path, lineno, y, mo, d, hh, mi, number(path, lineno, words[5], f"the seconds of {label}")
            )
        if label == "TIME OF FIRST OBS":
            # A3 in columns 49-51; some writers (gLAB) put it one column early, so take the word after the
            # seconds field
            ts = next((w for w in line[43:60].split() if w.isalpha()), "")
            if ts:
                hdr["time_system"] = ts
            elif sysletter in "RECJ":
                hdr["time_system"] = {"R": "GLO", "E": "GAL", "C": "BDT", "J": "QZS"}[sysletter]
        elif label == "# / TYPES OF OBSERV":
            if line[0:6].strip():
                n_types2 = integer(path, lineno, line[0:6], "the number of observation types")
            types2 += _codes(path, lineno, line[6:60], types2, False)
            announced[sysletter] = (n_types2, lineno)
            if len(types2) > n_types2:
                raise RinexError(path, lineno, f"announced {n_types2} observation types, got {len(types2)}")
        elif label == "SYS / # / OBS TYPES":
            if line[0:1].strip():
                sys3 = line[0]
                if sys3 not in _SYSTEMS or sys3 in types3:
                    raise RinexError(path, lineno, f"expected a new satellite system letter, got {sys3!r}")
                n3 = integer(path, lineno, line[3:6], "the number of observation types")
                types3[sys3] = []
            elif not sys3:
                raise RinexError(path, lineno, "continuation of 'SYS / # / OBS TYPES' without a system")
            types3[sys3] += _codes(path, lineno, line[7:58], types3[sys3], True)
            announced[sys3] = (n3, lineno)
            if len(types3[sys3]) > n3:
                raise RinexError(
                    path, lineno, f"system {sys3}: announced {n3} types, got {len(types3[sys3])}"
                )
        elif label == "SYS / PHASE SHIFT" and version >= 3:
            phase_last = _phase_shift(path, lineno, line, hdr["phase_shift"], phase_last)  # type: ignore[arg-type]
        elif label == "SYS / SCALE FACTOR" and version >= 3:
            scale_last = _scale_factor(path, lineno, line, scale, scale_last, types3)
        elif label == "LEAP SECONDS":
            hdr["leap"] = integer(path, lineno, line[0:6], "LEAP SECONDS")
        elif label == "GLONASS SLOT / FRQ #":
            body = line[4:60]
            glo = hdr["glo"]
            assert isinstance(glo, dict)
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
    raise RinexError(
        path,
        min(last_known + 1, len(lines)),
        "missing header line 'END OF HEADER': expected it here, after the last line with a known header "
        "label (file truncated in the header?)",
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


def _used(code: str, v3: bool) -> bool:
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
        if _used(c, v3) and (c in before or c in codes[:k]):
            raise RinexError(path, lineno, f"expected distinct observation codes, got {c!r} twice")
    return codes


def read_obs(path: str | PathLike[str]) -> RinexObs:
    """Read a RINEX 2.xx, 3.xx or 4.xx observation file (plain, or compressed with the optional
    ``hatanaka`` package).

    The reader follows the rule of ``docs/robustness.md`` ("Real files"). It refuses what a careful reader
    refuses, naming the file and the line of the fault: a date or time that does not exist (month 13, hour
    24, minute 60, second 60 except a leap second at 23:59), in an epoch or in ``TIME OF FIRST OBS`` /
    ``TIME OF LAST OBS``, an ``INTERVAL`` <= 0, epochs that do not increase strictly, a number that is not
    a finite F14.3 value (``nan``, ``inf``, ``1e999``), a line cut inside a field, a satellite count that
    differs from the satellites listed or the records that follow, a satellite twice in one epoch, a code
    twice in a system's types, and an unknown epoch flag. It reads every valid file whole: observation
    codes it does not use (:attr:`RinexObs.unused_codes`) are read past, a file with a header and no epochs
    reads as zero epochs, and a file cut inside its last epoch (the file ends before the records the epoch
    announces, with no epoch after it, or ends without a line end inside a field) gives the epochs before
    it; both with a :class:`~gnssatt.errors.RecordsSkippedWarning`.

    Epoch flags are handled as RINEX defines them: 0 and 1 (power failure before the epoch) are observation
    epochs; 2-5 (antenna moving, new occupation, header information, external event) announce that many
    header records, which are checked to be header records and skipped (one that changes the layout of
    the records after it, ``SYS / # / OBS TYPES``, ``# / TYPES OF OBSERV`` or ``SYS / SCALE FACTOR``, is
    refused: split the file there); 6 announces that many cycle-slip records (observation records
    repeating an epoch), which are skipped; any other flag is an error.

    Values stored with a RINEX 3 ``SYS / SCALE FACTOR`` (10, 100, 1000) are divided by it.

    Duplicated epochs are refused, with no option to merge them: a repeated label comes from concatenated
    files or a corrupted clock label, and any silent choice (first, last, union) can pair wrong data. Merge
    such files with a RINEX tool (``gfzrnx -splice``, ``teqc``) first.

    Parameters
    ----------
    path
        The file.

    Returns
    -------
    RinexObs

    Warns
    -----
    RecordsSkippedWarning
        One per kind: the observation codes read past, the last epoch of a file cut inside it.

    Raises
    ------
    RinexError
        Any fault above, a missing file, an unknown version or file type, a missing header line; the
        message names the file and the line. Every other failure while reading becomes a ``RinexError``
        naming the line being read. A file whose epochs x satellites x codes exceed :data:`MAX_CELLS`
        (the size of the dense arrays returned) is refused before they are allocated.
        ``InvalidTypeError`` if ``path`` is not a str or ``os.PathLike``, ``InvalidInputError`` if it is
        empty.

    Examples
    --------
    A file written by :func:`~gnssatt.rinex.writer.write_obs` reads back with its labels, satellites, codes
    and values (NaN where a field is blank):

    >>> import tempfile
    >>> from pathlib import Path
    >>> import numpy as np
    >>> from gnssatt.rinex import read_obs, write_obs
    >>> time = np.array(["2024-03-01T00:00:00", "2024-03-01T00:00:30"], dtype="datetime64[ns]")  # GPST
    >>> phase = np.array([[110_356_087.125, np.nan], [110_356_612.5, 123_264_018.25]])  # (2, 2) cycles
    >>> with tempfile.TemporaryDirectory() as folder:
    ...     path = Path(folder) / "sim.obs"
    ...     write_obs(path, time, ["G05", "R07"], {"L1C": phase}, glonass_channels={"R07": 5})
    ...     obs = read_obs(path)
    >>> obs.time.tolist() == time.tolist(), obs.sats, obs.glonass_channels
    (True, ('G05', 'R07'), {'R07': 5})
    >>> bool(np.array_equal(obs.get("L1C"), phase, equal_nan=True))
    True
    """
    p = path_text(path)
    with reading(p) as cursor:
        skips = Skips(p)
        obs = _read_obs(p, *read_lines(p), cursor, skips)
    skips.warn()
    return obs


#: Kinds of what :func:`read_obs` reads past, for its warnings.
_UNUSED_CODES = "observation codes read past (not used by gnssatt; their values are not parsed)"
_CUT_EPOCH = "epoch left out: the file ends inside it (the epochs before it are read)"


def _read_obs(p: str, lines: list[str], ended: bool, cursor: Cursor, skips: Skips) -> RinexObs:
    hdr, i = _parse_header(p, lines)
    scales: dict[str, dict[str, int]] = hdr["scale"]  # type: ignore[assignment]
    version = float(hdr["version"])  # type: ignore[arg-type]
    types: dict[str, tuple[str, ...]] = hdr["types"]  # type: ignore[assignment]
    layout: dict[str, tuple[str, ...]] = hdr["layout"]  # type: ignore[assignment]
    for code in hdr.get("unused", ()):  # type: ignore[attr-defined]
        skips.add(_UNUSED_CODES, code)
    default_sys = str(hdr["system"]) if hdr["system"] != "M" else "G"
    v3 = version >= 3
    n_lines = len(lines)
    ep_time: list[int] = []
    ep_flag: list[int] = []
    ep_clock: list[float] = []
    rec_epoch: list[int] = []
    rec_sat: list[str] = []
    rec_line: list[int] = []
    chunks: dict[str, list[str]] = {}
    n_types2 = len(next(iter(layout.values())))
    sat_lines2 = (n_types2 + 4) // 5
    previous: tuple[int, int] | None = None  # (label, line) of the last observation epoch
    block: tuple[int, int] | None = None  # (line, count) of the last epoch block read
    while i < n_lines:
        line = lines[i]
        lineno = i + 1
        cursor.line = lineno
        if not line.strip():
            i += 1
            continue
        if v3 and line[0] != ">":
            if block is not None and line[0:1] in _SYSTEMS:
                raise RinexError(
                    p,
                    block[0],
                    f"the epoch announces {block[1]} satellites, but line {lineno} holds one more record",
                )
            raise RinexError(p, lineno, f"expected an epoch line starting with '>', got {line[:40]!r}")
        saved = (len(ep_time), len(rec_sat), {k: len(v) for k, v in chunks.items()})
        reach = 0  # the lines of this epoch block, once known
        try:
            flag, n, t_ns, clk = _epoch_line(p, lineno, line, v3)
            # RINEX 2 lists the satellites on the epoch line and its continuation lines (12 per line)
            n_head = 1 + ((n - 1) // 12 if n > 0 and not v3 and not 2 <= flag <= 5 else 0)
            per_sat = 1 if v3 else sat_lines2
            n_body = n if (v3 or 2 <= flag <= 5) else n * sat_lines2
            reach = i + n_head + n_body
            if i + n_head + n_body > n_lines and not any(
                _NEXT_EPOCH[v3].match(ln) for ln in lines[i + 1 : i + n_head + n_body]
            ):
                # the last epoch, cut by the end of the file (no epoch follows it): the epochs before it
                skips.add(
                    _CUT_EPOCH,
                    f"the epoch at line {lineno} announces {n} "
                    f"{'special records' if 2 <= flag <= 5 else 'satellites'} in {n_head + n_body} lines, "
                    f"the file ends {n_lines - i - 1} line(s) later",
                )
                break
            if i + n_head + n_body > n_lines:
                raise RinexError(
                    p,
                    lineno,
                    f"the epoch announces {n} {'special records' if 2 <= flag <= 5 else 'satellites'}, but "
                    f"the file ends {n_lines - i - 1} line(s) later, with other epochs among them",
                )
            if 2 <= flag <= 5:
                for j in range(i + 1, i + 1 + n):
                    label = lines[j][60:80].strip()
                    if label not in HEADER_LABELS or lines[j][0:1] == ">":
                        raise RinexError(
                            p,
                            lineno,
                            f"epoch flag {flag} announces {n} header records, but line {j + 1} is not one "
                            f"(no header label in columns 61-80)",
                        )
                    if label in _LAYOUT_LABELS:
                        # the records after it would be laid out otherwise: reading them with the old
                        # types (or factors) would put values under wrong codes
                        raise RinexError(
                            p,
                            j + 1,
                            f"'{label}' inside the data (epoch flag {flag} at line {lineno}) changes how "
                            "the records after it are laid out, which this reader does not follow: split the "
                            "file at that epoch with a RINEX tool (gfzrnx -splice, teqc) and read the parts",
                        )
                i += 1 + n
                block = None
                continue
            if v3:
                ids = []
                for j in range(i + 1, i + 1 + n):
                    if lines[j][0:1] == ">":
                        raise RinexError(
                            p,
                            lineno,
                            f"the epoch announces {n} satellites, but line {j + 1} starts the next epoch "
                            f"after {j - i - 1}",
                        )
                    ids.append(_sat_id(p, j + 1, lines[j][0:3], None))
            else:
                listed = "".join(lines[i + c][32:68].ljust(36) for c in range(n_head))
                for c in range(1, n_head):
                    if lines[i + c][:32].strip():
                        raise RinexError(
                            p,
                            lineno,
                            f"the epoch lists {n} satellites, but line {i + c + 1} does not continue "
                            f"the list (columns 1-32 not blank)",
                        )
                if listed[3 * n :].strip() or len(listed[: 3 * n].rstrip()) < 3 * n - 2:
                    raise RinexError(
                        p,
                        lineno,
                        f"the epoch announces {n} satellites, but lists {listed.strip()!r}",
                    )
                ids = [_sat_id(p, lineno + j // 12, listed[3 * j : 3 * j + 3], default_sys) for j in range(n)]
            if not v3 and n % 12 == 0 and i + n_head < n_lines and _SAT_LIST.fullmatch(lines[i + n_head]):
                raise RinexError(
                    p,
                    lineno,
                    f"the epoch announces {n} satellites, but line {i + n_head + 1} continues the list",
                )
            if flag == 6:  # cycle-slip records repeat observations of an epoch already given
                i += n_head + n_body
                block = None
                continue
            if t_ns is None:
                raise RinexError(p, lineno, "an observation epoch needs its date and time")
            if previous is not None and t_ns <= previous[0]:
                what = "repeats" if t_ns == previous[0] else "comes before"
                raise RinexError(
                    p,
                    lineno,
                    f"epoch {np.datetime64(t_ns, 'ns')} {what} the epoch at line {previous[1]}: epochs must "
                    "increase strictly (merge duplicated files with a RINEX tool first)",
                )
            previous = (t_ns, lineno)
            e = len(ep_time)
            ep_time.append(t_ns)
            ep_flag.append(flag)
            ep_clock.append(clk)
            seen: dict[str, int] = {}
            start = i + n_head
            for j, sat in enumerate(ids):
                base = start + j * per_sat
                if sat in seen:
                    raise RinexError(
                        p, base + 1, f"satellite {sat} appears twice in the epoch of line {lineno}"
                    )
                seen[sat] = base
                if v3:
                    sys_types = layout.get(sat[0])
                    if sys_types is None:
                        raise RinexError(
                            p,
                            base + 1,
                            f"satellite system {sat[0]!r} has no 'SYS / # / OBS TYPES' header line",
                        )
                    cursor.line = base + 1
                    _check_fields(p, base + 1, lines[base][3:], len(sys_types), f"satellite {sat}")
                    width = 16 * len(sys_types)
                    chunks.setdefault(sat[0], []).append(lines[base][3 : 3 + width].ljust(width))
                else:
                    for q in range(sat_lines2):
                        cursor.line = base + q + 1
                        fields = min(5, n_types2 - 5 * q)
                        _check_fields(p, base + q + 1, lines[base + q], fields, f"satellite {sat}")
                    rec = "".join(lines[base + q].ljust(80) for q in range(sat_lines2))
                    chunks.setdefault("*", []).append(rec[: 16 * n_types2])
                rec_epoch.append(e)
                rec_sat.append(sat)
                rec_line.append(base + 1)
            i = start + n * per_sat
            block = (lineno, n)
        except RinexError as exc:
            if ended or exc.line is None or exc.line < lineno or (exc.line < n_lines and reach < n_lines):
                raise
            # the file has no line end and this epoch reaches it: the file was cut inside the epoch
            n_ep, n_rec, n_chunk = saved
            del ep_time[n_ep:], ep_flag[n_ep:], ep_clock[n_ep:]
            del rec_epoch[n_rec:], rec_sat[n_rec:], rec_line[n_rec:]
            for key in list(chunks):
                del chunks[key][n_chunk.get(key, 0) :]
            skips.add(_CUT_EPOCH, f"the epoch at line {lineno}, cut at line {n_lines} ({exc.message})")
            break
    cursor.line = n_lines
    sats = tuple(sorted(set(rec_sat)))
    codes_list: list[str] = []
    for t in types.values():
        codes_list += [c for c in t if c not in codes_list]
    codes = tuple(codes_list)
    n_ep, n_sat, n_code = len(ep_time), len(sats), len(codes)
    if n_ep * n_sat * n_code > MAX_CELLS:
        raise RinexError(
            p,
            None,
            f"{n_ep} epochs x {n_sat} satellites x {n_code} codes = {n_ep * n_sat * n_code} values exceed "
            f"the limit of {MAX_CELLS} (gnssatt.rinex.obs.MAX_CELLS); split the file by time or system",
        )
    data = np.full((n_ep, n_sat, n_code), np.nan)
    lli = np.zeros((n_ep, n_sat, n_code), dtype=np.uint8)
    ssi = np.zeros((n_ep, n_sat, n_code), dtype=np.uint8)
    sat_idx = {s: k for k, s in enumerate(sats)}
    rec_e = np.array(rec_epoch, dtype=np.int64)
    rec_s = np.array([sat_idx[s] for s in rec_sat], dtype=np.int64)
    rec_l = np.array(rec_line, dtype=np.int64)
    rec_sys = np.array([s[0] for s in rec_sat])
    for key, texts in chunks.items():
        sel = np.arange(len(rec_sat)) if key == "*" else np.flatnonzero(rec_sys == key)
        columns = layout[key] if key != "*" else next(iter(layout.values()))
        keep = np.array([k for k, c in enumerate(columns) if _used(c, v3)], dtype=np.int64)
        sys_types = tuple(columns[k] for k in keep)
        # RINEX 2 puts five fields on a line; RINEX 3 a whole record on one
        line_of = rec_l[sel][:, None] + (
            keep[None, :] // 5 if key == "*" else np.zeros((1, len(keep)), np.int64)
        )
        values, l_flags, s_flags = _convert(p, texts, len(columns), keep, line_of)
        factors = scales.get(key, {})
        if factors:
            values /= np.array([factors.get(c, factors.get("*", 1)) for c in sys_types], dtype=np.float64)
        cols = np.array([codes.index(c) for c in sys_types])[None, :]
        ee, ss = rec_e[sel][:, None], rec_s[sel][:, None]
        data[ee, ss, cols] = values
        lli[ee, ss, cols] = l_flags
        ssi[ee, ss, cols] = s_flags
    return RinexObs(
        path=p,
        version=version,
        marker_name=str(hdr["marker"]),
        approx_position_m=np.asarray(hdr["pos"], dtype=np.float64),
        antenna_delta_hen_m=np.asarray(hdr["delta"], dtype=np.float64),
        time_system=str(hdr["time_system"]),
        interval_s=float(hdr["interval"]),  # type: ignore[arg-type]
        obs_types=types,
        time=np.array(ep_time, dtype=np.int64).astype("datetime64[ns]"),
        epoch_flag=np.array(ep_flag, dtype=np.uint8),
        clock_offset_s=np.array(ep_clock),
        sats=sats,
        codes=codes,
        data=data,
        lli=lli,
        ssi=ssi,
        glonass_channels=dict(hdr["glo"]),  # type: ignore[call-overload]
        leap_seconds=hdr["leap"],  # type: ignore[arg-type]
        phase_shift_cycles=hdr["phase_shift"],  # type: ignore[arg-type]
        unused_codes=tuple(hdr.get("unused", ())),  # type: ignore[arg-type]
    )
