"""Bunyaeva et al. maximum-likelihood grid: Rust against a numpy reference, recovery, statistics, search,
errors."""

from __future__ import annotations

import zlib

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import gnssatt
from gnssatt import InvalidInputError
from gnssatt.rotation import ENU_FROM_NORMAL, euler_from_rotation, rotation_from_euler

L1 = 0.19029367279836487
TRIANGLE = 0.71 * np.array([[1.0, 0.0, 0.0], [0.5, 0.0, np.sqrt(3) / 2]])


def sky(rng: np.random.Generator, m: int) -> np.ndarray:
    az = rng.uniform(0, 2 * np.pi, m)
    el = rng.uniform(0.2, 1.45, m)
    return np.stack([np.sin(az) * np.cos(el), np.cos(az) * np.cos(el), np.sin(el)], axis=1)


def phases(rng, baselines, los, lam, euler_deg, *, noise=0.0, wrap=True, osc=True):
    """(m, M) phase differences, RINEX sign, random oscillator phase per baseline, wrapped to [0, 2 pi)."""
    r = rotation_from_euler(euler_deg)
    lam = np.broadcast_to(lam, (los.shape[0],))
    p = -2 * np.pi / lam * (r.apply(baselines) @ los.T)
    if osc:
        p = p + rng.uniform(-3, 3, (len(baselines), 1))
    p = p + noise * rng.standard_normal(p.shape)
    return np.mod(p, 2 * np.pi) if wrap else p


def reference_z(phase_diffs, los, baselines, lam, cells_deg, statistic):
    """Slow numpy reference of the three statistics at (N, 3) cells (psi, theta, phi) in degrees."""
    p = np.atleast_3d(phase_diffs) if np.ndim(phase_diffs) == 3 else np.asarray(phase_diffs)[None]
    ne, _, m = p.shape
    s = np.broadcast_to(los, (ne, m, 3))
    w = np.broadcast_to(lam, (ne, m))
    g = 2 * np.pi * s / w[..., None]  # (E, M, 3) ENU
    if statistic == "mean":
        d = p - p.mean(axis=2, keepdims=True)
        g = g - g.mean(axis=1, keepdims=True)
    elif statistic == "double_difference":
        top = np.argmax(s[..., 2], axis=1)
        d = p - p[np.arange(ne), :, top][:, :, None]
        g = g - g[np.arange(ne), top][:, None, :]
    else:
        d = p
    r = np.stack([rotation_from_euler(c).as_matrix() for c in cells_deg])  # (N, 3, 3)
    v = np.einsum("nab,ib->nia", r, baselines)  # (N, m, 3)
    x = d[None] + np.einsum("ekc,nic->neik", g, v)  # (N, E, m, M)
    e = np.exp(1j * x)
    if statistic == "ambiguity_function":
        return np.abs(e.sum(axis=(1, 3))).sum(axis=1)
    return np.abs(1 + e.sum(axis=2)).sum(axis=(1, 2))


def test_rotation_convention_matches_eq5_and_scipy():
    psi, theta, phi = 30.0, 10.0, -20.0
    r = rotation_from_euler([psi, theta, phi])
    expected = ENU_FROM_NORMAL @ Rotation.from_euler("YZX", [psi, theta, phi], degrees=True).as_matrix()
    np.testing.assert_allclose(r.as_matrix(), expected, atol=1e-14)
    # Eq. (5) first column (N, U, E) = (cos psi cos theta, sin theta, -sin psi cos theta).
    ps, th = np.radians([psi, theta])
    nose = r.apply([1.0, 0.0, 0.0])
    np.testing.assert_allclose(
        nose, [-np.sin(ps) * np.cos(th), np.cos(ps) * np.cos(th), np.sin(th)], atol=1e-14
    )
    assert nose[0] < 0  # positive psi turns the nose West
    assert r.apply([0.0, 0.0, 1.0])[2] > 0 or phi > 0  # negative roll raises the right wing
    np.testing.assert_allclose(euler_from_rotation(r), [psi, theta, phi], atol=1e-10)


