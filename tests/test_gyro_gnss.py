"""Gyro + multi-antenna GNSS filter (Dzhepe Ali): kinematics, consistency, ambiguities, sensitivity, bad
input.

Statistical checks use fixed seeds; their bounds are chi-square quantiles at a two-sided level of 1e-3 per
check (so a correct filter fails a check about once in a thousand seeds), or binomial arguments stated at
the check.
"""

from __future__ import annotations

from functools import cache
from pathlib import Path

import numpy as np
import pytest
from references.gyro_gnss_numpy import run_reference
from scipy.spatial.transform import Rotation
from scipy.stats import chi2

from gnssatt import sim
from gnssatt.attitude.gyro_gnss import gyro_gnss_filter, gyro_propagate
from gnssatt.attitude.phase_attitude import phase_attitude_fixes
from gnssatt.errors import InvalidInputError
from gnssatt.experiments import gyro_gnss as exp
from gnssatt.sim import attitude_scenario as sc

RX = sim.OrbitalReceiver(altitude_m=700e3, inclination_deg=51.6)
ARW = 1e-5  # rad/s/sqrt(Hz)
DRIFT = np.radians([10.0, -5.0, 3.0]) / 3600.0
BASELINES = sim.equilateral_triangle(1.0)[1:]
SIGMA_ATT = np.radians(0.5)
SIGMA_DRIFT = np.radians(20.0) / 3600.0
P0 = np.diag([SIGMA_ATT**2] * 3 + [SIGMA_DRIFT**2] * 3)
LEVEL = 1e-3


@cache
def gnss() -> sim.Constellation:
    return sim.gps_nominal() + sim.glonass_nominal()


@cache
def motion(duration_s: float) -> tuple[np.ndarray, Rotation, np.ndarray]:
    t = np.arange(0.0, duration_s + 1e-9, 0.1)
    att, rate = sc.orbital_hold_motion(
        RX, t, np.radians([2.0, 1.0, 3.0]), [200.0, 250.0, 300.0], [0.0, 1.0, 2.0]
    )
    return t, att, rate


def trial(
    seed: int,
    duration_s: float = 300.0,
    *,
    phase_sigma_cycles: float = 0.01,
    max_satellites: int | None = None,
    mode: str = "tight",
    slips: tuple = (),
    **kw: object,
) -> tuple:
    """One run: (result, errors at the outputs, phases)."""
    rng = np.random.default_rng(seed)
    t, att, _ = motion(duration_s)
    g = sc.gyro_output(t, att, rng, drift_rad_s=DRIFT, arw=ARW)
    ph = sc.phase_observations(
        RX,
        gnss(),
        t[::10],
        att[::10],
        BASELINES,
        rng,
        phase_sigma_cycles=phase_sigma_cycles,
        max_satellites=max_satellites,
        slips=slips,
    )
    e0 = rng.multivariate_normal(np.zeros(6), P0)
    q0 = att[0] * Rotation.from_rotvec(-e0[:3])
    meas: dict[str, object] = {"phases": ph, "baselines_m": BASELINES}
    if mode == "loose":
        meas = {
            "attitude_fixes": sc.attitude_fixes(
                ph, att[::10], BASELINES, rng, phase_sigma_cycles=phase_sigma_cycles
            )
        }
    elif mode == "matrix":
        meas = {
            "attitude_fixes": phase_attitude_fixes(
                ph, BASELINES, ph.ambiguity, phase_sigma_cycles=phase_sigma_cycles
            )
        }
    r = gyro_gnss_filter(
        t,
        g.rates,
        initial_rotation=q0,
        initial_covariance=P0,
        initial_drift=DRIFT - e0[3:],
        arw=ARW,
        phase_sigma_cycles=phase_sigma_cycles,
        output_every=10,
        **meas,
        **kw,
    )
    return r, r.errors(att[::10], g.drift[::10]), ph


def chi2_bounds(dof: int) -> tuple[float, float]:
    return chi2.ppf(LEVEL / 2, dof), chi2.isf(LEVEL / 2, dof)


# --- kinematics and scenario ------------------------------------------------------------------------------


