"""The result of :func:`~gnssatt.gnss.attitude.attitude_from_rinex`: :class:`AttitudeSeries` (its CSV columns
and summary) and :class:`CombinedBaseline` (a static session's fixed epochs combined), built from the
engine's ``gnssatt._core.GnssSession``. Public through :mod:`gnssatt.gnss.attitude`.
"""

from __future__ import annotations

import csv
from collections.abc import Mapping
from dataclasses import dataclass
from os import PathLike
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from gnssatt.errors import InvalidInputError

if TYPE_CHECKING:
    from scipy.spatial.transform import Rotation

#: System letters in the engine's order (columns ``sats_G`` ... and rows of ``double_differences``).
SYSTEMS = "GRECJ"
#: Signal of each frequency slot per system (``rust/core/src/gnss/signal.rs``).
SLOT_NAMES = {
    "G": ("L1", "L2", "L5"),
    "R": ("G1", "G2", "G3"),
    "E": ("E1", "E5b", "E5a"),
    "C": ("B1I", "B2I", "B3I"),
    "J": ("L1", "L2", "L5"),
}
#: GPS time zero (1980-01-06 00:00:00): the engine reports epochs as nanoseconds since it.
GPS_EPOCH = np.datetime64("1980-01-06T00:00:00", "ns")


@dataclass(frozen=True)
class CombinedBaseline:
    """The baselines of a static session from every fixed epoch (:meth:`AttitudeSeries.combined_baseline`).

    Attributes
    ----------
    baselines_enu_m
        (m, 3) rover minus reference antenna, East-North-Up at the reference antenna, m.
    covariances_enu_m2
        (m, 3, 3) their covariances, m^2 (white noise across epochs).
    epochs
        Fixed epochs combined.
    """

    baselines_enu_m: NDArray[np.float64]
    covariances_enu_m2: NDArray[np.float64]
    epochs: int

    def summary(self) -> str:
        """One line per rover: ENU components with their one-sigma, mm, and the epochs combined."""
        lines = []
        for r, (b, q) in enumerate(zip(self.baselines_enu_m, self.covariances_enu_m2, strict=True), start=1):
            sd = 1e3 * np.sqrt(np.diag(q))
            lines.append(
                f"combined baseline, rover {r} ({self.epochs} fixed epochs): "
                f"east {b[0]:.4f} +- {sd[0]:.1f} mm, north {b[1]:.4f} +- {sd[1]:.1f} mm, "
                f"up {b[2]:.4f} +- {sd[2]:.1f} mm"
            )
        return "\n".join(lines)


