"""The Bunyaeva et al. experiment's scenario: what it returns is what its docstring and annotation say (mypy
found the annotation naming three arrays where the first item is the geometry)."""

from __future__ import annotations

import numpy as np

from gnssatt import sim
from gnssatt.experiments import ml_grid

# GPS L1: c / 1575.42 MHz (IS-GPS-200).
L1_WAVELENGTH_M = 299_792_458.0 / 1575.42e6


def test_scenario_returns_the_geometry_of_the_eight_highest_satellites() -> None:
    geom, lam, truth = ml_grid.scenario(np.random.default_rng(7))
    assert isinstance(geom, sim.Geometry)
    assert geom.frame == "enu"
    assert geom.los.shape == (ml_grid.N_SATELLITES, 3)
    np.testing.assert_allclose(np.linalg.norm(geom.los, axis=1), 1.0, rtol=1e-12)
    np.testing.assert_allclose(lam, np.full(ml_grid.N_SATELLITES, L1_WAVELENGTH_M), rtol=1e-12)
    assert truth.shape == (3,)
    assert -180.0 <= truth[0] <= 180.0 and np.all(np.abs(truth[1:]) <= 20.0)
    # The whole sky at the same epoch, elevations from the ENU up component: the chosen ones are the highest
    # eight, all above the mask.
    every = sim.line_of_sight(sim.GroundReceiver(**ml_grid.RECEIVER), sim.gps_nominal(), t=float(geom.t))
    elevation_deg = np.degrees(np.arcsin(every.los[:, 2]))
    highest = {every.ids[k] for k in np.argsort(elevation_deg)[::-1][: ml_grid.N_SATELLITES]}
    assert set(geom.ids) == highest
    assert np.all(np.degrees(np.arcsin(geom.los[:, 2])) > ml_grid.MASK_DEG)
