"""RINEX reading speed: the current :func:`gnssatt.rinex.read_obs` (epochs read by the Rust core), or with
``--nav`` :func:`gnssatt.rinex.read_nav` (records read by the Rust core), against the reader of an earlier
commit (the Python record loop by default). Prints the median time of each, their ratio and the speed in MB
of decompressed text per second, per file.

    python benches/python/rinex_read_speed.py FILE [FILE ...] [--nav] [--rev REV] [--repeats N]

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

from gnssatt.rinex import read_nav, read_obs
from gnssatt.rinex._fields import read_bytes

sys.path.insert(0, str(Path(__file__).parent))
from _reference import PYTHON_NAV_REV, PYTHON_READER_REV, reference_nav_reader, reference_reader


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
    ap.add_argument("--nav", action="store_true", help="navigation files (read_nav)")
    ap.add_argument("--rev", help="git revision of the reference reader (default: the last Python loop)")
    ap.add_argument("--repeats", type=int, default=5)
    args = ap.parse_args()
    rev = args.rev or (PYTHON_NAV_REV if args.nav else PYTHON_READER_REV)
    old = (reference_nav_reader if args.nav else reference_reader)(rev)
    new: Callable[[Any], Any] = read_nav if args.nav else read_obs
    unit = "records" if args.nav else "epochs"
    print(f"| file | MB | {unit} | decompress ms | {rev} ms | now ms | speed-up | {rev} MB/s | now MB/s |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|---:|")
    for f in args.files:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            size_mb = len(read_bytes(str(f))) / 1e6
            got = new(f)
            n_rec = len(got.kepler) + len(got.glonass) if args.nav else len(got.time)
            raw_ms = 1e3 * median_s(functools.partial(read_bytes, str(f)), args.repeats)
            t_old = 1e3 * median_s(functools.partial(old, f), args.repeats)
            t_new = 1e3 * median_s(functools.partial(new, f), args.repeats)
        print(
            f"| {f.name} | {size_mb:.2f} | {n_rec} | {raw_ms:.1f} | {t_old:.1f} | {t_new:.1f} | "
            f"{t_old / t_new:.1f}x | {1e3 * size_mb / t_old:.1f} | {1e3 * size_mb / t_new:.1f} |"
        )


if __name__ == "__main__":
    main()
