"""RINEX 2.xx and 3.xx/4.xx observation files: :func:`read_obs` and what it returns, :class:`RinexObs`.

The header is parsed in Python (:mod:`._obs_header`); the epochs are read by the Rust core from the
decompressed file (:mod:`._obs_body`), which is where a reader spends its time
(``benches/python/rinex_read_speed.py`` measures it).

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

import numpy as np
from numpy.typing import NDArray

from gnssatt.errors import RinexError
from gnssatt.rinex._fields import Skips, path_text, read_bytes, reading
from gnssatt.rinex._obs_body import header_lines, read_body
from gnssatt.rinex._obs_header import parse_header

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
    with reading(p):
        skips = Skips(p)
        obs = _read(p, skips)
    skips.warn()
    return obs


#: Kinds of what :func:`read_obs` reads past, for its warnings.
_UNUSED_CODES = "observation codes read past (not used by gnssatt; their values are not parsed)"
_CUT_EPOCH = "epoch left out: the file ends inside it (the epochs before it are read)"


def _read(p: str, skips: Skips) -> RinexObs:
    raw = read_bytes(p)
    hdr, first_line = parse_header(p, header_lines(raw))
    for code in hdr.unused:
        skips.add(_UNUSED_CODES, code)
    codes_list: list[str] = []
    for t in hdr.types.values():
        codes_list += [c for c in t if c not in codes_list]
    codes = tuple(codes_list)
    body = read_body(p, raw, first_line, hdr, codes, MAX_CELLS)
    if body.cut is not None:
        skips.add(_CUT_EPOCH, body.cut)
    return RinexObs(
        path=p,
        version=hdr.version,
        marker_name=hdr.marker,
        approx_position_m=hdr.pos,
        antenna_delta_hen_m=hdr.delta,
        time_system=hdr.time_system,
        interval_s=hdr.interval,
        obs_types=hdr.types,
        time=body.time_ns.view("datetime64[ns]"),
        epoch_flag=body.epoch_flag,
        clock_offset_s=body.clock_offset_s,
        sats=tuple(body.sats),
        codes=codes,
        data=body.data,
        lli=body.lli,
        ssi=body.ssi,
        glonass_channels=hdr.glo,
        leap_seconds=hdr.leap,
        phase_shift_cycles=hdr.phase_shift,
        unused_codes=hdr.unused,
    )
