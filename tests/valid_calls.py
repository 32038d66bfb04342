"""One valid call per public function of gnssatt, keyed by its qualified name: the table the intake tests
(``test_intake_models``, ``test_intake_estimators``) and the hostile suite (``hostile/inventory.py``) share.

``VALID_CALLS[name]()`` returns fresh keyword arguments of a call that must succeed (each test kind checks
that it does before mutating it); what each test kind does with the call (which arguments to mutate, which
error to expect, which outputs may be NaN) stays beside that test kind.
"""

from __future__ import annotations

import importlib
from collections.abc import Callable
from functools import cache
from typing import Any

import numpy as np
from hostile import scenario as s
from hostile.trials import monte_trial
from scipy.spatial.transform import Rotation

from gnssatt import montecarlo, orbit, sim
from gnssatt.attitude import dynamics as tumble


@cache
def _attitude_series() -> Any:
    """A solved series of the shared RINEX array (the NMEA writers' input)."""
    from gnssatt.gnss.attitude import attitude_from_rinex

    a = s.rinex_array()
    return attitude_from_rinex(list(a.obs_paths), a.nav_path, method="lambda", systems="G")


def _unit(rows: list[list[float]]) -> np.ndarray:
    v = np.array(rows)
    return v / np.linalg.norm(v, axis=1, keepdims=True)


def _amb() -> dict[str, Any]:
    p = s.ambiguity_problem()
    return {"float_ambiguities": p["float"].copy(), "covariance": p["cov"].copy()}


def _att() -> dict[str, Any]:
    return s.attitude_problem()


def _phase_args(n_base: int = 2) -> dict[str, Any]:
    p = _att()
    return {
        "phase_diffs": p["phase"][:n_base].copy(),
        "los": p["los"].copy(),
        "baselines": s.BASELINES[:n_base].copy(),
        "wavelength": p["wavelength"],
    }


def _tumble_args() -> dict[str, Any]:
    return {"params": s.TUMBLE_TRUTH.copy(), "t": np.arange(0.0, 31.0, 10.0), "model": s.TUMBLE_MODEL}


def _fit_args() -> dict[str, Any]:
    t = np.arange(0.0, 61.0, 5.0)
    axes = tumble.propagate_axes(s.TUMBLE_TRUTH, t, s.TUMBLE_MODEL)
    return {
        "t": t,
        "measured_axes": axes,
        "model": s.TUMBLE_MODEL,
        "rng": 1,
        "axis_sigma_deg": 1.0,
        "max_restarts": 0,
        "popsize": 5,
        "maxiter": 5,
        "polish": False,
    }


def _gyro_filter() -> dict[str, Any]:
    g = s.gyro()
    ph = s.phases()
    p0 = np.diag([np.radians(0.5) ** 2] * 3 + [(np.radians(20.0) / 3600.0) ** 2] * 3)
    return {
        "gyro_t": g["t"].copy(),
        "gyro_rates": g["rates"].copy(),
        "initial_rotation": g["att"][0],
        "initial_covariance": p0,
        "arw": 1e-5,
        "baselines_m": s.BASELINES.copy(),
        "phases": ph,
        "phase_sigma_cycles": 0.01,
        "ratio_threshold": 3.0,
        "output_every": 1,
    }


def _sb() -> dict[str, Any]:
    return s.spaceborne()


def _obs() -> list[Any]:
    return list(s.rinex_read()["obs"])


_WINDOW = np.array([[-60.0, 60.0], [-20.0, 20.0], [-20.0, 20.0]])  # (3, 2) psi, theta, phi bounds, degrees


