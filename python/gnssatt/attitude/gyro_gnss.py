"""Gyro + multi-antenna GNSS attitude filter (Dzhepe Ali, chapters 2-3), run by the Rust core.

An error-state Kalman filter propagates the attitude with the gyro rates (exact quaternion step for a rate
constant over each gyro interval) and corrects it with either

- the receiver's own attitude solutions (loosely coupled,
  :class:`~gnssatt.sim.attitude_scenario.AttitudeFixes`), or
- carrier-phase first differences between master and slave antennas (tightly coupled,
  :class:`~gnssatt.sim.attitude_scenario.PhaseObservations`): float ambiguities join the state when a
  satellite is first tracked and leave when it is no longer tracked, are fixed by LAMBDA when the bootstrapped
  success rate and the ratio test allow, and a satellite whose innovations fail a chi-square test (cycle slip,
  wrong fix) has its ambiguities reset.

State ``[dtheta (3), ddrift (3), N (m per float satellite)]``: true attitude ``R = R_hat exp([dtheta x])``
(body-frame rotation vector, rad), ``ddrift = drift - drift_hat`` (rad/s), gyro model
``omega_meas = omega - drift - w``. Frames, signs, units: ``docs/conventions.md`` ("Gyro + GNSS filter").

The sensitivity analysis (``sensitivity=(misalignment_sigma_rad, baseline_sigma_m)``) propagates, next to the
filter's own covariance, the covariance of its TRUE error when the gyro triad is misaligned and the baselines
are in error by those amounts, which the filter ignores (phase updates with known integers only).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.spatial.transform import Rotation
from scipy.stats import chi2

from gnssatt import _core
from gnssatt._arrays import (
    finite_outputs,
    flag,
    instance,
    integer,
    integer_array,
    plain_array,
    scalar,
    shaped,
)
from gnssatt.errors import InvalidInputError, WorkLimitError
from gnssatt.geometry import checked_baselines
from gnssatt.observations import AttitudeFixes, PhaseObservations

__all__ = [
    "MAX_GYRO_NOISE",
    "MAX_PHASE_SIGMA_CYCLES",
    "MAX_PROPAGATE_SAMPLES",
    "MAX_STEP_ANGLE_RAD",
    "MIN_GYRO_INTERVAL_S",
    "FixAttempt",
    "GyroGnssResult",
    "GyroPropagation",
    "gyro_gnss_filter",
    "gyro_propagate",
]

#: Largest rotation over one gyro interval, ``|rates[k]| (t[k+1] - t[k])``, rad. The step is exact for a
#: constant rate at any angle, but the angle's rounding error grows with it (1e-10 rad here); far beyond,
#: the product overflows and the attitude would be NaN.
MAX_STEP_ANGLE_RAD = 1e6
#: Most samples :func:`gyro_propagate` takes: the core's ``gyro_gnss::kinematics::MAX_SAMPLES``
#: (``docs/limits.md``), checked here too so that a larger batch is refused before it is copied.
MAX_PROPAGATE_SAMPLES = 20_000_000

#: Largest ``arw`` (rad/s/sqrt(Hz)) and ``rrw`` (rad/s^2/sqrt(Hz)) of :func:`gyro_gnss_filter`: a white rate
#: noise of 1 rad/s/sqrt(Hz) already loses the attitude within a second; beyond, the process noise
#: ``Qc * dt`` can overflow the filter's covariance.
MAX_GYRO_NOISE = 1.0
#: Largest ``phase_sigma_cycles`` of :func:`gyro_gnss_filter`: a carrier phase noisier than 10 cycles
#: carries no attitude information, and the measurement covariance must stay finite.
MAX_PHASE_SIGMA_CYCLES = 10.0
#: Shortest interval of ``gyro_t`` in :func:`gyro_gnss_filter`, s (a 1 MHz gyro); shorter intervals are not
#: sampled gyro records and make the record's span vanish next to the measurement times.
MIN_GYRO_INTERVAL_S = 1e-6


def _times_and_rates(
    t_name: str, t: ArrayLike, rates_name: str, rates: ArrayLike
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """(n,) times and (n, 3) rates, with every interval finite and turning by at most MAX_STEP_ANGLE_RAD."""
    tt = shaped(t_name, t, "(n,)", (None,))
    w = shaped(rates_name, rates, f"(n, 3) = ({len(tt)}, 3), one per time stamp of {t_name}", (len(tt), 3))
    with np.errstate(over="ignore", invalid="ignore"):
        dt = np.diff(tt)
        # an upper bound of |omega| dt (max component times sqrt(3)) that cannot overflow before the test
        angle = np.sqrt(3.0) * np.max(np.abs(w[:-1]), axis=1, initial=0.0) * np.abs(dt)
    bad = np.flatnonzero(~np.isfinite(dt) | ~(angle <= MAX_STEP_ANGLE_RAD))
    if bad.size:
        k = int(bad[0])
        rate = np.sqrt(3.0) * np.max(np.abs(w[k]))
        raise InvalidInputError(
            f"expected {rates_name} times the interval of {t_name} to turn by at most "
            f"{MAX_STEP_ANGLE_RAD:g} rad per interval, got |{rates_name}[{k}]| <= {rate:.6g} rad/s over "
            f"{t_name}[{k + 1}] - {t_name}[{k}] = {dt[k]:.6g} s"
        )
    return tt, w


@dataclass(frozen=True)
class GyroPropagation:
    """Attitudes of :func:`gyro_propagate` at its times ``t`` (s).

    ``rotation`` body -> reference (the reference of ``q0``), one per time; ``quaternions`` the same, (n, 4)
    scalar-last, as the core computed them (row 0 is ``q0`` normalised).
    """

    t: NDArray[np.float64]
    rotation: Rotation
    quaternions: NDArray[np.float64]


def gyro_propagate(q0: ArrayLike, t: ArrayLike, rates: ArrayLike) -> GyroPropagation:
    """Attitude quaternions (n, 4) scalar-last, body -> reference, at ``t`` (s) from ``q0`` with the body
    rates ``rates`` (n, 3) rad/s, ``rates[k]`` held over ``[t[k], t[k+1]]`` (exact for constant rates).

    Parameters
    ----------
    q0
        (4,) initial attitude quaternion, scalar-last, body -> reference (normalised here).
    t
        (n,) strictly increasing times, s; ``t[0]`` is the epoch of ``q0``.
    rates
        (n, 3) body angular rates in the body frame, rad/s; the last row is not used (no interval follows).

    Returns
    -------
    GyroPropagation
        ``rotation`` (n attitudes, body -> reference) and ``quaternions`` (n, 4), scalar-last, at ``t``; row
        0 is ``q0`` normalised.

    Raises
    ------
    InvalidInputError
        Wrong shapes, non-finite values, a zero ``q0``, ``t`` not strictly increasing, or a rotation over
        one interval beyond :data:`MAX_STEP_ANGLE_RAD` (:class:`~gnssatt.errors.InvalidTypeError` for values
        that are not real numbers).

    Examples
    --------
    A constant 0.1 rad/s about body Z for 10 s turns by 1 rad: ``q = [0, 0, sin(1/2), cos(1/2)]``:

    >>> import numpy as np
    >>> from gnssatt.attitude.gyro_gnss import gyro_propagate
    >>> t = np.arange(11.0)  # s
    >>> rates = np.tile([0.0, 0.0, 0.1], (11, 1))  # (11, 3) rad/s, body
    >>> np.round(gyro_propagate([0.0, 0.0, 0.0, 1.0], t, rates).quaternions[-1], 6) + 0.0
    array([0.      , 0.      , 0.479426, 0.877583])
    """
    q = shaped("q0", q0, "(4,)", (4,))
    # the core normalises q0 by its norm, whose square overflows (or underflows) far from 1: scale first
    largest = float(np.max(np.abs(q)))
    q = q / largest if largest > 0.0 else q
    n_samples = np.size(plain_array("t", t))
    if n_samples > MAX_PROPAGATE_SAMPLES:
        # before the samples are copied (a zero-stride view of 2e7 samples is 640 MB once copied)
        raise WorkLimitError(
            f"t asks for {n_samples} gyro samples, more than the limit of {MAX_PROPAGATE_SAMPLES}"
        )
    tt, w = _times_and_rates("t", t, "rates", rates)
    out = _core.gyro_propagate(q, tt, w)
    finite_outputs("gyro_propagate", quaternions=out)
    return GyroPropagation(tt, Rotation.from_quat(out), out)


@dataclass(frozen=True)
class FixAttempt:
    """One LAMBDA attempt: ``values`` are ``(track, baseline, integer)`` of the best candidate."""

    t: float
    accepted: bool
    ratio: float
    success_rate: float
    values: list[tuple[int, int, int]]


@dataclass(frozen=True)
class GyroGnssResult:
    """Filter output at the recorded gyro times ``t``.

    ``rotation`` body -> ECI; ``drift`` rad/s; ``covariance`` (n, 6, 6) of ``[dtheta, ddrift]`` as the filter
    believes it; ``true_covariance`` the covariance of the TRUE error (sensitivity analysis), else ``None``;
    ``misalignment`` (n, 3) rad and its ``misalignment_covariance`` (zeros unless estimated);
    ``n_float``/``n_fixed`` ambiguities held; ``nis`` (n_updates, 3) rows ``(t, NIS, dof)``; ``slips`` rows
    ``(t, track, NIS)``.
    """

    t: NDArray[np.float64]
    rotation: Rotation
    drift: NDArray[np.float64]
    covariance: NDArray[np.float64]
    true_covariance: NDArray[np.float64] | None
    misalignment: NDArray[np.float64]
    misalignment_covariance: NDArray[np.float64]
    n_float: NDArray[np.int64]
    n_fixed: NDArray[np.int64]
    fixes: list[FixAttempt]
    slips: NDArray[np.float64]
    nis: NDArray[np.float64]

    def errors(self, true_rotation: Rotation, true_drift: ArrayLike) -> NDArray[np.float64]:
        """(n, 6) true errors ``[dtheta, ddrift]``, filter sign: ``R_true = R_hat exp([dtheta x])``;
        ``true_rotation`` a Rotation of length n (or single), ``true_drift`` (3,) or (n, 3) rad/s."""
        truth = instance("true_rotation", true_rotation, Rotation, "a scipy Rotation")
        drift = shaped("true_drift", true_drift, "(3,) or (n, 3)", (3,), (None, 3))
        if (not truth.single and len(truth) != len(self.t)) or (
            drift.ndim == 2 and len(drift) != len(self.t)
        ):
            raise InvalidInputError(
                f"expected true_rotation and true_drift for the {len(self.t)} output times, got "
                f"{'one' if truth.single else len(truth)} rotation(s) and drift {drift.shape}"
            )
        dtheta = (self.rotation.inv() * truth).as_rotvec()
        return np.hstack([dtheta, drift - self.drift])

    def nees(self, errors: ArrayLike, *, true: bool = False) -> NDArray[np.float64]:
        """(n,) ``e^T P^-1 e`` with the filter's covariance (or the true-error covariance if ``true``) for
        (n, 6) ``errors``."""
        p = self.true_covariance if flag("true", true) else self.covariance
        if p is None:
            raise InvalidInputError("no true-error covariance: run with sensitivity=(...)")
        e = shaped("errors", errors, f"(n, 6) = ({len(p)}, 6)", (len(p), 6))
        # typed here: numpy types einsum's result as Any
        nees: NDArray[np.float64] = np.einsum("ki,ki->k", e, np.linalg.solve(p, e[..., None])[..., 0])
        return nees


def _covariance(name: str, value: ArrayLike, n: int) -> NDArray[np.float64]:
    """An (n, n) symmetric positive definite matrix (symmetric to 1e-9 of its largest entry)."""
    p = shaped(name, value, f"({n}, {n})", (n, n))
    tol = 1e-9 * float(np.max(np.abs(p)))
    if np.any(np.abs(p - p.T) > tol):
        raise InvalidInputError(
            f"expected {name} symmetric, got an asymmetry of {np.max(np.abs(p - p.T)):.3e}"
        )
    smallest = float(np.linalg.eigvalsh(p)[0])
    try:
        np.linalg.cholesky(p)
        definite = smallest > 0.0
    except np.linalg.LinAlgError:
        definite = False
    if not definite:
        raise InvalidInputError(f"expected {name} positive definite, got an eigenvalue of {smallest:.3e}")
    return p


def _empty_phases(m: int) -> tuple[Any, ...]:
    return (
        np.zeros(0),
        np.zeros(0, np.int64),
        np.zeros(0, np.int64),
        np.zeros((0, 3)),
        np.zeros(0),
        np.zeros((0, m)),
    )


def _check_gyro_intervals(t: NDArray[np.float64]) -> None:
    """Refuses gyro samples closer than ``MIN_GYRO_INTERVAL_S``; non-increasing stamps are refused by the
    core, which says "strictly increasing"."""
    dt = np.diff(t)
    short = np.flatnonzero((dt > 0.0) & (dt < MIN_GYRO_INTERVAL_S))
    if short.size:
        k = int(short[0])
        raise InvalidInputError(
            f"expected gyro_t intervals of at least MIN_GYRO_INTERVAL_S = {MIN_GYRO_INTERVAL_S:g} s, got "
            f"gyro_t[{k + 1}] - gyro_t[{k}] = {t[k + 1] - t[k]:.6g} s"
        )


def _checked_sensitivity(sensitivity: tuple[float, float]) -> tuple[float, float]:
    pair = shaped("sensitivity", sensitivity, "(2,) (misalignment_sigma_rad, baseline_sigma_m)", (2,))
    if np.any(pair < 0.0):
        raise InvalidInputError(f"expected sensitivity sigmas >= 0, got {pair.tolist()}")
    return (float(pair[0]), float(pair[1]))


def _checked_fixes(
    attitude_fixes: AttitudeFixes | None,
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """The core's (times, scalar-last quaternions, covariances) of the attitude fixes; empty without."""
    if attitude_fixes is None:
        return (np.zeros(0), np.zeros((0, 4)), np.zeros((0, 3, 3)))
    fixes = instance("attitude_fixes", attitude_fixes, AttitudeFixes, "AttitudeFixes")
    ft = shaped("attitude_fixes.t", fixes.t, "(n_fix,)", (None,))
    rot = instance("attitude_fixes.rotation", fixes.rotation, Rotation, "a scipy Rotation")
    return (
        ft,
        rot.as_quat().reshape(-1, 4),
        shaped(
            "attitude_fixes.covariance",
            fixes.covariance,
            f"(n_fix, 3, 3) = ({len(ft)}, 3, 3)",
            (len(ft), 3, 3),
        ),
    )


