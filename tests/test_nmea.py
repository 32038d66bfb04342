"""NMEA 0183 output (`gnssatt.gnss.nmea`, `gnssatt attitude --nmea`): the sentences parsed back by pynmea2,
an independent parser that checks every checksum, heading values against the series, UTC times against
GPST minus the 18 leap seconds of 2024 (IERS Bulletin C 52), and the leap-second boundary of 2017."""

from __future__ import annotations

import dataclasses
import datetime as dt
from functools import cache
from pathlib import Path

import numpy as np
import pynmea2
import pytest

from gnssatt import sim
from gnssatt.cli import main
from gnssatt.gnss.attitude import AttitudeSeries, attitude_from_rinex
from gnssatt.gnss.nmea import _checksum, _hdt_sentence, _utc_from_gpst, nmea_sentences, write_nmea
from gnssatt.sim.rinex_scenario import SimulatedRinex, simulate_rinex_array

ANT = sim.equilateral_triangle(1.0, plane="xz")
EULER = np.array([[-40.0, 5.0, 3.0], [-37.0, 4.0, 2.0], [-34.0, 3.0, 1.0], [-31.0, 2.0, 0.0]])


@cache
def _session(folder: Path) -> tuple[SimulatedRinex, AttitudeSeries]:
    s = simulate_rinex_array(folder, ANT, EULER, rng=3)
    series = attitude_from_rinex(list(s.obs_paths), s.nav_path, ANT[1:] - ANT[0], method="lambda")
    return s, series


@pytest.fixture(scope="module")
def session(tmp_path_factory: pytest.TempPathFactory) -> tuple[SimulatedRinex, AttitudeSeries]:
    return _session(tmp_path_factory.mktemp("nmea"))


def test_checksum_of_a_published_sentence() -> None:
    # A Hemisphere VS100's output as logged on NOAA's R/V Ronald H. Brown (psl.noaa.gov ATOMIC 2020 raw
    # GPS log): "$GPHDT,74.20,T*34".
    assert _checksum("GPHDT,74.20,T") == "34"
    assert _hdt_sentence(-0.5) == f"$GNHDT,359.500,T*{_checksum('GNHDT,359.500,T')}"


def test_sentences_parse_back_with_headings_and_utc_times(
    session: tuple[SimulatedRinex, AttitudeSeries], tmp_path: Path
) -> None:
    _, series = session
    assert np.all(np.isfinite(series.angles_deg[:, 0]))
    path = tmp_path / "att.nmea"
    assert write_nmea(path, series) == len(EULER)
    raw = path.read_bytes()
    assert raw.endswith(b"\r\n") and raw.count(b"\r\n") == 2 * len(EULER)
    msgs = [pynmea2.parse(line, check=True) for line in raw.decode("ascii").split("\r\n") if line]
    hdt, hpr = msgs[0::2], msgs[1::2]
    assert all(isinstance(m, pynmea2.types.talker.HDT) and m.talker == "GN" for m in hdt)
    assert all(isinstance(m, pynmea2.ProprietarySentence) and m.data[1] == "HPR" for m in hpr)
    heading = np.array([float(m.heading) for m in hdt])
    np.testing.assert_allclose(heading, series.angles_deg[:, 0], atol=5e-4)
    fields = np.array([[float(v) for v in m.data[3:6]] for m in hpr])
    np.testing.assert_allclose(fields, series.angles_deg, atol=5e-4)
    assert all(m.data[6] == "N" for m in hpr)
    # UTC = GPST - 18 s in 2024; the truth's compass heading, -psi (tests/test_rinex_rotating_platform.py).
    for m, t in zip(hpr, series.time, strict=True):
        gpst = dt.datetime.fromisoformat(str(t.astype("datetime64[ms]")))
        expected = (gpst - dt.timedelta(seconds=18)).strftime("%H%M%S.%f")[:9]
        assert m.data[2] == expected
    err = (heading - (-EULER[:, 0]) % 360.0 + 180.0) % 360.0 - 180.0
    assert np.all(np.abs(err) < 5.0 * series.angle_sigmas_deg[:, 0] + 1e-3)


def test_two_angles_write_an_empty_roll(session: tuple[SimulatedRinex, AttitudeSeries]) -> None:
    # Baseline mode's two angles (azimuth, elevation): roll is empty; a NaN heading writes nothing.
    angles = np.full((len(EULER), 2), np.nan)
    angles[0] = [12.5, -1.25]
    series = dataclasses.replace(session[1], angles_deg=angles)
    lines = nmea_sentences(series)
    assert len(lines) == 2
    m = pynmea2.parse(lines[1], check=True)
    gpst = dt.datetime.fromisoformat(str(series.time[0].astype("datetime64[ms]")))
    hms = (gpst - dt.timedelta(seconds=18)).strftime("%H%M%S.%f")[:9]
    assert m.data[2:] == [hms, "12.500", "-1.250", "", "N"]


@pytest.mark.parametrize(
    ("gpst", "utc"),
    [
        ("2016-12-31T23:59:59", "2016-12-31T23:59:42"),
        ("2017-01-01T00:00:16", "2016-12-31T23:59:59"),
        ("2017-01-01T00:00:18", "2017-01-01T00:00:00"),
        ("2024-03-01T10:00:00", "2024-03-01T09:59:42"),
    ],
)
def test_utc_from_gpst_across_the_2017_leap_second(gpst: str, utc: str) -> None:
    got = _utc_from_gpst(np.array([gpst], dtype="datetime64[ns]"))
    assert got[0] == np.datetime64(utc, "ns")


def test_cli_writes_the_nmea_file(session: tuple[SimulatedRinex, AttitudeSeries], tmp_path: Path) -> None:
    s, series = session
    baselines = tmp_path / "b.txt"
    np.savetxt(baselines, ANT[1:] - ANT[0])
    obs = [a for p in s.obs_paths for a in ("--obs", str(p))]
    out, nmea = tmp_path / "r.csv", tmp_path / "r.nmea"
    args = ["attitude", *obs, "--nav", str(s.nav_path), "--baselines", str(baselines), "--method", "lambda"]
    assert main([*args, "--out", str(out), "--no-plot", "--nmea", str(nmea)]) == 0
    assert nmea.read_text(encoding="ascii").splitlines() == nmea_sentences(series)
