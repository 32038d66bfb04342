"""Single-receiver code positioning from a RINEX observation file by the Rust observation engine's
single-point solver (``rust/core/src/gnss/spp.rs``): at every epoch on its own, weighted least squares on
the pseudoranges of the chosen systems with broadcast orbits, clocks and group delays, the Klobuchar
ionosphere of the navigation header and the standard troposphere; one receiver clock per system.

Python reads the files and picks each system's code per frequency slot (:mod:`gnssatt.rinex.signals`);
the engine solves every epoch in one GIL-released call, epochs in parallel. Each satellite contributes the
code of its lowest frequency slot among those used (``frequencies``).
"""

from __future__ import annotations

import csv
import warnings
from collections.abc import Sequence
from dataclasses import dataclass
from os import PathLike
from typing import TYPE_CHECKING, Any, Literal

import numpy as np
from numpy.typing import NDArray

from gnssatt._arrays import instance, integer, path_text, scalar
from gnssatt.errors import InvalidInputError, InvalidTypeError
from gnssatt.gnss._attitude_series import nan_median
from gnssatt.gnss.session_input import epochs_gpst_ns
from gnssatt.rinex.nav import GPS_EPOCH, RinexNav, nav_input, navigation
from gnssatt.rinex.obs import RinexObs, read_obs
from gnssatt.rinex.signals import choose_signals

if TYPE_CHECKING:  # a type only: the core itself is imported where it is called, as before
    from gnssatt._core import SinglePoints

__all__ = ["SYSTEMS", "PositionSeries", "position_from_rinex"]

#: System letters in the engine's order (columns ``sats_G`` ... and of ``satellites_per_system``).
SYSTEMS = "GRECJ"
#: Frequency slots of the engine per system.
_SLOTS = 3
#: ``glonass_channel`` of a satellite that is not GLONASS or whose channel is unknown.
_NO_CHANNEL = 99


