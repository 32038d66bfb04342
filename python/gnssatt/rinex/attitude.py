"""Attitude and baseline-direction time series from recorded RINEX data of antennas on one platform.

Two antennas and no baselines: baseline-direction mode, the azimuth (clockwise from North) and elevation
of the vector from the first antenna to the second. Three or more antennas with body-frame baselines:
attitude mode, heading / pitch / roll of :func:`gnssatt.ml_attitude` (eq. (5) of seed 001, compass
heading ``= -psi``).

Methods (the ``method`` column says which produced each row):

- ``"ml"``: the ambiguity-function grid (:func:`gnssatt.ml_baseline` / :func:`gnssatt.ml_attitude`) on the
  wrapped single differences of each epoch, at one common instant (receiver clocks from the pseudoranges),
  optionally windowed around the previous epoch's solution (``window_deg``); meant for metre-scale arrays
  (the grid step is ``lambda / (10 L)``), not for kilometre baselines. ``fixed`` is always 0.
- ``"lambda"``: LAMBDA-fixed double differences. Baseline-direction mode, ``motion="static"``: the
  ambiguities of the whole session fixed once (:func:`~gnssatt.rinex.baseline.static_baseline`), each
  epoch's baseline from them; ``motion="moving"``: every epoch fixed on its own, or with the integers held
  along slip-free arcs (``continuity``). Attitude mode: every epoch's baselines fixed with the array
  geometry as constraint, then Wahba's problem (:func:`gnssatt.wahba`, weights the squared baseline
  lengths) gives the attitude (:func:`~gnssatt.rinex.epoch_lambda.epoch_lambda`). ``fixed`` is 1 where the
  integers passed validation; otherwise the float baselines are reported.
- ``"auto"``: ``"lambda"`` for baselines beyond 100 m (baseline-direction mode), else ``"ml"``.
"""

from __future__ import annotations

import csv
from collections.abc import Sequence
from dataclasses import dataclass
from os import PathLike
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.spatial.transform import Rotation

from gnssatt._arrays import choice, flag, scalar, shaped
from gnssatt.errors import InvalidInputError, InvalidTypeError
from gnssatt.likelihood import euler_from_rotation, ml_attitude, ml_baseline
from gnssatt.rinex._fields import path_text
from gnssatt.rinex.align import Aligned, align_receivers
from gnssatt.rinex.baseline import epoch_baselines, static_baseline
from gnssatt.rinex.epoch_lambda import epoch_lambda
from gnssatt.rinex.nav import RinexNav, read_nav
from gnssatt.rinex.obs import RinexObs, read_obs

__all__ = ["AttitudeSeries", "attitude_from_rinex"]

MethodName = Literal["auto", "ml", "lambda"]
MotionName = Literal["static", "moving"]


@dataclass(frozen=True)
class AttitudeSeries:
    """Per-epoch results; :meth:`columns` gives the CSV columns in order.

    Attributes
    ----------
    time
        (n,) GPST epoch labels of the reference receiver, ``datetime64[ns]``.
    mode
        ``"baseline"`` or ``"attitude"``.
    angles_deg
        (n, 2) azimuth, elevation (baseline mode) or (n, 3) heading, pitch, roll (attitude mode), degrees;
        NaN where the epoch was not solved.
    method
        (n,) ``"ml"`` or ``"lambda"``.
    fixed
        (n,) 1 where integer ambiguities were fixed and accepted, else 0.
    satellites
        (n,) satellites used.
    baseline_length_m
        Length used by the grid in baseline mode (from the double-difference solution), m.
    """

    time: NDArray[np.datetime64]
    mode: str
    angles_deg: NDArray[np.float64]
    method: NDArray[np.str_]
    fixed: NDArray[np.int64]
    satellites: NDArray[np.int64]
    baseline_length_m: float = float("nan")

    @property
    def angle_names(self) -> tuple[str, ...]:
        if self.mode == "baseline":
            return ("azimuth_deg", "elevation_deg")
        return ("heading_deg", "pitch_deg", "roll_deg")

    @property
    def solved(self) -> NDArray[np.bool_]:
        return np.all(np.isfinite(self.angles_deg), axis=1)

    def columns(self) -> dict[str, NDArray[np.generic]]:
        """Column name -> array, in the CSV order."""
        iso = np.datetime_as_string(self.time, unit="ms")
        out: dict[str, NDArray[np.generic]] = {"time_gpst": iso}
        for j, name in enumerate(self.angle_names):
            out[name] = self.angles_deg[:, j]
        out["method"] = self.method
        out["fixed"] = self.fixed
        out["satellites"] = self.satellites
        return out

    def to_csv(self, path: str | PathLike[str]) -> None:
        """Write the CSV (``time_gpst`` ISO 8601, angles, ``method``, ``fixed``, ``satellites``)."""
        cols = self.columns()
        with open(path, "w", newline="") as fh:
            w = csv.writer(fh)
            w.writerow(list(cols))
            for i in range(len(self.time)):
                row = []
                for name, v in cols.items():
                    x = v[i]
                    row.append(f"{x:.6f}" if name.endswith("_deg") else str(x))
                w.writerow(row)

    def summary(self) -> str:
        """Epochs solved, fix rate, mean and standard deviation of each angle."""
        ok = self.solved
        lines = [f"epochs solved: {int(ok.sum())} of {len(ok)}", f"fix rate: {float(self.fixed.mean()):.3f}"]
        for j, name in enumerate(self.angle_names):
            v = self.angles_deg[ok, j]
            if name in ("azimuth_deg", "heading_deg") and v.size:
                c = np.degrees(np.angle(np.mean(np.exp(1j * np.radians(v)))))
                spread = np.degrees(np.std(np.angle(np.exp(1j * np.radians(v - c)))))
                mean = c % 360.0
            else:
                mean, spread = (float(np.mean(v)), float(np.std(v))) if v.size else (np.nan, np.nan)
            lines.append(f"{name}: mean {mean:.4f}, std {spread:.4f}")
        return "\n".join(lines)


