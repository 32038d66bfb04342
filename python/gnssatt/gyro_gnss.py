"""Gyro + multi-antenna GNSS attitude filter (seed 003, chapters 2-3), run by the Rust core.

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
from gnssatt._arrays import float_array
from gnssatt.errors import InvalidInputError
from gnssatt.sim.attitude_scenario import AttitudeFixes, PhaseObservations

__all__ = ["FixAttempt", "GyroGnssResult", "gyro_gnss_filter", "gyro_propagate"]


def gyro_propagate(q0: ArrayLike, t: ArrayLike, rates: ArrayLike) -> NDArray[np.float64]:
    """Attitude quaternions (n, 4) scalar-last, body -> reference, at ``t`` (s) from ``q0`` with the body
    rates ``rates`` (n, 3) rad/s, ``rates[k]`` held over ``[t[k], t[k+1]]`` (exact for constant rates)."""
    return _core.gyro_propagate(
        float_array("q0", q0, ndim=1, shape="(4,)"),
        float_array("t", t, ndim=1, shape="(n,)"),
        float_array("rates", rates, ndim=2, shape="(n, 3)"),
    )


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
        """(n, 6) true errors ``[dtheta, ddrift]``, filter sign: ``R_true = R_hat exp([dtheta x])``."""
        dtheta = (self.rotation.inv() * true_rotation).as_rotvec()
        return np.hstack([dtheta, np.asarray(true_drift, dtype=np.float64) - self.drift])

    def nees(self, errors: ArrayLike, *, true: bool = False) -> NDArray[np.float64]:
        """(n,) ``e^T P^-1 e`` with the filter's covariance (or the true-error covariance if ``true``)."""
        p = self.true_covariance if true else self.covariance
        if p is None:
            raise InvalidInputError("no true-error covariance: run with sensitivity=(...)")
        e = np.asarray(errors, dtype=np.float64)
        return np.einsum("ki,ki->k", e, np.linalg.solve(p, e[..., None])[..., 0])


def _empty_phases(m: int) -> tuple[Any, ...]:
    return (
        np.zeros(0),
        np.zeros(0, np.int64),
        np.zeros(0, np.int64),
        np.zeros((0, 3)),
        np.zeros(0),
        np.zeros((0, m)),
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
    fix_ambiguities, ratio_threshold, min_success_rate
        LAMBDA fixing, accepted when the bootstrapped success rate of the float ambiguities reaches
        ``min_success_rate`` and the ratio test passes ``ratio_threshold``.
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
        Record every ``output_every``-th gyro sample (and the first and last).
    """
    if not isinstance(initial_rotation, Rotation) or not initial_rotation.single:
        raise TypeError("expected initial_rotation as a single scipy Rotation")
    t = float_array("gyro_t", gyro_t, ndim=1, shape="(n,)")
    w = float_array("gyro_rates", gyro_rates, ndim=2, shape="(n, 3)")
    p0 = float_array("initial_covariance", initial_covariance, ndim=2, shape="(6, 6)")
    b0 = float_array("initial_drift", initial_drift, ndim=1, shape="(3,)")
    if phases is not None and baselines_m is None:
        raise InvalidInputError("expected baselines_m with phase observations")
    b = (
        np.zeros((0, 3))
        if baselines_m is None
        else float_array("baselines_m", baselines_m, ndim=2, shape="(m, 3)")
    )
    m = len(b)
    if slip_false_alarm is None:
        slip = float("inf")
    elif not 0.0 < slip_false_alarm < 1.0:
        raise InvalidInputError(f"expected slip_false_alarm in (0, 1) or None, got {slip_false_alarm}")
    else:
        slip = float(chi2.isf(slip_false_alarm, max(m, 1)))
    if isinstance(output_every, bool) or not isinstance(output_every, int | np.integer) or output_every < 1:
        raise InvalidInputError(f"expected output_every as an integer >= 1, got {output_every!r}")
    if attitude_fixes is None:
        fx = (np.zeros(0), np.zeros((0, 4)), np.zeros((0, 3, 3)))
    else:
        fx = (
            float_array("attitude_fixes.t", attitude_fixes.t, ndim=1, shape="(n_fix,)"),
            attitude_fixes.rotation.as_quat().reshape(-1, 4),
            float_array(
                "attitude_fixes.covariance", attitude_fixes.covariance, ndim=3, shape="(n_fix, 3, 3)"
            ),
        )
    if phases is None:
        ph = _empty_phases(m)
    else:
        ph = (
            float_array("phases.epoch_t", phases.epoch_t, ndim=1, shape="(n_e,)"),
            np.ascontiguousarray(phases.epoch, dtype=np.int64),
            np.ascontiguousarray(phases.track, dtype=np.int64),
            float_array("phases.los", phases.los, ndim=2, shape="(n_rows, 3)"),
            float_array("phases.wavelength", phases.wavelength, ndim=1, shape="(n_rows,)"),
            float_array("phases.phase", phases.phase, ndim=2, shape="(n_rows, m)"),
        )
    sens = None if sensitivity is None else (float(sensitivity[0]), float(sensitivity[1]))
    mis = None if misalignment_sigma_rad is None else float(misalignment_sigma_rad)
    d = _core.gyro_gnss_filter(
        t,
        w,
        initial_rotation.as_quat(),
        b0,
        p0,
        float(arw),
        float(rrw),
        b,
        float(phase_sigma_cycles),
        bool(fix_ambiguities),
        float(ratio_threshold),
        float(min_success_rate),
        slip,
        bool(known_ambiguities),
        sens,
        mis,
        int(output_every),
        *fx,
        *ph,
    )
    return GyroGnssResult(
        t=d["t"],
        rotation=Rotation.from_quat(d["quaternion"]),
        drift=d["drift"],
        covariance=d["covariance"],
        true_covariance=d["true_covariance"] if sens is not None else None,
        misalignment=d["misalignment"],
        misalignment_covariance=d["misalignment_covariance"],
        n_float=d["n_float"].astype(np.int64),
        n_fixed=d["n_fixed"].astype(np.int64),
        fixes=[FixAttempt(*f) for f in d["fixes"]],
        slips=np.array(d["slips"], dtype=np.float64).reshape(-1, 3),
        nis=np.array(d["nis"], dtype=np.float64).reshape(-1, 3),
    )