@dataclass(frozen=True)
class PositionSeries:
    """Per-epoch results of :func:`position_from_rinex`; :meth:`columns` gives the CSV columns in order.

    Attributes
    ----------
    time
        (n,) GPST epoch labels, ``datetime64[ns]``.
    position_ecef_m
        (n, 3) ECEF (WGS-84) position, m; NaN rows where the epoch has no solution.
    lat_deg, lon_deg, height_m
        (n,) geodetic WGS-84 latitude and longitude (degrees) and ellipsoidal height (m) of it.
    satellites
        (n,) satellites used (0 where no solution).
    pdop
        (n,) position dilution of precision of the satellites used (NaN where no solution).
    satellites_per_system
        (n, 5) satellites used per system, order :data:`SYSTEMS`.
    residual_rms_m
        (n,) RMS of the code residuals, m.
    systems
        The system letters asked for.
    path
        The observation file.
    marker_name
        Its ``MARKER NAME`` (may be empty).
    header_position_m
        (3,) its ``APPROX POSITION XYZ``, ECEF m; NaN where the header gives none.
    warnings
        What the engine or the reader said a user should know (also issued as warnings).
    """

    time: NDArray[np.datetime64]
    position_ecef_m: NDArray[np.float64]
    lat_deg: NDArray[np.float64]
    lon_deg: NDArray[np.float64]
    height_m: NDArray[np.float64]
    satellites: NDArray[np.int64]
    pdop: NDArray[np.float64]
    satellites_per_system: NDArray[np.int64]
    residual_rms_m: NDArray[np.float64]
    systems: str
    path: str
    marker_name: str
    header_position_m: NDArray[np.float64]
    warnings: tuple[str, ...] = ()

    @property
    def solved(self) -> NDArray[np.bool_]:
        """(n,) epochs with a solution."""
        return np.asarray(self.satellites > 0)

    @property
    def median_position_m(self) -> NDArray[np.float64]:
        """(3,) per-axis median of the ECEF positions solved, m (NaN when none is)."""
        ok = self.solved
        if not ok.any():
            return np.full(3, np.nan)
        solved = self.position_ecef_m[ok]  # np.median would load numpy.ma (nan_median says why)
        return np.array([nan_median(solved[:, axis]) for axis in range(3)], dtype=np.float64)

    def enu_about_median_m(self) -> NDArray[np.float64]:
        """(n, 3) East, North, Up of each position about :attr:`median_position_m`, m (NaN rows unsolved)."""
        from gnssatt.frames import dcm_ecef_from_enu, ecef_to_geodetic

        med = self.median_position_m
        if not np.isfinite(med).all():
            return np.full((len(self.time), 3), np.nan)
        lat, lon, _ = ecef_to_geodetic(med)
        rot = dcm_ecef_from_enu(float(lat), float(lon))
        return np.asarray((self.position_ecef_m - med) @ rot, dtype=np.float64)

    def columns(self) -> dict[str, NDArray[np.generic]]:
        """Column name -> array, in the CSV order: ``time_gpst, x_m, y_m, z_m, lat_deg, lon_deg, height_m,
        satellites, pdop, sats_<system>`` (one per system asked for)."""
        out: dict[str, NDArray[np.generic]] = {"time_gpst": np.datetime_as_string(self.time, unit="ms")}
        for j, axis in enumerate("xyz"):
            out[f"{axis}_m"] = self.position_ecef_m[:, j]
        out["lat_deg"] = self.lat_deg
        out["lon_deg"] = self.lon_deg
        out["height_m"] = self.height_m
        out["satellites"] = self.satellites
        out["pdop"] = self.pdop
        for s, letter in enumerate(SYSTEMS):
            if letter in self.systems:
                out[f"sats_{letter}"] = self.satellites_per_system[:, s]
        return out

    def to_csv(self, path: str | PathLike[str]) -> None:
        """Write the CSV: a header line, one row per epoch (ECEF and height to 0.1 mm, angles to 1e-9 deg,
        PDOP to 0.001; ``nan`` where an epoch has no solution)."""
        cols = self.columns()
        formats = {name: _format(name) for name in cols}
        with open(path, "w", newline="") as fh:
            w = csv.writer(fh)
            w.writerow(list(cols))
            for i in range(len(self.time)):
                w.writerow([formats[name](v[i]) for name, v in cols.items()])

    def summary(self) -> str:
        """One line: epochs solved, the median position (ECEF and geodetic), the standard deviation of the
        positions about it in East, North and Up, and its distance from the header position."""
        from gnssatt.frames import ecef_to_geodetic

        ok = self.solved
        head = f"{self.path}: {int(ok.sum())} of {len(ok)} epochs solved"
        if not ok.any():
            return head
        med = self.median_position_m
        lat, lon, h = (float(v) for v in ecef_to_geodetic(med))
        spread = np.std(self.enu_about_median_m()[ok], axis=0)
        text = (
            f"{head}; median position X {med[0]:.3f} Y {med[1]:.3f} Z {med[2]:.3f} m (lat {lat:.8f} deg, "
            f"lon {lon:.8f} deg, height {h:.3f} m); spread (std) east {spread[0]:.2f} m, north "
            f"{spread[1]:.2f} m, up {spread[2]:.2f} m"
        )
        if np.isfinite(self.header_position_m).all():
            text += f"; {float(np.linalg.norm(med - self.header_position_m)):.2f} m from the header position"
        return text


def _format(name: str) -> Any:
    if name.endswith("_deg"):
        return lambda x: f"{x:.9f}"
    if name.endswith("_m"):
        return lambda x: f"{x:.4f}"
    if name == "pdop":
        return lambda x: f"{x:.3f}"
    return str


def _systems(value: object) -> str:
    if not isinstance(value, str):
        raise InvalidTypeError(f"expected systems as system letters such as 'GE', got {type(value).__name__}")
    if not value or any(ch not in SYSTEMS for ch in value) or len(set(value)) != len(value):
        raise InvalidInputError(f"expected systems as distinct letters of {SYSTEMS!r}, got {value!r}")
    return "".join(ch for ch in SYSTEMS if ch in value)


