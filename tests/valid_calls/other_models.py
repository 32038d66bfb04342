"""Valid calls of the models and the simulator that are not a public function by their name: classes,
methods (of the objects below), and a second form of a public function (other values, which specific cases
of ``test_intake_models`` are written against), keyed by the intake test's names."""

from __future__ import annotations

import numpy as np
from scipy.spatial.transform import Rotation

from gnssatt import magnetic, orbit, sim
from gnssatt.attitude import dynamics as tumble
from gnssatt.observations import SpaceborneMeasurements
from gnssatt.orbit import determination
from gnssatt.sim import attitude_scenario as scen

from .spec import Arg, Call

RNG = np.random.default_rng(0)
GPS = sim.gps_nominal()
GROUND = sim.GroundReceiver(lat_deg=50.0, lon_deg=36.2, height_m=150.0)
LEO = sim.OrbitalReceiver(altitude_m=500e3, inclination_deg=97.0)
GEOM = sim.line_of_sight(GROUND, GPS, t=0.0)
KEPLER = GPS.orbits
T3 = np.array([0.0, 10.0, 20.0])
ATT3 = Rotation.from_rotvec(np.zeros((3, 3)))
BASELINES = np.array([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])
P0 = np.diag([100.0, 100.0, 100.0, 1.0, 1.0, 1.0])


def _spaceborne() -> SpaceborneMeasurements:
    times = np.arange(0.0, 30.0, 10.0)
    r, v = LEO.state_ecef(times)
    return sim.simulate_spaceborne(r, v, times, GPS, np.random.default_rng(1))


MEAS = _spaceborne()
PHASES = scen.phase_observations(
    LEO, GPS, T3, ATT3, BASELINES, np.random.default_rng(2), phase_sigma_cycles=0.01, half_angle_deg=180.0
)
FILTERED = determination.orbit_filter(MEAS, [*LEO.state_ecef(MEAS.times_s)[0][0], 0.0, 7.6e3, 0.0], P0)


