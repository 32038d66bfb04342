"""Public single-receiver positioning (``gnssatt.position_from_rinex``, ``gnssatt position``).

Checked against what the engine did not compute: the GEONET stations' surveyed header positions, and the
truth of a simulated session (:func:`gnssatt.sim.rinex_scenario.simulate_gnss_rinex`, which draws the
ranges from its own orbits with 0.3 m code noise; the engine's models of its atmosphere are the same, so
the error left is the noise through the geometry).
"""

from __future__ import annotations

import csv
from pathlib import Path

import numpy as np
import pytest

import gnssatt
from gnssatt.cli import main
from gnssatt.data import geonet_dir
from gnssatt.errors import InvalidInputError, InvalidTypeError
from gnssatt.gnss.position import PositionSeries, position_from_rinex
from gnssatt.sim import equilateral_triangle
from gnssatt.sim.rinex_scenario import simulate_gnss_rinex


@pytest.mark.parametrize("station", ["0759", "3040"])
def test_geonet_median_is_at_the_header_position(station: str) -> None:
    p = position_from_rinex(geonet_dir() / f"{station}0920.05o", geonet_dir() / f"{station}0920.05n")
    assert isinstance(p, PositionSeries)
    assert p.solved.all() and len(p.time) == 120
    # measured 0.34 m (0759) and 0.62 m (3040); the header positions are good to a few metres (RTKLIB's
    # station list puts 0759 about 2 m away)
    assert np.linalg.norm(p.median_position_m - p.header_position_m) < 3.0
    assert set(p.satellites_per_system[:, 1:].ravel()) == {0}  # a GPS-only file
    assert np.array_equal(p.satellites, p.satellites_per_system.sum(axis=1))
    # 7-8 GPS satellites of a mid-latitude sky: PDOP about 2
    assert 1.0 < np.median(p.pdop) < 4.0
    # the geodetic columns are those of the ECEF ones (frames.geodetic_to_ecef round trip)
    back = gnssatt.frames.geodetic_to_ecef(p.lat_deg, p.lon_deg, p.height_m)
    np.testing.assert_allclose(back, p.position_ecef_m, atol=1e-6)


def test_simulated_session_recovers_the_truth(tmp_path: Path) -> None:
    antennas = equilateral_triangle(1.0, plane="xz")[:2]
    sim = simulate_gnss_rinex(
        tmp_path, antennas, [30.0, 0.0, 0.0], systems="GEC", frequencies=2, n_epochs=20, rng=4
    )
    truth = sim.antenna_ecef_m[:, 0]
    p = position_from_rinex(sim.obs_paths[0], sim.nav_path)
    assert p.solved.all()
    err = np.linalg.norm(p.position_ecef_m - truth, axis=1)
    # 0.3 m code noise times a PDOP of about 1.5 with three systems: the 3-D error is about 0.5 m at one
    # sigma; 3 m is beyond six sigma
    assert np.median(err) < 1.0 and err.max() < 3.0, err
    letters = {s[0] for s in sim.sats}
    counts = dict(zip("GRECJ", p.satellites_per_system[0], strict=True))
    assert all((counts[s] > 0) == (s in letters) for s in "GRECJ")
    # one system alone uses only its satellites
    g = position_from_rinex(sim.obs_paths[0], sim.nav_path, systems="G")
    assert set(g.satellites_per_system[:, 1:].ravel()) == {0}
    assert g.columns().keys() >= {"sats_G"} and "sats_E" not in g.columns()


def test_a_header_only_file_gives_zero_epochs() -> None:
    blank = Path(__file__).resolve().parent / "data" / "real" / "blank.10o"
    p = position_from_rinex(blank, geonet_dir() / "07590920.05n")
    assert len(p.time) == 0 and p.summary().endswith("0 of 0 epochs solved")


def test_bad_arguments_are_refused() -> None:
    o, n = geonet_dir() / "07590920.05o", geonet_dir() / "07590920.05n"
    with pytest.raises(InvalidInputError, match="systems"):
        position_from_rinex(o, n, systems="GX")
    with pytest.raises(InvalidInputError, match="systems"):
        position_from_rinex(o, n, systems="GG")
    with pytest.raises(InvalidTypeError, match="systems"):
        position_from_rinex(o, n, systems=5)  # type: ignore[arg-type]
    with pytest.raises(InvalidInputError, match="frequencies"):
        position_from_rinex(o, n, frequencies=4)
    with pytest.raises(InvalidInputError, match="elevation_mask_deg"):
        position_from_rinex(o, n, elevation_mask_deg=91.0)
    with pytest.raises(InvalidInputError, match="nav"):
        position_from_rinex(o, [])
    with pytest.raises(InvalidTypeError, match="nav"):
        position_from_rinex(o, 3)  # type: ignore[arg-type]
    with pytest.raises(InvalidTypeError, match="obs"):
        position_from_rinex(3, n)  # type: ignore[arg-type]


def test_cli_writes_csv_plot_and_summary(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / "p.csv"
    o, n = geonet_dir() / "30400920.05o", geonet_dir() / "30400920.05n"
    assert main(["position", "--obs", str(o), "--nav", str(n), "--out", str(out), "--systems", "GE"]) == 0
    with out.open() as f:
        rows = list(csv.reader(f))
    assert rows[0] == [
        "time_gpst", "x_m", "y_m", "z_m", "lat_deg", "lon_deg", "height_m", "satellites", "pdop",
        "sats_G", "sats_E",
    ]  # fmt: skip
    assert len(rows) == 121
    assert out.with_suffix(".png").stat().st_size > 10_000
    text = capsys.readouterr().out
    assert "120 of 120 epochs solved; median position X -3978242" in text
    assert "m from the header position" in text
    assert main(["position", "--obs", str(o), "--nav", str(n), "--out", str(out), "--systems", "X"]) == 2
    assert "expected system letters among GRECJ" in capsys.readouterr().err
    assert main(["position", "--obs", str(o), "--nav", str(n), "--out", str(tmp_path / "p.png")]) == 2


def test_exported_lazily() -> None:
    assert gnssatt.position_from_rinex is position_from_rinex
    assert gnssatt.PositionSeries is PositionSeries
