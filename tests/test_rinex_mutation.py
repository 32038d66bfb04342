"""Mutation tests of the RINEX readers: every file is read clean, then mutated one way at a time.

The files: the four navigation files of ``tests/data`` (RINEX 3.02-3.04), a RINEX 2.11 GPS navigation file
made from the GPS records of one of them, and two observation files written here from known values (RINEX
2.11 with a 13-satellite epoch and two lines per satellite; RINEX 3.04 with GPS and Galileo, a clock offset
and a leap-second label). For each mutation the reader either returns what a careful reading gives (stated
per test, from the clean reading or from the values written) or raises :class:`RinexError` whose message
names the file and a line at or before the mutated one; never another exception.

Random byte flips (fixed seed) cannot name one expected reading, so there the test checks what a single
changed byte allows: a ``RinexError`` naming the file, or a reading in which at most one epoch (one
navigation record) differs from the clean one and everything is finite or NaN. A flipped byte in a header
label can only be noticed where the label is missing, so flips are not held to the line bound.
"""

from __future__ import annotations

import math
import warnings
from collections import Counter
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from gnssatt.errors import RecordsSkippedWarning, RinexError
from gnssatt.rinex import RinexNav, RinexObs, read_nav, read_obs

DATA = Path(__file__).resolve().parent / "data"
NAV_FILES = sorted(DATA.glob("*.rnx"))
SEED = 20261202

# --- the observation files, from known values -----------------------------------------------------------

V2_TYPES = ("L1", "C1", "L2", "P2", "S1", "S2")
V2_EPOCHS = (  # (h, m, s), satellites
    ((0, 0, 0.0), (3, 7, 8, 11, 13, 14, 16, 19, 20, 23, 24, 27, 28)),
    ((0, 0, 30.0), (3, 7, 8, 11)),
    ((0, 1, 0.0), (3, 7, 8, 11, 19)),
)
V3_TYPES = {"G": ("C1C", "L1C", "D1C", "S1C", "C2W", "L2W"), "E": ("C1C", "L1C", "C5Q", "L5Q")}
V3_EPOCHS = (  # (y, mo, d, h, m, s), clock offset or None, satellites
    ((2016, 12, 31, 23, 58, 30.0), -1.25e-4, ("G05", "G12", "E11", "E24")),
    ((2016, 12, 31, 23, 59, 0.0), None, ("G05", "G12", "G25", "E11")),
    ((2016, 12, 31, 23, 59, 60.0), 2.5e-5, ("G05", "G25", "E11", "E24")),  # the leap second
    ((2017, 1, 1, 0, 0, 30.0), None, ("G05", "G12", "G25", "E24")),
)


def _value(e: int, sat: str, k: int) -> float | None:
    """The observation written for epoch ``e``, satellite ``sat``, field ``k`` (None: blank)."""
    prn = int(sat[1:])
    if (prn + e + k) % 7 == 0:
        return None
    return round(2.0e7 + 1.0e5 * prn + 1.0e3 * k + 30.123 * e - 0.001 * prn * k, 3) * (-1 if k == 2 else 1)


def _indicators(e: int, sat: str, k: int) -> str:
    prn = int(sat[1:])
    lli = str((prn + k) % 3) if (prn + e) % 2 else " "
    return lli + (str(1 + (prn + k) % 9) if k % 2 else " ")


def _fields(e: int, sat: str, n: int) -> list[str]:
    out = []
    for k in range(n):
        v = _value(e, sat, k)
        out.append(" " * 16 if v is None else f"{v:14.3f}{_indicators(e, sat, k)}")
    return out


def _hdr(text: str, label: str) -> str:
    return f"{text:<60}{label:<20}\n"


