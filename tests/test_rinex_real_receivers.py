"""Observation files of real receivers (RINEX 3.01-3.04; Leica GR50 / GRX1200, an Ashtech file written by
gLAB), from ``tests/data/real`` (sources, licences and cuts in ``tests/data/README.md``).

Expected values come from the file text, not from the reader: the epoch lines are found by their ``>``,
the observation types by their header label, and each observation is the F14.3 field at the column the
RINEX 3 format gives it (``3 + 16 k`` after the satellite id), or a value quoted from the file by hand.
The engine runs on the shipped GEONET pair where a navigation file of the same day exists (a zero
baseline: the same file twice), and refuses the real RINEX 3 files whose navigation file is of another day
with a :class:`~gnssatt.errors.RinexError` that names it.
"""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np
import pytest

from gnssatt.data import geonet_dir
from gnssatt.errors import RinexError
from gnssatt.gnss.attitude import MIN_DIRECTION_BASELINE_M, ZeroBaselineWarning, attitude_from_rinex
from gnssatt.rinex import read_obs
from gnssatt.rinex.signals import choose_signals

REAL = Path(__file__).parent / "data" / "real"
DATA = Path(__file__).parent / "data"
ACOR = "ACOR00ESP_R_20213550000_01D_30S_MO.rnx"

#: Quoted from each file by hand: version, APPROX POSITION XYZ, the first epoch's first satellite and its
#: first pseudorange code with the value written there, some GLONASS SLOT / FRQ # pairs, LEAP SECONDS.
QUOTED = {
    ACOR: (3.04, (4594489.8680, -678367.9920, 4357065.8700), "G01", "C1C", 24600158.420,
           {"R01": 1, "R10": -7, "R24": 2}, 18),
    # excerpt kept by gnss-tec: 4-5 satellites an epoch, an event (flag 4) without a time between them
    "AJAC_gnss_tec_excerpt.rnx": (3.02, (4696989.7040, 723994.2090, 4239678.3140), "G06", "C1C",
                                  20835332.939, {"R04": 6, "R06": -4, "R11": 0}, 18),
    "DUTH0630.22O": (3.02, (4362689.8809, 2026647.9686, 4174234.2239), "G01", "C1C", 20243517.560,
                     {"R02": -4, "R15": 0, "R23": 3}, 18),
    "NOA10630.22O": (3.02, (4599643.3185, 2034827.9762, 3909890.7491), "G01", "C1C", 20176608.780, {}, 18),
    "flrs0010.12o": (3.02, (4221530.0272, -2549242.3485, 4031397.8561), "G01", "C1C", 23184989.980,
                     {"R01": 1, "R16": -1, "R19": 3}, 18),
    "pdel0010.21o": (3.02, (4551596.0624, -2186893.3724, 3883410.6118), "G01", "C1C", 23304001.080,
                     {"R16": -1, "R18": -3, "R24": 2}, 18),
    # gLAB writes the XYZ in 15 columns, the channels without their separating blank ("R11 -5R19 +3")
    "demo3.10o": (3.01, (4789028.4701, 176610.0133, 4195017.0310), "G13", "C1C", 23095483.463,
                  {"R11": -5, "R19": 3, "R23": -6}, 15),
}  # fmt: skip


def _lines(name: str) -> list[str]:
    return (REAL / name).read_text().splitlines()


def _header_types(lines: list[str]) -> dict[str, list[str]]:
    """Observation types per system from the 'SYS / # / OBS TYPES' lines (continuations included)."""
    types: dict[str, list[str]] = {}
    system = ""
    for line in lines:
        if line[60:].strip() == "END OF HEADER":
            break
        if line[60:].strip() == "SYS / # / OBS TYPES":
            if line[0] != " ":
                system = line[0]
                types[system] = []
            types[system] += line[7:60].split()
    return types


def _epochs(lines: list[str]) -> list[tuple[int, list[str]]]:
    """(line index, records) of each observation epoch (flag 0 or 1); the records are the lines after it."""
    out = []
    for i, line in enumerate(lines):
        if line.startswith(">"):
            flag, n = int(line[31]), int(line[32:35])  # an event may leave the date blank
            if flag in (0, 1):
                out.append((i, lines[i + 1 : i + 1 + n]))
    return out


def _field(record: str, k: int) -> float:
    """Observation ``k`` (0-based) of a RINEX 3 record: F14.3 in columns 4 + 16 k (1-based), NaN if blank."""
    text = record[3 + 16 * k : 3 + 16 * k + 14]
    return float(text) if text.strip() else float("nan")


