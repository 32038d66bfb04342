"""Orbit-determination filter of Dzhepe Ali: Rust vs the numpy reference, chi-square consistency over Monte
Carlo runs (NIS and NEES), long stretches with two tracked satellites, the receiver fix, bad input."""

from __future__ import annotations

import numpy as np
import pytest
from references.orbit_reference import tight_filter
from scipy.stats import chi2

from gnssatt import orbit, sim
from gnssatt.errors import InvalidInputError
from gnssatt.orbit.determination import noisy_orbit, orbit_filter, receiver_fix

LEO = orbit.CircularOrbit(6_878_137.0, np.radians(97.4), 0.3, 0.0)
P0 = np.diag([30.0**2] * 3 + [0.05**2] * 3)
CONSTELLATION = sim.gps_nominal() + sim.glonass_nominal()


def _scenario(
    seed: int, n_t: int, q: float, constellation: sim.Constellation = CONSTELLATION, **kwargs: object
) -> tuple[np.ndarray, sim.SpaceborneMeasurements, np.ndarray]:
    rng = np.random.default_rng(seed)
    t = np.arange(n_t) * 10.0
    r, v = LEO.state_ecef(t[:1])
    truth = noisy_orbit(np.concatenate([r[0], v[0]]), t, rng=rng, accel_psd_m2_s3=q)
    meas = sim.simulate_spaceborne(truth[:, :3], truth[:, 3:], t, constellation, rng, **kwargs)  # type: ignore[arg-type]
    x0 = truth[0] + rng.multivariate_normal(np.zeros(6), P0)
    return truth, meas, x0


@pytest.mark.slow
def test_rust_filter_matches_numpy_reference() -> None:
    _, meas, x0 = _scenario(3, 25, 1e-8, outages=[(100.0, 150.0, 3)])
    res = orbit_filter(meas, x0, P0, coupling="tight", accel_psd_m2_s3=1e-8, step_s=5.0)
    xs, ps, nis = tight_filter(meas, x0, P0, accel_psd_m2_s3=1e-8, step_s=5.0)
    # Same equations; the reference differentiates the gravity numerically (1 m steps: ~1e-13 relative
    # error in F) and orders its sums differently: agreement to 1e-6 m / 1e-9 m/s and 1e-6 in NIS.
    np.testing.assert_allclose(res.states[:, :3], xs[:, :3], rtol=0, atol=1e-6)
    np.testing.assert_allclose(res.states[:, 3:], xs[:, 3:], rtol=0, atol=1e-9)
    np.testing.assert_allclose(res.covariances, ps, rtol=1e-6, atol=1e-12)
    np.testing.assert_allclose(res.nis, nis, rtol=1e-6, equal_nan=True)
    assert np.array_equal(np.isnan(res.nis), res.nis_dof == 0)


@pytest.mark.slow
@pytest.mark.parametrize(("coupling", "systems"), [("tight", "G"), ("tight", "GR"), ("loose", "GR")])
def test_filter_is_consistent_over_monte_carlo_runs(coupling: str, systems: str) -> None:
    q, runs, n_t = 1e-8, 12, 40
    nis_sum, dof_sum, nees_final = 0.0, 0, []
    for seed in range(runs):
        truth, meas, x0 = _scenario(100 + seed, n_t, q)
        res = orbit_filter(meas.select_systems(systems), x0, P0, coupling=coupling, accel_psd_m2_s3=q)
        ok = res.nis_dof > 0
        nis_sum += float(res.nis[ok].sum())
        dof_sum += int(res.nis_dof[ok].sum())
        nees_final.append(res.nees(truth)[-1])
    # Innovations of a consistent linear-Gaussian filter are white: the NIS summed over epochs and runs is
    # chi-square with the summed degrees of freedom. Final-epoch NEES of independent runs: chi-square(6 runs).
    # Two-sided 99.9 % bounds (fixed seeds; the linearisation error is ~1e-6 of the innovations).
    lo, hi = chi2.ppf([0.0005, 0.9995], dof_sum)
    assert lo < nis_sum < hi, (nis_sum, dof_sum)
    lo, hi = chi2.ppf([0.0005, 0.9995], 6 * runs)
    assert lo < sum(nees_final) < hi, nees_final


