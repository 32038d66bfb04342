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
import dataclasses
import random
import sys
import tempfile
import warnings
from pathlib import Path
from typing import Any

import numpy as np

from gnssatt.errors import RinexError
from gnssatt.rinex import read_nav
from gnssatt.rinex._fields import read_bytes

sys.path.insert(0, str(Path(__file__).parent))
from _reference import PYTHON_NAV_REV, reference_nav_reader
from rinex_obs_equal import mutant

_NOT_RINEX = {"LICENSE", "COMMIT", "SHA256SUMS"}
#: Values put into a broadcast field by the field mutants (each 19 columns wide where it fits).
_FIELD_VALUES = (
    " 0.000000000000D+00", "-5.153000000000D+03", " 1.000000000000D+00", " 9.999999999999D-01",
    " 1.000000000000D+200", " 2.175500000000D+03", " 6.048010000000D+05", " 1.400000000000D+01",
    "-8.000000000000D+00", "                   ", " 1.0E+999          ", "   1.5", " 1.000000000000D+03",
    " nan               ", "1.0D+01 2.0D+00    ",
)  # fmt: skip


def _outcome(reader: Any, path: Path) -> tuple[str, Any, list[str]]:
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            result: Any = reader(path)
            kind = "read"
        except RinexError as exc:
            kind, result = "error", (str(exc), exc.line)
    return kind, result, [f"{w.category.__name__}: {w.message}" for w in caught]


def _same(a: Any, b: Any, where: str, out: list[str]) -> None:
    """Append to ``out`` where ``a`` and ``b`` differ (dataclasses and dicts field by field, arrays by
    bytes, dtype and shape, floats by bits)."""
    if dataclasses.is_dataclass(a) and dataclasses.is_dataclass(b):
        for f in dataclasses.fields(a):
            _same(getattr(a, f.name), getattr(b, f.name), f"{where}.{f.name}", out)
    elif isinstance(a, dict) and isinstance(b, dict):
        if list(a) != list(b):
            out.append(f"{where}: keys {list(a)} against {list(b)}")
        for k in a:
            if k in b:
                _same(a[k], b[k], f"{where}[{k!r}]", out)
    elif isinstance(a, np.ndarray) or isinstance(b, np.ndarray):
        a, b = np.asarray(a), np.asarray(b)
        if not (a.dtype == b.dtype and a.shape == b.shape and a.tobytes() == b.tobytes()):
            out.append(f"{where} differs")
    elif isinstance(a, float) and isinstance(b, float):
        if np.float64(a).tobytes() != np.float64(b).tobytes():
            out.append(f"{where} differs")
    elif type(a) is not type(b) or a != b:
        out.append(f"{where}: {a!r} against {b!r}")


def differences(path: Path, old: Any) -> list[str]:
    """What differs between the current reader and ``old`` on ``path`` (empty: nothing)."""
    k_new, r_new, w_new = _outcome(read_nav, path)
    k_old, r_old, w_old = _outcome(old, path)
    out: list[str] = []
    if k_new != k_old:
        shown_new = r_new if k_new == "error" else ""
        shown_old = r_old if k_old == "error" else ""
        return [f"new {k_new} {shown_new}, old {k_old} {shown_old}"]
    if k_new == "error":
        if r_new != r_old:
            out.append(f"error: new {r_new}, old {r_old}")
    else:
        _same(r_new, r_old, "nav", out)
    if w_new != w_old:
        out.append(f"warnings: new {w_new}, old {w_old}")
    return out


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
    old = reference_nav_reader(args.rev)
    rng = random.Random(args.seed)
    files = navigation_files(args.paths)
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
                    p.write_bytes(field_mutant(raw, rng) if m % 2 else mutant(raw, rng))
                    diff = differences(p, old)
                    n_mut += 1
                    n_mut_err += _outcome(read_nav, p)[0] == "error"
                    if diff:
                        n_diff += 1
                        print(f"DIFFERENT mutant {m} of {f}" + "".join(f"\n    {d}" for d in diff))
    print(f"{len(files)} files, {n_mut} mutants ({n_mut_err} refused): {n_diff} different from {args.rev}")
    return 1 if n_diff else 0


if __name__ == "__main__":
    sys.exit(main())
