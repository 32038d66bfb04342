"""Single-epoch LAMBDA of the engine (``attitude_from_rinex``) on a rotating three-antenna platform written
to RINEX 3 and read back (known truth): constrained fixes against the truth, integers held along arcs, an
undetected one-cycle slip, and the windowed ML grid. (The GEONET pair epoch by epoch:
tests/test_gnss_attitude.py and tests/test_gnss_prototype_reference.py.)"""

from __future__ import annotations

import dataclasses
from functools import cache
from pathlib import Path

import numpy as np
import pytest

from gnssatt import sim
from gnssatt.errors import InvalidInputError
from gnssatt.gnss.attitude import AttitudeSeries, attitude_from_rinex
from gnssatt.rinex import read_nav, read_obs
from gnssatt.sim.rinex_scenario import SimulatedRinex, simulate_rinex_array

SIGMA_PHASE = 0.002
N_EP = 20
ANT = sim.equilateral_triangle(1.0, plane="xz")
BODY = ANT[1:] - ANT[0]
#: Fixed single-epoch baselines of 2 mm phase noise and six GPS satellites: 3 mm RMS horizontally and 8 mm
#: up (measured; the engine's angle sigmas agree: every angle error within 1.3 sigma), so 5 sigma of the up
#: component; a wrong integer moves a 1 m baseline by a share of the 19 cm wavelength, several centimetres
#: to decimetres, and its angles by many sigma (below).
WRONG_M = 0.04
#: Largest angle error of a fixed epoch in units of the engine's one-sigma.
WRONG_SIGMAS = 5.0
#: Fewest of the 20 single epochs fixed: six GPS L1 satellites leave most epochs below the constrained
#: gate (exact ratio >= 3 against the true second best, simulated success rate >= 0.95): 6 measured with
#: the exact search, 3 with the 200-candidate lists before it (whose truncated second best refused more).
#: The bound is what would catch a gate that refuses everything; rightness is checked on every fix.
MIN_FIXED = 5


def _euler() -> np.ndarray:
    k = np.arange(N_EP)
    return np.stack([-40.0 + 3.0 * k, 5.0 * np.sin(k / 3.0), 3.0 * np.cos(k / 4.0)], axis=1)


@pytest.fixture(scope="module")
def rotating(tmp_path_factory: pytest.TempPathFactory) -> SimulatedRinex:
    folder = tmp_path_factory.mktemp("rotating")
    return simulate_rinex_array(folder, ANT, _euler(), rng=1, phase_sigma_m=SIGMA_PHASE)


@cache
def _solve(paths: tuple[Path, ...], nav: Path) -> AttitudeSeries:
    return attitude_from_rinex(
        list(paths), nav, BODY, method="lambda", motion="moving", elevation_mask_deg=5.0
    )


def _fixed_errors(series: AttitudeSeries, s: SimulatedRinex) -> np.ndarray:
    """(n_fixed, n_rovers) 3-D baseline errors of the fixed epochs, m; checks on the way that their angle
    errors are within ``WRONG_SIGMAS`` of the engine's one-sigma."""
    fixed = series.fixed == 1
    truth = np.stack(
        [(-s.euler_gost_deg[:, 0]) % 360.0, s.euler_gost_deg[:, 1], s.euler_gost_deg[:, 2]], axis=1
    )
    angle = (series.angles_deg - truth + 180.0) % 360.0 - 180.0
    normalised = np.abs(angle[fixed]) / series.angle_sigmas_deg[fixed]
    assert normalised.max() < WRONG_SIGMAS, normalised.max()
    return np.linalg.norm(series.baselines_enu_m[fixed] - s.baselines_enu_m[fixed], axis=2)


@pytest.mark.slow
def test_single_epoch_constrained_fix_matches_truth(rotating: SimulatedRinex) -> None:
    s = rotating
    sol = _solve(s.obs_paths, s.nav_path)
    assert sol.fixed.sum() >= MIN_FIXED
    err = _fixed_errors(sol, s)
    assert err.max() < WRONG_M, err.max()
    # the fitted rotation carries the body baselines onto the true ones (mm-level baselines -> sub-degree)
    assert sol.rotation_matrices is not None
    rot = sol.rotation_matrices[sol.fixed == 1]
    fitted = np.einsum("tij,aj->tai", rot, BODY)
    assert np.max(np.linalg.norm(fitted - s.baselines_enu_m[sol.fixed == 1], axis=2)) < WRONG_M