@pytest.mark.slow
@pytest.mark.parametrize("statistic", ["ambiguity_function", "mean", "double_difference"])
def test_rust_matches_numpy_reference(statistic):
    rng = np.random.default_rng(10)
    los = sky(rng, 7)
    lam = L1 * (1 + 0.01 * rng.uniform(-1, 1, 7))
    truth = [100.0, -20.0, 35.0]
    p = phases(rng, TRIANGLE, los, lam, truth, noise=0.2)
    window = np.array([[90.0, 112.0], [-30.0, -8.0], [25.0, 47.0]])
    grid = gnssatt.likelihood_grid(
        p, los, TRIANGLE, lam, statistic=statistic, step_deg=2.0, window_deg=window
    )
    cells = np.stack(np.meshgrid(grid.psi_deg, grid.theta_deg, grid.phi_deg, indexing="ij"), -1).reshape(
        -1, 3
    )
    z_ref = reference_z(p, los, TRIANGLE, lam, cells, statistic).reshape(grid.z.shape)
    np.testing.assert_allclose(grid.z, z_ref, rtol=1e-4)
    assert np.argmax(grid.z) == np.argmax(z_ref)
    res = gnssatt.ml_attitude(
        p, los, TRIANGLE, lam, statistic=statistic, step_deg=2.0, window_deg=window, refine=False
    )
    np.testing.assert_allclose(res.euler_gost_deg, grid.argmax_deg(), atol=1e-9)
    assert res.z_max == pytest.approx(float(grid.z.max()))


GEOMETRIES = {
    "triangle": TRIANGLE,
    "l_shape": np.array([[0.8, 0.0, 0.0], [0.0, 0.0, 0.6]]),
    "four": np.array([[0.6, 0.05, 0.0], [0.0, 0.0, 0.5], [0.4, -0.1, 0.4]]),
}


@pytest.mark.parametrize("name", sorted(GEOMETRIES))
def test_noise_free_recovery_random_attitudes(name):
    # crc32, not hash(): str hashes are salted per process, which made the draws (and failures) vary.
    rng = np.random.default_rng(zlib.crc32(name.encode()))
    b = GEOMETRIES[name]
    for _ in range(4):
        truth = rng.uniform([-180, -70, -180], [180, 70, 180])
        los = sky(rng, 8)
        lam = L1 if name != "four" else 299792458.0 / (1602e6 + 0.5625e6 * rng.integers(-7, 7, 8))
        p = phases(rng, b, los, lam, truth)
        res = gnssatt.ml_attitude(p, los, b, lam, step_deg=1.5)
        err = (res.rotation * rotation_from_euler(truth).inv()).magnitude()
        # Without noise the continuous maximum of Z is the truth: Newton reaches it to rounding.
        assert np.degrees(err) < 1e-5, (truth, res.euler_gost_deg)
        assert res.step_deg == pytest.approx(1.5)
        # Per-axis parabolas (16) ignore the coupling of the Euler angles near the peak. The peak is a
        # tilted ellipsoid, so the grid maximum is the cell nearest the truth or one of its neighbours
        # (<= 1.5 steps per axis), and the parabola moves at most half a step: <= 2 steps per angle.
        para = gnssatt.ml_attitude(p, los, b, lam, step_deg=1.5, refine="parabolic")
        d = (np.asarray(para.euler_gost_deg) - truth + 180.0) % 360.0 - 180.0
        assert np.all(np.abs(d) <= 2 * 1.5), (truth, para.euler_gost_deg)


def test_glonass_wavelengths_and_epochs():
    rng = np.random.default_rng(3)
    truth = [-150.0, 5.0, 12.0]
    los = np.stack([sky(rng, 6), sky(rng, 6)])
    lam = 299792458.0 / (1602e6 + 0.5625e6 * rng.integers(-7, 7, 6))
    r = rotation_from_euler(truth)
    osc = rng.uniform(-3, 3, (2, 1))
    p = np.stack([np.mod(-2 * np.pi / lam * (r.apply(TRIANGLE) @ s.T) + osc, 2 * np.pi) for s in los])
    res = gnssatt.ml_attitude(p, los, TRIANGLE, lam, step_deg=1.5)
    assert np.degrees((res.rotation * r.inv()).magnitude()) < 1e-5


@pytest.mark.slow
def test_mean_statistic_fails_on_wrapped_and_works_on_consistent_phases():
    rng = np.random.default_rng(4)
    errs = {"wrapped": [], "consistent": [], "af": []}
    for _ in range(6):
        truth = rng.uniform([-180, -40, -60], [180, 40, 60])
        los = sky(rng, 8)
        r = rotation_from_euler(truth)
        for key, wrap in (("wrapped", True), ("consistent", False)):
            p = phases(rng, TRIANGLE, los, L1, truth, wrap=wrap)
            res = gnssatt.ml_attitude(p, los, TRIANGLE, L1, statistic="mean", step_deg=1.5)
            errs[key].append(np.degrees((res.rotation * r.inv()).magnitude()))
        p = phases(rng, TRIANGLE, los, L1, truth)
        res = gnssatt.ml_attitude(p, los, TRIANGLE, L1, step_deg=1.5)
        errs["af"].append(np.degrees((res.rotation * r.inv()).magnitude()))
    assert max(errs["consistent"]) < 1e-5
    assert max(errs["af"]) < 1e-5
    assert np.median(errs["wrapped"]) > 3.0, errs


