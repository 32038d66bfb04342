"""Writing RINEX 3.04 observation and GPS navigation files, so that simulated scenarios run through the
whole recorded-data path with a known truth.

:func:`write_nav_from_constellation` turns the simulator's two-body orbits into broadcast records that
reproduce them exactly: with the scenario epoch ``T0`` (GPST label of ``t = 0``, ``theta0 = 0``) and
``toe`` at ``T0``, ``OMEGA0 = RAAN + omega_E sow(T0)``, ``M0`` the mean anomaly at ``t = 0``,
``delta_n = n_sim - sqrt(mu_GPS / a^3)``, every harmonic correction and clock term zero.
"""

from __future__ import annotations

import re
from collections.abc import Mapping, Sequence
from os import PathLike

import numpy as np
from numpy.typing import ArrayLike, NDArray

from gnssatt._arrays import instance, shaped
from gnssatt.errors import InvalidInputError, InvalidTypeError
from gnssatt.rinex._fields import output_path, sat_list, time_labels
from gnssatt.rinex.nav import gps_ns
from gnssatt.sim.constellation import Constellation

__all__ = ["write_nav_from_constellation", "write_obs"]

_MU_GPS = 3.986005e14
_OMEGA_E = 7.2921151467e-5
_WEEK_NS = 604_800 * 1_000_000_000
_CODE = re.compile(r"[CLDS][1-9][A-Z]")
#: Largest magnitude a 14.3f observation field holds; largest coordinate of APPROX POSITION XYZ (14.4f).
MAX_OBSERVATION = 9.999e9
MAX_POSITION_M = 9.999e8


def _hdr(text: str, label: str) -> str:
    return f"{text:<60.60}{label:<20}\n"


