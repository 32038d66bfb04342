"""Writing RINEX 3.04 observation and (mixed) navigation files, so that simulated scenarios run through the
whole recorded-data path with a known truth.

:func:`write_nav_from_constellation` turns the simulator's two-body orbits into broadcast records that
reproduce them exactly: with the scenario epoch ``T0`` (GPST label of ``t = 0``, ``theta0 = 0``) and
``toe`` at ``T0``, ``OMEGA0 = RAAN + omega_E sow(T0)``, ``M0`` the mean anomaly at ``t = 0``,
``delta_n = n_sim - sqrt(mu_sys / a^3)``, ``OMEGA_DOT = omega_sys - omega_E`` (zero for GPS), every
harmonic correction zero.
"""

from __future__ import annotations

import re
from collections.abc import Mapping, Sequence
from os import PathLike

import numpy as np
from numpy.typing import ArrayLike, NDArray

from gnssatt import constants as _constants
from gnssatt._arrays import instance, scalar, shaped
from gnssatt.errors import InvalidInputError, InvalidTypeError
from gnssatt.orbit.constellation import Constellation
from gnssatt.rinex._fields import output_path, sat_list, time_labels
from gnssatt.rinex.nav import GPS_EPOCH, gps_ns

__all__ = ["write_nav_from_constellation", "write_obs"]

#: Gravitational constants and Earth rotation rates of each system's ICD (GPS/QZSS IS-GPS-200, Galileo
#: OS SIS ICD, BeiDou BDS-SIS-ICD); the simulator's Earth turns at ``_OMEGA_E``.
_MU = {"G": 3.986005e14, "J": 3.986005e14, "E": 3.986004418e14, "C": 3.986004418e14, "R": 3.9860044e14}
_OMEGA_E = _constants.OMEGA_E_RAD_S
_OMEGA = {"G": _OMEGA_E, "J": _OMEGA_E, "E": _OMEGA_E, "C": 7.292115e-5}
_BDT_NS = 14 * 1_000_000_000
_BDT_WEEK = 1356
#: GPS - UTC written with GLONASS records (valid since 2017-01-01).
_LEAP_SECONDS = 18
#: GLONASS records: every 30 minutes at 15 and 45 minutes past each UTC hour, as broadcast files have them
#: (t_b is a 15-minute index of the day in UTC(SU) = UTC + 3 h; readers such as RTKLIB round the label to
#: 15 minutes of UTC and take that as t_b), s.
_GLONASS_STEP_S = 1800
_GLONASS_PHASE_S = 900
#: Spacing of the Keplerian records written, s: every epoch is within 30 minutes of a ``toe``, well inside
#: the 4-hour fit interval.
_KEPLER_STEP_S = 3600
#: Galileo data-source word of the records written: I/NAV E1-B, clock for E5b (bits 0 and 9).
_DATA_SOURCE = 513.0
#: Longest span the records of :func:`write_nav_from_constellation` cover, s (a day); largest ``|start_s|``
#: (ten years).
MAX_SPAN_S = 86400.0
MAX_START_S = 3.2e8
_WEEK_NS = 604_800 * 1_000_000_000
_CODE = re.compile(r"[CLDS][1-9][A-Z]")
#: Largest magnitude a 14.3f observation field holds; largest coordinate of APPROX POSITION XYZ (14.4f).
MAX_OBSERVATION = 9.999e9
MAX_POSITION_M = 9.999e8


def _hdr(text: str, label: str) -> str:
    return f"{text:<60.60}{label:<20}\n"


def _parts(t: np.datetime64) -> tuple[int, int, int, int, int, float]:
    # numpy's stubs have no datetime64(datetime64, unit) overload; numpy converts the unit
    s = str(np.datetime64(t, "ns"))  # type: ignore[call-overload]
    date, clock = s.split("T")
    y, mo, d = (int(x) for x in date.split("-"))
    hh, mi, sec = clock.split(":")
    return y, mo, d, int(hh), int(mi), float(sec)