def _checked_phases(phases: PhaseObservations, m: int) -> tuple[Any, ...]:
    """The core's (epoch times, epoch, track, los, wavelength, phase) rows of the phase observations, for
    ``m`` baselines."""
    obs = instance("phases", phases, PhaseObservations, "PhaseObservations")
    rows = len(np.atleast_1d(obs.epoch))
    epoch_t = shaped("phases.epoch_t", obs.epoch_t, "(n_e,)", (None,))
    epoch = integer_array("phases.epoch", obs.epoch, f"(n_rows,) = ({rows},)", (rows,))
    outside = (epoch < 0) | (epoch >= len(epoch_t))
    if np.any(outside):
        k = int(np.flatnonzero(outside)[0])
        raise InvalidInputError(f"expected phases.epoch in [0, {len(epoch_t)}), got {epoch[k]} at row {k}")
    return (
        epoch_t,
        epoch,
        integer_array("phases.track", obs.track, f"(n_rows,) = ({rows},)", (rows,)),
        shaped("phases.los", obs.los, f"(n_rows, 3) = ({rows}, 3)", (rows, 3)),
        shaped("phases.wavelength", obs.wavelength, f"(n_rows,) = ({rows},)", (rows,)),
        shaped(
            "phases.phase",
            obs.phase,
            f"(n_rows, m) = ({rows}, {m}) for the {m} rows of baselines_m",
            (rows, m),
        ),
    )


