"""Attitude and baseline-direction time series from recorded RINEX data of antennas on one platform.

Two antennas and no baselines: baseline-direction mode, the azimuth (clockwise from North) and elevation
of the vector from the first antenna to the second. Three or more antennas with body-frame baselines:
attitude mode, heading / pitch / roll of :func:`gnssatt.ml_attitude` (eq. (5) of seed 001, compass
heading ``= -psi``).

Methods: ``"ml"`` runs the ambiguity-function grid (:func:`gnssatt.ml_baseline` / :func:`gnssatt.ml_attitude`)
on the wrapped single differences of each epoch, at one common instant (receiver clocks from the
pseudoranges); it is meant for metre-scale arrays (the grid step is ``lambda / (10 L)``), not for
kilometre baselines. ``"lambda"`` (baseline-direction mode) fixes the double-difference ambiguities of the
whole static session with LAMBDA and reports each epoch's fixed baseline. ``"auto"``: ``"lambda"`` beyond
100 m, else ``"ml"``.
"""

from __future__ import annotations

import csv
from collections.abc import Sequence
from dataclasses import dataclass
from os import PathLike
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from gnssatt.errors import InvalidInputError
from gnssatt.likelihood import ml_attitude, ml_baseline
from gnssatt.rinex.align import align_receivers
from gnssatt.rinex.baseline import epoch_baselines, static_baseline
from gnssatt.rinex.nav import RinexNav, read_nav
from gnssatt.rinex.obs import RinexObs, read_obs

__all__ = ["AttitudeSeries", "attitude_from_rinex"]

MethodName = Literal["auto", "ml", "lambda"]


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


def _as_obs(x: RinexObs | str | PathLike[str]) -> RinexObs:
    return x if isinstance(x, RinexObs) else read_obs(x)


def _as_nav(x: RinexNav | str | PathLike[str] | Sequence[str | PathLike[str]]) -> RinexNav:
    if isinstance(x, RinexNav):
        return x
    if isinstance(x, str | PathLike):
        return read_nav(x)
    navs = [read_nav(p) for p in x]
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
    systems: str = "G",
    elevation_mask_deg: float = 10.0,
    step_deg: float | None = None,
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
    systems
        Satellite systems: one carrier frequency per system pair is assumed by the grid (CDMA), default GPS.
    elevation_mask_deg, step_deg
        Elevation mask at the reference antenna; grid step (default: eq. (15)).

    Raises
    ------
    RinexError
        Unreadable files, no common epochs or satellites.
    InvalidInputError
        Baselines of the wrong shape; ``"lambda"`` asked in attitude mode (not implemented).
    """
    obs = [_as_obs(o) for o in observations]
    nv = _as_nav(nav)
    al = align_receivers(obs, nv, systems=systems, elevation_mask_deg=elevation_mask_deg)
    n_ep = len(al.time)
    usable = al.usable
    sd = al.single_differences_rad()
    if baselines is None:
        if len(obs) != 2:
            raise InvalidInputError(f"expected baselines (m, 3) for {len(obs)} antennas, got none")
        dd = static_baseline(al)
        length = float(np.linalg.norm(dd.baseline_ecef_m))
        chosen = method if method != "auto" else ("lambda" if length > 100.0 else "ml")
        angles = np.full((n_ep, 2), np.nan)
        nsat = usable.sum(axis=1).astype(np.int64)
        if chosen == "lambda":
            eb = epoch_baselines(al, dd)
            e, n, u = eb.baseline_enu_m.T
            angles[:, 0] = np.degrees(np.arctan2(e, n)) % 360.0
            angles[:, 1] = np.degrees(np.arctan2(u, np.hypot(e, n)))
            nsat = eb.satellites
            fixed = np.full(n_ep, int(dd.fixed))
        else:
            for k in range(n_ep):
                m = usable[k]
                if m.sum() < 3:
                    continue
                r = ml_baseline(sd[0, k, m], al.los_enu[k, m], length, al.wavelength_m[m], step_deg=step_deg)
                angles[k] = [r.heading_deg, r.elevation_deg]
            fixed = np.zeros(n_ep, dtype=np.int64)
        return AttitudeSeries(al.time, "baseline", angles, np.full(n_ep, chosen), fixed, nsat, length)
    b = np.asarray(baselines, dtype=np.float64)
    if b.ndim != 2 or b.shape != (len(obs) - 1, 3):
        raise InvalidInputError(f"expected baselines of shape ({len(obs) - 1}, 3), got {b.shape}")
    if method == "lambda":
        raise InvalidInputError("method 'lambda' is not implemented in attitude mode: use 'ml'")
    angles = np.full((n_ep, 3), np.nan)
    for k in range(n_ep):
        m = usable[k]
        if m.sum() < 3:
            continue
        r = ml_attitude(sd[:, k, m], al.los_enu[k, m], b, al.wavelength_m[m], step_deg=step_deg)
        psi, theta, phi = r.euler_deg
        angles[k] = [(-psi) % 360.0, theta, phi]
    return AttitudeSeries(
        al.time,
        "attitude",
        angles,
        np.full(n_ep, "ml"),
        np.zeros(n_ep, dtype=np.int64),
        usable.sum(axis=1).astype(np.int64),
    )