def rinex2_obs() -> str:
    out = [
        _hdr("     2.11           OBSERVATION DATA    G (GPS)", "RINEX VERSION / TYPE"),
        _hdr("MUTANT", "MARKER NAME"),
        _hdr(" -3976219.5082  3382372.5671  3652512.9849", "APPROX POSITION XYZ"),
        _hdr("        0.0000        0.0000        0.0000", "ANTENNA: DELTA H/E/N"),
        _hdr(f"{len(V2_TYPES):6d}" + "".join(f"{t:>6}" for t in V2_TYPES), "# / TYPES OF OBSERV"),
        _hdr("    30.000", "INTERVAL"),
        _hdr("  2005     4     2     0     0    0.0000000     GPS", "TIME OF FIRST OBS"),
        _hdr("", "END OF HEADER"),
    ]
    for e, ((h, m, s), prns) in enumerate(V2_EPOCHS):
        ids = [f"G{p:02d}" for p in prns]
        head = f" 05  4  2 {h:2d} {m:2d}{s:11.7f}  0{len(ids):3d}"
        first = head + "".join(ids[:12])
        out.append(f"{first:<68}{-0.000123456 * (e + 1):12.9f}\n")
        if len(ids) > 12:
            out.append(" " * 32 + "".join(ids[12:]) + "\n")
        for sat in ids:
            f = _fields(e, sat, len(V2_TYPES))
            out += ["".join(f[0:5]).rstrip() + "\n", "".join(f[5:]).rstrip() + "\n"]
    return "".join(out)


def rinex3_obs() -> str:
    out = [
        _hdr("     3.04           OBSERVATION DATA    M", "RINEX VERSION / TYPE"),
        _hdr("MUTANT", "MARKER NAME"),
        _hdr("   4027881.6   307045.6  4919475.0", "COMMENT"),
    ]
    for s, codes in V3_TYPES.items():
        out.append(_hdr(f"{s}  {len(codes):3d} " + " ".join(codes), "SYS / # / OBS TYPES"))
    out += [
        _hdr("  2016    12    31    23    58   30.0000000     GPS", "TIME OF FIRST OBS"),
        _hdr("", "END OF HEADER"),
    ]
    for e, ((y, mo, d, h, mi, s), clk, sats) in enumerate(V3_EPOCHS):
        line = f"> {y:4d} {mo:02d} {d:02d} {h:02d} {mi:02d}{s:11.7f}  0{len(sats):3d}"
        out.append(line + (f"{'':6}{clk:15.12f}" if clk is not None else "") + "\n")
        for sat in sats:
            out.append(sat + "".join(_fields(e, sat, len(V3_TYPES[sat[0]]))).rstrip() + "\n")
    return "".join(out)


def rinex2_nav() -> str:
    """The GPS records of the DLR file in RINEX 2.11 layout (the same numbers, 2-digit years)."""
    src = (DATA / "BRDM00DLR_R_20130010000_01D_MN.rnx").read_text().splitlines()
    body = src[[ln[60:].strip() for ln in src].index("END OF HEADER") + 1 :]
    out = [
        _hdr("     2.11           N: GPS NAV DATA", "RINEX VERSION / TYPE"),
        _hdr("    16", "LEAP SECONDS"),
        _hdr("", "END OF HEADER"),
    ]
    for r in range(0, 8 * 4, 8):
        head = body[r]
        assert head[0] == "G"
        y, mo, d, h, mi, s = (int(x) for x in head[4:23].split())
        out.append(f"{int(head[1:3]):2d} {y % 100:02d} {mo:2d} {d:2d} {h:2d} {mi:2d}{s:5.1f}{head[23:]}\n")
        out += [ln[1:].rstrip() + "\n" for ln in body[r + 1 : r + 8]]
    return "".join(out)


OBS_TEXTS: dict[str, Callable[[], str]] = {"mut.05o": rinex2_obs, "mut.16o": rinex3_obs}


def _obs_text(name: str) -> str:
    return OBS_TEXTS[name]()


def _nav_text(name: str) -> str:
    if name == "mut.13n":
        return rinex2_nav()
    with open(DATA / name, newline="") as fh:  # as stored, CRLF line ends included
        return fh.read()


NAV_NAMES = [p.name for p in NAV_FILES] + ["mut.13n"]

# --- readings as comparable multisets --------------------------------------------------------------------


def _key(x: float) -> Any:
    return None if math.isnan(x) else x