def write_obs(
    path: str | PathLike[str],
    time: ArrayLike,
    sats: Sequence[str],
    observations: Mapping[str, ArrayLike],
    *,
    approx_position_m: ArrayLike = (0.0, 0.0, 0.0),
    marker_name: str = "SIM",
    lli: Mapping[str, ArrayLike] | None = None,
    glonass_channels: Mapping[str, int] | None = None,
) -> None:
    """Write a RINEX 3.04 observation file.

    Parameters
    ----------
    path
        Output file.
    time
        (n_ep,) GPST labels, ``datetime64``.
    sats
        (n_sat,) satellite ids.
    observations
        RINEX 3 code (``"C1C"``, ``"L1C"``, ``"D1C"``, ``"S1C"``) -> (n_ep, n_sat) values (m, cycles, Hz,
        dB-Hz); NaN leaves a field blank, a satellite with every field blank is left out of the epoch, an
        epoch with every satellite left out is not written. Each
        system's ``SYS / # / OBS TYPES`` lists the codes with a value for one of its satellites (every code
        where none has any).
    approx_position_m
        (3,) APPROX POSITION XYZ, ECEF, m.
    marker_name
        MARKER NAME.
    lli
        Code -> (n_ep, n_sat) loss-of-lock digits (0-9), optional.
    glonass_channels
        GLONASS satellite id -> FDMA channel (-7..6), written as ``GLONASS SLOT / FRQ #``; optional.

    Raises
    ------
    InvalidTypeError
        ``path`` not a path, ``time`` not datetime64, ``sats`` not a list of satellite ids,
        ``observations`` or ``lli`` not a mapping of codes to real arrays, ``marker_name`` not text.
    InvalidInputError
        ``path`` empty, a folder or in a missing folder; ``time`` empty, not 1-d, NaT or out of range;
        malformed satellite ids or codes; arrays not (n_ep, n_sat); observations beyond
        ``MAX_OBSERVATION``; ``approx_position_m`` not a finite (3,) within ``MAX_POSITION_M``;
        ``marker_name`` longer than 60 characters or not printable ASCII; ``lli`` not digits 0-9 of
        codes in ``observations``; ``glonass_channels`` not GLONASS ids with channels in -7..6.

    Examples
    --------
    Two epochs of two GPS satellites written and read back (:func:`~gnssatt.rinex.obs.read_obs`): the values
    survive to the file's 3 decimals, and a NaN stays a blank field:

    >>> import tempfile
    >>> from pathlib import Path
    >>> import numpy as np
    >>> from gnssatt.rinex import read_obs, write_obs
    >>> time = np.array(["2024-03-01T00:00:00", "2024-03-01T00:00:30"], dtype="datetime64[ns]")  # GPST
    >>> c1c = np.array([[21_000_123.456, 23_456_789.012], [21_000_223.456, np.nan]])  # (2, 2) m
    >>> with tempfile.TemporaryDirectory() as folder:
    ...     path = Path(folder) / "sim.obs"
    ...     write_obs(path, time, ["G05", "G12"], {"C1C": c1c, "L1C": np.round(c1c / 0.190294, 3)})
    ...     obs = read_obs(path)
    >>> obs.version, obs.sats, obs.codes
    (3.04, ('G05', 'G12'), ('C1C', 'L1C'))
    >>> bool(np.array_equal(obs.get("C1C"), c1c, equal_nan=True))
    True
    """
    path = output_path("path", path)
    t = _epoch_labels(time)
    sats = sat_list("sats", sats)
    codes, data = _observation_data(observations, len(t), len(sats))
    flags = _lli_flags(lli, codes, data)
    pos, marker_name = _station(approx_position_m, marker_name)
    channels = _glonass_channels(glonass_channels)
    systems, sys_codes = _codes_per_system(sats, codes, data)
    out = _obs_header(systems, sys_codes, codes, marker_name, pos, channels, t[0])
    out += _obs_records(t, sats, data, flags, sys_codes)
    with open(path, "w", encoding="ascii") as fh:
        fh.writelines(out)


def _epoch_labels(time: ArrayLike) -> NDArray[np.datetime64]:
    """The (n_ep >= 1,) epoch labels of :func:`write_obs`."""
    t = time_labels("time", time)
    if t.ndim != 1 or t.size == 0:
        raise InvalidInputError(f"expected time of shape (n_ep >= 1,), got {t.shape}")
    return t