def test_constant_rate_propagation_matches_closed_form() -> None:
    w = np.array([0.01, -0.02, 0.03])
    t = np.linspace(0.0, 100.0, 1001)
    q0 = Rotation.from_euler("ZYX", [30.0, 10.0, -20.0], degrees=True)
    q = gyro_propagate(q0.as_quat(), t, np.tile(w, (len(t), 1))).rotation
    closed = q0 * Rotation.from_rotvec(np.outer(t, w))
    assert np.max((q.inv() * closed).magnitude()) < 1e-12


def test_truth_rate_is_the_derivative_of_the_truth_attitude() -> None:
    t = np.array([10.0, 123.4, 250.0])
    h = 1e-3
    amp, per, ph = np.radians([5.0, 3.0, 4.0]), [100.0, 130.0, 170.0], [0.3, 1.0, 2.0]
    _, rate = sc.orbital_hold_motion(RX, t, amp, per, ph)
    before, _ = sc.orbital_hold_motion(RX, t - h, amp, per, ph)
    after, _ = sc.orbital_hold_motion(RX, t + h, amp, per, ph)
    numeric = (before.inv() * after).as_rotvec() / (2 * h)
    # central difference error ~ |omega''| h^2 / 6 (< 1e-9 rad/s here); 1e-8 leaves room for round-off
    np.testing.assert_allclose(rate, numeric, atol=1e-8)


def test_noise_free_gyro_reproduces_the_truth() -> None:
    t, att, _ = motion(300.0)
    g = sc.gyro_output(t, att, np.random.default_rng(0), drift_rad_s=np.zeros(3), arw=0.0)
    q = gyro_propagate(att[0].as_quat(), t, g.rates).rotation
    assert np.max((q.inv() * att).magnitude()) < 1e-9


# --- Rust against the numpy reference ----------------------------------------------------------------------


@pytest.mark.slow
@pytest.mark.parametrize("mode", ["tight", "loose"])
def test_rust_filter_matches_numpy_reference(mode: str) -> None:
    rng = np.random.default_rng(5)
    t, att, _ = motion(60.0)
    g = sc.gyro_output(t, att, rng, drift_rad_s=DRIFT, arw=ARW)
    ph = sc.phase_observations(
        RX, gnss(), t[::10], att[::10], BASELINES, rng, phase_sigma_cycles=0.01, max_satellites=4
    )
    fixes = (
        sc.attitude_fixes(ph, att[::10], BASELINES, rng, phase_sigma_cycles=0.01) if mode == "loose" else None
    )
    phases = ph if mode == "tight" else None
    q0 = att[0] * Rotation.from_rotvec(np.radians([0.3, -0.2, 0.4]))
    r = gyro_gnss_filter(
        t,
        g.rates,
        initial_rotation=q0,
        initial_covariance=P0,
        arw=ARW,
        rrw=1e-9,
        baselines_m=BASELINES,
        phases=phases,
        attitude_fixes=fixes,
        fix_ambiguities=False,
        slip_false_alarm=None,
    )
    q, b, p = run_reference(t, g.rates, q0, np.zeros(3), P0, ARW, 1e-9, BASELINES, 0.01, fixes, phases)
    assert np.max((r.rotation.inv() * Rotation.from_quat(q)).magnitude()) < 1e-10
    np.testing.assert_allclose(r.drift, b, atol=1e-13)
    np.testing.assert_allclose(r.covariance, p, rtol=1e-7, atol=1e-16)


# --- consistency -------------------------------------------------------------------------------------------


@pytest.mark.slow
@pytest.mark.parametrize("mode", ["tight", "loose", "matrix"])
def test_filter_is_consistent_over_monte_carlo_runs(mode: str) -> None:
    runs = 30
    results = [trial(seed, mode=mode) for seed in range(runs)]
    nees = np.array([r.nees(e) for r, e, _ in results])
    lo, hi = chi2_bounds(6 * runs)
    # sum over runs of NEES ~ chi2(6 runs) at each time for a consistent filter
    for k in (1, 10, 100, 300):
        assert lo <= nees[:, k].sum() <= hi, (k, nees[:, k].mean())