#: Largest search window, grid step (degrees) and baseline length (m) accepted.
MAX_WINDOW_DEG = 3600.0
MAX_STEP_DEG = 180.0
MAX_BASELINE_LENGTH_M = 1e5


def _as_obs(x: RinexObs | str | PathLike[str]) -> RinexObs:
    return x if isinstance(x, RinexObs) else read_obs(x)


def _obs_list(name: str, value: object) -> list[RinexObs | str | PathLike[str]]:
    if isinstance(value, str | PathLike | RinexObs) or not isinstance(value, list | tuple):
        raise InvalidTypeError(
            f"expected {name} as a list of observation files or RinexObs, got {type(value).__name__}"
        )
    for i, o in enumerate(value):
        if not isinstance(o, RinexObs):
            path_text(o, f"{name}[{i}]")
    if len(value) < 2:
        raise InvalidInputError(f"expected two or more {name} (antennas), got {len(value)}")
    return list(value)


def _as_nav(x: RinexNav | str | PathLike[str] | Sequence[str | PathLike[str]]) -> RinexNav:
    if isinstance(x, RinexNav):
        return x
    if isinstance(x, str | PathLike):
        return read_nav(path_text(x, "nav"))
    if not isinstance(x, list | tuple):
        raise InvalidTypeError(
            f"expected nav as a RinexNav, a navigation file or a list of them, got {type(x).__name__}"
        )
    if not x:
        raise InvalidInputError("expected at least one navigation file in nav, got none")
    navs = [read_nav(path_text(p, f"nav[{i}]")) for i, p in enumerate(x)]
    out = navs[0]
    for n in navs[1:]:
        out = out + n
    return out


