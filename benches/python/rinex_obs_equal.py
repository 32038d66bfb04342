"""The observation reader against the one of an earlier commit (the Python epoch loop by default): on
every observation file found, and on mutants of them, both must give the same result, bit for bit (every
array's bytes, dtype and shape, every header field, every warning), or the same error (message and line).

    python benches/python/rinex_obs_equal.py PATH [PATH ...] [--rev REV] [--mutants N] [--seed S]

PATH: files or folders (searched recursively; files whose first line is not an observation header are
left out). ``--mutants N`` also writes N mutants of each file (one line changed, removed, doubled or cut,
or the file cut at a byte, drawn with ``--seed``) and compares the readers on each. Exit status 1 on any
difference.
"""

from __future__ import annotations

import argparse
import random
import sys
from pathlib import Path

from gnssatt.errors import RinexError
from gnssatt.rinex import read_obs
from gnssatt.rinex._fields import read_bytes

sys.path.insert(0, str(Path(__file__).parent))
from _reference import PYTHON_READER_REV, compare, reference_reader

_NOT_RINEX = {"LICENSE", "COMMIT", "SHA256SUMS"}


def observation_files(paths: list[Path]) -> list[Path]:
    found = []
    for p in paths:
        for f in sorted(p.rglob("*")) if p.is_dir() else [p]:
            if f.is_file() and f.name not in _NOT_RINEX and not f.name.startswith("README"):
                try:
                    first = read_bytes(str(f))[:81]
                except RinexError:
                    continue
                if first[20:21] == b"O":
                    found.append(f)
    return found


def mutant(raw: bytes, rng: random.Random) -> bytes:
    """``raw`` with one change drawn by ``rng`` in its second half (where the epochs are)."""
    lines = raw.split(b"\n")
    k = rng.randrange(len(lines) // 2, len(lines))
    line = lines[k]
    how = rng.randrange(6)
    if how == 0 and line:  # one character replaced
        c = rng.randrange(len(line))
        line = line[:c] + bytes([rng.choice(b" 0123456789.-+>GREX\t\xff")]) + line[c + 1 :]
    elif how == 1 and line:  # one character removed
        c = rng.randrange(len(line))
        line = line[:c] + line[c + 1 :]
    elif how == 2:  # line cut
        line = line[: rng.randrange(len(line) + 1)]
    elif how == 3:
        del lines[k]
        return b"\n".join(lines)
    elif how == 4:
        lines.insert(k, line)
        return b"\n".join(lines)
    else:  # file cut at a byte
        return raw[: rng.randrange(len(raw) // 2, len(raw))]
    lines[k] = line
    return b"\n".join(lines)


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("paths", nargs="+", type=Path)
    ap.add_argument("--rev", default=PYTHON_READER_REV, help="git revision of the reference reader")
    ap.add_argument("--mutants", type=int, default=0)
    ap.add_argument("--seed", type=int, default=1)
    args = ap.parse_args()
    files = observation_files(args.paths)
    old = reference_reader(args.rev)
    return compare(
        files,
        read_obs,
        old,
        args.rev,
        args.mutants,
        random.Random(args.seed),
        lambda raw, rng, m: mutant(raw, rng),
    )


if __name__ == "__main__":
    sys.exit(main())