@pytest.mark.slow
def test_tightly_coupled_converges_with_two_satellites_where_loosely_coupled_cannot() -> None:
    runs = 20
    tight = [trial(seed, max_satellites=2) for seed in range(runs)]
    loose = [trial(seed, max_satellites=2, mode="loose") for seed in range(runs)]
    # the receiver's own solution needs three lines of sight: no loosely coupled update happens at all
    assert all(len(r.nis) == 0 for r, _, _ in loose)
    sig = lambda r: np.degrees(np.sqrt(np.linalg.eigvalsh(r.covariance[-1][:3, :3]).max()))  # noqa: E731
    assert all(sig(r) > np.degrees(SIGMA_ATT) for r, _, _ in loose)
    assert all(sig(r) < 0.05 for r, _, _ in tight)
    nees = sum(r.nees(e)[-1] for r, e, _ in tight)
    lo, hi = chi2_bounds(6 * runs)
    assert lo <= nees <= hi


# --- ambiguities -------------------------------------------------------------------------------------------


def wrong_fixes(results: list) -> tuple[int, int]:
    accepted = wrong = 0
    for r, _, ph in results:
        truth = {int(tr): a for tr, a in zip(ph.track, ph.ambiguity, strict=True)}
        for f in r.fixes:
            if f.accepted:
                accepted += 1
                wrong += any(truth[tr][bl] != v for tr, bl, v in f.values)
    return accepted, wrong


@pytest.mark.slow
def test_validation_stops_the_wrong_fixes_that_an_unvalidated_filter_makes() -> None:
    # noisy phases (0.3 cycle) and two satellites: the first float solutions round wrongly about a third of
    # the time
    runs = 20
    kw = {"phase_sigma_cycles": 0.3, "max_satellites": 2}
    checked = [trial(seed, **kw) for seed in range(runs)]
    unchecked = [trial(seed, **kw, ratio_threshold=1.0, min_success_rate=0.0) for seed in range(runs)]
    n_ok, wrong_ok = wrong_fixes(checked)
    _, wrong_bad = wrong_fixes(unchecked)
    assert n_ok >= runs  # at least one fix per run
    # each accepted fix had a success rate >= 0.999; with < 200 fixes P(>= 3 wrong) < 2e-3
    assert n_ok < 200 and wrong_ok <= 2
    assert wrong_bad >= 5


@pytest.mark.slow
def test_fixed_failure_rate_test_admits_fixes_the_success_rate_gate_alone_refuses() -> None:
    # The observation engine's gate (lambda::gate): with min_success_rate = 1 only a converged float set
    # (bootstrapped rate 1 in f64) fixes; with max_failure_rate > 0 the fixed-failure-rate test admits
    # earlier sets whose ratio makes a wrong fix unlikely.
    runs = 10
    kw = {"phase_sigma_cycles": 0.3, "max_satellites": 2, "min_success_rate": 1.0}
    off = [trial(seed, **kw) for seed in range(runs)]
    on = [trial(seed, **kw, max_failure_rate=0.01) for seed in range(runs)]
    assert all(f.success_rate >= 1.0 for r, _, _ in off for f in r.fixes if f.accepted)
    admitted = [f for r, _, _ in on for f in r.fixes if f.accepted and f.success_rate < 1.0]
    assert len(admitted) >= runs
    n_on, wrong_on = wrong_fixes(on)
    # each admitted fix has a wrong-fix probability of at most about 0.01: with n_on < 200 fixes,
    # P(>= 7 wrong | p = 0.01) < 5e-3 (binomial)
    assert n_on < 200 and wrong_on <= 6


def test_max_failure_rate_outside_its_range_is_rejected() -> None:
    for bad in (-0.01, 0.2, float("nan")):
        with pytest.raises(InvalidInputError, match="max_failure_rate"):
            gyro_gnss_filter(np.arange(11.0), np.zeros((11, 3)), **base_args(), max_failure_rate=bad)


