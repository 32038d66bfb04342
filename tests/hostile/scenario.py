"""Small valid objects shared by the inventory's examples: one GPS constellation, one geometry, simulated
phases, RINEX files written by the simulator. Everything is built once per process from fixed seeds, so a
worker process rebuilds exactly what its parent enumerated."""

from __future__ import annotations

import atexit
import functools
import shutil
import tempfile
from pathlib import Path
from typing import Any

import numpy as np
from scipy.spatial.transform import Rotation

from gnssatt import orbit, rinex, sim
from gnssatt.attitude import dynamics as tumble
from gnssatt.sim import attitude_scenario as sc
from gnssatt.sim import rinex_scenario

SEED = 20261202
BASELINES = sim.equilateral_triangle(1.0)[1:]
GROUND = sim.GroundReceiver(lat_deg=50.0, lon_deg=36.2, height_m=150.0)
ORBITAL = sim.OrbitalReceiver(altitude_m=700e3, inclination_deg=51.6)
LEO = orbit.CircularOrbit(6_878_137.0, np.radians(97.4), 0.3, 0.0)
TUMBLE_MODEL = tumble.TumbleModel.circular(500e3)
TUMBLE_TRUTH = np.array([0.7, 1.1, 4.0, 0.03, -0.026, 0.028])
TLE = (
    "1 25544U 98067A   08264.51782528 -.00002182  00000-0 -11606-4 0  2927",
    "2 25544  51.6416 247.4627 0006703 130.5360 325.0288 15.72125391563537",
)


def rng() -> np.random.Generator:
    return np.random.default_rng(SEED)


@functools.cache
def gps() -> sim.Constellation:
    return sim.gps_nominal()


@functools.cache
def geometry() -> sim.Geometry:
    """Ground receiver, the 8 highest GPS satellites, 3 epochs 1 s apart."""
    t = np.arange(3.0)
    el = sim.line_of_sight(GROUND, gps(), t).los[0, :, 2]
    ids = [gps().ids[i] for i in np.argsort(-el)[:8]]
    return sim.line_of_sight(GROUND, gps().select(ids), t)


@functools.cache
def attitude_problem() -> dict[str, Any]:
    """One epoch: 8 lines of sight (ENU), 2 baselines, exact range differences and phases."""
    geo = geometry()
    los = geo.los[0]
    rot = Rotation.from_euler("ZYX", [30.0, 5.0, -3.0], degrees=True)
    b_ref = rot.apply(BASELINES)
    wavelength = float(299792458.0 / 1575.42e6)
    range_diffs = b_ref @ los.T  # (n_base, n_sat)
    phase = 2.0 * np.pi * range_diffs / wavelength
    return {"los": los, "rotation": rot, "range_diffs": range_diffs, "phase": phase, "wavelength": wavelength}


@functools.cache
def ambiguity_problem() -> dict[str, Any]:
    """A 4-dimensional float ambiguity vector and a correlated covariance (cycles^2)."""
    r = rng()
    a = r.normal(size=(4, 4))
    q = 0.01 * (a @ a.T + 4 * np.eye(4))
    return {"float": np.array([3.1, -1.9, 0.2, 7.05]), "cov": q}


@functools.cache
def phases() -> sc.PhaseObservations:
    t = np.arange(0.0, 2.1, 1.0)
    att, _ = sc.orbital_hold_motion(ORBITAL, t, np.radians([2.0, 1.0, 3.0]), [200.0, 250.0, 300.0], [0, 1, 2])
    return sc.phase_observations(ORBITAL, gps(), t, att, BASELINES, rng(), phase_sigma_cycles=0.01)


@functools.cache
def gyro() -> dict[str, Any]:
    t = np.arange(0.0, 2.05, 0.1)
    att, _ = sc.orbital_hold_motion(ORBITAL, t, np.radians([2.0, 1.0, 3.0]), [200.0, 250.0, 300.0], [0, 1, 2])
    g = sc.gyro_output(t, att, rng(), drift_rad_s=np.zeros(3), arw=1e-5)
    return {"t": t, "rates": g.rates, "att": att}


@functools.cache
def spaceborne() -> dict[str, Any]:
    t = np.arange(4) * 10.0
    r, v = LEO.state_ecef(t)
    x0 = np.concatenate([r[0], v[0]])
    meas = sim.simulate_spaceborne(r, v, t, gps(), rng())
    return {"t": t, "r": r, "v": v, "x0": x0, "meas": meas}


@functools.cache
def folder() -> Path:
    path = Path(tempfile.mkdtemp(prefix="gnssatt-hostile-"))
    atexit.register(shutil.rmtree, path, True)
    return path


@functools.cache
def rinex_array() -> rinex_scenario.SimulatedRinex:
    """Two antennas, 8 epochs, 6 satellites: RINEX 3 observation files and a GPS navigation file."""
    out = folder() / "array"
    out.mkdir()
    ant = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]])
    return rinex_scenario.simulate_rinex_array(out, ant, np.zeros((8, 3)), n_sats=6, rng=SEED)


@functools.cache
def rinex_read() -> dict[str, Any]:
    s = rinex_array()
    obs = [rinex.read_obs(p) for p in s.obs_paths]
    nav = rinex.read_nav(s.nav_path)
    return {"obs": obs, "nav": nav}