def attitude_from_rinex(
    observations: Sequence[RinexObs | str | PathLike[str]],
    nav: RinexNav | str | PathLike[str] | Sequence[str | PathLike[str]],
    baselines: ArrayLike | None = None,
    *,
    method: MethodName = "auto",
    motion: MotionName = "static",
    continuity: bool = False,
    window_deg: float | None = None,
    systems: str = "G",
    elevation_mask_deg: float = 10.0,
    step_deg: float | None = None,
    ratio_threshold: float = 3.0,
    baseline_length_m: float | None = None,
) -> AttitudeSeries:
    """Attitude (with ``baselines``) or baseline direction (two antennas, none) at every common epoch.

    Parameters
    ----------
    observations
        Observation files (or read :class:`RinexObs`), one per antenna, the reference antenna first.
    nav
        Navigation file(s) or a read :class:`RinexNav`.
    baselines
        (n_ant - 1, 3) antenna positions relative to the first, body frame of seed 001 (X nose, Y up,
        Z right wing), m; required with three or more antennas.
    method
        ``"auto"``, ``"ml"`` or ``"lambda"`` (module docstring).
    motion
        ``"static"``: in baseline-direction mode the LAMBDA ambiguities of the whole session are fixed
        once (a static pair); ``"moving"``: every epoch is fixed on its own
        (:func:`~gnssatt.rinex.epoch_lambda.epoch_lambda`). Attitude mode always fixes epoch by epoch.
    continuity
        Per-epoch LAMBDA: hold fixed integers along slip-free arcs instead of fixing every epoch afresh.
    window_deg
        ML grid: search only +/- this many degrees around the previous epoch's solution in every angle
        (the whole domain where the previous epoch is unsolved); None searches the whole domain each epoch.
    systems
        Satellite systems: one carrier frequency per system pair is assumed by the grid (CDMA), default GPS.
    elevation_mask_deg, step_deg
        Elevation mask at the reference antenna; grid step (default: eq. (15)).
    ratio_threshold
        Acceptance threshold of the LAMBDA validation.
    baseline_length_m
        Baseline length for the ML grid in baseline-direction mode; default: from the static LAMBDA
        solution (``motion="static"``) or the median length of the per-epoch fixed baselines.

    Raises
    ------
    RinexError
        Unreadable files, no common epochs or satellites.
    InvalidTypeError
        ``observations`` not a list of files or :class:`RinexObs`, ``nav`` not a :class:`RinexNav`, file
        or list of files, another argument of the wrong kind.
    InvalidInputError
        Fewer than two observations, baselines of the wrong shape or not finite, unknown method or motion,
        ``window_deg``, ``step_deg`` or ``baseline_length_m`` not positive or above ``MAX_WINDOW_DEG``,
        ``MAX_STEP_DEG``, ``MAX_BASELINE_LENGTH_M``, ``ratio_threshold`` below 1; ``systems`` and
        ``elevation_mask_deg`` as :func:`~gnssatt.rinex.align_receivers`.
    """
    method = choice("method", method, ("auto", "ml", "lambda"))
    motion = choice("motion", motion, ("static", "moving"))
    continuity = flag("continuity", continuity)
    if window_deg is not None:
        window_deg = scalar("window_deg", window_deg, minimum=0.0, maximum=MAX_WINDOW_DEG, strict=True)
    if step_deg is not None:
        step_deg = scalar("step_deg", step_deg, minimum=0.0, maximum=MAX_STEP_DEG, strict=True)
    ratio_threshold = scalar("ratio_threshold", ratio_threshold, minimum=1.0)
    if baseline_length_m is not None:
        baseline_length_m = scalar(
            "baseline_length_m", baseline_length_m, minimum=0.0, maximum=MAX_BASELINE_LENGTH_M, strict=True
        )
    observations = _obs_list("observations", observations)
    if baselines is not None:
        shaped("baselines", baselines, "(n_ant - 1, 3)", (len(observations) - 1, 3))
    if not isinstance(systems, str):
        raise InvalidTypeError(
            f"expected systems as system letters such as 'G', got {type(systems).__name__}"
        )
    if not systems or any(ch not in "GREJC" for ch in systems):
        raise InvalidInputError(f"expected systems as letters among 'GREJC', got {systems!r}")
    elevation_mask_deg = scalar("elevation_mask_deg", elevation_mask_deg, minimum=-90.0, maximum=90.0)
    obs = [_as_obs(o) for o in observations]
    nv = _as_nav(nav)
    b = None
    if baselines is not None:
        b = np.asarray(baselines, dtype=np.float64)
        if b.ndim != 2 or b.shape != (len(obs) - 1, 3):
            raise InvalidInputError(f"expected baselines of shape ({len(obs) - 1}, 3), got {b.shape}")
        if b.shape[0] < 2:
            raise InvalidInputError(
                "attitude mode needs three or more antennas; for two, omit the baselines (baseline mode)"
            )
    elif len(obs) != 2:
        raise InvalidInputError(f"expected baselines (m, 3) for {len(obs)} antennas, got none")
    al = align_receivers(obs, nv, systems=systems, elevation_mask_deg=elevation_mask_deg)
    if b is None:
        return _baseline_mode(
            al, method, motion, continuity, window_deg, step_deg, ratio_threshold, baseline_length_m
        )
    return _attitude_mode(al, b, method, continuity, window_deg, step_deg, ratio_threshold)


def _enu_angles(enu: NDArray[np.float64]) -> NDArray[np.float64]:
    e, n, u = enu.T
    return np.stack([np.degrees(np.arctan2(e, n)) % 360.0, np.degrees(np.arctan2(u, np.hypot(e, n)))], axis=1)