def _observation_data(
    observations: Mapping[str, ArrayLike], n_ep: int, n_sat: int
) -> tuple[list[str], NDArray[np.float64]]:
    """The codes of :func:`write_obs` and their values stacked (n_ep, n_sat, n_codes), within the field."""
    arrays = _code_arrays("observations", observations, n_ep, n_sat, nonfinite=True)
    codes = list(arrays)
    data = np.stack([arrays[c] for c in codes], axis=-1)
    if np.any(np.abs(np.where(np.isfinite(data), data, 0.0)) > MAX_OBSERVATION):
        raise InvalidInputError(f"expected |observations| <= {MAX_OBSERVATION} (the 14.3f field)")
    return codes, data


def _lli_flags(
    lli: Mapping[str, ArrayLike] | None, codes: list[str], data: NDArray[np.float64]
) -> NDArray[np.int64]:
    """The loss-of-lock digits of each value of ``data`` (0 where ``lli`` gives none)."""
    flags = np.zeros(data.shape, dtype=np.int64)
    if lli is not None:
        for c, v in _code_arrays("lli", lli, data.shape[0], data.shape[1], nonfinite=False).items():
            if c not in codes:
                raise InvalidInputError(f"expected lli codes among those of observations, got {c!r}")
            if np.any((v != np.round(v)) | (v < 0) | (v > 9)):
                raise InvalidInputError(f"expected lli[{c!r}] as digits 0 to 9")
            flags[..., codes.index(c)] = v.astype(np.int64)
    return flags


def _station(approx_position_m: ArrayLike, marker_name: str) -> tuple[NDArray[np.float64], str]:
    """The header's approximate position (m) and marker name, each within its field."""
    pos = shaped("approx_position_m", approx_position_m, "(3,)", (3,))
    if np.any(np.abs(pos) > MAX_POSITION_M):
        raise InvalidInputError(f"expected |approx_position_m| <= {MAX_POSITION_M} m, got {pos.tolist()}")
    marker_name = instance("marker_name", marker_name, str, "text")
    if len(marker_name) > 60 or not all(" " <= ch <= "~" for ch in marker_name):
        raise InvalidInputError(
            f"expected marker_name as at most 60 printable ASCII characters, got {marker_name!r}"
        )
    return pos, marker_name


def _codes_per_system(
    sats: Sequence[str], codes: list[str], data: NDArray[np.float64]
) -> tuple[list[str], dict[str, list[int]]]:
    """The systems of ``sats`` and, per system, the columns of the codes it has a value of (all codes
    where it has none)."""
    systems = sorted({s[0] for s in sats})
    sys_of = np.array([s[0] for s in sats])
    # np.any rather than the method: numpy types the method over an axis as a scalar or an array
    has: NDArray[np.bool_] = np.any(np.isfinite(data), axis=0)  # (n_sat, n_codes)
    sys_codes = {}
    for sy in systems:
        cols = [j for j in range(len(codes)) if has[sys_of == sy, j].any()]
        sys_codes[sy] = cols or list(range(len(codes)))
    return systems, sys_codes


def _obs_header(
    systems: list[str], sys_codes: dict[str, list[int]], codes: list[str], marker_name: str,
    pos: NDArray[np.float64], channels: Mapping[str, int], t0: np.datetime64,
) -> list[str]:  # fmt: skip
    """The header lines of a RINEX 3.04 observation file whose first epoch is ``t0``."""
    out = [
        _hdr(
            f"{'3.04':>9}{'':11}{'OBSERVATION DATA':<20}{'M' if len(systems) > 1 else systems[0]}",
            "RINEX VERSION / TYPE",
        )
    ]
    out.append(_hdr(f"{'gnssatt':<20}{'':20}{'':20}", "PGM / RUN BY / DATE"))
    out.append(_hdr(marker_name, "MARKER NAME"))
    out.append(_hdr(f"{pos[0]:14.4f}{pos[1]:14.4f}{pos[2]:14.4f}", "APPROX POSITION XYZ"))
    out.append(_hdr(f"{0.0:14.4f}{0.0:14.4f}{0.0:14.4f}", "ANTENNA: DELTA H/E/N"))
    for sy in systems:
        names = [codes[j] for j in sys_codes[sy]]
        for k in range(0, len(names), 13):  # 13 codes per line, continuation lines blank in front
            head = f"{sy}  {len(names):3d}" if k == 0 else " " * 6
            out.append(_hdr(head + "".join(f" {c}" for c in names[k : k + 13]), "SYS / # / OBS TYPES"))
    if channels:
        items = sorted(channels.items())
        for k in range(0, len(items), 8):  # 8 satellites per line
            head = f"{len(items):3d} " if k == 0 else " " * 4
            body = "".join(f"{sat} {ch:2d} " for sat, ch in items[k : k + 8])
            out.append(_hdr(head + body, "GLONASS SLOT / FRQ #"))
    y, mo, d, hh, mi, sec = _parts(t0)
    out.append(_hdr(f"{y:6d}{mo:6d}{d:6d}{hh:6d}{mi:6d}{sec:13.7f}     GPS", "TIME OF FIRST OBS"))
    out.append(_hdr("", "END OF HEADER"))
    return out