def obs_rows(obs: RinexObs) -> Counter[tuple[Any, ...]]:
    """One row per epoch and one per observed satellite and epoch; values in the order of their system's
    type list (a renamed code does not move them)."""
    rows: Counter[tuple[Any, ...]] = Counter()
    for e, t in enumerate(obs.time.astype(np.int64)):
        head = (int(t), int(obs.epoch_flag[e]), _key(float(obs.clock_offset_s[e])))
        rows[(*head, "epoch")] += 1
        for s, sat in enumerate(obs.sats):
            order = obs.obs_types.get(sat[0], obs.codes)
            cols = [obs.codes.index(c) for c in order]
            vals = obs.data[e, s, cols]
            if np.isnan(vals).all():
                continue
            rows[
                (*head, sat, tuple(map(_key, vals)), tuple(obs.lli[e, s, cols]), tuple(obs.ssi[e, s, cols]))
            ] += 1
    return rows


def nav_rows(nav: RinexNav) -> Counter[tuple[Any, ...]]:
    k, g = nav.kepler, nav.glonass
    rows: Counter[tuple[Any, ...]] = Counter()
    for i in range(len(k)):
        rows[
            (
                str(k.sats[i]),
                int(k.toc_ns[i]),
                int(k.toe_ns[i]),
                *k.af[i],
                *(k.fields[f][i] for f in k.fields),
            )
        ] += 1
    for i in range(len(g)):
        rows[(str(g.sats[i]), int(g.tb_ns[i]), *g.position_m[i], *g.velocity_m_s[i], int(g.channel[i]))] += 1
    return rows


def _write(tmp_path: Path, name: str, text: str | bytes) -> Path:
    p = tmp_path / name
    p.write_bytes(text if isinstance(text, bytes) else text.encode("latin-1"))
    return p


def _refused(reader: Callable[[Path], object], path: Path, at_or_before: int | None) -> RinexError:
    """The reader raises RinexError naming the file and a line (at or before ``at_or_before``)."""
    with pytest.raises(RinexError) as info:
        reader(path)
    err = info.value
    assert path.name in str(err)
    assert err.line is not None and f"line {err.line}" in str(err)
    if at_or_before is not None:
        assert 1 <= err.line <= at_or_before, (str(err), at_or_before)
    return err


def _epoch_lines(text: str, v3: bool) -> list[int]:
    """0-based indices of the epoch lines of one of the observation files written here."""
    lines = text.splitlines()
    end = [ln[60:].strip() for ln in lines].index("END OF HEADER")
    if v3:
        return [i for i, ln in enumerate(lines) if ln.startswith(">")]
    return [i for i, ln in enumerate(lines) if i > end and ln[:4] == " 05 "]


def _record_lines(text: str) -> list[int]:
    """0-based indices of the first lines of the records of a navigation file."""
    lines = text.splitlines()
    end = [ln[60:].strip() for ln in lines].index("END OF HEADER")
    # continuation lines start with 3 (RINEX 2) or 4 blanks; a record starts with its satellite
    return [i for i, ln in enumerate(lines) if i > end and ln[:3].strip()]


def _set(line: str, a: int, b: int, text: str) -> str:
    return line[:a] + text.rjust(b - a)[: b - a] + line[b:]


# --- clean files ------------------------------------------------------------------------------------------


def test_written_observation_files_read_as_written(tmp_path: Path) -> None:
    for name, epochs, is_v3 in (("mut.05o", V2_EPOCHS, False), ("mut.16o", V3_EPOCHS, True)):
        obs = read_obs(_write(tmp_path, name, _obs_text(name)))
        assert len(obs.time) == len(epochs)
        for e, ep in enumerate(epochs):
            sats = ep[-1] if is_v3 else tuple(f"G{p:02d}" for p in ep[1])
            for sat in sats:
                codes = V3_TYPES[sat[0]] if is_v3 else V2_TYPES
                s = obs.sats.index(sat)
                for k, c in enumerate(codes):
                    want = _value(e, sat, k)
                    got = obs.data[e, s, obs.codes.index(c)]
                    assert (math.isnan(got) and want is None) or got == want
                    if want is not None:
                        lli, ssi = _indicators(e, sat, k)
                        assert obs.lli[e, s, obs.codes.index(c)] == (0 if lli == " " else int(lli))
                        assert obs.ssi[e, s, obs.codes.index(c)] == (0 if ssi == " " else int(ssi))
    # the leap second 2016-12-31 23:59:60 is kept as 2017-01-01 00:00:00 (datetime64 has none)
    assert str(obs.time[2]) == "2017-01-01T00:00:00.000000000"
    assert obs.clock_offset_s[0] == -1.25e-4 and math.isnan(obs.clock_offset_s[1])