def gyro_gnss_filter(
    gyro_t: ArrayLike,
    gyro_rates: ArrayLike,
    *,
    initial_rotation: Rotation,
    initial_covariance: ArrayLike,
    arw: float,
    rrw: float = 0.0,
    initial_drift: ArrayLike = (0.0, 0.0, 0.0),
    baselines_m: ArrayLike | None = None,
    phase_sigma_cycles: float = 0.01,
    attitude_fixes: AttitudeFixes | None = None,
    phases: PhaseObservations | None = None,
    fix_ambiguities: bool = True,
    ratio_threshold: float = 3.0,
    min_success_rate: float = 0.999,
    max_failure_rate: float = 0.0,
    slip_false_alarm: float | None = 1e-6,
    known_ambiguities: bool = False,
    sensitivity: tuple[float, float] | None = None,
    misalignment_sigma_rad: float | None = None,
    output_every: int = 1,
) -> GyroGnssResult:
    """Run the gyro + GNSS attitude filter.

    Parameters
    ----------
    gyro_t, gyro_rates
        (n,) strictly increasing times, s, and (n, 3) measured body rates, rad/s; ``gyro_rates[k]`` holds over
        ``[gyro_t[k], gyro_t[k+1]]`` (the last one is unused).
    initial_rotation, initial_covariance, initial_drift
        Initial attitude (body -> ECI), the (6, 6) covariance of ``[dtheta, ddrift]`` (rad^2, (rad/s)^2)
        and the drift estimate (rad/s).
    arw, rrw
        Gyro angle random walk (rad/s/sqrt(Hz)) and drift random walk (rad/s^2/sqrt(Hz)).
    baselines_m
        (m, 3) body baselines slave minus master, m (needed with ``phases``; non-zero lengths).
    phase_sigma_cycles
        Standard deviation of one first difference, cycles.
    attitude_fixes, phases
        Loosely coupled and/or tightly coupled measurements, within ``[gyro_t[0], gyro_t[-1]]``.
    fix_ambiguities, ratio_threshold, min_success_rate, max_failure_rate
        LAMBDA fixing through the same gate as the observation engine (``gnssatt attitude``,
        ``lambda::gate`` in the core): accepted when the ratio test passes ``ratio_threshold`` and the
        bootstrapped success rate of the float ambiguities reaches ``min_success_rate`` or, when
        ``max_failure_rate`` > 0, the ratio passes the fixed-failure-rate test for that probability of a
        wrong fix (0 turns the test off; at most 0.1).
    slip_false_alarm
        False-alarm probability of the per-satellite chi-square innovation test (cycle slips, wrong fixes);
        ``None`` disables it.
    known_ambiguities
        The phases carry no ambiguity (integers removed): no ambiguity states.
    sensitivity
        ``(misalignment_sigma_rad, baseline_sigma_m)``: also propagate the true-error covariance (needs
        ``known_ambiguities`` and no attitude fixes).
    misalignment_sigma_rad
        Estimate the misalignment of the gyro triad (three more states, ``mu`` with
        ``omega_meas = exp(-[mu x]) omega - drift - w``) with this prior sigma per axis, rad.
    output_every
        Record every ``output_every``-th gyro sample (and the first and last); an integer >= 1.

    Returns
    -------
    GyroGnssResult
        At the recorded gyro times: attitude (body -> ECI), drift estimate (rad/s), the filter's covariance of
        ``[dtheta, ddrift]``, ambiguity counts, LAMBDA attempts, slips and innovation statistics.

    Raises
    ------
    InvalidInputError
        Wrong shapes or non-finite values; ``gyro_t`` not strictly increasing; a rotation over one gyro
        interval beyond :data:`MAX_STEP_ANGLE_RAD`; a ``gyro_t`` interval below :data:`MIN_GYRO_INTERVAL_S`;
        an ``initial_covariance`` that is not symmetric positive definite; ``arw``, ``rrw`` or a
        ``sensitivity`` sigma below 0; ``arw`` or ``rrw`` above :data:`MAX_GYRO_NOISE`;
        ``phase_sigma_cycles`` not in (0, :data:`MAX_PHASE_SIGMA_CYCLES`]; ``misalignment_sigma_rad`` not
        above 0; ``ratio_threshold`` below 1; ``min_success_rate`` outside [0, 1]; ``max_failure_rate``
        outside [0, 0.1]; ``slip_false_alarm`` outside (0, 1); ``output_every`` below 1; baselines outside
        the limits of
        :func:`gnssatt.geometry.checked_baselines`; measurements outside the gyro record or inconsistent
        (:class:`~gnssatt.errors.InvalidTypeError` for values of the wrong kind: text, ``None``, complex,
        a ``phases`` that is not :class:`~gnssatt.sim.attitude_scenario.PhaseObservations` ...).
    DegenerateGeometryError
        An innovation covariance that is not positive definite.
    ConvergenceError
        A non-finite filter output from finite input.

    Examples
    --------
    A gyro at rest for 10 s without GNSS updates: the attitude stays put and its variance per axis grows as
    ``sigma_0^2 + arw^2 t + sigma_drift^2 t^2 = 1e-4 + 1e-5 + 1e-6 = 1.11e-4`` rad^2:

    >>> import numpy as np
    >>> from scipy.spatial.transform import Rotation
    >>> from gnssatt.attitude.gyro_gnss import gyro_gnss_filter
    >>> t = np.arange(11.0)  # s
    >>> p0 = np.diag([1e-4] * 3 + [1e-8] * 3)  # rad^2, (rad/s)^2
    >>> result = gyro_gnss_filter(
    ...     t, np.zeros((11, 3)), initial_rotation=Rotation.identity(), initial_covariance=p0, arw=1e-3
    ... )
    >>> round(float(result.rotation[-1].magnitude()), 9) + 0.0
    0.0
    >>> np.round(np.diag(result.covariance[-1])[:3] / 1e-4, 6)
    array([1.11, 1.11, 1.11])
    """
    rot0 = instance("initial_rotation", initial_rotation, Rotation, "a single scipy Rotation")
    if not rot0.single:
        raise InvalidInputError(f"expected initial_rotation as a single Rotation, got a stack of {len(rot0)}")
    t, w = _times_and_rates("gyro_t", gyro_t, "gyro_rates", gyro_rates)
    p0 = _covariance("initial_covariance", initial_covariance, 6)
    b0 = shaped("initial_drift", initial_drift, "(3,)", (3,))
    _check_gyro_intervals(t)
    options, m, with_sensitivity = _filter_options(
        len(t), arw, rrw, phase_sigma_cycles, fix_ambiguities, ratio_threshold, min_success_rate,
        max_failure_rate, known_ambiguities, output_every, phases is not None, baselines_m, slip_false_alarm,
        sensitivity, misalignment_sigma_rad,
    )  # fmt: skip
    fix_t, fix_q, fix_cov = _checked_fixes(attitude_fixes)
    ph = _empty_phases(m) if phases is None else _checked_phases(phases, m)
    epoch_t, phase_epoch, phase_track, phase_los, phase_wavelength, phase = ph
    d = _core.gyro_gnss_filter(
        t,
        w,
        q0=rot0.as_quat(),
        drift0=b0,
        p0=p0,
        options=options,
        fix_t=fix_t,
        fix_q=fix_q,
        fix_cov=fix_cov,
        epoch_t=epoch_t,
        phase_epoch=phase_epoch,
        phase_track=phase_track,
        phase_los=phase_los,
        phase_wavelength=phase_wavelength,
        phase=phase,
    )
    return _result(d, with_true_covariance=with_sensitivity)


