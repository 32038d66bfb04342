"""TRIAD and Wahba solvers against scipy's align_vectors, identities, and a Monte Carlo covariance check."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import gnssatt
from gnssatt import DegenerateGeometryError, InvalidInputError, NearDegenerateWarning

METHODS = ("svd", "davenport", "quest")


def unit(rng: np.random.Generator, *shape: int) -> np.ndarray:
    v = rng.normal(size=(*shape, 3))
    return v / np.linalg.norm(v, axis=-1, keepdims=True)


def angle(a: Rotation, b: Rotation) -> np.ndarray:
    return (a * b.inv()).magnitude()


@pytest.mark.slow
@pytest.mark.parametrize("method", METHODS)
def test_wahba_matches_scipy_align_vectors_on_noisy_cases(rng: np.random.Generator, method: str) -> None:
    for _ in range(100):
        n = int(rng.integers(2, 7))
        truth = Rotation.random(random_state=rng)
        body = unit(rng, n) * rng.uniform(0.5, 2.0, (n, 1))
        ref = truth.apply(body / np.linalg.norm(body, axis=1, keepdims=True)) + 0.2 * unit(rng, n)
        w = rng.uniform(0.1, 3.0, n)
        ours = gnssatt.wahba(body, ref, w, method=method)
        unit_ref = ref / np.linalg.norm(ref, axis=1, keepdims=True)
        unit_body = body / np.linalg.norm(body, axis=1, keepdims=True)
        scipy_rot, _ = Rotation.align_vectors(unit_ref, unit_body, weights=w)
        assert angle(ours.rotation, scipy_rot) < 1e-8


def test_reflection_case_gives_the_best_proper_rotation(rng: np.random.Generator) -> None:
    # Profile matrix diag(3, 2, -1): the polar factor U V^T is the reflection diag(1, 1, -1).
    body = np.eye(3)
    ref = np.diag([1.0, 1.0, -1.0])
    w = np.array([3.0, 2.0, 1.0])
    h = (w[:, None, None] * ref[:, :, None] * body[:, None, :]).sum(0)
    u, _, vt = np.linalg.svd(h)
    assert np.linalg.det(u @ vt) < 0  # a careless SVD returns a reflection here
    for method in METHODS:
        est = gnssatt.wahba(body, ref, w, method=method)
        assert est.rotation.magnitude() < 1e-12  # identity: flip the smallest singular direction
    # Random cases whose polar factor is a reflection: all methods agree with scipy.
    found = 0
    while found < 20:
        body = unit(rng, 3)
        ref = unit(rng, 3)
        w = rng.uniform(0.5, 2.0, 3)
        h = (w[:, None, None] * ref[:, :, None] * body[:, None, :]).sum(0)
        u, _, vt = np.linalg.svd(h)
        if np.linalg.det(u @ vt) > 0:
            continue
        found += 1
        scipy_rot, _ = Rotation.align_vectors(ref, body, weights=w)
        for method in METHODS:
            est = gnssatt.wahba(body, ref, w, method=method)
            assert np.linalg.det(est.rotation.as_matrix()) == pytest.approx(1.0)
            assert angle(est.rotation, scipy_rot) < 1e-8


def test_batch_equals_epoch_by_epoch(rng: np.random.Generator) -> None:
    truth = Rotation.random(50, random_state=rng)
    body = unit(rng, 50, 4)
    ref = np.stack([truth[k].apply(body[k]) for k in range(50)]) + 0.05 * unit(rng, 50, 4)
    w = rng.uniform(0.5, 2.0, (50, 4))
    for method in METHODS:
        batch = gnssatt.wahba(body, ref, w, method=method)
        assert len(batch.rotation) == 50 and batch.covariance.shape == (50, 3, 3)
        for k in (0, 17, 49):
            one = gnssatt.wahba(body[k], ref[k], w[k], method=method)
            assert angle(batch.rotation[k], one.rotation) < 1e-12
            np.testing.assert_allclose(batch.covariance[k], one.covariance, rtol=1e-12)
    shared = gnssatt.wahba(body, ref, w[0])  # (n,) weights broadcast over epochs
    assert len(shared.rotation) == 50


def test_near_half_turns_quest_agrees(rng: np.random.Generator) -> None:
    axes = unit(rng, 30)
    truth = Rotation.from_rotvec(axes * (np.pi - rng.uniform(0, 1e-4, (30, 1))))
    body = unit(rng, 30, 3)
    ref = np.stack([truth[k].apply(body[k]) for k in range(30)]) + 0.01 * unit(rng, 30, 3)
    svd = gnssatt.wahba(body, ref, method="svd")
    quest = gnssatt.wahba(body, ref, method="quest")
    assert np.max(angle(svd.rotation, quest.rotation)) < 1e-8


def test_covariance_matches_monte_carlo(rng: np.random.Generator) -> None:
    """Shuster's covariance against 4000 noisy trials: the mean of delta^T P^-1 delta is chi-square(3)/N,
    3 +- 0.04 (1 sigma); the whitened sample covariance has eigenvalues within 1 +- 0.1."""
    trials = 4000
    truth = Rotation.from_euler("ZYX", [2.0, 0.5, -1.0])
    ref = np.array([[1.0, 0.0, 0.0], [0.6, 0.8, 0.0], [0.0, 0.6, 0.8]])
    sigma = np.array([0.002, 0.01, 0.02])
    body_true = truth.inv().apply(ref)
    body = body_true + sigma[:, None] * rng.normal(size=(trials, 3, 3))
    est = gnssatt.wahba(body, np.broadcast_to(ref, body.shape), 1.0 / sigma**2, method="quest")
    delta = (est.rotation * truth.inv()).as_rotvec()
    p = est.covariance[0]
    np.testing.assert_allclose(est.covariance, np.broadcast_to(p, est.covariance.shape), rtol=1e-9)
    chi2 = np.einsum("ni,ij,nj->n", delta, np.linalg.inv(p), delta)
    assert abs(chi2.mean() - 3.0) < 5 * np.sqrt(6.0 / trials)
    # Whitened sample covariance ~ I (Wishart: elementwise sd about sqrt(2/N) = 0.022).
    ell = np.linalg.cholesky(np.linalg.inv(p))
    white = delta @ ell
    eig = np.linalg.eigvalsh(white.T @ white / trials)
    assert np.all(np.abs(eig - 1.0) < 0.1), eig
    # In the body frame it would be wrong: the reference-frame statement is the one that holds.
    r = truth.as_matrix()
    p_body = r.T @ p @ r
    chi2_body = np.einsum("ni,ij,nj->n", delta, np.linalg.inv(p_body), delta)
    assert abs(chi2_body.mean() - 3.0) > 0.5


def test_triad_identities(rng: np.random.Generator) -> None:
    truth = Rotation.random(200, random_state=rng)
    b1, b2 = 2.0 * unit(rng, 200), unit(rng, 200)
    r1 = truth.apply(b1)
    r2 = truth.apply(b2) + 0.1 * unit(rng, 200)
    est = gnssatt.triad(b1, b2, r1, r2)
    # First pair exact.
    np.testing.assert_allclose(est.rotation.apply(b1 / 2.0), r1 / 2.0, atol=1e-12)
    # Second body vector lands in the plane of r1, r2, on the same side of r1 as r2.
    n = np.cross(r1, r2)
    mapped = est.rotation.apply(b2)
    assert np.max(np.abs(np.einsum("ij,ij->i", mapped, n))) < 1e-12
    assert np.all(np.einsum("ij,ij->i", np.cross(r1, mapped), n) > 0)
    # Exact data: TRIAD returns the truth; and TRIAD is Wahba's limit for w1 >> w2.
    exact = gnssatt.triad(b1, b2, r1, truth.apply(b2))
    assert np.max(angle(exact.rotation, truth)) < 1e-12
    k = 3
    for method in ("svd", "davenport"):  # 1e8 weight ratio: nalgebra's bare SVD was 0.03 rad off here
        with pytest.warns(NearDegenerateWarning):
            lim = gnssatt.wahba(np.stack([b1[k], b2[k]]), np.stack([r1[k], r2[k]]), [1e8, 1.0], method=method)
        assert angle(lim.rotation, est.rotation[k]) < 1e-6
    one = gnssatt.triad(b1[k], b2[k], r1[k], r2[k])
    assert isinstance(one.sin_angle_body, float) and one.rotation.single


def test_degenerate_and_bad_input() -> None:
    z, x, y = np.eye(3)[2], np.eye(3)[0], np.eye(3)[1]
    with pytest.raises(DegenerateGeometryError, match="sine of the angle"):
        gnssatt.triad(z, -3 * z, x, y)
    with pytest.raises(DegenerateGeometryError, match="b2 is zero"):
        gnssatt.triad(z, np.zeros(3), x, y)
    with pytest.raises(DegenerateGeometryError, match=r"epoch 1: .*r1 and r2 are parallel"):
        gnssatt.triad([z, z], [x, x], [x, x], [y, x])
    with pytest.raises(DegenerateGeometryError, match="all parallel"):
        gnssatt.wahba([z, 2 * z], [x, x])
    with pytest.raises(DegenerateGeometryError, match="body vector 1 is zero"):
        gnssatt.wahba([z, np.zeros(3)], [x, y])
    with pytest.raises(InvalidInputError, match="expected 'svd', 'davenport' or 'quest'"):
        gnssatt.wahba([z, x], [z, x], method="bogus")  # type: ignore[arg-type]
    with pytest.raises(InvalidInputError, match="non-negative"):
        gnssatt.wahba([z, x], [z, x], [1.0, -1.0])
    with pytest.raises(InvalidInputError, match="one shape"):
        gnssatt.wahba([z, x], [z, x, y])
    with pytest.raises(InvalidInputError, match="at least 2"):
        gnssatt.wahba([z], [z])
    with pytest.raises(InvalidInputError, match="non-finite"):
        gnssatt.triad([np.nan, 0, 1], x, y, z)
    with pytest.raises(InvalidInputError, match="shape"):
        gnssatt.triad(np.ones(4), x, y, z)


def test_near_degenerate_warns() -> None:
    z, x = np.eye(3)[2], np.eye(3)[0]
    tilt = np.array([1e-3, 0.0, 1.0])
    with pytest.warns(NearDegenerateWarning, match="TRIAD vectors"):
        gnssatt.triad(z, tilt, z, tilt)
    with pytest.warns(NearDegenerateWarning, match="information ratio"):
        gnssatt.wahba([z, tilt], [z, tilt])
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        gnssatt.triad(z, x, z, x)
        gnssatt.wahba([z, x], [z, x])


def test_a_single_pair_against_an_empty_batch_is_refused_not_broadcast_to_nothing() -> None:
    # issue 31: numpy broadcasts (3,) against (0, 3) to (0, 3), and the result was empty
    z, x, y = np.eye(3)[2], np.eye(3)[0], np.eye(3)[1]
    with pytest.raises(InvalidInputError, match=r"b1, b2, r1, r2 with at least one epoch.*\(0, 3\)"):
        gnssatt.triad(z, np.zeros((0, 3)), x, y)
    with pytest.raises(InvalidInputError, match="at least one epoch"):
        gnssatt.yaw_from_magnetometer(z, np.zeros((0, 3)), 0.0, 0.0)
    with pytest.raises(InvalidInputError, match="at least one epoch"):
        gnssatt.yaw_from_magnetometer(z, x, np.zeros(0), 0.0)
    # a single pair against a batch of one still broadcasts
    assert len(gnssatt.triad(z, x[None], x, y).rotation) == 1


def _align(body: np.ndarray, ref: np.ndarray, w: np.ndarray) -> Rotation:
    unit = body / np.linalg.norm(body, axis=1)[:, None]  # wahba normalises; align_vectors weights by length
    rotation, _ = Rotation.align_vectors(ref, unit, weights=w)
    return rotation


def test_quest_agrees_with_scipy_up_to_its_weight_span_and_refuses_beyond() -> None:
    # Noise-free pairs, one weight QUEST_MAX_WEIGHT_SPAN times the others: QUEST gives scipy's rotation.
    # At 1e6 it returned rotations up to pi away (4 of 1000 such problems), silently.
    from gnssatt.attitude.wahba import QUEST_MAX_WEIGHT_SPAN

    rng = np.random.default_rng(3)
    worst = 0.0
    for _ in range(300):
        n = int(rng.integers(2, 8))
        truth = Rotation.random(random_state=rng)
        ref = rng.normal(size=(n, 3))
        ref /= np.linalg.norm(ref, axis=1)[:, None]
        body = truth.inv().apply(ref)
        w = np.ones(n)
        w[int(rng.integers(n))] = QUEST_MAX_WEIGHT_SPAN
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", NearDegenerateWarning)
            quest = gnssatt.wahba(body, ref, w, method="quest").rotation
        worst = max(worst, angle(quest, _align(body, ref, w)))
    assert worst < 1e-7, worst
    z, x = np.eye(3)[2], np.eye(3)[0]
    with pytest.raises(
        InvalidInputError, match=r"weights spanning at most 100000 .*1e\+09 at epoch 0.*'svd'"
    ):
        gnssatt.wahba([z, x], [z, x], [1.0, 1e9], method="quest")
    # zero weights do not count in the span; svd takes any span
    assert (
        angle(
            gnssatt.wahba([z, x, z], [z, x, z], [1.0, 1e4, 0.0], method="quest").rotation, Rotation.identity()
        )
        < 1e-12
    )
    assert angle(gnssatt.wahba([z, x], [z, x], [1.0, 1e9]).rotation, Rotation.identity()) < 1e-9
