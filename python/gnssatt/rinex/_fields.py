"""Fixed-width field reading shared by the observation and navigation readers: lines, numbers, integers,
epoch labels, and the guard that turns any unexpected failure into a :class:`~gnssatt.errors.RinexError`.

A careful reader refuses rather than guesses: a number must look like a Fortran number (no ``nan``, ``inf``,
underscores or overflow to infinity) and an epoch label must be a real calendar date and time. A file that
ends without a line end is read to its end; the readers check that its last record is complete and leave
it out with a warning where it is cut (:class:`RecordsSkippedWarning`).

Records that are valid but cannot be used are collected in a :class:`Skips` and reported with one
:class:`RecordsSkippedWarning` per kind (``docs/robustness.md``, "Real files").
"""

from __future__ import annotations

import datetime
import math
import re
import warnings
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

# Argument checks that other units share live in the intake; the readers and the writer take them from here
# as before.
from gnssatt._arrays import folder_path, path_text, sat_list
from gnssatt.errors import InvalidInputError, InvalidTypeError, RecordsSkippedWarning, RinexError

__all__ = [
    "HEADER_LABELS",
    "Cursor",
    "Skips",
    "epoch_ns",
    "folder_path",
    "integer",
    "number",
    "output_path",
    "path_text",
    "read_bytes",
    "read_lines",
    "reading",
    "sat_list",
    "split_lines",
    "time_labels",
]

_NUMBER = re.compile(r"\s*[+-]?(?:\d+\.?\d*|\.\d+)(?:[EeDd][+-]?\d+)?\s*")
_INTEGER = re.compile(r"\s*[+-]?\d+\s*")
_COMPRESSED_MAGIC = (b"\x1f\x8b", b"\x1f\x9d", b"PK\x03\x04", b"BZh")
#: Years a label may carry: datetime64[ns] holds 1678-2262; GNSS data start in 1980.
YEARS = (1980, 2200)
_EPOCH_1970 = datetime.date(1970, 1, 1).toordinal()


#: Records named in a skip warning; the count covers all of them.
_NAMED = 8


@dataclass
class Skips:
    """Records left out of one file, per kind: each kind is reported once, with its count and the first
    :data:`_NAMED` records (``"E14 at line 120"``)."""

    path: str
    kinds: dict[str, list[str]] = field(default_factory=dict)
    totals: dict[str, int] = field(default_factory=dict)

    def add(self, kind: str, record: str, count: int = 1) -> None:
        """Count ``record`` under ``kind`` (a plural noun phrase saying what was skipped and why, such as
        ``"observation codes read past (...)"``); ``count`` records where ``record`` names a group."""
        self.kinds.setdefault(kind, []).append(record)
        self.totals[kind] = self.totals.get(kind, 0) + count

    def warn(self, stacklevel: int = 3) -> None:
        """One :class:`RecordsSkippedWarning` per kind."""
        for kind, records in self.kinds.items():
            named = ", ".join(records[:_NAMED]) + (", ..." if len(records) > _NAMED else "")
            warnings.warn(
                f"{self.path}: {self.totals[kind]} {kind}: {named}",
                RecordsSkippedWarning,
                stacklevel=stacklevel,
            )


@dataclass
class Cursor:
    """The line being read (1-based), so that an unexpected failure can still name it."""

    line: int | None = None


@contextmanager
def reading(path: str) -> Iterator[Cursor]:
    """Run a reader's body; any exception other than :class:`RinexError` becomes one naming ``path`` and the
    cursor's line, so that no ``IndexError`` or ``OverflowError`` from a hostile file reaches the caller."""
    cursor = Cursor()
    try:
        yield cursor
    except RinexError:
        raise
    except Exception as exc:
        raise RinexError(
            path, cursor.line, f"cannot read this line ({type(exc).__name__}: {exc}); the file is malformed"
        ) from exc


