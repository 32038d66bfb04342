"""The navigation reader's walk over the records (``gnssatt_core::rinex::nav``) on files edited from a real
one: the faults that the Python loop it replaced met as exceptions of the language read as they did then
(the message of ``gnssatt.rinex._fields.reading``), a file cut in its last record gives the records before
it, and a RINEX 4 file's records are told apart by their markers. The whole corpus and 1,400 mutants are
compared bit for bit with the Python loop by ``benches/python/rinex_nav_equal.py``."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from gnssatt.errors import RecordsSkippedWarning, RinexError
from gnssatt.rinex import read_nav

SEPT = Path(__file__).parent / "data" / "real" / "SEPT2650_excerpt.21P"
#: The first record (G06) starts on line 11 of the excerpt; its broadcast orbit 2 is line 13.
G06 = 11


def _edited(tmp_path: Path, edit: dict[int, str | None], cut_end: bool = False) -> Path:
    """The excerpt with lines replaced (1-based; None removes the line), optionally without its final line
    end."""
    lines = SEPT.read_text().split("\n")[:-1]
    for lineno in sorted(edit, reverse=True):
        new = edit[lineno]
        if new is None:
            del lines[lineno - 1]
        else:
            lines[lineno - 1] = new
    p = tmp_path / "edited.rnx"
    p.write_text("\n".join(lines) + ("" if cut_end else "\n"))
    return p


def _line(lineno: int) -> str:
    return SEPT.read_text().split("\n")[lineno - 1]


def test_the_excerpt_reads_its_records() -> None:
    nav = read_nav(SEPT)
    assert nav.kepler.sats.tolist()[:3] == ["G06", "E18", "J07"]
    assert nav.leap_seconds == 18
    # GPSA line: 8.3819E-09 ...
    assert nav.iono_alpha[0] == 8.3819e-09
    # G06: sqrt(A) 5.153581537247E+03 (line 13, field 4), week 2176, toe 266400 s of week 2176
    assert nav.kepler.fields["sqrt_a"][0] == 5.153581537247e03
    assert nav.kepler.toe_ns[0] == (2176 * 604_800 + 266_400) * 1_000_000_000


def test_a_square_of_sqrt_a_that_overflows_is_refused_on_the_last_line_read(tmp_path: Path) -> None:
    line = _line(G06 + 2)
    p = _edited(tmp_path, {G06 + 2: line[:61] + " 1.00000000000D+200"})
    with pytest.raises(RinexError, match=r"OverflowError: \(34, 'Numerical result out of range'\)") as e:
        read_nav(p)
    assert e.value.line == G06 + 7


def test_a_record_start_shorter_than_its_separators_is_refused(tmp_path: Path) -> None:
    p = _edited(tmp_path, {G06: "G06 2021 09 22"})
    with pytest.raises(RinexError, match=r"IndexError: string index out of range") as e:
        read_nav(p)
    assert e.value.line == G06


def test_a_broadcast_field_cut_short_is_named(tmp_path: Path) -> None:
    p = _edited(tmp_path, {G06 + 1: _line(G06 + 1)[:30]})
    cut = r"the line ends inside broadcast field 2 \(a field cut short\)"
    with pytest.raises(RinexError, match=cut) as e:
        read_nav(p)
    assert e.value.line == G06 + 1


def test_an_unknown_system_letter_is_quoted(tmp_path: Path) -> None:
    p = _edited(tmp_path, {G06: "X" + _line(G06)[1:]})
    with pytest.raises(RinexError, match=r"unknown satellite system 'X' in a navigation record"):
        read_nav(p)


def test_a_file_cut_inside_its_last_line_keeps_the_records_before_it(tmp_path: Path) -> None:
    lines = SEPT.read_text().split("\n")[:-1]
    n = len(lines)
    p = _edited(tmp_path, {n: lines[n - 1][:30]}, cut_end=True)
    with pytest.warns(RecordsSkippedWarning, match="record left out: the file ends inside it"):
        nav = read_nav(p)
    assert len(nav.kepler) + len(nav.glonass) == len(read_nav(SEPT).kepler) + len(read_nav(SEPT).glonass) - 1


def test_rinex4_markers_choose_the_records(tmp_path: Path) -> None:
    lines = SEPT.read_text().split("\n")
    header = lines[: G06 - 1]
    header[0] = "     4.00" + header[0][9:]
    g06 = lines[G06 - 1 : G06 + 7]
    ion = [
        "> ION G06 LNAV",
        "    2021 09 22 02 00 00 1.000000000000E-08 2.000000000000E-08 3.000000000000E-08",
        "     4.000000000000E-08 5.000000000000E+04 6.000000000000E+04 7.000000000000E+04",
        "     8.000000000000E+04 1.000000000000E+00",
    ]
    body = ["> STO G06 LNAV", "    only counted", "> EPH G06 LNAV", *g06]
    body += ["> EPH G06 CNAV", "    counted", *ion]
    p = tmp_path / "v4.rnx"
    p.write_text("\n".join(header[:2] + header[-2:] + body) + "\n")
    with pytest.warns(RecordsSkippedWarning, match="STO G LNAV x1, EPH G CNAV x1"):
        nav = read_nav(p)
    assert nav.kepler.sats.tolist() == ["G06"]
    assert nav.skipped == {"STO G LNAV": 1, "EPH G CNAV": 1}
    # the header has no IONOSPHERIC CORR lines here: the ION record gives alpha and beta
    np.testing.assert_array_equal(nav.iono_alpha, [1e-8, 2e-8, 3e-8, 4e-8])
    np.testing.assert_array_equal(nav.iono_beta, [5e4, 6e4, 7e4, 8e4])