def test_rinex2_navigation_made_here_matches_its_source(tmp_path: Path) -> None:
    v2 = read_nav(_write(tmp_path, "mut.13n", rinex2_nav())).kepler
    v3 = read_nav(DATA / "BRDM00DLR_R_20130010000_01D_MN.rnx").kepler
    assert list(v2.sats) == list(v3.sats[:4])
    np.testing.assert_array_equal(v2.toe_ns, v3.toe_ns[:4])
    np.testing.assert_array_equal(v2.af, v3.af[:4])


# --- dates -----------------------------------------------------------------------------------------------

OBS_DATE_SLICES = {False: ((1, 3), (4, 6), (7, 9), (10, 12), (13, 15), (15, 26)),
                   True: ((2, 6), (7, 9), (10, 12), (13, 15), (16, 18), (18, 29))}  # fmt: skip
NAV_DATE_SLICES = {False: ((3, 5), (6, 8), (9, 11), (12, 14), (15, 17), (17, 22)),
                   True: ((4, 8), (9, 11), (12, 14), (15, 17), (18, 20), (21, 23))}  # fmt: skip
BAD_DATES = [(1, "13"), (1, "0"), (2, "32"), (2, "0"), (3, "24"), (3, "25"), (4, "60"), (5, "61")]


@pytest.mark.parametrize("name", OBS_TEXTS)
@pytest.mark.parametrize(("field", "value"), [*BAD_DATES, (5, "60.5"), (2, "31")])
def test_invalid_observation_dates(name: str, field: int, value: str, tmp_path: Path) -> None:
    text = _obs_text(name)
    v3 = name.endswith("16o")
    lines = text.splitlines(keepends=True)
    at = _epoch_lines(text, v3)[0]  # 2005-04-02 or 2016-12-31 23:58:30: no leap second, April has 30 days
    if (field, value) == (2, "31") and v3:
        lines[at] = _set(lines[at], *OBS_DATE_SLICES[v3][1], "11")  # November 31
    a, b = OBS_DATE_SLICES[v3][field]
    lines[at] = _set(lines[at], a, b, value if field < 5 else f"{float(value):11.7f}")
    err = _refused(read_obs, _write(tmp_path, name, "".join(lines)), at + 1)
    assert err.line == at + 1 and "epoch" in err.message


@pytest.mark.parametrize("name", NAV_NAMES)
@pytest.mark.parametrize(("field", "value"), BAD_DATES)
def test_invalid_navigation_dates(name: str, field: int, value: str, tmp_path: Path) -> None:
    text = _nav_text(name)
    v3 = not name.endswith("13n")
    lines = text.splitlines(keepends=True)
    at = _record_lines(text)[1]
    a, b = NAV_DATE_SLICES[v3][field]
    if field == 5:
        value = f"{float(value):5.1f}" if not v3 else value
    lines[at] = _set(lines[at], a, b, value)
    err = _refused(read_nav, _write(tmp_path, name, "".join(lines)), at + 1)
    assert err.line == at + 1


def test_leap_second_only_at_the_end_of_a_day(tmp_path: Path) -> None:
    text = _obs_text("mut.16o")
    lines = text.splitlines(keepends=True)
    leap = _epoch_lines(text, True)[2]
    lines[leap] = _set(lines[leap], 16, 18, "58")  # 23:58:60 is no leap second
    err = _refused(read_obs, _write(tmp_path, "mut.16o", "".join(lines)), leap + 1)
    assert "61 only at 23:59" in err.message


# --- order of epochs -------------------------------------------------------------------------------------


def _flat(blocks: list[list[str]]) -> list[str]:
    return [ln for b in blocks for ln in b]


def _blocks(text: str, v3: bool) -> tuple[list[str], list[list[str]]]:
    lines = text.splitlines(keepends=True)
    starts = _epoch_lines(text, v3)
    return lines[: starts[0]], [lines[a:b] for a, b in zip(starts, [*starts[1:], len(lines)], strict=True)]


