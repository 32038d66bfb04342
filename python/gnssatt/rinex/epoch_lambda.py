"""Epoch-by-epoch double-difference baselines fixed by LAMBDA, for moving platforms (no ambiguity carried
across epochs unless asked), and attitude from the fixed baselines of three or more antennas.

Model, one epoch, all receivers' phases and codes moved to the reference receiver's sampling instant with
the range rate (:meth:`~gnssatt.rinex.align.Aligned.phase_at_common_time`); receiver 0 is the reference
antenna at ``x0``, rover ``i`` at ``x0 + b_i``, satellite ``k``, reference satellite ``q`` (highest
elevation; in continuity mode kept while it stays usable):

``lambda DD phi_i = DD rho(b_i) + lambda N_i + e``, ``DD P_i = DD rho(b_i) + e``,
``DD rho(b) = (|s_k - x0 - b| - |s_k - x0|) - (|s_q - x0 - b| - |s_q - x0|)`` (exact ranges, so kilometre
baselines work too), linearised with ``A = -(u_k - u_q)`` and iterated.

Covariance: the single differences of rovers i and j share antenna 0, ``cov(SD_i, SD_j) = sigma^2 (delta_ij
+ 1)``, so the double differences of all baselines have ``sigma^2 K (x) C`` with ``K = I + 1 1^T`` over the
baselines and ``C = I + 1 1^T`` over the satellites. With one design for every baseline the least-squares
float solution separates by baseline and its covariance is ``K (x) Q1``:
``b_float`` from the codes, ``N_float = (DD phi - DD rho(b_float) / lambda)``,
``Q1_NN = (sigma_phi^2 C + A Q_b A^T) / lambda^2``, ``Q_b = sigma_P^2 (A^T C^-1 A)^-1``,
``Q1_bN = -Q_b A^T / lambda``; the fixed baseline is ``b_float - Q_bN Q_NN^-1 (N_float - N_fix)``, then
re-iterated on the phases alone.

Integer fix and validation:

- without body baselines (two antennas, baseline-direction mode): LAMBDA on the joint ambiguity vector,
  accepted when the ratio test passes (:func:`gnssatt.ratio_test`) and the bootstrapped success rate is at
  least ``min_success_rate``;
- with body baselines (attitude mode): the known array geometry constrains the fix. The ``candidates``
  best integer vectors of each baseline (:func:`gnssatt.lambda_ils`) are kept when their fixed baseline
  length is within ``length_tolerance_m`` of the body length; every combination of kept candidates is
  scored with the objective of the multivariate constrained LAMBDA (Teunissen 2010, J. Geodesy 84:
  ``||a - z||^2_{Q_NN} + ||B(z) - R B_body||^2 / sigma_B^2``, ``R`` from Wahba's problem weighted by the
  squared lengths, ``sigma_B = length_tolerance_m / 3``), evaluated on the candidate lists rather than
  by a bounded search; the best combination is accepted when the second-best objective is ``ratio_threshold``
  times larger. Epochs with no combination keep the float baselines (``fixed`` False).

Every epoch reports the bootstrapped success rate of its float ambiguities
(:func:`gnssatt.bootstrap_success_rate`, unconstrained: a lower bound of the ILS success rate).

Continuity (``continuity=True``): integers fixed at one epoch are held on the next for every satellite
whose arc continues without a slip at any receiver (re-expressed when the reference satellite changes);
with three or more held double differences per baseline the baseline comes from them and the new
satellites are fixed on that baseline. Held integers whose phase residuals exceed five times the phase
sigma (an undetected slip) are dropped and the epoch is fixed afresh.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from gnssatt._arrays import flag, instance, integer, scalar, shaped
from gnssatt.ambiguity import bootstrap_success_rate, lambda_ils, ratio_test
from gnssatt.errors import InvalidInputError, NearDegenerateWarning, RinexError
from gnssatt.rinex.align import Aligned
from gnssatt.rinex.baseline import fixing_settings
from gnssatt.sim.frames import dcm_ecef_from_enu, ecef_to_geodetic
from gnssatt.vector_attitude import wahba

__all__ = ["EpochSolutions", "epoch_lambda"]

#: Largest body coordinate and length tolerance accepted, m; most integer candidates per baseline.
MAX_BODY_M = 1e4
MAX_CANDIDATES = 100_000


@dataclass(frozen=True)
class EpochSolutions:
    """Per-epoch LAMBDA baselines.

    Attributes
    ----------
    baselines_enu_m
        (n_ep, n_rx - 1, 3) rover minus reference antenna, East-North-Up at the reference antenna, m;
        fixed where ``fixed``, else float; NaN where fewer than 4 satellites.
    fixed
        (n_ep,) the integers were accepted (or held, in continuity mode).
    held
        (n_ep,) the integers came from earlier epochs (continuity mode).
    ratio
        (n_ep,) second-best over best objective (NaN where not tried; ``inf`` for held integers).
    success_rate
        (n_ep,) bootstrapped success rate of the epoch's float ambiguities (unconstrained).
    satellites
        (n_ep,) satellites in the double differences (reference included).
    rotation_enu_from_body
        (n_ep, 3, 3) attitude from the baselines (attitude mode), NaN where unsolved; None otherwise.
    """

    baselines_enu_m: NDArray[np.float64]
    fixed: NDArray[np.bool_]
    held: NDArray[np.bool_]
    ratio: NDArray[np.float64]
    success_rate: NDArray[np.float64]
    satellites: NDArray[np.int64]
    rotation_enu_from_body: NDArray[np.float64] | None


@dataclass
class _Epoch:
    """One epoch's double-difference problem for every baseline (shared satellites)."""

    x0: NDArray[np.float64]  # (3,) reference antenna, ECEF
    sat: NDArray[np.float64]  # (n, 3) satellites (reference q first), ECEF
    phi_m: NDArray[np.float64]  # (nb, m) lambda DD phase, m
    code_m: NDArray[np.float64]  # (nb, m) DD code, m
    lam: float
    ids: list[int]  # satellite indices of the m double differences (q excluded)
    q: int