def test_cycle_slip_is_detected_and_the_ambiguity_refixed() -> None:
    t, att, _ = motion(300.0)
    seen = sc.phase_observations(
        RX, gnss(), t[::10], att[::10], BASELINES, np.random.default_rng(0), phase_sigma_cycles=0.01
    )
    sat = int(np.bincount(seen.satellite).argmax())  # visible throughout (checked below)
    assert np.all(np.isin(np.arange(len(seen.epoch_t)), seen.epoch[seen.satellite == sat]))
    r, e, ph = trial(3, slips=((150.0, sat, 1),))
    slipped = int(ph.track[ph.satellite == sat][0])
    assert [(t, int(tr)) for t, tr, _ in r.slips] == [(150.0, slipped)]
    refix = [
        f for f in r.fixes if f.accepted and f.t >= 150.0 and any(tr == slipped for tr, _, _ in f.values)
    ]
    truth_after = ph.ambiguity[(ph.track == slipped) & (ph.epoch_t[ph.epoch] >= 150.0)][0]
    assert refix and [v for tr, _, v in refix[0].values if tr == slipped] == truth_after.tolist()
    assert r.nees(e)[-1] < chi2.isf(LEVEL, 6)


# --- sensitivity -------------------------------------------------------------------------------------------


@pytest.mark.slow
def test_true_error_covariance_matches_monte_carlo_errors() -> None:
    runs, duration = 40, 300.0
    mis, base = np.radians(0.5), 0.005
    t, att, _ = motion(duration)
    z_true, z_filter = [], []
    for seed in range(runs):
        rng = np.random.default_rng(seed)
        mu, db = rng.normal(0.0, mis, 3), rng.normal(0.0, base, (2, 3))
        g = sc.gyro_output(t, att, rng, drift_rad_s=DRIFT, arw=ARW, misalignment_rad=mu)
        ph = sc.phase_observations(
            RX, gnss(), t[::10], att[::10], BASELINES, rng, phase_sigma_cycles=0.01, baseline_errors_m=db
        ).without_ambiguities()
        e0 = rng.multivariate_normal(np.zeros(6), P0)
        r = gyro_gnss_filter(
            t,
            g.rates,
            initial_rotation=att[0] * Rotation.from_rotvec(-e0[:3]),
            initial_covariance=P0,
            initial_drift=DRIFT - e0[3:],
            arw=ARW,
            output_every=1000,
            phases=ph,
            baselines_m=BASELINES,
            known_ambiguities=True,
            sensitivity=(mis, base),
        )
        e = r.errors(att[::1000], g.drift[::1000])[-1]
        z_true.append(e / np.sqrt(np.diag(r.true_covariance[-1])))
        z_filter.append(e / np.sqrt(np.diag(r.covariance[-1])))
    z_true, z_filter = np.array(z_true), np.array(z_filter)
    # per component, sum of squared normalised errors ~ chi2(runs); Bonferroni over the 6 components
    lo, hi = chi2.ppf(LEVEL / 12, runs), chi2.isf(LEVEL / 12, runs)
    assert np.all((lo <= (z_true**2).sum(0)) & ((z_true**2).sum(0) <= hi)), (z_true**2).mean(0)
    # the reduced filter's own covariance misses the baseline errors: its attitude errors are far too large
    assert np.all((z_filter[:, :3] ** 2).sum(0) > hi)


# --- bad input ---------------------------------------------------------------------------------------------


def base_args() -> dict:
    return {"initial_rotation": Rotation.identity(), "initial_covariance": P0, "arw": ARW}


def test_non_finite_rates_are_rejected() -> None:
    rates = np.zeros((11, 3))
    rates[4, 1] = np.nan
    with pytest.raises(InvalidInputError, match="gyro_rates"):
        gyro_gnss_filter(np.arange(11.0), rates, **base_args())


def test_non_increasing_time_stamps_are_rejected() -> None:
    t = np.arange(11.0)
    t[5] = t[4]
    with pytest.raises(InvalidInputError, match="strictly increasing"):
        gyro_gnss_filter(t, np.zeros((11, 3)), **base_args())
    with pytest.raises(InvalidInputError, match="one per time stamp"):
        gyro_gnss_filter(np.arange(11.0), np.zeros((10, 3)), **base_args())


