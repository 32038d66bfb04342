"""Attitude and baseline-direction time series from recorded RINEX data of antennas on one platform, by the
Rust observation engine (``gnssatt._core.gnss_run``; ``docs/observation_engine.md``).

Two antennas and no baselines: baseline-direction mode, the azimuth (clockwise from North) and elevation
of the vector from the first antenna to the second. Three or more antennas with body-frame baselines:
attitude mode, heading / pitch / roll (eq. (5) of Bunyaeva et al., compass heading ``= -psi``).

Python only reads the files (:func:`~gnssatt.gnss.session_input.session_input`,
:func:`~gnssatt.rinex.nav.nav_input`), checks the arguments and shapes the results; the engine
does the rest in one GIL-released call: single-point positioning of every receiver (Klobuchar,
Saastamoinen), double differences of every system and frequency slot chosen, float solution, LAMBDA fixing
with a success-rate gate and partial fixing (or the ambiguity-function grid, ``method="ml"``).

Methods (the ``method`` column says which produced each row): ``"lambda"`` (double differences, LAMBDA;
geometry-constrained in attitude mode, then Wahba's problem), ``"ml"`` (the grid on the wrapped single
differences), ``"auto"`` (``"lambda"`` for baselines beyond 100 m, else ``"ml"``).
"""

from __future__ import annotations

import csv
import warnings
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, replace
from os import PathLike
from typing import TYPE_CHECKING, Any, Literal, get_args

import numpy as np
from numpy.typing import ArrayLike, NDArray

from gnssatt._arrays import choice, flag, path_text, scalar, shaped
from gnssatt.errors import ConvergenceError, GnssattWarning, InvalidInputError, InvalidTypeError, RinexError
from gnssatt.rinex.nav import RinexNav, navigation
from gnssatt.rinex.obs import RinexObs, read_obs

if TYPE_CHECKING:
    from scipy.spatial.transform import Rotation

__all__ = [
    "KNOWN_LENGTH_TOLERANCE_M",
    "KNOWN_LENGTH_TOLERANCE_RELATIVE",
    "MIN_DIRECTION_BASELINE_M",
    "SYSTEMS",
    "AttitudeSeries",
    "CombinedBaseline",
    "EngineWarning",
    "ZeroBaselineWarning",
    "attitude_from_rinex",
]

MethodName = Literal["auto", "ml", "lambda"]
MotionName = Literal["static", "moving"]
FilterName = Literal["static", "kinematic", "velocity"]

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
#: Largest search window and grid step, degrees.
MAX_WINDOW_DEG = 3600.0
MAX_STEP_DEG = 180.0
_GPS_EPOCH = np.datetime64("1980-01-06T00:00:00", "ns")
#: Baseline mode: a baseline shorter than this, m, has no direction (its azimuth and elevation are NaN, with
#: a :class:`ZeroBaselineWarning`). Two antennas' phase centres stand at least their diameter (several cm)
#: apart, and the known-length option takes no length below it either; a solution this short means one
#: antenna seen twice (the same file, or two receivers on one antenna splitter: a zero-baseline test), where
#: the fixed baseline is the receivers' noise, mm, and its direction is arbitrary (atan2 of zeros).
MIN_DIRECTION_BASELINE_M = 0.01


class EngineWarning(GnssattWarning):
    """Something the observation engine says a user should know (a base position far from the code
    solution, a system without ephemerides, ...); also kept in :attr:`AttitudeSeries.warnings`."""


