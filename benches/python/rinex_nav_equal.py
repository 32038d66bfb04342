"""The navigation reader against the one of an earlier commit (the Python record loop by default): on every
navigation file found, and on mutants of them, both must give the same result, bit for bit (every array's
bytes, dtype and shape, the header values, the skipped counts, every warning), or the same error (message
and line).

    python benches/python/rinex_nav_equal.py PATH [PATH ...] [--rev REV] [--mutants N] [--seed S]

PATH: files or folders (searched recursively; files whose first line is not a navigation header are left
out). ``--mutants N`` also writes N mutants of each file and compares the readers on each: half of them
with one line changed, removed, doubled or cut, or the file cut at a byte (``rinex_obs_equal.mutant``), half
with one broadcast field of a record replaced by a value at or past a limit of the checks (a zero or
negative sqrt(A), an eccentricity of 1, a fractional week or channel, an overflowing number, a blank, a
cut field). Exit status 1 on any difference.
"""

from __future__ import annotations

import argparse
import random
import sys
from pathlib import Path

from gnssatt.errors import RinexError
from gnssatt.rinex import read_nav
from gnssatt.rinex._fields import read_bytes

sys.path.insert(0, str(Path(__file__).parent))
from _reference import PYTHON_NAV_REV, compare, reference_nav_reader
from rinex_obs_equal import mutant

_NOT_RINEX = {"LICENSE", "COMMIT", "SHA256SUMS"}
#: Values put into a broadcast field by the field mutants (each 19 columns wide where it fits).
_FIELD_VALUES = (
    " 0.000000000000D+00", "-5.153000000000D+03", " 1.000000000000D+00", " 9.999999999999D-01",
    " 1.000000000000D+200", " 2.175500000000D+03", " 6.048010000000D+05", " 1.400000000000D+01",
    "-8.000000000000D+00", "                   ", " 1.0E+999          ", "   1.5", " 1.000000000000D+03",
    " nan               ", "1.0D+01 2.0D+00    ",
)  # fmt: skip


def navigation_files(paths: list[Path]) -> list[Path]:
    found = []
    for p in paths:
        for f in sorted(p.rglob("*")) if p.is_dir() else [p]:
            if f.is_file() and f.name not in _NOT_RINEX and not f.name.startswith("README"):
                try:
                    first = read_bytes(str(f)).split(b"\n", 1)[0]
                except RinexError:
                    continue
                if first[60:80].strip() == b"RINEX VERSION / TYPE" and (
                    first[20:21] in b"NGH" or (first[20:21] == b"E" and first[:9].strip().startswith(b"2"))
                ):
                    found.append(f)
    return found


def field_mutant(raw: bytes, rng: random.Random) -> bytes:
    """``raw`` with one broadcast field of a record line (after the header) replaced."""
    lines = raw.split(b"\n")
    end = next((k for k, ln in enumerate(lines) if b"END OF HEADER" in ln), 0)
    body = [k for k in range(end + 1, len(lines)) if len(lines[k]) > 22 and not lines[k].startswith(b">")]
    if not body:
        return mutant(raw, rng)
    k = rng.choice(body)
    line = lines[k]
    if line[:1].isalpha():  # RINEX 3/4 record start
        first = 23
    elif line[:2].strip().isdigit():  # RINEX 2 record start
        first = 22
    else:  # a broadcast-orbit line
        first = 4 if line[:4].isspace() else 3
    start = first + 19 * rng.randrange(4 if first < 22 else 3)
    value = rng.choice(_FIELD_VALUES).encode()
    lines[k] = line[:start] + value + line[start + len(value) :]
    return b"\n".join(lines)


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("paths", nargs="+", type=Path)
    ap.add_argument("--rev", default=PYTHON_NAV_REV, help="git revision of the reference reader")
    ap.add_argument("--mutants", type=int, default=0)
    ap.add_argument("--seed", type=int, default=1)
    args = ap.parse_args()
    files = navigation_files(args.paths)
    old = reference_nav_reader(args.rev)

    def mutate(raw: bytes, rng: random.Random, m: int) -> bytes:
        return field_mutant(raw, rng) if m % 2 else mutant(raw, rng)

    return compare(files, read_nav, old, args.rev, args.mutants, random.Random(args.seed), mutate)


if __name__ == "__main__":
    sys.exit(main())