def test_measurements_outside_the_gyro_record_are_rejected() -> None:
    t, att, _ = motion(60.0)
    ph = sc.phase_observations(
        RX, gnss(), t[::10] + 5.0, att[::10], BASELINES, np.random.default_rng(0), phase_sigma_cycles=0.01
    )
    with pytest.raises(InvalidInputError, match="within the gyro record"):
        gyro_gnss_filter(t, np.zeros((len(t), 3)), **base_args(), baselines_m=BASELINES, phases=ph)


def test_zero_length_baseline_is_rejected() -> None:
    t, att, _ = motion(60.0)
    ph = sc.phase_observations(
        RX, gnss(), t[::10], att[::10], BASELINES, np.random.default_rng(0), phase_sigma_cycles=0.01
    )
    bad = BASELINES.copy()
    bad[1] = 0.0
    with pytest.raises(InvalidInputError, match="baseline 1 has length 0"):
        gyro_gnss_filter(t, np.zeros((len(t), 3)), **base_args(), baselines_m=bad, phases=ph)


def test_sensitivity_needs_known_ambiguities() -> None:
    t, att, _ = motion(60.0)
    ph = sc.phase_observations(
        RX, gnss(), t[::10], att[::10], BASELINES, np.random.default_rng(0), phase_sigma_cycles=0.01
    )
    with pytest.raises(InvalidInputError, match="known ambiguities"):
        gyro_gnss_filter(
            t,
            np.zeros((len(t), 3)),
            **base_args(),
            baselines_m=BASELINES,
            phases=ph,
            sensitivity=(0.01, 0.01),
        )


def test_true_error_covariance_equals_the_filters_without_unmodelled_errors() -> None:
    rng = np.random.default_rng(2)
    t, att, _ = motion(60.0)
    g = sc.gyro_output(t, att, rng, drift_rad_s=DRIFT, arw=ARW)
    ph = sc.phase_observations(RX, gnss(), t[::10], att[::10], BASELINES, rng, phase_sigma_cycles=0.01)
    r = gyro_gnss_filter(
        t,
        g.rates,
        initial_rotation=att[0],
        initial_covariance=P0,
        arw=ARW,
        baselines_m=BASELINES,
        phases=ph.without_ambiguities(),
        known_ambiguities=True,
        sensitivity=(0.0, 0.0),
    )
    assert r.true_covariance is not None
    # both are the Joseph-form covariance of the same gains: equal up to round-off
    np.testing.assert_allclose(r.true_covariance, r.covariance, rtol=1e-9, atol=1e-20)


@pytest.mark.slow
def test_misalignment_states_make_the_filter_consistent_where_the_reduced_one_is_not() -> None:
    runs, sigma_mu = 20, np.radians(1.0)
    t, att, _ = motion(300.0)
    nees_full, nees_mu, nees_reduced = 0.0, 0.0, 0.0
    for seed in range(runs):
        rng = np.random.default_rng(seed)
        mu = rng.normal(0.0, sigma_mu, 3)
        g = sc.gyro_output(t, att, rng, drift_rad_s=DRIFT, arw=ARW, misalignment_rad=mu)
        ph = sc.phase_observations(RX, gnss(), t[::10], att[::10], BASELINES, rng, phase_sigma_cycles=0.01)
        e0 = rng.multivariate_normal(np.zeros(6), P0)
        kw = {
            "initial_rotation": att[0] * Rotation.from_rotvec(-e0[:3]),
            "initial_covariance": P0,
            "initial_drift": DRIFT - e0[3:],
            "arw": ARW,
            "output_every": len(t) - 1,
            "phases": ph,
            "baselines_m": BASELINES,
        }
        truth = (att[[0, -1]], g.drift[[0, -1]])
        full = gyro_gnss_filter(t, g.rates, **kw, misalignment_sigma_rad=sigma_mu)
        reduced = gyro_gnss_filter(t, g.rates, **kw)
        nees_full += full.nees(full.errors(*truth))[-1]
        e_mu = mu - full.misalignment[-1]
        nees_mu += e_mu @ np.linalg.solve(full.misalignment_covariance[-1], e_mu)
        nees_reduced += reduced.nees(reduced.errors(*truth))[-1]
    lo, hi = chi2_bounds(6 * runs)
    assert lo <= nees_full <= hi
    lo3, hi3 = chi2_bounds(3 * runs)
    assert lo3 <= nees_mu <= hi3
    assert nees_reduced > hi