def _frequencies(value: object) -> int:
    if isinstance(value, str):
        if value != "all":
            raise InvalidInputError(f"expected frequencies 1..{_SLOTS} or 'all', got {value!r}")
        return _SLOTS
    return integer("frequencies", value, minimum=1, maximum=_SLOTS)


def position_from_rinex(
    obs: RinexObs | str | PathLike[str],
    nav: RinexNav | str | PathLike[str] | Sequence[str | PathLike[str]],
    *,
    systems: str = SYSTEMS,
    frequencies: int | Literal["all"] = 1,
    elevation_mask_deg: float = 10.0,
) -> PositionSeries:
    """Code position of one receiver at every epoch of an observation file.

    Parameters
    ----------
    obs
        An observation file or a read :class:`~gnssatt.rinex.obs.RinexObs`.
    nav
        Navigation file(s) or a read :class:`~gnssatt.rinex.nav.RinexNav`.
    systems
        Satellite systems, distinct letters of ``"GRECJ"`` (default all; systems the file lacks give no
        satellites).
    frequencies
        Frequency slots a satellite's code may come from, 1..3 or ``"all"`` (3): slot 1 L1/G1/E1/B1I, 2
        L2/G2/E5b/B2I, 3 L5/G3/E5a/B3I; each satellite uses its lowest slot with a code (default 1, the
        first frequency only, as RTKLIB's single mode).
    elevation_mask_deg
        Satellites below this elevation are not used, degrees, in [-90, 90] (default 10).

    Returns
    -------
    PositionSeries
        One row per epoch of the file; NaN and 0 satellites where an epoch has too few satellites.

    Warns
    -----
    GnssattWarning
        Navigation records the engine cannot use (skipped and named).

    Raises
    ------
    RinexError
        An unreadable file; an unknown time system.
    InvalidTypeError
        ``obs`` not a file or :class:`RinexObs`, ``nav`` not a :class:`RinexNav`, file or list of files, an
        option of the wrong kind.
    InvalidInputError
        ``systems`` not distinct letters of ``"GRECJ"``, ``frequencies`` outside 1..3, an elevation mask
        outside [-90, 90], no navigation file.

    Examples
    --------
    The GEONET station 0759 (GPS L1, 2005) shipped with gnssatt: its 120 epochs solve within a metre of the
    header position.

    >>> import numpy as np
    >>> from gnssatt.data import geonet_dir
    >>> from gnssatt.gnss.position import position_from_rinex
    >>> p = position_from_rinex(geonet_dir() / "07590920.05o", geonet_dir() / "07590920.05n")
    >>> int(p.solved.sum()), bool(np.linalg.norm(p.median_position_m - p.header_position_m) < 1.0)
    (120, True)
    """
    letters = _systems(systems)
    n_freq = _frequencies(frequencies)
    mask = scalar("elevation_mask_deg", elevation_mask_deg, minimum=-90.0, maximum=90.0)
    if not isinstance(obs, RinexObs):
        obs = read_obs(path_text(obs, "obs"))
    obs = instance("obs", obs, RinexObs, "an observation file or a RinexObs (from read_obs)")
    nv = navigation(nav, "nav")
    t = epochs_gpst_ns(obs, obs.leap_seconds if obs.leap_seconds is not None else nv.leap_seconds)
    sats, code = _code_ranges(obs, letters, n_freq, len(t))
    header = np.asarray(obs.approx_position_m, dtype=np.float64)
    header = header if np.any(header != 0.0) and np.isfinite(header).all() else np.full(3, np.nan)
    channel = _glonass_channels(nv, obs, sats)
    sp, messages = _single_point(nv, t, sats, channel, code, header, letters, n_freq, mask)
    return _position_series(t, sp, letters, obs, header, messages)