@pytest.mark.slow
def test_branch_and_bound_equals_exhaustive_on_200_scenarios():
    rng = np.random.default_rng(5)
    stats = ["ambiguity_function", "double_difference", "mean"]
    for trial in range(210):
        b = list(GEOMETRIES.values())[trial % 3]
        m = 3 + trial % 8
        los = sky(rng, m)
        truth = rng.uniform([-180, -80, -180], [180, 80, 180])
        p = phases(rng, b, los, L1, truth, noise=rng.uniform(0, 1.0))
        centre = truth + rng.uniform(-15, 15, 3)
        window = np.stack([centre - 20, centre + 20], axis=1)
        kw = dict(statistic=stats[trial % 3], step_deg=2.0, window_deg=window, refine=False)
        ex = gnssatt.ml_attitude(p, los, b, L1, search="exhaustive", **kw)
        bb = gnssatt.ml_attitude(p, los, b, L1, search="branch_and_bound", **kw)
        assert (ex.z_max, tuple(ex.euler_gost_deg)) == (bb.z_max, tuple(bb.euler_gost_deg)), trial


@pytest.mark.slow
def test_branch_and_bound_saves_cells_on_paper_scenario():
    rng = np.random.default_rng(6)
    los = sky(rng, 8)
    truth = [25.0, 3.0, -4.0]
    p = phases(rng, TRIANGLE, los, L1, truth, noise=0.1)
    ex = gnssatt.ml_attitude(p, los, TRIANGLE, L1, step_deg=1.5, refine=False, search="exhaustive")
    bb = gnssatt.ml_attitude(p, los, TRIANGLE, L1, step_deg=1.5, refine=False, search="branch_and_bound")
    auto = gnssatt.ml_attitude(p, los, TRIANGLE, L1, step_deg=1.5, refine=False)
    assert bb.z_max == ex.z_max == auto.z_max
    np.testing.assert_array_equal(bb.euler_gost_deg, ex.euler_gost_deg)
    np.testing.assert_array_equal(auto.euler_gost_deg, ex.euler_gost_deg)
    # 7.0e6 cells: the default search is the branch-and-bound, which evaluates well under 1% of them.
    assert bb.cells_evaluated * 100 < ex.cells_evaluated
    assert auto.cells_evaluated == bb.cells_evaluated


def test_unknown_search_is_refused():
    rng = np.random.default_rng(8)
    los = sky(rng, 6)
    p = phases(rng, TRIANGLE, los, L1, [0.0, 0.0, 0.0])
    with pytest.raises(InvalidInputError, match="expected search 'auto', 'exhaustive' or 'branch_and_bound'"):
        gnssatt.ml_attitude(p, los, TRIANGLE, L1, step_deg=6.0, search="fastest")


@pytest.mark.slow
def test_window_and_prior_from_velocity():
    prior = gnssatt.prior_from_velocity([0.0, 50.0, 0.0])
    np.testing.assert_allclose(prior.euler_gost_deg, [0.0, 0.0, 0.0], atol=1e-12)
    east = gnssatt.prior_from_velocity([50.0, 0.0, 5.0], [0.0, -3.0, 0.0])  # turning right while heading east
    assert east.euler_gost_deg[0] == pytest.approx(-90.0)
    assert east.euler_gost_deg[1] == pytest.approx(np.degrees(np.arctan2(5, 50)))
    assert east.euler_gost_deg[2] == pytest.approx(np.degrees(np.arctan2(3.0, 9.80665)))
    rng = np.random.default_rng(7)
    los = sky(rng, 8)
    truth = east.euler_gost_deg + np.array([3.0, -2.0, 4.0])
    p = phases(rng, TRIANGLE, los, L1, truth)
    res = gnssatt.ml_attitude(p, los, TRIANGLE, L1, window_deg=east)
    full = gnssatt.ml_attitude(p, los, TRIANGLE, L1, search="exhaustive")
    np.testing.assert_allclose(res.euler_gost_deg, full.euler_gost_deg, atol=1e-9)
    assert res.cells_evaluated < full.cells_evaluated / 1000