def test_attitude_fixes_out_of_order_are_rejected() -> None:
    t, att, _ = motion(60.0)
    fixes = sc.AttitudeFixes(np.array([20.0, 10.0]), att[[200, 100]], np.tile(np.eye(3) * 1e-6, (2, 1, 1)))
    with pytest.raises(InvalidInputError, match="in order"):
        gyro_gnss_filter(t, np.zeros((len(t), 3)), **base_args(), attitude_fixes=fixes)


# --- loosely coupled input from matrix_attitude ------------------------------------------------------------


def repeated_epoch(
    los: np.ndarray, wavelength: np.ndarray, truth: Rotation, baselines: np.ndarray, sigma: float, draws: int
) -> sc.PhaseObservations:
    """``draws`` epochs of the same geometry (truth body -> ECI), independent phase noise, random integers."""
    rng = np.random.default_rng(11)
    n = len(los)
    geom = -(truth.inv().apply(los) @ baselines.T) / wavelength[:, None]
    amb = rng.integers(-50, 51, size=(draws * n, len(baselines)))
    return sc.PhaseObservations(
        np.arange(float(draws)),
        np.repeat(np.arange(draws), n),
        np.tile(np.arange(n), draws),
        np.tile(los, (draws, 1)),
        np.tile(wavelength, draws),
        np.tile(geom, (draws, 1)) + amb + sigma * rng.standard_normal((draws * n, len(baselines))),
        amb,
        np.tile(np.arange(n), draws),
    )


@pytest.mark.slow
@pytest.mark.parametrize("n_sat", [3, None])
def test_matrix_fix_covariance_matches_monte_carlo_errors(n_sat: int | None) -> None:
    # one epoch of the scenario: three satellites (the fewest a coplanar array needs) or all (GPS + GLONASS,
    # several wavelengths); a noisy 0.05 cycle so that the errors are far from round-off
    draws, sigma = 500, 0.05
    t, att, _ = motion(60.0)
    ph = sc.phase_observations(
        RX,
        gnss(),
        t[:1],
        att[:1],
        BASELINES,
        np.random.default_rng(0),
        phase_sigma_cycles=0.0,
        max_satellites=n_sat,
    )
    assert n_sat is not None or len(np.unique(ph.wavelength)) > 1
    mc = repeated_epoch(ph.los, ph.wavelength, att[0], BASELINES, sigma, draws)
    fixes = phase_attitude_fixes(mc, BASELINES, mc.ambiguity, phase_sigma_cycles=sigma)
    assert len(fixes.t) == draws
    eta = (fixes.rotation.inv() * att[0]).as_rotvec()  # R_true = R_hat exp([eta x])
    z = np.linalg.solve(np.linalg.cholesky(fixes.covariance), eta[..., None])[..., 0]
    # a consistent covariance makes z ~ N(0, I): sum of NEES ~ chi2(3 draws), and each whitened component's
    # sum of squares ~ chi2(draws) (Bonferroni over the three)
    lo, hi = chi2_bounds(3 * draws)
    assert lo <= (z**2).sum() <= hi, (z**2).sum() / draws
    lo1, hi1 = chi2.ppf(LEVEL / 6, draws), chi2.isf(LEVEL / 6, draws)
    assert np.all((lo1 <= (z**2).sum(0)) & ((z**2).sum(0) <= hi1)), (z**2).mean(0)


def test_matrix_fixes_without_noise_are_the_truth() -> None:
    # pins the sign of the range differences: a wrong sign gives a different rotation, not the truth
    t, att, _ = motion(60.0)
    ph = sc.phase_observations(
        RX, gnss(), t[::100], att[::100], BASELINES, np.random.default_rng(1), phase_sigma_cycles=0.0
    )
    fixes = phase_attitude_fixes(ph, BASELINES, ph.ambiguity, phase_sigma_cycles=0.01)
    np.testing.assert_array_equal(fixes.t, ph.epoch_t)
    assert np.max((fixes.rotation.inv() * att[::100]).magnitude()) < 1e-9
    known = ph.without_ambiguities()
    again = phase_attitude_fixes(known, BASELINES, known.ambiguity, phase_sigma_cycles=0.01)
    assert np.max((again.rotation.inv() * fixes.rotation).magnitude()) < 1e-12