def _filter_options(
    n_t: int, arw: float, rrw: float, phase_sigma_cycles: float, fix_ambiguities: bool,
    ratio_threshold: float, min_success_rate: float, max_failure_rate: float, known_ambiguities: bool,
    output_every: int, has_phases: bool, baselines_m: ArrayLike | None, slip_false_alarm: float | None,
    sensitivity: tuple[float, float] | None, misalignment_sigma_rad: float | None,
) -> tuple[_core.GyroGnssOptions, int, bool]:  # fmt: skip
    """The core's options of :func:`gyro_gnss_filter` from its arguments, checked in their order
    (``n_t`` gyro samples; ``has_phases``: phase observations given, which need baselines); the number of
    baselines, and whether ``sensitivity`` is given."""
    arw = scalar("arw", arw, minimum=0.0, maximum=MAX_GYRO_NOISE, unit="rad/s/sqrt(Hz)")
    rrw = scalar("rrw", rrw, minimum=0.0, maximum=MAX_GYRO_NOISE, unit="rad/s^2/sqrt(Hz)")
    sigma = scalar(
        "phase_sigma_cycles",
        phase_sigma_cycles,
        minimum=0.0,
        maximum=MAX_PHASE_SIGMA_CYCLES,
        strict=True,
        unit="cycles",
    )
    fix = flag("fix_ambiguities", fix_ambiguities)
    ratio = scalar("ratio_threshold", ratio_threshold, minimum=1.0)
    success = scalar("min_success_rate", min_success_rate, minimum=0.0, maximum=1.0)
    failure = scalar("max_failure_rate", max_failure_rate, minimum=0.0, maximum=0.1)
    known = flag("known_ambiguities", known_ambiguities)
    every = min(integer("output_every", output_every, minimum=1), max(n_t, 1))  # beyond n: first and last
    if has_phases and baselines_m is None:
        raise InvalidInputError("expected baselines_m with phase observations")
    b = np.zeros((0, 3)) if baselines_m is None else checked_baselines("baselines_m", baselines_m)
    if slip_false_alarm is None:
        slip = float("inf")
    else:
        alarm = scalar("slip_false_alarm", slip_false_alarm, minimum=0.0, maximum=1.0, strict=True)
        slip = float(chi2.isf(alarm, max(len(b), 1)))
    sens = None if sensitivity is None else _checked_sensitivity(sensitivity)
    mis = (
        None
        if misalignment_sigma_rad is None
        else scalar("misalignment_sigma_rad", misalignment_sigma_rad, minimum=0.0, strict=True, unit="rad")
    )
    options = _core.GyroGnssOptions(
        arw=arw,
        rrw=rrw,
        baselines=b,
        phase_sigma=sigma,
        fix_enabled=fix,
        ratio_threshold=ratio,
        min_success_rate=success,
        slip_threshold=slip,
        known_ambiguities=known,
        output_every=every,
        sensitivity=sens,
        misalignment_sigma=mis,
        max_failure_rate=failure,
    )
    return options, len(b), sens is not None


def _result(d: _core.GyroGnssRun, *, with_true_covariance: bool) -> GyroGnssResult:
    """The :class:`GyroGnssResult` of the core's run (its outputs checked finite)."""
    finite_outputs(
        "gyro_gnss_filter",
        quaternions=d.quaternion,
        drift=d.drift,
        covariance=d.covariance,
        misalignment=d.misalignment,
    )
    return GyroGnssResult(
        t=d.t,
        rotation=Rotation.from_quat(d.quaternion),
        drift=d.drift,
        covariance=d.covariance,
        true_covariance=d.true_covariance if with_true_covariance else None,
        misalignment=d.misalignment,
        misalignment_covariance=d.misalignment_covariance,
        n_float=d.n_float.astype(np.int64),
        n_fixed=d.n_fixed.astype(np.int64),
        fixes=[FixAttempt(f.t, f.accepted, f.ratio, f.success_rate, f.values) for f in d.fixes],
        slips=d.slips,
        nis=d.nis,
    )
