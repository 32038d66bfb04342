"""Mutated RINEX files: byte flips, truncations and field edits of the files in ``tests/data`` and of a
simulated observation file, from a fixed seed.

Field edits put in what a careful reader refuses (an invalid date, an epoch flag RINEX does not define,
a satellite count that does not match, a duplicated or out-of-order epoch, ``nan``/``1e999`` values): these
must be refused with a :class:`~gnssatt.errors.RinexError` naming the file. A cut inside a number truncates
the file there: it is read without its last record, with a warning. Byte flips and cuts at line ends may be
read; then nothing may crash.
"""

from __future__ import annotations

import re
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path

import numpy as np

DATA = Path(__file__).resolve().parents[1] / "data"
NAV_FILES = tuple(sorted(DATA.glob("*.rnx")))


@dataclass(frozen=True)
class FileMutant:
    source: str  # file name of the original
    reader: str  # "gnssatt.rinex.read_obs" or "gnssatt.rinex.read_nav"
    category: str  # byte-flip, truncate, field-edit
    label: str
    text: bytes
    must_refuse: bool


def _body_start(text: str) -> int:
    i = text.find("END OF HEADER")
    return text.index("\n", i) + 1 if i >= 0 else 0


def _flip(rng: np.random.Generator, data: bytes) -> tuple[str, bytes]:
    pos = int(rng.integers(len(data)))
    new = int(rng.choice([rng.integers(32, 127), rng.integers(0, 256)]))
    return f"byte {pos} -> {new:#04x}", data[:pos] + bytes([new]) + data[pos + 1 :]


def _cut_in_number(rng: np.random.Generator, text: str) -> tuple[str, bytes] | None:
    body = _body_start(text)
    spots = [i for i in range(body + 1, len(text)) if text[i - 1].isdigit() and text[i].isdigit()]
    if not spots:
        return None
    pos = int(rng.choice(spots))
    return f"cut at {pos}, inside a number", text[:pos].encode()


def _cut_at_line(rng: np.random.Generator, text: str) -> tuple[str, bytes]:
    ends = [m.end() for m in re.finditer("\n", text)]
    pos = int(rng.choice(ends))
    return f"cut after byte {pos}, a line end", text[:pos].encode()


_OBS_EPOCH = re.compile(r"^> (\d{4}) (\d\d) (\d\d) (\d\d) (\d\d)( *[\d.]+)  (\d)( *\d+)", re.M)
_NAV_EPOCH = re.compile(r"^([GECJ]\d\d) (\d{4}) (\d\d) (\d\d) (\d\d) (\d\d) (\d\d)", re.M)


def _obs_edits(text: str) -> Iterator[tuple[str, str]]:
    """(label, edited text) of a RINEX 3 observation file, each of which a careful reader refuses."""
    epochs = list(_OBS_EPOCH.finditer(text))
    m = epochs[len(epochs) // 2]

    def put(group: int, value: str) -> str:
        return text[: m.start(group)] + value + text[m.end(group) :]

    yield "month 13", put(2, "13")
    yield "day 32", put(3, "32")
    yield "hour 24", put(4, "24")
    yield "epoch flag 7", put(7, "7")
    yield "epoch flag 9", put(7, "9")
    count = m.group(8)
    yield "satellite count + 1", put(8, f"{int(count) + 1:{len(count)}d}")
    yield "satellite count - 1", put(8, f"{int(count) - 1:{len(count)}d}")
    # whole epoch blocks: from one "> " line to the next
    a, b = m.start(), epochs[len(epochs) // 2 + 1].start()
    block = text[a:b]
    yield "duplicated epoch", text[:b] + block + text[b:]
    prev = epochs[len(epochs) // 2 - 1].start()
    yield "epochs out of order", text[:prev] + block + text[prev:a] + text[b:]
    line_end = text.index("\n", m.end())
    first = line_end + 1  # the first observation line of the block: "Gnn" then 16-character fields
    for label, value in (("value nan", "nan"), ("value 1e999", "1e999"), ("value inf", "inf")):
        yield label, text[: first + 3] + f"{value:>14s}" + text[first + 17 :]


def _nav_edits(text: str) -> Iterator[tuple[str, str]]:
    m = next(_NAV_EPOCH.finditer(text), None)
    if m is None:
        return

    def put(group: int, value: str) -> str:
        return text[: m.start(group)] + value + text[m.end(group) :]

    yield "month 13", put(3, "13")
    yield "day 00", put(4, "00")
    yield "minute 61", put(6, "61")
    orbit1 = text.index("\n", m.end()) + 1  # broadcast orbit 1: 4 spaces, then 19-character fields
    for label, value in (("value nan", "nan"), ("value 1e999", "1e999"), ("field of letters", "x" * 19)):
        yield label, text[: orbit1 + 4] + f"{value:>19s}" + text[orbit1 + 23 :]


def file_mutants(sources: dict[str, tuple[str, bytes]], n_random: int, seed: int) -> list[FileMutant]:
    """``sources``: name -> (reader, original bytes). Per source: every field edit, and ``n_random`` each
    of byte flips, cuts inside numbers and cuts at line ends."""
    rng = np.random.default_rng(seed)
    out: list[FileMutant] = []
    for name, (reader, data) in sources.items():
        text = data.decode("ascii", errors="replace")
        edits = _obs_edits(text) if reader.endswith("read_obs") else _nav_edits(text)
        out.extend(FileMutant(name, reader, "field-edit", label, t.encode(), True) for label, t in edits)
        for _ in range(n_random):
            label, flipped = _flip(rng, data)
            out.append(FileMutant(name, reader, "byte-flip", label, flipped, False))
            cut = _cut_in_number(rng, text)
            if cut is not None:
                # a file cut inside its last record is read without that record, with a warning
                out.append(FileMutant(name, reader, "truncate", cut[0], cut[1], False))
            label, cut_line = _cut_at_line(rng, text)
            out.append(FileMutant(name, reader, "truncate", label, cut_line, False))
    return out


def default_sources(simulated_obs: Path, simulated_nav: Path) -> dict[str, tuple[str, bytes]]:
    """The navigation files of ``tests/data`` and a simulated observation/navigation pair."""
    out = {p.name: ("gnssatt.rinex.read_nav", p.read_bytes()) for p in NAV_FILES}
    out["simulated.24o"] = ("gnssatt.rinex.read_obs", simulated_obs.read_bytes())
    out["simulated.24n"] = ("gnssatt.rinex.read_nav", simulated_nav.read_bytes())
    return out
