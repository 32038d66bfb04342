"""Fix, hold and float counts of attitude mode (three antennas) and of a known-length pair on a simulated
rotating platform, GPS L1 only, single-epoch against ``continuity`` (held integers) and, for the pair, the
multi-epoch filter (``filter="kinematic"``, its fix the length-constrained search on its covariance), with
the wrong fixes against the simulator's truth.

A fixed or held epoch is wrong when any of its baselines is more than ``WRONG_M`` from the truth (a wrong
integer moves a 1 m baseline by centimetres to decimetres; a right fix of 2 mm phase noise is within about
1 cm: tests/test_rinex_rotating_platform.py).

Run: ``python benches/python/attitude_hold.py [n_epochs] [n_sessions]``.
"""

from __future__ import annotations

import sys
import tempfile
import warnings
from pathlib import Path

import numpy as np

from gnssatt import sim
from gnssatt.gnss.attitude import attitude_from_rinex
from gnssatt.sim.rinex_scenario import simulate_rinex_array

WRONG_M = 0.04


def euler(n: int) -> np.ndarray:
    k = np.arange(n)
    return np.stack([-40.0 + 3.0 * k, 5.0 * np.sin(k / 3.0), 3.0 * np.cos(k / 4.0)], axis=1)


def run(n_ep: int, n_sessions: int) -> None:
    tri = sim.equilateral_triangle(1.0, plane="xz")
    pair = tri[:2]
    rows = []
    modes: dict[str, dict[str, object]] = {
        "single-epoch": {},
        "continuity": {"continuity": True},
        "filter": {"filter": "kinematic"},
    }
    for name, ant in (("3 antennas", tri), ("2 antennas + length", pair)):
        for mode, extra in modes.items():
            if mode == "filter" and len(ant) > 2:
                continue  # the filter is baseline mode only
            counts = {"fixed": 0, "held": 0, "float": 0}
            wrong = 0
            for session in range(n_sessions):
                with tempfile.TemporaryDirectory() as d:
                    s = simulate_rinex_array(
                        Path(d), ant, euler(n_ep), rng=100 + session, n_sats=7, start_s=3600.0 * session
                    )
                    body = ant[1:] - ant[0]
                    kw: dict[str, object] = {"method": "lambda", "motion": "moving", **extra}
                    if len(ant) == 2:
                        kw["baseline_length_m"] = [float(np.linalg.norm(body[0]))]
                        args: tuple[object, ...] = ()
                    else:
                        args = (body,)
                    try:
                        with warnings.catch_warnings():
                            warnings.simplefilter("ignore")
                            sol = attitude_from_rinex(list(s.obs_paths), s.nav_path, *args, **kw)  # type: ignore[arg-type]
                    except ValueError as e:
                        print(f"{name}, {mode}: refused ({e})")
                        break
                for state in counts:
                    counts[state] += int(np.sum(sol.fix_state == state))
                err = np.linalg.norm(sol.baselines_enu_m - s.baselines_enu_m, axis=2).max(axis=1)
                wrong += int(np.sum((sol.fix_state != "float") & (err > WRONG_M)))
            rows.append((name, mode, counts, wrong))
    total = n_ep * n_sessions
    print(f"{n_sessions} sessions x {n_ep} epochs, GPS L1, 7 satellites, 1 m baselines, 2 mm phase noise")
    print(f"{'array':22s} {'mode':13s} {'fixed':>6s} {'held':>6s} {'float':>6s} {'wrong':>6s} of {total}")
    for name, mode, c, w in rows:
        print(f"{name:22s} {mode:13s} {c['fixed']:6d} {c['held']:6d} {c['float']:6d} {w:6d}")


if __name__ == "__main__":
    run(int(sys.argv[1]) if len(sys.argv) > 1 else 30, int(sys.argv[2]) if len(sys.argv) > 2 else 3)