VALID_CALLS: dict[str, Callable[[], dict[str, Any]]] = {
    # --- gnssatt (estimators, ambiguities) ---
    "gnssatt.bootstrap_success_rate": lambda: {"covariance": _amb()["covariance"]},
    "gnssatt.lambda_decorrelate": lambda: {"covariance": _amb()["covariance"]},
    "gnssatt.lambda_ils": lambda: {**_amb(), "candidates": 2},
    "gnssatt.lambda_ils_batch": lambda: {
        "float_ambiguities": np.stack([_amb()["float_ambiguities"] + k for k in range(3)]),
        "covariance": _amb()["covariance"],
        "candidates": 2,
    },
    "gnssatt.ratio_test": lambda: {**_amb(), "failure_rate": 1e-3, "samples": 2000, "seed": 0},
    "gnssatt.partial_fix": lambda: {
        **_amb(),
        "min_success_rate": 0.5,
        "threshold": 2.0,
        "samples": 2000,
        "seed": 0,
    },
    "gnssatt.ratio_threshold_fixed_failure_rate": lambda: {
        "covariance": _amb()["covariance"],
        "failure_rate": 1e-3,
        "samples": 2000,
        "seed": 0,
    },
    "gnssatt.matrix_attitude": lambda: {
        "baselines": s.BASELINES.copy(),
        "los": _att()["los"].copy(),
        "range_diffs": _att()["range_diffs"].copy(),
        "method": "svd",
    },
    "gnssatt.likelihood_grid": lambda: {**_phase_args(), "step_deg": 5.0, "window_deg": _WINDOW.copy()},
    "gnssatt.ml_attitude": lambda: {**_phase_args(), "step_deg": 5.0, "window_deg": _WINDOW.copy()},
    "gnssatt.ml_baseline": lambda: {
        "phase_diffs": _att()["phase"][0].copy(),
        "los": _att()["los"].copy(),
        "baseline_length_m": 1.0,
        "wavelength": _att()["wavelength"],
        "step_deg": 2.0,
        "window_deg": np.array([[0.0, 40.0], [-10.0, 20.0]]),
    },
    "gnssatt.ml_attitude_series": lambda: {
        "sd_phase": np.stack([_att()["phase"][:2], _att()["phase"][:2]]),
        "los": _att()["los"].copy(),
        "baselines": s.BASELINES[:2].copy(),
        "wavelength": _att()["wavelength"],
        "step_deg": 5.0,
        "window_deg": 10.0,
    },
    "gnssatt.ml_baseline_series": lambda: {
        "sd_phase": np.stack([_att()["phase"][0], _att()["phase"][0]]),
        "los": _att()["los"].copy(),
        "baseline_length_m": 1.0,
        "wavelength": _att()["wavelength"],
        "step_deg": 2.0,
        "window_deg": 5.0,
    },
    "gnssatt.prior_from_velocity": lambda: {
        "velocity_enu": np.array([10.0, 20.0, 0.5]),
        "acceleration_enu": np.array([0.1, -0.2, 0.0]),
        "half_width_deg": (7.0, 7.0, 7.0),
        "gravity": 9.80665,
    },
    "gnssatt.triad": lambda: {
        "b1": np.array([1.0, 0.0, 0.0]),
        "b2": np.array([0.0, 1.0, 0.0]),
        "r1": np.array([0.0, 1.0, 0.0]),
        "r2": np.array([-1.0, 0.0, 0.0]),
    },
    "gnssatt.wahba": lambda: {
        "body": np.eye(3),
        "ref": Rotation.from_euler("z", 30, degrees=True).apply(np.eye(3)),
        "weights": np.array([1.0, 2.0, 3.0]),
    },
    "gnssatt.yaw_from_magnetometer": lambda: {
        "b_body": np.array([2e-5, 1e-5, -3e-5]),
        "b_orbital": np.array([1e-5, 2e-5, -3e-5]),
        "pitch": 0.01,
        "roll": -0.02,
    },
    "gnssatt.gyro_propagate": lambda: {
        "q0": np.array([0.0, 0.0, 0.0, 1.0]),
        "t": np.arange(0.0, 1.01, 0.1),
        "rates": np.full((11, 3), 0.01),
    },
    "gnssatt.gyro_gnss_filter": _gyro_filter,
    "gnssatt.phase_attitude_fixes": lambda: {
        "phases": s.phases(),
        "baselines_m": s.BASELINES.copy(),
        "ambiguities": s.phases().ambiguity.copy(),
        "phase_sigma_cycles": 0.01,
    },
    "gnssatt.fit_rotation": _fit_args,
    "gnssatt.visibility_axis": lambda: {
        "visible_los": _unit([[0.0, 0.0, 1.0], [0.3, 0.0, 0.95], [0.0, 0.3, 0.95]]),
        "invisible_los": _unit([[0.0, 0.0, -1.0], [0.3, 0.0, -0.95]]),
        "method": "paper",
    },
    # --- gnssatt.magnetic ---
    "gnssatt.magnetic.dcm_ned_from_ecef": lambda: {"lat_deg": 50.0, "lon_deg": 36.2},
    "gnssatt.magnetic.dipole_coefficients": lambda: {"decimal_year": 2025.0},
    "gnssatt.magnetic.dipole_field_ecef": lambda: {
        "position_ecef_m": np.array([7e6, 0.0, 1e6]),
        "decimal_year": 2025.0,
    },
    "gnssatt.magnetic.dipole_field_eci": lambda: {
        "position_eci_m": np.array([7e6, 0.0, 1e6]),
        "decimal_year": 2025.0,
        "earth_rotation_angle_rad": 0.3,
    },
    "gnssatt.magnetic.dipole_field_ned": lambda: {
        "lat_deg": 50.0,
        "lon_deg": 36.2,
        "height_m": 500e3,
        "decimal_year": 2025.0,
    },
    "gnssatt.magnetic.dipole_orbital": lambda: {
        "u": np.linspace(0.0, 6.0, 5),
        "inclination": 0.9,
        "radius": 6.9e6,
        "strength": 7.7e15,
    },
    "gnssatt.magnetic.igrf_field_ecef": lambda: {
        "position_ecef_m": np.array([7e6, 0.0, 1e6]),
        "decimal_year": 2025.0,
        "max_degree": 13,
    },
    # --- gnssatt.sim ---
    "gnssatt.sim.antenna_cone_mask": lambda: {
        "los_ref": _att()["los"].copy(),
        "attitude": Rotation.identity(),
        "boresight_body": (0.0, 0.0, 1.0),
        "half_angle_deg": 80.0,
    },
    "gnssatt.sim.correlator_amplitude": lambda: {
        "cn0_dbhz": np.array([35.0, 45.0]),
        "integration_time_s": 0.001,
    },
    "gnssatt.sim.dcm_ecef_from_eci": lambda: {"t": np.arange(3.0), "theta0_rad": 0.1},
    "gnssatt.sim.dcm_eci_from_ecef": lambda: {"t": np.arange(3.0), "theta0_rad": 0.1},
    "gnssatt.sim.dcm_ecef_from_enu": lambda: {"lat_deg": 50.0, "lon_deg": 36.2},
    "gnssatt.sim.earth_occlusion_mask": lambda: {
        "receiver_m": np.array([7e6, 0.0, 0.0]),
        "satellites_m": np.array([[2.6e7, 0.0, 0.0], [-2.6e7, 0.0, 0.0]]),
        "atmosphere_m": 5e4,
        "radius_m": 6378137.0,
    },
    "gnssatt.sim.earth_rotation_angle": lambda: {"t": np.arange(3.0), "theta0_rad": 0.1},
    "gnssatt.sim.ecef_to_eci": lambda: {
        "r_ecef": np.array([7e6, 0.0, 0.0]),
        "v_ecef": np.array([0.0, 7.5e3, 0.0]),
        "t": 10.0,
        "theta0_rad": 0.1,
    },
    "gnssatt.sim.eci_to_ecef": lambda: {
        "r_eci": np.array([7e6, 0.0, 0.0]),
        "v_eci": np.array([0.0, 7.5e3, 0.0]),
        "t": 10.0,
        "theta0_rad": 0.1,
    },
    "gnssatt.sim.ecef_to_geodetic": lambda: {"r_ecef": np.array([3.9e6, 2.8e6, 4.9e6])},
    "gnssatt.sim.elevation_azimuth": lambda: {"los_enu": _att()["los"].copy()},
    "gnssatt.sim.elevation_mask": lambda: {"los_ref": _att()["los"].copy(), "mask_deg": 10.0},
    "gnssatt.sim.equilateral_triangle": lambda: {"side_m": 1.0, "plane": "xy"},
    "gnssatt.sim.geodetic_to_ecef": lambda: {"lat_deg": 50.0, "lon_deg": 36.2, "height_m": 150.0},
    "gnssatt.sim.glonass_nominal": lambda: {"raan0_deg": 10.0, "arg_latitude0_deg": 5.0},
    "gnssatt.sim.gps_nominal": lambda: {"extra_slots_deg": [(10.0, 20.0)]},
    "gnssatt.sim.line_of_sight": lambda: {
        "receiver": s.GROUND,
        "constellation": s.gps(),
        "t": np.arange(3.0),
    },
    "gnssatt.sim.los_body": lambda: {"los": _att()["los"].copy(), "attitude": _att()["rotation"]},
    "gnssatt.sim.phase_diffs": lambda: {"phases": np.array([[0.1, 0.2], [0.3, 0.5], [1.0, -1.0]])},
    "gnssatt.sim.random_attitude": lambda: {"rng": 1, "n": 3},
    "gnssatt.sim.random_los": lambda: {"rng": 1, "n_sat": 5, "min_elevation_deg": 10.0},
    "gnssatt.sim.simulate_array": lambda: {
        "geometry": s.geometry(),
        "attitude": Rotation.identity(),
        "antennas_body_m": sim.equilateral_triangle(1.0),
        "wavelengths_m": np.full(len(s.geometry().ids), 0.19),
        "rng": 1,
        "code_sigma_m": 0.3,
        "phase_sigma_rad": 0.01,
        "doppler_sigma_hz": 0.1,
        "clock_bias_s": 1e-4,
        "ambiguity_max": 100,
        "cn0_dbhz": np.full(len(s.geometry().ids), 45.0),
        "integration_time_s": 0.001,
    },
    "gnssatt.sim.simulate_platform": lambda: {
        "folder": s.folder(),
        "trajectory": sim.Trajectory((sim.Leg(5.0, 10.0, 3.0),)),
        "antennas_body_m": np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]]),
        "duration_s": 1.0,
        "interval_s": 0.5,
        "noise": "gps_l1_ublox",
        "blockage": sim.Blockage(outages_s=((0.4, 0.6),)),
        "base_offset_enu_m": np.array([-50.0, 20.0, 0.0]),
        "elevation_min_deg": 10.0,
        "start_s": 7200.0,
        "atmosphere": True,
        "rng": 1,
    },
    **{
        f"gnssatt.sim.{name}": lambda: {
            "folder": s.folder(),
            "n_antennas": 2,
            "duration_s": 1.0,
            "interval_s": 0.5,
            "noise": "gps_l1_ublox",
            "baseline_m": (1.0, 0.8),
            "base_offset_enu_m": np.array([-50.0, 20.0, 0.0]),
            "start_s": 7200.0,
            "rng": 1,
        }
        for name in ("car", "ship", "aircraft")
    },
    "gnssatt.sim.simulate_spaceborne": lambda: {
        "receiver_position_m": _sb()["r"].copy(),
        "receiver_velocity_m_s": _sb()["v"].copy(),
        "times_s": _sb()["t"].copy(),
        "constellation": s.gps(),
        "rng": 1,
        "half_angle_deg": 85.0,
        "code_sigma_m": 1.0,
        "atmosphere_m": 5e4,
        "doppler_sigma_hz": 0.2,
        "clock_bias0_s": 1e-4,
        "clock_drift0": 1e-8,
        "q_bias_s2_s": 1e-20,
        "q_drift_1_s": 1e-20,
        "isb_m": 20.0,
        "outages": [(10.0, 20.0, 2)],
    },
    "gnssatt.sim.solve_kepler": lambda: {
        "mean_anomaly_rad": np.array([0.1, 2.0]),
        "eccentricity": 0.1,
        "tol": 1e-14,
        "max_iter": 50,
    },
    "gnssatt.sim.walker": lambda: {
        "n_sat": 6,
        "n_planes": 3,
        "phasing": 1,
        "inclination_deg": 55.0,
        "semi_major_axis_m": 26.56e6,
        "frequency_hz": 1575.42e6,
        "prefix": "E",
        "raan0_deg": 0.0,
    },
    "gnssatt.sim.wrap_rad": lambda: {"x": np.array([-7.0, 0.5, 10.0])},
    "gnssatt.sim.attitude_scenario.attitude_fixes": lambda: {
        "phases": s.phases(),
        "attitude": Rotation.identity(len(s.phases().epoch_t)),
        "baselines_m": s.BASELINES.copy(),
        "rng": 1,
        "phase_sigma_cycles": 0.01,
        "min_satellites": 3,
    },
    "gnssatt.sim.attitude_scenario.gyro_output": lambda: {
        "t": s.gyro()["t"].copy(),
        "attitude": s.gyro()["att"],
        "rng": 1,
        "drift_rad_s": np.zeros(3),
        "arw": 1e-5,
        "rrw": 1e-7,
    },
    "gnssatt.sim.attitude_scenario.orbital_hold_motion": lambda: {
        "receiver": s.ORBITAL,
        "t": np.arange(0.0, 2.1, 1.0),
        "amplitude_rad": (0.03, 0.02, 0.05),
        "period_s": (200.0, 250.0, 300.0),
        "phase_rad": (0.0, 1.0, 2.0),
    },
    "gnssatt.sim.attitude_scenario.phase_observations": lambda: {
        "receiver": s.ORBITAL,
        "gnss": s.gps(),
        "t": s.gyro()["t"][::10].copy(),
        "attitude": s.gyro()["att"][::10],
        "baselines_m": s.BASELINES.copy(),
        "rng": 1,
        "phase_sigma_cycles": 0.01,
        "half_angle_deg": 80.0,
    },
    "gnssatt.sim.attitude_scenario.right_jacobian": lambda: {"a": np.array([0.1, -0.2, 0.3])},
    "gnssatt.constants.glonass_frequency_hz": lambda: {"k": np.array([-7, 0, 6]), "band": "L1"},
    "gnssatt.constants.glonass_wavelength_m": lambda: {"k": np.array([-7, 0, 6]), "band": "L2"},
    # --- gnssatt.orbit ---
    "gnssatt.orbit.glonass_propagate": lambda: {
        "position_m": np.array([7003008.789, -12206626.953, 21280765.625]),
        "velocity_m_s": np.array([783.86, 2804.61, 1352.32]),
        "duration_s": 600.0,
        "step_s": 10.0,
        "lunisolar_m_s2": np.array([1e-6, 2e-6, -1e-6]),
        "model": orbit.GlonassModel(),
    },
    "gnssatt.orbit.gmst_rad": lambda: {"jd_ut1": np.array([2451545.0, 2460000.5])},
    "gnssatt.orbit.teme_to_ecef": lambda: {
        "r_teme_m": np.array([[7e6, 0.0, 0.0]]),  # (1, 3): one state, as rows
        "v_teme_m_s": np.array([[0.0, 7.5e3, 0.0]]),
        "jd_ut1": 2460000.5,
    },
    "gnssatt.orbit.tle_states": lambda: {
        "line1": s.TLE[0],
        "line2": s.TLE[1],
        "times": np.array(["2008-09-20T12:25:40", "2008-09-20T12:26:40"], dtype="datetime64[ns]"),
        "dut1_s": 0.1,
    },
    # --- gnssatt.orbit.determination ---
    "gnssatt.orbit.determination.noisy_orbit": lambda: {
        "x0": _sb()["x0"].copy(),
        "times_s": _sb()["t"].copy(),
        "rng": 1,
        "accel_psd_m2_s3": 1e-8,
        "step_s": 10.0,
    },
    "gnssatt.orbit.determination.orbit_filter": lambda: {
        "data": _sb()["meas"],
        "x0": _sb()["x0"] + 10.0,
        "p0": np.diag([30.0**2] * 3 + [0.05**2] * 3),
        "coupling": "tight",
        "accel_psd_m2_s3": 1e-8,
        "step_s": 10.0,
        "use_doppler": True,
    },
    "gnssatt.orbit.determination.receiver_fix": lambda: {"measurements": _sb()["meas"]},
    "gnssatt.orbit.determination.white_acceleration_noise": lambda: {"accel_psd_m2_s3": 1e-8, "dt_s": 10.0},
    # --- gnssatt.attitude.dynamics ---
    "gnssatt.attitude.dynamics.axis_cost": lambda: {
        **_tumble_args(),
        "measured_axes": tumble.propagate_axes(s.TUMBLE_TRUTH, np.arange(0.0, 31.0, 10.0), s.TUMBLE_MODEL),
        "step_s": 1.0,
    },
    "gnssatt.attitude.dynamics.fold_symmetric": lambda: {
        "params": s.TUMBLE_TRUTH.copy(),
        "reference": s.TUMBLE_TRUTH + 0.1,
    },
    "gnssatt.attitude.dynamics.noise_cost_threshold": lambda: {
        "n_epochs": 100,
        "axis_sigma_deg": 1.0,
        "false_restart": 1e-3,
    },
    "gnssatt.attitude.dynamics.propagate": lambda: {**_tumble_args(), "step_s": 1.0},
    "gnssatt.attitude.dynamics.propagate_axes": lambda: {**_tumble_args(), "step_s": 1.0},
    # --- gnssatt.rinex ---
    "gnssatt.rinex.read_obs": lambda: {"path": s.rinex_array().obs_paths[0]},
    "gnssatt.rinex.read_nav": lambda: {"path": s.rinex_array().nav_path},
    "gnssatt.gnss.attitude.attitude_from_rinex": lambda: {
        "observations": list(s.rinex_array().obs_paths),
        "nav": s.rinex_array().nav_path,
        "method": "auto",
        "systems": "G",
        "elevation_mask_deg": 10.0,
    },
    "gnssatt.gnss.nmea.nmea_sentences": lambda: {"series": _attitude_series()},
    "gnssatt.gnss.nmea.write_nmea": lambda: {
        "path": s.folder() / "written.nmea",
        "series": _attitude_series(),
    },
    "gnssatt.position_from_rinex": lambda: {
        "obs": s.rinex_array().obs_paths[0],
        "nav": s.rinex_array().nav_path,
        "systems": "G",
        "frequencies": 1,
        "elevation_mask_deg": 10.0,
    },
    "gnssatt.rinex.gps_ns": lambda: {"time": np.array(["2024-03-01T10:00:00"], dtype="datetime64[ns]")},
    "gnssatt.rinex.write_nav_from_constellation": lambda: {
        "path": s.folder() / "written.24n",
        "constellation": s.gps(),
        "epoch_gpst": np.datetime64("2024-03-01T10:00:00", "ns"),
        "start_s": 60.0,
        "span_s": 7200.0,
        "clock_bias_s": np.full(len(s.gps()), 1e-5),
        "klobuchar": np.array(
            [1.1176e-08, 7.4506e-09, -5.9605e-08, -5.9605e-08, 9.0112e04, 0.0, -1.9661e05, -6.5536e04]
        ),
    },
    "gnssatt.rinex.write_obs": lambda: {
        "path": s.folder() / "written.24o",
        "time": np.array(["2024-03-01T10:00:00", "2024-03-01T10:00:01"], dtype="datetime64[ns]"),
        "sats": ["G01", "G02"],
        "observations": {"C1C": np.array([[2.1e7, 2.2e7], [2.1e7 + 1, np.nan]])},
        "approx_position_m": (1.0, 2.0, 3.0),
        "marker_name": "SIM",
        "glonass_channels": {"R01": 1, "R02": -4},
    },
    "gnssatt.sim.rinex_scenario.simulate_rinex_array": lambda: {
        "folder": s.folder(),
        "antennas_body_m": np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]]),
        "euler_gost_deg": np.zeros((2, 3)),
        "interval_s": 1.0,
        "rng": 1,
        "n_sats": 5,
    },
    "gnssatt.sim.rinex_scenario.gnss_constellation": lambda: {"systems": "GRE", "lon_deg": 36.2},
    "gnssatt.sim.rinex_scenario.simulate_gnss_rinex": lambda: {
        "folder": s.folder(),
        "antennas_body_m": np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]]),
        "euler_gost_deg": np.array([-40.0, 5.0, 3.0]),
        "systems": "GC",
        "frequencies": 2,
        "n_epochs": 2,
        "interval_s": 1.0,
        "start_s": 0.0,
        "rng": 1,
        "receiver_clock_s": np.array([1e-5, -2e-5]),
        "code_sigma_m": 0.3,
        "phase_sigma_m": 0.002,
        "doppler_sigma_hz": 0.05,
        "elevation_min_deg": 10.0,
        "slips": [],  # a valid slip names a satellite the mutated geometry may not keep
        "lat_deg": 50.0,
        "lon_deg": 36.2,
        "height_m": 150.0,
        "n_sats": 8,
        "file_names": ("hostile{i}.rnx", "hostile_nav.rnx"),
        "atmosphere": True,
    },
    "gnssatt.rinex.nav.nav_input": lambda: {"nav": s.rinex_read()["nav"]},
    "gnssatt.gnss.session_input.session_input": lambda: {
        "observations": _obs(),
        "systems": "G",
        "frequencies": 1,
        "nav": s.rinex_read()["nav"],
    },
    "gnssatt.gnss.session_input.epochs_gpst_ns": lambda: {"obs": _obs()[0], "leaps": 18},
    "gnssatt.rinex.signals.choose_signals": lambda: {"obs": _obs()[0], "system": "G"},
    "gnssatt.rinex.signals.slot_bands": lambda: {"system": "C", "version": 3.02},
    "gnssatt.rinex.signals.slot_frequency_hz": lambda: {"system": "R", "slot": 1, "glonass_channel": -3},
    "gnssatt.sim.atmosphere.niell_mapping": lambda: {
        "lat_rad": 0.8,
        "height_m": 150.0,
        "elevation_rad": np.array([0.2, 1.0]),
    },
    "gnssatt.sim.atmosphere.saastamoinen_zenith_m": lambda: {"lat_rad": 0.8, "height_m": 150.0},
    "gnssatt.sim.atmosphere.troposphere_delay_m": lambda: {
        "lat_rad": 0.8,
        "height_m": 150.0,
        "elevation_rad": np.array([0.2, 1.0]),
    },
    "gnssatt.sim.rinex_scenario.write_array_rinex": lambda: {
        "folder": s.folder(),
        "measurements": sim.simulate_array(
            s.geometry(), Rotation.identity(), sim.equilateral_triangle(1.0), np.full(8, 0.19), s.rng()
        ),
        "t_s": np.arange(3.0),
        "constellation": s.gps(),
        "sat_ids": list(s.geometry().ids),
        "receiver": s.GROUND,
    },
    # --- gnssatt.montecarlo ---
    "gnssatt.montecarlo.run": lambda: {
        "trial": monte_trial,
        "n_trials": 4,
        "seed": 1,
        "executor": montecarlo.SerialExecutor(),
        "progress": False,
        "chunksize": 2,
    },
    "gnssatt.montecarlo.trial_generators": lambda: {"seed": 1, "n_trials": 3},
    # --- gnssatt.attitude.visibility ---
    "gnssatt.attitude.visibility.visibility_sets": lambda: {
        "receiver": s.ORBITAL,
        "constellation": s.gps(),
        "t": np.arange(0.0, 21.0, 10.0),
        "axes_orbital": np.tile([0.0, 0.0, 1.0], (3, 1)),
        "half_angle_deg": 90.0,
    },
    # --- gnssatt.rotation, gnssatt.geometry ---
    "gnssatt.rotation.dcm_to_euler": lambda: {
        "seq": "ZYX",
        "dcm": Rotation.from_euler("ZYX", [0.3, 0.2, 0.1]).as_matrix(),
    },
    "gnssatt.rotation.dcm_to_quat": lambda: {"dcm": Rotation.from_euler("ZYX", [0.3, 0.2, 0.1]).as_matrix()},
    "gnssatt.rotation.euler_to_dcm": lambda: {"seq": "ZYX", "angles": np.array([0.3, 0.2, 0.1])},
    "gnssatt.rotation.nearest_rotation": lambda: {"matrix": np.eye(3) + 0.01},
    "gnssatt.rotation.quat_to_dcm": lambda: {"quat": np.array([0.1, 0.2, 0.3, 0.9])},
    "gnssatt.rotation.rotation_from_euler": lambda: {"euler_gost_deg": np.array([-40.0, 5.0, 3.0])},
    "gnssatt.rotation.euler_from_rotation": lambda: {
        "rotation": Rotation.from_euler("YZX", [10.0, 5.0, 3.0], degrees=True)
    },
    "gnssatt.geometry.attitude_dop": lambda: {
        "baselines": s.BASELINES.copy(),
        "los": _att()["los"].copy(),
        "rotation": _att()["rotation"],
    },
    "gnssatt.data.geonet_dir": dict,
    "gnssatt.geometry.range_difference_fisher": lambda: {
        "baselines": s.BASELINES.copy(),
        "los": _att()["los"].copy(),
        "rotation": _att()["rotation"],
    },
}


def resolve(qualified: str) -> Callable[..., Any]:
    """The public function named ``qualified`` (``module.attribute``)."""
    module, attr = qualified.rsplit(".", 1)
    return getattr(importlib.import_module(module), attr)