def test_matrix_fixes_skip_epochs_that_do_not_fix_the_attitude() -> None:
    t, att, _ = motion(60.0)
    rng = np.random.default_rng(2)
    ph = sc.phase_observations(
        RX, gnss(), t[:1], att[:1], BASELINES, rng, phase_sigma_cycles=0.0, max_satellites=3
    )
    los, lam, truth = ph.los, ph.wavelength, att[0]
    tetra = np.vstack([BASELINES, [0.0, 0.0, 0.7]])  # a fourth antenna off the plane
    for baselines, solved in ((BASELINES, [3.0]), (tetra, [2.0, 3.0])):
        # epochs with 0 (absent), 1, 2 and 3 satellites
        rows = [(1, 0), (2, 0), (2, 1), (3, 0), (3, 1), (3, 2)]
        geom = -(truth.inv().apply(los) @ baselines.T) / lam[:, None]
        k = np.array([j for _, j in rows])
        obs = sc.PhaseObservations(
            np.arange(4.0),
            np.array([e for e, _ in rows]),
            k,
            los[k],
            lam[k],
            geom[k],
            np.zeros((len(rows), len(baselines)), np.int64),
            k,
        )
        fixes = phase_attitude_fixes(obs, baselines, obs.ambiguity, phase_sigma_cycles=0.01)
        # two lines of sight fix the attitude of a non-coplanar array, not of a coplanar one
        np.testing.assert_array_equal(fixes.t, solved)
        assert fixes.covariance.shape == (len(solved), 3, 3)
        assert np.max((fixes.rotation.inv() * truth).magnitude()) < 1e-9


def test_matrix_fixes_reject_bad_input() -> None:
    t, att, _ = motion(60.0)
    ph = sc.phase_observations(
        RX, gnss(), t[::100], att[::100], BASELINES, np.random.default_rng(3), phase_sigma_cycles=0.01
    )
    with pytest.raises(InvalidInputError, match="ambiguities of shape"):
        phase_attitude_fixes(ph, BASELINES, ph.ambiguity[:-1], phase_sigma_cycles=0.01)
    with pytest.raises(InvalidInputError, match="expected integers in ambiguities"):
        phase_attitude_fixes(ph, BASELINES, ph.ambiguity + 0.5, phase_sigma_cycles=0.01)
    with pytest.raises(InvalidInputError, match="for the 3 rows of baselines_m"):
        extra = np.vstack([BASELINES, [0.0, 0.0, 1.0]])
        phase_attitude_fixes(ph, extra, ph.ambiguity, phase_sigma_cycles=0.01)
    with pytest.raises(InvalidInputError, match=r"baselines_m of shape \(m, 3\)"):
        phase_attitude_fixes(ph, BASELINES[:, :2], ph.ambiguity, phase_sigma_cycles=0.01)
    with pytest.raises(InvalidInputError, match="phase_sigma_cycles > 0"):
        phase_attitude_fixes(ph, BASELINES, ph.ambiguity, phase_sigma_cycles=0.0)
    with pytest.raises(TypeError, match="PhaseObservations"):
        phase_attitude_fixes(ph.phase, BASELINES, ph.ambiguity, phase_sigma_cycles=0.01)  # type: ignore[arg-type]


@pytest.mark.slow
@pytest.mark.parametrize("kind", ["matrix", "simulated"])
def test_experiment_feeds_the_loose_filter_with_consistent_fixes(kind: str, tmp_path: Path) -> None:
    r = exp.orbit_trial(np.random.default_rng(4), duration_s=120.0, loose_fixes=kind)  # type: ignore[arg-type]
    # a consistent filter exceeds this NEES with probability 1e-3; wrongly signed or scaled fixes do not stay
    # under it
    assert r["loose"]["nees"][-1] < chi2.isf(LEVEL, 6)
    with pytest.raises(InvalidInputError, match="loose_fixes"):
        exp.run(runs=1, seed=0, out=tmp_path, progress=False, loose_fixes="truth")  # type: ignore[arg-type]
