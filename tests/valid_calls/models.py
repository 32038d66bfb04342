"""Valid calls of the models and the simulator: ``gnssatt.magnetic``, ``sim``, ``orbit``,
``attitude.dynamics``, ``montecarlo``."""

from __future__ import annotations

from typing import Any

import numpy as np
from hostile import scenario as s
from hostile.trials import monte_trial
from scipy.spatial.transform import Rotation

from gnssatt import montecarlo, orbit, sim
from gnssatt.attitude import dynamics as tumble

from .spec import WORK_TINY_STEP, Arg, Call


def _tumble_args() -> dict[str, Any]:
    return {"params": s.TUMBLE_TRUTH.copy(), "t": np.arange(0.0, 31.0, 10.0), "model": s.TUMBLE_MODEL}


def _sb() -> dict[str, Any]:
    return s.spaceborne()


CALLS: dict[str, Call] = {
    # --- gnssatt.magnetic ---
    "gnssatt.magnetic.dcm_ned_from_ecef": Call(lambda: {"lat_deg": 50.0, "lon_deg": 36.2}),
    "gnssatt.magnetic.dipole_coefficients": Call(lambda: {"decimal_year": 2025.0}),
    "gnssatt.magnetic.dipole_field_ecef": Call(
        lambda: {
            "position_ecef_m": np.array([7e6, 0.0, 1e6]),
            "decimal_year": 2025.0,
        }
    ),
    "gnssatt.magnetic.dipole_field_eci": Call(
        lambda: {
            "position_eci_m": np.array([7e6, 0.0, 1e6]),
            "decimal_year": 2025.0,
            "earth_rotation_angle_rad": 0.3,
        }
    ),
    "gnssatt.magnetic.dipole_field_ned": Call(
        lambda: {
            "lat_deg": 50.0,
            "lon_deg": 36.2,
            "height_m": 500e3,
            "decimal_year": 2025.0,
        }
    ),
    "gnssatt.magnetic.dipole_orbital": Call(
        lambda: {
            "u": np.linspace(0.0, 6.0, 5),
            "inclination": 0.9,
            "radius": 6.9e6,
            "strength": 7.7e15,
        }
    ),
    "gnssatt.magnetic.igrf_field_ecef": Call(
        lambda: {
            "position_ecef_m": np.array([7e6, 0.0, 1e6]),
            "decimal_year": 2025.0,
            "max_degree": 13,
        },
        args={"max_degree": Arg(count=True)},
    ),
    # --- gnssatt.sim ---
    "gnssatt.sim.antenna_cone_mask": Call(
        lambda: {
            "los_ref": s.attitude_problem()["los"].copy(),
            "attitude": Rotation.identity(),
            "boresight_body": (0.0, 0.0, 1.0),
            "half_angle_deg": 80.0,
        }
    ),
    "gnssatt.sim.correlator_amplitude": Call(
        lambda: {
            "cn0_dbhz": np.array([35.0, 45.0]),
            "integration_time_s": 0.001,
        }
    ),
    "gnssatt.sim.dcm_ecef_from_eci": Call(lambda: {"t": np.arange(3.0), "theta0_rad": 0.1}),
    "gnssatt.sim.dcm_eci_from_ecef": Call(lambda: {"t": np.arange(3.0), "theta0_rad": 0.1}),
    "gnssatt.sim.dcm_ecef_from_enu": Call(lambda: {"lat_deg": 50.0, "lon_deg": 36.2}),
    "gnssatt.sim.earth_occlusion_mask": Call(
        lambda: {
            "receiver_m": np.array([7e6, 0.0, 0.0]),
            "satellites_m": np.array([[2.6e7, 0.0, 0.0], [-2.6e7, 0.0, 0.0]]),
            "atmosphere_m": 5e4,
            "radius_m": 6378137.0,
        }
    ),
    "gnssatt.sim.earth_rotation_angle": Call(lambda: {"t": np.arange(3.0), "theta0_rad": 0.1}),
    "gnssatt.sim.ecef_to_eci": Call(
        lambda: {
            "r_ecef": np.array([7e6, 0.0, 0.0]),
            "v_ecef": np.array([0.0, 7.5e3, 0.0]),
            "t": 10.0,
            "theta0_rad": 0.1,
        }
    ),
    "gnssatt.sim.eci_to_ecef": Call(
        lambda: {
            "r_eci": np.array([7e6, 0.0, 0.0]),
            "v_eci": np.array([0.0, 7.5e3, 0.0]),
            "t": 10.0,
            "theta0_rad": 0.1,
        }
    ),
    "gnssatt.sim.ecef_to_geodetic": Call(lambda: {"r_ecef": np.array([3.9e6, 2.8e6, 4.9e6])}),
    "gnssatt.sim.elevation_azimuth": Call(lambda: {"los_enu": s.attitude_problem()["los"].copy()}),
    "gnssatt.sim.elevation_mask": Call(
        lambda: {"los_ref": s.attitude_problem()["los"].copy(), "mask_deg": 10.0}
    ),
    "gnssatt.sim.equilateral_triangle": Call(lambda: {"side_m": 1.0, "plane": "xy"}),
    "gnssatt.sim.geodetic_to_ecef": Call(lambda: {"lat_deg": 50.0, "lon_deg": 36.2, "height_m": 150.0}),
    "gnssatt.sim.glonass_nominal": Call(lambda: {"raan0_deg": 10.0, "arg_latitude0_deg": 5.0}),
    "gnssatt.sim.gps_nominal": Call(lambda: {"extra_slots_deg": [(10.0, 20.0)]}),
    "gnssatt.sim.line_of_sight": Call(
        lambda: {
            "receiver": s.GROUND,
            "constellation": s.gps(),
            "t": np.arange(3.0),
        }
    ),
    "gnssatt.sim.los_body": Call(
        lambda: {"los": s.attitude_problem()["los"].copy(), "attitude": s.attitude_problem()["rotation"]}
    ),
    # complex correlator outputs are documented input
    "gnssatt.sim.phase_diffs": Call(
        lambda: {"phases": np.array([[0.1, 0.2], [0.3, 0.5], [1.0, -1.0]])},
        args={"phases": Arg(complex_ok=True)},
    ),
    "gnssatt.sim.random_attitude": Call(
        lambda: {"rng": 1, "n": 3}, args={"n": Arg(count=True, optional=True), "rng": Arg(optional=True)}
    ),
    "gnssatt.sim.random_los": Call(
        lambda: {"rng": 1, "n_sat": 5, "min_elevation_deg": 10.0},
        args={"n_sat": Arg(count=True), "rng": Arg(optional=True)},
    ),
    "gnssatt.sim.simulate_array": Call(
        lambda: {
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
        args={"ambiguity_max": Arg(count=True), "cn0_dbhz": Arg(optional=True), "rng": Arg(optional=True)},
    ),
    "gnssatt.sim.simulate_platform": Call(
        lambda: {
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
        args={
            "base_offset_enu_m": Arg(optional=True),
            "blockage": Arg(optional=True),
            "rng": Arg(optional=True),
        },
    ),
    **{
        f"gnssatt.sim.{name}": Call(
            lambda: {
                "folder": s.folder(),
                "n_antennas": 2,
                "duration_s": 1.0,
                "interval_s": 0.5,
                "noise": "gps_l1_ublox",
                "baseline_m": (1.0, 0.8),
                "base_offset_enu_m": np.array([-50.0, 20.0, 0.0]),
                "start_s": 7200.0,
                "rng": 1,
            },
            args={"n_antennas": Arg(count=True), "rng": Arg(optional=True)},
        )
        for name in ("car", "ship", "aircraft")
    },
    "gnssatt.sim.simulate_spaceborne": Call(
        lambda: {
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
        nan_output="measurements of satellites out of view are NaN, flagged by visible",
        args={"rng": Arg(optional=True)},
    ),
    "gnssatt.sim.solve_kepler": Call(
        lambda: {
            "mean_anomaly_rad": np.array([0.1, 2.0]),
            "eccentricity": 0.1,
            "tol": 1e-14,
            "max_iter": 50,
        },
        args={"max_iter": Arg(count=True)},
    ),
    "gnssatt.sim.walker": Call(
        lambda: {
            "n_sat": 6,
            "n_planes": 3,
            "phasing": 1,
            "inclination_deg": 55.0,
            "semi_major_axis_m": 26.56e6,
            "frequency_hz": 1575.42e6,
            "prefix": "E",
            "raan0_deg": 0.0,
        },
        args={"n_sat": Arg(count=True), "n_planes": Arg(count=True)},
    ),
    "gnssatt.sim.wrap_rad": Call(lambda: {"x": np.array([-7.0, 0.5, 10.0])}),
    "gnssatt.sim.attitude_scenario.attitude_fixes": Call(
        lambda: {
            "phases": s.phases(),
            "attitude": Rotation.identity(len(s.phases().epoch_t)),
            "baselines_m": s.BASELINES.copy(),
            "rng": 1,
            "phase_sigma_cycles": 0.01,
            "min_satellites": 3,
        },
        args={"rng": Arg(optional=True)},
    ),
    "gnssatt.sim.attitude_scenario.gyro_output": Call(
        lambda: {
            "t": s.gyro()["t"].copy(),
            "attitude": s.gyro()["att"],
            "rng": 1,
            "drift_rad_s": np.zeros(3),
            "arw": 1e-5,
            "rrw": 1e-7,
        }
    ),
    "gnssatt.sim.attitude_scenario.orbital_hold_motion": Call(
        lambda: {
            "receiver": s.ORBITAL,
            "t": np.arange(0.0, 2.1, 1.0),
            "amplitude_rad": (0.03, 0.02, 0.05),
            "period_s": (200.0, 250.0, 300.0),
            "phase_rad": (0.0, 1.0, 2.0),
        }
    ),
    "gnssatt.sim.attitude_scenario.phase_observations": Call(
        lambda: {
            "receiver": s.ORBITAL,
            "gnss": s.gps(),
            "t": s.gyro()["t"][::10].copy(),
            "attitude": s.gyro()["att"][::10],
            "baselines_m": s.BASELINES.copy(),
            "rng": 1,
            "phase_sigma_cycles": 0.01,
            "half_angle_deg": 80.0,
        }
    ),
    "gnssatt.sim.attitude_scenario.right_jacobian": Call(lambda: {"a": np.array([0.1, -0.2, 0.3])}),
    "gnssatt.constants.glonass_frequency_hz": Call(lambda: {"k": np.array([-7, 0, 6]), "band": "L1"}),
    "gnssatt.constants.glonass_wavelength_m": Call(lambda: {"k": np.array([-7, 0, 6]), "band": "L2"}),
    # --- gnssatt.orbit ---
    "gnssatt.orbit.glonass_propagate": Call(
        lambda: {
            "position_m": np.array([7003008.789, -12206626.953, 21280765.625]),
            "velocity_m_s": np.array([783.86, 2804.61, 1352.32]),
            "duration_s": 600.0,
            "step_s": 10.0,
            "lunisolar_m_s2": np.array([1e-6, 2e-6, -1e-6]),
            "model": orbit.GlonassModel(),
        },
        args={
            "step_s": Arg(work=WORK_TINY_STEP),
            "duration_s": Arg(work=(1e12, 1e300)),
            "model": Arg(optional=True),
        },
    ),
    "gnssatt.orbit.gmst_rad": Call(lambda: {"jd_ut1": np.array([2451545.0, 2460000.5])}),
    "gnssatt.orbit.teme_to_ecef": Call(
        lambda: {
            "r_teme_m": np.array([[7e6, 0.0, 0.0]]),  # (1, 3): one state, as rows
            "v_teme_m_s": np.array([[0.0, 7.5e3, 0.0]]),
            "jd_ut1": 2460000.5,
        }
    ),
    "gnssatt.orbit.tle_states": Call(
        lambda: {
            "line1": s.TLE[0],
            "line2": s.TLE[1],
            "times": np.array(["2008-09-20T12:25:40", "2008-09-20T12:26:40"], dtype="datetime64[ns]"),
            "dut1_s": 0.1,
        }
    ),
    # --- gnssatt.orbit.determination ---
    "gnssatt.orbit.determination.noisy_orbit": Call(
        lambda: {
            "x0": _sb()["x0"].copy(),
            "times_s": _sb()["t"].copy(),
            "rng": 1,
            "accel_psd_m2_s3": 1e-8,
            "step_s": 10.0,
        },
        args={"step_s": Arg(work=WORK_TINY_STEP), "rng": Arg(optional=True)},
    ),
    "gnssatt.orbit.determination.orbit_filter": Call(
        lambda: {
            "data": _sb()["meas"],
            "x0": _sb()["x0"] + 10.0,
            "p0": np.diag([30.0**2] * 3 + [0.05**2] * 3),
            "coupling": "tight",
            "accel_psd_m2_s3": 1e-8,
            "step_s": 10.0,
            "use_doppler": True,
        },
        args={"step_s": Arg(work=WORK_TINY_STEP)},
    ),
    "gnssatt.orbit.determination.receiver_fix": Call(
        lambda: {"measurements": _sb()["meas"]}, nan_output="invalid epochs' fixes are NaN, flagged by valid"
    ),
    "gnssatt.orbit.determination.white_acceleration_noise": Call(
        lambda: {"accel_psd_m2_s3": 1e-8, "dt_s": 10.0}
    ),
    # --- gnssatt.attitude.dynamics ---
    "gnssatt.attitude.dynamics.axis_cost": Call(
        lambda: {
            **_tumble_args(),
            "measured_axes": tumble.propagate_axes(
                s.TUMBLE_TRUTH, np.arange(0.0, 31.0, 10.0), s.TUMBLE_MODEL
            ),
            "step_s": 1.0,
        },
        args={"step_s": Arg(work=WORK_TINY_STEP), "model": Arg(optional=True)},
    ),
    "gnssatt.attitude.dynamics.fold_symmetric": Call(
        lambda: {
            "params": s.TUMBLE_TRUTH.copy(),
            "reference": s.TUMBLE_TRUTH + 0.1,
        }
    ),
    "gnssatt.attitude.dynamics.noise_cost_threshold": Call(
        lambda: {
            "n_epochs": 100,
            "axis_sigma_deg": 1.0,
            "false_restart": 1e-3,
        },
        args={"n_epochs": Arg(count=True)},
    ),
    "gnssatt.attitude.dynamics.propagate": Call(
        lambda: {**_tumble_args(), "step_s": 1.0},
        args={"step_s": Arg(work=WORK_TINY_STEP), "model": Arg(optional=True)},
    ),
    "gnssatt.attitude.dynamics.propagate_axes": Call(
        lambda: {**_tumble_args(), "step_s": 1.0},
        args={"step_s": Arg(work=WORK_TINY_STEP), "model": Arg(optional=True)},
    ),
    # --- gnssatt.montecarlo ---
    "gnssatt.montecarlo.run": Call(
        lambda: {
            "trial": monte_trial,
            "n_trials": 4,
            "seed": 1,
            "executor": montecarlo.SerialExecutor(),
            "progress": False,
            "chunksize": 2,
        },
        args={"n_trials": Arg(count=True), "chunksize": Arg(count=True)},
    ),
    "gnssatt.montecarlo.trial_generators": Call(
        lambda: {"seed": 1, "n_trials": 3}, args={"n_trials": Arg(count=True)}
    ),
}
