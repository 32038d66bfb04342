"""`gnssatt attitude` on the engine: its options refused with their own names before any work, library
messages translated to option names, and a GEONET run end to end (CSV, summary per system and frequency,
the paths written)."""

from __future__ import annotations

import csv
from pathlib import Path

import pytest

from gnssatt.cli import main
from gnssatt.data import geonet_dir
from gnssatt.errors import InvalidInputError

BASE = ["attitude", "--obs", "a.o", "--obs", "b.o", "--nav", "c.n"]


def _one_error_line(capsys: pytest.CaptureFixture[str]) -> str:
    err = capsys.readouterr().err
    lines = err.splitlines()
    assert len(lines) == 1 and lines[0].startswith("gnssatt: error: "), err
    return lines[0]


@pytest.mark.parametrize(
    ("extra", "says"),
    [
        (["--systems", "GX"], "argument --systems: expected system letters among GRECJ"),
        (["--frequencies", "4"], "argument --frequencies: invalid choice: '4'"),
        (
            ["--min-success-rate", "1.5"],
            "argument --min-success-rate: expected a number in [0.0, 1.0], got 1.5",
        ),
        (["--min-success-rate", "high"], "argument --min-success-rate"),
        (["--ratio-threshold", "0.5"], "argument --ratio-threshold: expected a number in [1.0,"),
        (["--elevation-mask", "95"], "argument --elevation-mask: expected a number in [-90.0, 90.0]"),
        (["--base-position", "1", "2"], "argument --base-position: expected 3 arguments"),
        (["--motion", "flying"], "argument --motion: invalid choice"),
        (["--method", "best"], "argument --method: invalid choice"),
    ],
)
def test_bad_options_are_named(
    extra: list[str], says: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    assert main([*BASE, "--out", str(tmp_path / "r.csv"), *extra]) == 2
    assert says in _one_error_line(capsys)


@pytest.mark.parametrize(
    ("message", "says"),
    [
        ("expected min_success_rate <= 1.0, got 2.0", "expected --min-success-rate <= 1.0"),
        ("expected ratio_threshold >= 1.0, got 0.5", "expected --ratio-threshold >= 1.0"),
        ("expected base_position_m of shape (3,)", "expected --base-position of shape (3,)"),
        ("expected step_deg > 0.0", "expected --step > 0.0"),
    ],
)
def test_library_messages_name_the_options(
    message: str,
    says: str,
    tmp_path: Path,
    monkeypatch: pytest.MonkeyPatch,
    capsys: pytest.CaptureFixture[str],
) -> None:
    def fail(*args: object, **kwargs: object) -> None:
        raise InvalidInputError(message)

    monkeypatch.setattr("gnssatt.gnss.attitude.attitude_from_rinex", fail)
    assert main([*BASE, "--out", str(tmp_path / "r.csv")]) == 2
    assert says in _one_error_line(capsys)


@pytest.mark.slow
def test_geonet_l1_l2_static(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    d = geonet_dir()
    out = tmp_path / "geonet.csv"
    argv = ["attitude", "--obs", str(d / "07590920.05o"), "--obs", str(d / "30400920.05o")]
    argv += ["--nav", str(d / "07590920.05n"), "--out", str(out), "--frequencies", "2", "--method", "lambda"]
    assert main(argv) == 0
    printed = capsys.readouterr().out
    assert f"wrote {out} and {out.with_suffix('.png')}" in printed
    # every epoch fixed since the troposphere is removed at each antenna's own height (117 of 120 before:
    # epochs 57-59, one-epoch arcs of a 12 deg satellite, stayed float); none wrong by the azimuth below
    assert "epochs solved: 120 of 120" in printed and "fix rate: 1.000" in printed
    assert "G L1: " in printed and "(C1/L1)" in printed and "G L2: " in printed and "(P2/L2)" in printed
    with open(out, newline="") as fh:
        rows = list(csv.DictReader(fh))
    assert (
        len(rows) == 120
        and sum(r["fixed"] == "1" for r in rows) >= 117
        and {r["frequencies"] for r in rows} == {"1+2"}
    )
    # the prototype's static L1 azimuth (tests/data/prototype_geonet.json), to the centimetre over 3.3 km
    assert float(rows[0]["azimuth_deg"]) == pytest.approx(163.3858, abs=1e-3)
    assert float(rows[0]["length_m"]) == pytest.approx(3335.4, abs=0.5)


@pytest.mark.slow
def test_warnings_are_one_line_each(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """GEONET has GPS only: asking for Galileo too drops it with a warning naming the files, on one line."""
    d = geonet_dir()
    argv = ["attitude", "--obs", str(d / "07590920.05o"), "--obs", str(d / "30400920.05o")]
    argv += ["--nav", str(d / "07590920.05n"), "--out", str(tmp_path / "r.csv"), "--systems", "GE"]
    assert main([*argv, "--frequencies", "1", "--motion", "moving"]) == 0
    err = capsys.readouterr().err.splitlines()
    assert err and all(line.startswith("gnssatt: warning: ") for line in err), err
    assert any("system E dropped" in line and "07590920.05o" in line for line in err), err


def test_no_plot_writes_only_the_csv(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    d = geonet_dir()
    out = tmp_path / "g.csv"
    argv = ["attitude", "--obs", str(d / "07590920.05o"), "--obs", str(d / "30400920.05o")]
    assert main([*argv, "--nav", str(d / "07590920.05n"), "--out", str(out), "--no-plot"]) == 0
    assert out.exists() and not out.with_suffix(".png").exists()
    assert f"wrote {out}\n" in capsys.readouterr().out
    with out.open() as fh:
        assert len(list(csv.reader(fh))) == 121


GEONET_PAIR = ["07590920.05o", "30400920.05o"]


def _geonet(out: Path, *extra: str) -> list[str]:
    d = geonet_dir()
    argv = ["attitude", "--obs", str(d / GEONET_PAIR[0]), "--obs", str(d / GEONET_PAIR[1])]
    return [*argv, "--nav", str(d / "07590920.05n"), "--out", str(out), "--no-plot", *extra]


def test_a_known_length_the_data_contradict_is_refused_with_the_measured_length(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    # issue 31: the same CSV as without it, no warning; the pair is 3335.4 m apart
    out = tmp_path / "r.csv"
    assert main(_geonet(out, "--baseline-length", "10")) == 2
    line = _one_error_line(capsys)
    assert "--baseline-length: rover 1 is given as 10 m" in line and "measure 3335.3" in line, line
    assert not out.exists()
    assert main(_geonet(out, "--baseline-length", "3335.39")) == 0


def test_method_ml_whose_grid_fails_exits_non_zero_and_writes_no_lambda_rows(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    # eq. (15) over 3.3 km asks for a step finer than the whole-domain grid takes
    out = tmp_path / "r.csv"
    assert main(_geonet(out, "--method", "ml")) == 2
    line = _one_error_line(capsys)
    assert "method 'ml': the likelihood grid solved 0 of 120 epochs" in line and "--step" in line, line
    assert not out.exists()


def test_missing_files_and_folders_are_named_and_no_folder_is_created(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    assert main(_geonet(tmp_path / "r.csv", "--baselines", str(tmp_path / "absent.txt"))) == 2
    assert _one_error_line(capsys).endswith(f"--baselines {tmp_path / 'absent.txt'}: does not exist")
    assert main(_geonet(tmp_path / "r.csv", "--baselines", str(tmp_path))) == 2
    assert _one_error_line(capsys).endswith(f"--baselines {tmp_path}: is not a file")
    out = tmp_path / "absent" / "deeper" / "x.csv"
    assert main(_geonet(out)) == 2
    assert _one_error_line(capsys).endswith(f"--out {out}: {out.parent} does not exist")
    assert not (tmp_path / "absent").exists()
