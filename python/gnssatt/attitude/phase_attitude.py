"""Per-epoch attitude solutions from integer-fixed carrier-phase first differences, with their covariance:
the loosely coupled input of :func:`gnssatt.gyro_gnss_filter`.

Each epoch is solved on its own by :func:`gnssatt.matrix_attitude` (``method="ml"``: the least-squares
minimiser of the range-difference residuals, by Gauss-Newton on SO(3)). Frames and signs:
``docs/conventions.md`` ("Gyro + GNSS filter").
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.spatial.transform import Rotation

from gnssatt._arrays import instance, integer_array, scalar, shaped, unit_rows
from gnssatt.attitude.matrix_method import matrix_attitude
from gnssatt.errors import ConvergenceError, DegenerateGeometryError, InvalidInputError
from gnssatt.geometry import MAX_BASELINE_M, checked_baselines
from gnssatt.observations import AttitudeFixes, PhaseObservations

__all__ = ["MAX_SIGMA_CYCLES", "phase_attitude_fixes"]

#: Largest accepted phase noise, cycles: beyond a few cycles no integer is fixed anyway, and the covariance,
#: which grows with its square, stays far from overflow.
MAX_SIGMA_CYCLES = 1e3


def phase_attitude_fixes(
    phases: PhaseObservations,
    baselines_m: ArrayLike,
    ambiguities: ArrayLike,
    *,
    phase_sigma_cycles: float,
) -> AttitudeFixes:
    """Attitude (body -> ECI) and its covariance at each epoch of ``phases`` that fixes the attitude.

    Parameters
    ----------
    phases
        First differences slave ``i`` minus master, cycles, with ECI lines of sight receiver -> satellite
        (:class:`~gnssatt.sim.attitude_scenario.PhaseObservations`):
        ``phase_ik = -los_k . (R b_i) / lambda_k + N_ik + v``.
    baselines_m
        (m, 3) body baselines slave minus master, m.
    ambiguities
        (n_rows, m) integers ``N_ik`` of the rows of ``phases``, as fixed by the user (e.g. with
        :func:`gnssatt.lambda_ils`); in simulation ``phases.ambiguity`` (the truth), or zeros with
        :meth:`~gnssatt.sim.attitude_scenario.PhaseObservations.without_ambiguities`.
    phase_sigma_cycles
        Standard deviation of one first difference, cycles, in (0, :data:`MAX_SIGMA_CYCLES`]; first
        differences are taken as independent, as the simulator and the filter take them.

    Returns
    -------
    AttitudeFixes
        ``t`` the solved epochs, ``rotation`` body -> ECI, ``covariance`` (n, 3, 3) rad^2 of the body-frame
        rotation-vector error ``eta`` with ``R_true = R_hat exp([eta x])``. The filter's loosely coupled
        model ``R_m = R_true exp([eta_m x])`` has ``eta_m = -eta``, with the same covariance.

    Notes
    -----
    The range difference passed to :func:`~gnssatt.matrix_attitude` is
    ``r_ik = -(phase_ik - N_ik) lambda_k = b_i . (R^T los_k)`` m: how much closer slave ``i`` is to
    satellite ``k`` than the master (the phase grows with range). Its derivative in ``eta`` at ``R_hat`` is
    ``H_ik = (b_i x s_k)^T`` m/rad with ``s_k = R_hat^T los_k`` (body frame). ``matrix_attitude`` minimises
    the unweighted sum of squared residuals, so the covariance is the Gauss-Newton sandwich
    ``(H^T H)^-1 H^T W H (H^T H)^-1`` with ``W = diag((phase_sigma_cycles lambda_k)^2)``; with one wavelength
    (GPS only) this is ``sigma^2 (H^T H)^-1``. GLONASS wavelengths differ by up to about 1 %, so the
    unweighted estimate is within a fraction of a percent of the weighted one.

    Epochs with fewer than 2 satellites, and epochs whose geometry does not fix the attitude (two
    satellites with a coplanar array; :class:`~gnssatt.errors.DegenerateGeometryError` from
    ``matrix_attitude``), are skipped: they are absent from ``t``.

    Raises
    ------
    InvalidInputError
        Wrong shapes or non-finite values (in the arguments or the fields of ``phases``), epoch indices
        outside ``[0, len(phases.epoch_t))``, lines of sight that are not unit vectors, non-positive
        wavelengths, non-integer ambiguities, range differences ``(phase - N) lambda`` beyond
        :data:`~gnssatt.geometry.MAX_BASELINE_M`, baselines outside the limits of
        :func:`~gnssatt.geometry.checked_baselines`, ``phase_sigma_cycles`` outside (0,
        :data:`MAX_SIGMA_CYCLES`];
        :class:`~gnssatt.errors.InvalidTypeError` for a ``phases`` that is not
        :class:`~gnssatt.sim.attitude_scenario.PhaseObservations` or values that are not real numbers.
    ConvergenceError
        A covariance that is not finite (an information matrix too small to invert).

    Examples
    --------
    One epoch, four satellites, noise-free phases of a 1 m triangle with known integers: the fix is the true
    attitude, and its covariance grows with ``sigma_cycles^2``:

    >>> import numpy as np
    >>> from scipy.spatial.transform import Rotation
    >>> from gnssatt.attitude.phase_attitude import phase_attitude_fixes
    >>> from gnssatt.observations import PhaseObservations
    >>> from gnssatt.sim import equilateral_triangle, random_los
    >>> baselines = equilateral_triangle(1.0)[1:]  # (2, 3) m, body
    >>> los = random_los(1, 4, min_elevation_deg=15.0)  # (4, 3) unit vectors, ECI
    >>> true = Rotation.from_euler("ZYX", [30.0, 5.0, -2.0], degrees=True)  # body -> ECI
    >>> ints = np.array([[3, -7], [12, 0], [-5, 4], [8, 8]])  # (4, 2) N_ik
    >>> phase = -(true.inv().apply(los) @ baselines.T) / 0.19 + ints  # (4, 2) cycles
    >>> rows, epoch = np.arange(4), np.zeros(4, int)  # one row per satellite, all at epoch 0
    >>> obs = PhaseObservations(np.array([0.0]), epoch, rows, los, np.full(4, 0.19), phase, ints, rows)
    >>> fixes = phase_attitude_fixes(obs, baselines, ints, phase_sigma_cycles=0.01)
    >>> fixes.t, np.round(fixes.rotation.as_euler("ZYX", degrees=True), 6) + 0.0
    (array([0.]), array([[30.,  5., -2.]]))
    >>> twice = phase_attitude_fixes(obs, baselines, ints, phase_sigma_cycles=0.02)
    >>> bool(np.allclose(twice.covariance, 4.0 * fixes.covariance))
    True
    """
    obs = instance("phases", phases, PhaseObservations, "PhaseObservations")
    b = checked_baselines("baselines_m", baselines_m)
    m = len(b)
    if m == 0:
        raise InvalidInputError(f"expected baselines_m of shape (m, 3) with m >= 1, got {b.shape}")
    epoch_t, epoch, los_all, wavelength, phase = _checked_rows(obs, m)
    n_rows = len(epoch)
    amb = integer_array("ambiguities", ambiguities, f"(n_rows, m) = ({n_rows}, {m})", (n_rows, m))
    sigma = scalar("phase_sigma_cycles", phase_sigma_cycles, minimum=0.0, strict=True, unit="cycles")
    if sigma > MAX_SIGMA_CYCLES:
        raise InvalidInputError(
            f"expected phase_sigma_cycles <= {MAX_SIGMA_CYCLES:g} cycles, got {sigma} cycles"
        )
    range_diffs = _range_diffs(phase, amb, wavelength)
    order = np.argsort(epoch, kind="stable")
    starts = np.searchsorted(epoch[order], np.arange(len(epoch_t) + 1))
    t, quats, covs = [], [], []
    for e in range(len(epoch_t)):
        rows = order[starts[e] : starts[e + 1]]
        if len(rows) < 2:
            continue
        fix = _epoch_fix(b, los_all[rows], range_diffs[rows], sigma * wavelength[rows], e, float(epoch_t[e]))
        if fix is None:
            continue
        t.append(epoch_t[e])
        quats.append(fix[0])
        covs.append(fix[1])
    return AttitudeFixes(
        np.array(t, dtype=np.float64),
        Rotation.from_quat(np.array(quats).reshape(-1, 4)),
        np.array(covs, dtype=np.float64).reshape(-1, 3, 3),
    )


def _checked_rows(
    obs: PhaseObservations, m: int
) -> tuple[
    NDArray[np.float64], NDArray[np.int64], NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]
]:
    """The epoch times (n_e,) and, per row, the epoch index, line of sight, wavelength (m) and the phases
    of the ``m`` baselines (cycles) of ``obs``."""
    epoch_t = shaped("phases.epoch_t", obs.epoch_t, "(n_e,)", (None,))
    n_rows = len(np.atleast_1d(obs.epoch))
    rows_shape = f"(n_rows,) = ({n_rows},)"
    epoch = integer_array("phases.epoch", obs.epoch, rows_shape, (n_rows,))
    if np.any((epoch < 0) | (epoch >= len(epoch_t))):
        k = int(np.flatnonzero((epoch < 0) | (epoch >= len(epoch_t)))[0])
        raise InvalidInputError(f"expected phases.epoch in [0, {len(epoch_t)}), got {epoch[k]} at row {k}")
    los_all = unit_rows("phases.los", obs.los, f"(n_rows, 3) = ({n_rows}, 3)", (n_rows, 3))
    wavelength = shaped("phases.wavelength", obs.wavelength, rows_shape, (n_rows,))
    if np.any(wavelength <= 0.0):
        k = int(np.flatnonzero(wavelength <= 0.0)[0])
        raise InvalidInputError(f"expected phases.wavelength > 0 m, got {wavelength[k]} at row {k}")
    phase = shaped(
        "phases.phase",
        obs.phase,
        f"(n_rows, m) = ({n_rows}, {m}) for the {m} rows of baselines_m",
        (n_rows, m),
    )
    return epoch_t, epoch, los_all, wavelength, phase


def _range_diffs(
    phase: NDArray[np.float64], amb: NDArray[np.int64], wavelength: NDArray[np.float64]
) -> NDArray[np.float64]:
    """(n_rows, m) range differences, m, of the phases less the integers; none longer than a baseline."""
    with np.errstate(over="ignore"):
        range_diffs = -(phase - amb) * wavelength[:, None]  # (n_rows, m), m
    too_far = ~(np.abs(range_diffs) <= MAX_BASELINE_M)
    if np.any(too_far):
        at = tuple(int(i) for i in np.argwhere(too_far)[0])
        raise InvalidInputError(
            f"expected (phases.phase - ambiguities) * phases.wavelength at most {MAX_BASELINE_M:g} m in "
            f"magnitude (a range difference never exceeds the baseline), got {range_diffs[at]:.6g} m at {at}"
        )
    result: NDArray[np.float64] = range_diffs
    return result


def _epoch_fix(
    b: NDArray[np.float64], los: NDArray[np.float64], range_diffs: NDArray[np.float64],
    sigma_m: NDArray[np.float64], e: int, t_e: float,
) -> tuple[NDArray[np.float64], NDArray[np.float64]] | None:  # fmt: skip
    """One epoch's fix: the quaternion of :func:`matrix_attitude` (``"ml"``) on its rows (lines of sight,
    range differences (rows, m), phase sigmas in metres) and its 3 x 3 covariance; None when the rows'
    geometry is degenerate."""
    try:
        fix = matrix_attitude(b, los, range_diffs.T, method="ml")
    except DegenerateGeometryError:
        return None
    s_body = fix.rotation.inv().apply(los)
    h = np.cross(b[:, None, :], s_body[None, :, :]).reshape(-1, 3)  # rows (i, k), i-major
    w = np.tile(sigma_m**2, len(b))
    info_inv = np.linalg.inv(h.T @ h)
    cov = info_inv @ (h.T * w) @ h @ info_inv
    if not np.all(np.isfinite(cov)):
        raise ConvergenceError(
            f"phase_attitude_fixes: the covariance at epoch {e} (t = {t_e} s) is not finite; the "
            f"information H^T H has eigenvalues {np.linalg.eigvalsh(h.T @ h).tolist()} m^2/rad^2"
        )
    return fix.rotation.as_quat(), 0.5 * (cov + cov.T)