@pytest.mark.parametrize("name", sorted(QUOTED))
def test_header_and_first_epoch_as_written(name: str) -> None:
    version, xyz, first_sat, code, value, channels, leap = QUOTED[name]
    lines = _lines(name)
    obs = read_obs(REAL / name)
    assert obs.version == pytest.approx(version)
    np.testing.assert_allclose(obs.approx_position_m, xyz, rtol=0, atol=1e-9)
    assert {s: list(t) for s, t in obs.obs_types.items()} == _header_types(lines)
    epochs = _epochs(lines)
    assert len(obs.time) == len(epochs)
    first = [r[0:3].replace(" ", "0") for r in epochs[0][1]]
    assert first[0] == first_sat
    assert obs.leap_seconds == leap
    assert obs.time_system == "GPS"
    for sat, want in channels.items():
        assert obs.glonass_channels[sat] == want
    # the quoted pseudorange, then every value of the first epoch, field by field
    assert obs.get(code)[0, obs.sats.index(first_sat)] == value
    present = [s for s in obs.sats if np.isfinite(obs.data[0, obs.sats.index(s)]).any()]
    assert sorted(present) == sorted(first)
    for sat, record in zip(first, epochs[0][1], strict=True):
        types = obs.obs_types[sat[0]]
        got = obs.data[0, obs.sats.index(sat), [obs.codes.index(c) for c in types]]
        want = [_field(record, k) for k in range(len(types))]
        np.testing.assert_array_equal(got, want, err_msg=f"{name} {sat}")


def test_epoch_labels_and_clock_offsets_as_written() -> None:
    """Every epoch label, and the receiver clock offset where the epoch line gives one: gLAB writes the
    satellite count of its second epoch as I2 (one column early), so the offset starts in column 41 and a
    reader cutting columns 42-56 loses its sign."""
    for name in QUOTED:
        lines = _lines(name)
        obs = read_obs(REAL / name)
        want = []
        clocks = []
        for i, _ in _epochs(lines):
            w = lines[i][1:].split()
            sec = float(w[5])
            want.append(
                np.datetime64(f"{w[0]}-{w[1]:0>2}-{w[2]:0>2}T{w[3]:0>2}:{w[4]:0>2}:00", "ns")
                + np.timedelta64(round(sec * 1e9), "ns")
            )
            clocks.append(float(w[8]) if len(w) > 8 else np.nan)
        np.testing.assert_array_equal(obs.time, np.array(want), err_msg=name)
        np.testing.assert_array_equal(obs.clock_offset_s, clocks, err_msg=name)
    assert read_obs(REAL / "demo3.10o").clock_offset_s.tolist() == [-0.123456789012, -0.123456789012]


def test_signals_chosen_per_system() -> None:
    """The slots of a 3.04 mixed file: GPS L2 by RTKLIB's priority (W before S), BeiDou B1I in band 2
    (RINEX 3.03 on), Galileo E5b in band 7, GLONASS G3 in band 3; and B1I of a 3.02 file."""
    obs = read_obs(REAL / ACOR)
    labels = {s: [c.label for c in choose_signals(obs, s)] for s in "GREC"}
    assert labels == {
        "G": ["C1C/L1C", "C2W/L2W", "C5Q/L5Q"],
        "R": ["C1C/L1C", "C2P/L2P", "C3Q/L3Q"],
        "E": ["C1C/L1C", "C7Q/L7Q", "C5Q/L5Q"],
        "C": ["C2I/L2I", "C7I/L7I", "C6I/L6I"],
    }
    # RINEX 3.02 writes B1I in band 1 (C1I), 3.03 on in band 2
    ajac = read_obs(REAL / "AJAC_gnss_tec_excerpt.rnx")
    assert [c.label for c in choose_signals(ajac, "C")] == ["C1I/L1I", "C7I/L7I", ""]


def test_two_stations_of_one_day_keep_every_common_signal() -> None:
    """PDEL and FLRS (Azores, 2021-01-01, both Leica): every satellite both first epochs list is in the
    session, with each file's C1C/L1C/C2W/L2W (GPS) or C1C/L1C/C2P/L2P (GLONASS) value as written, and the
    GLONASS channels of the headers."""
    from gnssatt.gnss.session_input import session_input

    names = ["pdel0010.21o", "flrs0010.12o"]
    records = [{r[0:3]: r for r in _epochs(_lines(n))[0][1]} for n in names]
    both = sorted(set(records[0]) & set(records[1]), key=lambda s: ("GR".index(s[0]), s))
    si = session_input([read_obs(REAL / n) for n in names], systems="GR", frequencies=2)
    assert si.sats == tuple(both) and si.epochs_dropped == (0, 0) and len(si.time_gpst_ns) == 2
    # fields 0 C1C, 1 L1C, 4 C2W or C2P, 5 L2W or L2P of both systems' header types (the same layout)
    for r, recs in enumerate(records):
        for k, sat in enumerate(both):
            np.testing.assert_array_equal(
                si.code_m[r, 0, k, :2], [_field(recs[sat], 0), _field(recs[sat], 4)]
            )
            np.testing.assert_array_equal(
                si.phase_cycles[r, 0, k, :2], [_field(recs[sat], 1), _field(recs[sat], 5)]
            )
    channels = dict(zip(si.sats, si.glonass_channel.tolist(), strict=True))
    assert channels["R02"] == -4 and channels["R16"] == -1 and channels["G01"] == 99