@pytest.mark.parametrize("name", OBS_TEXTS)
def test_swapped_and_duplicated_epochs(name: str, tmp_path: Path) -> None:
    head, blocks = _blocks(_obs_text(name), name.endswith("16o"))
    swapped = [blocks[1], blocks[0], *blocks[2:]]
    last_mutated = len(head) + len(blocks[0]) + len(blocks[1])
    err = _refused(read_obs, _write(tmp_path, name, "".join(head + _flat(swapped))), last_mutated)
    assert "comes before the epoch at line" in err.message
    dup = [blocks[0], blocks[1], blocks[1], *blocks[2:]]
    second = len(head) + len(blocks[0]) + len(blocks[1]) + 1
    err = _refused(read_obs, _write(tmp_path, name, "".join(head + _flat(dup))), second)
    assert err.line == second and "repeats the epoch" in err.message


@pytest.mark.parametrize("name", NAV_NAMES)
def test_navigation_records_swapped_or_repeated_are_kept(name: str, tmp_path: Path) -> None:
    text = _nav_text(name)
    clean = nav_rows(read_nav(_write(tmp_path, name, text)))
    lines = text.splitlines(keepends=True)
    starts = _record_lines(text)
    a, b, c = starts[0], starts[1], starts[2]
    swapped = lines[:a] + lines[b:c] + lines[a:b] + lines[c:]
    assert nav_rows(read_nav(_write(tmp_path, name, "".join(swapped)))) == clean
    repeated = lines[:c] + lines[b:c] + lines[c:]
    got = nav_rows(read_nav(_write(tmp_path, name, "".join(repeated))))
    assert not clean - got and sum((got - clean).values()) == 1


# --- non-finite numbers ----------------------------------------------------------------------------------

NOT_NUMBERS = ["nan", "NaN", "inf", "-inf", "Infinity", "1e999", "1_000.5", "1.0.0"]


@pytest.mark.parametrize("name", OBS_TEXTS)
@pytest.mark.parametrize("word", NOT_NUMBERS)
def test_non_finite_observations_and_clock(name: str, word: str, tmp_path: Path) -> None:
    v3 = name.endswith("16o")
    text = _obs_text(name)
    lines = text.splitlines(keepends=True)
    ep = _epoch_lines(text, v3)[0]
    rec = ep + (1 if v3 else 2)  # the first record line (RINEX 2: after the list's continuation)
    col = 3 + 16 if v3 else 16  # the second field
    mutated = [*lines]
    mutated[rec] = _set(lines[rec], col, col + 14, word)
    err = _refused(read_obs, _write(tmp_path, name, "".join(mutated)), rec + 1)
    assert err.line == rec + 1
    clock = (41, 56) if v3 else (68, 80)
    mutated = [*lines]
    mutated[ep] = _set(lines[ep].rstrip("\n").ljust(clock[1]), *clock, word) + "\n"
    err = _refused(read_obs, _write(tmp_path, name, "".join(mutated)), ep + 1)
    assert err.line == ep + 1


@pytest.mark.parametrize("name", NAV_NAMES)
@pytest.mark.parametrize("word", NOT_NUMBERS)
def test_non_finite_broadcast_fields(name: str, word: str, tmp_path: Path) -> None:
    text = _nav_text(name)
    lines = text.splitlines(keepends=True)
    at = _record_lines(text)[-1] + 2  # a full orbit line of the last record
    start = 4 if not name.endswith("13n") else 3
    lines[at] = _set(lines[at], start + 19, start + 38, word)
    err = _refused(read_nav, _write(tmp_path, name, "".join(lines)), at + 1)
    assert err.line == at + 1


# --- truncation ------------------------------------------------------------------------------------------


