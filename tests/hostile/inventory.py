"""The public API of gnssatt, discovered from the modules' ``__all__``, and for each function a valid call.

Each :class:`Entry` builds the keyword arguments of one call that must succeed (``test_inventory`` checks
that it does: the harness's own test). The hostile harness then replaces one argument at a time. An entry
also says which arguments are work counts (``counts``), which values are absurd amounts of work that must be
refused quickly (``work``), and where non-finite values are part of the documented input (``nonfinite_ok``)
or output (``nan_output``).

Excluded modules (``EXCLUDED``): ``gnssatt.cli`` (driven through subprocesses by the CLI cases),
``gnssatt.plots`` (draws files from results of the functions here) and ``gnssatt.experiments`` (the papers'
reproductions, reached through ``gnssatt reproduce``).
"""

from __future__ import annotations

import importlib
import inspect
import pkgutil
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from scipy.spatial.transform import Rotation

import gnssatt
from gnssatt import montecarlo, sim
from gnssatt.attitude import dynamics as tumble

from . import scenario as s
from .trials import monte_trial

# Searched first, so that a function re-exported in several places is known by its most public name.
PREFERRED = (
    "gnssatt",
    "gnssatt.magnetic",
    "gnssatt.sim",
    "gnssatt.orbit",
    "gnssatt.orbit_nav",
    "gnssatt.attitude.dynamics",
    "gnssatt.rinex",
    "gnssatt.montecarlo",
    "gnssatt.attitude.visibility",
    "gnssatt.rotation",
    "gnssatt.geometry",
)
EXCLUDED = ("gnssatt.cli", "gnssatt.plots", "gnssatt.experiments")

WORK_TINY_STEP = (1e-300, 1e-9)  # integration steps: 1e300 and 1e9+ steps per second of span


@dataclass(frozen=True)
class Entry:
    """A valid call of one public function and what its arguments mean to the harness.

    Attributes
    ----------
    build
        Returns fresh valid keyword arguments; only these are mutated (others keep their defaults).
    counts
        Integer arguments that size work or memory: get the overflow-size counts.
    work
        Per argument, absurd values (tiny steps, huge spans) that must be refused before the work starts.
    nonfinite_ok
        Arguments where NaN/inf is documented input (e.g. missing observations).
    nan_output
        Why the result may hold NaN (documented "not available" fields), or None: all outputs must be finite.
    nan_fields
        Result attributes documented as possibly non-finite (the rest is checked).
    free_text
        Text arguments where any (short, printable) text is valid, such as a marker name: no invalid-name
        or empty-text mutants.
    complex_ok
        Arguments where complex values are documented input (e.g. correlator outputs).
    """

    build: Callable[[], dict[str, Any]]
    counts: frozenset[str] = frozenset()
    work: Mapping[str, tuple[Any, ...]] = field(default_factory=dict)
    nonfinite_ok: frozenset[str] = frozenset()
    nan_output: str | None = None
    nan_fields: frozenset[str] = frozenset()
    free_text: frozenset[str] = frozenset()
    complex_ok: frozenset[str] = frozenset()


def _e(build: Callable[[], dict[str, Any]], **kw: Any) -> Entry:
    for key in ("counts", "nonfinite_ok", "nan_fields", "free_text", "complex_ok"):
        if key in kw:
            kw[key] = frozenset(kw[key])
    return Entry(build, **kw)


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


