"""Scenario simulator of gnssatt: constellations, receivers, geometry, visibility and array measurements.

Conventions (fixed for the whole package)
-----------------------------------------
- SI units and radians inside; public arguments in degrees carry ``_deg`` in their name.
- Frames: ECI (J2000-like, no precession/nutation); ECEF = ECI rotated about z by
  ``theta(t) = theta0 + OMEGA_E t`` (``OMEGA_E = 7.2921151467e-5 rad/s``, ``theta0`` default 0); ENU (East,
  North, Up) at a geodetic WGS-84 point; the orbital frame of a circular orbit: x along-track (velocity),
  y orbit normal (``r x v``), z radial (zenith). Matrices ``dcm_<to>_from_<from>`` map <from> coordinates to
  <to> coordinates.
- Attitude: a scipy ``Rotation`` body -> reference frame (ENU on the ground, orbital frame in orbit).
- ``t``: seconds from the scenario epoch; scalar ``t`` -> unbatched arrays, ``t`` of shape (n_t,) -> a
  leading epoch axis everywhere.
- Carrier phase and Doppler signs as in RINEX (phase grows with range; Doppler positive when approaching);
  measurement model in :mod:`gnssatt.sim.measurements`.
- Randomness only through the ``rng`` argument (int, ``numpy.random.Generator`` or None, as scipy's
  ``rng``: ``numpy.random.default_rng(rng)``; ``docs/conventions.md``, "Randomness").

Typical use::

    from scipy.spatial.transform import Rotation
    import numpy as np
    from gnssatt import sim

    gps = sim.gps_nominal()
    rx = sim.GroundReceiver(lat_deg=50.0, lon_deg=36.2, height_m=150.0)
    geom = sim.line_of_sight(rx, gps, t=0.0)
    geom = geom.select(sim.elevation_mask(geom.los, 10.0))
    meas = sim.simulate_array(geom, Rotation.identity(), sim.equilateral_triangle(0.71),
                              gps.select(list(geom.ids)).wavelengths_m(), np.random.default_rng(1),
                              phase_sigma_rad=0.1)
    dphi = meas.phase_diffs()  # (2, n_visible), rad

Moving platforms written as RINEX with their truth (:mod:`gnssatt.sim.platforms`)::

    run = sim.car("folder", n_antennas=2, duration_s=60.0, noise="gps_l1_ublox", rng=1)
    run.obs_paths, run.base_path, run.nav_path, run.heading_deg
"""

from gnssatt.frames import (
    dcm_ecef_from_eci,
    dcm_ecef_from_enu,
    dcm_eci_from_ecef,
    earth_rotation_angle,
    ecef_to_eci,
    ecef_to_geodetic,
    eci_to_ecef,
    geodetic_to_ecef,
)
from gnssatt.observations import SpaceborneMeasurements
from gnssatt.orbit.constellation import (
    GLONASS_SLOT_CHANNELS,
    GPS_BASELINE_SLOTS,
    GPS_SLOT_EPOCH_GHA_RAD,
    Constellation,
    glonass_nominal,
    gps_nominal,
    walker,
)
from gnssatt.orbit.kepler import KeplerOrbits, solve_kepler
from gnssatt.orbit.line_of_sight import Geometry, elevation_azimuth, line_of_sight, los_body
from gnssatt.orbit.masks import antenna_cone_mask, earth_occlusion_mask, elevation_mask
from gnssatt.orbit.receivers import GroundReceiver, OrbitalReceiver, Receiver
from gnssatt.sim.arrays import equilateral_triangle, random_attitude, random_los
from gnssatt.sim.measurements import (
    ArrayMeasurements,
    correlator_amplitude,
    phase_diffs,
    simulate_array,
    wrap_rad,
)
from gnssatt.sim.platform_presets import aircraft, car, ship
from gnssatt.sim.platforms import (
    NOISE_PROFILES,
    Blockage,
    Leg,
    NoiseProfile,
    SimulatedPlatform,
    Trajectory,
    simulate_platform,
)
from gnssatt.sim.spaceborne import simulate_spaceborne

__all__ = [
    "GLONASS_SLOT_CHANNELS",
    "GPS_BASELINE_SLOTS",
    "GPS_SLOT_EPOCH_GHA_RAD",
    "NOISE_PROFILES",
    "ArrayMeasurements",
    "Blockage",
    "Constellation",
    "Geometry",
    "GroundReceiver",
    "KeplerOrbits",
    "Leg",
    "NoiseProfile",
    "OrbitalReceiver",
    "Receiver",
    "SimulatedPlatform",
    "SpaceborneMeasurements",
    "Trajectory",
    "aircraft",
    "antenna_cone_mask",
    "car",
    "correlator_amplitude",
    "dcm_ecef_from_eci",
    "dcm_ecef_from_enu",
    "dcm_eci_from_ecef",
    "earth_occlusion_mask",
    "earth_rotation_angle",
    "ecef_to_eci",
    "ecef_to_geodetic",
    "eci_to_ecef",
    "elevation_azimuth",
    "elevation_mask",
    "equilateral_triangle",
    "geodetic_to_ecef",
    "glonass_nominal",
    "gps_nominal",
    "line_of_sight",
    "los_body",
    "phase_diffs",
    "random_attitude",
    "random_los",
    "ship",
    "simulate_array",
    "simulate_platform",
    "simulate_spaceborne",
    "solve_kepler",
    "walker",
    "wrap_rad",
]