@pytest.mark.slow
def test_two_satellites_keep_the_tightly_coupled_filter_bounded() -> None:
    q = 1e-6  # large process noise, so that prediction alone would drift visibly
    window = (200.0, 1400.0)
    kept = {}
    for n_sats in (0, 2):
        truth, gps, x0 = _scenario(7, 150, q, sim.gps_nominal(), outages=[(*window, n_sats)])
        inside = (gps.times_s >= window[0]) & (gps.times_s <= window[1])
        if n_sats == 2:
            # No fix exists during the window.
            assert np.all(gps.visible[inside].sum(axis=1) == 2)
            assert not receiver_fix(gps).valid[inside].any()
        res = orbit_filter(gps, x0, P0, coupling="tight", accel_psd_m2_s3=q)
        kept[n_sats] = (res, truth, inside)
    res2, truth, inside = kept[2]
    sig2 = res2.sigma()[inside, :3]
    sig0 = kept[0][0].sigma()[inside, :3]
    # One pseudorange and one range-rate difference per epoch observe the orbit over time: at the end of
    # the 20-minute window the position sigma is well below that of pure prediction.
    assert np.linalg.norm(sig2[-1]) < 0.5 * np.linalg.norm(sig0[-1])
    err = np.abs(res2.states[inside, :3] - truth[inside, :3])
    # And the filter's bounds hold: 5 sigma (per-sample exceedance 6e-7; 360 samples).
    assert np.all(err < 5 * sig2)


def test_receiver_fix_is_exact_without_noise() -> None:
    truth, meas, _ = _scenario(11, 5, 0.0, code_sigma_m=1e-9, doppler_sigma_hz=1e-9)
    fix = receiver_fix(meas)
    assert fix.valid.all()
    np.testing.assert_allclose(fix.position_m, truth[:, :3], atol=1e-4)
    np.testing.assert_allclose(fix.velocity_m_s, truth[:, 3:], atol=1e-6)
    # With fewer than 4 satellites there is no fix.
    _, few, _ = _scenario(11, 5, 0.0, outages=[(0.0, 100.0, 3)])
    assert not receiver_fix(few).valid.any()


def test_filter_bad_input() -> None:
    truth, meas, x0 = _scenario(5, 6, 1e-8)
    with pytest.raises(InvalidInputError, match="no measurement"):
        _, none, _ = _scenario(5, 6, 1e-8, outages=[(0.0, 100.0, 1)])
        orbit_filter(none, x0, P0)
    # SpaceborneMeasurements is also the intake of a real receiver's data: it refuses these on construction.
    with pytest.raises(InvalidInputError, match="non-finite"):
        sim.SpaceborneMeasurements(**{**meas.__dict__, "pseudorange_m": np.where(meas.visible, np.inf, 0.0)})
    with pytest.raises(InvalidInputError, match="non-finite"):
        orbit_filter(meas, np.full(6, np.nan), P0)
    with pytest.raises(InvalidInputError, match="strictly increasing"):
        sim.SpaceborneMeasurements(**{**meas.__dict__, "times_s": meas.times_s[::-1].copy()})
    with pytest.raises(InvalidInputError, match="coupling"):
        orbit_filter(meas, x0, P0, coupling="ultra")
    with pytest.raises(InvalidInputError, match=r"\(6, 6\)"):
        orbit_filter(meas, x0, np.eye(5))
    with pytest.raises(TypeError, match="SpaceborneMeasurements"):
        orbit_filter(truth, x0, P0)  # type: ignore[arg-type]


@pytest.mark.parametrize("radius_m", [1.5e6, 6.0e6, 0.98 * 6_378_136.0])
def test_noisy_orbit_refuses_x0_below_the_models_surface_by_name(radius_m: float) -> None:
    # The core propagates only above 0.99 of the model's equatorial radius; the check before it names x0
    # (a radius of 1e6-6.3e6 m used to pass and come back from the core as position_m).
    x0 = np.array([radius_m, 0.0, 0.0, 0.0, 7.5e3, 0.0])
    with pytest.raises(InvalidInputError, match=r"x0\[:3\]"):
        noisy_orbit(x0, np.arange(0.0, 30.0, 10.0), 1, accel_psd_m2_s3=0.0)
    with pytest.raises(InvalidInputError, match="position_m"):
        orbit.glonass_propagate([radius_m, 0.0, 0.0], [0.0, 7.5e3, 0.0], 10.0)
    with pytest.raises(InvalidInputError, match="radius_m"):
        orbit.CircularOrbit(radius_m, 0.0, 0.0, 0.0)


def test_the_orbit_radius_bound_is_the_cores() -> None:
    # Just above the bound the core propagates (no error from either layer).
    r = 1.0001 * orbit.MIN_ORBIT_RADIUS_FRACTION * orbit.GlonassModel().equatorial_radius_m
    state = orbit.glonass_propagate([r, 0.0, 0.0], [0.0, 7.9e3, 0.0], 10.0)
    assert np.isfinite(state.position_m).all()
