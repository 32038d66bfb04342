"""The GEONET pair ships with the package: present, readable, and used by ``reproduce recorded-methods``."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from gnssatt.data import geonet_dir
from gnssatt.experiments.recorded_methods import geonet
from gnssatt.rinex import read_nav, read_obs

FILES = ("07590920.05o", "07590920.05n", "30400920.05o", "30400920.05n", "LICENSE.RTKLIB-excerpt.txt")


def test_shipped_files_are_present_and_parse() -> None:
    # Fails (rather than skips) when a build leaves the data out of the wheel.
    folder = geonet_dir()
    for name in (*FILES, "README.md"):
        assert (folder / name).is_file(), name
    for station in ("0759", "3040"):
        assert len(read_obs(folder / f"{station}0920.05o").time) == 120  # 00:00-00:59:30 at 30 s
        assert len(read_nav(folder / f"{station}0920.05n").kepler.toe_ns) > 0


def test_module_main_prints_the_folder() -> None:
    out = subprocess.run(
        [sys.executable, "-m", "gnssatt.data"], capture_output=True, text=True, check=True
    ).stdout
    assert Path(out.strip()) == geonet_dir()


@pytest.mark.slow
def test_recorded_methods_geonet_part_runs_on_the_shipped_pair() -> None:
    m = geonet()
    assert m["geonet_static_fixed"] == 1.0
    # The header positions are the only truth and are good to a few metres (data README).
    assert m["geonet_static_vs_header_m"] < 3.0
    assert np.isfinite(m["geonet_single_epoch_float_error_median_m"])
