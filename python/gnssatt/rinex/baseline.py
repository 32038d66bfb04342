"""Double-difference baselines with LAMBDA-fixed ambiguities (static batch), and per-epoch baselines with
the fixed ambiguities.

Observation model (one band, equal wavelengths, i.e. CDMA systems), receivers 0 (base) and r (rover),
satellites k and the reference satellite q, each range computed at its receiver's own sampling instant:
``lambda DD phi = DD rho + lambda DD N + e``, ``DD P = DD rho + e``;
``DD x = (x_r^k - x_0^k) - (x_r^q - x_0^q)``.
Receiver and satellite clocks cancel; ionosphere and troposphere are left in (they cancel to centimetres
over a few kilometres). Single differences are uncorrelated with variance ``2 sigma^2``, so the double
differences of one epoch have covariance ``2 sigma^2 (I + 1 1^T)``. One DD ambiguity per satellite and arc
(a slip at either receiver or on the reference satellite starts a new arc). The float solution is the
weighted batch least squares over all epochs (static baseline); its ambiguities are fixed with LAMBDA
(:func:`gnssatt.ratio_test`) and the baseline conditioned on them:
``b_fix = b_float - Q_bN Q_NN^-1 (N_float - N_fix)`` (Teunissen 1995).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from gnssatt._arrays import instance, integer, scalar
from gnssatt.ambiguity import ratio_test
from gnssatt.errors import InvalidInputError, RinexError
from gnssatt.rinex.align import Aligned
from gnssatt.sim.frames import dcm_ecef_from_enu, ecef_to_geodetic

__all__ = ["EpochBaselines", "StaticBaseline", "epoch_baselines", "static_baseline"]

#: Accepted carrier-phase noise, m: below, the weights overflow; above a metre, phase is no longer phase.
SIGMA_PHASE_RANGE_M = (1e-6, 1.0)
#: Accepted pseudorange noise, m.
SIGMA_CODE_RANGE_M = (1e-4, 1e4)


@dataclass(frozen=True)
class StaticBaseline:
    """A static double-difference baseline.

    Attributes
    ----------
    baseline_ecef_m
        (3,) rover minus base, ECEF, m: the fixed solution when ``fixed``, else the float one.
    float_baseline_ecef_m
        (3,) float solution, m.
    baseline_enu_m
        (3,) the same vector in East-North-Up at the base, m.
    fixed
        The ratio test accepted the integer solution.
    ratio
        Ratio of the second-best to the best squared norm.
    reference_sat
        Reference satellite of the double differences.
    arcs
        (n_amb,) (satellite, arc index) of each ambiguity.
    float_ambiguities, fixed_ambiguities
        (n_amb,) cycles.
    ambiguity_covariance
        (n_amb, n_amb) cycles^2.
    epochs_used
        Epochs with at least one double difference.
    phase_residual_rms_m
        RMS of the phase residuals of the (fixed) solution, m.
    """

    baseline_ecef_m: NDArray[np.float64]
    float_baseline_ecef_m: NDArray[np.float64]
    baseline_enu_m: NDArray[np.float64]
    fixed: bool
    ratio: float
    reference_sat: str
    arcs: tuple[tuple[str, int], ...]
    float_ambiguities: NDArray[np.float64]
    fixed_ambiguities: NDArray[np.int64]
    ambiguity_covariance: NDArray[np.float64]
    epochs_used: int
    phase_residual_rms_m: float
    _arc_index: NDArray[np.int64]
    _ref_index: int


def _arcs(slip: NDArray[np.bool_], usable: NDArray[np.bool_]) -> NDArray[np.int64]:
    """(n_ep, n_sat) arc counter per satellite: increments at every slip (either receiver)."""
    return np.cumsum(slip & usable, axis=0)


def _ranges(
    al: Aligned, rover: int, x_rover: NDArray[np.float64]
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    d0 = al.sat_ecef_m[0] - al.position_ecef_m[0]
    dr = al.sat_ecef_m[rover] - x_rover
    rr = np.linalg.norm(dr, axis=-1)
    return np.linalg.norm(d0, axis=-1), rr, dr / rr[..., None]


def fixing_settings(
    sigma_phase_m: Any, sigma_code_m: Any, ratio_threshold: Any
) -> tuple[float, float, float]:
    """The intake of the settings every recorded-data fix shares (:func:`static_baseline` and
    :func:`gnssatt.rinex.epoch_lambda.epoch_lambda`): sigmas within ``SIGMA_PHASE_RANGE_M`` /
    ``SIGMA_CODE_RANGE_M``, the ratio threshold finite and at least 1."""
    lo, hi = SIGMA_PHASE_RANGE_M
    phase = scalar("sigma_phase_m", sigma_phase_m, minimum=lo, maximum=hi, unit="m")
    lo, hi = SIGMA_CODE_RANGE_M
    code = scalar("sigma_code_m", sigma_code_m, minimum=lo, maximum=hi, unit="m")
    return phase, code, scalar("ratio_threshold", ratio_threshold, minimum=1.0)


def static_baseline(
    aligned: Aligned,
    *,
    rover: int = 1,
    sigma_phase_m: float = 0.003,
    sigma_code_m: float = 0.5,
    ratio_threshold: float = 3.0,
    min_epochs_per_arc: int = 5,
) -> StaticBaseline:
    """Static baseline from receiver 0 (its position taken as known) to receiver ``rover`` (module docs).

    Raises
    ------
    InvalidTypeError
        ``aligned`` is not an :class:`Aligned`, or a number or count is of the wrong kind.
    InvalidInputError
        ``rover`` is not a receiver index other than 0, ``sigma_phase_m`` outside ``SIGMA_PHASE_RANGE_M``,
        ``sigma_code_m`` outside ``SIGMA_CODE_RANGE_M``, ``ratio_threshold`` below 1 or not finite.
    WorkLimitError
        ``min_epochs_per_arc`` above the number of epochs.
    RinexError
        Mixed wavelengths (GLONASS FDMA), no satellite usable as the reference, too few double differences.
    """
    al = instance("aligned", aligned, Aligned, "an Aligned (from align_receivers)")
    n_rx = al.phase_cycles.shape[0]
    rover = integer("rover", rover, minimum=1)
    if rover >= n_rx:
        raise InvalidInputError(f"expected rover < {n_rx} (the receivers of aligned), got {rover}")
    sigma_phase_m, sigma_code_m, ratio_threshold = fixing_settings(
        sigma_phase_m, sigma_code_m, ratio_threshold
    )
    min_epochs_per_arc = integer(
        "min_epochs_per_arc", min_epochs_per_arc, minimum=1, maximum=max(al.phase_cycles.shape[1], 1)
    )
    if np.ptp(al.wavelength_m) > 1e-9:
        raise RinexError(
            " and ".join(al.paths),
            None,
            "double differences need one wavelength: select CDMA systems (systems='G')",
        )
    lam = float(al.wavelength_m[0])
    usable = np.isfinite(al.phase_cycles[0]) & np.isfinite(al.phase_cycles[rover]) & al.usable
    slip = al.slip[0] | al.slip[rover]
    arc = _arcs(slip, usable)
    n_ep, n_sat = usable.shape
    # reference: the satellite with the most usable epochs, highest mean elevation breaking ties
    elev_sum = np.where(usable, np.degrees(al.elevation_rad), 0.0).sum(axis=0)
    score = usable.sum(axis=0) * 100.0 + elev_sum / np.maximum(usable.sum(axis=0), 1)
    q = int(np.argmax(score))
    if usable[:, q].sum() == 0:
        raise RinexError(
            " and ".join(al.paths), None, "no satellite usable as the double-difference reference"
        )
    # ambiguity per (satellite k, arc of k, arc of q); drop arcs shorter than min_epochs_per_arc
    keys: dict[tuple[int, int, int], int] = {}
    counts: dict[tuple[int, int, int], int] = {}
    for e in range(n_ep):
        if not usable[e, q]:
            continue
        for k in range(n_sat):
            if k != q and usable[e, k]:
                key = (k, int(arc[e, k]), int(arc[e, q]))
                counts[key] = counts.get(key, 0) + 1
    for key, c in sorted(counts.items()):
        if c >= min_epochs_per_arc:
            keys[key] = len(keys)
    n_amb = len(keys)
    if n_amb < 3:
        raise RinexError(" and ".join(al.paths), None, f"only {n_amb} double-difference arcs: need 3 or more")
    amb_of = np.full((n_ep, n_sat), -1, dtype=np.int64)
    for e in range(n_ep):
        if usable[e, q]:
            for k in range(n_sat):
                if k != q and usable[e, k]:
                    amb_of[e, k] = keys.get((k, int(arc[e, k]), int(arc[e, q])), -1)
    phase_m = lam * al.phase_cycles
    x_rover = al.position_ecef_m[rover].copy()
    n_par = 3 + n_amb
    epochs_used = 0
    for _ in range(3):
        r0, rr, u = _ranges(al, rover, x_rover)
        nmat = np.zeros((n_par, n_par))
        rhs = np.zeros(n_par)
        epochs_used = 0
        for e in range(n_ep):
            ks = np.flatnonzero(amb_of[e] >= 0)
            if ks.size == 0:
                continue
            epochs_used += 1
            ddm = (rr[e, ks] - r0[e, ks]) - (rr[e, q] - r0[e, q])
            a_b = -(u[e, ks] - u[e, q])
            dd_phi = (phase_m[rover, e, ks] - phase_m[0, e, ks]) - (phase_m[rover, e, q] - phase_m[0, e, q])
            dd_p = (al.code_m[rover, e, ks] - al.code_m[0, e, ks]) - (
                al.code_m[rover, e, q] - al.code_m[0, e, q]
            )
            m = ks.size
            cinv = np.linalg.inv(np.eye(m) + np.ones((m, m)))
            a_phi = np.zeros((m, n_par))
            a_phi[:, :3] = a_b
            a_phi[np.arange(m), 3 + amb_of[e, ks]] = lam
            w_phi = cinv / (2 * sigma_phase_m**2)
            nmat += a_phi.T @ w_phi @ a_phi
            rhs += a_phi.T @ w_phi @ (dd_phi - ddm)
            good = np.isfinite(dd_p)
            if np.all(good):
                a_p = np.zeros((m, n_par))
                a_p[:, :3] = a_b
                w_p = cinv / (2 * sigma_code_m**2)
                nmat += a_p.T @ w_p @ a_p
                rhs += a_p.T @ w_p @ (dd_p - ddm)
        q_all = np.linalg.inv(nmat)
        dx = q_all @ rhs
        x_rover = x_rover + dx[:3]
        if np.linalg.norm(dx[:3]) < 1e-4:
            break
    a_float = dx[3:]
    q_b = q_all[:3, :3]
    q_aa = 0.5 * (q_all[3:, 3:] + q_all[3:, 3:].T)
    q_ba = q_all[:3, 3:]
    test = ratio_test(a_float, q_aa, threshold=ratio_threshold)
    b_float = x_rover - al.position_ecef_m[0]
    b_fixed = b_float - q_ba @ np.linalg.solve(q_aa, a_float - test.fixed)
    del q_b
    b = b_fixed if test.accepted else b_float
    lat, lon, _ = ecef_to_geodetic(al.position_ecef_m[0])
    enu = dcm_ecef_from_enu(float(lat), float(lon)).T @ b
    arcs_list = [("", 0)] * n_amb
    for (k, ak, _aq), j in keys.items():
        arcs_list[j] = (al.sats[k], ak)
    res = epoch_baselines(al, _partial(al, b, q, amb_of, test.fixed if test.accepted else a_float, rover))
    return StaticBaseline(
        baseline_ecef_m=b,
        float_baseline_ecef_m=b_float,
        baseline_enu_m=enu,
        fixed=bool(test.accepted),
        ratio=float(test.ratio),
        reference_sat=al.sats[q],
        arcs=tuple(arcs_list),
        float_ambiguities=a_float,
        fixed_ambiguities=test.fixed,
        ambiguity_covariance=q_aa,
        epochs_used=epochs_used,
        phase_residual_rms_m=float(np.sqrt(np.nanmean(res.residual_m**2)))
        if res.residual_m.size
        else float("nan"),
        _arc_index=amb_of,
        _ref_index=q,
    )


@dataclass(frozen=True)
class EpochBaselines:
    """Per-epoch baselines with known ambiguities.

    Attributes
    ----------
    baseline_ecef_m
        (n_ep, 3) rover minus base, ECEF, m (NaN where fewer than 3 double differences).
    baseline_enu_m
        (n_ep, 3) East-North-Up at the base, m.
    satellites
        (n_ep,) satellites in the double differences (reference included).
    residual_m
        (n_ep, n_sat) phase residuals, m (NaN where unused).
    """

    baseline_ecef_m: NDArray[np.float64]
    baseline_enu_m: NDArray[np.float64]
    satellites: NDArray[np.int64]
    residual_m: NDArray[np.float64]


@dataclass(frozen=True)
class _Known:
    baseline: NDArray[np.float64]
    ref: int
    amb_of: NDArray[np.int64]
    amb: NDArray[np.float64]
    rover: int


def _partial(
    al: Aligned,
    b: NDArray[np.float64],
    q: int,
    amb_of: NDArray[np.int64],
    amb: NDArray[np.float64],
    rover: int,
) -> _Known:
    return _Known(np.asarray(b, dtype=np.float64), q, amb_of, np.asarray(amb, dtype=np.float64), rover)


def epoch_baselines(aligned: Aligned, known: StaticBaseline | _Known) -> EpochBaselines:
    """Baseline at every epoch from the double-difference phases with the ambiguities of a static solution
    (for a static pair: the time series the attitude command reports).

    Raises
    ------
    InvalidTypeError
        ``aligned`` is not an :class:`Aligned`, or ``known`` not a :class:`StaticBaseline`.
    """
    aligned = instance("aligned", aligned, Aligned, "an Aligned (from align_receivers)")
    known = instance("known", known, (StaticBaseline, _Known), "a StaticBaseline (from static_baseline)")
    if isinstance(known, StaticBaseline):
        known = _Known(
            known.baseline_ecef_m,
            known._ref_index,
            known._arc_index,
            (known.fixed_ambiguities if known.fixed else known.float_ambiguities).astype(np.float64),
            1,
        )
    al = aligned
    lam = float(al.wavelength_m[0])
    rover, q = known.rover, known.ref
    n_ep, n_sat = al.phase_cycles.shape[1:]
    out = np.full((n_ep, 3), np.nan)
    nsat = np.zeros(n_ep, dtype=np.int64)
    resid = np.full((n_ep, n_sat), np.nan)
    phase_m = lam * al.phase_cycles
    for e in range(n_ep):
        ks = np.flatnonzero(known.amb_of[e] >= 0)
        if ks.size < 3:
            continue
        x = al.position_ecef_m[0] + known.baseline
        for _ in range(3):
            r0 = np.linalg.norm(al.sat_ecef_m[0, e] - al.position_ecef_m[0], axis=-1)
            dr = al.sat_ecef_m[rover, e] - x
            rr = np.linalg.norm(dr, axis=-1)
            u = dr / rr[:, None]
            ddm = (rr[ks] - r0[ks]) - (rr[q] - r0[q])
            dd_phi = (phase_m[rover, e, ks] - phase_m[0, e, ks]) - (phase_m[rover, e, q] - phase_m[0, e, q])
            y = dd_phi - lam * known.amb[known.amb_of[e, ks]] - ddm
            a = -(u[ks] - u[q])
            m = ks.size
            w = np.linalg.inv(np.eye(m) + np.ones((m, m)))
            dx = np.linalg.solve(a.T @ w @ a, a.T @ w @ y)
            x = x + dx
            if np.linalg.norm(dx) < 1e-5:
                break
        out[e] = x - al.position_ecef_m[0]
        nsat[e] = m + 1
        resid[e, ks] = y - a @ dx
    lat, lon, _ = ecef_to_geodetic(al.position_ecef_m[0])
    enu = out @ dcm_ecef_from_enu(float(lat), float(lon))
    return EpochBaselines(out, enu, nsat, resid)