ENTRIES: dict[str, Entry] = {
    # --- gnssatt (estimators, ambiguities) ---
    "gnssatt.bootstrap_success_rate": _e(lambda: {"covariance": _amb()["covariance"]}),
    "gnssatt.lambda_decorrelate": _e(lambda: {"covariance": _amb()["covariance"]}),
    "gnssatt.lambda_ils": _e(lambda: {**_amb(), "candidates": 2}, counts={"candidates"}),
    "gnssatt.lambda_ils_batch": _e(
        lambda: {
            "float_ambiguities": np.stack([_amb()["float_ambiguities"] + k for k in range(3)]),
            "covariance": _amb()["covariance"],
            "candidates": 2,
        },
        counts={"candidates"},
    ),
    "gnssatt.ratio_test": _e(
        lambda: {**_amb(), "failure_rate": 1e-3, "samples": 2000, "seed": 0},
        counts={"samples"},
        nan_fields={"ratio"},  # inf when the best squared norm is 0 (integer float vector), documented
    ),
    "gnssatt.partial_fix": _e(
        lambda: {**_amb(), "min_success_rate": 0.5, "threshold": 2.0, "samples": 2000, "seed": 0},
        counts={"samples"},
        nan_fields={"ratio", "threshold"},  # NaN when nothing is fixed, ratio inf on integers: documented
    ),
    "gnssatt.ratio_threshold_fixed_failure_rate": _e(
        lambda: {"covariance": _amb()["covariance"], "failure_rate": 1e-3, "samples": 2000, "seed": 0},
        counts={"samples"},
    ),
    "gnssatt.matrix_attitude": _e(
        lambda: {
            "baselines": s.BASELINES.copy(),
            "los": _att()["los"].copy(),
            "range_diffs": _att()["range_diffs"].copy(),
            "method": "svd",
        }
    ),
    "gnssatt.likelihood_grid": _e(lambda: {**_phase_args(), "step_deg": 5.0, "window_deg": _WINDOW.copy()}),
    "gnssatt.ml_attitude": _e(lambda: {**_phase_args(), "step_deg": 5.0, "window_deg": _WINDOW.copy()}),
    "gnssatt.ml_baseline": _e(
        lambda: {
            "phase_diffs": _att()["phase"][0].copy(),
            "los": _att()["los"].copy(),
            "baseline_length_m": 1.0,
            "wavelength": _att()["wavelength"],
            "step_deg": 2.0,
        }
    ),
    "gnssatt.ml_attitude_series": _e(
        lambda: {
            "sd_phase": np.stack([_att()["phase"][:2], _att()["phase"][:2]]),
            "los": _att()["los"].copy(),
            "baselines": s.BASELINES[:2].copy(),
            "wavelength": _att()["wavelength"],
            "step_deg": 5.0,
            "window_deg": 10.0,
        },
        nonfinite_ok={"sd_phase", "los", "wavelength"},  # NaN marks absent signals, documented
        nan_fields={"euler_gost_deg", "z_max"},  # NaN at unsolved epochs, flagged by solved
    ),
    "gnssatt.ml_baseline_series": _e(
        lambda: {
            "sd_phase": np.stack([_att()["phase"][0], _att()["phase"][0]]),
            "los": _att()["los"].copy(),
            "baseline_length_m": 1.0,
            "wavelength": _att()["wavelength"],
            "step_deg": 2.0,
            "window_deg": 5.0,
        },
        nonfinite_ok={"sd_phase", "los", "wavelength"},  # NaN marks absent signals, documented
        nan_fields={"heading_deg", "elevation_deg", "direction_enu", "z_max"},  # unsolved epochs
    ),
    "gnssatt.prior_from_velocity": _e(
        lambda: {
            "velocity_enu": np.array([10.0, 20.0, 0.5]),
            "acceleration_enu": np.array([0.1, -0.2, 0.0]),
            "half_width_deg": (7.0, 7.0, 7.0),
            "gravity": 9.80665,
        }
    ),
    "gnssatt.triad": _e(
        lambda: {
            "b1": np.array([1.0, 0.0, 0.0]),
            "b2": np.array([0.0, 1.0, 0.0]),
            "r1": np.array([0.0, 1.0, 0.0]),
            "r2": np.array([-1.0, 0.0, 0.0]),
        }
    ),
    "gnssatt.wahba": _e(
        lambda: {
            "body": np.eye(3),
            "ref": Rotation.from_euler("z", 30, degrees=True).apply(np.eye(3)),
            "weights": np.array([1.0, 2.0, 3.0]),
        }
    ),
    "gnssatt.yaw_from_magnetometer": _e(
        lambda: {
            "b_body": np.array([2e-5, 1e-5, -3e-5]),
            "b_orbital": np.array([1e-5, 2e-5, -3e-5]),
            "pitch": 0.01,
            "roll": -0.02,
        }
    ),
    "gnssatt.gyro_propagate": _e(
        lambda: {
            "q0": np.array([0.0, 0.0, 0.0, 1.0]),
            "t": np.arange(0.0, 1.01, 0.1),
            "rates": np.full((11, 3), 0.01),
        }
    ),
    "gnssatt.gyro_gnss_filter": _e(_gyro_filter, counts={"output_every"}),
    "gnssatt.phase_attitude_fixes": _e(
        lambda: {
            "phases": s.phases(),
            "baselines_m": s.BASELINES.copy(),
            "ambiguities": s.phases().ambiguity.copy(),
            "phase_sigma_cycles": 0.01,
        }
    ),
    "gnssatt.fit_rotation": _e(
        _fit_args,
        counts={"max_restarts", "popsize", "maxiter", "patience"},
        work={"step_s": WORK_TINY_STEP},
        nan_fields={"cost_threshold"},  # inf when axis_sigma_deg is None (no restart test), documented
    ),
    "gnssatt.visibility_axis": _e(
        lambda: {
            "visible_los": _unit([[0.0, 0.0, 1.0], [0.3, 0.0, 0.95], [0.0, 0.3, 0.95]]),
            "invisible_los": _unit([[0.0, 0.0, -1.0], [0.3, 0.0, -0.95]]),
            "method": "paper",
        }
    ),
    # --- gnssatt.magnetic ---
    "gnssatt.magnetic.dcm_ned_from_ecef": _e(lambda: {"lat_deg": 50.0, "lon_deg": 36.2}),
    "gnssatt.magnetic.dipole_coefficients": _e(lambda: {"decimal_year": 2025.0}),
    "gnssatt.magnetic.dipole_field_ecef": _e(
        lambda: {"position_ecef_m": np.array([7e6, 0.0, 1e6]), "decimal_year": 2025.0}
    ),
    "gnssatt.magnetic.dipole_field_eci": _e(
        lambda: {
            "position_eci_m": np.array([7e6, 0.0, 1e6]),
            "decimal_year": 2025.0,
            "earth_rotation_angle_rad": 0.3,
        }
    ),
    "gnssatt.magnetic.dipole_field_ned": _e(
        lambda: {"lat_deg": 50.0, "lon_deg": 36.2, "height_m": 500e3, "decimal_year": 2025.0}
    ),
    "gnssatt.magnetic.dipole_orbital": _e(
        lambda: {"u": np.linspace(0.0, 6.0, 5), "inclination": 0.9, "radius": 6.9e6, "strength": 7.7e15}
    ),
    "gnssatt.magnetic.igrf_field_ecef": _e(
        lambda: {"position_ecef_m": np.array([7e6, 0.0, 1e6]), "decimal_year": 2025.0, "max_degree": 13},
        counts={"max_degree"},
    ),
    # --- gnssatt.sim ---
    "gnssatt.sim.antenna_cone_mask": _e(
        lambda: {
            "los_ref": _att()["los"].copy(),
            "attitude": Rotation.identity(),
            "boresight_body": (0.0, 0.0, 1.0),
            "half_angle_deg": 80.0,
        }
    ),
    "gnssatt.sim.correlator_amplitude": _e(
        lambda: {"cn0_dbhz": np.array([35.0, 45.0]), "integration_time_s": 0.001}
    ),
    "gnssatt.sim.dcm_ecef_from_eci": _e(lambda: {"t": np.arange(3.0), "theta0_rad": 0.1}),
    "gnssatt.sim.dcm_eci_from_ecef": _e(lambda: {"t": np.arange(3.0), "theta0_rad": 0.1}),
    "gnssatt.sim.dcm_ecef_from_enu": _e(lambda: {"lat_deg": 50.0, "lon_deg": 36.2}),
    "gnssatt.sim.earth_occlusion_mask": _e(
        lambda: {
            "receiver_m": np.array([7e6, 0.0, 0.0]),
            "satellites_m": np.array([[2.6e7, 0.0, 0.0], [-2.6e7, 0.0, 0.0]]),
            "atmosphere_m": 5e4,
            "radius_m": 6378137.0,
        }
    ),
    "gnssatt.sim.earth_rotation_angle": _e(lambda: {"t": np.arange(3.0), "theta0_rad": 0.1}),
    "gnssatt.sim.ecef_to_eci": _e(
        lambda: {
            "r_ecef": np.array([7e6, 0.0, 0.0]),
            "v_ecef": np.array([0.0, 7.5e3, 0.0]),
            "t": 10.0,
            "theta0_rad": 0.1,
        }
    ),
    "gnssatt.sim.eci_to_ecef": _e(
        lambda: {
            "r_eci": np.array([7e6, 0.0, 0.0]),
            "v_eci": np.array([0.0, 7.5e3, 0.0]),
            "t": 10.0,
            "theta0_rad": 0.1,
        }
    ),
    "gnssatt.sim.ecef_to_geodetic": _e(lambda: {"r_ecef": np.array([3.9e6, 2.8e6, 4.9e6])}),
    "gnssatt.sim.elevation_azimuth": _e(lambda: {"los_enu": _att()["los"].copy()}),
    "gnssatt.sim.elevation_mask": _e(lambda: {"los_ref": _att()["los"].copy(), "mask_deg": 10.0}),
    "gnssatt.sim.equilateral_triangle": _e(lambda: {"side_m": 1.0, "plane": "xy"}),
    "gnssatt.sim.geodetic_to_ecef": _e(lambda: {"lat_deg": 50.0, "lon_deg": 36.2, "height_m": 150.0}),
    "gnssatt.sim.glonass_nominal": _e(lambda: {"raan0_deg": 10.0, "arg_latitude0_deg": 5.0}),
    "gnssatt.sim.gps_nominal": _e(lambda: {"extra_slots_deg": [(10.0, 20.0)]}),
    "gnssatt.sim.line_of_sight": _e(
        lambda: {"receiver": s.GROUND, "constellation": s.gps(), "t": np.arange(3.0)}
    ),
    "gnssatt.sim.los_body": _e(lambda: {"los": _att()["los"].copy(), "attitude": _att()["rotation"]}),
    "gnssatt.sim.phase_diffs": _e(
        lambda: {"phases": np.array([[0.1, 0.2], [0.3, 0.5], [1.0, -1.0]])},
        complex_ok={"phases"},  # complex correlator outputs are documented input
    ),
    "gnssatt.sim.random_attitude": _e(lambda: {"rng": 1, "n": 3}, counts={"n"}),
    "gnssatt.sim.random_los": _e(lambda: {"rng": 1, "n_sat": 5, "min_elevation_deg": 10.0}, counts={"n_sat"}),
    "gnssatt.sim.simulate_array": _e(
        lambda: {
            "geometry": s.geometry(),
            "attitude": Rotation.identity(),
            "antennas_body_m": sim.equilateral_triangle(1.0),
            "wavelengths_m": np.full(len(s.geometry().ids), 0.19),
            "rng": 1,
            "code_sigma_m": 0.3,
            "phase_sigma_rad": 0.01,
            "ambiguity_max": 100,
            "cn0_dbhz": np.full(len(s.geometry().ids), 45.0),
            "integration_time_s": 0.001,
        },
        counts={"ambiguity_max"},
    ),
    "gnssatt.sim.simulate_spaceborne": _e(
        lambda: {
            "receiver_position_m": _sb()["r"].copy(),
            "receiver_velocity_m_s": _sb()["v"].copy(),
            "times_s": _sb()["t"].copy(),
            "constellation": s.gps(),
            "rng": 1,
            "half_angle_deg": 85.0,
            "code_sigma_m": 1.0,
            "outages": [(10.0, 20.0, 2)],
        },
        nan_output="measurements of satellites out of view are NaN, flagged by visible",
    ),
    "gnssatt.sim.solve_kepler": _e(
        lambda: {"mean_anomaly_rad": np.array([0.1, 2.0]), "eccentricity": 0.1, "tol": 1e-14, "max_iter": 50},
        counts={"max_iter"},
    ),
    "gnssatt.sim.walker": _e(
        lambda: {
            "n_sat": 6,
            "n_planes": 3,
            "phasing": 1,
            "inclination_deg": 55.0,
            "semi_major_axis_m": 26.56e6,
            "frequency_hz": 1575.42e6,
        },
        counts={"n_sat", "n_planes"},
    ),
    "gnssatt.sim.wrap_rad": _e(lambda: {"x": np.array([-7.0, 0.5, 10.0])}),
    "gnssatt.sim.attitude_scenario.attitude_fixes": _e(
        lambda: {
            "phases": s.phases(),
            "attitude": Rotation.identity(len(s.phases().epoch_t)),
            "baselines_m": s.BASELINES.copy(),
            "rng": 1,
            "phase_sigma_cycles": 0.01,
            "min_satellites": 3,
        }
    ),
    "gnssatt.sim.attitude_scenario.gyro_output": _e(
        lambda: {
            "t": s.gyro()["t"].copy(),
            "attitude": s.gyro()["att"],
            "rng": 1,
            "drift_rad_s": np.zeros(3),
            "arw": 1e-5,
            "rrw": 1e-7,
        }
    ),
    "gnssatt.sim.attitude_scenario.orbital_hold_motion": _e(
        lambda: {
            "receiver": s.ORBITAL,
            "t": np.arange(0.0, 2.1, 1.0),
            "amplitude_rad": (0.03, 0.02, 0.05),
            "period_s": (200.0, 250.0, 300.0),
            "phase_rad": (0.0, 1.0, 2.0),
        }
    ),
    "gnssatt.sim.attitude_scenario.phase_observations": _e(
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
    "gnssatt.sim.attitude_scenario.right_jacobian": _e(lambda: {"a": np.array([0.1, -0.2, 0.3])}),
    "gnssatt.constants.glonass_frequency_hz": _e(lambda: {"k": np.array([-7, 0, 6]), "band": "L1"}),
    "gnssatt.constants.glonass_wavelength_m": _e(lambda: {"k": np.array([-7, 0, 6]), "band": "L2"}),
    # --- gnssatt.orbit ---
    "gnssatt.orbit.glonass_propagate": _e(
        lambda: {
            "position_m": np.array([7003008.789, -12206626.953, 21280765.625]),
            "velocity_m_s": np.array([783.86, 2804.61, 1352.32]),
            "duration_s": 600.0,
            "step_s": 10.0,
            "lunisolar_m_s2": np.array([1e-6, 2e-6, -1e-6]),
        },
        work={"step_s": WORK_TINY_STEP, "duration_s": (1e12, 1e300)},
    ),
    "gnssatt.orbit.gmst_rad": _e(lambda: {"jd_ut1": np.array([2451545.0, 2460000.5])}),
    "gnssatt.orbit.teme_to_ecef": _e(
        lambda: {
            "r_teme_m": np.array([7e6, 0.0, 0.0]),
            "v_teme_m_s": np.array([0.0, 7.5e3, 0.0]),
            "jd_ut1": 2460000.5,
        }
    ),
    "gnssatt.orbit.tle_states": _e(
        lambda: {
            "line1": s.TLE[0],
            "line2": s.TLE[1],
            "times": np.array(["2008-09-20T12:25:40", "2008-09-20T12:26:40"], dtype="datetime64[ns]"),
            "dut1_s": 0.1,
        }
    ),
    # --- gnssatt.orbit_nav ---
    "gnssatt.orbit_nav.noisy_orbit": _e(
        lambda: {
            "x0": _sb()["x0"].copy(),
            "times_s": _sb()["t"].copy(),
            "rng": 1,
            "accel_psd_m2_s3": 1e-8,
            "step_s": 10.0,
        },
        work={"step_s": WORK_TINY_STEP},
    ),
    "gnssatt.orbit_nav.orbit_filter": _e(
        lambda: {
            "data": _sb()["meas"],
            "x0": _sb()["x0"] + 10.0,
            "p0": np.diag([30.0**2] * 3 + [0.05**2] * 3),
            "coupling": "tight",
            "accel_psd_m2_s3": 1e-8,
            "step_s": 10.0,
        },
        work={"step_s": WORK_TINY_STEP},
    ),
    "gnssatt.orbit_nav.receiver_fix": _e(
        lambda: {"measurements": _sb()["meas"]}, nan_output="invalid epochs' fixes are NaN, flagged by valid"
    ),
    "gnssatt.orbit_nav.white_acceleration_noise": _e(lambda: {"accel_psd_m2_s3": 1e-8, "dt_s": 10.0}),
    # --- gnssatt.attitude.dynamics ---
    "gnssatt.attitude.dynamics.axis_cost": _e(
        lambda: {
            **_tumble_args(),
            "measured_axes": tumble.propagate_axes(
                s.TUMBLE_TRUTH, np.arange(0.0, 31.0, 10.0), s.TUMBLE_MODEL
            ),
            "step_s": 1.0,
        },
        work={"step_s": WORK_TINY_STEP},
    ),
    "gnssatt.attitude.dynamics.fold_symmetric": _e(
        lambda: {"params": s.TUMBLE_TRUTH.copy(), "reference": s.TUMBLE_TRUTH + 0.1}
    ),
    "gnssatt.attitude.dynamics.noise_cost_threshold": _e(
        lambda: {"n_epochs": 100, "axis_sigma_deg": 1.0, "false_restart": 1e-3}, counts={"n_epochs"}
    ),
    "gnssatt.attitude.dynamics.propagate": _e(
        lambda: {**_tumble_args(), "step_s": 1.0}, work={"step_s": WORK_TINY_STEP}
    ),
    "gnssatt.attitude.dynamics.propagate_axes": _e(
        lambda: {**_tumble_args(), "step_s": 1.0}, work={"step_s": WORK_TINY_STEP}
    ),
    # --- gnssatt.rinex ---
    "gnssatt.rinex.read_obs": _e(
        lambda: {"path": s.rinex_array().obs_paths[0]}, nan_output="missing observations are NaN"
    ),
    "gnssatt.rinex.read_nav": _e(
        lambda: {"path": s.rinex_array().nav_path}, nan_output="absent header Klobuchar coefficients are NaN"
    ),
    "gnssatt.gnss.attitude.attitude_from_rinex": _e(
        lambda: {
            "observations": list(s.rinex_array().obs_paths),
            "nav": s.rinex_array().nav_path,
            "method": "auto",
            "systems": "G",
            "elevation_mask_deg": 10.0,
        },
        nan_output="epochs without a solution are NaN, flagged in the series",
    ),
    "gnssatt.position_from_rinex": _e(
        lambda: {
            "obs": s.rinex_array().obs_paths[0],
            "nav": s.rinex_array().nav_path,
            "systems": "G",
            "frequencies": 1,
            "elevation_mask_deg": 10.0,
        },
        nan_output="epochs without a solution are NaN, flagged in the series",
    ),
    "gnssatt.rinex.gps_ns": _e(lambda: {"time": np.array(["2024-03-01T10:00:00"], dtype="datetime64[ns]")}),
    "gnssatt.rinex.write_nav_from_constellation": _e(
        lambda: {
            "path": s.folder() / "written.24n",
            "constellation": s.gps(),
            "epoch_gpst": np.datetime64("2024-03-01T10:00:00", "ns"),
            "start_s": 60.0,
            "span_s": 7200.0,
            "clock_bias_s": np.full(len(s.gps()), 1e-5),
            "klobuchar": np.array(
                [1.1176e-08, 7.4506e-09, -5.9605e-08, -5.9605e-08, 9.0112e04, 0.0, -1.9661e05, -6.5536e04]
            ),
        }
    ),
    "gnssatt.rinex.write_obs": _e(
        lambda: {
            "path": s.folder() / "written.24o",
            "time": np.array(["2024-03-01T10:00:00", "2024-03-01T10:00:01"], dtype="datetime64[ns]"),
            "sats": ["G01", "G02"],
            "observations": {"C1C": np.array([[2.1e7, 2.2e7], [2.1e7 + 1, np.nan]])},
            "approx_position_m": (1.0, 2.0, 3.0),
            "marker_name": "SIM",
            "glonass_channels": {"R01": 1, "R02": -4},
        },
        nonfinite_ok={"observations"},
        free_text={"marker_name"},
    ),
    "gnssatt.sim.rinex_scenario.simulate_rinex_array": _e(
        lambda: {
            "folder": s.folder(),
            "antennas_body_m": np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]]),
            "euler_gost_deg": np.zeros((2, 3)),
            "interval_s": 1.0,
            "rng": 1,
            "n_sats": 5,
        },
        counts={"n_sats"},
    ),
    "gnssatt.sim.rinex_scenario.gnss_constellation": _e(lambda: {"systems": "GRE", "lon_deg": 36.2}),
    "gnssatt.sim.rinex_scenario.simulate_gnss_rinex": _e(
        lambda: {
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
        counts={"n_epochs", "n_sats"},
    ),
    "gnssatt.rinex.nav.nav_input": _e(
        lambda: {"nav": s.rinex_read()["nav"]},
        nan_output="group delays, fit interval and data source are NaN where a system has none",
    ),
    "gnssatt.gnss.session_input.session_input": _e(
        lambda: {"observations": _obs(), "systems": "G", "frequencies": 1, "nav": s.rinex_read()["nav"]},
        nan_output="absent observations (slots, satellites, epochs) are NaN",
    ),
    "gnssatt.gnss.session_input.epochs_gpst_ns": _e(lambda: {"obs": _obs()[0], "leaps": 14}),
    "gnssatt.rinex.signals.choose_signals": _e(lambda: {"obs": _obs()[0], "system": "G"}),
    "gnssatt.rinex.signals.slot_bands": _e(lambda: {"system": "C", "version": 3.02}),
    "gnssatt.rinex.signals.slot_frequency_hz": _e(lambda: {"system": "R", "slot": 1, "glonass_channel": -3}),
    "gnssatt.sim.atmosphere.niell_mapping": _e(
        lambda: {"lat_rad": 0.8, "height_m": 150.0, "elevation_rad": np.array([0.2, 1.0])}
    ),
    "gnssatt.sim.atmosphere.saastamoinen_zenith_m": _e(lambda: {"lat_rad": 0.8, "height_m": 150.0}),
    "gnssatt.sim.atmosphere.troposphere_delay_m": _e(
        lambda: {"lat_rad": 0.8, "height_m": 150.0, "elevation_rad": np.array([0.2, 1.0])}
    ),
    "gnssatt.sim.rinex_scenario.write_array_rinex": _e(
        lambda: {
            "folder": s.folder(),
            "measurements": sim.simulate_array(
                s.geometry(), Rotation.identity(), sim.equilateral_triangle(1.0), np.full(8, 0.19), s.rng()
            ),
            "t_s": np.arange(3.0),
            "constellation": s.gps(),
            "sat_ids": list(s.geometry().ids),
            "receiver": s.GROUND,
        }
    ),
    # --- gnssatt.montecarlo ---
    "gnssatt.montecarlo.run": _e(
        lambda: {
            "trial": monte_trial,
            "n_trials": 4,
            "seed": 1,
            "executor": montecarlo.SerialExecutor(),
            "progress": False,
            "chunksize": 2,
        },
        counts={"n_trials", "chunksize"},
    ),
    "gnssatt.montecarlo.trial_generators": _e(lambda: {"seed": 1, "n_trials": 3}, counts={"n_trials"}),
    # --- gnssatt.attitude.visibility ---
    "gnssatt.attitude.visibility.visibility_sets": _e(
        lambda: {
            "receiver": s.ORBITAL,
            "constellation": s.gps(),
            "t": np.arange(0.0, 21.0, 10.0),
            "axes_orbital": np.tile([0.0, 0.0, 1.0], (3, 1)),
            "half_angle_deg": 90.0,
        }
    ),
    # --- gnssatt.rotation, gnssatt.geometry ---
    "gnssatt.rotation.dcm_to_euler": _e(
        lambda: {"seq": "ZYX", "dcm": Rotation.from_euler("ZYX", [0.3, 0.2, 0.1]).as_matrix()}
    ),
    "gnssatt.rotation.dcm_to_quat": _e(
        lambda: {"dcm": Rotation.from_euler("ZYX", [0.3, 0.2, 0.1]).as_matrix()}
    ),
    "gnssatt.rotation.euler_to_dcm": _e(lambda: {"seq": "ZYX", "angles": np.array([0.3, 0.2, 0.1])}),
    "gnssatt.rotation.nearest_rotation": _e(lambda: {"matrix": np.eye(3) + 0.01}),
    "gnssatt.rotation.quat_to_dcm": _e(lambda: {"quat": np.array([0.1, 0.2, 0.3, 0.9])}),
    "gnssatt.rotation.rotation_from_euler": _e(lambda: {"euler_gost_deg": np.array([-40.0, 5.0, 3.0])}),
    "gnssatt.rotation.euler_from_rotation": _e(
        lambda: {"rotation": Rotation.from_euler("YZX", [10.0, 5.0, 3.0], degrees=True)}
    ),
    "gnssatt.geometry.attitude_dop": _e(
        lambda: {"baselines": s.BASELINES.copy(), "los": _att()["los"].copy(), "rotation": _att()["rotation"]}
    ),
    "gnssatt.data.geonet_dir": _e(dict),
    "gnssatt.geometry.range_difference_fisher": _e(
        lambda: {"baselines": s.BASELINES.copy(), "los": _att()["los"].copy(), "rotation": _att()["rotation"]}
    ),
}


