"""Array measurements of gnssatt.sim: phase model, Doppler, correlator noise statistics, errors."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.transform import Rotation
from scipy.stats import chi2

from gnssatt import sim
from gnssatt.constants import GPS_L1_WAVELENGTH_M, SPEED_OF_LIGHT_M_S
from gnssatt.errors import InvalidInputError

LAM = GPS_L1_WAVELENGTH_M


def static_case(seed: int = 11, n_sat: int = 8):
    rng = np.random.default_rng(seed)
    los = sim.random_los(rng, n_sat, min_elevation_deg=10.0)
    geom = sim.Geometry.from_los(los, range_m=rng.uniform(2.0e7, 2.5e7, n_sat))
    att = sim.random_attitude(rng)
    ant = sim.equilateral_triangle(0.71)
    return geom, att, ant, rng


def wrap(x: np.ndarray) -> np.ndarray:
    return np.angle(np.exp(1j * x))


def test_equilateral_triangle() -> None:
    tri = sim.equilateral_triangle(0.71)
    assert tri.shape == (3, 3)
    np.testing.assert_array_equal(tri[0], 0.0)
    sides = [np.linalg.norm(tri[i] - tri[j]) for i, j in ((0, 1), (1, 2), (0, 2))]
    np.testing.assert_allclose(sides, 0.71)
    np.testing.assert_allclose(tri[:, 2], 0.0)  # default plane xy
    np.testing.assert_allclose(tri[1], [0.71, 0, 0])
    xz = sim.equilateral_triangle(1.0, plane="xz")
    np.testing.assert_allclose(xz[:, 1], 0.0)
    assert xz[2, 2] > 0
    with pytest.raises(InvalidInputError, match="side_m > 0"):
        sim.equilateral_triangle(0.0)
    with pytest.raises(InvalidInputError, match="plane"):
        sim.equilateral_triangle(1.0, plane="xx")  # type: ignore[arg-type]


def test_noise_free_phase_differences_match_far_field_formula() -> None:
    geom, att, ant, rng = static_case()
    meas = sim.simulate_array(geom, att, ant, np.full(8, LAM), rng, oscillator_phases_rad=np.zeros(3))
    dphi = meas.phase_diffs()
    assert dphi.shape == (2, 8)
    expected = -2 * np.pi * (att.apply(ant) @ geom.los.T) / LAM  # (n_ant, n_sat), gamma . R r_i
    np.testing.assert_allclose(dphi, wrap(expected[1:] - expected[0]), atol=1e-6)
    assert np.all((dphi >= -np.pi) & (dphi < np.pi))
    # With oscillator phases, the first differences pick up osc_i - osc_0.
    osc = np.array([0.3, -1.0, 2.5])
    meas2 = sim.simulate_array(geom, att, ant, np.full(8, LAM), rng, oscillator_phases_rad=osc)
    np.testing.assert_allclose(
        wrap(meas2.phase_diffs() - (expected[1:] - expected[0]) - (osc[1:, None] - osc[0])), 0.0, atol=1e-6
    )
    # Correlator phases at a very high C/N0 agree.
    meas3 = sim.simulate_array(geom, att, ant, np.full(8, LAM), rng, cn0_dbhz=150.0)
    diff = meas3.phase_diffs(source="correlator") - meas3.phase_diffs()
    np.testing.assert_allclose(wrap(diff), 0.0, atol=1e-5)


def test_phase_composition_and_pseudorange() -> None:
    geom, att, ant, rng = static_case()
    lam = np.linspace(0.18, 0.25, 8)
    amb = np.arange(24).reshape(3, 8) - 12
    meas = sim.simulate_array(geom, att, ant, lam, rng, ambiguities=amb, clock_bias_s=[1e-3, 2e-3, -1e-3])
    rho = geom.range_m - att.apply(ant) @ geom.los.T
    np.testing.assert_allclose(meas.range_m, rho, rtol=1e-15)
    np.testing.assert_array_equal(meas.ambiguities, amb)
    cycles = rho / lam + amb + (meas.oscillator_phases_rad[:, None] + meas.satellite_phases_rad) / (2 * np.pi)
    np.testing.assert_allclose(meas.carrier_phase_cycles, cycles, rtol=0, atol=1e-6)
    np.testing.assert_allclose(meas.pseudorange_m, rho + SPEED_OF_LIGHT_M_S * meas.clock_bias_s[:, None])
    np.testing.assert_allclose(meas.carrier_phase_rad(wrapped=False), 2 * np.pi * meas.carrier_phase_cycles)
    np.testing.assert_allclose(
        wrap(meas.carrier_phase_rad() - 2 * np.pi * meas.carrier_phase_cycles), 0.0, atol=1e-6
    )
    assert meas.correlator is None
    with pytest.raises(ValueError, match="read-only"):
        meas.pseudorange_m[0, 0] = 0.0


def test_doppler_is_minus_range_derivative_over_wavelength() -> None:
    rx = sim.OrbitalReceiver(600e3, 97.8, 20.0, 5.0)
    both = sim.gps_nominal() + sim.glonass_nominal()
    lam = both.wavelengths_m("L1")
    t = np.array([0.0, 900.0])
    geom = sim.line_of_sight(rx, both, t)
    att = Rotation.from_euler("z", [[10.0], [20.0]], degrees=True)
    meas = sim.simulate_array(geom, att, sim.equilateral_triangle(1.0), lam, np.random.default_rng(2))
    h = 0.05
    rho_p = sim.line_of_sight(rx, both, t + h).range_m
    rho_m = sim.line_of_sight(rx, both, t - h).range_m
    expected = -(rho_p - rho_m) / (2 * h) / lam
    assert meas.doppler_hz.shape == (2, 3, 48)
    np.testing.assert_allclose(meas.doppler_hz[:, 0, :], expected, atol=0.02)
    assert np.max(np.abs(expected)) > 1e3  # LEO Dopplers are tens of kHz


def test_correlator_phase_noise_matches_formula() -> None:
    n_sat, n_ant = 2000, 10
    rng = np.random.default_rng(2024)
    geom = sim.Geometry.from_los(sim.random_los(rng, n_sat), range_m=rng.uniform(2e7, 2.5e7, n_sat))
    ant = rng.normal(size=(n_ant, 3))
    cn0, t_int = 42.0, 0.02
    meas = sim.simulate_array(
        geom, Rotation.identity(), ant, np.full(n_sat, LAM), rng, cn0_dbhz=cn0, integration_time_s=t_int
    )
    err = np.angle(meas.correlator * np.exp(-2j * np.pi * meas.carrier_phase_cycles)).ravel()
    sigma = 1.0 / np.sqrt(2 * 10 ** (cn0 / 10) * t_int)
    n = err.size
    stat = np.sum(err**2) / sigma**2  # ~ chi2(n) for zero-mean Gaussian errors of std sigma
    lo, hi = chi2.ppf([0.0005, 0.9995], n)
    assert lo < stat < hi, (np.std(err), sigma)
    # The amplitude follows the same normalisation.
    np.testing.assert_allclose(sim.correlator_amplitude(cn0, t_int), 1 / sigma)
    np.testing.assert_allclose(np.mean(np.abs(meas.correlator)), 1 / sigma, rtol=0.01)


def test_carrier_and_code_noise_levels() -> None:
    n_sat, n_ant = 500, 20
    rng = np.random.default_rng(99)
    geom = sim.Geometry.from_los(sim.random_los(rng, n_sat))
    ant = np.zeros((n_ant, 3))
    kw = {"ambiguities": np.zeros((n_ant, n_sat), dtype=int), "code_sigma_m": 0.3}
    lam = np.full(n_sat, LAM)
    meas = sim.simulate_array(geom, Rotation.identity(), ant, lam, rng, phase_sigma_m=0.004, **kw)
    free = sim.simulate_array(geom, Rotation.identity(), ant, np.full(n_sat, LAM), np.random.default_rng(99))
    n = n_sat * n_ant
    lo, hi = chi2.ppf([0.0005, 0.9995], n)
    phase_err_m = (meas.carrier_phase_cycles - meas.range_m / LAM) * LAM
    phase_err_m -= (meas.oscillator_phases_rad[:, None] + meas.satellite_phases_rad) / (2 * np.pi) * LAM
    assert lo < np.sum(phase_err_m**2) / 0.004**2 < hi
    assert lo < np.sum((meas.pseudorange_m - meas.range_m) ** 2) / 0.3**2 < hi
    assert free.pseudorange_m[0, 0] == pytest.approx(free.range_m[0, 0])


def test_reproducible_with_same_seed() -> None:
    geom, att, ant, _ = static_case()
    kw = {"code_sigma_m": 0.3, "phase_sigma_rad": 0.1, "doppler_sigma_hz": 0.5, "cn0_dbhz": 45.0}
    a = sim.simulate_array(geom, att, ant, np.full(8, LAM), np.random.default_rng(5), **kw)
    b = sim.simulate_array(geom, att, ant, np.full(8, LAM), np.random.default_rng(5), **kw)
    c = sim.simulate_array(geom, att, ant, np.full(8, LAM), np.random.default_rng(6), **kw)
    for name in ("pseudorange_m", "carrier_phase_cycles", "doppler_hz", "correlator", "ambiguities"):
        np.testing.assert_array_equal(getattr(a, name), getattr(b, name))
        assert not np.array_equal(getattr(a, name), getattr(c, name))


def test_multi_epoch_matches_single_epochs() -> None:
    rx = sim.GroundReceiver(48.0, 11.0, 500.0)
    gps = sim.gps_nominal().select(["G01", "G05", "G09", "G13"])
    t = np.array([0.0, 30.0, 60.0])
    geom = sim.line_of_sight(rx, gps, t)
    att = Rotation.from_euler("zyx", [[0, 0, 0], [10, 5, 1], [20, -5, 2]], degrees=True)
    ant = sim.equilateral_triangle(1.0)
    fixed = {"ambiguities": np.ones((3, 4), dtype=np.int64), "oscillator_phases_rad": [0, 1, 2]}
    fixed["satellite_phases_rad"] = [0.1, 0.2, 0.3, 0.4]
    lam = gps.wavelengths_m()
    multi = sim.simulate_array(geom, att, ant, lam, np.random.default_rng(0), **fixed)
    assert multi.carrier_phase_cycles.shape == (3, 3, 4)
    for k in range(3):
        single = sim.simulate_array(
            sim.line_of_sight(rx, gps, t[k]), att[k], ant, lam, np.random.default_rng(0), **fixed
        )
        np.testing.assert_allclose(multi.carrier_phase_cycles[k], single.carrier_phase_cycles, rtol=1e-15)
        np.testing.assert_allclose(multi.doppler_hz[k], single.doppler_hz)
    assert multi.phase_diffs().shape == (3, 2, 4)
    one_att = sim.simulate_array(geom, att[1], ant, lam, np.random.default_rng(0), **fixed)
    assert one_att.pseudorange_m.shape == (3, 3, 4)


def test_phase_diffs_function() -> None:
    p = np.array([[3.0, -3.0], [-3.0, 3.0], [0.5, 0.5]])
    d = sim.phase_diffs(p)
    np.testing.assert_allclose(d, [[2 * np.pi - 6.0, 6.0 - 2 * np.pi], [-2.5, 3.5 - 2 * np.pi]])
    u = np.exp(1j * p)
    np.testing.assert_allclose(sim.phase_diffs(u), d, atol=1e-12)
    with pytest.raises(InvalidInputError, match="n_ant >= 2"):
        sim.phase_diffs(np.zeros((1, 4)))
    with pytest.raises(InvalidInputError, match=r"\(\.\.\., n_ant, M\)"):
        sim.phase_diffs(np.zeros(4))


def test_input_errors_have_helpful_messages() -> None:
    geom, att, ant, rng = static_case()
    lam = np.full(8, LAM)
    ant_msg = r"expected antennas_body_m of shape \(n_ant, 3\), got "
    with pytest.raises(InvalidInputError, match=ant_msg + r"\(3,\)"):
        sim.simulate_array(geom, att, np.zeros(3), lam, rng)
    with pytest.raises(InvalidInputError, match=ant_msg + r"\(3, 2\)"):
        sim.simulate_array(geom, att, np.zeros((3, 2)), lam, rng)
    with pytest.raises(InvalidInputError, match=r"expected wavelengths_m of shape \(8,\)"):
        sim.simulate_array(geom, att, ant, lam[:5], rng)
    with pytest.raises(InvalidInputError, match="wavelengths_m > 0"):
        sim.simulate_array(geom, att, ant, -lam, rng)
    with pytest.raises(TypeError, match=r"expected rng as an int, a numpy\.random\.Generator"):
        sim.simulate_array(geom, att, ant, lam, 4.2)  # type: ignore[arg-type]
    with pytest.raises(TypeError, match="scipy Rotation"):
        sim.simulate_array(geom, np.eye(3), ant, lam, rng)  # type: ignore[arg-type]
    with pytest.raises(TypeError, match="Geometry"):
        sim.simulate_array(geom.los, att, ant, lam, rng)  # type: ignore[arg-type]
    with pytest.raises(TypeError, match="integer ambiguities"):
        sim.simulate_array(geom, att, ant, lam, rng, ambiguities=np.zeros((3, 8)))
    with pytest.raises(InvalidInputError, match=r"ambiguities of shape \(3, 8\)"):
        sim.simulate_array(geom, att, ant, lam, rng, ambiguities=np.zeros((8, 3), dtype=int))
    with pytest.raises(InvalidInputError, match="one of phase_sigma_rad, phase_sigma_m"):
        sim.simulate_array(geom, att, ant, lam, rng, phase_sigma_rad=0.1, phase_sigma_m=0.004)
    with pytest.raises(InvalidInputError, match="code_sigma_m >= 0"):
        sim.simulate_array(geom, att, ant, lam, rng, code_sigma_m=-1.0)
    with pytest.raises(InvalidInputError, match=r"oscillator_phases_rad of shape \(\) or \(3,\)"):
        sim.simulate_array(geom, att, ant, lam, rng, oscillator_phases_rad=[0.0, 1.0])
    with pytest.raises(InvalidInputError, match="non-finite"):
        sim.simulate_array(geom, att, ant, np.full(8, np.nan), rng)
    with pytest.raises(InvalidInputError, match="one per epoch"):
        sim.simulate_array(geom, sim.random_attitude(rng, 2), ant, lam, rng)
    with pytest.raises(InvalidInputError, match="integration_time_s > 0"):
        sim.simulate_array(geom, att, ant, lam, rng, cn0_dbhz=45.0, integration_time_s=0.0)
    with pytest.raises(InvalidInputError, match="correlator"):
        sim.simulate_array(geom, att, ant, lam, rng).phase_diffs(source="correlator")


def test_range_differences_feed_the_matrix_method() -> None:
    """Noise-free simulated range differences give back the true attitude through gnssatt.matrix_attitude."""
    from gnssatt import matrix_attitude

    geom, att, ant, rng = static_case(seed=3, n_sat=5)
    meas = sim.simulate_array(geom, att, ant, np.full(5, LAM), rng)
    range_diffs = meas.range_m[0] - meas.range_m[1:]  # b_i . (A s_j), A = reference -> body
    result = matrix_attitude(ant[1:], geom.los, range_diffs)
    assert (result.rotation * att.inv()).magnitude() < 1e-9