def _obs_records(
    t: NDArray[np.datetime64], sats: Sequence[str], data: NDArray[np.float64], flags: NDArray[np.int64],
    sys_codes: dict[str, list[int]],
) -> list[str]:  # fmt: skip
    """The epoch records: each epoch's line, then a line per satellite with a value (the codes of its
    system)."""
    out = []
    for e in range(len(t)):
        present = [k for k in range(len(sats)) if np.any(np.isfinite(data[e, k]))]
        if not present:  # a receiver that tracks nothing (a tunnel) writes no epoch
            continue
        y, mo, d, hh, mi, sec = _parts(t[e])
        out.append(f"> {y:4d} {mo:02d} {d:02d} {hh:02d} {mi:02d}{sec:11.7f}  0{len(present):3d}\n")
        for k in present:
            fields = []
            for j in sys_codes[sats[k][0]]:
                v = data[e, k, j]
                if np.isfinite(v):
                    f = flags[e, k, j]
                    fields.append(f"{v:14.3f}{f if f else ' '} ")
                else:
                    fields.append(" " * 16)
            out.append(sats[k] + "".join(fields).rstrip() + "\n")
    return out


def _glonass_channels(value: object) -> dict[str, int]:
    """``value`` as GLONASS id -> channel in -7..6 (empty for None)."""
    if value is None:
        return {}
    if not isinstance(value, Mapping):
        raise InvalidTypeError(
            f"expected glonass_channels as a mapping of GLONASS ids to channels, got {type(value).__name__}"
        )
    out = {}
    for sat, ch in value.items():
        if not isinstance(sat, str) or not re.fullmatch(r"R\d\d", sat):
            raise InvalidInputError(f"expected GLONASS ids such as 'R07' in glonass_channels, got {sat!r}")
        if isinstance(ch, bool) or not isinstance(ch, int | np.integer) or not -7 <= ch <= 6:
            raise InvalidInputError(f"expected glonass_channels[{sat!r}] as an integer in -7..6, got {ch!r}")
        out[sat] = int(ch)
    return out


def _code_arrays(
    name: str, value: object, n_ep: int, n_sat: int, *, nonfinite: bool
) -> dict[str, NDArray[np.float64]]:
    """``value`` as RINEX 3 code -> (n_ep, n_sat) float arrays (NaN and infinity kept if ``nonfinite``)."""
    if not isinstance(value, Mapping):
        raise InvalidTypeError(
            f"expected {name} as a mapping of RINEX 3 codes to arrays, got {type(value).__name__}"
        )
    if not value:
        raise InvalidInputError(f"expected at least one code in {name}, got none")
    out = {}
    for c, v in value.items():
        if not isinstance(c, str) or not _CODE.fullmatch(c):
            raise InvalidInputError(f"expected RINEX 3 codes such as 'C1C' as the keys of {name}, got {c!r}")
        key = f"{name}[{c!r}]"
        if nonfinite:
            try:
                raw = np.asarray(v)
            except (TypeError, ValueError) as exc:
                raise InvalidTypeError(f"expected {key} as a numeric array, got {type(v).__name__}") from exc
            if raw.dtype.kind not in "iuf":
                raise InvalidTypeError(f"expected {key} as a real numeric array, got dtype {raw.dtype}")
            arr = raw.astype(np.float64)
        else:
            arr = shaped(key, v, f"({n_ep}, {n_sat})", (n_ep, n_sat))
        if arr.shape != (n_ep, n_sat):
            raise InvalidInputError(
                f"expected {key} of shape ({n_ep}, {n_sat}) (time, sats), got {arr.shape}"
            )
        out[c] = arr
    return out


def _d19(x: float) -> str:
    s = f"{x:19.12E}"
    return s.replace("E", "D")