def public_modules() -> list[str]:
    """Every importable gnssatt module without an underscore in its path, outside ``EXCLUDED``,
    ``PREFERRED`` first."""
    found = [m.name for m in pkgutil.walk_packages(gnssatt.__path__, "gnssatt.")]
    rest = sorted(
        m
        for m in found
        if not any(part.startswith("_") for part in m.split("."))
        and not any(m == x or m.startswith(x + ".") for x in EXCLUDED)
        and m not in PREFERRED
    )
    return [*PREFERRED, *rest]


def public_functions() -> dict[str, Callable[..., Any]]:
    """Qualified name -> function, for every function in a public module's ``__all__`` (or, without one,
    every public name it defines); a function exported in several places is named once, where first
    found in :func:`public_modules` order."""
    seen: dict[int, str] = {}
    out: dict[str, Callable[..., Any]] = {}
    for name in public_modules():
        mod = importlib.import_module(name)
        names = getattr(mod, "__all__", None)
        if names is None:
            names = [
                n
                for n, v in vars(mod).items()
                if not n.startswith("_") and getattr(v, "__module__", "") == name
            ]
        for attr in names:
            obj = getattr(mod, attr)
            if inspect.isroutine(obj) and id(obj) not in seen:
                seen[id(obj)] = f"{name}.{attr}"
                out[f"{name}.{attr}"] = obj
    return out


def resolve(qualified: str) -> Callable[..., Any]:
    module, attr = qualified.rsplit(".", 1)
    return getattr(importlib.import_module(module), attr)


def valid_call(qualified: str) -> tuple[Callable[..., Any], dict[str, Any]]:
    return resolve(qualified), ENTRIES[qualified].build()