def output_path(name: str, value: object) -> Path:
    """A file to write: a non-empty path whose folder exists and which is not itself a folder.

    Raises
    ------
    InvalidTypeError
        ``value`` is not a str or os.PathLike.
    InvalidInputError
        ``value`` is empty, a folder, or in a folder that does not exist.
    """
    p = Path(path_text(value, name))
    if p.is_dir():
        raise InvalidInputError(f"expected {name} as a file to write, got the folder {str(p)!r}")
    if not p.parent.is_dir():
        raise InvalidInputError(f"expected {name} in an existing folder, got {str(p)!r}")
    return p


def time_labels(name: str, value: object) -> np.ndarray:
    """GPST labels as a ``datetime64[ns]`` array (any shape): datetime64 input only, no NaT, years in
    :data:`YEARS`.

    Raises
    ------
    InvalidTypeError
        ``value`` is not of a datetime64 dtype (numbers, texts, ``None`` are refused rather than guessed).
    InvalidInputError
        A NaT or a label outside the years :data:`YEARS`.
    """
    if isinstance(value, np.datetime64):
        value = np.asarray(value)
    if not isinstance(value, np.ndarray) or value.dtype.kind != "M":
        kind = f"an array of dtype {value.dtype}" if isinstance(value, np.ndarray) else type(value).__name__
        raise InvalidTypeError(f"expected {name} as datetime64 labels, got {kind}")
    lo, hi = np.datetime64(f"{YEARS[0]}-01-01", "s"), np.datetime64(f"{YEARS[1]}-01-01", "s")
    secs = value.astype("datetime64[s]")
    bad = np.isnat(value) | (secs < lo) | (secs >= hi)
    if np.any(bad):
        k = tuple(int(i) for i in np.argwhere(bad)[0]) if value.ndim else ()
        raise InvalidInputError(
            f"expected {name} as labels in the years {YEARS[0]} to {YEARS[1] - 1}, "
            f"got {value[k]} at index {k}"
        )
    return value.astype("datetime64[ns]")


def read_bytes(p: str) -> bytes:
    """The bytes of file ``p``, decompressed where it is compressed.

    Hatanaka (``.crx``, ``.??d``) and gzip / Unix-compress / zip / bzip2 files are decompressed with the
    optional ``hatanaka`` package (``pip install gnssatt[hatanaka]``).
    """
    try:
        raw = Path(p).read_bytes()
    except OSError as exc:
        raise RinexError(p, None, f"cannot open: {exc.strerror or exc}") from exc
    if raw.startswith(_COMPRESSED_MAGIC) or raw[60:80].startswith(b"CRINEX VERS"):
        try:
            import hatanaka
        except ImportError:
            raise RinexError(
                p,
                None,
                "compressed (Hatanaka or gzip/Z/zip/bz2) file: install the optional 'hatanaka' package "
                "(pip install gnssatt[hatanaka]) or decompress it first (crx2rnx)",
            ) from None
        try:
            raw = hatanaka.decompress(raw)
        except Exception as exc:  # the package raises ValueError and its own errors on corrupt input
            raise RinexError(p, None, f"cannot decompress: {exc}") from exc
    return bytes(raw)


def split_lines(raw: bytes) -> tuple[list[str], bool]:
    """The lines of ``raw`` without their line ends, and whether the last line has a line end.

    Lines are split at ``\\n`` only (a ``\\r`` before it is dropped): a stray form feed or other control
    byte stays inside its line, where the field check sees it, instead of shifting every later line
    number. A byte outside ASCII reads as U+FFFD. A last line without a line end may be complete (writers
    that omit the final line end) or cut: the readers check its fields.
    """
    lines = raw.decode("ascii", errors="replace").split("\n")
    ended = lines[-1] == ""
    if ended:
        lines.pop()
    return [ln[:-1] if ln.endswith("\r") else ln for ln in lines], ended


def read_lines(p: str) -> tuple[list[str], bool]:
    """The lines of file ``p`` (:func:`read_bytes`, :func:`split_lines`) and whether the last one ends."""
    return split_lines(read_bytes(p))


def number(path: str, lineno: int, text: str, what: str) -> float:
    """A finite Fortran number (``D`` or ``E`` exponent) from a fixed-width field."""
    if not _NUMBER.fullmatch(text):
        raise RinexError(path, lineno, f"expected a number for {what}, got {text.strip()!r}")
    value = float(text.replace("D", "E").replace("d", "e"))
    if not math.isfinite(value):
        raise RinexError(path, lineno, f"expected a finite number for {what}, got {text.strip()!r}")
    return value


