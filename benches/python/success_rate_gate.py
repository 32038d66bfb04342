"""Fixed epochs and wrong fixes of single-epoch LAMBDA per acceptance rule, simulated and real.

Usage: ``python benches/python/success_rate_gate.py [--seeds N] [--epochs E] [--length L] [--sets ...]
[--rules ...]`` (defaults 10 seeds of 60 epochs at 60 s, 1 m, every set and rule). For every seed (a different
start time and noise), three simulated baselines of ``--length`` metres
(``simulate_gnss_rinex``: GPS L1, GPS L1+L2, GPS+Galileo L1; code 0.3 m, phase 2 mm, troposphere and broadcast
ionosphere) and the GEONET pair shipped in the package (3.3 km, 120 epochs, GPS L1 and L1+L2) are solved
epoch by epoch (``motion="moving"``, ``method="lambda"``) under each acceptance rule:

- ``ratio only``: ratio >= 3 (RTKLIB's rule; gate 0, no failure-rate test);
- ``gate 0.5``: bootstrapped success rate >= 0.5 and ratio >= 3;
- ``gate 0.5 + FFRT 1e-3`` (the default) and ``+ FFRT 1e-2``: as ``gate 0.5``, and below the gate the full
  set is still fixed when its ratio also passes the fixed-failure-rate test for that probability of a wrong
  fix;
- ``gate 0.5 + known length``: the defaults with the antennas' distance given (``baseline_length_m``: the
  simulated length, or for GEONET the length of RTKLIB's static L1+L2 solution below, 3335.389 m): the
  length-constrained fix gated by its simulated success rate, else the default rule;
- ``gate 0.5 + filter``: the defaults with the multi-epoch filter (``filter="kinematic"``: each epoch's
  baseline from its own data, the float ambiguities carried along their arcs, integers fixed on the
  filter's covariance and held).

A fix is off when its baseline is more than 5 cm from the truth (simulation) or from RTKLIB 2.4.3's static
L1+L2 solution of the GEONET pair (ENU 953.6732, -3196.1396, 4.6497 m at the base's header position, measured
with ``benches/python/rtklib_compare.py``), and wrong when it is off and its heading or pitch is also more
than 4 of its own sigmas from the reference's (``WRONG_SIGMAS``): a fix with the right integers is off the
truth by its covariance, which is decimetres where few satellites pass through a nearly coplanar geometry
(GDOP in the hundreds; RTKLIB refuses such epochs, GDOP above its ``maxgdop`` 30), while a wrong integer
set moves it by a wavelength that its covariance does not cover. Each cell gives both counts (``off`` /
``wrong``). Prints one line per data set and rule, then the totals and, for
the simulations, the wrong fixes among those accepted below the gate against what the failure rate allows
(binomial 97.5 % upper bound). The measured table is in ``docs/observation_engine.md``.
"""

from __future__ import annotations

import argparse
import tempfile
import warnings
from collections.abc import Iterator
from typing import Any

import numpy as np
from numpy.typing import NDArray

import gnssatt.data
from gnssatt.gnss.attitude import attitude_from_rinex
from gnssatt.sim.rinex_scenario import simulate_gnss_rinex

RULES: dict[str, dict[str, Any]] = {
    "ratio only": {"min_success_rate": 0.0, "max_failure_rate": 0.0},
    "gate 0.5": {"min_success_rate": 0.5, "max_failure_rate": 0.0},
    "gate 0.5 + FFRT 1e-3": {"min_success_rate": 0.5, "max_failure_rate": 1e-3},
    "gate 0.5 + FFRT 1e-2": {"min_success_rate": 0.5, "max_failure_rate": 1e-2},
    "gate 0.5 + known length": {"min_success_rate": 0.5, "max_failure_rate": 0.0, "known_length": True},
    "gate 0.5 + filter": {"min_success_rate": 0.5, "max_failure_rate": 0.0, "filter": "kinematic"},
}
SIM_SETS = (("G", 1), ("G", 2), ("GE", 1))
GEONET_BASE_M = (-3976219.5082, 3382372.5671, 3652512.9849)
GEONET_REFERENCE_ENU_M = np.array([953.6732, -3196.1396, 4.6497])
GEONET_REFERENCE_LENGTH_M = float(np.linalg.norm(GEONET_REFERENCE_ENU_M))
WRONG_M = 0.05
#: Heading or pitch error, in its own sigmas, beyond which an off fix is a wrong one (two-sided normal tail
#: 6e-5 per angle: under 0.1 expected among the 3000 fixes of a full run with the right integers).
WRONG_SIGMAS = 4.0


def heading_pitch_deg(enu: NDArray[np.float64]) -> NDArray[np.float64]:
    """(..., 2) heading (clockwise from north, 0-360) and pitch (elevation) of ENU baselines, degrees."""
    e, n, u = enu[..., 0], enu[..., 1], enu[..., 2]
    heading = np.degrees(np.arctan2(e, n)) % 360.0
    return np.stack([heading, np.degrees(np.arctan2(u, np.hypot(e, n)))], axis=-1)


