"""Slow numpy reference of the gyro + GNSS filter of :mod:`gnssatt.attitude.gyro_gnss` (no ambiguity fixing,
no slip test, no sensitivity analysis), written from the equations rather than from the Rust code: the test
suite compares the two, and ``benches/python/gyro_gnss_speed.py`` times them.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray
from scipy.spatial.transform import Rotation

from gnssatt.observations import AttitudeFixes, PhaseObservations


def _skew(v: NDArray[np.float64]) -> NDArray[np.float64]:
    return np.array([[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]])


def _expm(a: NDArray[np.float64]) -> NDArray[np.float64]:
    """Matrix exponential by scaling and squaring of a 16-term Taylor series (scipy's Pade routine threads
    badly on 12 x 12 matrices)."""
    norm = np.max(np.sum(np.abs(a), axis=1))
    squarings = max(0, int(np.ceil(np.log2(norm / 0.25)))) if norm > 0 else 0
    a = a / 2.0**squarings
    term = np.eye(len(a))
    e = term.copy()
    for k in range(1, 17):
        term = term @ a / k
        e = e + term
    for _ in range(squarings):
        e = e @ e
    return e


def _discretize(w: NDArray[np.float64], arw: float, rrw: float, h: float) -> tuple[NDArray, NDArray]:
    f = np.zeros((6, 6))
    f[:3, :3] = -_skew(w)
    f[:3, 3:] = np.eye(3)
    qc = np.diag([arw**2] * 3 + [rrw**2] * 3)
    m = np.zeros((12, 12))
    m[:6, :6] = -f * h
    m[:6, 6:] = qc * h
    m[6:, 6:] = f.T * h
    e = _expm(m)
    phi = e[6:, 6:].T
    return phi, phi @ e[:6, 6:]


def run_reference(
    gyro_t: NDArray[np.float64],
    gyro_rates: NDArray[np.float64],
    q0: Rotation,
    drift0: NDArray[np.float64],
    p0: NDArray[np.float64],
    arw: float,
    rrw: float,
    baselines: NDArray[np.float64],
    sigma: float,
    fixes: AttitudeFixes | None,
    phases: PhaseObservations | None,
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """Quaternions (n, 4), drifts (n, 3) and covariances (n, 6, 6) at every gyro time."""
    rot, drift = q0, np.array(drift0, dtype=np.float64)
    x, p = np.zeros(6), np.array(p0, dtype=np.float64)
    tracks: list[int] = []
    m = len(baselines)
    events: list[tuple[float, int, int]] = []
    if fixes is not None:
        events += [(float(t), 0, k) for k, t in enumerate(fixes.t)]
    if phases is not None:
        events += [(float(t), 1, k) for k, t in enumerate(phases.epoch_t)]
    events.sort()
    out_q, out_b, out_p = [rot.as_quat()], [drift.copy()], [p[:6, :6].copy()]
    now, ie = gyro_t[0], 0

    def propagate(w: NDArray[np.float64], t: float) -> None:
        nonlocal rot, p, now
        h = t - now
        if h <= 0:
            return
        we = w + drift
        rot = rot * Rotation.from_rotvec(we * h)
        phi, qd = _discretize(we, arw, rrw, h)
        big = np.eye(len(p))
        big[:6, :6] = phi
        p = big @ p @ big.T
        p[:6, :6] += qd
        p = (p + p.T) / 2
        now = t

    def update(nu: NDArray, h: NDArray, r: NDArray) -> None:
        nonlocal x, p, rot, drift
        s = h @ p @ h.T + r
        k = np.linalg.solve(s, h @ p).T
        x = x + k @ nu
        a = np.eye(len(p)) - k @ h
        p = a @ p @ a.T + k @ r @ k.T
        p = (p + p.T) / 2
        rot = rot * Rotation.from_rotvec(x[:3])
        drift = drift + x[3:6]
        x[:6] = 0.0

    def phase_epoch(k: int) -> None:
        nonlocal x, p
        assert phases is not None
        rows = np.nonzero(phases.epoch == k)[0]
        seen = [int(phases.track[r]) for r in rows]
        for tr in [t for t in tracks if t not in seen]:
            g = tracks.index(tr)
            keep = np.r_[0 : 6 + g * m, 6 + (g + 1) * m : len(x)]
            x, p = x[keep], p[np.ix_(keep, keep)]
            tracks.remove(tr)
        old = [r for r in rows if int(phases.track[r]) in tracks]
        new = [r for r in rows if int(phases.track[r]) not in tracks]
        if old:
            h = np.zeros((m * len(old), len(x)))
            nu = np.zeros(m * len(old))
            for j, r in enumerate(old):
                s_body = rot.inv().apply(phases.los[r])
                g = tracks.index(int(phases.track[r]))
                for i, b in enumerate(baselines):
                    h[j * m + i, :3] = np.cross(s_body, b) / phases.wavelength[r]
                    h[j * m + i, 6 + g * m + i] = 1.0
                    pred = -s_body @ b / phases.wavelength[r] + x[6 + g * m + i]
                    nu[j * m + i] = phases.phase[r, i] - pred
            update(nu, h, sigma**2 * np.eye(len(nu)))
        for r in new:
            s_body = rot.inv().apply(phases.los[r])
            g = np.zeros((m, len(x)))
            g[:, :3] = np.cross(s_body, baselines) / phases.wavelength[r]
            tr = np.trace(p[:3, :3])
            pnn = g @ p @ g.T + sigma**2 * np.eye(m)
            pnn += np.diag((0.5 * tr * np.linalg.norm(baselines, axis=1) / phases.wavelength[r]) ** 2)
            n = len(x)
            big = np.zeros((n + m, n + m))
            big[:n, :n] = p
            big[n:, :n] = -g @ p
            big[:n, n:] = -(g @ p).T
            big[n:, n:] = pnn
            p = big
            x = np.r_[x, phases.phase[r] + s_body @ baselines.T / phases.wavelength[r]]
            tracks.append(int(phases.track[r]))

    for k in range(len(gyro_t) - 1):
        w = gyro_rates[k]
        while ie < len(events) and events[ie][0] <= gyro_t[k + 1]:
            t, kind, j = events[ie]
            propagate(w, t)
            if kind == 0:
                assert fixes is not None
                z = (rot.inv() * fixes.rotation[j]).as_rotvec()
                h = np.zeros((3, len(x)))
                h[:, :3] = np.eye(3)
                update(z, h, fixes.covariance[j])
            else:
                phase_epoch(j)
            ie += 1
        propagate(w, gyro_t[k + 1])
        out_q.append(rot.as_quat())
        out_b.append(drift.copy())
        out_p.append(p[:6, :6].copy())
    return np.array(out_q), np.array(out_b), np.array(out_p)