@dataclass(frozen=True)
class AttitudeSeries:
    """Per-epoch results of :func:`~gnssatt.gnss.attitude.attitude_from_rinex`; :meth:`columns` gives the CSV
    columns in order.

    ``n`` epochs, ``m`` rovers (antennas after the reference), ``k`` angles (2 or 3).

    Attributes
    ----------
    time
        (n,) GPST epoch labels, ``datetime64[ns]``.
    mode
        ``"baseline"`` or ``"attitude"``.
    angles_deg, angle_sigmas_deg
        (n, k) azimuth, elevation (baseline mode) or heading, pitch, roll (attitude mode) and their
        one-sigma (first-order propagation of the baseline covariance), degrees; NaN where unsolved.
    method
        (n,) ``"ml"`` or ``"lambda"``.
    fixed
        (n,) 1 where every ambiguity was fixed and validated (or held along an arc), else 0.
    fix_state
        (n,) ``"fixed"`` (every ambiguity fixed and validated at the epoch), ``"held"`` (every ambiguity
        fixed through integers held from earlier epochs: ``continuity`` or ``filter``) or ``"float"``
        (not every ambiguity fixed, or unsolved).
    satellites
        (n,) satellites used.
    baselines_enu_m
        (n, m, 3) rover minus reference antenna, East-North-Up at the reference antenna, m.
    ratio, success_rate
        (n,) ratio-test statistic of the set fixed and bootstrapped success rate of the full float set
        (NaN for ``ml`` or where nothing was fixed).
    satellites_per_system
        (n, 5) satellites used per system, order :data:`SYSTEMS`.
    frequency_slots_used
        (n,) bit ``s`` set when frequency slot ``s`` (0: L1/G1/E1/B1I, 1: L2/G2/E5b/B2I, 2: L5/G3/E5a/B3I)
        contributed double differences.
    double_differences
        (5, 3) double differences formed over the session per system and slot.
    rotation_matrices
        (n, 3, 3) body -> ENU rotation in attitude mode (NaN where unsolved), None in baseline mode.
    signal_codes
        RINEX codes chosen per system and slot, as the reader reports them.
    warnings
        What the engine said a user should know, one sentence each (each also issued as an
        :class:`EngineWarning`).
    code_sigma_scale
        Per rover, the code sigma the receivers showed against the model's, estimated from the float
        solutions' residuals in moving mode, and applied to the code variances within 0.5-10 of the
        model's sigma (NaN where not estimated: static mode, or fewer than 50 residual degrees of
        freedom); ``docs/observation_engine.md``.
    baseline_covariances_enu_m2
        (n, m, 3, 3) covariance of each baseline, ENU, m^2 (NaN where unsolved or from the ML grid);
        :meth:`combined_baseline` combines the fixed epochs.
    """

    time: NDArray[np.datetime64]
    mode: str
    angles_deg: NDArray[np.float64]
    method: NDArray[np.str_]
    fixed: NDArray[np.int64]
    fix_state: NDArray[np.str_]
    satellites: NDArray[np.int64]
    angle_sigmas_deg: NDArray[np.float64]
    baselines_enu_m: NDArray[np.float64]
    ratio: NDArray[np.float64]
    success_rate: NDArray[np.float64]
    satellites_per_system: NDArray[np.int64]
    frequency_slots_used: NDArray[np.uint8]
    double_differences: NDArray[np.uint64]
    rotation_matrices: NDArray[np.float64] | None
    signal_codes: Mapping[str, Any]
    warnings: tuple[str, ...]
    code_sigma_scale: tuple[float, ...] = ()
    baseline_covariances_enu_m2: NDArray[np.float64] | None = None

    def combined_baseline(self) -> CombinedBaseline:
        """One baseline per rover from every fixed epoch: the batch least-squares solution of a static
        session with its covariance.

        With the integers fixed, an epoch's double differences depend on the baseline alone, and with white
        noise across epochs the batch least-squares baseline of all of them is the information-weighted
        mean of the per-epoch fixed baselines: ``Q = (sum_k Q_k^-1)^-1``, ``b = Q sum_k Q_k^-1 b_k``. The
        epochs used are the solved ones with every ambiguity fixed (``fixed == 1``, state ``fixed`` or
        ``held``) and a finite covariance. It is the static solution only where the antennas did not move
        (``motion="static"``, or a moving run of a static pair); time-correlated errors (multipath) make
        ``Q`` optimistic by up to the number of epochs per correlation time.

        Returns
        -------
        CombinedBaseline
            Baselines (m, 3), covariances (m, 3, 3) and the number of epochs used.

        Raises
        ------
        InvalidInputError
            No fixed epoch with a finite covariance (``epochs`` 0), or a series without covariances.
        """
        cov = self.baseline_covariances_enu_m2
        if cov is None:
            raise InvalidInputError(
                "combined_baseline: expected a series with baseline covariances, got none"
            )
        finite = np.all(np.isfinite(cov), axis=(1, 2, 3)) & np.all(
            np.isfinite(self.baselines_enu_m), axis=(1, 2)
        )
        rows = self.solved & (self.fixed == 1) & finite
        if not rows.any():
            raise InvalidInputError(
                f"combined_baseline: expected at least one fixed epoch with a finite covariance, got none of "
                f"{len(rows)} epochs"
            )
        info = np.linalg.inv(cov[rows])  # (k, m, 3, 3)
        total = info.sum(axis=0)
        q = np.linalg.inv(total)
        b = np.einsum("rij,rj->ri", q, np.einsum("krij,krj->ri", info, self.baselines_enu_m[rows]))
        return CombinedBaseline(
            baselines_enu_m=b, covariances_enu_m2=0.5 * (q + q.transpose(0, 2, 1)), epochs=int(rows.sum())
        )

    @property
    def angle_names(self) -> tuple[str, ...]:
        if self.mode == "baseline":
            return ("azimuth_deg", "elevation_deg")
        return ("heading_deg", "pitch_deg", "roll_deg")

    @property
    def solved(self) -> NDArray[np.bool_]:
        """(n,) epochs with every angle finite."""
        solved: NDArray[np.bool_] = np.all(np.isfinite(self.angles_deg), axis=1)  # np.all is typed Any
        return solved

    @property
    def baseline_length_m(self) -> float:
        """Median length of the first baseline over the solved epochs, m (NaN if none)."""
        lengths = np.linalg.norm(self.baselines_enu_m[self.solved, 0], axis=1)
        lengths = lengths[np.isfinite(lengths)]
        return nan_median(lengths)

    @property
    def rotation(self) -> Rotation:
        """(n,) body -> ENU rotations at the reference antenna, one per epoch (attitude mode), the identity
        where ``solved`` is False (the batched-result rule of ``docs/conventions.md``, as
        :class:`gnssatt.AttitudeSeries`).

        Raises
        ------
        InvalidInputError
            In baseline mode (two antennas: no attitude).
        """
        if self.rotation_matrices is None:
            raise InvalidInputError(
                "rotation: expected attitude mode (body baselines given), got baseline mode"
            )
        # Imported here: scipy.spatial costs 0.3-0.7 s that `gnssatt attitude` need not pay in baseline mode.
        from scipy.spatial.transform import Rotation

        ok = self.solved[:, None, None]
        return Rotation.from_matrix(np.where(ok, np.nan_to_num(self.rotation_matrices), np.eye(3)))

    def frequencies(self) -> NDArray[np.str_]:
        """(n,) frequency slots used per epoch, 1-based and joined by ``+`` (``"1+2"``); empty if none."""
        return np.array(
            [
                "+".join(str(s + 1) for s in range(3) if int(bits) >> s & 1)
                for bits in self.frequency_slots_used
            ]
        )

    def columns(self) -> dict[str, NDArray[np.generic]]:
        """Column name -> array, in the CSV order (``docs/conventions.md``)."""
        out: dict[str, NDArray[np.generic]] = {"time_gpst": np.datetime_as_string(self.time, unit="ms")}
        for j, name in enumerate(self.angle_names):
            out[name] = self.angles_deg[:, j]
        out["method"] = self.method
        out["fixed"] = self.fixed
        out["state"] = self.fix_state
        out["satellites"] = self.satellites
        for r in range(self.baselines_enu_m.shape[1]):
            suffix = "" if r == 0 else f"_{r + 1}"
            b = self.baselines_enu_m[:, r]
            for j, axis in enumerate(("east", "north", "up")):
                out[f"{axis}_m{suffix}"] = b[:, j]
            out[f"length_m{suffix}"] = np.linalg.norm(b, axis=1)
        for j, name in enumerate(self.angle_names):
            out[name.replace("_deg", "_sigma_deg")] = self.angle_sigmas_deg[:, j]
        out["ratio"] = self.ratio
        out["success_rate"] = self.success_rate
        for s, letter in enumerate(SYSTEMS):
            out[f"sats_{letter}"] = self.satellites_per_system[:, s]
        out["frequencies"] = self.frequencies()
        return out

    def to_csv(self, path: str | PathLike[str]) -> None:
        """Write the CSV: a header line, one row per epoch (angles to 1e-6 deg, lengths to 0.1 mm)."""
        cols = self.columns()
        formats = {name: _format(name) for name in cols}
        with open(path, "w", newline="") as fh:
            w = csv.writer(fh)
            w.writerow(list(cols))
            for i in range(len(self.time)):
                w.writerow([formats[name](v[i]) for name, v in cols.items()])

    def summary(self) -> str:
        """Epochs solved, fix rate, mean and spread of each angle, a line per system and frequency used, the
        estimated code noise."""
        ok = self.solved
        n = len(ok)
        fix_rate = float(self.fixed.mean()) if n else float("nan")
        lines = [f"epochs solved: {int(ok.sum())} of {n}", f"fix rate: {fix_rate:.3f}"]
        for j, name in enumerate(self.angle_names):
            v = self.angles_deg[ok, j]
            if name in ("azimuth_deg", "heading_deg") and v.size:
                c = np.degrees(np.angle(np.mean(np.exp(1j * np.radians(v)))))
                spread = np.degrees(np.std(np.angle(np.exp(1j * np.radians(v - c)))))
                mean = c % 360.0
            else:
                mean, spread = (float(np.mean(v)), float(np.std(v))) if v.size else (np.nan, np.nan)
            sigma = self.angle_sigmas_deg[ok, j]
            median_sigma = nan_median(sigma) if np.isfinite(sigma).any() else float("nan")
            lines.append(f"{name}: mean {mean:.4f}, std {spread:.4f}, median sigma {median_sigma:.4f}")
        for s, letter in enumerate(SYSTEMS):
            for slot in range(3):
                count = int(self.double_differences[s, slot])
                if count:
                    codes = _codes(self.signal_codes, letter, slot)
                    lines.append(
                        f"{letter} {SLOT_NAMES[letter][slot]}: {count} double differences"
                        + (f" ({codes})" if codes else "")
                    )
        for r, scale in enumerate(self.code_sigma_scale, start=1):
            if np.isfinite(scale):
                # The engine's rule (rust/core/src/gnss/stream/code_scale.rs): baseline mode scales code
                # and phase together (the ratio test keeps the model's shape), a known length and attitude
                # mode the code alone; sigma factors 0.5-10, 0.1-10 with a known length.
                applied = (
                    "applied within 0.5-10 to code and phase, to code alone within 0.1-10 with a known"
                    " length and within 0.5-10 in attitude mode"
                )
                lines.append(f"code noise, rover {r}: {scale:.2f} x the model's sigma (estimated; {applied})")
        return "\n".join(lines)