def _check_nav_systems(ids: Sequence[str]) -> None:
    """Refuse satellites the navigation records cannot carry: systems other than G, R, E, C and J, and
    BeiDou's GEO (C01-C05, C59 on)."""
    bad = [s for s in ids if s[0] not in _MU or (s[0] == "C" and (int(s[1:]) <= 5 or int(s[1:]) >= 59))]
    if bad:
        raise InvalidInputError(
            f"expected satellites of G, R, E, C (MEO/IGSO numbers 6-58), J, got {bad[:5]}"
        )


def _nav_header(systems: list[str], iono: list[float]) -> list[str]:
    """The header lines of a RINEX 3.04 navigation file of ``systems`` (Klobuchar coefficients ``iono``,
    eight or none)."""
    return [
        _hdr(
            f"{'3.04':>9}{'':11}{'N: GNSS NAV DATA':<20}{'M' if len(systems) > 1 else systems[0]}",
            "RINEX VERSION / TYPE",
        ),
        _hdr("gnssatt", "PGM / RUN BY / DATE"),
        *(
            _hdr(f"{name} " + "".join(f"{x:12.4E}" for x in iono[k : k + 4]), "IONOSPHERIC CORR")
            for name, k in (("GPSA", 0), ("GPSB", 4))
            if iono
        ),
        _hdr(f"{_LEAP_SECONDS:6d}", "LEAP SECONDS"),
        _hdr("", "END OF HEADER"),
    ]


