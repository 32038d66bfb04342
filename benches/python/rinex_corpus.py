"""Read every RINEX file of a folder with gnssatt.rinex and print one Markdown table row per file: what it
is, what was read, what was skipped (with the warnings issued), or the refusal.

    python benches/python/rinex_corpus.py CORPUS_DIR [--times]

Files are found recursively: observation and navigation files, plain, Hatanaka (``.crx``, ``.??d``) and
gzip / Unix-compress; files named ``LICENSE``, ``README*``, ``COMMIT`` and ``SHA256SUMS`` are not RINEX and
are left out. A file's kind and version come from its first line (after decompression), its result from
:func:`gnssatt.rinex.read_obs` or :func:`gnssatt.rinex.read_nav`. ``--times`` adds a column with the time of
each read (one run; for speed use ``benches/python/rinex_read.py``). Exit status 1 if any file is refused.
"""

from __future__ import annotations

import argparse
import time
import warnings
from pathlib import Path

from gnssatt.errors import RinexError
from gnssatt.rinex import read_nav, read_obs
from gnssatt.rinex._fields import read_lines

_NOT_RINEX = {"LICENSE", "COMMIT", "SHA256SUMS"}


def _first_line(path: Path) -> str:
    """The first line of a file, decompressed where it is compressed (without the reader's checks)."""
    lines, _ = read_lines(str(path))
    return lines[0] if lines else ""


def _row(path: Path, root: Path, timed: bool) -> tuple[str, bool]:
    """One table row for ``path`` and whether it was read."""
    name = str(path.relative_to(root))
    try:
        first = _first_line(path)
    except Exception as exc:  # a corrupt archive: the reader names it too
        first = ""
        kind_note = f"({type(exc).__name__})"
    else:
        kind_note = ""
    kind = {"O": "obs", "N": "nav", "G": "nav (GLONASS)", "E": "nav (Galileo)"}.get(first[20:21], "?")
    if first[20:21] == "N" and first[40:41].strip():
        kind = f"nav ({first[40:41]})"
    version = first[0:9].strip() or "?"
    t0 = time.perf_counter()
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            if first[20:21] == "O":
                obs = read_obs(path)
                result = (
                    f"{len(obs.time)} epochs, {len(obs.sats)} satellites, "
                    f"{sum(len(v) for v in obs.obs_types.values())} codes"
                )
            else:
                nav = read_nav(path)
                result = f"{len(nav.kepler)} Keplerian + {len(nav.glonass)} GLONASS records"
                if nav.skipped:
                    result += "; skipped " + ", ".join(f"{k} {v}" for k, v in sorted(nav.skipped.items()))
            ok = True
        except RinexError as exc:
            result = f"**refused**: {exc.message} (line {exc.line})"
            ok = False
    elapsed = time.perf_counter() - t0
    notes = "; ".join(str(w.message).replace(str(path), "<file>") for w in caught)
    cells = [f"`{name}`", f"{kind} {kind_note}".strip(), version, result, notes.replace("|", "/")]
    if timed:
        cells.append(f"{elapsed:.2f} s")
    return "| " + " | ".join(cells) + " |", ok


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("folder", type=Path)
    ap.add_argument("--times", action="store_true", help="add the time of each read")
    args = ap.parse_args()
    files = sorted(
        p
        for p in args.folder.rglob("*")
        if p.is_file() and p.name not in _NOT_RINEX and not p.name.startswith("README")
    )
    head = ["file", "kind", "version", "result", "warnings"] + (["time"] if args.times else [])
    print("| " + " | ".join(head) + " |")
    print("|" + "---|" * len(head))
    refused = 0
    for p in files:
        row, ok = _row(p, args.folder, args.times)
        refused += not ok
        print(row, flush=True)
    print(f"\n{len(files)} files: {len(files) - refused} read, {refused} refused")
    return 1 if refused else 0


if __name__ == "__main__":
    raise SystemExit(main())
