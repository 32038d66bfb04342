"""Observation-file reading speed: gnssatt.rinex.read_obs against georinex (the Python reader users would
otherwise pick). Prints median times and the ratio.

    python benches/python/rinex_read.py [FILE.obs ...] [--simulated N]

Without files it reads the GEONET RINEX 2.10 file shipped in ``gnssatt.data``; ``--simulated N`` also writes
and reads a simulated RINEX 3 file of N epochs at 1 s (GPS, two antennas: the first file is timed) from
``gnssatt.rinex.simulate_rinex_array``. georinex must be installed for the ratio (``pip install georinex``).
"""

from __future__ import annotations

import argparse
import statistics
import tempfile
import time
import warnings
from pathlib import Path

import numpy as np

from gnssatt.data import geonet_dir
from gnssatt.rinex import read_obs
from gnssatt.sim.rinex_scenario import simulate_rinex_array

DEFAULT = geonet_dir() / "07590920.05o"


def _median(fn, repeats: int) -> float:  # type: ignore[no-untyped-def]
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return statistics.median(times)


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("files", nargs="*", type=Path)
    ap.add_argument("--simulated", type=int, default=0, help="epochs of a simulated RINEX 3 file (0: none)")
    args = ap.parse_args()
    files = list(args.files) or [DEFAULT]
    try:
        import georinex
    except ImportError:
        georinex = None
    with tempfile.TemporaryDirectory() as tmp:
        if args.simulated > 0:
            ants = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]])
            simulate_rinex_array(tmp, ants, np.zeros((args.simulated, 3)), rng=0)
            files.append(Path(tmp) / "ant0.24o")
        for f in files:
            ours = _median(lambda f=f: read_obs(f), 20 if f.stat().st_size < 5e6 else 5)
            size = f.stat().st_size / 1e6
            line = f"{f.name} ({size:.1f} MB): gnssatt read_obs median {ours * 1e3:.2f} ms"
            if georinex is not None:
                with warnings.catch_warnings():
                    # georinex 1.16 + xarray 2026 warn about a future merge default on every call.
                    warnings.simplefilter("ignore", FutureWarning)
                    theirs = _median(lambda f=f: georinex.load(f), 3)
                line += f"; georinex.load median {theirs * 1e3:.1f} ms; ratio {theirs / ours:.0f}x"
            else:
                line += "; georinex not installed"
            print(line, flush=True)


if __name__ == "__main__":
    main()