def _scaled(field: str) -> str:
    """An F14.3 field times 10, by moving the decimal point in the text (no rounding)."""
    whole, frac = field.strip().split(".")
    return f"{whole}{frac[0]}.{frac[1:]}0".rjust(14)


def test_scale_factor_divides_the_stored_values(tmp_path: Path) -> None:
    """RINEX 3 ``SYS / SCALE FACTOR``: the file stores value x factor. DUTH rewritten with factor 10 on GPS
    C1C and L1C (fields 0 and 1, stored x 10) reads back to the values DUTH writes."""
    lines = _lines("DUTH0630.22O")
    body = next(i for i, line in enumerate(lines) if line[60:].strip() == "END OF HEADER") + 1
    out = []
    for i, line in enumerate(lines):
        if i >= body and line.startswith("G"):
            line = line[:3] + _scaled(line[3:17]) + line[17:19] + _scaled(line[19:33]) + line[33:]
        out.append(line)
        if line[60:].strip() == "SYS / # / OBS TYPES" and line[0] == "R":
            out.append(f"{'G   10   2 C1C L1C':<60}SYS / SCALE FACTOR")
    path = tmp_path / "scaled.22O"
    path.write_text("\n".join(out) + "\n")
    scaled, plain = read_obs(path), read_obs(REAL / "DUTH0630.22O")
    assert scaled.get("C1C")[0, scaled.sats.index("G01")] == pytest.approx(20243517.560, rel=1e-15)
    np.testing.assert_allclose(scaled.data, plain.data, rtol=1e-15, atol=0)
    np.testing.assert_array_equal(scaled.lli, plain.lli)


def test_observation_types_changed_inside_the_data_are_refused(tmp_path: Path) -> None:
    """An event (flag 4) whose header records change the GPS observation types: the records after it are
    laid out otherwise, so reading them with the header's types would put values under wrong codes."""
    lines = _lines("DUTH0630.22O")
    second = [i for i, line in enumerate(lines) if line.startswith(">")][1]
    event = [">                              4  1", f"{'G    4 C1C L1C C2W L2W':<60}SYS / # / OBS TYPES"]
    path = tmp_path / "types_changed.22O"
    path.write_text("\n".join(lines[:second] + event + lines[second:]) + "\n")
    with pytest.raises(RinexError, match=r"line 56: 'SYS / # / OBS TYPES' inside the data \(epoch flag 4"):
        read_obs(path)
    # a comment in an event changes nothing: the file reads as the original
    path.write_text(
        "\n".join([*lines[:second], event[0], f"{'antenna moved':<60}COMMENT", *lines[second:]]) + "\n"
    )
    np.testing.assert_array_equal(read_obs(path).data, read_obs(REAL / "DUTH0630.22O").data)


@pytest.mark.parametrize(
    ("files", "nav"),
    [
        (["DUTH0630.22O", "NOA10630.22O"], "CBW100NLD_R_20210010000_01D_MN.rnx"),  # 2022 obs, 2021 nav
        ([ACOR, ACOR], "BRDC00IGS_R_20201360000_01D_MN.rnx"),  # 2021 obs, 2020 nav
        (["pdel0010.21o", "pdel0010.21o"], "CBW100NLD_R_20210010000_01D_MN.rnx"),  # same day, 16 h off
    ],
)
def test_navigation_of_another_time_is_named(files: list[str], nav: str) -> None:
    """No navigation file of these days is in the test data: the engine refuses, naming the navigation file,
    the observation span and the records' span, instead of reporting 'no satellite with an ephemeris'."""
    with warnings.catch_warnings():
        warnings.simplefilter(
            "ignore"
        )  # a system or epochs one file lacks (named in test_rinex_session_input)
        with pytest.raises(RinexError, match="no broadcast ephemeris") as err:
            attitude_from_rinex([REAL / f for f in files], DATA / nav)
    assert nav in str(err.value) and "expected the navigation file of the observation day" in str(err.value)


@pytest.mark.slow
def test_zero_baseline_is_named_and_has_no_direction() -> None:
    """The same real file given twice (GEONET 0759 with its own day's navigation file): the baseline is 0,
    its azimuth and elevation are undefined; they come back NaN with a warning, not as atan2(0, 0) = 0."""
    folder = geonet_dir()
    with pytest.warns(ZeroBaselineWarning, match=r"shorter than 0\.01 m at 120 of 120 epochs"):
        series = attitude_from_rinex(
            [folder / "07590920.05o", folder / "07590920.05o"], folder / "07590920.05n", systems="G"
        )
    assert series.mode == "baseline" and len(series.time) == 120
    lengths = np.linalg.norm(series.baselines_enu_m[:, 0], axis=1)
    assert np.all(lengths < MIN_DIRECTION_BASELINE_M)
    assert np.isnan(series.angles_deg).all() and np.isnan(series.angle_sigmas_deg).all()
    assert any("shorter than" in w for w in series.warnings)
