"""Attitude mode with ``continuity``: integers of the three-antenna array held across epochs on a simulated
rotating platform, GPS L1 (truth known). Held epochs' attitude agrees with the truth, nothing wrong is
fixed or held, and a slip on one antenna's arc (loss-of-lock flagged) restarts only that arc: the epoch
of the slip is still held (the other arcs' integers kept, the slipped one fixed on them). The wrong
integer injected into a held set is `rtk/constrained_tests.rs`."""

from __future__ import annotations

import warnings
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from gnssatt import sim
from gnssatt.gnss.attitude import AttitudeSeries, attitude_from_rinex
from gnssatt.sim.rinex_scenario import simulate_gnss_rinex

ANT = sim.equilateral_triangle(1.0, plane="xz")
N_EP = 30
SLIP_EPOCH = 15
#: A wrong integer moves a 1 m baseline by centimetres to decimetres; right fixes of 2 mm phase noise are
#: within about 1 cm (tests/test_rinex_rotating_platform.py).
WRONG_M = 0.04
#: Largest angle error of a fixed or held epoch in units of the engine's one-sigma.
WRONG_SIGMAS = 5.0


def _euler() -> np.ndarray:
    k = np.arange(N_EP)
    return np.stack([-40.0 + 3.0 * k, 5.0 * np.sin(k / 3.0), 3.0 * np.cos(k / 4.0)], axis=1)


def _simulate(folder: Path, slips: list[tuple[int, int, str, int]]) -> Any:
    return simulate_gnss_rinex(
        folder, ANT, _euler(), systems="G", frequencies=1, n_epochs=N_EP, rng=21, atmosphere=False,
        slips=slips,
    )  # fmt: skip


def _solve(s: Any, continuity: bool) -> AttitudeSeries:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return attitude_from_rinex(
            list(s.obs_paths), s.nav_path, ANT[1:] - ANT[0], method="lambda", continuity=continuity
        )


@pytest.fixture(scope="module")
def slipped(tmp_path_factory: pytest.TempPathFactory) -> tuple[Any, str, AttitudeSeries, AttitudeSeries]:
    clean = _simulate(tmp_path_factory.mktemp("clean"), [])
    # the lowest satellite at the slip epoch: not a reference (the engine takes the highest)
    sat = clean.sats[int(np.argmin(clean.elevation_deg[SLIP_EPOCH]))]
    s = _simulate(tmp_path_factory.mktemp("slip"), [(SLIP_EPOCH, 2, sat, 0)])
    return s, sat, _solve(s, False), _solve(s, True)


def _check_against_truth(series: AttitudeSeries, s: Any) -> None:
    solid = series.fix_state != "float"
    err = np.linalg.norm(series.baselines_enu_m - s.baselines_enu_m, axis=2).max(axis=1)
    assert np.all(err[solid] < WRONG_M), err[solid].max()
    truth = np.stack([(-s.euler_gost_deg[:, 0]) % 360.0, s.euler_gost_deg[:, 1], s.euler_gost_deg[:, 2]], 1)
    angle = (series.angles_deg - truth + 180.0) % 360.0 - 180.0
    normalised = np.abs(angle[solid]) / series.angle_sigmas_deg[solid]
    assert normalised.max() < WRONG_SIGMAS, normalised.max()


def test_held_epochs_agree_with_the_truth(slipped: tuple[Any, str, AttitudeSeries, AttitudeSeries]) -> None:
    s, _, single, held = slipped
    _check_against_truth(single, s)
    _check_against_truth(held, s)
    states = {k: int(np.sum(held.fix_state == k)) for k in ("fixed", "held", "float")}
    # once fixed, the integers are held to the end (no slip that loses the whole set)
    first = int(np.argmax(held.fix_state != "float"))
    assert np.all(held.fix_state[first + 1 :] == "held"), held.fix_state
    assert states["fixed"] + states["held"] >= int(np.sum(single.fix_state == "fixed")), states
    assert np.all(held.fixed == (held.fix_state != "float"))


def test_a_slip_on_one_antenna_restarts_only_its_arc(
    slipped: tuple[Any, str, AttitudeSeries, AttitudeSeries],
) -> None:
    s, sat, _, held = slipped
    assert s.slips and s.slips[0][:3] == (SLIP_EPOCH, 2, sat)
    assert held.fix_state[SLIP_EPOCH - 1] != "float"
    # held, not fixed afresh: the other arcs' integers (both rovers) were kept through the slip
    assert held.fix_state[SLIP_EPOCH] == "held"
    assert not any("held integers disagreed" in w for w in held.warnings)


def test_the_filtered_array_fixes_at_least_the_single_epochs_and_nothing_wrong(
    slipped: tuple[Any, str, AttitudeSeries, AttitudeSeries],
) -> None:
    # attitude mode with --filter: each rover's filter (its length the body baseline's), the filtered floats
    # fixed together under the body baselines; an epoch the filters leave float is fixed on its own, so
    # the filtered array fixes every epoch the single epochs fix, and nothing it fixes is off the truth
    s, _, single, _ = slipped
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        filtered = attitude_from_rinex(
            list(s.obs_paths), s.nav_path, ANT[1:] - ANT[0], method="lambda", filter="kinematic"
        )
    _check_against_truth(filtered, s)
    assert np.all(filtered.fixed == (filtered.fix_state != "float"))
    assert np.all(filtered.fixed[single.fixed.astype(bool)]), (filtered.fix_state, single.fix_state)
