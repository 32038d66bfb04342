"""Per-epoch ML over a batch in one call: the single-epoch functions epoch by epoch, the truth, bad input."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from gnssatt.attitude.likelihood import (
    ml_attitude,
    ml_attitude_series,
    ml_baseline,
    ml_baseline_series,
)
from gnssatt.errors import DegenerateGeometryError, InvalidInputError
from gnssatt.rotation import rotation_from_euler

L1, L2 = 299792458.0 / 1575.42e6, 299792458.0 / 1227.6e6


def glonass(k: int) -> float:
    """GLONASS L1 FDMA wavelength of channel ``k``, metres."""
    return 299792458.0 / (1602e6 + k * 0.5625e6)


def sky(rng: np.random.Generator, m: int) -> np.ndarray:
    az = rng.uniform(0.0, 2.0 * np.pi, m)
    el = rng.uniform(0.2, 1.5, m)
    return np.stack([np.sin(az) * np.cos(el), np.cos(az) * np.cos(el), np.sin(el)], axis=1)


def phases(rng, baselines, los, lam, euler_deg, noise):
    """(n_rover, n_sig) wrapped single differences (RINEX sign) at attitude ``euler_deg``."""
    r = rotation_from_euler(euler_deg).as_matrix()
    osc = rng.uniform(-3.0, 3.0, (len(baselines), 1))
    p = -2.0 * np.pi / lam * ((r @ np.asarray(baselines).T).T @ los.T) + osc
    return np.mod(p + rng.normal(0.0, noise, p.shape), 2.0 * np.pi)


def batch(rng, baselines, n_ep, m, drift_deg):
    """A slowly turning platform: phases (n_ep, n_rover, m) with some NaN, los (n_ep, m, 3), lambdas (m,),
    truths (n_ep, 3); epoch 2 keeps only 2 complete signals."""
    lam = np.array([[glonass(int(rng.integers(-7, 7))), L1, L2][k % 3] for k in range(m)])
    truth = np.array([rng.uniform(-170, 170), rng.uniform(-60, 60), rng.uniform(-170, 170)])
    p, s, t = [], [], []
    for k in range(n_ep):
        truth = truth + rng.uniform(-drift_deg, drift_deg, 3)
        los = sky(rng, m)
        pk = phases(rng, baselines, los, lam, truth, 0.05)
        keep = 2 if k == 2 else m - 2
        for j in range(keep, m):
            pk[rng.integers(len(baselines)), j] = np.nan
        p.append(pk)
        s.append(los)
        t.append(truth)
    return np.array(p), np.array(s), lam, np.array(t)


def epoch_by_epoch(p, s, lam, window_deg, single, **kw):
    """The single-epoch function on each epoch's complete signals, windowed around the previous result."""
    out, prev = [], None
    for k in range(p.shape[0]):
        used = ~np.any(np.isnan(p[k]), axis=0)
        if used.sum() < 3:
            out.append(None)
            prev = None
            continue
        win = None
        if window_deg is not None and prev is not None:
            win = np.stack([prev - window_deg, prev + window_deg], axis=1)
        res = single(p[k][:, used], s[k][used], lam[used], win, **kw)
        out.append(res)
        prev = res[0]
    return out