def write_nav_from_constellation(
    path: str | PathLike[str],
    constellation: Constellation,
    epoch_gpst: np.datetime64,
    *,
    start_s: float = 0.0,
    span_s: float = 0.0,
    clock_bias_s: ArrayLike | None = None,
    klobuchar: ArrayLike | None = None,
) -> NDArray[np.int64]:
    """Write a RINEX 3.04 navigation file (mixed where the constellation is) whose records give the
    simulator's orbits; the ECEF frame is the simulator's with ``theta0 = 0`` at ``epoch_gpst``.

    Records start at ``epoch_gpst + start_s`` (whole seconds) and cover ``span_s`` after it. GPS,
    Galileo, BeiDou and QZSS get a Keplerian record every hour (``toe`` on the record) that reproduces the
    two-body orbit exactly (module docstring; each system's ``mu`` and ``omega_E``, BeiDou in BDT =
    GPST - 14 s; satellites C01-C05 would be read as GEO and are refused). GLONASS gets state vectors (ECEF
    position and velocity, no luni-solar acceleration) every 30 minutes at 15 and 45 minutes past each
    UTC hour (t_b on the 15-minute grid of the day, as broadcast), labelled in UTC with 18 leap seconds
    (written as ``LEAP SECONDS``), the first at or before ``epoch_gpst + start_s``: the first from the
    two-body orbit, the next ones continuing it by the ICD's equations of motion, whose J2 term moves it
    99 m from the two-body orbit in 30 minutes; so simulate ranges from the records read back (as
    :func:`gnssatt.sim.rinex_scenario.simulate_gnss_rinex` does), not from the orbits.

    Parameters
    ----------
    path
        Output file.
    constellation
        Satellites of ``G``, ``R``, ``E``, ``C``, ``J`` ids.
    epoch_gpst
        GPST label of the simulator's ``t = 0``.
    start_s
        Time of the first records after ``epoch_gpst``, s (rounded to whole seconds; ``|start_s|`` up to
        ``MAX_START_S``).
    span_s
        Seconds after the first records that the records must cover (0 to ``MAX_SPAN_S``).
    clock_bias_s
        (n_sat,) satellite clock bias ``af0`` (GLONASS ``-tau_n``), s; zeros by default.
    klobuchar
        (8,) GPS Klobuchar alpha0..3, beta0..3 for the header (``IONOSPHERIC CORR GPSA``/``GPSB``, written
        to 4 decimals as RINEX does: read the file back for the values); none by default.

    Returns
    -------
    toe_ns
        (n_sat,) GPST nanoseconds of each satellite's first record (GLONASS: its t_b).

    Raises
    ------
    InvalidTypeError
        ``path`` not a path, ``constellation`` not a :class:`~gnssatt.sim.Constellation`, ``epoch_gpst``
        not a datetime64, ``start_s``, ``span_s`` or ``clock_bias_s`` not real.
    InvalidInputError
        ``path`` empty, a folder or in a missing folder; ids of other systems or BeiDou GEO ids (C01-C05,
        C59-C63); ``epoch_gpst`` not a single label in range; ``start_s`` or ``span_s`` out of range;
        ``clock_bias_s`` not finite (n_sat,) within 1 ms; ``klobuchar`` not finite (8,) below 1e9.

    Examples
    --------
    The first records of every GPS satellite start at the epoch itself, 2024-03-01 00:00:00 GPST, 16 126
    days after the GPS epoch (1980-01-06); reading the file back: :func:`~gnssatt.rinex.nav.read_nav`.

    >>> import tempfile
    >>> from pathlib import Path
    >>> import numpy as np
    >>> from gnssatt.orbit.constellation import gps_nominal
    >>> from gnssatt.rinex.writer import write_nav_from_constellation
    >>> with tempfile.TemporaryDirectory() as folder:
    ...     toe_ns = write_nav_from_constellation(
    ...         Path(folder) / "sim.nav", gps_nominal(), np.datetime64("2024-03-01T00:00:00")
    ...     )
    >>> toe_ns.shape, bool(np.all(toe_ns == 16126 * 86400 * 10**9))
    ((24,), True)
    """
    path = output_path("path", path)
    constellation = instance("constellation", constellation, Constellation, "a sim.Constellation")
    epoch = time_labels("epoch_gpst", epoch_gpst)
    if epoch.ndim != 0:
        raise InvalidInputError(f"expected epoch_gpst as one datetime64 label, got shape {epoch.shape}")
    # numpy's stubs type [()] as an array; on this 0-d array it is the datetime64 scalar
    epoch_gpst = epoch[()]  # type: ignore[assignment]
    start = round(scalar("start_s", start_s, minimum=-MAX_START_S, maximum=MAX_START_S, unit="s"))
    span_s = scalar("span_s", span_s, minimum=0.0, maximum=MAX_SPAN_S, unit="s")
    ids = constellation.ids
    n = len(ids)
    _check_nav_systems(ids)
    clk = np.zeros(n) if clock_bias_s is None else shaped("clock_bias_s", clock_bias_s, f"({n},)", (n,))
    if np.any(np.abs(clk) > 1e-3):
        raise InvalidInputError(f"expected |clock_bias_s| <= 1e-3 s, got {np.max(np.abs(clk))}")
    iono = [] if klobuchar is None else shaped("klobuchar", klobuchar, "(8,)", (8,)).tolist()
    if any(abs(x) >= 1e9 for x in iono):
        raise InvalidInputError(f"expected |klobuchar| < 1e9 (the 12.4E field), got {iono}")
    t0_ns = int(gps_ns(np.array([epoch_gpst]))[0])
    out = _nav_header(sorted({s[0] for s in ids}), iono)
    first = np.full(n, t0_ns + start * 1_000_000_000, dtype=np.int64)
    glonass_tb = _glonass_grid(t0_ns + start * 1_000_000_000, span_s)
    for j, sat in enumerate(ids):
        if sat[0] == "R":
            out += _glonass_records(sat, constellation, j, glonass_tb, t0_ns, float(clk[j]))
            first[j] = glonass_tb[0]
            continue
        for k in range(int(np.ceil(span_s / _KEPLER_STEP_S)) + 1):
            t_r = start + k * _KEPLER_STEP_S
            out += _kepler_record(sat, constellation, j, t_r, t0_ns + t_r * 1_000_000_000, float(clk[j]))
    with open(path, "w", encoding="ascii") as fh:
        fh.writelines(out)
    return first


def _glonass_grid(first_ns: int, span_s: float) -> list[int]:
    """GPST nanoseconds of the GLONASS records covering ``[first_ns, first_ns + span_s]``: the UTC instants
    at 15 and 45 minutes past the hour from the last one at or before ``first_ns`` to the first one at or
    after the end (every instant within 15 minutes of a record)."""
    second = 1_000_000_000
    leap, phase, step = _LEAP_SECONDS * second, _GLONASS_PHASE_S * second, _GLONASS_STEP_S * second
    # the GPS epoch is a UTC midnight, so whole steps from it (less the leap seconds) are UTC clock times
    utc = (first_ns - leap - phase) // step * step + phase
    end = first_ns + round(span_s * second) - leap
    grid = [utc]
    while grid[-1] < end:
        grid.append(grid[-1] + step)
    return [t + leap for t in grid]