def _position_series(
    t: NDArray[np.int64], sp: SinglePoints, letters: str, obs: RinexObs, header: NDArray[np.float64],
    messages: tuple[str, ...],
) -> PositionSeries:  # fmt: skip
    """The :class:`PositionSeries` of the core's solutions ``sp`` at the epochs ``t`` (GPST ns), with their
    geodetic coordinates (NaN where unsolved)."""
    from gnssatt.frames import ecef_to_geodetic

    pos = np.asarray(sp.position_m, dtype=np.float64)
    # unsolved rows are converted at a point of the equator, then set to NaN
    lat, lon, h = ecef_to_geodetic(np.where(np.isfinite(pos), pos, [6378137.0, 0.0, 0.0]).reshape(-1, 3))
    bad = ~np.isfinite(pos).all(axis=1)
    lat, lon, h = (np.where(bad, np.nan, np.asarray(v, dtype=np.float64).reshape(-1)) for v in (lat, lon, h))
    return PositionSeries(
        time=GPS_EPOCH + t.astype("timedelta64[ns]"),
        position_ecef_m=pos,
        lat_deg=lat,
        lon_deg=lon,
        height_m=h,
        satellites=np.asarray(sp.satellites, dtype=np.int64),
        pdop=np.asarray(sp.pdop, dtype=np.float64),
        satellites_per_system=np.asarray(sp.satellites_per_system, dtype=np.int64),
        residual_rms_m=np.asarray(sp.residual_rms_m, dtype=np.float64),
        systems=letters,
        path=obs.path,
        marker_name=obs.marker_name,
        header_position_m=header,
        warnings=messages,
    )


def _code_ranges(
    obs: RinexObs, letters: str, n_freq: int, n_epochs: int
) -> tuple[list[str], NDArray[np.float64]]:
    """The satellites of ``letters`` and their code ranges (epochs, satellites, slots), m: each system's
    chosen signals (:func:`~gnssatt.rinex.signals.choose_signals`) in its first ``n_freq`` slots."""
    keep = [k for k, s in enumerate(obs.sats) if s[0] in letters]
    sats = [obs.sats[k] for k in keep]
    code = np.full((n_epochs, len(sats), _SLOTS), np.nan)
    for letter in letters:
        choices = choose_signals(obs, letter)
        cols = [j for j, s in enumerate(sats) if s[0] == letter]
        for slot, choice in enumerate(choices[:n_freq]):
            if choice.code is not None and cols:
                c = obs.codes.index(choice.code)
                code[:, cols, slot] = obs.data[:, [keep[j] for j in cols], c]
    return sats, code


def _glonass_channels(nv: RinexNav, obs: RinexObs, sats: list[str]) -> NDArray[np.int64]:
    """The GLONASS channel of each satellite (``_NO_CHANNEL`` for the others and where none is known): the
    observation header's, else the navigation records'."""
    known = {s: int(k) for s, k in zip(nv.glonass.sats.tolist(), nv.glonass.channel.tolist(), strict=True)}
    known.update(obs.glonass_channels)
    return np.array(
        [known[s] if s[0] == "R" and s in known and -7 <= known[s] <= 6 else _NO_CHANNEL for s in sats],
        dtype=np.int64,
    )


def _single_point(
    nv: RinexNav, t: NDArray[np.int64], sats: list[str], channel: NDArray[np.int64],
    code: NDArray[np.float64], header: NDArray[np.float64], letters: str, n_freq: int, mask: float,
) -> tuple[SinglePoints, tuple[str, ...]]:  # fmt: skip
    """The core's code solutions of every epoch, and the warnings it issued (issued again, from the line
    that called :func:`position_from_rinex`)."""
    from gnssatt import _core

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        sp = _core.gnss_single_point(
            nav_input(nv).navigation(),
            np.ascontiguousarray(t),
            sats,
            channel,
            code,
            approx_position_m=header if np.isfinite(header).all() else None,
            systems=letters,
            frequencies=n_freq,
            elevation_mask_deg=mask,
        )
    messages = tuple(str(w.message) for w in caught)
    for w in caught:  # issued again, from the caller's line, and kept in the result
        warnings.warn(str(w.message), w.category, stacklevel=3)
    return sp, messages
