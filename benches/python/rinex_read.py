"""Observation-file reading speed: gnssatt.rinex.read_obs against georinex (the Python reader users would
otherwise pick). Prints median times and the ratio.

    PYTHONPATH=python:/path/to/georinex/site python benches/python/rinex_read.py [FILE.obs ...]
"""

from __future__ import annotations

import statistics
import sys
import time
from pathlib import Path

from gnssatt.rinex import read_obs

DEFAULT = Path(__file__).resolve().parents[3] / "shared" / "data" / "rtklib_geonet_0759_3040" / "07590920.05o"


def _median(fn, repeats: int) -> float:  # type: ignore[no-untyped-def]
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return statistics.median(times)


def main() -> None:
    files = [Path(a) for a in sys.argv[1:]] or [DEFAULT]
    try:
        import georinex
    except ImportError:
        georinex = None
    for f in files:
        ours = _median(lambda f=f: read_obs(f), 20)
        line = f"{f.name}: gnssatt read_obs median {ours * 1e3:.2f} ms"
        if georinex is not None:
            theirs = _median(lambda f=f: georinex.load(f), 3)
            line += f"; georinex.load median {theirs * 1e3:.1f} ms; ratio {theirs / ours:.0f}x"
        else:
            line += "; georinex not installed"
        print(line)


if __name__ == "__main__":
    main()
