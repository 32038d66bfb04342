"""`gnssatt reproduce`: listing, running one experiment, the common JSON shape, and usage errors."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

from gnssatt.cli import main
from gnssatt.errors import ConvergenceError, InternalError, InvalidInputError, RinexError, WorkLimitError
from gnssatt.experiments import EXPERIMENTS
from gnssatt.sim.rinex_scenario import simulate_rinex_array

ROOT = Path(__file__).resolve().parents[1]


def test_list(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["reproduce", "--list"]) == 0
    out = capsys.readouterr().out
    for name in EXPERIMENTS:
        assert name in out


@pytest.mark.slow
def test_matrix_method_writes_json_and_plot(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert (
        main(
            [
                "reproduce",
                "matrix-method",
                "--runs",
                "60",
                "--seed",
                "7",
                "--out",
                str(tmp_path),
                "--no-progress",
            ]
        )
        == 0
    )
    doc = json.loads((tmp_path / "matrix-method.json").read_text())
    assert set(doc) == {
        "experiment",
        "paper",
        "measured",
        "tolerance",
        "verdict",
        "unavailable",
        "runs",
        "seed",
        "version",
        "commit",
        "results_page",
    }
    from gnssatt import __version__

    assert doc["version"] == __version__ and doc["results_page"] == "docs/results/matrix_method.md"
    assert (ROOT / doc["results_page"]).is_file()
    # the paper's mean errors against the measured ones, judged by the declared factor
    for name, paper in doc["paper"].items():
        agrees = paper / 10.0 <= doc["measured"][name] <= paper * 10.0
        assert doc["tolerance"][name] == 10.0 and doc["verdict"][name] == ("agrees" if agrees else "differs")
    assert doc["experiment"] == "matrix-method" and doc["runs"] == 60 and doc["seed"] == 7
    assert doc["paper"]["heading_mean_abs_error_deg"] == 0.282
    assert all(k.endswith(("_deg", "_fraction")) for k in doc["measured"])
    assert (tmp_path / "matrix-method-geometry.png").stat().st_size > 10_000
    assert "heading_mean_abs_error_deg" in capsys.readouterr().out


@pytest.mark.parametrize(
    "argv", [["reproduce"], ["reproduce", "no-such-thing"], ["reproduce", "--all", "matrix-method"]]
)
def test_usage_errors(argv: list[str], capsys: pytest.CaptureFixture[str]) -> None:
    assert main(argv) == 2
    assert capsys.readouterr().err.startswith("gnssatt: error: reproduce: ")


@pytest.mark.slow
def test_ml_grid_writes_json_and_sections(tmp_path: Path) -> None:
    assert main(["reproduce", "ml-grid", "--runs", "3", "--out", str(tmp_path), "--no-progress"]) == 0
    doc = json.loads((tmp_path / "ml-grid.json").read_text())
    assert doc["paper"]["variance_ratio_dd_over_optimal"] == 2.0
    assert doc["measured"]["sigma0p05rad_af_heading_rms_deg"] < 1.0
    assert (tmp_path / "ml-grid-sections.png").stat().st_size > 10_000


@pytest.mark.slow
def test_magnetometer_yaw_methods_agree(tmp_path: Path) -> None:
    assert main(["reproduce", "magnetometer-yaw", "--out", str(tmp_path), "--no-progress"]) == 0
    m = json.loads((tmp_path / "magnetometer-yaw.json").read_text())["measured"]
    # The paper's conclusion: TRIAD and eq. (3) are close. With an exact Earth sensor they differ by far
    # less than the yaw error the 5 % scale factor causes.
    for channel in ("x", "y"):
        for tag in ("i51p6", "i87"):
            gap = m[f"{channel}_scale_{tag}_max_triad_minus_eq3_deg"]
            assert gap < 0.1 * m[f"triad_{channel}_scale_{tag}_max_yaw_error_deg"]
    assert (tmp_path / "magnetometer-yaw-x-scale.png").stat().st_size > 10_000


@pytest.mark.slow
def test_orbit_filter_writes_json_and_plots(tmp_path: Path) -> None:
    assert main(["reproduce", "orbit-filter", "--runs", "2", "--out", str(tmp_path), "--no-progress"]) == 0
    doc = json.loads((tmp_path / "orbit-filter.json").read_text())
    assert doc["runs"] == 2
    for lab in ("loose_gps", "loose_gps_glonass", "tight_gps", "tight_gps_glonass"):
        assert doc["measured"][f"{lab}_position_rms_m"] > 0
    assert (tmp_path / "orbit-filter-errors.png").stat().st_size > 10_000
    assert (tmp_path / "orbit-filter-nees.png").stat().st_size > 10_000


@pytest.mark.slow  # ~30 s on 2 cores even with one run: 4 satellite counts x 3 methods x 20 epochs
def test_recorded_methods_writes_json_without_paper_column(tmp_path: Path) -> None:
    argv = ["reproduce", "recorded-methods", "--runs", "1", "--out", str(tmp_path), "--no-progress"]
    assert main(argv) == 0
    doc = json.loads((tmp_path / "recorded-methods.json").read_text())
    assert doc["paper"] == {} and doc["runs"] == 1
    m = doc["measured"]
    for n in (5, 6, 7, 8):
        for name in ("ml", "ml_window", "lambda"):
            assert 0.0 <= m[f"{name}_n{n}_wrong_fraction"] <= 1.0
        assert 0.0 <= m[f"lambda_n{n}_fix_rate"] <= 1.0


# --- failures: one line on stderr, exit status 2 (130 after Ctrl-C), never a traceback ---------------------


def _one_error_line(capsys: pytest.CaptureFixture[str]) -> str:
    err = capsys.readouterr().err
    lines = err.splitlines()
    assert len(lines) == 1 and lines[0].startswith("gnssatt: error: "), err
    assert "Traceback" not in err
    return lines[0]


@pytest.mark.parametrize(
    ("argv", "says"),
    [
        ([], "the following arguments are required: command"),
        (["attitude"], "--obs"),
        (["attitude", "--obs", "a.o"], "--nav"),
        (["attitude", "--obs", "a.o", "--nav", "b.n", "--method", "best"], "--method"),
        (["attitude", "--obs", "a.o", "--nav", "b.n", "--window", "wide"], "--window"),
        (["reproduce", "--runs", "x", "matrix-method"], "--runs"),
        (["reproduce", "--runs", "0", "matrix-method"], "argument --runs: expected an integer >= 1, got 0"),
        (["reproduce", "--seed", "-1", "matrix-method"], "argument --seed: expected an integer >= 0, got -1"),
        (["reproduce"], "give experiment names, --all, or --list"),
        (["reproduce", "no-such-thing"], "unknown experiment 'no-such-thing'"),
        (["nonsense"], "invalid choice: 'nonsense'"),
    ],
)
def test_bad_command_lines_are_one_line(
    argv: list[str], says: str, capsys: pytest.CaptureFixture[str]
) -> None:
    assert main(argv) == 2
    assert says in _one_error_line(capsys)


def test_help_exits_zero(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["attitude", "--help"]) == 0
    assert "--obs" in capsys.readouterr().out


def test_unwritable_out_is_refused_before_any_work(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    blocker = tmp_path / "a-file"
    blocker.write_text("not a folder\n")
    out = blocker / "results.csv"  # its parent is a file: cannot be created, even by root
    argv = [
        "attitude",
        "--obs",
        str(tmp_path / "absent.o"),
        "--nav",
        str(tmp_path / "absent.n"),
        "--out",
        str(out),
    ]
    assert main(argv) == 2
    line = _one_error_line(capsys)
    assert f"--out {out}: {blocker} is not a folder" in line
    assert main(["reproduce", "matrix-method", "--runs", "2", "--out", str(blocker), "--no-progress"]) == 2
    assert f"--out {blocker}: cannot create folder" in _one_error_line(capsys)
    assert main([*argv[:-1], str(tmp_path)]) == 2
    assert "is a folder, expected a file name" in _one_error_line(capsys)


def test_missing_and_garbage_rinex_name_the_file(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    garbage = tmp_path / "garbage.o"
    garbage.write_bytes(bytes(range(256)) * 4 + b"\n")
    nav = tmp_path / "absent.n"
    for obs, says in [(tmp_path / "absent.o", "cannot open"), (garbage, "RINEX VERSION / TYPE")]:
        argv = [
            "attitude",
            "--obs",
            str(obs),
            "--obs",
            str(obs),
            "--nav",
            str(nav),
            "--out",
            str(tmp_path / "r.csv"),
        ]
        assert main(argv) == 2
        line = _one_error_line(capsys)
        assert str(obs) in line and says in line


def test_unreadable_baselines_name_the_option(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    bad = tmp_path / "baselines.txt"
    bad.write_text("1 2\n3\n")
    argv = [
        "attitude",
        "--obs",
        "a.o",
        "--nav",
        "b.n",
        "--baselines",
        str(bad),
        "--out",
        str(tmp_path / "r.csv"),
    ]
    assert main(argv) == 2
    assert f"--baselines {bad}: cannot read rows 'x y z'" in _one_error_line(capsys)


@pytest.mark.parametrize(
    ("raised", "status", "says"),
    [
        (InvalidInputError("expected window_deg > 0, got -5.0"), 2, "expected --window > 0, got -5.0"),
        (WorkLimitError("n_trials = 10 exceeds the limit of 5"), 2, "--runs = 10 exceeds the limit of 5"),
        (ConvergenceError("LAMBDA:\nZ overflow"), 2, "LAMBDA: Z overflow"),
        (InternalError("index out of bounds"), 2, "internal error, please report it"),
        (RinexError("x.o", 7, "expected a number"), 2, "x.o, line 7: expected a number"),
        (PermissionError(13, "Permission denied", "/root/out.csv"), 2, "/root/out.csv: Permission denied"),
        (ZeroDivisionError("division by zero"), 2, "unexpected ZeroDivisionError"),
        (KeyboardInterrupt(), 130, "interrupted"),
    ],
)
def test_library_failures_are_one_line(
    raised: BaseException,
    status: int,
    says: str,
    tmp_path: Path,
    monkeypatch: pytest.MonkeyPatch,
    capsys: pytest.CaptureFixture[str],
) -> None:
    def fail(*args: object, **kwargs: object) -> None:
        raise raised

    monkeypatch.setattr("gnssatt.gnss.attitude.attitude_from_rinex", fail)
    argv = ["attitude", "--obs", "a.o", "--obs", "b.o", "--nav", "c.n", "--out", str(tmp_path / "r.csv")]
    assert main(argv) == status
    assert says in _one_error_line(capsys)


@pytest.mark.slow
def test_attitude_reports_the_files_it_wrote(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    files = simulate_rinex_array(tmp_path, [[0.0, 0.0, 0.0], [1.2, 0.0, 0.0]], [-40.0, 5.0, 0.0], rng=0)
    out = tmp_path / "run" / "series.csv"
    out.parent.mkdir()  # the CSV's folder must exist (a missing one is refused, not created)
    argv = ["attitude", "--nav", str(files.nav_path), "--out", str(out), "--elevation-mask", "5"]
    for p in files.obs_paths:
        argv += ["--obs", str(p)]
    assert main(argv) == 0
    png = out.with_suffix(".png")
    assert f"wrote {out} and {png}" in capsys.readouterr().out
    assert out.is_file() and png.stat().st_size > 10_000


@pytest.mark.slow
def test_console_run_prints_no_traceback(tmp_path: Path) -> None:
    bad = tmp_path / "bad.o"
    bad.write_text("     3.04           OBSERVATION DATA    G                   RINEX VERSION / TYPE\n")
    argv = [
        "attitude",
        "--obs",
        str(bad),
        "--obs",
        str(bad),
        "--nav",
        str(bad),
        "--out",
        str(tmp_path / "r.csv"),
    ]
    proc = subprocess.run(
        [sys.executable, "-m", "gnssatt.cli", *argv], capture_output=True, text=True, timeout=120, check=False
    )
    assert proc.returncode == 2
    assert proc.stderr.startswith("gnssatt: error: ") and proc.stderr.count("\n") == 1, proc.stderr
    assert "Traceback" not in proc.stderr and "bad.o" in proc.stderr


def test_version_and_plain_help(capsys: pytest.CaptureFixture[str]) -> None:
    from gnssatt import __version__

    assert main(["--version"]) == 0
    assert capsys.readouterr().out.strip() == f"gnssatt {__version__}"
    for argv in (["--help"], ["reproduce", "--help"], ["attitude", "--help"]):
        assert main(argv) == 0
        text = capsys.readouterr().out
        # a description, an example, no reStructuredText markup
        assert "examples:\n  gnssatt " in text and "``" not in text and ":func:" not in text, argv
    assert main(["attitude", "--help"]) == 0
    assert "default results.csv" in capsys.readouterr().out
