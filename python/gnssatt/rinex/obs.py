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

from dataclasses import dataclass, field
from os import PathLike
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from gnssatt.errors import RinexError

__all__ = ["RinexObs", "read_obs"]

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


def _float(path: str, lineno: int, text: str, what: str) -> float:
    try:
        return float(text.replace("D", "E").replace("d", "e"))
    except ValueError:
        raise RinexError(path, lineno, f"expected a number for {what}, got {text.strip()!r}") from None


def _int(path: str, lineno: int, text: str, what: str) -> int:
    try:
        return int(text)
    except ValueError:
        raise RinexError(path, lineno, f"expected an integer for {what}, got {text.strip()!r}") from None


_COMPRESSED_MAGIC = (b"\x1f\x8b", b"\x1f\x9d", b"PK\x03\x04", b"BZh")


def _read_lines(path: str | PathLike[str]) -> tuple[str, list[str]]:
    """Lines of a RINEX file; Hatanaka (``.crx``, ``.??d``) and gzip / Unix-compress / zip / bzip2 files are
    decompressed with the optional ``hatanaka`` package (``pip install gnssatt[hatanaka]``)."""
    p = str(path)
    try:
        raw = Path(p).read_bytes()
    except OSError as exc:
        raise RinexError(p, None, f"cannot open: {exc.strerror}") from exc
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
    return p, raw.decode("ascii", errors="replace").splitlines()


def _parse_header(path: str, lines: list[str]) -> tuple[dict[str, object], int]:
    """Header dict and the index of the first body line."""
    if not lines:
        raise RinexError(path, 1, "empty file: expected a RINEX VERSION / TYPE line")
    first = lines[0]
    if first[60:80].strip() != "RINEX VERSION / TYPE":
        raise RinexError(path, 1, f"expected 'RINEX VERSION / TYPE' in columns 61-80, got {first[60:80]!r}")
    version = _float(path, 1, first[0:9], "the RINEX version")
    if not (2.0 <= version < 5.0):
        raise RinexError(path, 1, f"unknown RINEX version {version}: expected 2.xx, 3.xx or 4.xx")
    ftype = first[20:21]
    if ftype != "O":
        raise RinexError(path, 1, f"expected an observation file (type 'O' in column 21), got {ftype!r}")
    sysletter = first[40:41].strip() or "G"
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
    }
    types2: list[str] = []
    n_types2 = 0
    sys3 = ""
    n3 = 0
    types3: dict[str, list[str]] = {}
    for i in range(1, len(lines)):
        line = lines[i]
        label = line[60:80].strip()
        lineno = i + 1
        if label == "END OF HEADER":
            if version < 3:
                if not types2:
                    raise RinexError(path, None, "missing header line '# / TYPES OF OBSERV'")
                if len(types2) != n_types2:
                    raise RinexError(
                        path, lineno, f"'# / TYPES OF OBSERV' announced {n_types2} types, got {len(types2)}"
                    )
                systems = "GRESJCI" if sysletter == "M" else sysletter
                hdr["types"] = {s: tuple(types2) for s in systems}
            else:
                if not types3:
                    raise RinexError(path, None, "missing header line 'SYS / # / OBS TYPES'")
                hdr["types"] = {s: tuple(v) for s, v in types3.items()}
            return hdr, i + 1
        if label == "MARKER NAME":
            hdr["marker"] = line[0:60].strip()
        elif label == "APPROX POSITION XYZ":
            hdr["pos"] = np.array(
                [_float(path, lineno, line[k : k + 14], "APPROX POSITION") for k in (0, 14, 28)]
            )
        elif label == "ANTENNA: DELTA H/E/N":
            hdr["delta"] = np.array(
                [_float(path, lineno, line[k : k + 14], "ANTENNA DELTA") for k in (0, 14, 28)]
            )
        elif label == "INTERVAL":
            hdr["interval"] = _float(path, lineno, line[0:10], "INTERVAL")
        elif label == "TIME OF FIRST OBS":
            ts = line[48:51].strip()
            if ts:
                hdr["time_system"] = ts
            elif sysletter in "RECJ":
                hdr["time_system"] = {"R": "GLO", "E": "GAL", "C": "BDT", "J": "QZS"}[sysletter]
        elif label == "# / TYPES OF OBSERV":
            if line[0:6].strip():
                n_types2 = _int(path, lineno, line[0:6], "the number of observation types")
            types2 += line[6:60].split()
        elif label == "SYS / # / OBS TYPES":
            if line[0:1].strip():
                sys3 = line[0]
                n3 = _int(path, lineno, line[3:6], "the number of observation types")
                types3[sys3] = []
            elif not sys3:
                raise RinexError(path, lineno, "continuation of 'SYS / # / OBS TYPES' without a system")
            types3[sys3] += line[7:58].split()
            if len(types3[sys3]) > n3:
                raise RinexError(
                    path, lineno, f"system {sys3}: announced {n3} types, got {len(types3[sys3])}"
                )
        elif label == "GLONASS SLOT / FRQ #":
            body = line[4:60]
            glo = hdr["glo"]
            assert isinstance(glo, dict)
            for k in range(0, len(body) - 6, 7):
                sat, frq = body[k : k + 3].strip(), body[k + 4 : k + 6].strip()
                if sat and frq:
                    glo[sat] = _int(path, lineno, frq, "a GLONASS channel")
    raise RinexError(path, len(lines), "missing header line 'END OF HEADER' (file truncated in the header?)")