CALLS: dict[str, Call] = {
    "magnetic.geodetic_to_ecef": Call(
        lambda: {"lat_deg": np.array([10.0, 20.0]), "lon_deg": 5.0, "height_m": 100.0},
        function=magnetic.geodetic_to_ecef,
    ),
    "Geometry.from_los": Call(
        lambda: {
            "los": np.array([[0, 0, 1.0], [0, 1, 1.0]]),
            "range_m": 2e7,
            "range_rate_mps": 0.0,
            "frame": "enu",
        },
        function=sim.Geometry.from_los,
    ),
    "Geometry": Call(
        lambda: {
            "los": np.array([[0, 0, 1.0]]),
            "range_m": np.array([2e7]),
            "range_rate_mps": np.array([0.0]),
            "frame": "enu",
            "ids": ("G01",),
            "t": np.array(0.0),
            "receiver_eci_m": np.full(3, np.nan),
            "satellites_eci_m": np.full((1, 3), np.nan),
        },
        function=sim.Geometry,
    ),
    "Geometry.select": Call(lambda: {"mask": np.array([0, 1])}, function=GEOM.select),
    "KeplerOrbits": Call(
        lambda: {
            "semi_major_axis_m": np.array([2.6e7]),
            "eccentricity": np.array([0.01]),
            "inclination_rad": np.array([1.0]),
            "raan_rad": np.array([0.0]),
            "arg_perigee_rad": np.array([0.0]),
            "mean_anomaly_rad": np.array([0.0]),
            "gm_m3_s2": 3.986e14,
        },
        function=sim.KeplerOrbits,
    ),
    "KeplerOrbits.circular": Call(
        lambda: {
            "semi_major_axis_m": 2.6e7,
            "inclination_rad": 1.0,
            "raan_rad": 0.0,
            "arg_latitude_rad": [0.0, 1.0],
        },
        function=sim.KeplerOrbits.circular,
    ),
    "KeplerOrbits.state_eci": Call(lambda: {"t": T3}, function=KEPLER.state_eci),
    "KeplerOrbits.subset": Call(lambda: {"index": np.array([0, 1])}, function=KEPLER.subset),
    "Constellation": Call(
        lambda: {
            "ids": ("G01",),
            "orbits": KEPLER.subset(np.array([0])),
            "frequencies_hz": {"L1": np.array([1.57542e9])},
            "slots": ("",),
            "glonass_channels": np.array([0]),
        },
        function=sim.Constellation,
    ),
    "Constellation.select": Call(lambda: {"which": np.array([0, 1])}, function=GPS.select),
    "Constellation.wavelengths_m": Call(lambda: {"band": "L1"}, function=GPS.wavelengths_m),
    "Constellation.state_ecef": Call(lambda: {"t": T3, "theta0_rad": 0.0}, function=GPS.state_ecef),
    "GroundReceiver": Call(
        lambda: {"lat_deg": 10.0, "lon_deg": 20.0, "height_m": 0.0, "theta0_rad": 0.0},
        function=sim.GroundReceiver,
    ),
    "OrbitalReceiver": Call(
        lambda: {
            "altitude_m": 5e5,
            "inclination_deg": 97.0,
            "raan_deg": 0.0,
            "arg_latitude_deg": 0.0,
            "theta0_rad": 0.0,
            "gm_m3_s2": 3.986e14,
        },
        function=sim.OrbitalReceiver,
    ),
    "OrbitalReceiver.state_eci": Call(lambda: {"t": T3}, function=LEO.state_eci),
    "GroundReceiver.dcm_eci_from_enu": Call(lambda: {"t": T3}, function=GROUND.dcm_eci_from_enu),
    "Leg": Call(
        lambda: {"duration_s": 5.0, "speed_m_s": 10.0, "turn_rate_deg_s": 3.0, "climb_rate_m_s": 1.0},
        function=sim.Leg,
    ),
    "Trajectory": Call(
        lambda: {
            "legs": (sim.Leg(5.0, 10.0),),
            "heading0_deg": 30.0,
            "start_enu_m": np.zeros(3),
            "roll_amplitude_deg": 5.0,
            "roll_period_s": 8.0,
        },
        function=sim.Trajectory,
    ),
    "Blockage": Call(
        lambda: {
            "outages_s": np.array([[1.0, 2.0]]),
            "tree_lined_s": np.array([[3.0, 5.0]]),
            "along_deg": 15.0,
            "across_deg": 45.0,
        },
        function=sim.Blockage,
    ),
    "NoiseProfile": Call(
        lambda: {
            "systems": "G",
            "frequencies": 1,
            "code_sigma_m": np.array([0.25, 0.25]),
            "phase_sigma_m": np.array([0.002, 0.002]),
            "doppler_sigma_hz": 0.1,
            "slip_rate_per_s": 0.001,
        },
        function=sim.NoiseProfile,
    ),
    "SpaceborneMeasurements": Call(
        lambda: dict(MEAS.__dict__),
        args={"doppler_hz": Arg(nonfinite_ok=True), "pseudorange_m": Arg(nonfinite_ok=True)},
        function=SpaceborneMeasurements,
    ),
    "SpaceborneMeasurements.select_systems": Call(lambda: {"prefixes": "G"}, function=MEAS.select_systems),
    "gyro_output": Call(
        lambda: {
            "t": T3,
            "attitude": ATT3,
            "rng": RNG,
            "drift_rad_s": np.zeros(3),
            "arw": 1e-5,
            "rrw": 1e-7,
            "misalignment_rad": np.zeros(3),
        },
        args={"rng": Arg(optional=True)},
        function=scen.gyro_output,
    ),
    "phase_observations": Call(
        lambda: {
            "receiver": LEO,
            "gnss": GPS,
            "t": T3,
            "attitude": ATT3,
            "baselines_m": BASELINES,
            "rng": RNG,
            "phase_sigma_cycles": 0.01,
            "half_angle_deg": 80.0,
            "atmosphere_m": 1e5,
            "max_satellites": 8,
            "new_arcs_after": np.array([5.0]),
            "slips": np.array([[10.0, 3.0, 1.0]]),
        },
        args={"max_satellites": Arg(optional=True), "rng": Arg(optional=True)},
        function=scen.phase_observations,
    ),
    "PhaseObservations": Call(lambda: dict(PHASES.__dict__), function=scen.PhaseObservations),
    "GyroOutput": Call(
        lambda: {"t": T3, "rates": np.zeros((3, 3)), "drift": np.zeros((3, 3))}, function=scen.GyroOutput
    ),
    "AttitudeFixes": Call(
        lambda: {"t": T3, "rotation": ATT3, "covariance": np.tile(np.eye(3), (3, 1, 1))},
        function=scen.AttitudeFixes,
    ),
    "GlonassModel": Call(
        lambda: {
            "gm_m3_s2": 3.986e14,
            "j2": 1e-3,
            "equatorial_radius_m": 6.378e6,
            "omega_rad_s": 7.29e-5,
            "lunisolar_m_s2": (0.0, 0.0, 1e-6),
        },
        function=orbit.GlonassModel,
    ),
    "CircularOrbit": Call(
        lambda: {
            "radius_m": 7e6,
            "inclination_rad": 1.7,
            "raan_rad": 0.0,
            "arg_latitude0_rad": 0.0,
            "gm_m3_s2": 3.986e14,
        },
        function=orbit.CircularOrbit,
    ),
    "CircularOrbit.state_ecef": Call(
        lambda: {"times_s": T3, "theta0_rad": 0.0, "omega_rad_s": 7.29e-5},
        function=orbit.CircularOrbit(7e6, 1.7, 0.0, 0.0).state_ecef,
    ),
    "OrbitFilterResult.nees": Call(lambda: {"truth": FILTERED.states}, function=FILTERED.nees),
    "TumbleModel": Call(
        lambda: {
            "orbital_rate_rad_s": 1.1e-3,
            "speed_m_s": 7.6e3,
            "inertia_kg_m2": (0.035, 0.008, 0.030),
            "gravity_gradient": True,
            "density_kg_m3": 5e-13,
            "drag_coefficient": 2.2,
            "area_m2": 0.03,
            "cp_offset_m": (0.0, -0.02, 0.0),
        },
        function=tumble.TumbleModel,
    ),
    "TumbleModel.circular": Call(lambda: {"altitude_m": 5e5}, function=tumble.TumbleModel.circular),
    "fit_rotation": Call(
        lambda: {
            "t": T3,
            "measured_axes": np.tile([0.0, 1.0, 0.0], (3, 1)),
            "rng": 1,
            "axis_sigma_deg": 5.0,
            "max_restarts": 1,
            "min_restarts": 0,
            "false_restart": 1e-3,
            "popsize": 2,
            "mutation": (0.5, 1.0),
            "recombination": 0.9,
            "tol_abs": 1e-3,
            "patience": 2,
            "maxiter": 2,
            "max_rate_rad_s": 0.05,
            "step_s": 1.0,
        },
        args={"axis_sigma_deg": Arg(optional=True), "rng": Arg(optional=True)},
        function=tumble.fit_rotation,
    ),
}
