"""Every option of ``attitude_from_rinex`` and of ``gnssatt attitude`` / ``gnssatt reproduce`` either changes
the result or is refused with the reason (issue 31, third round): a known baseline length the first epochs
contradict is refused before the session runs (counted: the engine runs once, on those epochs), the grid's
options where no grid runs, the run options of ``reproduce --list``.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest

from gnssatt import _core
from gnssatt.cli import main
from gnssatt.data import geonet_dir
from gnssatt.errors import InvalidInputError
from gnssatt.gnss.attitude import KNOWN_LENGTH_PROBE_EPOCHS, attitude_from_rinex

PAIR = ["07590920.05o", "30400920.05o"]  # GEONET, 120 epochs at 30 s, 3335.39 m apart (RTKLIB: 3335.39)


def _pair(**kwargs: Any) -> Any:
    d = geonet_dir()
    return attitude_from_rinex([d / PAIR[0], d / PAIR[1]], d / "07590920.05n", **kwargs)


@pytest.fixture
def engine_runs(monkeypatch: pytest.MonkeyPatch) -> list[int]:
    """The number of epochs of each call of the engine (``_core.gnss_run``), in order."""
    runs: list[int] = []
    run = _core.gnss_run

    def counting(observations: Any, *args: Any) -> Any:
        runs.append(observations.epochs)
        return run(observations, *args)

    monkeypatch.setattr(_core, "gnss_run", counting)
    return runs


def test_a_contradicted_known_length_is_refused_after_the_first_epochs(engine_runs: list[int]) -> None:
    with pytest.raises(InvalidInputError, match="baseline_length_m") as info:
        _pair(baseline_length_m=10.0)
    message = str(info.value)
    assert "given as 10 m" in message and "measure 3335.3" in message, message
    assert f"the first {KNOWN_LENGTH_PROBE_EPOCHS} epochs" in message, message
    # the session itself never ran: one engine call, on the probe's epochs
    assert engine_runs == [KNOWN_LENGTH_PROBE_EPOCHS]


def test_a_consistent_known_length_runs_the_probe_then_the_session(engine_runs: list[int]) -> None:
    series = _pair(baseline_length_m=3335.39)
    assert engine_runs == [KNOWN_LENGTH_PROBE_EPOCHS, 120]
    assert series.fixed.sum() == 120


def test_a_contradicted_length_on_a_session_no_longer_than_the_probe_is_refused_by_the_session(
    engine_runs: list[int],
) -> None:
    # without the probe's epochs to spare, the session is the probe: one run, then the same refusal
    from dataclasses import replace

    from gnssatt.rinex.obs import read_obs

    d = geonet_dir()
    keep = slice(0, KNOWN_LENGTH_PROBE_EPOCHS)
    fields = ("time", "epoch_flag", "clock_offset_s", "data", "lli", "ssi")
    short = []
    for name in PAIR:
        obs = read_obs(d / name)
        short.append(replace(obs, **{f: getattr(obs, f)[keep] for f in fields}))
    with pytest.raises(InvalidInputError, match=r"fixed epochs of the session measure 3335\.3"):
        attitude_from_rinex(short, d / "07590920.05n", baseline_length_m=10.0)
    assert engine_runs == [KNOWN_LENGTH_PROBE_EPOCHS]


@pytest.mark.parametrize(
    ("options", "says"),
    [
        (
            {"method": "lambda", "step_deg": 2.0},
            "step_deg set the likelihood grid, which method 'lambda' never",
        ),
        (
            {"method": "lambda", "step_deg": 2.0, "window_deg": 5.0},
            "step_deg and window_deg set the likelihood grid",
        ),
        (
            {"filter": "static", "window_deg": 5.0},
            "window_deg set the likelihood grid, which filter 'static'",
        ),
    ],
)
def test_grid_options_where_no_grid_runs_are_refused_before_the_engine(
    options: dict[str, Any], says: str, engine_runs: list[int]
) -> None:
    with pytest.raises(InvalidInputError, match=says):
        _pair(**options)
    assert engine_runs == []


def test_grid_options_the_grid_never_used_are_refused_after_the_session(engine_runs: list[int]) -> None:
    # method auto on 3.3 km: LAMBDA fixes all 120 epochs, the grid runs on none (and beyond 100 m never)
    with pytest.raises(
        InvalidInputError, match="step_deg set the likelihood grid, which solved none of the 120"
    ):
        _pair(step_deg=2.0)
    assert engine_runs == [120]


def _geonet_cli(out: Path, *extra: str) -> list[str]:
    d = geonet_dir()
    argv = [
        "attitude",
        "--obs",
        str(d / PAIR[0]),
        "--obs",
        str(d / PAIR[1]),
        "--nav",
        str(d / "07590920.05n"),
    ]
    return [*argv, "--out", str(out), "--no-plot", *extra]


def test_the_cli_names_the_options_that_change_nothing(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    out = tmp_path / "r.csv"
    assert main(_geonet_cli(out, "--method", "lambda", "--window", "5")) == 2
    err = capsys.readouterr().err
    assert "--window set the likelihood grid, which method 'lambda' never runs" in err, err
    assert not out.exists()


@pytest.mark.parametrize(
    ("extra", "named"),
    [
        (["--runs", "5"], "--runs"),
        (["--seed", "0"], "--seed"),
        (["--out", "elsewhere"], "--out"),
        (["--no-progress"], "--no-progress"),
        (["--all"], "--all"),
        (["matrix-method"], "experiment names"),
    ],
)
def test_reproduce_list_refuses_the_options_of_a_run(
    extra: list[str],
    named: str,
    tmp_path: Path,
    capsys: pytest.CaptureFixture[str],
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    monkeypatch.chdir(tmp_path)
    assert main(["reproduce", "--list", *extra]) == 2
    err = capsys.readouterr().err
    assert f"runs none: {named} would change nothing" in err, err
    assert not (tmp_path / "elsewhere").exists()
    assert main(["reproduce", "--list"]) == 0
