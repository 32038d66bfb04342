"""Real files in (issue 27): excerpts of real receivers' and networks' files that were refused or lost, now
read; invalid values refused naming file, line, expected and got; unusable records skipped with one warning
per kind. Files and their provenance: ``tests/data/README.md``."""

from __future__ import annotations

import warnings
from collections.abc import Callable
from pathlib import Path
from typing import TypeVar

import numpy as np
import pytest

from gnssatt.errors import RecordsSkippedWarning, RinexError
from gnssatt.gnss.session_input import MixedTrackingWarning, session_input
from gnssatt.rinex import read_nav, read_obs

REAL = Path(__file__).resolve().parent / "data" / "real"
T = TypeVar("T")


def _copy(tmp_path: Path, name: str, edit: tuple[str, str] | None = None, *, strip_end: bool = False) -> Path:
    text = (REAL / name).read_bytes().decode("ascii")
    if edit is not None:
        assert edit[0] in text
        text = text.replace(edit[0], edit[1], 1)
    if strip_end:
        text = text.rstrip("\n")
    p = tmp_path / name
    p.write_bytes(text.encode("ascii"))
    return p


def _quiet_read(reader: Callable[[Path], T], path: Path) -> tuple[T, list[str]]:
    """What ``reader`` returns, and the messages of the RecordsSkippedWarnings it issued."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        out = reader(path)
    return out, [str(w.message) for w in caught if issubclass(w.category, RecordsSkippedWarning)]


# --- observation headers ---------------------------------------------------------------------------------


def test_septentrio_x1_channel_column_read_past() -> None:
    plain, _ = _quiet_read(read_obs, REAL / "SEPT265G_excerpt.21O")
    x1, said = _quiet_read(read_obs, REAL / "SEPT265G_X1_excerpt.21O")
    assert x1.unused_codes == ("E X1", "G X1", "J X1")
    assert len(said) == 1 and "3 observation codes read past" in said[0] and "G X1" in said[0]
    # the codes used keep their meaning: the same codes and values as the file without the column
    assert x1.codes == plain.codes and x1.obs_types == plain.obs_types
    np.testing.assert_array_equal(x1.data, plain.data)
    np.testing.assert_array_equal(x1.lli, plain.lli)
    assert len(x1.time) == 2 and x1.sats == plain.sats


def test_two_character_and_unknown_codes_read_past(tmp_path: Path) -> None:
    # an unknown attribute and a receiver's own type in place of codes of the Trimble header
    p = _copy(tmp_path, "3034265G_excerpt.21O", ("C5X L5X D5X S5X      SYS", "C5X L5R D5X Y5X      SYS"))
    obs, said = _quiet_read(read_obs, p)
    assert set(obs.unused_codes) == {"E L5R", "E Y5X"} and len(said) == 1
    assert "L5R" not in obs.codes and "C5X" in obs.obs_types["E"]


def test_repeated_code_still_refused(tmp_path: Path) -> None:
    p = _copy(tmp_path, "3034265G_excerpt.21O", ("C1X L1X D1X S1X", "C1X L1X D1X L1X"))
    with pytest.raises(RinexError, match=r"line 8: expected distinct observation codes, got 'L1X' twice"):
        read_obs(p)


# --- cut files, header-only files ------------------------------------------------------------------------


def test_euref_file_cut_inside_its_last_epoch() -> None:
    obs, said = _quiet_read(read_obs, REAL / "rovn0010_excerpt.21o")
    # the excerpt keeps the last complete epoch (line 162) and the cut one (line 224)
    assert obs.time.tolist() == [np.datetime64("2021-01-01T02:25:30", "ns").astype(int)]
    assert len(said) == 1 and "the epoch at line 224 announces 20 satellites" in said[0]


def test_file_cut_inside_a_number_of_its_last_line(tmp_path: Path) -> None:
    text = (REAL / "3034265G_excerpt.21O").read_text()
    p = tmp_path / "cut.21O"
    p.write_text(text[: text.rstrip("\n").rfind(".") + 2])  # inside the last number
    obs, said = _quiet_read(read_obs, p)
    assert len(obs.time) == 2 and len(said) == 1 and "cut at line" in said[0]


def test_header_only_file_reads_as_zero_epochs_and_the_engine_says_so() -> None:
    empty, said = _quiet_read(read_obs, REAL / "blank.10o")
    assert len(empty.time) == 0 and empty.data.shape == (0, 0, 7) and not said
    full, _ = _quiet_read(read_obs, REAL / "3034265G_excerpt.21O")
    with pytest.raises(RinexError, match=r"blank\.10o: the observation file holds no epochs"):
        session_input([full, empty])


# --- invalid header values -------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("edit", "message"),
    [
        (
            ("  2021     9    22     6    30", "  2021    13    22     6    30"),
            r"line 28: epoch 2021-13-22 06:30:0: not a calendar date \(month 13, day 22\)",
        ),
        (
            ("     1.000", "   -30.000"),
            r"line 27: expected INTERVAL as a positive number of seconds, got -30.000",
        ),
        (
            ("     1.000", "     0.000"),
            r"line 27: expected INTERVAL as a positive number of seconds, got 0.000",
        ),
    ],
)
def test_impossible_header_values_refused(tmp_path: Path, edit: tuple[str, str], message: str) -> None:
    with pytest.raises(RinexError, match=r"SEPT265G_excerpt\.21O, " + message):
        read_obs(_copy(tmp_path, "SEPT265G_excerpt.21O", edit))


# --- navigation -------------------------------------------------------------------------------------------


def test_rinex2_galileo_navigation_with_e18() -> None:
    nav, said = _quiet_read(read_nav, REAL / "ceda2100_excerpt.18e")
    assert nav.kepler.sats.tolist() == ["E05", "E18", "E19"] and not said
    e18 = nav.kepler.fields["e"][1]
    assert e18 == pytest.approx(0.1659004657995)
    # GAL week 2012 (aligned with GPS weeks), toe 10200 s of week
    assert nav.kepler.toe_ns[0] == (2012 * 604_800 + 10_200) * 10**9


def test_eccentric_galileo_orbits_kept() -> None:
    nav, said = _quiet_read(read_nav, REAL / "BRUX00BEL_excerpt_EN.rnx")
    assert nav.kepler.sats.tolist() == ["E02", "E14", "E18"] and not said
    assert np.all(nav.kepler.fields["e"][1:] > 0.16)
    nav, _ = _quiet_read(read_nav, REAL / "SEPT2650_excerpt.21P")
    assert "E18" in nav.kepler.sats.tolist()


def test_navigation_without_final_line_end(tmp_path: Path) -> None:
    whole, _ = _quiet_read(read_nav, REAL / "BRUX00BEL_excerpt_EN.rnx")
    nav, said = _quiet_read(read_nav, _copy(tmp_path, "BRUX00BEL_excerpt_EN.rnx", strip_end=True))
    assert nav.kepler.sats.tolist() == whole.kepler.sats.tolist() and not said
    np.testing.assert_array_equal(nav.kepler.fields["sqrt_a"], whole.kepler.fields["sqrt_a"])


def test_rinex3_sbas_counted_in_skipped() -> None:
    nav, said = _quiet_read(read_nav, REAL / "ESBC00DNK_excerpt_MN.rnx")
    assert nav.kepler.sats.tolist() == ["C05", "G01"] and nav.skipped == {"EPH S SBAS": 1}
    assert len(said) == 1 and "EPH S SBAS x1" in said[0]


# the E02 record: broadcast orbit 2 (line 10) holds Cuc, e, Cus, sqrt(A)
_E02_ORBIT2 = "     4.472211003304E-06 4.126706626266E-04 8.661299943924E-06 5.440621263504E+03"


@pytest.mark.parametrize(
    ("value", "message"),
    [
        ((None, "-5.440621263504E+03"), r"expected sqrt\(A\) > 0 m\^0.5 \(broadcast field 4\), got -5440.62"),
        ((None, " 0.000000000000E+00"), r"expected sqrt\(A\) > 0 m\^0.5 \(broadcast field 4\), got 0.0"),
        (
            ("1.000000000000E+00", None),
            r"expected an eccentricity in \[0, 1\) \(broadcast field 2\), got 1.0",
        ),
        (
            ("-4.12670662627E-04", None),
            r"expected an eccentricity in \[0, 1\) \(broadcast field 2\), got -0.0004",
        ),
    ],
)
def test_impossible_orbits_refused(
    tmp_path: Path, value: tuple[str | None, str | None], message: str
) -> None:
    e, sqrt_a = value
    line = _E02_ORBIT2
    if e is not None:
        line = line[:23] + e.rjust(19) + line[42:]
    if sqrt_a is not None:
        line = line[:61] + sqrt_a.rjust(19)
    with pytest.raises(RinexError, match=r"BRUX00BEL_excerpt_EN\.rnx, line 10: " + message):
        read_nav(_copy(tmp_path, "BRUX00BEL_excerpt_EN.rnx", (_E02_ORBIT2, line)))


def test_orbit_inside_the_earth_skipped_with_a_warning(tmp_path: Path) -> None:
    # the values of the BeiDou C16 records of issue 27 put into the E02 record: a valid ellipse, not an orbit
    line = _E02_ORBIT2[:23] + " 4.900000000000E-01" + _E02_ORBIT2[42:61] + " 1.992000000000E+03"
    nav, said = _quiet_read(read_nav, _copy(tmp_path, "BRUX00BEL_excerpt_EN.rnx", (_E02_ORBIT2, line)))
    assert nav.kepler.sats.tolist() == ["E14", "E18"]
    assert len(said) == 1 and "1 Keplerian records skipped: not an orbit" in said[0]
    assert "E02 at line 8 (sqrt(A) 1992 m^0.5, e 0.49)" in said[0]


# --- SYS / PHASE SHIFT ------------------------------------------------------------------------------------


def test_phase_shift_records_read_and_honoured() -> None:
    trimble, _ = _quiet_read(read_obs, REAL / "3034265G_excerpt.21O")
    sept, _ = _quiet_read(read_obs, REAL / "SEPT265G_excerpt.21O")
    assert trimble.phase_shift_cycles["G"]["L2X"] == (-0.25, ())
    assert trimble.phase_shift_cycles["G"]["L1C"] == (0.0, ())  # the reference signal: blank correction
    assert sept.phase_shift_cycles["J"]["L2L"] == (0.0, ())
    # both files declare their phases aligned: different modes of a band pair without a warning
    with warnings.catch_warnings():
        warnings.simplefilter("error", MixedTrackingWarning)
        si = session_input([trimble, sept], systems="GEJ")
    assert si.signal_codes[trimble.path]["E"][0] == "C1X/L1X"
    assert si.signal_codes[sept.path]["E"][0] == "C1C/L1C"


def test_mixed_tracking_without_phase_shift_records_warns(tmp_path: Path) -> None:
    text = (REAL / "SEPT265G_excerpt.21O").read_text()
    p = tmp_path / "noshift.21O"
    p.write_text("".join(ln for ln in text.splitlines(keepends=True) if "SYS / PHASE SHIFT" not in ln))
    trimble, _ = _quiet_read(read_obs, REAL / "3034265G_excerpt.21O")
    sept, _ = _quiet_read(read_obs, p)
    with pytest.warns(MixedTrackingWarning, match="system E slot 1"):
        session_input([trimble, sept], systems="GEJ")


def test_rinex3_navic_counted_in_skipped(tmp_path: Path) -> None:
    # no NavIC record in the stored corpus: the excerpt's GPS record relabelled I01 (the layouts agree)
    p = _copy(tmp_path, "ESBC00DNK_excerpt_MN.rnx", ("\nG01 2020 06 25", "\nI01 2020 06 25"))
    nav, said = _quiet_read(read_nav, p)
    assert nav.kepler.sats.tolist() == ["C05"]
    assert nav.skipped == {"EPH S SBAS": 1, "EPH I LNAV": 1}
    assert len(said) == 1 and "2 records skipped" in said[0]