def _epoch_ns(
    y: NDArray[np.int64], mo: NDArray[np.int64], d: NDArray[np.int64], sod_ns: NDArray[np.int64]
) -> NDArray[np.datetime64]:
    months = (y - 1970) * 12 + (mo - 1)
    days = months.astype("datetime64[M]").astype("datetime64[D]") + (d - 1).astype("timedelta64[D]")
    return days.astype("datetime64[ns]") + sod_ns.astype("timedelta64[ns]")


def _sat_id(token: str, default: str) -> str:
    s = token[0] if token[0] != " " else default
    return f"{s}{int(token[1:3] or 0):02d}"


def _convert(
    path: str, buf: bytearray, n_rec: int, n_types: int, linenos: list[int]
) -> tuple[NDArray[np.float64], NDArray[np.uint8], NDArray[np.uint8]]:
    raw = np.frombuffer(bytes(buf), dtype=np.uint8).reshape(n_rec, n_types, 16)
    num = np.ascontiguousarray(raw[:, :, :14])
    blank = np.all((num == 32) | (num == 0), axis=2)
    strings = num.view("S14").reshape(n_rec, n_types).copy()
    strings[blank] = b"nan"
    try:
        values = strings.astype(np.float64)
    except ValueError:
        for r in range(n_rec):
            for k in range(n_types):
                try:
                    float(strings[r, k])
                except ValueError:
                    raise RinexError(
                        path,
                        linenos[r] + (k // 5 if linenos else 0),
                        f"expected a number in observation field {k + 1}, got {strings[r, k].decode()!r}",
                    ) from None
        raise
    digits = raw[:, :, 14:16]
    flags = np.where((digits >= 48) & (digits <= 57), digits - 48, 0).astype(np.uint8)
    return values, flags[:, :, 0], flags[:, :, 1]


def read_obs(path: str | PathLike[str]) -> RinexObs:
    """Read a RINEX 2.xx, 3.xx or 4.xx observation file (uncompressed, not Hatanaka).

    Parameters
    ----------
    path
        The file.

    Returns
    -------
    RinexObs

    Raises
    ------
    RinexError
        A missing file, an unknown version or file type, a missing header line, a malformed epoch line or
        observation field, or a file truncated inside an epoch; the message names the file and line.
    """
    p, lines = _read_lines(path)
    hdr, i = _parse_header(p, lines)
    version = float(hdr["version"])  # type: ignore[arg-type]
    types: dict[str, tuple[str, ...]] = hdr["types"]  # type: ignore[assignment]
    default_sys = str(hdr["system"]) if hdr["system"] != "M" else "G"
    v3 = version >= 3
    n_lines = len(lines)
    ep_fields: list[tuple[int, int, int, int, int, float, int, float]] = []
    rec_epoch: list[int] = []
    rec_sat: list[str] = []
    rec_line: list[int] = []
    chunks: dict[str, list[str]] = {}
    n_types_max = max(len(t) for t in types.values())
    width = n_types_max * 16
    sat_lines2 = (n_types_max + 4) // 5
    while i < n_lines:
        line = lines[i]
        lineno = i + 1
        if not line.strip():
            i += 1
            continue
        if v3:
            if line[0] != ">":
                raise RinexError(p, lineno, f"expected an epoch line starting with '>', got {line[:40]!r}")
            flag = _int(p, lineno, line[31:32] or "0", "the epoch flag")
            n = _int(p, lineno, line[32:35], "the number of satellites")
            date = line[2:29]
        else:
            flag = _int(p, lineno, line[28:29] or "0", "the epoch flag")
            n = _int(p, lineno, line[29:32], "the number of satellites")
            date = line[0:26]
        if flag > 1:  # events: n header/record lines follow (flag 6: cycle slip records, skipped)
            skip = n if flag != 6 else n * (1 if v3 else sat_lines2)
            i += 1 + skip
            continue
        parts = date.split()
        if len(parts) != 6:
            raise RinexError(p, lineno, f"expected an epoch 'yy mm dd hh mm ss', got {date.strip()!r}")
        y, mo, d, hh, mi = (_int(p, lineno, x, "the epoch") for x in parts[:5])
        sec = _float(p, lineno, parts[5], "the epoch seconds")
        if not v3:
            y += 1900 if y >= 80 else 2000
        clk_text = line[41:56] if v3 else line[68:80]
        clk = _float(p, lineno, clk_text, "the clock offset") if clk_text.strip() else float("nan")
        e = len(ep_fields)
        ep_fields.append((y, mo, d, hh, mi, sec, flag, clk))
        if v3:
            if i + n >= n_lines:
                raise RinexError(
                    p, n_lines, f"file truncated: epoch at line {lineno} announces {n} satellites"
                )
            for j in range(1, n + 1):
                rl = lines[i + j]
                sat = _sat_id(rl[0:3], default_sys)
                if rl[0:1] == ">" or len(rl) < 3:
                    raise RinexError(p, i + j + 1, f"expected {n} satellite records after line {lineno}")
                rec_epoch.append(e)
                rec_sat.append(sat)
                rec_line.append(i + j + 1)
                chunks.setdefault(sat[0], []).append(rl[3 : 3 + width].ljust(width))
            i += n + 1
        else:
            n_cont = (n - 1) // 12 if n > 0 else 0
            if i + n_cont >= n_lines:
                raise RinexError(p, n_lines, f"file truncated in the satellite list of line {lineno}")
            sats_text = "".join(lines[i + c][32:68].ljust(36) for c in range(n_cont + 1))
            k = i + n_cont
            ids = [_sat_id(sats_text[3 * j : 3 * j + 3], default_sys) for j in range(n)]
            start = k + 1
            if start + n * sat_lines2 > n_lines:
                raise RinexError(
                    p,
                    n_lines,
                    f"file truncated: epoch at line {lineno} announces {n} satellites with "
                    f"{sat_lines2} line(s) each",
                )
            for j, sat in enumerate(ids):
                base = start + j * sat_lines2
                rec = "".join(lines[base + q][:80].ljust(80) for q in range(sat_lines2))
                rec_epoch.append(e)
                rec_sat.append(sat)
                rec_line.append(base + 1)
                chunks.setdefault("*", []).append(rec[:width])
            i = start + n * sat_lines2
    if not ep_fields:
        raise RinexError(p, n_lines, "no observation epochs after the header")
    ep = np.array([f[:5] for f in ep_fields], dtype=np.int64)
    sec_arr = np.array([f[5] for f in ep_fields])
    sod_ns = (ep[:, 3] * 3600 + ep[:, 4] * 60) * 1_000_000_000 + np.round(sec_arr * 1e9).astype(np.int64)
    time = _epoch_ns(ep[:, 0], ep[:, 1], ep[:, 2], sod_ns)
    sats = tuple(sorted(set(rec_sat)))
    codes_list: list[str] = []
    for t in types.values():
        codes_list += [c for c in t if c not in codes_list]
    codes = tuple(codes_list)
    n_ep, n_sat, n_code = len(ep_fields), len(sats), len(codes)
    data = np.full((n_ep, n_sat, n_code), np.nan)
    lli = np.zeros((n_ep, n_sat, n_code), dtype=np.uint8)
    ssi = np.zeros((n_ep, n_sat, n_code), dtype=np.uint8)
    sat_idx = {s: k for k, s in enumerate(sats)}
    rec_e = np.array(rec_epoch, dtype=np.int64)
    rec_s = np.array([sat_idx[s] for s in rec_sat], dtype=np.int64)
    rec_l = np.array(rec_line, dtype=np.int64)
    rec_sys = np.array([s[0] for s in rec_sat]) if v3 else None
    for key, texts in chunks.items():
        sel = np.arange(len(rec_sat)) if key == "*" else np.flatnonzero(rec_sys == key)
        sys_types = types.get(key) if key != "*" else next(iter(types.values()))
        if sys_types is None:
            raise RinexError(
                p, int(rec_l[sel[0]]), f"satellite system {key!r} has no 'SYS / # / OBS TYPES' line"
            )
        buf = bytearray("".join(texts), "ascii", errors="replace")
        values, l_flags, s_flags = _convert(p, buf, len(texts), n_types_max, list(rec_l[sel]))
        cols = [codes.index(c) for c in sys_types]
        nt = len(sys_types)
        ee, ss = rec_e[sel][:, None], rec_s[sel][:, None]
        data[ee, ss, np.array(cols)[None, :]] = values[:, :nt]
        lli[ee, ss, np.array(cols)[None, :]] = l_flags[:, :nt]
        ssi[ee, ss, np.array(cols)[None, :]] = s_flags[:, :nt]
    return RinexObs(
        path=p,
        version=version,
        marker_name=str(hdr["marker"]),
        approx_position_m=np.asarray(hdr["pos"], dtype=np.float64),
        antenna_delta_hen_m=np.asarray(hdr["delta"], dtype=np.float64),
        time_system=str(hdr["time_system"]),
        interval_s=float(hdr["interval"]),  # type: ignore[arg-type]
        obs_types=types,
        time=time,
        epoch_flag=np.array([f[6] for f in ep_fields], dtype=np.uint8),
        clock_offset_s=np.array([f[7] for f in ep_fields]),
        sats=sats,
        codes=codes,
        data=data,
        lli=lli,
        ssi=ssi,
        glonass_channels=dict(hdr["glo"]),  # type: ignore[call-overload]
    )
