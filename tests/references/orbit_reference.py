"""Slow numpy reference of the tightly coupled orbit filter
(:func:`gnssatt.orbit.determination.orbit_filter`), written out independently of the Rust core for tests
and benchmarks: the same equations (ICD model + RK4 with variational equations, Van Loan by
``scipy.linalg.expm``, Joseph update, between-satellite differences with ``D R D^T``), one epoch at a
time."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray
from scipy.linalg import block_diag, expm

from gnssatt.observations import SpaceborneMeasurements
from gnssatt.orbit import GlonassModel


def _accel(m: GlonassModel, r: NDArray[np.float64], v: NDArray[np.float64]) -> NDArray[np.float64]:
    rn = np.linalg.norm(r)
    a = -m.gm_m3_s2 / rn**3
    b = 1.5 * m.j2 * m.gm_m3_s2 * m.equatorial_radius_m**2 / rn**5
    z2 = 5 * r[2] ** 2 / rn**2
    w = m.omega_rad_s
    return np.array(
        [
            (a - b * (1 - z2) + w * w) * r[0] + 2 * w * v[1],
            (a - b * (1 - z2) + w * w) * r[1] - 2 * w * v[0],
            (a - b * (3 - z2)) * r[2],
        ]
    ) + np.asarray(m.lunisolar_m_s2)


def _jacobian(m: GlonassModel, r: NDArray[np.float64]) -> NDArray[np.float64]:
    """Central differences of the acceleration (independent of the Rust analytic Jacobian)."""
    f = np.zeros((6, 6))
    f[:3, 3:] = np.eye(3)
    zero = np.zeros(3)
    for j in range(3):
        h = np.zeros(3)
        h[j] = 1.0
        f[3:, j] = (_accel(m, r + h, zero) - _accel(m, r - h, zero)) / 2.0
    w = m.omega_rad_s
    f[3, 4], f[4, 3] = 2 * w, -2 * w
    return f


def _deriv(m: GlonassModel, y: NDArray[np.float64]) -> NDArray[np.float64]:
    x, phi = y[:6], y[6:].reshape(6, 6)
    return np.concatenate([x[3:], _accel(m, x[:3], x[3:]), (_jacobian(m, x[:3]) @ phi).ravel()])


def tight_filter(
    d: SpaceborneMeasurements,
    x0: NDArray[np.float64],
    p0: NDArray[np.float64],
    *,
    accel_psd_m2_s3: float,
    step_s: float,
    model: GlonassModel | None = None,
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """States (n_t, 6), covariances (n_t, 6, 6), NIS (n_t,) (NaN without update)."""
    m = model if model is not None else GlonassModel()
    x, p = x0.astype(float).copy(), p0.astype(float).copy()
    qc = np.diag([0, 0, 0] + [accel_psd_m2_s3] * 3)
    n_t = d.times_s.size
    xs, ps, nis = np.empty((n_t, 6)), np.empty((n_t, 6, 6)), np.full(n_t, np.nan)
    for k in range(n_t):
        if k > 0:
            dt = d.times_s[k] - d.times_s[k - 1]
            n = max(int(np.ceil(dt / step_s)), 1)
            h = dt / n
            for _ in range(n):
                f = _jacobian(m, x[:3])
                big = expm(np.block([[-f, qc], [np.zeros((6, 6)), f.T]]) * h)
                phi_vl = big[6:, 6:].T
                qd = phi_vl @ big[:6, 6:]
                y = np.concatenate([x, np.eye(6).ravel()])
                k1 = _deriv(m, y)
                k2 = _deriv(m, y + 0.5 * h * k1)
                k3 = _deriv(m, y + 0.5 * h * k2)
                k4 = _deriv(m, y + h * k3)
                y = y + h / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
                x, phi = y[:6], y[6:].reshape(6, 6)
                p = phi @ p @ phi.T + 0.5 * (qd + qd.T)
        rows_nu, rows_h, blocks_code, blocks_rate = [], [], [], []
        rate_nu, rate_h = [], []
        for s in np.unique(d.system):
            idx = np.flatnonzero(d.visible[k] & (d.system == s))
            if idx.size < 2:
                continue
            sp, sv = d.sat_position_m[k, idx], d.sat_velocity_m_s[k, idx]
            dr = sp - x[:3]
            rho = np.linalg.norm(dr, axis=1)
            u = dr / rho[:, None]
            dv = sv - x[3:]
            rr = np.sum(u * dv, axis=1)
            h_code = np.hstack([-u, np.zeros((idx.size, 3))])
            h_rate = np.hstack([-(dv - u * rr[:, None]) / rho[:, None], -u])
            lam = d.wavelength_m[idx]
            res_code = d.pseudorange_m[k, idx] - rho
            res_rate = -lam * d.doppler_hz[k, idx] - rr
            diff = np.hstack([-np.ones((idx.size - 1, 1)), np.eye(idx.size - 1)])
            rows_nu.append(diff @ res_code)
            rows_h.append(diff @ h_code)
            blocks_code.append(d.code_sigma_m**2 * diff @ diff.T)
            rate_nu.append(diff @ res_rate)
            rate_h.append(diff @ h_rate)
            blocks_rate.append(diff @ np.diag((lam * d.doppler_sigma_hz) ** 2) @ diff.T)
        if rows_nu:
            nu = np.concatenate(rows_nu + rate_nu)
            hm = np.vstack(rows_h + rate_h)
            r = block_diag(*blocks_code, *blocks_rate)
            s_mat = hm @ p @ hm.T + r
            gain = np.linalg.solve(s_mat, hm @ p).T
            nis[k] = nu @ np.linalg.solve(s_mat, nu)
            x = x + gain @ nu
            ikh = np.eye(6) - gain @ hm
            p = ikh @ p @ ikh.T + gain @ r @ gain.T
            p = 0.5 * (p + p.T)
        xs[k], ps[k] = x, p
    return xs, ps, nis