class ZeroBaselineWarning(EngineWarning):
    """Baseline mode: the baseline solved is shorter than :data:`MIN_DIRECTION_BASELINE_M` at some epochs,
    whose azimuth and elevation are therefore NaN (the baseline itself is kept)."""


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
    """Per-epoch results of :func:`attitude_from_rinex`; :meth:`columns` gives the CSV columns in order.

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
        return float(np.median(lengths)) if lengths.size else float("nan")

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
            median_sigma = float(np.nanmedian(sigma)) if np.isfinite(sigma).any() else float("nan")
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
                applied = "applied within 0.5-10, 0.1-10 with a known length"
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


def _systems(value: object) -> str:
    if not isinstance(value, str):
        raise InvalidTypeError(f"expected systems as system letters such as 'GE', got {type(value).__name__}")
    if not value or any(ch not in SYSTEMS for ch in value):
        raise InvalidInputError(f"expected systems as letters among {SYSTEMS!r}, got {value!r}")
    return "".join(ch for ch in SYSTEMS if ch in value)


def _frequencies(value: object) -> int:
    from gnssatt import _core

    top = int(_core.GNSS_MAX_FREQUENCIES)
    if value == "all":
        return top
    if isinstance(value, bool) or not isinstance(value, int | np.integer) or not 1 <= int(value) <= top:
        raise InvalidInputError(f"expected frequencies 1..{top} or 'all', got {value!r}")
    return int(value)


def attitude_from_rinex(
    observations: Sequence[RinexObs | str | PathLike[str]],
    nav: RinexNav | str | PathLike[str] | Sequence[str | PathLike[str]],
    baselines: ArrayLike | None = None,
    *,
    method: MethodName = "auto",
    motion: MotionName | None = None,
    continuity: bool = False,
    filter: FilterName | None = None,
    rigid: bool = False,
    systems: str = SYSTEMS,
    frequencies: int | Literal["all"] = "all",
    elevation_mask_deg: float | None = None,
    min_success_rate: float | None = None,
    ratio_threshold: float | None = None,
    max_failure_rate: float | None = None,
    base_position_m: ArrayLike | None = None,
    step_deg: float | None = None,
    window_deg: float | None = None,
    baseline_length_m: ArrayLike | None = None,
) -> AttitudeSeries:
    """Attitude (with ``baselines``) or baseline direction (two antennas, none) at every common epoch.

    Parameters
    ----------
    observations
        Observation files (or read :class:`RinexObs`), one per antenna, the reference antenna first.
    nav
        Navigation file(s) or a read :class:`RinexNav`.
    baselines
        (n_ant - 1, 3) antenna positions relative to the first, body frame of Bunyaeva et al. (X nose, Y up,
        Z right wing), m; required with three or more antennas.
    method
        ``"auto"``, ``"ml"`` or ``"lambda"`` (module docstring).
    motion
        ``"static"``: the ambiguities of the whole session fixed once (a static pair); ``"moving"``: every
        epoch fixed on its own (or held along arcs with ``continuity``). Default: static for two antennas
        (moving with ``continuity``), moving in attitude mode, where ``"static"`` is refused.
    continuity
        Moving mode: hold fixed integers along slip-free arcs while each epoch's data agree with them
        (chi-square), instead of fixing every epoch afresh; in attitude mode the integers of the whole
        array, new arcs fixed on them, a fresh fix replacing them only when the data prefer it
        (``fix_state`` says ``held``; ``docs/observation_engine.md``). Refused with ``motion="static"``
        (one set for the session already).
    filter
        A multi-epoch Kalman filter of each baseline (implies ``motion="moving"``) with the
        process model ``"static"`` (the baseline does not change), ``"kinematic"`` (a random walk of
        30 m/sqrt(s): each epoch's baseline from its own data and the ambiguities carried along their arcs)
        or ``"velocity"`` (constant velocity, white acceleration 1 (m/s^2)^2/Hz); integers fixed on the
        filter's covariance every epoch and held while they agree with it (``fix_state``;
        ``docs/observation_engine.md``). With ``baseline_length_m`` the filter's fix is the
        length-constrained integer search on its covariance, and every fix's length is checked against the
        known one. With ``baselines`` (attitude mode) each rover's baseline has its filter, which knows
        the body baseline's length and holds its own integers; the filtered floats are fixed together
        under the body baselines (the constrained search and its simulated success rate on the
        filters' covariances), and an epoch the filters leave float is fixed on its own as without a
        filter. Refused with ``motion="static"``, ``continuity`` and ``method="ml"``.
    rigid
        With ``filter``: both antennas are on one rigid body (a moving base on the rover's vehicle), so the
        baseline's length is constant. The filter learns it from its first fixes and refuses a fix whose
        length disagrees beyond 4 sigma (``docs/observation_engine.md``). Wrong for a rover moving against a
        static base (its length changes); refused without ``filter`` and with ``baseline_length_m`` or
        ``baselines`` (a known length or body baselines are checked already).
    systems
        Satellite systems, letters among ``"GRECJ"`` (default all).
    frequencies
        Frequency slots used per system, 1..3 or ``"all"`` (3): slot 1 L1/G1/E1/B1I, 2 L2/G2/E5b/B2I,
        3 L5/G3/E5a/B3I (``docs/observation_engine.md``).
    elevation_mask_deg
        Elevation mask at the reference antenna, degrees (default: the engine's, 10).
    min_success_rate
        Smallest bootstrapped success rate of the ambiguity set fixed; the largest subset that reaches it
        is fixed when the full set does not (default ``gnssatt._core.GNSS_DEFAULT_MIN_SUCCESS_RATE``).
    ratio_threshold
        Ratio-test acceptance threshold, >= 1 (default ``gnssatt._core.GNSS_DEFAULT_RATIO_THRESHOLD``).
    max_failure_rate
        In [0, 0.1]: a full set below ``min_success_rate`` whose ratio passes ``ratio_threshold`` is still
        fixed when the ratio also passes the fixed-failure-rate threshold for this probability of accepting
        a wrong fix, simulated for the epoch's own float covariance (0: off; default
        ``gnssatt._core.GNSS_DEFAULT_MAX_FAILURE_RATE``, ``docs/observation_engine.md``).
    base_position_m
        (3,) surveyed ECEF position of the reference antenna, m; default its code solution at each epoch.
    step_deg, window_deg
        ML grid step (default eq. (15) of Bunyaeva et al.) and search window around the previous epoch's
        solution (default the whole domain), degrees.
    baseline_length_m
        Baseline mode: the known distance of each rover antenna from the reference antenna (a number for
        two antennas, else (n_ant - 1,)), m, in [0.01, 1e4]: the integers are fixed with the length
        constraint, gated by its own simulated success rate (``docs/observation_engine.md``).

    Returns
    -------
    AttitudeSeries
        One row per epoch common to all files.

    Warns
    -----
    EngineWarning
        What the engine says a user should know (also in :attr:`AttitudeSeries.warnings`).
    ZeroBaselineWarning
        Baseline mode: the baseline is shorter than :data:`MIN_DIRECTION_BASELINE_M` (one antenna seen
        twice); azimuth and elevation are NaN at those epochs, the baselines are kept.

    Raises
    ------
    RinexError
        Unreadable files, no common epochs, a file without phase or a system another file lacks; a
        navigation file with no record of the satellites observed within 6 h of their epochs (of another
        day), named with both time spans.
    InvalidTypeError
        ``observations`` not a list of files or :class:`RinexObs`, ``nav`` not a :class:`RinexNav`, file
        or list of files, another argument of the wrong kind.
    InvalidInputError
        Fewer than two observations, baselines of the wrong shape or not finite, an unknown method, motion
        or system letter, an option out of its range; ``method="ml"`` where the likelihood grid failed
        or solved no epoch; ``step_deg`` or ``window_deg`` where the grid never runs (``method="lambda"``,
        a ``filter``) or solved no epoch (``method="auto"`` with every epoch fixed), since they would change
        nothing; a ``baseline_length_m`` that the fixed epochs contradict (beyond
        :data:`KNOWN_LENGTH_TOLERANCE_M` plus :data:`KNOWN_LENGTH_TOLERANCE_RELATIVE` of it), the
        message giving the measured length: checked first on the first :data:`KNOWN_LENGTH_PROBE_EPOCHS`
        epochs of a longer session, before the session runs, then on the session.

    Examples
    --------
    Three epochs of a 1 m triangle simulated at heading 330, pitch 10, roll -5 deg (eq. (5) angles
    ``psi = 30``, ``theta = 10``, ``phi = -5``; GPS + Galileo, two frequencies, phase noise 0.01 mm, code
    1 cm, no atmosphere), written as RINEX and read back: every epoch fixed, the attitude given back:

    >>> import tempfile
    >>> import numpy as np
    >>> from gnssatt.gnss.attitude import attitude_from_rinex
    >>> from gnssatt.sim import equilateral_triangle
    >>> from gnssatt.sim.rinex_scenario import simulate_gnss_rinex
    >>> antennas = equilateral_triangle(1.0, plane="xz")  # (3, 3) m, body (X nose, Y up, Z right wing)
    >>> quiet = {"phase_sigma_m": 1e-5, "code_sigma_m": 0.01, "atmosphere": False}
    >>> with tempfile.TemporaryDirectory() as folder:
    ...     sim = simulate_gnss_rinex(folder, antennas, [30.0, 10.0, -5.0], systems="GE", frequencies=2,
    ...                               n_epochs=3, rng=1, **quiet)
    ...     series = attitude_from_rinex(list(sim.obs_paths), sim.nav_path, antennas[1:])
    >>> series.mode, series.angle_names, series.fixed.tolist()
    ('attitude', ('heading_deg', 'pitch_deg', 'roll_deg'), [1, 1, 1])
    >>> np.round(series.angles_deg, 1) + 0.0
    array([[330.,  10.,  -5.],
           [330.,  10.,  -5.],
           [330.,  10.,  -5.]])
    """
    from gnssatt import _core
    from gnssatt.gnss.session_input import session_input
    from gnssatt.rinex.nav import nav_input

    method = choice("method", method, ("auto", "ml", "lambda"))
    if motion is not None:
        motion = choice("motion", motion, get_args(MotionName))
    continuity = flag("continuity", continuity)
    rigid = flag("rigid", rigid)
    if filter is not None:
        filter = choice("filter", filter, get_args(FilterName))
    systems = _systems(systems)
    n_freq = _frequencies(frequencies)
    opts: dict[str, Any] = {}
    if elevation_mask_deg is not None:
        opts["elevation_mask_deg"] = scalar(
            "elevation_mask_deg", elevation_mask_deg, minimum=-90.0, maximum=90.0
        )
    if min_success_rate is not None:
        opts["min_success_rate"] = scalar("min_success_rate", min_success_rate, minimum=0.0, maximum=1.0)
    if ratio_threshold is not None:
        opts["ratio_threshold"] = scalar("ratio_threshold", ratio_threshold, minimum=1.0)
    if max_failure_rate is not None:
        opts["max_failure_rate"] = scalar("max_failure_rate", max_failure_rate, minimum=0.0, maximum=0.1)
    if base_position_m is not None:
        opts["base_position_m"] = shaped("base_position_m", base_position_m, "(3,)", (3,))
    if step_deg is not None:
        opts["step_deg"] = scalar("step_deg", step_deg, minimum=0.0, maximum=MAX_STEP_DEG, strict=True)
    if window_deg is not None:
        opts["window_deg"] = scalar(
            "window_deg", window_deg, minimum=0.0, maximum=MAX_WINDOW_DEG, strict=True
        )
    grid_options: list[str] = [n for n in ("step_deg", "window_deg") if n in opts]
    if grid_options and (method == "lambda" or filter is not None):
        # the engine runs the likelihood grid with method ml or auto and without a filter only: these
        # options would change nothing
        without = "method 'lambda'" if method == "lambda" else f"filter {filter!r}"
        raise InvalidInputError(
            f"{' and '.join(grid_options)} set the likelihood grid, which {without} never runs: leave "
            "them out, or use method 'ml' or 'auto'"
        )
    observations = _obs_list("observations", observations)
    n_rover = len(observations) - 1
    if baseline_length_m is not None:
        lengths = shaped("baseline_length_m", np.atleast_1d(baseline_length_m), "(n_ant - 1,)", (n_rover,))
        opts["baseline_lengths_m"] = [float(v) for v in lengths]
    if baselines is not None:
        b = shaped("baselines", baselines, "(n_ant - 1, 3)", (n_rover, 3))
        if n_rover < 2:
            raise InvalidInputError(
                "attitude mode needs three or more antennas; for two, omit the baselines (baseline mode)"
            )
        opts["body_baselines_m"] = b
    elif n_rover != 1:
        raise InvalidInputError(f"expected baselines ({n_rover}, 3) for {n_rover + 1} antennas, got none")
    if motion is None:
        motion = "moving" if baselines is not None or continuity or filter is not None else "static"
    obs = [o if isinstance(o, RinexObs) else read_obs(o) for o in observations]
    nv = navigation(nav, "nav")
    si = session_input(obs, systems=systems, frequencies=n_freq, nav=nv)
    _check_nav_covers(si.time_gpst_ns, si.sats, nv)
    ni = nav_input(nv)
    modes: dict[str, Any] = {
        "systems": systems,
        "frequencies": n_freq,
        "motion": motion,
        "continuity": continuity,
    }
    options = _core.GnssOptions(  # checks every option
        **modes, method=method, filter=filter, rigid=rigid, **opts
    )
    if baseline_length_m is not None and len(si.time_gpst_ns) > KNOWN_LENGTH_PROBE_EPOCHS:
        _probe_known_lengths(opts["baseline_lengths_m"], si, ni.navigation(), modes, opts)
    s = _core.gnss_run(si.observations(), ni.navigation(), options)
    series = _series(s, si.signal_codes)
    _check_method(method, series)
    _check_grid_options(grid_options, series)
    if baseline_length_m is not None:
        _check_known_lengths(opts["baseline_lengths_m"], series, "the session")
    for message in s.warnings:
        warnings.warn(message, EngineWarning, stacklevel=2)
    return _undirected(series, [str(o.path) for o in obs])


#: A known baseline length is refused when the fixed solutions measure a length further from it than
#: ``KNOWN_LENGTH_TOLERANCE_M + KNOWN_LENGTH_TOLERANCE_RELATIVE x length``: fixed double differences give
#: the length to millimetres, and the engine's grid needs it to 1 % (``docs/observation_engine.md``).
KNOWN_LENGTH_TOLERANCE_M = 0.01
KNOWN_LENGTH_TOLERANCE_RELATIVE = 1e-3


#: Epochs of the probe that checks ``baseline_length_m`` before a longer session runs: the first ones,
#: solved without the length (LAMBDA alone). The GEONET pair of ``tests/test_option_effects.py`` (3.3 km,
#: 30 s epochs) fixes from its first epoch, so a contradicted length is refused after these instead of the
#: whole session; a probe that fixes none of them leaves the check to the session.
KNOWN_LENGTH_PROBE_EPOCHS = 30


def _probe_known_lengths(
    lengths_m: list[float],
    si: Any,
    navigation: Any,
    modes: dict[str, Any],
    opts: dict[str, Any],
) -> None:
    """:func:`_check_known_lengths` on the first :data:`KNOWN_LENGTH_PROBE_EPOCHS` epochs solved without
    the known length, before the session runs. A probe that fixes nothing, or fails, decides nothing: the
    session's own check (and its own errors) follow."""
    from gnssatt import _core

    free = {k: v for k, v in opts.items() if k not in ("baseline_lengths_m", "step_deg", "window_deg")}
    try:
        probe = _core.gnss_run(
            si.observations(slice(0, KNOWN_LENGTH_PROBE_EPOCHS)),
            navigation,
            _core.GnssOptions(**modes, method="lambda", filter=None, **free),
        )
    except (InvalidInputError, ConvergenceError):
        return
    first = f"the first {KNOWN_LENGTH_PROBE_EPOCHS} epochs (solved without the length, before the session)"
    _check_known_lengths(lengths_m, _series(probe, si.signal_codes), first)


def _check_known_lengths(lengths_m: list[float], series: AttitudeSeries, epochs: str) -> None:
    """Refuses ``baseline_length_m`` where the epochs fixed by LAMBDA measure another length (the engine
    uses the known length only where it helps, so a wrong one left the result unchanged); ``epochs`` says
    which epochs were looked at in the message."""
    rows = series.solved & (series.fixed == 1) & (series.method == "lambda")
    if not np.any(rows):
        return  # nothing measured the length independently
    measured = np.median(np.linalg.norm(series.baselines_enu_m[rows], axis=2), axis=0)
    for r, (given, got) in enumerate(zip(lengths_m, measured, strict=True)):
        if abs(got - given) > KNOWN_LENGTH_TOLERANCE_M + KNOWN_LENGTH_TOLERANCE_RELATIVE * given:
            raise InvalidInputError(
                f"baseline_length_m: rover {r + 1} is given as {given:.4g} m, but {int(np.sum(rows))} "
                f"fixed epochs of {epochs} measure {got:.4f} m (median): give the measured length or none"
            )


def _check_grid_options(names: list[str], series: AttitudeSeries) -> None:
    """Refuses ``step_deg`` and ``window_deg`` where the likelihood grid solved no epoch: with method
    ``"auto"`` it runs only on epochs LAMBDA left unfixed (and within 100 m in baseline mode), so the
    options changed nothing."""
    if names and not np.any(series.method == "ml"):
        raise InvalidInputError(
            f"{' and '.join(names)} set the likelihood grid, which solved none of the {len(series.method)} "
            "epochs (method 'auto' runs it only where LAMBDA fixed nothing, and in baseline mode within "
            "100 m): they changed nothing; leave them out, or use method 'ml'"
        )


def _check_method(method: str, series: AttitudeSeries) -> None:
    """Refuses ``method="ml"`` where the likelihood grid solved no epoch or failed (the engine then keeps
    the double-difference solution, which ``method="ml"`` did not ask for)."""
    if method != "ml":
        return
    failed = [w for w in series.warnings if "likelihood grid failed" in w]
    if failed or not np.any(series.method == "ml"):
        reason = "; ".join(failed) or "; ".join(w for w in series.warnings if "grid" in w) or "no epoch"
        raise InvalidInputError(
            f"method 'ml': the likelihood grid solved {int(np.sum(series.method == 'ml'))} of "
            f"{len(series.method)} epochs ({reason}): use method 'auto' or 'lambda', or a coarser step_deg "
            "or a window_deg"
        )


#: Longest validity of a broadcast record on either side of its reference time, s (BeiDou's 6 h in
#: ``max_age_s`` of ``rust/core/src/gnss/ephemeris/mod.rs``): beyond it from every epoch, no record can serve.
_LONGEST_EPHEMERIS_AGE_NS = 6 * 3600 * 1_000_000_000


def _check_nav_covers(time_gpst_ns: NDArray[np.int64], sats: tuple[str, ...], nav: RinexNav) -> None:
    """Refuse, naming the navigation file and both time spans, when no broadcast record of a satellite of
    the session lies within the longest validity of any epoch (a navigation file of another day): the
    engine would otherwise report only that no satellite had an ephemeris."""
    k, g = nav.kepler, nav.glonass
    wanted = np.array(sats, dtype=str)
    times = np.concatenate([k.toe_ns[np.isin(k.sats, wanted)], g.tb_ns[np.isin(g.sats, wanted)]]).astype(
        np.int64
    )
    epochs = np.sort(np.asarray(time_gpst_ns, dtype=np.int64))
    if len(times) and len(epochs):
        after = np.clip(np.searchsorted(epochs, times), 0, len(epochs) - 1)
        before = np.clip(after - 1, 0, len(epochs) - 1)
        nearest = np.minimum(np.abs(times - epochs[after]), np.abs(times - epochs[before]))
        if nearest.min() <= _LONGEST_EPHEMERIS_AGE_NS:
            return
    first, last = (_GPS_EPOCH + np.array([epochs[0], epochs[-1]]).astype("timedelta64[ns]")).astype(
        "datetime64[s]"
    )
    if len(times):
        lo, hi = (_GPS_EPOCH + np.array([times.min(), times.max()]).astype("timedelta64[ns]")).astype(
            "datetime64[s]"
        )
        span = f"its records of these satellites refer to {lo} to {hi} (GPST)"
    else:
        span = "it has no record of any of them"
    raise RinexError(
        nav.path,
        None,
        f"no broadcast ephemeris for the {len(sats)} satellites observed (systems "
        f"{''.join(dict.fromkeys(x[0] for x in sats))}) within 6 h of the "
        f"observation epochs {first} to {last} (GPST); {span}: expected the navigation file of the "
        "observation day",
    )


def _undirected(series: AttitudeSeries, paths: list[str]) -> AttitudeSeries:
    """Baseline mode: azimuth and elevation NaN (with a :class:`ZeroBaselineWarning`) where the baseline is
    shorter than :data:`MIN_DIRECTION_BASELINE_M`, instead of the angles of a vector of noise."""
    if series.mode != "baseline":
        return series
    length = np.linalg.norm(series.baselines_enu_m[:, 0, :], axis=1)
    short = length < MIN_DIRECTION_BASELINE_M
    if not short.any():
        return series
    message = (
        f"baseline shorter than {MIN_DIRECTION_BASELINE_M} m at {int(short.sum())} of {len(short)} epochs "
        f"(longest {float(length[short].max()):.4f} m) between {paths[0]} and {paths[1]}: one antenna seen "
        "twice (the same file, or a zero-baseline receiver test); azimuth and elevation are undefined there "
        "and set to NaN, the baselines are kept"
    )
    warnings.warn(message, ZeroBaselineWarning, stacklevel=3)
    angles = series.angles_deg.copy()
    sigmas = series.angle_sigmas_deg.copy()
    angles[short] = np.nan
    sigmas[short] = np.nan
    return replace(series, angles_deg=angles, angle_sigmas_deg=sigmas, warnings=(*series.warnings, message))


def _series(s: Any, signal_codes: Mapping[str, Any]) -> AttitudeSeries:
    """An :class:`AttitudeSeries` of a ``gnssatt._core.GnssSession``."""
    per_system = np.asarray(s.satellites_per_system, dtype=np.int64)
    dd = s.double_differences
    return AttitudeSeries(
        time=_GPS_EPOCH + np.asarray(s.time_gpst_ns, dtype=np.int64).astype("timedelta64[ns]"),
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
