"""Observation-file reading speed: the current :func:`gnssatt.rinex.read_obs` (epochs read by the Rust core)
against the reader of an earlier commit (the Python epoch loop by default). Prints the median time of each
and their ratio per file.

    python benches/python/rinex_read_speed.py FILE [FILE ...] [--rev REV] [--repeats N]

Files compressed with Hatanaka or gzip are decompressed by both readers in each read (the ``hatanaka``
package), as a user's read does; the ``decompress`` column is that share, measured alone.
"""

from __future__ import annotations

import argparse
import functools
import statistics
import sys
import time
import warnings
from collections.abc import Callable
from pathlib import Path
from typing import Any

from gnssatt.rinex import read_obs
from gnssatt.rinex._fields import read_bytes

sys.path.insert(0, str(Path(__file__).parent))
from _reference import PYTHON_READER_REV, reference_reader


def median_s(fn: Callable[[], Any], repeats: int) -> float:
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return statistics.median(times)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("files", nargs="+", type=Path)
    ap.add_argument("--rev", default=PYTHON_READER_REV, help="git revision of the reference reader")
    ap.add_argument("--repeats", type=int, default=5)
    args = ap.parse_args()
    old = reference_reader(args.rev)
    print(f"| file | MB | epochs | decompress ms | {args.rev} ms | now ms | speed-up |")
    print("|---|---:|---:|---:|---:|---:|---:|")
    for f in args.files:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            size_mb = len(read_bytes(str(f))) / 1e6
            n_ep = len(read_obs(f).time)
            raw_ms = 1e3 * median_s(functools.partial(read_bytes, str(f)), args.repeats)
            t_old = 1e3 * median_s(functools.partial(old, f), args.repeats)
            t_new = 1e3 * median_s(functools.partial(read_obs, f), args.repeats)
        print(
            f"| {f.name} | {size_mb:.1f} | {n_ep} | {raw_ms:.1f} | {t_old:.1f} | {t_new:.1f} | "
            f"{t_old / t_new:.1f}x |"
        )


if __name__ == "__main__":
    main()