@pytest.mark.slow
def test_attitude_series_equals_ml_attitude_epoch_by_epoch():
    rng = np.random.default_rng(1700)
    for _ in range(4):
        b = np.array([[0.6, 0.0, 0.0], [0.2, 0.05, 0.5], [-0.3, 0.1, 0.4]])[: rng.integers(2, 4)]
        p, s, lam, _ = batch(rng, b, n_ep=6, m=int(rng.integers(6, 11)), drift_deg=2.0)

        def single(pk, sk, lk, win, b=b):
            r = ml_attitude(pk, sk, b, lk, step_deg=3.0, window_deg=win)
            return r.euler_gost_deg, r.z_max, r.rotation

        for window in (None, 12.0):
            got = ml_attitude_series(p, s, b, lam, step_deg=3.0, window_deg=window)
            want = epoch_by_epoch(p, s, lam, window, single)
            for k, w in enumerate(want):
                if w is None:
                    assert not got.solved[k]
                    assert np.all(np.isnan(got.euler_gost_deg[k])) and np.isnan(got.z_max[k])
                    np.testing.assert_array_equal(got.rotation[k].as_matrix(), np.eye(3))
                    continue
                assert got.solved[k]
                np.testing.assert_array_equal(got.euler_gost_deg[k], w[0])
                assert got.z_max[k] == w[1]
                np.testing.assert_allclose(got.rotation[k].as_matrix(), w[2].as_matrix(), atol=1e-12)


def test_baseline_series_equals_ml_baseline_epoch_by_epoch():
    rng = np.random.default_rng(1701)
    for length in (0.8, 2.5):
        p, s, lam, _ = batch(rng, [[length, 0.0, 0.0]], n_ep=6, m=8, drift_deg=1.0)

        def single(pk, sk, lk, win, length=length):
            win = None if win is None else win[:2]
            r = ml_baseline(pk[0], sk, length, lk, window_deg=win)
            psi = -r.heading_deg if r.heading_deg < 180.0 else 360.0 - r.heading_deg
            return np.array([psi, r.elevation_deg, 0.0]), r.z_max, r

        for window in (None, 5.0):
            got = ml_baseline_series(p[:, 0, :], s, length, lam, window_deg=window)
            want = epoch_by_epoch(p, s, lam, window, single)
            for k, w in enumerate(want):
                if w is None:
                    assert not got.solved[k] and np.isnan(got.heading_deg[k])
                    continue
                r = w[2]
                assert got.solved[k] and got.z_max[k] == r.z_max
                # psi in (-180, 180] here, from -heading there (the window limits round in the last bits)
                assert abs(got.elevation_deg[k] - r.elevation_deg) < 1e-9
                assert abs(got.heading_deg[k] - r.heading_deg) < 1e-9
                np.testing.assert_allclose(got.direction_enu[k], r.direction_enu, atol=1e-12)


@pytest.mark.slow
def test_series_recovers_the_truth_and_mask_equals_nan():
    # Noise-free phases, default step: the refined attitude is the truth (Newton polish on the noise-free
    # statistic, whose maximum is the truth itself).
    rng = np.random.default_rng(1702)
    b = np.array([[0.5, 0.0, 0.0], [0.0, 0.0, 0.4]])
    truths = np.array([[20.0, 5.0, -10.0], [21.0, 5.5, -9.0], [22.5, 6.0, -8.0]])
    p, s = [], []
    for t in truths:
        los = sky(rng, 8)
        p.append(np.mod(phases(rng, b, los, np.full(8, L1), t, 0.0), 2 * np.pi))
        s.append(los)
    p, s = np.array(p), np.array(s)
    for window in (None, 5.0):
        got = ml_attitude_series(p, s, b, L1, window_deg=window)
        np.testing.assert_allclose(got.euler_gost_deg, truths, atol=1e-6)
        rel = got.rotation * rotation_from_euler(truths).inv()
        assert np.max(rel.magnitude()) < 1e-7
    # A mask is the same as NaN phases; absent signals' los and wavelengths may be NaN.
    mask = np.ones(p.shape, dtype=bool)
    mask[1, 0, [0, 3]] = False
    with_nan = p.copy()
    with_nan[1, 0, [0, 3]] = np.nan
    lam = np.full((3, 8), L1)
    s_nan = s.copy()
    s_nan[1, [0, 3]] = np.nan
    lam[1, [0, 3]] = np.nan
    a = ml_attitude_series(p, s, b, L1, mask=mask, step_deg=2.0)
    c = ml_attitude_series(with_nan, s_nan, b, lam, step_deg=2.0)
    np.testing.assert_array_equal(a.euler_gost_deg, c.euler_gost_deg)
    d = ml_attitude_series(p, s, b, L1, step_deg=2.0)
    assert not np.array_equal(a.euler_gost_deg[1], d.euler_gost_deg[1])
    np.testing.assert_array_equal(a.euler_gost_deg[[0, 2]], d.euler_gost_deg[[0, 2]])


