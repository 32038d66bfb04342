"""Writing RINEX 3.04 observation and GPS navigation files, so that simulated scenarios run through the
whole recorded-data path with a known truth.

:func:`write_nav_from_constellation` turns the simulator's two-body orbits into broadcast records that
reproduce them exactly: with the scenario epoch ``T0`` (GPST label of ``t = 0``, ``theta0 = 0``) and
``toe`` at ``T0``, ``OMEGA0 = RAAN + omega_E sow(T0)``, ``M0`` the mean anomaly at ``t = 0``,
``delta_n = n_sim - sqrt(mu_GPS / a^3)``, every harmonic correction and clock term zero.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from os import PathLike

import numpy as np
from numpy.typing import ArrayLike, NDArray

from gnssatt.errors import InvalidInputError
from gnssatt.rinex.nav import gps_ns
from gnssatt.sim.constellation import Constellation

__all__ = ["write_nav_from_constellation", "write_obs"]

_MU_GPS = 3.986005e14
_OMEGA_E = 7.2921151467e-5
_WEEK_NS = 604_800 * 1_000_000_000


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
) -> None:
    """Write a RINEX 3.04 observation file.

    Parameters
    ----------
    path
        Output file.
    time
        (n_ep,) GPST labels, ``datetime64``.
    sats
        (n_sat,) satellite ids; every system present gets the same observation codes.
    observations
        RINEX 3 code (``"C1C"``, ``"L1C"``, ``"D1C"``, ``"S1C"``) -> (n_ep, n_sat) values (m, cycles, Hz,
        dB-Hz); NaN leaves a field blank, a satellite with every field blank is left out of the epoch.
    approx_position_m
        (3,) APPROX POSITION XYZ, ECEF, m.
    marker_name
        MARKER NAME.
    lli
        Code -> (n_ep, n_sat) loss-of-lock digits (0-9), optional.
    """
    t = np.asarray(time, dtype="datetime64[ns]")
    codes = list(observations)
    data = np.stack([np.asarray(observations[c], dtype=np.float64) for c in codes], axis=-1)
    if data.shape[:2] != (len(t), len(sats)):
        raise InvalidInputError(
            f"expected observations of shape ({len(t)}, {len(sats)}), got {data.shape[:2]}"
        )
    flags = np.zeros(data.shape, dtype=np.int64)
    if lli is not None:
        for c, v in lli.items():
            flags[..., codes.index(c)] = np.asarray(v)
    pos = np.asarray(approx_position_m, dtype=np.float64)
    systems = sorted({s[0] for s in sats})
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
    for s in systems:
        out.append(_hdr(f"{s}  {len(codes):3d} " + " ".join(codes), "SYS / # / OBS TYPES"))
    y, mo, d, hh, mi, sec = _parts(t[0])
    out.append(_hdr(f"{y:6d}{mo:6d}{d:6d}{hh:6d}{mi:6d}{sec:13.7f}     GPS", "TIME OF FIRST OBS"))
    out.append(_hdr("", "END OF HEADER"))
    for e in range(len(t)):
        present = [k for k in range(len(sats)) if np.any(np.isfinite(data[e, k]))]
        y, mo, d, hh, mi, sec = _parts(t[e])
        out.append(f"> {y:4d} {mo:02d} {d:02d} {hh:02d} {mi:02d}{sec:11.7f}  0{len(present):3d}\n")
        for k in present:
            fields = []
            for j in range(len(codes)):
                v = data[e, k, j]
                if np.isfinite(v):
                    f = flags[e, k, j]
                    fields.append(f"{v:14.3f}{f if f else ' '} ")
                else:
                    fields.append(" " * 16)
            out.append(sats[k] + "".join(fields).rstrip() + "\n")
    with open(path, "w", encoding="ascii") as fh:
        fh.writelines(out)


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
    """
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