@pytest.mark.parametrize("name", [*OBS_TEXTS, *NAV_NAMES])
def test_cut_inside_the_last_record(name: str, tmp_path: Path) -> None:
    is_obs = name in OBS_TEXTS
    text = (_obs_text if is_obs else _nav_text)(name)
    reader: Callable[[Path], Any] = read_obs if is_obs else read_nav
    rows: Callable[[Any], Counter[tuple[Any, ...]]] = obs_rows if is_obs else nav_rows  # type: ignore[assignment]
    raw = text.encode("latin-1")
    lines = raw.splitlines(keepends=True)
    starts = _epoch_lines(text, name.endswith("16o")) if is_obs else _record_lines(text)
    block = sum(len(ln) for ln in lines[: starts[-1]])
    clean = rows(reader(_write(tmp_path, name, raw)))
    without_last = rows(reader(_write(tmp_path, name, raw[:block])))
    assert sum((clean - without_last).values()) >= 1 and not without_last - clean
    start_line = starts[-1] + 1
    for cut in range(block + 1, len(raw), 5):
        piece = raw[:cut]
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            got = rows(reader(_write(tmp_path, name, piece)))
        said = [str(w.message) for w in caught if issubclass(w.category, RecordsSkippedWarning)]
        if got == without_last:
            # the last epoch (record) is left out, with a warning naming it; a cut leaving only blanks of
            # its first line leaves nothing to name
            if piece[piece.rfind(b"\n") + 1 :].strip():
                assert len(said) == 1 and f"line {start_line}" in said[0] and "file ends inside" in said[0]
        else:
            # cut after the numbers of its last line: the last epoch (record) is read, without the
            # indicators or blank fields after the cut; nothing before it changes
            assert not without_last - got and sum((got - without_last).values()) >= 1
            assert not said
            if is_obs:
                last = max(r[0] for r in clean)
                assert all(r[0] == last for r in got - without_last)
            else:
                assert sum((got - without_last).values()) == 1


# --- satellite counts and epoch flags --------------------------------------------------------------------


@pytest.mark.parametrize("name", OBS_TEXTS)
@pytest.mark.parametrize("delta", [-1, 1])
def test_satellite_count_off_by_one(name: str, delta: int, tmp_path: Path) -> None:
    v3 = name.endswith("16o")
    text = _obs_text(name)
    epochs = _epoch_lines(text, v3)
    for at in epochs:
        lines = text.splitlines(keepends=True)
        a, b = (32, 35) if v3 else (29, 32)
        lines[at] = _set(lines[at], a, b, str(int(lines[at][a:b]) + delta))
        path = _write(tmp_path, name, "".join(lines))
        if at == epochs[-1] and delta == 1:
            # the last epoch announcing more than the file holds is a file cut inside it: the epochs before
            # it are read and the warning names it
            with pytest.warns(RecordsSkippedWarning, match=f"the epoch at line {at + 1} announces"):
                obs = read_obs(path)
            assert len(obs.time) == len(epochs) - 1
            continue
        err = _refused(read_obs, path, at + 1)
        assert err.line == at + 1 and "satellites" in err.message


def _with_flag(name: str, epoch: int, flag: str) -> tuple[str, int]:
    v3 = name.endswith("16o")
    text = _obs_text(name)
    lines = text.splitlines(keepends=True)
    at = _epoch_lines(text, v3)[epoch]
    col = 31 if v3 else 28
    lines[at] = lines[at][:col] + flag + lines[at][col + 1 :]
    return "".join(lines), at


@pytest.mark.parametrize("name", OBS_TEXTS)
@pytest.mark.parametrize("flag", list("2345789X "))
def test_unknown_or_misused_epoch_flags(name: str, flag: str, tmp_path: Path) -> None:
    text, at = _with_flag(name, 1, flag)
    err = _refused(read_obs, _write(tmp_path, name, text), at + 1)
    assert err.line == at + 1
    if flag not in "2345":
        assert f"unknown epoch flag {flag!r}" in err.message


@pytest.mark.parametrize("name", OBS_TEXTS)
def test_flags_one_and_six_read_as_defined(name: str, tmp_path: Path) -> None:
    clean = read_obs(_write(tmp_path, name, _obs_text(name)))
    power = read_obs(_write(tmp_path, name, _with_flag(name, 1, "1")[0]))
    assert list(power.epoch_flag) == [0, 1, 0] + [0] * (len(clean.time) - 3)
    np.testing.assert_array_equal(power.data, clean.data)
    # flag 6: the records are cycle slips, not observations: the epoch is not an observation epoch
    slips = read_obs(_write(tmp_path, name, _with_flag(name, 1, "6")[0]))
    assert list(slips.time) == [t for k, t in enumerate(clean.time) if k != 1]
    keep = obs_rows(clean) - obs_rows(slips)
    assert {r[0] for r in keep} == {int(clean.time[1].astype(np.int64))}


