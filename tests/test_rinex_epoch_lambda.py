"""Per-epoch LAMBDA on a rotating three-antenna platform written to RINEX 3 and read back (known truth),
ambiguity continuity, the windowed ML grid, and the GEONET pair epoch by epoch."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from scipy import stats

from gnssatt import sim
from gnssatt.data import geonet_dir
from gnssatt.errors import InvalidInputError
from gnssatt.rinex import align_receivers, read_nav, read_obs, static_baseline
from gnssatt.rinex.attitude import attitude_from_rinex
from gnssatt.rinex.epoch_lambda import epoch_lambda
from gnssatt.rinex.scenario import simulate_rinex_array

DATA = geonet_dir()  # the GEONET pair shipped in the package (gnssatt/data)
SIGMA_PHASE = 0.002
N_EP = 20
ANT = sim.equilateral_triangle(1.0, plane="xz")
BODY = ANT[1:] - ANT[0]


def _euler() -> np.ndarray:
    k = np.arange(N_EP)
    return np.stack([-40.0 + 3.0 * k, 5.0 * np.sin(k / 3.0), 3.0 * np.cos(k / 4.0)], axis=1)


@pytest.fixture(scope="module")
def rotating(tmp_path_factory: pytest.TempPathFactory):  # type: ignore[no-untyped-def]
    folder = tmp_path_factory.mktemp("rotating")
    s = simulate_rinex_array(folder, ANT, _euler(), seed=1, phase_sigma_m=SIGMA_PHASE)
    al = align_receivers([read_obs(p) for p in s.obs_paths], read_nav(s.nav_path), elevation_mask_deg=5.0)
    return s, al


def _fixed_baseline_nees(al, sol, truth) -> np.ndarray:  # type: ignore[no-untyped-def]
    """Normalised squared errors of the fixed baselines with the phase-only covariance
    ``2 sigma^2 (A^T C^-1 A)^-1`` (a baseline's double differences: ``2 sigma^2 C``)."""
    out = []
    for e in np.flatnonzero(sol.fixed):
        idx = np.flatnonzero(al.usable[e])
        q = idx[np.argmax(al.elevation_rad[e, idx])]
        a = -(al.los_enu[e, [k for k in idx if k != q]] - al.los_enu[e, q])
        c = np.eye(len(a)) + 1.0
        q_b = 2.0 * SIGMA_PHASE**2 * np.linalg.inv(a.T @ np.linalg.solve(c, a))
        for i in range(truth.shape[1]):
            d = sol.baselines_enu_m[e, i] - truth[e, i]
            out.append(d @ np.linalg.solve(q_b, d))
    return np.array(out)


def test_single_epoch_constrained_fix_matches_truth(rotating) -> None:  # type: ignore[no-untyped-def]
    s, al = rotating
    sol = epoch_lambda(al, BODY, sigma_phase_m=SIGMA_PHASE)
    assert sol.fixed.sum() >= 10 and not sol.held.any()
    nees = _fixed_baseline_nees(al, sol, s.baselines_enu_m)
    # every fixed baseline chi-square(3): a wrong integer moves it by a wavelength fraction (~ 100 sigma)
    assert nees.max() < stats.chi2.ppf(1 - 1e-6, 3)
    # mean of n chi-square(3) (pairs of baselines correlated: n/2 independent pairs bound the spread)
    n = len(nees)
    assert abs(nees.mean() - 3.0) < 4.0 * np.sqrt(2 * 3.0 / (n / 2))
    rot = sol.rotation_enu_from_body[sol.fixed]
    truth_dirs = s.baselines_enu_m[sol.fixed]
    fitted = np.einsum("tij,aj->tai", rot, BODY)
    assert np.max(np.linalg.norm(fitted - truth_dirs, axis=2)) < 0.02  # mm-level baselines -> sub-degree


def test_continuity_holds_the_same_integers(rotating) -> None:  # type: ignore[no-untyped-def]
    s, al = rotating
    single = epoch_lambda(al, BODY, sigma_phase_m=SIGMA_PHASE)
    held = epoch_lambda(al, BODY, sigma_phase_m=SIGMA_PHASE, continuity=True)
    assert held.held.sum() > 0 and held.fixed.sum() >= single.fixed.sum()
    both = single.fixed & held.fixed
    # the same integers give the same baselines (to rounding)
    np.testing.assert_allclose(held.baselines_enu_m[both], single.baselines_enu_m[both], atol=1e-9)
    nees = _fixed_baseline_nees(al, held, s.baselines_enu_m)
    assert nees.max() < stats.chi2.ppf(1 - 1e-6, 3)


def test_undetected_slip_drops_held_integers(rotating) -> None:  # type: ignore[no-untyped-def]
    s, al = rotating
    phase = al.phase_cycles.copy()
    k = int(np.argmin(np.nanmean(al.elevation_rad, axis=0)))  # not the reference satellite
    phase[1, 10:, k] += 1.0  # one cycle, no loss-of-lock flag, far below the code-jump threshold
    slipped = dataclasses.replace(al, phase_cycles=phase)
    sol = epoch_lambda(slipped, BODY, sigma_phase_m=SIGMA_PHASE, continuity=True)
    assert sol.fixed[10:].any()
    nees = _fixed_baseline_nees(slipped, sol, s.baselines_enu_m)
    assert nees.max() < stats.chi2.ppf(1 - 1e-6, 3)


def test_attitude_lambda_and_windowed_ml_agree_with_truth(rotating) -> None:  # type: ignore[no-untyped-def]
    s, _ = rotating
    truth = np.stack([(-s.euler_deg[:, 0]) % 360.0, s.euler_deg[:, 1], s.euler_deg[:, 2]], axis=1)
    lam = attitude_from_rinex(s.obs_paths, s.nav_path, BODY, method="lambda", elevation_mask_deg=5.0)
    assert set(lam.method) == {"lambda"} and lam.fixed.sum() >= 10
    d = (lam.angles_deg[lam.fixed == 1] - truth[lam.fixed == 1] + 180.0) % 360.0 - 180.0
    assert np.max(np.abs(d)) < 1.5  # 5-sigma of ~ 3 mm baseline errors over 1 m
    full = attitude_from_rinex(s.obs_paths, s.nav_path, BODY, method="ml", elevation_mask_deg=5.0)
    win = attitude_from_rinex(
        s.obs_paths, s.nav_path, BODY, method="ml", window_deg=10.0, elevation_mask_deg=5.0
    )

    def err(a: np.ndarray) -> np.ndarray:
        return np.max(np.abs((a - truth + 180.0) % 360.0 - 180.0), axis=1)

    # six satellites: the whole-domain grid picks a wrong peak at some epochs; the window (the platform
    # turns 3 deg per epoch) keeps the right one, and where both are right they are the same lattice maximum
    right = err(full.angles_deg) < 1.5
    assert right[0] and np.all(err(win.angles_deg) < 1.5)
    np.testing.assert_allclose(win.angles_deg[right], full.angles_deg[right], atol=1e-6)


def test_bad_arguments(rotating) -> None:  # type: ignore[no-untyped-def]
    s, al = rotating
    with pytest.raises(InvalidInputError, match=r"baselines_body of shape \(2, 3\)"):
        epoch_lambda(al, BODY[:1])
    with pytest.raises(InvalidInputError, match="candidates"):
        epoch_lambda(al, BODY, candidates=1)
    with pytest.raises(InvalidInputError, match="sigma_code_m >="):
        epoch_lambda(al, BODY, sigma_code_m=0.0)
    with pytest.raises(InvalidInputError, match="window_deg >"):
        attitude_from_rinex(s.obs_paths, s.nav_path, BODY, window_deg=-1.0)
    with pytest.raises(InvalidInputError, match="motion"):
        attitude_from_rinex(s.obs_paths, s.nav_path, BODY, motion="flying")  # type: ignore[arg-type]
    with pytest.raises(InvalidInputError, match="three or more antennas"):
        attitude_from_rinex(s.obs_paths[:2], s.nav_path, BODY[:1])


@pytest.mark.skipif(not DATA.is_dir(), reason="GEONET test data not present")
def test_geonet_single_epoch_is_not_fixed_but_float_is_near() -> None:
    al = align_receivers(
        [read_obs(DATA / "07590920.05o"), read_obs(DATA / "30400920.05o")],
        read_nav(DATA / "07590920.05n"),
        systems="G",
    )
    ref = static_baseline(al).baseline_enu_m
    sol = epoch_lambda(al, None)
    # single-epoch L1 code over 3.3 km: success rate far below 0.99, so nothing is accepted (the ratio test
    # alone would accept wrong integers)
    assert np.median(sol.success_rate) < 0.9 and not sol.fixed.any()
    err = np.linalg.norm(sol.baselines_enu_m[:, 0] - ref, axis=1)
    assert np.median(err) < 10.0  # float from metre-level codes, DOP of a few