def test_baseline_series_truth():
    rng = np.random.default_rng(1703)
    los = sky(rng, 7)
    # heading 30 deg (psi = -30), elevation 10 deg
    p = phases(rng, [[1.5, 0.0, 0.0]], los, np.full(7, L1), [-30.0, 10.0, 0.0], 0.0)
    got = ml_baseline_series(p, los, 1.5, L1)
    assert abs(got.heading_deg[0] - 30.0) < 1e-6 and abs(got.elevation_deg[0] - 10.0) < 1e-6
    e = np.radians(10.0)
    want = [np.sin(np.radians(30.0)) * np.cos(e), np.cos(np.radians(30.0)) * np.cos(e), np.sin(e)]
    np.testing.assert_allclose(got.direction_enu[0], want, atol=1e-7)


def test_bad_input():
    rng = np.random.default_rng(1704)
    b = np.array([[0.5, 0.0, 0.0], [0.0, 0.0, 0.4]])
    los = sky(rng, 6)
    p = phases(rng, b, los, np.full(6, L1), [0.0, 0.0, 0.0], 0.0)[None]
    ok = ml_attitude_series(p, los, b, L1, step_deg=3.0)
    assert ok.solved.tolist() == [True]
    with pytest.raises(InvalidInputError, match="at least one epoch"):
        ml_attitude_series(p[:0], los, b, L1)
    with pytest.raises(InvalidInputError, match=r"sd_phase of shape \(n_ep, 3, n_sig\)"):
        ml_attitude_series(p, los, np.vstack([b, [[0.1, 0.2, 0.3]]]), L1)
    with pytest.raises(InvalidInputError, match="at least 2 baselines"):
        ml_attitude_series(p[:, :1], los, b[:1], L1)
    with pytest.raises(InvalidInputError, match="mask"):
        ml_attitude_series(p, los, b, L1, mask=np.ones(p.shape))
    with pytest.raises(InvalidInputError, match="non-finite"):
        ml_attitude_series(np.where(p > 3, np.inf, p), los, b, L1)
    bad = los.copy()
    bad[2] = np.nan
    with pytest.raises(InvalidInputError, match=r"los is NaN at \(epoch, signal\) \(0, 2\)"):
        ml_attitude_series(p, bad, b, L1)
    with pytest.raises(InvalidInputError, match="wavelength"):
        ml_attitude_series(p, los, b, [L1] * 5)
    with pytest.raises(InvalidInputError, match="window_deg"):
        ml_attitude_series(p, los, b, L1, step_deg=3.0, window_deg=1.0)
    with pytest.raises(InvalidInputError, match="window_deg"):
        ml_attitude_series(p, los, b, L1, window_deg=400.0)
    with pytest.raises(InvalidInputError, match="main lobe"):
        ml_attitude_series(p, los, b, L1, step_deg=20.0)
    with pytest.raises(InvalidInputError, match="unit lines of sight"):
        ml_attitude_series(p, 2.0 * los, b, L1)
    with pytest.raises(DegenerateGeometryError):
        ml_attitude_series(p, los, [[0.5, 0.0, 0.0], [1.0, 0.0, 0.0]], L1)
    with pytest.raises(InvalidInputError, match="baseline_length_m"):
        ml_baseline_series(p[:, 0], los, 0.0, L1)
    with pytest.raises(InvalidInputError, match="sd_phase"):
        ml_baseline_series(p, los, 0.5, L1)
    assert isinstance(ok.rotation, Rotation)
