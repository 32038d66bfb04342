"""`AttitudeSeries.combined_baseline`: the batch least-squares baseline of a static session's fixed epochs
against a batch solution computed here by stacking every epoch's whitened equations (numpy's lstsq), and
against the simulator's truth within its covariance; refused without a fixed epoch."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np
import pytest

from gnssatt.errors import InvalidInputError
from gnssatt.gnss.attitude import AttitudeSeries, attitude_from_rinex
from gnssatt.sim.rinex_scenario import SimulatedRinex, simulate_rinex_array

ANT = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]])
#: 0.999 quantile of the chi-square distribution with 3 degrees of freedom (scipy.stats.chi2.ppf).
CHI2_3_999 = 16.266


@pytest.fixture(scope="module")
def static_pair(tmp_path_factory: pytest.TempPathFactory) -> tuple[SimulatedRinex, AttitudeSeries]:
    s = simulate_rinex_array(
        tmp_path_factory.mktemp("pair"), ANT, np.tile([-30.0, 2.0, 0.0], (30, 1)), rng=11
    )
    series = attitude_from_rinex(list(s.obs_paths), s.nav_path, method="lambda", motion="static")
    return s, series


def _stacked_least_squares(b: np.ndarray, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Batch least squares of one baseline observed as b_k with covariance Q_k: rows C_k b = C_k b_k with
    C_k^T C_k = Q_k^-1, solved with lstsq; its covariance from the stacked design matrix."""
    rows, rhs = [], []
    for bk, qk in zip(b, q, strict=True):
        c = np.linalg.cholesky(np.linalg.inv(qk)).T
        rows.append(c)
        rhs.append(c @ bk)
    a = np.vstack(rows)
    x, *_ = np.linalg.lstsq(a, np.concatenate(rhs), rcond=None)
    return x, np.linalg.inv(a.T @ a)


def test_combined_baseline_is_the_batch_solution_and_holds_the_truth(
    static_pair: tuple[SimulatedRinex, AttitudeSeries],
) -> None:
    s, series = static_pair
    fixed = series.fixed == 1
    assert fixed.sum() == len(fixed)
    c = series.combined_baseline()
    assert c.epochs == len(fixed)
    assert series.baseline_covariances_enu_m2 is not None
    b, q = _stacked_least_squares(series.baselines_enu_m[:, 0], series.baseline_covariances_enu_m2[:, 0])
    np.testing.assert_allclose(c.baselines_enu_m[0], b, atol=1e-9)
    np.testing.assert_allclose(c.covariances_enu_m2[0], q, rtol=1e-9, atol=1e-15)
    err = c.baselines_enu_m[0] - s.baselines_enu_m[0, 0]
    assert err @ np.linalg.solve(c.covariances_enu_m2[0], err) < CHI2_3_999
    # combining 30 epochs shrinks the covariance about 30 times against one epoch's
    one = np.trace(series.baseline_covariances_enu_m2[0, 0])
    assert 15.0 < one / np.trace(c.covariances_enu_m2[0]) < 60.0
    assert "combined baseline, rover 1 (30 fixed epochs)" in c.summary()


def test_combined_baseline_refuses_a_series_without_fixed_epochs(
    static_pair: tuple[SimulatedRinex, AttitudeSeries],
) -> None:
    series = dataclasses.replace(static_pair[1], fixed=np.zeros_like(static_pair[1].fixed))
    with pytest.raises(InvalidInputError, match="combined_baseline: expected at least one fixed epoch"):
        series.combined_baseline()


def test_cli_static_prints_the_combined_baseline(
    static_pair: tuple[SimulatedRinex, AttitudeSeries], tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    from gnssatt.cli import main

    s, _ = static_pair
    obs = [a for p in s.obs_paths for a in ("--obs", str(p))]
    args = ["attitude", *obs, "--nav", str(s.nav_path), "--method", "lambda", "--motion", "static"]
    assert main([*args, "--out", str(tmp_path / "r.csv"), "--no-plot"]) == 0
    assert "combined baseline, rover 1 (30 fixed epochs): east" in capsys.readouterr().out