def _record_start(sat: str, label_ns: int, clk: float) -> str:
    """First line of a record: satellite, epoch (whole seconds since the GPS epoch, in the system's time
    scale), clock bias, then two zero fields."""
    y, mo, d, hh, mi, sec = _parts(GPS_EPOCH + np.timedelta64(label_ns, "ns"))
    return (
        f"{sat} {y:4d} {mo:02d} {d:02d} {hh:02d} {mi:02d} {int(sec):02d}" + _d19(clk) + _d19(0.0) * 2 + "\n"
    )


def _kepler_record(
    sat: str, constellation: Constellation, j: int, t_r: int, t_ns: int, clk: float
) -> list[str]:
    """Keplerian record of satellite ``j`` with ``toe`` ``t_r`` seconds after the simulator's ``t = 0``
    (GPST ``t_ns``)."""
    sy = sat[0]
    o = constellation.orbits
    # system time of the record: BDT runs 14 s behind GPST, the others with it
    sys_ns = t_ns - (_BDT_NS if sy == "C" else 0)
    week, sow_ns = divmod(sys_ns, _WEEK_NS)
    sow = sow_ns * 1e-9
    if sy == "C":
        week -= _BDT_WEEK
    a = float(o.semi_major_axis_m[j])
    n_sim = float(o.mean_motion_rad_s[j])
    dn = n_sim - np.sqrt(_MU[sy] / a**3)
    # at toe the node's ECEF longitude is RAAN - omega_E t_r; it moves at -omega_E, the ICD model's at
    # (OMEGA_DOT - omega_sys)
    omega0 = float(o.raan_rad[j]) - _OMEGA_E * t_r + _OMEGA[sy] * sow
    m0 = float(o.mean_anomaly_rad[j]) + n_sim * t_r
    rows = [
        [0.0, 0.0, dn, float(np.remainder(m0 + np.pi, 2 * np.pi) - np.pi)],
        [0.0, float(o.eccentricity[j]), 0.0, np.sqrt(a)],
        [sow, 0.0, float(np.remainder(omega0 + np.pi, 2 * np.pi) - np.pi), 0.0],
        [float(o.inclination_rad[j]), 0.0, float(o.arg_perigee_rad[j]), _OMEGA[sy] - _OMEGA_E],
        [0.0, _DATA_SOURCE if sy == "E" else 0.0, float(week), 0.0],
        [2.0, 0.0, 0.0, 0.0],
        # transmission time; GPS fit interval 4 h, QZSS fit-interval flag 0 (two hours)
        [sow, 4.0 if sy == "G" else 0.0],
    ]
    return [_record_start(sat, sys_ns, clk)] + ["    " + "".join(_d19(v) for v in r) + "\n" for r in rows]


def _glonass_records(
    sat: str, constellation: Constellation, j: int, tb_ns: list[int], t0_ns: int, clk: float
) -> list[str]:
    """GLONASS records of satellite ``j`` at GPST ``tb_ns`` (the simulator's ``t = 0`` is GPST ``t0_ns``),
    labelled in UTC: the first from the two-body orbit, each next one that record's state propagated by the
    ICD's equations of motion (:func:`gnssatt.orbit.glonass_propagate`, 60 s steps as the ephemeris), so
    that neighbouring records agree where either may be chosen (tens of metres apart otherwise: J2)."""
    from gnssatt.orbit import glonass_propagate

    r, v = constellation.select([constellation.ids[j]]).state_ecef((tb_ns[0] - t0_ns) * 1e-9)
    pos, vel = r[0], v[0]
    channel = float(constellation.glonass_channels[j])
    km = 1e-3
    lines = []
    for k, tb in enumerate(tb_ns):
        if k:
            nxt = glonass_propagate(pos, vel, (tb - tb_ns[k - 1]) * 1e-9, step_s=60.0)
            pos, vel = nxt.position_m, nxt.velocity_m_s
        lines.append(_record_start(sat, tb - _LEAP_SECONDS * 1_000_000_000, clk))
        for axis, extra in ((0, 0.0), (1, channel), (2, 0.0)):
            vals = (pos[axis] * km, vel[axis] * km, 0.0, extra)
            lines.append("    " + "".join(_d19(x) for x in vals) + "\n")
    return lines