def cases(
    seeds: int, epochs: int, length_m: float
) -> Iterator[tuple[str, dict[str, Any], NDArray[np.float64], float]]:
    """(label, attitude_from_rinex arguments, reference ENU per epoch, antenna distance) of every data set."""
    antennas = np.array([[0.0, 0, 0], [length_m, 0, 0]])
    for seed in range(seeds):
        for systems, freqs in SIM_SETS:
            sim = simulate_gnss_rinex(
                tempfile.mkdtemp(), antennas, [30, 0, 0], systems=systems, frequencies=freqs,
                n_epochs=epochs, interval_s=60.0, start_s=3600.0 * seed, rng=seed,
            )  # fmt: skip
            args = {"observations": list(sim.obs_paths), "nav": sim.nav_path, "systems": systems,
                    "frequencies": freqs}  # fmt: skip
            yield f"sim {systems} f{freqs}", args, np.asarray(sim.baselines_enu_m)[:, 0, :], length_m
    d = gnssatt.data.geonet_dir()
    obs = [d / "07590920.05o", d / "30400920.05o"]
    nav = [d / "07590920.05n", d / "30400920.05n"]
    for freqs in (1, 2):
        args = {"observations": obs, "nav": nav, "systems": "G", "frequencies": freqs,
                "base_position_m": GEONET_BASE_M}  # fmt: skip
        yield f"GEONET G f{freqs}", args, GEONET_REFERENCE_ENU_M[None, :], GEONET_REFERENCE_LENGTH_M


def binomial_upper(n: int, p: float) -> int:
    """Smallest count c with P(X > c) <= 2.5 % for X ~ Binomial(n, p) (the one-sided 97.5 % bound)."""
    from scipy.stats import binom

    return int(binom.ppf(0.975, n, p)) if n else 0


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--seeds", type=int, default=10)
    ap.add_argument("--epochs", type=int, default=60)
    ap.add_argument("--length", type=float, default=1.0, help="simulated antenna distance, m (default 1)")
    ap.add_argument("--sets", nargs="+", default=None, help="labels of the sets to run (e.g. 'GEONET G f1')")
    ap.add_argument("--rules", nargs="+", default=list(RULES), choices=list(RULES), help="rules to run")
    a = ap.parse_args()
    rules = {r: RULES[r] for r in a.rules}
    warnings.simplefilter("ignore")
    totals: dict[tuple[str, str], list[int]] = {}
    grey: dict[str, list[int]] = {r: [0, 0, 0] for r in rules}  # below the gate: epochs, fixed, wrong
    for label, args, reference, length in cases(a.seeds, a.epochs, a.length):
        if a.sets is not None and label not in a.sets:
            continue
        gate_fixed = None
        for rule, rule_opts in rules.items():
            opts = {k: v for k, v in rule_opts.items() if k != "known_length"}
            if rule_opts.get("known_length"):
                opts["baseline_length_m"] = length
            s = attitude_from_rinex(method="lambda", motion="moving", ratio_threshold=3.0, **args, **opts)
            err = np.linalg.norm(s.baselines_enu_m[:, 0] - reference, axis=-1)
            fixed = s.fixed.astype(bool)
            off = fixed & (err > WRONG_M)
            d = s.angles_deg[:, :2] - heading_pitch_deg(
                np.broadcast_to(reference, s.baselines_enu_m[:, 0].shape)
            )
            d[:, 0] = (d[:, 0] + 180.0) % 360.0 - 180.0
            wrong = off & np.any(np.abs(d) > WRONG_SIGMAS * s.angle_sigmas_deg[:, :2], axis=1)
            t = totals.setdefault((label, rule), [0, 0, 0, 0])
            t[0] += len(fixed)
            t[1] += int(fixed.sum())
            t[2] += int(wrong.sum())
            t[3] += int(off.sum())
            if rule == "gate 0.5":
                gate_fixed = fixed
            elif gate_fixed is not None and label.startswith("sim"):
                below = s.success_rate < 0.5
                g = grey[rule]
                g[0] += int(below.sum())
                g[1] += int((fixed & ~gate_fixed).sum())
                g[2] += int((wrong & ~gate_fixed).sum())
        print(label, "done", flush=True)
    print("\n| data | epochs | " + " | ".join(rules) + " |")
    print("|---|---|" + "---|" * len(rules))
    for label in dict.fromkeys(k[0] for k in totals):
        cells = [
            f"{totals[(label, r)][1]} fixed, {totals[(label, r)][3]} off / {totals[(label, r)][2]} wrong"
            for r in rules
        ]
        print(f"| {label} | {totals[(label, next(iter(rules)))][0]} | " + " | ".join(cells) + " |")
    print("\nBelow the gate (simulations): epochs with success rate < 0.5, fixed there, wrong among them")
    for rule, rate in (("gate 0.5 + FFRT 1e-3", 1e-3), ("gate 0.5 + FFRT 1e-2", 1e-2)):
        if rule not in grey:
            continue
        n, f, w = grey[rule]
        bound = binomial_upper(n, rate)
        print(f"{rule}: {n} epochs, {f} fixed, {w} wrong (binomial 97.5 % bound at {rate}: {bound})")


if __name__ == "__main__":
    main()
