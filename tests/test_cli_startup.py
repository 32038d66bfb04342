"""What a start of the command line loads (issues 29, 30): ``import gnssatt``, ``gnssatt attitude --help`` and
``gnssatt position --help`` load no numpy, a whole ``gnssatt attitude`` or ``gnssatt position`` run loads
neither numpy.ma, scipy, matplotlib (without a plot) nor the experiments, and with the plot matplotlib but not
pyplot. Each case runs in a fresh interpreter: this
test process has long since imported everything. Only what is loaded is checked; how long it takes is
measured by ``benches/python/attitude_startup.py``, never here."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from gnssatt.data import geonet_dir
from gnssatt.gnss._attitude_inputs import _among
from gnssatt.gnss._attitude_series import nan_median

#: Loaded only by work that needs them: masked arrays, scipy's rotations and statistics, plots, the papers'
#: experiments, the simulator and the estimators of synthetic data.
LAZY = ("numpy.ma", "scipy", "matplotlib", "gnssatt.experiments", "gnssatt.sim", "gnssatt.attitude")


def _loaded(code: str, watched: tuple[str, ...], cwd: Path | None = None) -> list[str]:
    """The modules among ``watched`` (or a submodule of one) that a fresh interpreter has after ``code``."""
    report = (
        f"import json, sys; print(json.dumps(sorted(w for w in {watched!r} "
        "if any(m == w or m.startswith(w + '.') for m in sys.modules))))"
    )
    out = subprocess.run(
        [sys.executable, "-c", f"{code}\n{report}"], capture_output=True, text=True, check=True, cwd=cwd
    )
    loaded: list[str] = json.loads(out.stdout.splitlines()[-1])
    return loaded


def test_import_gnssatt_loads_no_numpy() -> None:
    assert _loaded("import gnssatt", ("numpy", "argparse", *LAZY)) == []


@pytest.mark.parametrize("command", ["attitude", "position"])
def test_help_loads_no_numpy_nor_the_engine(command: str) -> None:
    code = f"from gnssatt.cli import main\nassert main([{command!r}, '--help']) == 0"
    assert _loaded(code, ("numpy", "gnssatt.gnss", "gnssatt.rinex", *LAZY)) == []


def _attitude_run(*options: str) -> str:
    d = geonet_dir()
    argv = ["attitude", "--obs", str(d / "07590920.05o"), "--obs", str(d / "30400920.05o")]
    argv += ["--nav", str(d / "07590920.05n"), *options]
    return f"from gnssatt.cli import main\nassert main({argv!r}) == 0"


@pytest.mark.slow
@pytest.mark.parametrize(
    "options", [("--motion", "moving", "--frequencies", "2"), ()], ids=["moving-L1L2", "default-static"]
)
def test_attitude_run_without_plot_loads_nothing_lazy(options: tuple[str, ...], tmp_path: Path) -> None:
    code = _attitude_run(*options, "--no-plot", "--out", str(tmp_path / "out.csv"))
    assert _loaded(code, LAZY, cwd=tmp_path) == []


def test_position_run_without_plot_loads_nothing_lazy(tmp_path: Path) -> None:
    d = geonet_dir()
    argv = ["position", "--obs", str(d / "07590920.05o"), "--nav", str(d / "07590920.05n"), "--no-plot"]
    code = f"from gnssatt.cli import main\nassert main({[*argv, '--out', str(tmp_path / 'p.csv')]!r}) == 0"
    assert _loaded(code, LAZY, cwd=tmp_path) == []


@pytest.mark.slow
def test_attitude_run_with_plot_loads_matplotlib_but_not_pyplot(tmp_path: Path) -> None:
    # the default writes the plot: then matplotlib must load (the check above would see it), its figure
    # and Agg canvas only: pyplot (backend resolution, figure managers) is start-up spent on nothing
    code = _attitude_run("--motion", "moving", "--out", str(tmp_path / "out.csv"))
    loaded = _loaded(code, (*LAZY, "matplotlib.pyplot"), cwd=tmp_path)
    assert "matplotlib" in loaded
    assert "matplotlib.pyplot" not in loaded
    assert (tmp_path / "out.png").stat().st_size > 0


@pytest.mark.parametrize("n", [1, 2, 3, 4, 7, 10])
def test_median_is_numpys_nanmedian(n: int, rng: np.random.Generator) -> None:
    for _ in range(20):
        values = rng.normal(size=n) * 10.0 ** rng.integers(-3, 4)
        values[rng.random(n) < 0.3] = np.nan
        if np.isnan(values).all():
            assert np.isnan(nan_median(values))
        else:
            assert nan_median(values) == float(np.nanmedian(values))  # bit for bit


def test_median_of_nothing_and_with_infinities() -> None:
    assert np.isnan(nan_median(np.array([])))
    assert np.isnan(nan_median(np.array([np.nan, np.nan])))
    assert nan_median(np.array([1.0, np.inf, np.nan])) == np.inf
    with pytest.warns(RuntimeWarning, match="invalid value"):  # as np.nanmedian's: inf - inf
        assert np.isnan(nan_median(np.array([-np.inf, np.inf])))


def test_among_is_numpys_isin(rng: np.random.Generator) -> None:
    names = np.array([f"{s}{p:02d}" for s in "GREC" for p in range(1, 12)])
    for _ in range(50):
        values = rng.choice(names, size=int(rng.integers(0, 30)))
        wanted = tuple(rng.choice(names, size=int(rng.integers(0, 10))).tolist())
        expected = np.isin(values, np.array(wanted, dtype=str))
        assert _among(values, wanted).tolist() == expected.tolist()
    assert _among(np.array(["G01", "G02"]), ()).tolist() == [False, False]
