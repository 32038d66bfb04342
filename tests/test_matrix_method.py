"""Ryzhkov and Oliinyk matrix method against independent references: the paper's formulas written in numpy,
scipy's Wahba solver (Rotation.align_vectors), scipy's least-squares solver and the Cramer-Rao bound."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.linalg
from scipy import stats
from scipy.optimize import least_squares
from scipy.spatial.transform import Rotation

import gnssatt
from gnssatt.geometry import range_difference_fisher

TETRA = np.array([[1.0, 0.0, 0.0], [0.0, 1.2, 0.0], [0.1, 0.2, 0.9]])
TRIANGLE = np.array([[1.0, 0.0, 0.0], [0.5, np.sqrt(3) / 2, 0.0]])


def unit_rows(x: np.ndarray) -> np.ndarray:
    return x / np.linalg.norm(x, axis=1, keepdims=True)


def measure(baselines: np.ndarray, los: np.ndarray, truth: Rotation) -> np.ndarray:
    """Range differences b_i . (A s_j), A = reference -> body."""
    return baselines @ truth.inv().as_matrix() @ los.T


def random_los(rng: np.random.Generator, n: int) -> np.ndarray:
    return unit_rows(rng.standard_normal((n, 3)))


@pytest.mark.parametrize("method", ["svd", "ml", "closed_form", "paper"])
def test_noise_free_recovery(method: str, rng: np.random.Generator) -> None:
    for _ in range(25):
        truth = Rotation.random(random_state=rng)
        los = random_los(rng, 5)
        res = gnssatt.matrix_attitude(TETRA, los, measure(TETRA, los, truth), method=method)
        assert (res.rotation * truth.inv()).magnitude() < 1e-9
        assert res.residual_rms_m < 1e-10


def test_coplanar_array_noise_free(rng: np.random.Generator) -> None:
    for _ in range(25):
        truth = Rotation.random(random_state=rng)
        los = random_los(rng, 3)
        for method in ("svd", "ml"):
            res = gnssatt.matrix_attitude(TRIANGLE, los, measure(TRIANGLE, los, truth), method=method)
            assert (res.rotation * truth.inv()).magnitude() < 1e-9


def test_paper_formulas_in_numpy(rng: np.random.Generator) -> None:
    """Eq. (3) and eq. (16) as printed, evaluated with numpy/scipy.linalg on noisy data."""
    hits = 0
    for _ in range(50):
        truth = Rotation.random(random_state=rng)
        los = random_los(rng, 6)
        r = measure(TETRA, los, truth) + rng.normal(0, 0.02, (3, 6))
        b, s = TETRA.T, los.T
        g_inv, n_inv = np.linalg.inv(b @ b.T), np.linalg.inv(s @ s.T)
        closed = g_inv @ b @ r @ s.T @ n_inv
        res = gnssatt.matrix_attitude(TETRA, los, r, method="closed_form")
        np.testing.assert_allclose(res.raw_matrix, closed, atol=1e-12)
        q = s @ (g_inv @ b @ r).T
        a16 = q.T @ np.linalg.inv(np.real(scipy.linalg.sqrtm(q @ q.T)))
        svd = gnssatt.matrix_attitude(TETRA, los, r, method="svd")
        if np.linalg.det(a16) > 0:
            hits += 1
            np.testing.assert_allclose(svd.rotation.inv().as_matrix(), a16, atol=1e-9)
            paper = gnssatt.matrix_attitude(TETRA, los, r, method="paper")
            np.testing.assert_allclose(paper.raw_matrix, a16, atol=1e-9)
        else:
            with pytest.raises(gnssatt.DegenerateGeometryError, match="reflection"):
                gnssatt.matrix_attitude(TETRA, los, r, method="paper")
    assert hits > 40


def test_svd_solves_wahba_like_scipy(rng: np.random.Generator) -> None:
    """Both branches of the SVD method are Wahba problems; scipy's align_vectors solves them independently."""
    for _ in range(30):
        truth = Rotation.random(random_state=rng)
        los = random_los(rng, 4)
        # Non-coplanar array: body-frame lines of sight K = G^-1 B R matched to S.
        r = measure(TETRA, los, truth) + rng.normal(0, 0.05, (3, 4))
        k = np.linalg.solve(TETRA.T @ TETRA, TETRA.T @ r)
        expected, _ = Rotation.align_vectors(los, k.T)
        got = gnssatt.matrix_attitude(TETRA, los, r).rotation
        assert (got * expected.inv()).magnitude() < 1e-9
        # Coplanar array: reference-frame baselines C = N^-1 S R^T matched to B.
        r2 = measure(TRIANGLE, los, truth) + rng.normal(0, 0.05, (2, 4))
        c = np.linalg.solve(los.T @ los, los.T @ r2.T)
        expected2, _ = Rotation.align_vectors(c.T, TRIANGLE)
        got2 = gnssatt.matrix_attitude(TRIANGLE, los, r2).rotation
        assert (got2 * expected2.inv()).magnitude() < 1e-9


def loss(baselines: np.ndarray, los: np.ndarray, r: np.ndarray, rot: Rotation) -> float:
    return float(np.sum((measure(baselines, los, rot) - r) ** 2))