def _baseline_mode(
    al: Aligned,
    method: MethodName,
    motion: MotionName,
    continuity: bool,
    window_deg: float | None,
    step_deg: float | None,
    ratio_threshold: float,
    baseline_length_m: float | None,
) -> AttitudeSeries:
    n_ep = len(al.time)
    usable = al.usable
    nsat = usable.sum(axis=1).astype(np.int64)
    dd = None
    eb = None
    if motion == "static":
        dd = static_baseline(al, ratio_threshold=ratio_threshold)
        length = float(np.linalg.norm(dd.baseline_ecef_m))
    else:
        eb = epoch_lambda(al, None, continuity=continuity, ratio_threshold=ratio_threshold)
        lengths = np.linalg.norm(eb.baselines_enu_m[eb.fixed, 0], axis=1)
        length = float(np.median(lengths)) if lengths.size else float("nan")
    if baseline_length_m is not None:
        length = float(baseline_length_m)
    chosen = method if method != "auto" else ("lambda" if not (length <= 100.0) else "ml")
    angles = np.full((n_ep, 2), np.nan)
    if chosen == "lambda":
        if dd is not None:
            series = epoch_baselines(al, dd)
            angles = _enu_angles(series.baseline_enu_m)
            nsat = series.satellites
            fixed = np.full(n_ep, int(dd.fixed))
        else:
            assert eb is not None
            angles = _enu_angles(eb.baselines_enu_m[:, 0])
            nsat = eb.satellites
            fixed = eb.fixed.astype(np.int64)
        return AttitudeSeries(al.time, "baseline", angles, np.full(n_ep, "lambda"), fixed, nsat, length)
    if not (np.isfinite(length) and length > 0):
        raise InvalidInputError(
            "no baseline length for the ML grid: no epoch was fixed; give baseline_length_m"
        )
    sd = al.single_differences_rad()
    prev: NDArray[np.float64] | None = None
    for k in range(n_ep):
        m = usable[k]
        if m.sum() < 3:
            prev = None
            continue
        win = None
        if window_deg is not None and prev is not None:
            win = [
                [-prev[0] - window_deg, -prev[0] + window_deg],
                [prev[1] - window_deg, prev[1] + window_deg],
            ]
        r = ml_baseline(
            sd[0, k, m], al.los_enu[k, m], length, al.wavelength_m[m], step_deg=step_deg, window_deg=win
        )
        angles[k] = [r.heading_deg, r.elevation_deg]
        prev = angles[k]
    fixed = np.zeros(n_ep, dtype=np.int64)
    return AttitudeSeries(al.time, "baseline", angles, np.full(n_ep, "ml"), fixed, nsat, length)


def _attitude_mode(
    al: Aligned,
    b: NDArray[np.float64],
    method: MethodName,
    continuity: bool,
    window_deg: float | None,
    step_deg: float | None,
    ratio_threshold: float,
) -> AttitudeSeries:
    n_ep = len(al.time)
    usable = al.usable
    angles = np.full((n_ep, 3), np.nan)
    if method == "lambda":
        eb = epoch_lambda(al, b, continuity=continuity, ratio_threshold=ratio_threshold)
        assert eb.rotation_enu_from_body is not None
        for k in range(n_ep):
            if np.all(np.isfinite(eb.rotation_enu_from_body[k])):
                psi, theta, phi = euler_from_rotation(Rotation.from_matrix(eb.rotation_enu_from_body[k]))
                angles[k] = [(-psi) % 360.0, theta, phi]
        return AttitudeSeries(
            al.time, "attitude", angles, np.full(n_ep, "lambda"), eb.fixed.astype(np.int64), eb.satellites
        )
    sd = al.single_differences_rad()
    prev: NDArray[np.float64] | None = None
    for k in range(n_ep):
        m = usable[k]
        if m.sum() < 3:
            prev = None
            continue
        win = None
        if window_deg is not None and prev is not None:
            win = np.stack([prev - window_deg, prev + window_deg], axis=1)
        r = ml_attitude(
            sd[:, k, m], al.los_enu[k, m], b, al.wavelength_m[m], step_deg=step_deg, window_deg=win
        )
        psi, theta, phi = r.euler_deg
        angles[k] = [(-psi) % 360.0, theta, phi]
        prev = r.euler_deg
    return AttitudeSeries(
        al.time,
        "attitude",
        angles,
        np.full(n_ep, "ml"),
        np.zeros(n_ep, dtype=np.int64),
        usable.sum(axis=1).astype(np.int64),
    )