def _parts(t: np.datetime64) -> tuple[int, int, int, int, int, float]:
    s = str(np.datetime64(t, "ns"))
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
        dB-Hz); NaN leaves a field blank, a satellite with every field blank is left out of the epoch. Each
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
    """
    path = output_path("path", path)
    t = time_labels("time", time)
    if t.ndim != 1 or t.size == 0:
        raise InvalidInputError(f"expected time of shape (n_ep >= 1,), got {t.shape}")
    sats = sat_list("sats", sats)
    n_ep, n_sat = len(t), len(sats)
    observations = _code_arrays("observations", observations, n_ep, n_sat, nonfinite=True)
    codes = list(observations)
    data = np.stack([observations[c] for c in codes], axis=-1)
    if np.any(np.abs(np.where(np.isfinite(data), data, 0.0)) > MAX_OBSERVATION):
        raise InvalidInputError(f"expected |observations| <= {MAX_OBSERVATION} (the 14.3f field)")
    flags = np.zeros(data.shape, dtype=np.int64)
    if lli is not None:
        for c, v in _code_arrays("lli", lli, n_ep, n_sat, nonfinite=False).items():
            if c not in codes:
                raise InvalidInputError(f"expected lli codes among those of observations, got {c!r}")
            if np.any((v != np.round(v)) | (v < 0) | (v > 9)):
                raise InvalidInputError(f"expected lli[{c!r}] as digits 0 to 9")
            flags[..., codes.index(c)] = v.astype(np.int64)
    pos = shaped("approx_position_m", approx_position_m, "(3,)", (3,))
    if np.any(np.abs(pos) > MAX_POSITION_M):
        raise InvalidInputError(f"expected |approx_position_m| <= {MAX_POSITION_M} m, got {pos.tolist()}")
    marker_name = instance("marker_name", marker_name, str, "text")
    if len(marker_name) > 60 or not all(" " <= ch <= "~" for ch in marker_name):
        raise InvalidInputError(
            f"expected marker_name as at most 60 printable ASCII characters, got {marker_name!r}"
        )
    channels = _glonass_channels(glonass_channels)
    systems = sorted({s[0] for s in sats})
    sys_of = np.array([s[0] for s in sats])
    has = np.isfinite(data).any(axis=0)  # (n_sat, n_codes)
    sys_codes = {}
    for sy in systems:
        cols = [j for j in range(len(codes)) if has[sys_of == sy, j].any()]
        sys_codes[sy] = cols or list(range(len(codes)))
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
    y, mo, d, hh, mi, sec = _parts(t[0])
    out.append(_hdr(f"{y:6d}{mo:6d}{d:6d}{hh:6d}{mi:6d}{sec:13.7f}     GPS", "TIME OF FIRST OBS"))
    out.append(_hdr("", "END OF HEADER"))
    for e in range(len(t)):
        present = [k for k in range(len(sats)) if np.any(np.isfinite(data[e, k]))]
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
    with open(path, "w", encoding="ascii") as fh:
        fh.writelines(out)


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


def write_nav_from_constellation(
    path: str | PathLike[str], constellation: Constellation, epoch_gpst: np.datetime64
) -> NDArray[np.int64]:
    """Write a RINEX 3.04 GPS navigation file whose records reproduce the simulator's orbits (module
    docstring); the ECEF frame is the simulator's with ``theta0 = 0`` at ``epoch_gpst``.

    Returns
    -------
    toe_ns
        GPST nanoseconds of the records' time of ephemeris.

    Raises
    ------
    InvalidTypeError
        ``path`` not a path, ``constellation`` not a :class:`~gnssatt.sim.Constellation`, ``epoch_gpst``
        not a datetime64.
    InvalidInputError
        ``path`` empty, a folder or in a missing folder; a constellation other than GPS; ``epoch_gpst``
        not a single label in range.
    """
    path = output_path("path", path)
    constellation = instance("constellation", constellation, Constellation, "a sim.Constellation")
    epoch = time_labels("epoch_gpst", epoch_gpst)
    if epoch.ndim != 0:
        raise InvalidInputError(f"expected epoch_gpst as one datetime64 label, got shape {epoch.shape}")
    epoch_gpst = epoch[()]
    if any(not s.startswith("G") for s in constellation.ids):
        raise InvalidInputError("expected a GPS constellation (ids 'Gnn')")
    t_ns = int(gps_ns(np.array([epoch_gpst]))[0])
    week, sow_ns = divmod(t_ns, _WEEK_NS)
    sow = sow_ns * 1e-9
    o = constellation.orbits
    y, mo, d, hh, mi, sec = _parts(np.datetime64(epoch_gpst, "ns"))
    out = [
        _hdr(f"{'3.04':>9}{'':11}{'N: GNSS NAV DATA':<20}G", "RINEX VERSION / TYPE"),
        _hdr("gnssatt", "PGM / RUN BY / DATE"),
        _hdr("", "END OF HEADER"),
    ]
    for j, sat in enumerate(constellation.ids):
        a = float(o.semi_major_axis_m[j])
        dn = float(o.mean_motion_rad_s[j]) - np.sqrt(_MU_GPS / a**3)
        rows = [
            [0.0, 0.0, dn, float(o.mean_anomaly_rad[j])],
            [0.0, float(o.eccentricity[j]), 0.0, np.sqrt(a)],
            [sow, 0.0, float(o.raan_rad[j]) + _OMEGA_E * sow, 0.0],
            [float(o.inclination_rad[j]), 0.0, float(o.arg_perigee_rad[j]), 0.0],
            [0.0, 0.0, float(week), 0.0],
            [2.0, 0.0, 0.0, 0.0],
            [sow, 4.0],
        ]
        out.append(f"{sat} {y:4d} {mo:02d} {d:02d} {hh:02d} {mi:02d} {int(sec):02d}" + _d19(0.0) * 3 + "\n")
        for r in rows:
            out.append("    " + "".join(_d19(v) for v in r) + "\n")
    with open(path, "w", encoding="ascii") as fh:
        fh.writelines(out)
    return np.full(len(constellation.ids), t_ns, dtype=np.int64)
