"""Time per epoch of the observation engine alone (``_core.gnss_run``, in-process, files read beforehand).

    python benches/python/engine_per_epoch.py [--cssrlib DIR] [--sim-epochs N] [--repeats N] [--out FILE]
    RAYON_NUM_THREADS=1 python benches/python/engine_per_epoch.py ...   # one thread

Sessions: GEONET 0759 -> 3040 (``gnssatt.data``, GPS L1+L2, 120 epochs), the cssrlib 3034 -> SEPT pair
(``--cssrlib DIR``, GREC three bands, 360 epochs) and a simulated 1 m pair (GRECJ, three frequencies,
``--sim-epochs``, seed 1: the two-antenna all-signal epoch), each single-epoch (``--motion moving``,
``--method lambda``, elevation mask 10 degrees, base at its header position), as
``benches/python/rtklib_compare.py`` runs them. Each session's ``gnss_run`` call is repeated ``--repeats``
times after a first call; the median and ms per epoch are printed with the threads of the engine
(``RAYON_NUM_THREADS``, default every CPU). ``--out FILE``: the fixed flags, baselines and warnings of each
session as ``.npz``, to compare two builds bit for bit.
"""

from __future__ import annotations

import argparse
import os
import statistics
import tempfile
import time
import warnings
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np


def header_position(path: Path) -> list[float]:
    """The ``APPROX POSITION XYZ`` of a RINEX observation header, m."""
    with path.open(errors="replace") as f:
        for line in f:
            if "APPROX POSITION XYZ" in line:
                return [float(x) for x in line.split()[:3]]
            if "END OF HEADER" in line:
                break
    raise ValueError(f"{path}: no APPROX POSITION XYZ in the header")


def sessions(
    cssrlib: Path | None, sim_epochs: int
) -> dict[str, tuple[list[Path], list[Path], dict[str, Any]]]:
    """Observation files (base first), navigation files and options of each session."""
    from gnssatt.data import geonet_dir
    from gnssatt.sim.rinex_scenario import simulate_gnss_rinex

    g = geonet_dir()
    out = {
        "geonet G L1+L2": (
            [g / "07590920.05o", g / "30400920.05o"],
            [g / "07590920.05n", g / "30400920.05n"],
            {"systems": "G", "frequencies": 2},
        )
    }
    if cssrlib is not None:
        out["cssrlib GREC 3 bands"] = (
            [cssrlib / "3034265G.21O", cssrlib / "SEPT265G.21O"],
            [cssrlib / "SEPT2650.21P"],
            {"systems": "GREC", "frequencies": 3},
        )
    folder = Path(tempfile.mkdtemp(prefix="engine_per_epoch_"))
    ants = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]])
    euler = np.tile([30.0, 0.0, 0.0], (sim_epochs, 1))
    sim = simulate_gnss_rinex(folder, ants, euler, systems="GRECJ", frequencies=3, n_epochs=sim_epochs, rng=1)
    out["sim GRECJ 3 frequencies"] = (
        [Path(p) for p in sim.obs_paths],
        [Path(sim.nav_path)],
        {"systems": "GRECJ", "frequencies": 3},
    )
    return out


def main(argv: Sequence[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--cssrlib", type=Path, default=None, help="folder of the cssrlib 3034/SEPT pair")
    ap.add_argument("--sim-epochs", type=int, default=300, help="epochs of the simulated pair (default 300)")
    ap.add_argument("--repeats", type=int, default=5, help="timed calls per session (default 5)")
    ap.add_argument("--out", type=Path, default=None, help="write the results of each session (.npz)")
    args = ap.parse_args(argv)
    if args.repeats < 1 or args.sim_epochs < 2:
        ap.error("expected --repeats >= 1 and --sim-epochs >= 2")

    from gnssatt import _core
    from gnssatt.gnss.attitude import attitude_from_rinex
    from gnssatt.rinex import read_nav, read_obs

    threads = os.environ.get("RAYON_NUM_THREADS", f"every CPU ({os.cpu_count()})")
    print(f"engine threads: {threads}; load average {os.getloadavg()[0]:.1f}")
    original = _core.gnss_run
    results: dict[str, Any] = {}
    try:
        for name, (obs_paths, nav_paths, kw) in sessions(args.cssrlib, args.sim_epochs).items():
            obs = [read_obs(p) for p in obs_paths]
            nav = read_nav([str(p) for p in nav_paths])
            walls: list[float] = []

            def timed(*a: Any, walls: list[float] = walls) -> Any:
                first = original(*a)
                for _ in range(args.repeats):
                    t0 = time.perf_counter()
                    original(*a)
                    walls.append(time.perf_counter() - t0)
                return first

            _core.gnss_run = timed
            with warnings.catch_warnings(record=True) as caught:
                warnings.simplefilter("always")
                s = attitude_from_rinex(
                    obs,
                    nav,
                    method="lambda",
                    motion="moving",
                    elevation_mask_deg=10.0,
                    base_position_m=header_position(obs_paths[0]),
                    **kw,
                )
            _core.gnss_run = original
            n = len(s.fixed)
            med = statistics.median(walls)
            print(
                f"{name}: {n} epochs, gnss_run median {med * 1e3:.1f} ms = {med / n * 1e3:.3f} ms/epoch "
                f"(of {len(walls)}), {int(np.sum(s.fixed == 1))} fixed"
            )
            key = name.replace(" ", "_").replace("+", "")
            results[f"{key}_fixed"] = np.asarray(s.fixed)
            results[f"{key}_baselines_enu_m"] = np.asarray(s.baselines_enu_m)
            results[f"{key}_warnings"] = np.array([str(w.message) for w in caught])
    finally:
        _core.gnss_run = original
    if args.out is not None:
        np.savez(args.out, **results)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
