"""Bad input to every public function of the models and the simulator (issue 15, part C).

Each case calls one function with valid arguments but one, which is replaced by a bad value of one
category: wrong shape, complex, boolean / object / text, None, NaN / inf, out of range, absurd size. The
call must raise :class:`~gnssatt.errors.InvalidInputError` (or a subclass: ``InvalidTypeError`` for the
wrong kinds, ``WorkLimitError`` for absurd sizes) before doing the work, with a message naming the
parameter. A second part checks the finite inputs that used to give NaN.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from functools import cache
from typing import Any

import numpy as np
import pytest
from scipy.spatial.transform import Rotation
from valid_calls import CALLS, OTHER_CALLS, Arg, Call, resolve
from valid_calls.other_models import ATT3, BASELINES, GPS, MEAS, PHASES, RNG, T3

from gnssatt import constants, magnetic, orbit, sim
from gnssatt.attitude import dynamics as tumble
from gnssatt.errors import (
    ConvergenceError,
    DegenerateGeometryError,
    InvalidInputError,
    InvalidTypeError,
    WorkLimitError,
)
from gnssatt.observations import SpaceborneMeasurements
from gnssatt.orbit import determination
from gnssatt.sim import attitude_scenario as scen


def _shared(qualified: str) -> tuple[Callable[..., Any], Call]:
    """The shared valid call of the public function ``qualified`` (``valid_calls.CALLS``)."""
    return resolve(qualified), CALLS[qualified]


def _other(name: str) -> tuple[Callable[..., Any], Call]:
    """The valid call of a class, a method or a second form (``valid_calls.OTHER_CALLS``)."""
    call = OTHER_CALLS[name]
    assert call.function is not None
    return call.function, call


# name -> (callable taking keyword arguments, valid keyword arguments): the shared valid call where the
# function is public (``_shared``), else (methods, classes, a second form of one function, calls whose
# specific cases below are written against other values) its own here
FUNCTIONS: dict[str, tuple[Callable[..., Any], Call]] = {
    # gnssatt.magnetic
    "dipole_orbital": _shared("gnssatt.magnetic.dipole_orbital"),
    "dipole_coefficients": _shared("gnssatt.magnetic.dipole_coefficients"),
    "magnetic.geodetic_to_ecef": _other("magnetic.geodetic_to_ecef"),
    "dcm_ned_from_ecef": _shared("gnssatt.magnetic.dcm_ned_from_ecef"),
    "dipole_field_ecef": _shared("gnssatt.magnetic.dipole_field_ecef"),
    "dipole_field_eci": _shared("gnssatt.magnetic.dipole_field_eci"),
    "dipole_field_ned": _shared("gnssatt.magnetic.dipole_field_ned"),
    "igrf_field_ecef": _shared("gnssatt.magnetic.igrf_field_ecef"),
    # gnssatt.frames
    "earth_rotation_angle": _shared("gnssatt.sim.earth_rotation_angle"),
    "dcm_eci_from_ecef": _shared("gnssatt.sim.dcm_eci_from_ecef"),
    "dcm_ecef_from_eci": _shared("gnssatt.sim.dcm_ecef_from_eci"),
    "eci_to_ecef": _shared("gnssatt.sim.eci_to_ecef"),
    "ecef_to_eci": _shared("gnssatt.sim.ecef_to_eci"),
    "sim.geodetic_to_ecef": _shared("gnssatt.sim.geodetic_to_ecef"),
    "ecef_to_geodetic": _shared("gnssatt.sim.ecef_to_geodetic"),
    "dcm_ecef_from_enu": _shared("gnssatt.sim.dcm_ecef_from_enu"),
    # gnssatt.orbit.line_of_sight
    "Geometry.from_los": _other("Geometry.from_los"),
    "Geometry": _other("Geometry"),
    "Geometry.select": _other("Geometry.select"),
    "los_body": _shared("gnssatt.sim.los_body"),
    "elevation_azimuth": _shared("gnssatt.sim.elevation_azimuth"),
    "line_of_sight": _shared("gnssatt.sim.line_of_sight"),
    # gnssatt.orbit.kepler
    "solve_kepler": _shared("gnssatt.sim.solve_kepler"),
    "KeplerOrbits": _other("KeplerOrbits"),
    "KeplerOrbits.circular": _other("KeplerOrbits.circular"),
    "KeplerOrbits.state_eci": _other("KeplerOrbits.state_eci"),
    "KeplerOrbits.subset": _other("KeplerOrbits.subset"),
    # gnssatt.orbit.masks
    "elevation_mask": _shared("gnssatt.sim.elevation_mask"),
    "antenna_cone_mask": _shared("gnssatt.sim.antenna_cone_mask"),
    "earth_occlusion_mask": _shared("gnssatt.sim.earth_occlusion_mask"),
    # gnssatt.sim.arrays
    "equilateral_triangle": _shared("gnssatt.sim.equilateral_triangle"),
    "random_attitude": _shared("gnssatt.sim.random_attitude"),
    "random_los": _shared("gnssatt.sim.random_los"),
    # gnssatt.orbit.constellation
    "Constellation": _other("Constellation"),
    "Constellation.select": _other("Constellation.select"),
    "Constellation.wavelengths_m": _other("Constellation.wavelengths_m"),
    "Constellation.state_ecef": _other("Constellation.state_ecef"),
    "gps_nominal": _shared("gnssatt.sim.gps_nominal"),
    "glonass_nominal": _shared("gnssatt.sim.glonass_nominal"),
    "walker": _shared("gnssatt.sim.walker"),
    # gnssatt.constants
    "glonass_frequency_hz": _shared("gnssatt.constants.glonass_frequency_hz"),
    "glonass_wavelength_m": _shared("gnssatt.constants.glonass_wavelength_m"),
    # gnssatt.sim.measurements
    "phase_diffs": _shared("gnssatt.sim.phase_diffs"),
    "correlator_amplitude": _shared("gnssatt.sim.correlator_amplitude"),
    "wrap_rad": _shared("gnssatt.sim.wrap_rad"),
    "simulate_array": _shared("gnssatt.sim.simulate_array"),
    # gnssatt.orbit.receivers
    "GroundReceiver": _other("GroundReceiver"),
    "OrbitalReceiver": _other("OrbitalReceiver"),
    "OrbitalReceiver.state_eci": _other("OrbitalReceiver.state_eci"),
    "GroundReceiver.dcm_eci_from_enu": _other("GroundReceiver.dcm_eci_from_enu"),
    # gnssatt.sim.platforms (one-second sessions written into a temporary folder)
    "simulate_platform": _shared("gnssatt.sim.simulate_platform"),
    **{name: _shared(f"gnssatt.sim.{name}") for name in ("car", "ship", "aircraft")},
    "Leg": _other("Leg"),
    "Trajectory": _other("Trajectory"),
    "Blockage": _other("Blockage"),
    "NoiseProfile": _other("NoiseProfile"),
    # gnssatt.sim.spaceborne
    "simulate_spaceborne": _shared("gnssatt.sim.simulate_spaceborne"),
    "SpaceborneMeasurements": _other("SpaceborneMeasurements"),
    "SpaceborneMeasurements.select_systems": _other("SpaceborneMeasurements.select_systems"),
    # gnssatt.sim.attitude_scenario
    "right_jacobian": _shared("gnssatt.sim.attitude_scenario.right_jacobian"),
    "orbital_hold_motion": _shared("gnssatt.sim.attitude_scenario.orbital_hold_motion"),
    "gyro_output": _other("gyro_output"),
    "phase_observations": _other("phase_observations"),
    "attitude_fixes": _shared("gnssatt.sim.attitude_scenario.attitude_fixes"),
    "PhaseObservations": _other("PhaseObservations"),
    "GyroOutput": _other("GyroOutput"),
    "AttitudeFixes": _other("AttitudeFixes"),
    # gnssatt.orbit
    "GlonassModel": _other("GlonassModel"),
    "glonass_propagate": _shared("gnssatt.orbit.glonass_propagate"),
    "CircularOrbit": _other("CircularOrbit"),
    "CircularOrbit.state_ecef": _other("CircularOrbit.state_ecef"),
    "gmst_rad": _shared("gnssatt.orbit.gmst_rad"),
    "teme_to_ecef": _shared("gnssatt.orbit.teme_to_ecef"),
    "tle_states": _shared("gnssatt.orbit.tle_states"),
    # gnssatt.orbit.determination
    "white_acceleration_noise": _shared("gnssatt.orbit.determination.white_acceleration_noise"),
    "noisy_orbit": _shared("gnssatt.orbit.determination.noisy_orbit"),
    "receiver_fix": _shared("gnssatt.orbit.determination.receiver_fix"),
    "orbit_filter": _shared("gnssatt.orbit.determination.orbit_filter"),
    "OrbitFilterResult.nees": _other("OrbitFilterResult.nees"),
    # gnssatt.attitude.dynamics
    "TumbleModel": _other("TumbleModel"),
    "TumbleModel.circular": _other("TumbleModel.circular"),
    "propagate_axes": _shared("gnssatt.attitude.dynamics.propagate_axes"),
    "axis_cost": _shared("gnssatt.attitude.dynamics.axis_cost"),
    "propagate": _shared("gnssatt.attitude.dynamics.propagate"),
    "fold_symmetric": _shared("gnssatt.attitude.dynamics.fold_symmetric"),
    "noise_cost_threshold": _shared("gnssatt.attitude.dynamics.noise_cost_threshold"),
    "fit_rotation": _other("fit_rotation"),
}

# Parameters that are objects of the library (receivers, rotations, generators, ...) rather than numbers.
OBJECTS = {
    "receiver",
    "constellation",
    "gnss",
    "attitude",
    "rng",
    "geometry",
    "orbits",
    "phases",
    "rotation",
    "measurements",
    "data",
    "model",
    "trajectory",
    "blockage",
}
# Parameters that take text.
TEXT = {"frame", "plane", "band", "prefix", "coupling", "prefixes", "line1", "line2", "noise", "systems"}
# Parameters that take integers (counts, indices, channels).
INTEGERS = {
    "max_degree",
    "max_iter",
    "n",
    "n_sat",
    "n_planes",
    "phasing",
    "ambiguity_max",
    "max_satellites",
    "min_satellites",
    "n_epochs",
    "max_restarts",
    "min_restarts",
    "popsize",
    "patience",
    "maxiter",
    "seed",
    "n_antennas",
    "frequencies",
}
# Containers of integers or mixed records, covered by the specific cases below.
SKIP = {
    "folder",
    "legs",
    "ids",
    "slots",
    "frequencies_hz",
    "glonass_channels",
    "extra_slots_deg",
    "outages",
    "mask",
    "index",
    "which",
    "k",
    "times",
    "system",
    "visible",
    "gravity_gradient",
    "use_doppler",
    "atmosphere",
    "mutation",
    "satellites_eci_m",
    "receiver_eci_m",
    "lunisolar_m_s2",
    "slips",
    "new_arcs_after",
    "epoch",
    "track",
    "satellite",
    "ambiguity",
}


def _bad_values(arg: Arg, name: str, value: Any) -> list[tuple[str, Any]]:
    """The generic bad values of each category for one parameter (its kind from its name and valid value;
    ``arg``: None valid (``optional``), NaN valid (``nonfinite_ok``), complex valid (``complex_ok``))."""
    kinds: list[tuple[str, Any]] = [] if arg.optional else [("none", None)]
    if name in OBJECTS and not isinstance(value, np.ndarray):
        return [*kinds, ("text", "abc"), ("number", 3.0)]
    if name in TEXT:
        return [*kinds, ("number", 3.0), ("bytes", b"L1")]
    if name in INTEGERS:
        return [*kinds, ("float", 2.5), ("bool", True), ("text", "3"), ("complex", 3 + 0j)]
    kinds += [("text", "abc"), ("object", np.array([object()], dtype=object))]
    if np.ndim(value) == 0 and not isinstance(value, np.ndarray):
        return [*kinds, ("bool", True), ("complex", 1 + 1j), ("nan", math.nan), ("inf", math.inf)]
    arr = np.asarray(value, dtype=np.float64)
    nan = arr.copy().reshape(-1)
    if nan.size:
        nan[0] = np.nan
    inf = -nan.copy()
    if inf.size:
        inf[0] = np.inf
    if not arg.complex_ok:
        kinds.append(("complex", arr.astype(np.complex128) + 1j))
    kinds += [
        ("bool", np.ones(arr.shape, dtype=bool)),
        ("ragged", [[1.0, 2.0], [3.0]]),
    ]
    if not arg.nonfinite_ok:
        kinds += [("nan", nan.reshape(arr.shape)), ("inf", inf.reshape(arr.shape))]
    return kinds


def _generic_cases() -> list[Any]:
    cases = []
    for fname, (_, spec) in FUNCTIONS.items():
        for param, value in _valid(fname).items():
            if param in SKIP or value is None:
                continue
            for category, bad in _bad_values(spec.arg(param), param, value):
                cases.append(pytest.param(fname, param, category, bad, id=f"{fname}-{param}-{category}"))
    return cases


@cache
def _valid(fname: str) -> dict[str, Any]:
    """The valid keyword arguments of ``fname``, built once (the overrides go into a copy)."""
    return FUNCTIONS[fname][1].build()


def _call(fname: str, **overrides: Any) -> Any:
    return FUNCTIONS[fname][0](**{**_valid(fname), **overrides})


@pytest.mark.slow
@pytest.mark.parametrize("fname", list(FUNCTIONS))
def test_valid_arguments_are_accepted(fname: str) -> None:
    # the baseline of every case below; a failing baseline would make the bad-input cases meaningless
    if fname == "igrf_field_ecef":
        pytest.importorskip("ppigrf")
    _call(fname)


@pytest.mark.parametrize(("fname", "param", "category", "bad"), _generic_cases())
def test_bad_kind_or_value_names_the_parameter(fname: str, param: str, category: str, bad: Any) -> None:
    # a value of the wrong kind is an InvalidTypeError (also a TypeError); NaN and inf an InvalidInputError
    error = InvalidInputError if category in ("nan", "inf") else InvalidTypeError
    with pytest.raises(error) as info:
        _call(fname, **{param: bad})
    assert param in str(info.value)


# (function, parameter, bad value, expected class): wrong shapes, out-of-range values, absurd sizes.
SPECIFIC = [
    # wrong shapes
    ("dipole_field_ecef", "position_ecef_m", np.zeros((2, 2)), InvalidInputError),
    ("dipole_field_eci", "position_eci_m", np.full((2, 4), 7e6), InvalidInputError),
    ("magnetic.geodetic_to_ecef", "height_m", np.zeros(3), InvalidInputError),
    ("dipole_orbital", "radius", np.full(3, 7e6), InvalidInputError),
    ("eci_to_ecef", "v_eci", np.zeros(2), InvalidInputError),
    ("eci_to_ecef", "r_eci", np.zeros((3, 2)), InvalidInputError),
    ("ecef_to_eci", "r_ecef", np.full((2, 3), 7e6), InvalidInputError),
    ("ecef_to_geodetic", "r_ecef", np.zeros((2, 2)), InvalidInputError),
    ("Geometry.from_los", "los", np.zeros((2, 2)), InvalidInputError),
    ("Geometry", "range_m", np.zeros(2), InvalidInputError),
    ("Geometry", "ids", ("G01", "G02"), InvalidInputError),
    ("los_body", "los", np.zeros((2, 2)), InvalidInputError),
    ("los_body", "attitude", Rotation.identity(2), InvalidInputError),
    ("elevation_azimuth", "los_enu", np.zeros((1, 2)), InvalidInputError),
    ("line_of_sight", "t", np.zeros((2, 2)), InvalidInputError),
    ("solve_kepler", "eccentricity", np.zeros(3), InvalidInputError),
    ("KeplerOrbits", "raan_rad", np.zeros((2, 2)), InvalidInputError),
    ("elevation_mask", "los_ref", np.zeros((2, 4)), InvalidInputError),
    ("antenna_cone_mask", "boresight_body", np.zeros(2) + 1, InvalidInputError),
    ("earth_occlusion_mask", "satellites_m", np.zeros((2, 2)), InvalidInputError),
    ("phase_diffs", "phases", np.zeros((1, 4)), InvalidInputError),
    ("simulate_array", "antennas_body_m", np.zeros((3, 2)), InvalidInputError),
    ("simulate_array", "wavelengths_m", np.full(2, 0.19), InvalidInputError),
    ("simulate_array", "clock_bias_s", np.zeros(5), InvalidInputError),
    ("simulate_spaceborne", "receiver_velocity_m_s", np.zeros((2, 3)), InvalidInputError),
    ("simulate_spaceborne", "times_s", np.zeros(3), InvalidInputError),
    ("gyro_output", "attitude", Rotation.identity(), InvalidInputError),
    ("gyro_output", "drift_rad_s", np.zeros(2), InvalidInputError),
    ("phase_observations", "baselines_m", np.zeros((2, 2)), InvalidInputError),
    ("phase_observations", "attitude", Rotation.identity(2), InvalidInputError),
    ("attitude_fixes", "attitude", Rotation.identity(), InvalidInputError),
    ("right_jacobian", "a", np.zeros(2), InvalidInputError),
    ("orbital_hold_motion", "period_s", np.ones(2), InvalidInputError),
    ("glonass_propagate", "velocity_m_s", np.zeros(4), InvalidInputError),
    ("GlonassModel", "lunisolar_m_s2", (0.0, 0.0), InvalidInputError),
    ("teme_to_ecef", "jd_ut1", np.full(3, 2460000.5), InvalidInputError),
    ("noisy_orbit", "x0", np.zeros(5), InvalidInputError),
    ("orbit_filter", "p0", np.eye(5), InvalidInputError),
    ("OrbitFilterResult.nees", "truth", np.zeros((2, 6)), InvalidInputError),
    ("propagate_axes", "params", np.zeros(5), InvalidInputError),
    ("axis_cost", "measured_axes", np.zeros((2, 3)), InvalidInputError),
    ("fold_symmetric", "reference", np.zeros(5), InvalidInputError),
    ("TumbleModel", "inertia_kg_m2", (1.0, 1.0), InvalidInputError),
    ("fit_rotation", "measured_axes", np.ones((4, 3)), InvalidInputError),
    # out of range
    ("dipole_orbital", "radius", 0.0, InvalidInputError),
    ("dipole_orbital", "inclination", 4.0, InvalidInputError),
    ("dipole_orbital", "strength", -1.0, InvalidInputError),
    ("dipole_coefficients", "decimal_year", 1999.0, InvalidInputError),
    ("magnetic.geodetic_to_ecef", "lat_deg", 91.0, InvalidInputError),
    ("magnetic.geodetic_to_ecef", "height_m", -6.3e6, InvalidInputError),
    ("dcm_ned_from_ecef", "lat_deg", -90.5, InvalidInputError),
    ("dipole_field_ecef", "position_ecef_m", np.zeros(3), InvalidInputError),
    ("dipole_field_ecef", "position_ecef_m", np.array([1e300, 0, 0]), InvalidInputError),
    ("dipole_field_ned", "lat_deg", 100.0, InvalidInputError),
    ("igrf_field_ecef", "max_degree", 14, InvalidInputError),
    ("igrf_field_ecef", "position_ecef_m", np.zeros(3), InvalidInputError),
    ("sim.geodetic_to_ecef", "lat_deg", 90.5, InvalidInputError),
    ("sim.geodetic_to_ecef", "height_m", -7e6, InvalidInputError),
    ("ecef_to_geodetic", "r_ecef", np.zeros(3), InvalidInputError),
    ("dcm_ecef_from_enu", "lat_deg", 95.0, InvalidInputError),
    ("Geometry.from_los", "los", np.zeros((2, 3)), InvalidInputError),
    ("Geometry.from_los", "range_m", -1.0, InvalidInputError),
    ("Geometry.select", "mask", np.array([99]), InvalidInputError),
    ("elevation_azimuth", "los_enu", np.zeros((1, 3)), InvalidInputError),
    ("solve_kepler", "eccentricity", 1.0, InvalidInputError),
    ("solve_kepler", "tol", 0.0, InvalidInputError),
    ("solve_kepler", "max_iter", 0, InvalidInputError),
    ("KeplerOrbits", "semi_major_axis_m", np.array([-1.0]), InvalidInputError),
    ("KeplerOrbits", "semi_major_axis_m", np.array([1e300]), InvalidInputError),
    ("KeplerOrbits", "gm_m3_s2", 0.0, InvalidInputError),
    ("KeplerOrbits.subset", "index", np.array([100]), InvalidInputError),
    ("KeplerOrbits.subset", "index", np.array([0.5]), InvalidTypeError),
    ("elevation_mask", "mask_deg", 91.0, InvalidInputError),
    ("elevation_mask", "los_ref", np.zeros((1, 3)), InvalidInputError),
    ("antenna_cone_mask", "half_angle_deg", 0.0, InvalidInputError),
    ("antenna_cone_mask", "half_angle_deg", 181.0, InvalidInputError),
    ("antenna_cone_mask", "boresight_body", np.zeros(3), InvalidInputError),
    ("earth_occlusion_mask", "atmosphere_m", -1.0, InvalidInputError),
    ("earth_occlusion_mask", "radius_m", 0.0, InvalidInputError),
    ("equilateral_triangle", "side_m", 0.0, InvalidInputError),
    ("equilateral_triangle", "plane", "xx", InvalidInputError),
    ("random_attitude", "n", 0, InvalidInputError),
    ("random_los", "n_sat", 0, InvalidInputError),
    ("random_los", "min_elevation_deg", 90.0, InvalidInputError),
    ("Constellation", "frequencies_hz", {"L1": np.array([-1.0])}, InvalidInputError),
    ("Constellation", "frequencies_hz", {"L1": np.array([1j])}, InvalidTypeError),
    ("Constellation", "ids", ("G01", "G02"), InvalidInputError),
    ("Constellation", "glonass_channels", np.array([0.5]), InvalidTypeError),
    ("Constellation", "orbits", "abc", InvalidTypeError),
    ("Constellation.select", "which", np.array([99]), InvalidInputError),
    ("Constellation.select", "which", ["G99"], InvalidInputError),
    ("Constellation.wavelengths_m", "band", "L5", InvalidInputError),
    ("gps_nominal", "extra_slots_deg", [(1.0, None)], InvalidTypeError),
    ("gps_nominal", "extra_slots_deg", [(1.0, math.nan)], InvalidInputError),
    ("gps_nominal", "extra_slots_deg", [(1.0, 2.0, 3.0)], InvalidInputError),
    ("walker", "n_planes", 5, InvalidInputError),
    ("walker", "inclination_deg", 181.0, InvalidInputError),
    ("walker", "frequency_hz", 0.0, InvalidInputError),
    ("walker", "prefix", "GPS", InvalidInputError),
    ("glonass_frequency_hz", "k", np.array([7]), InvalidInputError),
    ("glonass_frequency_hz", "k", np.array([0.5]), InvalidTypeError),
    ("glonass_frequency_hz", "k", np.array([1j]), InvalidTypeError),
    ("glonass_frequency_hz", "k", np.array([True]), InvalidTypeError),
    ("glonass_frequency_hz", "band", "L5", InvalidInputError),
    ("correlator_amplitude", "cn0_dbhz", 1e3, InvalidInputError),
    ("correlator_amplitude", "integration_time_s", 0.0, InvalidInputError),
    ("simulate_array", "wavelengths_m", np.zeros(len(GPS)), InvalidInputError),
    ("simulate_array", "code_sigma_m", -1.0, InvalidInputError),
    ("simulate_array", "ambiguity_max", -1, InvalidInputError),
    ("simulate_array", "ambiguities", np.zeros((3, len(GPS))), InvalidTypeError),
    ("simulate_array", "ambiguities", np.full((3, len(GPS)), 2**40), InvalidInputError),
    ("GroundReceiver", "lat_deg", 91.0, InvalidInputError),
    ("GroundReceiver", "height_m", -7e6, InvalidInputError),
    ("OrbitalReceiver", "altitude_m", -7e6, InvalidInputError),
    ("OrbitalReceiver", "altitude_m", 1e300, InvalidInputError),
    ("OrbitalReceiver", "gm_m3_s2", 0.0, InvalidInputError),
    ("simulate_spaceborne", "half_angle_deg", 0.0, InvalidInputError),
    ("simulate_spaceborne", "code_sigma_m", 0.0, InvalidInputError),
    ("simulate_spaceborne", "q_bias_s2_s", -1.0, InvalidInputError),
    ("simulate_spaceborne", "outages", [(0.0, 1.0, -1)], InvalidInputError),
    ("simulate_spaceborne", "outages", [(0.0, None, 1)], InvalidTypeError),
    ("simulate_spaceborne", "outages", [(0.0, 1.0)], InvalidInputError),
    ("simulate_spaceborne", "receiver_position_m", np.zeros((3, 3)), InvalidInputError),
    ("SpaceborneMeasurements", "times_s", np.zeros(3), InvalidInputError),
    ("SpaceborneMeasurements", "visible", np.ones((3, 2), dtype=bool), InvalidInputError),
    ("SpaceborneMeasurements", "system", np.full(len(GPS), 7, dtype=np.uint32), InvalidInputError),
    ("SpaceborneMeasurements", "code_sigma_m", -1.0, InvalidInputError),
    ("SpaceborneMeasurements", "pseudorange_m", np.where(MEAS.visible, np.nan, 0.0), InvalidInputError),
    ("SpaceborneMeasurements", "doppler_hz", np.where(MEAS.visible, np.inf, 0.0), InvalidInputError),
    ("SpaceborneMeasurements.select_systems", "prefixes", "E", InvalidInputError),
    ("orbital_hold_motion", "period_s", np.zeros(3), InvalidInputError),
    ("gyro_output", "t", np.array([0.0, 0.0, 1.0]), InvalidInputError),
    ("gyro_output", "arw", -1.0, InvalidInputError),
    ("phase_observations", "half_angle_deg", 181.0, InvalidInputError),
    ("phase_observations", "atmosphere_m", -1.0, InvalidInputError),
    ("phase_observations", "max_satellites", -1, InvalidInputError),
    ("phase_observations", "slips", np.array([[0.0, 99.0, 1.0]]), InvalidInputError),
    ("phase_observations", "slips", np.array([[0.0, 1.0, 0.5]]), InvalidInputError),
    ("phase_observations", "slips", np.array([[0.0, 1.0j, 1.0]]), InvalidTypeError),
    ("phase_observations", "new_arcs_after", np.array([math.nan]), InvalidInputError),
    # 1e308-cycle noise overflowed the simulated phases: refused as "phase contains a non-finite value"
    ("phase_observations", "phase_sigma_cycles", 1e308, InvalidInputError),
    ("walker", "phasing", 10**400, InvalidInputError),  # 360.0 * 10**400 raised OverflowError
    ("attitude_fixes", "phase_sigma_cycles", 0.0, InvalidInputError),
    ("PhaseObservations", "epoch", PHASES.epoch + 100, InvalidInputError),
    ("PhaseObservations", "epoch", PHASES.epoch + 0.5, InvalidTypeError),
    ("PhaseObservations", "track", PHASES.track[:-1], InvalidInputError),
    ("PhaseObservations", "ambiguity", PHASES.ambiguity[:, :1], InvalidInputError),
    ("PhaseObservations", "wavelength", -PHASES.wavelength, InvalidInputError),
    ("PhaseObservations", "los", PHASES.los[:, :2], InvalidInputError),
    ("GyroOutput", "rates", np.zeros((2, 3)), InvalidInputError),
    ("AttitudeFixes", "rotation", Rotation.identity(), InvalidInputError),
    ("AttitudeFixes", "covariance", np.zeros((3, 2, 2)), InvalidInputError),
    ("attitude_fixes", "min_satellites", 0, InvalidInputError),
    ("GlonassModel", "gm_m3_s2", 0.0, InvalidInputError),
    ("GlonassModel", "lunisolar_m_s2", (0.0, 0.0, math.nan), InvalidInputError),
    ("glonass_propagate", "position_m", np.array([1e5, 0.0, 0.0]), InvalidInputError),
    ("glonass_propagate", "duration_s", -1.0, InvalidInputError),
    ("glonass_propagate", "step_s", 0.0, InvalidInputError),
    ("glonass_propagate", "model", orbit.CircularOrbit(7e6, 0.0, 0.0, 0.0), InvalidTypeError),
    ("CircularOrbit", "radius_m", 0.0, InvalidInputError),
    ("CircularOrbit", "gm_m3_s2", -1.0, InvalidInputError),
    ("gmst_rad", "jd_ut1", 1e300, InvalidInputError),
    ("tle_states", "dut1_s", 5.0, InvalidInputError),
    ("tle_states", "times", np.array([1.0]), InvalidTypeError),
    ("tle_states", "times", np.array(["NaT"], dtype="datetime64[ns]"), InvalidInputError),
    ("white_acceleration_noise", "dt_s", -1.0, InvalidInputError),
    ("white_acceleration_noise", "accel_psd_m2_s3", -1.0, InvalidInputError),
    ("noisy_orbit", "times_s", np.array([0.0, 0.0]), InvalidInputError),
    ("noisy_orbit", "step_s", 0.0, InvalidInputError),
    ("orbit_filter", "coupling", "ultra", InvalidInputError),
    ("orbit_filter", "use_doppler", 1, InvalidTypeError),
    ("orbit_filter", "step_s", -1.0, InvalidInputError),
    ("TumbleModel", "inertia_kg_m2", (1.0, 1.0, 3.0), InvalidInputError),
    ("TumbleModel", "speed_m_s", -1.0, InvalidInputError),
    ("TumbleModel", "gravity_gradient", 1, InvalidTypeError),
    ("TumbleModel.circular", "altitude_m", -7e6, InvalidInputError),
    ("propagate_axes", "t", np.array([0.0, 2.0, 1.0]), InvalidInputError),
    ("propagate_axes", "t", np.array([-1.0]), InvalidInputError),
    ("propagate_axes", "step_s", 0.0, InvalidInputError),
    ("propagate_axes", "model", "abc", InvalidTypeError),
    ("axis_cost", "measured_axes", np.zeros((3, 2)), InvalidInputError),
    ("noise_cost_threshold", "false_restart", 1.0, InvalidInputError),
    ("noise_cost_threshold", "n_epochs", 0, InvalidInputError),
    ("noise_cost_threshold", "axis_sigma_deg", 0.0, InvalidInputError),
    ("fit_rotation", "max_restarts", -1, InvalidInputError),
    ("fit_rotation", "min_restarts", 2, InvalidInputError),
    ("fit_rotation", "recombination", 1.5, InvalidInputError),
    ("fit_rotation", "mutation", (0.5, 3.0), InvalidInputError),
    ("fit_rotation", "mutation", (0.5,), InvalidInputError),
    ("fit_rotation", "mutation", 2.0, InvalidInputError),
    ("fit_rotation", "mutation", (1.0, 0.5), InvalidInputError),
    ("fit_rotation", "rng", 2**70, InvalidInputError),
    ("fit_rotation", "rng", -1, InvalidInputError),
    ("fit_rotation", "max_rate_rad_s", 0.0, InvalidInputError),
    ("fit_rotation", "restart", "again", InvalidInputError),
    ("fit_rotation", "polish", "yes", InvalidTypeError),
    ("fit_rotation", "t", np.array([0.0, 1.0]), InvalidInputError),
    # finite but extreme: refused, or reported as an overflow, instead of NaN or a numpy/scipy error
    ("right_jacobian", "a", np.full(3, 1e300), InvalidInputError),
    ("orbital_hold_motion", "amplitude_rad", np.full(3, 4.0), InvalidInputError),
    ("attitude_fixes", "baselines_m", np.full((2, 3), 1e20), InvalidInputError),
    ("attitude_fixes", "baselines_m", np.zeros((2, 3)), InvalidInputError),
    ("attitude_fixes", "phase_sigma_cycles", 1e300, InvalidInputError),
    ("attitude_fixes", "phase_sigma_cycles", 1e-300, InvalidInputError),
    ("simulate_spaceborne", "receiver_velocity_m_s", np.full((3, 3), 1e300), InvalidInputError),
    ("simulate_spaceborne", "receiver_position_m", np.full((3, 3), 1e300), InvalidInputError),
    ("noise_cost_threshold", "n_epochs", 2**63, InvalidInputError),
    ("noise_cost_threshold", "axis_sigma_deg", 1e300, InvalidInputError),
    ("white_acceleration_noise", "dt_s", 1e300, ConvergenceError),
    ("OrbitFilterResult.nees", "truth", np.full((3, 6), 1e300), ConvergenceError),
    # absurd sizes: refused before any work
    ("igrf_field_ecef", "max_degree", 10**12, InvalidInputError),
    ("solve_kepler", "max_iter", 10**12, WorkLimitError),
    ("random_attitude", "n", 10**12, WorkLimitError),
    ("random_los", "n_sat", 10**12, WorkLimitError),
    ("walker", "n_sat", 10**12, WorkLimitError),
    ("simulate_array", "ambiguity_max", 2**62, WorkLimitError),
    ("simulate_spaceborne", "outages", [(0.0, 1.0, 1)] * 20_000, WorkLimitError),
    ("glonass_propagate", "step_s", 1e-300, WorkLimitError),
    ("glonass_propagate", "duration_s", 1e300, WorkLimitError),
    ("noisy_orbit", "step_s", 1e-300, WorkLimitError),
    ("noisy_orbit", "times_s", np.arange(2_000_000.0), WorkLimitError),
    ("orbit_filter", "step_s", 1e-300, WorkLimitError),
    ("propagate_axes", "step_s", 1e-300, WorkLimitError),
    ("propagate_axes", "t", np.array([0.0, 1e300]), WorkLimitError),
    ("axis_cost", "step_s", 1e-300, WorkLimitError),
    ("propagate", "step_s", 1e-300, WorkLimitError),
    ("fit_rotation", "popsize", 10**9, WorkLimitError),
    ("fit_rotation", "maxiter", 10**12, WorkLimitError),
    ("fit_rotation", "patience", 10**12, WorkLimitError),
    ("fit_rotation", "max_restarts", 10**6, WorkLimitError),
    ("fit_rotation", "step_s", 1e-300, WorkLimitError),
]


@pytest.mark.parametrize(
    ("fname", "param", "bad", "error"),
    [pytest.param(*case, id=f"{case[0]}-{case[1]}-{i}") for i, case in enumerate(SPECIFIC)],
)
def test_shape_range_and_size_names_the_parameter(fname: str, param: str, bad: Any, error: type) -> None:
    with pytest.raises(error) as info:
        _call(fname, **{param: bad})
    assert param in str(info.value)


def test_batch_size_counts_in_the_work_limit() -> None:
    # 10^4 initial states x 10^5 one-second steps: 10^9 RK4 steps, refused before any is taken
    with pytest.raises(WorkLimitError, match="10000 initial states"):
        tumble.propagate_axes(np.zeros((10_000, 6)), [0.0, 1e5])


def test_fit_rotation_counts_its_whole_work_before_starting() -> None:
    # each generation is within the per-call limit (12 states x 1e6 steps), the fit at its cap is not
    with pytest.raises(WorkLimitError, match="maxiter"):
        _call("fit_rotation", t=np.array([0.0, 5e5, 1e6]), maxiter=100_000)


def test_fit_rotation_takes_directions_of_any_scale() -> None:
    # measured axes of norm 1e300 are the same directions (their norm overflowed to inf: all-zero axes)
    axes = np.array([[0.0, 1.0, 0.0], [0.1, 1.0, 0.0], [0.2, 1.0, 0.1]])
    small, huge = (_call("fit_rotation", measured_axes=axes * k) for k in (1.0, 1e300))
    np.testing.assert_array_equal(small.params, huge.params)


def test_every_public_function_has_cases() -> None:
    # every name in the modules' __all__ that is a function or a class with a constructor is covered
    covered = {name.split(".")[-1] for name in FUNCTIONS} | {name.split(".")[0] for name in FUNCTIONS}
    modules = [magnetic, orbit, determination, tumble, sim, scen, constants]
    missing = set()
    for module in modules:
        for name in module.__all__:
            obj = getattr(module, name)
            if callable(obj) and not isinstance(obj, type(np.float64)) and name not in covered:
                missing.add(f"{module.__name__}.{name}")
    # results (no user input of their own), aliases and re-exports of covered names
    not_inputs = {
        "gnssatt.sim.ArrayMeasurements",
        "gnssatt.orbit.PropagatedState",
        "gnssatt.orbit.determination.OrbitFilterResult",
        "gnssatt.orbit.determination.ReceiverFixes",
        "gnssatt.attitude.dynamics.RotationFit",
        "gnssatt.attitude.dynamics.TumbleTrajectory",
        "gnssatt.sim.SpaceborneMeasurements",
        "gnssatt.sim.Receiver",
        "gnssatt.sim.SimulatedPlatform",
        "gnssatt.constants",
    }
    assert missing - not_inputs == set()


# --- finite input that used to give NaN or infinity -------------------------------------------------


def test_ecef_to_geodetic_of_the_centre_is_refused_and_poles_are_finite() -> None:
    with pytest.raises(InvalidInputError, match="Earth's centre"):
        sim.ecef_to_geodetic([0.0, 0.0, 0.0])
    lat, _, h = sim.ecef_to_geodetic(np.array([[0.0, 0.0, 6.4e6], [0.0, 0.0, -6.4e6], [1e5, 0.0, 0.0]]))
    # closed forms on the axis (h = |z| - b) and in the equatorial plane (h = p - a), down to the limit
    np.testing.assert_allclose(h, [6.4e6 - constants.WGS84_B_M] * 2 + [1e5 - constants.WGS84_A_M], atol=1e-6)
    np.testing.assert_allclose(lat, [90.0, -90.0, 0.0], atol=1e-12)


@pytest.mark.parametrize("radius_m", [1.0001e5, 1e6, 6.4e6, 1e12])
def test_ecef_to_geodetic_converges_down_to_its_limit(radius_m: float) -> None:
    # the closed-form forward map takes the answer back to the position (the iteration slows near the centre)
    d = np.random.default_rng(5).normal(size=(2000, 3))
    p = radius_m * d / np.linalg.norm(d, axis=1, keepdims=True)
    lat, lon, h = sim.ecef_to_geodetic(p)
    np.testing.assert_allclose(sim.geodetic_to_ecef(lat, lon, h), p, rtol=0, atol=1e-13 * radius_m)


def test_magnetic_field_refuses_the_centre_and_nan() -> None:
    with pytest.raises(InvalidInputError, match="position_ecef_m"):
        magnetic.dipole_field_ecef([1.0, 0.0, 0.0], 2020.0)
    with pytest.raises(InvalidInputError, match="radius"):
        magnetic.dipole_orbital(0.0, 1.0, 1e-100)
    with pytest.raises(InvalidInputError, match="non-finite"):
        magnetic.dipole_field_ned(np.nan, 0.0, 0.0, 2020.0)


def test_fast_tumbling_is_refused_not_nan() -> None:
    # 1000 rad/s in 1 s steps gave NaN axes; now refused with the step that would do
    with pytest.raises(InvalidInputError, match=r"step_s <= 0\.001"):
        tumble.propagate_axes([0.0, 0.0, 0.0, 1e3, 0.0, 0.0], [0.0, 10.0])
    # the same rate with a step below the suggested one is finite and keeps unit axes
    axes = tumble.propagate_axes([0.0, 0.0, 0.0, 1e3, 0.0, 0.0], [0.0, 0.5], step_s=0.99e-3)
    np.testing.assert_allclose(np.linalg.norm(axes, axis=1), 1.0, atol=1e-9)


@pytest.mark.parametrize("rate", [0.5, 3.0, 30.0])
def test_tumbling_at_the_rotation_bound_stays_finite(rate: float) -> None:
    # |omega| h at the documented bound over many steps: finite unit axes (or a ConvergenceError, never NaN)
    # the bound counts the body rate plus twice the orbital frame's (as the core does)
    # (just inside it: at the bound itself rounding decides)
    h = (
        0.999
        * tumble.MAX_ROTATION_PER_STEP_RAD
        / (rate + 2.0 * tumble.TumbleModel.circular().orbital_rate_rad_s)
    )
    params = np.array([[0.3, 1.0, 0.2, rate / math.sqrt(3)] + [rate / math.sqrt(3)] * 2])
    try:
        axes = tumble.propagate_axes(params, np.linspace(0.0, 200 * h, 5), step_s=h)
    except ConvergenceError as exc:  # the gravity-gradient torque spun the body past the bound: said so
        assert "diverged" in str(exc)
    else:
        assert np.all(np.isfinite(axes))


@pytest.mark.parametrize("velocity", [(0.0, 0.0, 0.0), (1e3, 0.0, 0.0)])
def test_spaceborne_receiver_without_horizontal_velocity_is_simulated(velocity: tuple[float, ...]) -> None:
    # at rest or moving radially: the antenna azimuth is arbitrary, the visibility is not (was a scipy error)
    r = np.tile([7.0e6, 0.0, 0.0], (3, 1))
    meas = sim.simulate_spaceborne(r, np.tile(velocity, (3, 1)), T3, GPS, np.random.default_rng(4))
    assert meas.visible.any()
    assert np.all(np.isfinite(meas.pseudorange_m[meas.visible]))


def test_glonass_propagate_with_absurd_velocity_raises_not_nan() -> None:
    # refused before integrating (not a bound orbit), or stopped when a state stops being finite
    with pytest.raises((ConvergenceError, InvalidInputError), match=r"not finite|velocity_m_s"):
        orbit.glonass_propagate([2.5e7, 0.0, 0.0], [0.0, 3e200, 1e3], 100.0, step_s=10.0)


def test_gmst_of_huge_julian_dates_is_refused_not_nan() -> None:
    with pytest.raises(InvalidInputError, match="jd_ut1"):
        orbit.gmst_rad(1e300)


def test_simulated_measurements_overflow_raises_not_inf() -> None:
    with pytest.raises(ConvergenceError, match="pseudorange"):
        _call("simulate_array", clock_bias_s=1e301)
    with pytest.raises(ConvergenceError, match="gyro output"):
        _call("gyro_output", arw=1e300, t=np.array([0.0, 1e-300, 1.0]))


def test_white_acceleration_noise_overflow_raises_not_inf() -> None:
    with pytest.raises(ConvergenceError, match="process noise"):
        determination.white_acceleration_noise(1e300, 1e10)


def test_attitude_fixes_with_one_baseline_and_one_satellite_is_degenerate() -> None:
    with pytest.raises(DegenerateGeometryError, match="min_satellites"):
        scen.attitude_fixes(PHASES, ATT3, BASELINES[:1], RNG, phase_sigma_cycles=0.01, min_satellites=1)


def test_receiver_fix_skips_collinear_satellites_instead_of_nan() -> None:
    # every satellite on one line through the receiver: no fix (was a NaN/inf solution or LinAlgError)
    pos = MEAS.sat_position_m.copy()
    pos[:] = np.linspace(1.0, 2.0, pos.shape[1])[None, :, None] * np.array([2.0e7, 0.0, 0.0])
    flat = SpaceborneMeasurements(**{**MEAS.__dict__, "sat_position_m": pos})
    fixes = determination.receiver_fix(flat)
    assert np.all(np.isfinite(fixes.position_m[fixes.valid]))