def integer(path: str, lineno: int, text: str, what: str) -> int:
    """An integer (digits with an optional sign) from a fixed-width field."""
    if not _INTEGER.fullmatch(text):
        raise RinexError(path, lineno, f"expected an integer for {what}, got {text.strip()!r}")
    return int(text)


def epoch_ns(path: str, lineno: int, y: int, mo: int, d: int, hh: int, mi: int, sec: float) -> int:
    """Nanoseconds since 1970-01-01 of a calendar label, after checking that it is one.

    Seconds lie in [0, 60); a label of 23:59:60.x (a UTC leap second, as in GLONASS files) is allowed and
    maps onto the first second of the next day, as ``datetime64`` has no leap seconds.
    """
    label = f"{y:04d}-{mo:02d}-{d:02d} {hh:02d}:{mi:02d}:{sec:g}"
    if not YEARS[0] <= y <= YEARS[1]:
        raise RinexError(path, lineno, f"epoch {label}: expected a year in {YEARS[0]}-{YEARS[1]}, got {y}")
    try:
        day = datetime.date(y, mo, d).toordinal() - _EPOCH_1970
    except ValueError:
        raise RinexError(path, lineno, f"epoch {label}: not a calendar date (month {mo}, day {d})") from None
    if not (0 <= hh <= 23 and 0 <= mi <= 59):
        raise RinexError(path, lineno, f"epoch {label}: expected hour 0-23 and minute 0-59")
    leap = hh == 23 and mi == 59
    if not (0.0 <= sec < (61.0 if leap else 60.0)):
        limit = "61 (a leap second at 23:59)" if leap else "60 (61 only at 23:59, a leap second)"
        raise RinexError(path, lineno, f"epoch {label}: expected seconds in [0, {limit}), got {sec}")
    return (day * 86_400 + hh * 3600 + mi * 60) * 1_000_000_000 + round(sec * 1e9)


#: Header labels of RINEX 2.11, 3.05 and 4.00 observation and navigation files. A label outside this set is
#: skipped (writers add their own), but it does not extend the header: when ``END OF HEADER`` is missing,
#: the fault is reported at the first line after the last known label, where the header should have ended.
HEADER_LABELS = frozenset(
    {
        "RINEX VERSION / TYPE", "PGM / RUN BY / DATE", "COMMENT", "MARKER NAME", "MARKER NUMBER",
        "MARKER TYPE", "OBSERVER / AGENCY", "REC # / TYPE / VERS", "ANT # / TYPE", "APPROX POSITION XYZ",
        "ANTENNA: DELTA H/E/N", "ANTENNA: DELTA X/Y/Z", "ANTENNA:PHASECENTER", "ANTENNA: PHASECENTER",
        "ANTENNA: B.SIGHT XYZ", "ANTENNA: ZERODIR AZI", "ANTENNA: ZERODIR XYZ", "CENTER OF MASS: XYZ",
        "WAVELENGTH FACT L1/2", "# / TYPES OF OBSERV", "SYS / # / OBS TYPES", "SIGNAL STRENGTH UNIT",
        "INTERVAL", "TIME OF FIRST OBS", "TIME OF LAST OBS", "RCV CLOCK OFFS APPL", "SYS / DCBS APPLIED",
        "SYS / PCVS APPLIED", "SYS / SCALE FACTOR", "SYS / PHASE SHIFT", "SYS / PHASE SHIFTS",
        "GLONASS SLOT / FRQ #", "GLONASS COD/PHS/BIS", "LEAP SECONDS", "# OF SATELLITES", "PRN / # OF OBS",
        "DOI", "LICENSE OF USE", "STATION INFORMATION", "ION ALPHA", "ION BETA", "DELTA-UTC: A0,A1,T,W",
        "CORR TO SYSTEM TIME", "D-UTC A0,A1,T,W,S,U", "IONOSPHERIC CORR", "TIME SYSTEM CORR",
        "MERGED FILE", "END OF HEADER",
    }
)  # fmt: skip