def _dd_model(ep: _Epoch, b: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """DD ranges (m,) and design (m, 3) at baseline ``b`` (ECEF)."""
    d0 = ep.sat - ep.x0
    d1 = d0 - b
    r0 = np.linalg.norm(d0, axis=1)
    r1 = np.linalg.norm(d1, axis=1)
    sd = r1 - r0
    u = d1 / r1[:, None]
    return sd[1:] - sd[0], -(u[1:] - u[0])


def _gls(a: NDArray[np.float64], cinv: NDArray[np.float64], y: NDArray[np.float64]) -> NDArray[np.float64]:
    return np.linalg.solve(a.T @ cinv @ a, a.T @ cinv @ y)


def _code_baseline(ep: _Epoch, i: int, cinv: NDArray[np.float64]) -> NDArray[np.float64]:
    b = np.zeros(3)
    for _ in range(6):
        f, a = _dd_model(ep, b)
        db = _gls(a, cinv, ep.code_m[i] - f)
        b = b + db
        if np.linalg.norm(db) < 1e-4:
            break
    return b


def _phase_baseline(
    ep: _Epoch, i: int, n_fix: NDArray[np.float64], b0: NDArray[np.float64], cinv: NDArray[np.float64]
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Baseline from the phases with known integers; returns it and the phase residuals (m)."""
    b = b0.copy()
    y = ep.phi_m[i] - ep.lam * n_fix
    for _ in range(4):
        f, a = _dd_model(ep, b)
        db = _gls(a, cinv, y - f)
        b = b + db
        if np.linalg.norm(db) < 1e-6:
            break
    f, _ = _dd_model(ep, b)
    return b, y - f


def _kron_k(nb: int) -> NDArray[np.float64]:
    return np.eye(nb) + np.ones((nb, nb))


@dataclass
class _Float:
    b: NDArray[np.float64]  # (nb, 3) ECEF
    a: NDArray[np.float64]  # (nb, m) cycles
    q1_nn: NDArray[np.float64]  # (m, m)
    q1_bn: NDArray[np.float64]  # (3, m)


def _float(ep: _Epoch, sigma_phase_m: float, sigma_code_m: float) -> _Float:
    nb, m = ep.phi_m.shape
    c = np.eye(m) + np.ones((m, m))
    cinv = np.linalg.inv(c)
    bs = np.array([_code_baseline(ep, i, cinv) for i in range(nb)])
    amb = np.empty((nb, m))
    for i in range(nb):
        f, _ = _dd_model(ep, bs[i])
        amb[i] = (ep.phi_m[i] - f) / ep.lam
    _, a = _dd_model(ep, bs[0])
    q_b = sigma_code_m**2 * np.linalg.inv(a.T @ cinv @ a)
    q_nn = (sigma_phase_m**2 * c + a @ q_b @ a.T) / ep.lam**2
    q_bn = -q_b @ a.T / ep.lam
    return _Float(bs, amb, 0.5 * (q_nn + q_nn.T), q_bn)


def _condition(fl: _Float, i: int, z: NDArray[np.float64]) -> NDArray[np.float64]:
    """(k, 3) baselines of rover i conditioned on candidate rows z (k, m)."""
    return fl.b[i] - (fl.q1_bn @ np.linalg.solve(fl.q1_nn, (fl.a[i] - z).T)).T


def _fix_unconstrained(
    fl: _Float, ratio_threshold: float, success: float, min_success_rate: float
) -> tuple[NDArray[np.float64] | None, float]:
    nb, m = fl.a.shape
    q = np.kron(_kron_k(nb), fl.q1_nn)
    t = ratio_test(fl.a.reshape(-1), q, threshold=ratio_threshold)
    ok = t.accepted and success >= min_success_rate
    return (t.fixed.reshape(nb, m).astype(np.float64) if ok else None), float(t.ratio)


def _fix_constrained(
    fl: _Float,
    body: NDArray[np.float64],
    to_enu: NDArray[np.float64],
    *,
    candidates: int,
    length_tolerance_m: float,
    ratio_threshold: float,
) -> tuple[NDArray[np.float64] | None, float]:
    nb = fl.a.shape[0]
    lengths = np.linalg.norm(body, axis=1)
    kept: list[NDArray[np.int64]] = []
    for i in range(nb):
        z, _ = lambda_ils(fl.a[i], 2.0 * fl.q1_nn, candidates=candidates)
        b = _condition(fl, i, z.astype(np.float64))
        ok = np.abs(np.linalg.norm(b, axis=1) - lengths[i]) <= length_tolerance_m
        kept.append(z[ok][: int(20_000 ** (1.0 / nb))])  # at most 20000 combinations
        if not ok.any():
            return None, float("nan")
    grids = np.meshgrid(*[np.arange(len(k)) for k in kept], indexing="ij")
    combo = np.stack([g.reshape(-1) for g in grids], axis=1)  # (n_combo, nb)
    zc = np.stack([kept[i][combo[:, i]] for i in range(nb)], axis=1).astype(np.float64)  # (n_combo, nb, m)
    bc = np.stack([_condition(fl, i, zc[:, i]) for i in range(nb)], axis=1) @ to_enu  # (n_combo, nb, 3)
    qinv = np.linalg.inv(np.kron(_kron_k(nb), fl.q1_nn))
    da = (fl.a[None] - zc).reshape(len(zc), -1)
    norm_a = np.einsum("ci,ij,cj->c", da, qinv, da)
    if nb >= 2:
        with warnings.catch_warnings():  # wrong candidates may be near-parallel: they score badly anyway
            warnings.simplefilter("ignore", NearDegenerateWarning)
            rot = wahba(np.broadcast_to(body, bc.shape), bc, lengths**2).rotation.as_matrix()
        fitted = np.einsum("cij,nj->cni", rot.reshape(-1, 3, 3), body)
    else:  # one baseline: only its length constrains (already screened)
        fitted = bc
    sigma_b = length_tolerance_m / 3.0
    cost = norm_a + np.sum((bc - fitted) ** 2, axis=(1, 2)) / sigma_b**2
    order = np.argsort(cost)
    ratio = float(cost[order[1]] / cost[order[0]]) if len(order) > 1 else float("inf")
    if ratio < ratio_threshold:
        return None, ratio
    return zc[order[0]], ratio


def _to_enu(x0: NDArray[np.float64]) -> NDArray[np.float64]:
    lat, lon, _ = ecef_to_geodetic(x0)
    return dcm_ecef_from_enu(float(lat), float(lon))


def epoch_lambda(
    aligned: Aligned,
    baselines_body: ArrayLike | None = None,
    *,
    continuity: bool = False,
    sigma_phase_m: float = 0.003,
    sigma_code_m: float = 0.5,
    ratio_threshold: float = 3.0,
    candidates: int = 200,
    length_tolerance_m: float = 0.03,
    min_success_rate: float = 0.99,
) -> EpochSolutions:
    """Fix every epoch's double-difference ambiguities with LAMBDA (module docstring).

    Parameters
    ----------
    aligned
        Receivers on common epochs (:func:`~gnssatt.rinex.align_receivers`), one carrier wavelength.
    baselines_body
        (n_rx - 1, 3) antenna positions relative to the reference antenna in the body frame, m: enables the
        geometry-constrained fix and the attitude; None: unconstrained fix (baselines only).
    continuity
        Hold fixed integers along slip-free arcs (module docstring); False: every epoch on its own.
    sigma_phase_m, sigma_code_m
        Undifferenced phase and code standard deviations, m.
    ratio_threshold
        Acceptance threshold of the ratio test (unconstrained) or of the objective ratio (constrained).
    candidates
        Integer candidates per baseline in the constrained fix.
    length_tolerance_m
        Largest difference between a fixed baseline's length and its body length, m.
    min_success_rate
        Unconstrained fix: also require this bootstrapped success rate (the ratio test alone accepts
        wrong integers when the float solution is poor, as single-epoch L1 code is over kilometres).

    Raises
    ------
    RinexError
        Mixed wavelengths (GLONASS FDMA).
    InvalidTypeError
        ``aligned`` not an :class:`~gnssatt.rinex.align.Aligned`, another argument of the wrong kind.
    InvalidInputError
        Baselines not finite (n_rx - 1, 3) within ``MAX_BODY_M``, sigmas outside
        :data:`~gnssatt.rinex.baseline.SIGMA_PHASE_RANGE_M` / ``SIGMA_CODE_RANGE_M``, ``ratio_threshold``
        below 1, ``length_tolerance_m`` not positive, ``min_success_rate`` outside [0, 1],
        ``candidates < 2``.
    WorkLimitError
        ``candidates`` above ``MAX_CANDIDATES``.
    """
    al = instance("aligned", aligned, Aligned, "an Aligned (from align_receivers)")
    n_rx, n_ep, _ = al.phase_cycles.shape
    nb = n_rx - 1
    body = None
    if baselines_body is not None:
        body = shaped("baselines_body", baselines_body, f"({nb}, 3)", (nb, 3))
        if np.any(np.abs(body) > MAX_BODY_M):
            raise InvalidInputError(f"expected |baselines_body| <= {MAX_BODY_M} m per coordinate")
    continuity = flag("continuity", continuity)
    sigma_phase_m, sigma_code_m, ratio_threshold = fixing_settings(
        sigma_phase_m, sigma_code_m, ratio_threshold
    )
    candidates = integer("candidates", candidates, minimum=2, maximum=MAX_CANDIDATES)
    length_tolerance_m = scalar(
        "length_tolerance_m", length_tolerance_m, minimum=0.0, maximum=MAX_BODY_M, strict=True, unit="m"
    )
    min_success_rate = scalar("min_success_rate", min_success_rate, minimum=0.0, maximum=1.0)
    if np.ptp(al.wavelength_m) > 1e-9:
        raise RinexError(
            " and ".join(al.paths), None, "double differences need one wavelength: select CDMA systems"
        )
    lam = float(al.wavelength_m[0])
    phase = al.phase_at_common_time() * lam
    shift = -(al.clock_s - al.clock_s[:1])
    code = al.code_m - al.range_rate_m_s[None] * shift[..., None]
    ok = al.usable & np.all(np.isfinite(code), axis=0)
    arc = np.cumsum(np.any(al.slip, axis=0), axis=0)  # (n_ep, n_sat): slip at any receiver
    traj = al.epoch_position_ecef_m
    out = np.full((n_ep, nb, 3), np.nan)
    fixed = np.zeros(n_ep, dtype=bool)
    held_out = np.zeros(n_ep, dtype=bool)
    ratio = np.full(n_ep, np.nan)
    succ = np.full(n_ep, np.nan)
    nsat = np.zeros(n_ep, dtype=np.int64)
    rot = None if body is None else np.full((n_ep, 3, 3), np.nan)
    held: dict[tuple[int, int], NDArray[np.float64]] = {}  # (sat, arc) -> (nb,) integers against held_ref
    held_ref: tuple[int, int] | None = None
    for e in range(n_ep):
        sats = np.flatnonzero(ok[e])
        if sats.size < 4:
            held, held_ref = {}, None
            continue
        x0 = traj[0, e] if traj is not None and np.all(np.isfinite(traj[0, e])) else al.position_ecef_m[0]
        q = int(sats[np.argmax(al.elevation_rad[e, sats])])
        if continuity and held_ref is not None and held_ref[0] in sats and arc[e, held_ref[0]] == held_ref[1]:
            q = held_ref[0]
        ks = [int(k) for k in sats if k != q]
        order = [q, *ks]
        dphi = phase[1:, e, ks] - phase[:1, e, ks] - (phase[1:, e, q] - phase[0, e, q])[:, None]
        dcode = code[1:, e, ks] - code[:1, e, ks] - (code[1:, e, q] - code[0, e, q])[:, None]
        ep = _Epoch(x0, al.sat_ecef_m[0, e, order], dphi, dcode, lam, ks, q)
        to_enu = _to_enu(x0)
        m = len(ks)
        cinv = np.linalg.inv(np.eye(m) + np.ones((m, m)))
        nsat[e] = m + 1
        fl = _float(ep, sigma_phase_m, sigma_code_m)
        succ[e] = bootstrap_success_rate(np.kron(_kron_k(nb), fl.q1_nn))
        z: NDArray[np.float64] | None = None
        was_held = False
        if continuity and held_ref is not None:
            z, was_held = _from_held(ep, fl, held, held_ref, arc[e], cinv, sigma_phase_m), True
        if z is None:
            was_held = False
            if body is None:
                z, ratio[e] = _fix_unconstrained(fl, ratio_threshold, succ[e], min_success_rate)
            else:
                z, ratio[e] = _fix_constrained(
                    fl,
                    body,
                    to_enu,
                    candidates=candidates,
                    length_tolerance_m=length_tolerance_m,
                    ratio_threshold=ratio_threshold,
                )
        else:
            ratio[e] = np.inf
        if z is None:
            bl = fl.b
            held, held_ref = {}, None
        else:
            bl = np.array(
                [_phase_baseline(ep, i, z[i], _condition(fl, i, z[i][None])[0], cinv)[0] for i in range(nb)]
            )
            fixed[e], held_out[e] = True, was_held
            held = {(k, int(arc[e, k])): z[:, j] for j, k in enumerate(ks)}
            held_ref = (q, int(arc[e, q]))
        out[e] = bl @ to_enu
        if rot is not None and body is not None:
            w = np.linalg.norm(body, axis=1) ** 2
            rot[e] = wahba(body, out[e], w).rotation.as_matrix() if nb >= 2 else np.nan
    return EpochSolutions(out, fixed, held_out, ratio, succ, nsat, rot)


def _from_held(
    ep: _Epoch,
    fl: _Float,
    held: dict[tuple[int, int], NDArray[np.float64]],
    held_ref: tuple[int, int],
    arc: NDArray[np.int64],
    cinv: NDArray[np.float64],
    sigma_phase_m: float,
) -> NDArray[np.float64] | None:
    """Integers of this epoch from the held ones, or None when fewer than 3 remain valid."""
    nb, m = fl.a.shape
    # held integers are against the old reference r: N_kq = N_kr - N_qr (N_rr = 0)
    ref_key = (ep.q, int(arc[ep.q]))
    if ref_key[0] == held_ref[0]:
        n_qr = np.zeros(nb)
    elif ref_key in held:
        n_qr = held[ref_key]
    else:
        return None
    known = np.zeros(m, dtype=bool)
    z = np.zeros((nb, m))
    for j, k in enumerate(ep.ids):
        if k == held_ref[0] and int(arc[k]) == held_ref[1]:
            known[j], z[:, j] = True, -n_qr
        elif (k, int(arc[k])) in held:
            known[j], z[:, j] = True, held[(k, int(arc[k]))] - n_qr
    if known.sum() < 3:
        return None
    sub = _Epoch(ep.x0, ep.sat[np.r_[0, 1 + np.flatnonzero(known)]], ep.phi_m[:, known], ep.code_m[:, known],
                 ep.lam, [k for k, o in zip(ep.ids, known, strict=True) if o], ep.q)  # fmt: skip
    mk = int(known.sum())
    cinv_k = np.linalg.inv(np.eye(mk) + np.ones((mk, mk)))
    limit = 5.0 * sigma_phase_m * 2.0  # DD of four phases: sigma * 2
    for i in range(nb):
        b, res = _phase_baseline(sub, i, z[i, known], fl.b[i], cinv_k)
        if np.sqrt(np.mean(res**2)) > limit:
            return None
        if not known.all():
            f, _ = _dd_model(ep, b)
            a_new = (ep.phi_m[i, ~known] - f[~known]) / ep.lam
            z[i, ~known] = np.round(a_new)
            if np.any(np.abs(a_new - z[i, ~known]) > 0.25):
                return None
    return z
