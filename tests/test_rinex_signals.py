"""Signal choice per system and frequency slot: the band table of ``rust/core/src/gnss/signal.rs`` and the
attribute priority of RTKLIB 2.4.3 (``codepris`` in rtkcmn.c), on files written for each case."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from gnssatt.data import geonet_dir
from gnssatt.rinex import read_obs, write_obs
from gnssatt.rinex.obs import RinexObs
from gnssatt.rinex.signals import choose_signals

T = np.array(["2024-03-01T10:00:00", "2024-03-01T10:00:01"], dtype="datetime64[ns]")


def _file(
    tmp_path: Path, sats: list[str], codes: list[str], *, version: str = "3.04", blank: tuple[str, ...] = ()
) -> RinexObs:
    """A two-epoch file with a value in every code (except those in ``blank``) for every satellite."""
    obs = {c: np.full((2, len(sats)), np.nan if c in blank else 2.0e7 + k) for k, c in enumerate(codes)}
    p = tmp_path / "f.rnx"
    write_obs(p, T, sats, obs)
    if version != "3.04":
        text = p.read_text()
        p.write_text(f"{version:>9}" + text[9:])
    return read_obs(p)


def _labels(obs: RinexObs, system: str) -> tuple[str, ...]:
    return tuple(c.label for c in choose_signals(obs, system))


def test_gps_slots_follow_rtklib_priority(tmp_path: Path) -> None:
    codes = ["C1C", "L1C", "C1W", "L1W", "C2L", "L2L", "C2W", "L2W", "C5Q", "L5Q", "C5X", "L5X"]
    obs = _file(tmp_path, ["G01"], codes)
    # L1: C before W; L2: W ("PYWC...") before L; L5: Q before X ("IQX")
    assert _labels(obs, "G") == ("C1C/L1C", "C2W/L2W", "C5Q/L5Q")
    doppler = choose_signals(_file(tmp_path, ["G01"], [*codes, "D1W", "D1C", "S1C"]), "G")[0]
    assert doppler.doppler == "D1C" and doppler.strength == "S1C"  # follow the phase's attribute


def test_code_and_phase_of_one_attribute_preferred(tmp_path: Path) -> None:
    # C1C is the better code, but only W has both code and phase
    obs = _file(tmp_path, ["G01"], ["C1C", "C1W", "L1W"])
    assert _labels(obs, "G")[0] == "C1W/L1W"
    # with no common attribute each is the best of its kind
    obs = _file(tmp_path, ["G01"], ["C1C", "L1W"])
    assert _labels(obs, "G")[0] == "C1C/L1W"


def test_unlisted_attribute_used_and_blank_columns_skipped(tmp_path: Path) -> None:
    obs = _file(tmp_path, ["G01"], ["C1X", "L1X"])  # X is not in RTKLIB's L1 list: still used
    assert _labels(obs, "G") == ("C1X/L1X", "", "")
    obs = _file(tmp_path, ["G01"], ["C1C", "L1C", "C1X", "L1X"], blank=("C1C", "L1C"))
    assert _labels(obs, "G")[0] == "C1X/L1X"


def test_galileo_beidou_qzss_glonass_bands(tmp_path: Path) -> None:
    codes = [
        "C1C", "L1C", "C1X", "L1X", "C2I", "L2I", "C7I", "L7I", "C5Q", "L5Q", "C6I", "L6I", "C2C", "L2C",
        "C2P", "L2P", "C3Q", "L3Q", "C4X", "L4X", "C2L", "L2L",
    ]  # fmt: skip
    obs = _file(tmp_path, ["G01", "R01", "E01", "C01", "J01"], codes)
    assert _labels(obs, "E") == ("C1C/L1C", "C7I/L7I", "C5Q/L5Q")  # E1, E5b (band 7), E5a (band 5)
    assert _labels(obs, "C") == ("C2I/L2I", "C7I/L7I", "C6I/L6I")  # B1I band 2 (3.04), B2I, B3I
    assert _labels(obs, "J") == ("C1C/L1C", "C2L/L2L", "C5Q/L5Q")  # QZSS L2: "LSX"
    assert _labels(obs, "R") == ("C1C/L1C", "C2P/L2P", "C3Q/L3Q")  # G1 C, G2 P before C; band 4 ignored


def test_beidou_b1i_band_depends_on_version(tmp_path: Path) -> None:
    codes = ["C1I", "L1I", "C7I", "L7I"]
    assert _labels(_file(tmp_path, ["C06"], codes, version="3.02"), "C")[0] == "C1I/L1I"
    # from RINEX 3.03 on band 1 is B1C (1575.42 MHz), another carrier
    assert _labels(_file(tmp_path, ["C06"], codes, version="3.04"), "C")[0] == ""
    both = _file(tmp_path, ["C06"], ["C1I", "L1I", "C2I", "L2I"], version="3.02")
    assert _labels(both, "C")[0] == "C2I/L2I"


def test_rinex2_codes() -> None:
    obs = read_obs(geonet_dir() / "07590920.05o")  # L1 C1 L2 P2
    assert _labels(obs, "G") == ("C1/L1", "P2/L2", "")
    assert _labels(obs, "E") == ("", "", "")


@pytest.mark.parametrize("band1", ["C1", "P1"])
def test_rinex2_band1_prefers_c1(tmp_path: Path, band1: str) -> None:
    text = (geonet_dir() / "07590920.05o").read_text()
    text = text.replace("     4    L1    C1    L2    P2", f"     4    L1    {band1}    L2    P2")
    p = tmp_path / "x.05o"
    p.write_text(text)
    assert _labels(read_obs(p), "G")[0] == f"{band1}/L1"


def test_rinex2_mixed_file(tmp_path: Path) -> None:
    # the GEONET file relabelled as a mixed file in which G03 is GLONASS R03 and G07 Galileo E07
    text = (geonet_dir() / "07590920.05o").read_text()
    text = text.replace("G (GPS)  ", "M (MIXED)").replace("8G 3G 7G 8", "8R 3E 7G 8")
    p = tmp_path / "mixed.05o"
    p.write_text(text)
    obs = read_obs(p)
    assert {"R03", "E07", "G08"} <= set(obs.sats)
    assert _labels(obs, "R") == ("C1/L1", "P2/L2", "")  # G1 C/A first, G2 P first ("PCABX")
    assert _labels(obs, "E") == ("C1/L1", "", "")  # Galileo has no band 2
    assert _labels(obs, "G") == ("C1/L1", "P2/L2", "")


def test_a_phase_every_file_has_is_preferred_and_mixed_modes_warned(tmp_path: Path) -> None:
    import warnings

    from gnssatt.gnss.session_input import MixedTrackingWarning, session_input

    # Base: L1C and L1W (RTKLIB's priority takes C); rover: L1W only. Paired per file, a double difference
    # would mix C/A and P(Y) phases; the common mode W is chosen for both.
    (tmp_path / "a").mkdir()
    (tmp_path / "b").mkdir()
    base = _file(tmp_path / "a", ["G01", "G02"], ["C1C", "L1C", "C1W", "L1W"])
    rover = _file(tmp_path / "b", ["G01", "G02"], ["C1W", "L1W"])
    assert _labels(base, "G")[0] == "C1C/L1C"
    with warnings.catch_warnings():
        warnings.simplefilter("error", MixedTrackingWarning)
        si = session_input([base, rover], systems="G", frequencies=1)
    assert [codes["G"][0] for codes in si.signal_codes.values()] == ["C1W/L1W", "C1W/L1W"]
    # No phase in common: each file keeps its own, with a warning naming both.
    (tmp_path / "c").mkdir()
    other = _file(tmp_path / "c", ["G01", "G02"], ["C1C", "L1C"])
    with pytest.warns(MixedTrackingWarning, match="L1C in .* L1W in|L1W in .* L1C in"):
        session_input([other, rover], systems="G", frequencies=1)