def test_attitude_mode_refuses_static_motion(rotating: SimulatedRinex) -> None:
    """One static set of integers is baseline mode's, refused here by name rather than ignored (holding
    integers along arcs, ``continuity``, is attitude mode's too: tests/test_gnss_attitude_hold.py)."""
    s = rotating
    with pytest.raises(InvalidInputError, match=r"--motion.*attitude mode fixes every epoch"):
        attitude_from_rinex(list(s.obs_paths), s.nav_path, BODY, method="lambda", motion="static")


@pytest.mark.slow
def test_undetected_slip_leaves_single_epoch_fixes_right(rotating: SimulatedRinex) -> None:
    s = rotating
    obs = [read_obs(p) for p in s.obs_paths]
    rover = obs[1]
    k = rover.sats.index(s.sats[-1])
    col = rover.codes.index("L1C")
    data = rover.data.copy()
    data[10:, k, col] += 1.0  # one cycle, no loss-of-lock flag, far below any code-jump threshold
    obs[1] = dataclasses.replace(rover, data=data)
    sol = attitude_from_rinex(
        obs, read_nav(s.nav_path), BODY, method="lambda", motion="moving", elevation_mask_deg=5.0,
    )  # fmt: skip
    assert (sol.fixed[10:] == 1).any()
    assert _fixed_errors(sol, s).max() < WRONG_M


@pytest.mark.slow
def test_attitude_lambda_and_windowed_ml_agree_with_truth(rotating: SimulatedRinex) -> None:
    s = rotating
    truth = np.stack(
        [(-s.euler_gost_deg[:, 0]) % 360.0, s.euler_gost_deg[:, 1], s.euler_gost_deg[:, 2]], axis=1
    )
    lam = attitude_from_rinex(s.obs_paths, s.nav_path, BODY, method="lambda", elevation_mask_deg=5.0)
    assert set(lam.method) == {"lambda"} and lam.fixed.sum() >= MIN_FIXED
    d = (lam.angles_deg[lam.fixed == 1] - truth[lam.fixed == 1] + 180.0) % 360.0 - 180.0
    assert np.max(np.abs(d)) < 1.5  # 5-sigma of ~ 3 mm baseline errors over 1 m
    full = attitude_from_rinex(s.obs_paths, s.nav_path, BODY, method="ml", elevation_mask_deg=5.0)
    win = attitude_from_rinex(
        s.obs_paths, s.nav_path, BODY, method="ml", window_deg=10.0, elevation_mask_deg=5.0
    )

    def err(a: np.ndarray) -> np.ndarray:
        return np.max(np.abs((a - truth + 180.0) % 360.0 - 180.0), axis=1)

    # six satellites: the whole-domain grid picks a wrong peak at some epochs; the window (the platform
    # turns 3 deg per epoch) keeps the right one, and where both are right they are the same lattice maximum
    right = err(full.angles_deg) < 1.5
    assert right[0] and np.all(err(win.angles_deg) < 1.5)
    np.testing.assert_allclose(win.angles_deg[right], full.angles_deg[right], atol=1e-6)


def test_bad_arguments(rotating: SimulatedRinex) -> None:
    s = rotating
    with pytest.raises(InvalidInputError, match="window_deg >"):
        attitude_from_rinex(s.obs_paths, s.nav_path, BODY, window_deg=-1.0)
    with pytest.raises(InvalidInputError, match="motion"):
        attitude_from_rinex(s.obs_paths, s.nav_path, BODY, motion="flying")  # type: ignore[arg-type]
    with pytest.raises(InvalidInputError, match="three or more antennas"):
        attitude_from_rinex(s.obs_paths[:2], s.nav_path, BODY[:1])