@pytest.mark.parametrize("name", OBS_TEXTS)
def test_event_records_are_skipped(name: str, tmp_path: Path) -> None:
    """Flags 4 and 5 with header records and flag 6 with cycle-slip records, inserted before the second
    epoch, leave the reading as it was."""
    v3 = name.endswith("16o")
    text = _obs_text(name)
    clean = obs_rows(read_obs(_write(tmp_path, name, text)))
    head, blocks = _blocks(text, v3)
    comment = [_hdr("antenna moved back", "COMMENT"), _hdr("", "COMMENT")]
    if v3:
        events = [">" + " " * 30 + "4  2\n", *comment, blocks[0][0][:31] + "5  0\n"]
    else:
        events = [" " * 28 + "4  2\n", *comment, blocks[0][0][:28] + "5  0\n"]
    slip_head = blocks[0][0][: 31 if v3 else 28] + "6" + blocks[0][0][(32 if v3 else 29) :]
    slips = [slip_head, *blocks[0][1:]]
    text2 = "".join(head + blocks[0] + events + slips + _flat(blocks[1:]))
    assert obs_rows(read_obs(_write(tmp_path, name, text2))) == clean
    # a flag-4 record count that reaches into the observations is refused at the event line
    wrong = events[0].replace("4  2", "4  3")
    text3 = "".join(head + blocks[0] + [wrong] + events[1:] + _flat(blocks[1:]))
    line = len(head) + len(blocks[0]) + 1
    err = _refused(read_obs, _write(tmp_path, name, text3), line)
    assert err.line == line and "header records" in err.message


# --- random byte flips -----------------------------------------------------------------------------------


@pytest.mark.parametrize("name", [*OBS_TEXTS, *NAV_NAMES])
def test_random_byte_flips(name: str, tmp_path: Path) -> None:
    is_obs = name in OBS_TEXTS
    raw = ((_obs_text if is_obs else _nav_text)(name)).encode("latin-1")
    reader: Callable[[Path], Any] = read_obs if is_obs else read_nav
    clean = (obs_rows if is_obs else nav_rows)(reader(_write(tmp_path, name, raw)))  # type: ignore[operator]
    rng = np.random.default_rng(SEED)
    n_lines = raw.count(b"\n")
    for _ in range(150):
        pos = int(rng.integers(len(raw)))
        new = int(rng.integers(256))
        if new == raw[pos]:
            continue
        mutated = raw[:pos] + bytes([new]) + raw[pos + 1 :]
        path = _write(tmp_path, name, mutated)
        try:
            got = reader(path)
        except RinexError as err:
            assert name in str(err)
            assert err.line is None or 1 <= err.line <= n_lines + 1
            continue
        if is_obs:
            assert not np.isinf(got.data).any() and np.all(np.diff(got.time.astype(np.int64)) > 0)
            rows = obs_rows(got)
            if got.unused_codes:
                continue  # a code renamed into one read past (with a warning): its values go in every epoch
            # one changed byte changes at most one epoch (a row starts with its epoch's label)
            assert len({r[0] for r in clean - rows}) <= 1 and len({r[0] for r in rows - clean}) <= 1
        else:
            assert all(np.isfinite(np.asarray(r[1:], dtype=float)).all() for r in nav_rows(got))
            rows = nav_rows(got)
            assert sum((clean - rows).values()) <= 1 and sum((rows - clean).values()) <= 1


def test_binary_garbage_and_control_bytes(tmp_path: Path) -> None:
    rng = np.random.default_rng(SEED)
    for k in range(20):
        path = _write(tmp_path, f"garbage{k}.o", rng.integers(0, 256, 2000, dtype=np.uint8).tobytes())
        for reader in (read_obs, read_nav):
            with pytest.raises(RinexError, match=f"garbage{k}"):
                reader(path)
    # a form feed inside a line does not split it (str.splitlines would), so line numbers stay right
    text = _obs_text("mut.16o")
    lines = text.splitlines(keepends=True)
    at = _epoch_lines(text, True)[1] + 1
    lines[at] = lines[at][:10] + "\f" + lines[at][11:]
    err = _refused(read_obs, _write(tmp_path, "ff.16o", "".join(lines)), at + 1)
    assert err.line == at + 1