def _format(name: str) -> Any:
    if name.endswith("_deg") or name == "success_rate":
        return lambda x: f"{x:.6f}"
    if name.endswith("_m") or "_m_" in name:
        return lambda x: f"{x:.4f}"
    if name == "ratio":
        return lambda x: f"{x:.3f}"
    return str


def _codes(signal_codes: Mapping[str, Any], letter: str, slot: int) -> str:
    """The RINEX codes of one system and slot, joined over receivers where they differ."""
    found: list[str] = []

    def add(per_system: Mapping[str, Any]) -> None:
        codes = per_system.get(letter)
        if codes is not None and slot < len(codes) and codes[slot] and codes[slot] not in found:
            found.append(str(codes[slot]))

    if any(isinstance(v, Mapping) for v in signal_codes.values()):
        for v in signal_codes.values():
            if isinstance(v, Mapping):
                add(v)
    else:
        add(signal_codes)
    return ", ".join(found)


def series_from_session(s: Any, signal_codes: Mapping[str, Any]) -> AttitudeSeries:
    """An :class:`AttitudeSeries` of a ``gnssatt._core.GnssSession``."""
    per_system = np.asarray(s.satellites_per_system, dtype=np.int64)
    dd = s.double_differences
    return AttitudeSeries(
        time=GPS_EPOCH + np.asarray(s.time_gpst_ns, dtype=np.int64).astype("timedelta64[ns]"),
        mode=s.mode,
        angles_deg=s.angles_deg,
        method=np.array(s.method, dtype=str),
        fixed=np.asarray(s.fixed, dtype=np.int64),
        fix_state=np.array(s.fix_state, dtype=str),
        satellites=per_system.sum(axis=1),
        angle_sigmas_deg=s.angle_sigmas_deg,
        baselines_enu_m=s.baselines_enu_m,
        ratio=s.ratio,
        success_rate=s.success_rate,
        satellites_per_system=per_system,
        frequency_slots_used=s.frequency_slots_used,
        double_differences=np.zeros((5, 3), np.uint64) if dd is None else dd,
        rotation_matrices=s.rotation_enu_from_body,
        signal_codes=dict(signal_codes),
        warnings=tuple(s.warnings),
        code_sigma_scale=tuple(float(x) for x in s.code_sigma_scale),
        baseline_covariances_enu_m2=np.asarray(s.baseline_covariance_enu_m2, dtype=np.float64),
    )


def nan_median(values: NDArray[np.float64]) -> float:
    """``np.nanmedian(values)`` (NaN when every value is NaN) by a sort: numpy's median looks for a masked
    array, which loads numpy.ma, 30-50 ms of a command-line start for input that is never masked here."""
    ordered = np.sort(values[~np.isnan(values)])
    n = len(ordered)
    if not n:
        return float("nan")
    # the mean of the middle two as numpy computes it: their sum halved
    return float(ordered[n // 2] if n % 2 else (ordered[n // 2 - 1] + ordered[n // 2]) / 2)