def test_single_baseline_heading_and_elevation():
    rng = np.random.default_rng(8)
    los = sky(rng, 8)
    heading, elev, length = 237.0, 12.0, 1.2
    h, e = np.radians([heading, elev])
    u = np.array([np.sin(h) * np.cos(e), np.cos(h) * np.cos(e), np.sin(e)])
    p = np.mod(-2 * np.pi / L1 * length * (los @ u) + 1.3, 2 * np.pi)
    res = gnssatt.ml_baseline(p, los, length, L1)
    assert res.heading_deg == pytest.approx(heading, abs=1e-5)
    assert res.elevation_deg == pytest.approx(elev, abs=1e-5)
    np.testing.assert_allclose(res.direction_enu, u, atol=1e-7)
    grid = gnssatt.likelihood_grid(p[None], los, [[length, 0, 0]], L1)
    assert grid.z.shape[2] == 1


def test_long_baseline_needs_a_window_not_the_whole_domain():
    """3.3 km (the GEONET pair): the default step (lambda / 10 L, 3.3e-4 deg) is over the lattice's 2^20
    nodes per turn, refused before any work; a 0.2-deg window around a rough start holds 3.7e5 cells."""
    rng = np.random.default_rng(12)
    los = sky(rng, 8)
    heading, elev, length = 163.3858, 0.0797, 3300.0
    h, e = np.radians([heading, elev])
    u = np.array([np.sin(h) * np.cos(e), np.cos(h) * np.cos(e), np.sin(e)])
    p = np.mod(-2 * np.pi / L1 * length * (los @ u) + 0.4, 2 * np.pi)
    with pytest.raises(InvalidInputError, match="2\\^20 nodes per turn"):
        gnssatt.ml_baseline(p, los, length, L1)
    # eq. (5) heading psi = -compass heading; a start 0.05 deg off, as a code baseline would give.
    start = np.array([-(heading + 0.05), elev - 0.05])
    res = gnssatt.ml_baseline(p, los, length, L1, window_deg=np.stack([start - 0.1, start + 0.1], axis=1))
    assert res.heading_deg == pytest.approx(heading, abs=1e-6)
    assert res.elevation_deg == pytest.approx(elev, abs=1e-6)


def test_default_step_and_grid_shape():
    rng = np.random.default_rng(9)
    los = sky(rng, 8)
    p = phases(rng, TRIANGLE, los, L1, [0, 0, 0])
    grid = gnssatt.likelihood_grid(p, los, TRIANGLE, L1, step_deg=6.0)
    assert grid.z.shape == (60, 31, 60) and grid.z.dtype == np.float32
    res = gnssatt.ml_attitude(p, los, TRIANGLE, L1, window_deg=[[-5, 5], [-5, 5], [-5, 5]])
    expected = np.degrees(L1 / (10 * 0.71))
    assert res.step_deg <= expected and res.step_deg > 0.98 * expected


def test_bad_input_raises_invalid_input_error():
    rng = np.random.default_rng(11)
    los = sky(rng, 6)
    p = phases(rng, TRIANGLE, los, L1, [0, 0, 0])
    ok = dict(phase_diffs=p, los=los, baselines=TRIANGLE, wavelength=L1)

    def call(**kw):
        args = {**ok, **kw}
        gnssatt.ml_attitude(
            args.pop("phase_diffs"), args.pop("los"), args.pop("baselines"), args.pop("wavelength"), **args
        )

    bad_p = p.copy()
    bad_p[1, 2] = np.nan
    cases = [
        dict(phase_diffs=bad_p),
        dict(los=los[:5]),
        dict(phase_diffs=p[:, :2], los=los[:2]),
        dict(baselines=np.array([[0.7, 0, 0], [0, 0, 0]])),
        dict(baselines=np.array([[0.7, 0, 0], [1.4, 0, 0]])),
        dict(baselines=TRIANGLE[:1], phase_diffs=p[:1]),
        dict(wavelength=0.0),
        dict(wavelength=-L1 * np.ones(6)),
        dict(wavelength=np.ones(4)),
        dict(step_deg=20.0),
        dict(step_deg=-1.0),
        dict(window_deg=[[10.2, 10.5], [0, 5], [0, 5]], step_deg=2.0),
        dict(window_deg=[[0, 5], [95, 100], [0, 5]]),
        dict(window_deg=[[5, 0], [0, 5], [0, 5]]),
        dict(statistic="bogus"),
        dict(search="bogus"),
        dict(refine="cubic"),
        dict(los=los * 2),
    ]
    for kw in cases:
        with pytest.raises(InvalidInputError):
            call(**kw)
