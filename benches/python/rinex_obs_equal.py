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
import tempfile
import warnings
from dataclasses import fields
from pathlib import Path
from typing import Any

import numpy as np

from gnssatt.errors import RinexError
from gnssatt.rinex import read_obs
from gnssatt.rinex._fields import read_bytes

sys.path.insert(0, str(Path(__file__).parent))
from _reference import PYTHON_READER_REV, reference_reader

_NOT_RINEX = {"LICENSE", "COMMIT", "SHA256SUMS"}


def _outcome(reader: Any, path: Path) -> tuple[str, Any, list[str]]:
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            result: Any = reader(path)
            kind = "read"
        except RinexError as exc:
            kind, result = "error", (str(exc), exc.line)
    return kind, result, [f"{w.category.__name__}: {w.message}" for w in caught]


def _same_value(a: Any, b: Any) -> bool:
    if isinstance(a, np.ndarray) or isinstance(b, np.ndarray):
        a, b = np.asarray(a), np.asarray(b)
        return bool(a.dtype == b.dtype and a.shape == b.shape and a.tobytes() == b.tobytes())
    if isinstance(a, float) and isinstance(b, float):
        return bool(np.float64(a).tobytes() == np.float64(b).tobytes())
    return type(a) is type(b) and bool(a == b)


def differences(path: Path, old: Any) -> list[str]:
    """What differs between the current reader and ``old`` on ``path`` (empty: nothing)."""
    k_new, r_new, w_new = _outcome(read_obs, path)
    k_old, r_old, w_old = _outcome(old, path)
    out = []
    if k_new != k_old:
        shown_new = r_new if k_new == "error" else ""
        shown_old = r_old if k_old == "error" else ""
        return [f"new {k_new} {shown_new}, old {k_old} {shown_old}"]
    if k_new == "error":
        if r_new != r_old:
            out.append(f"error: new {r_new}, old {r_old}")
    else:
        for f in fields(r_new):
            if not _same_value(getattr(r_new, f.name), getattr(r_old, f.name)):
                out.append(f"field {f.name} differs")
    if w_new != w_old:
        out.append(f"warnings: new {w_new}, old {w_old}")
    return out


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
    old = reference_reader(args.rev)
    rng = random.Random(args.seed)
    files = observation_files(args.paths)
    n_diff = n_mut = n_mut_err = 0
    for f in files:
        diff = differences(f, old)
        n_diff += bool(diff)
        print(f"{'DIFFERENT' if diff else 'same     '} {f}" + "".join(f"\n    {d}" for d in diff))
        if args.mutants:
            raw = read_bytes(str(f))
            with tempfile.TemporaryDirectory() as folder:
                for m in range(args.mutants):
                    p = Path(folder) / f"mutant{m}.rnx"
                    p.write_bytes(mutant(raw, rng))
                    diff = differences(p, old)
                    n_mut += 1
                    n_mut_err += _outcome(read_obs, p)[0] == "error"
                    if diff:
                        n_diff += 1
                        print(f"DIFFERENT mutant {m} of {f}" + "".join(f"\n    {d}" for d in diff))
    print(f"{len(files)} files, {n_mut} mutants ({n_mut_err} refused): {n_diff} different from {args.rev}")
    return 1 if n_diff else 0


if __name__ == "__main__":
    sys.exit(main())