@pytest.mark.slow
def test_ml_is_the_least_squares_minimum(rng: np.random.Generator) -> None:
    """scipy's Levenberg-Marquardt started at the ML answer finds nothing lower; SVD is never lower."""
    for _ in range(30):
        truth = Rotation.random(random_state=rng)
        los = random_los(rng, 3)
        r = measure(TRIANGLE, los, truth) + rng.normal(0, 0.01, (2, 3))
        ml = gnssatt.matrix_attitude(TRIANGLE, los, r, method="ml").rotation
        svd = gnssatt.matrix_attitude(TRIANGLE, los, r, method="svd").rotation
        fit = least_squares(
            lambda d, ml=ml, los=los, r=r: (measure(TRIANGLE, los, Rotation.from_rotvec(d) * ml) - r).ravel(),
            np.zeros(3),
            method="lm",
            xtol=1e-15,
            ftol=1e-15,
        )
        assert np.linalg.norm(fit.x) < 1e-7
        assert loss(TRIANGLE, los, r, ml) <= loss(TRIANGLE, los, r, svd) * (1 + 1e-12)


@pytest.mark.slow
def test_ml_reaches_the_cramer_rao_bound(rng: np.random.Generator) -> None:
    """At small noise the ML error delta is Gaussian with covariance sigma^2 J^-1, so
    sum over trials of delta^T J delta / sigma^2 is chi-square with 3 x trials degrees of freedom."""
    sigma, trials = 1e-4, 400
    los = unit_rows(np.array([[0.3, 0.2, 1.0], [-0.7, 0.1, 0.5], [0.2, -0.8, 0.4], [0.6, 0.6, 0.3]]))
    truth = Rotation.from_euler("ZYX", [180, 0, 0], degrees=True)
    info = range_difference_fisher(TRIANGLE, los, truth)
    clean = measure(TRIANGLE, los, truth)
    total = 0.0
    for _ in range(trials):
        est = gnssatt.matrix_attitude(TRIANGLE, los, clean + rng.normal(0, sigma, clean.shape), method="ml")
        delta = (est.rotation * truth.inv()).as_rotvec()
        total += delta @ info @ delta / sigma**2
    dof = 3 * trials
    assert stats.chi2.ppf(0.0005, dof) < total < stats.chi2.ppf(0.9995, dof)


def test_euler_angles_are_heading_pitch_roll() -> None:
    los = unit_rows(np.array([[0.3, 0.2, 1.0], [-0.7, 0.1, 0.5], [0.2, -0.8, 0.4]]))
    truth = Rotation.from_euler("ZYX", [-170, 5, -3], degrees=True)
    res = gnssatt.matrix_attitude(TRIANGLE, los, measure(TRIANGLE, los, truth))
    np.testing.assert_allclose(res.heading_pitch_roll_deg, [-170, 5, -3], atol=1e-9)


def test_degenerate_geometry_names_the_matrix() -> None:
    los = unit_rows(np.array([[0.3, 0.2, 1.0], [-0.7, 0.1, 0.5], [0.2, -0.8, 0.4]]))
    r = measure(TRIANGLE, los, Rotation.identity())
    with pytest.raises(gnssatt.DegenerateGeometryError, match=r"G = B B\^T has condition number"):
        gnssatt.matrix_attitude(TRIANGLE, los, r, method="paper")
    line = np.array([[1.0, 0, 0], [2.0, 0, 0]])
    with pytest.raises(gnssatt.DegenerateGeometryError, match="not fixed"):
        gnssatt.matrix_attitude(line, los, measure(line, los, Rotation.identity()))
    coplanar_los = unit_rows(np.array([[1.0, 0, 0.2], [0, 1.0, 0.2], [-1.0, -1.0, 0.4]]))
    coplanar_los[2] = unit_rows((coplanar_los[0] + coplanar_los[1])[None])[0]
    with pytest.raises(gnssatt.DegenerateGeometryError, match="N = S S"):
        gnssatt.matrix_attitude(TRIANGLE, coplanar_los, measure(TRIANGLE, coplanar_los, Rotation.identity()))


@pytest.mark.parametrize(
    ("kwargs", "error", "match"),
    [
        ({"baselines": TETRA[0]}, gnssatt.InvalidInputError, r"baselines of shape \(m, 3\)"),
        ({"baselines": TETRA[:1]}, gnssatt.InvalidInputError, "m >= 2"),
        ({"los": np.ones((3, 2))}, gnssatt.InvalidInputError, r"los of shape \(n, 3\)"),
        ({"los": 2 * np.eye(3)}, gnssatt.InvalidInputError, "unit vectors"),
        ({"range_diffs": np.zeros((3, 2))}, gnssatt.InvalidInputError, "range_diffs of shape"),
        ({"range_diffs": np.full((3, 3), np.inf)}, gnssatt.InvalidInputError, "non-finite"),
        ({"baselines": np.zeros((3, 3))}, gnssatt.InvalidInputError, "baseline 0 has length 0"),
        ({"method": "qr"}, gnssatt.InvalidInputError, "expected method"),
        ({"los": "north"}, TypeError, "numeric array"),
    ],
)
def test_bad_input(kwargs: dict, error: type, match: str) -> None:
    args = {"baselines": TETRA, "los": np.eye(3), "range_diffs": np.zeros((3, 3))} | kwargs
    method = args.pop("method", "svd")
    with pytest.raises(error, match=match):
        gnssatt.matrix_attitude(**args, method=method)
    assert issubclass(gnssatt.InvalidInputError, ValueError)
