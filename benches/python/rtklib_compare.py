"""Side by side with RTKLIB 2.4.3: ``gnssatt attitude`` and ``rnx2rtkp`` on the same files, modes and signals.

    python benches/python/rtklib_compare.py --rtklib-src ../shared/peers/rtklib-2.4.3 [--rnx2rtkp PATH]
        [--datasets geonet,sim] [--out DIR] [--repeats N] [--cssrlib DIR] [--threads N]
    python benches/python/rtklib_compare.py --rtklib-src ../shared/peers/rtklib-2.4.3 --datasets platforms
        [--profiles gps_l1_ublox,geodetic] [--platform-duration-s S] [--seed N]

Datasets: ``geonet`` (the GEONET pair shipped in ``gnssatt.data``: 3.3 km, GPS L1/L2, 120 epochs, base 0759 at
its header position) and ``sim`` (a simulated 1 m static baseline, 300 epochs at 1 s, every system and
frequency ``gnssatt.sim.rinex_scenario`` writes); ``cssrlib`` (``--cssrlib DIR``: the real kinematic pair of
``../shared/data/cssrlib_3034_sept_2021265``, a Septentrio rover 5.3 km from GEONET 3034, unmodified files,
base at 3034's header position), which has no truth: gnssatt's single-epoch fixes are compared with RTKLIB's
``kinematic-instantaneous`` ones (``pos1-navsys=45``, ``-f 3``) epoch by epoch where both fix (a table of its
own: fixed counts, median and largest difference).
Simulated platforms (``car``, ``ship``, ``aircraft``, or ``platforms`` for all three): the presets of
``gnssatt.sim.platforms`` with three antennas and a static base, each noise profile of ``--profiles``
(``gps_l1_ublox``: GPS L1, ``-f 1``; ``geodetic``: GRECJ, three frequencies, ``-f 3``). RTKLIB runs
``kinematic-instantaneous``, ``kinematic-continuous`` and ``kinematic-fix-and-hold`` (each antenna against the
static base at its true position, the pair's baseline the difference of the two solutions, fixed where both
are) and ``movingbase-instantaneous`` / ``-continuous`` / ``-fix-and-hold`` (antenna 0 the base of antenna 1,
``pos2-armode`` in a conf copy); gnssatt runs the pair single-epoch, ``--filter kinematic`` and ``--filter
velocity`` (antenna 0 the moving base, no base position) and the three antennas with ``--baselines``,
single-epoch and ``--filter velocity`` (baseline 1 of its CSV). Per run: fix rate over every epoch of the
session (outages included), wrong fixes (fixed pair baselines more than ``--wrong-fix-m`` from the truth),
time to first fix from the session's start, time to re-fix after each whole outage (the longest), heading
error RMS over fixed and over all solved epochs, wall time (both RTKLIB runs of a kinematic pair summed). A
table of its own (``platforms.md``).
Modes: single epoch (RTKLIB ``kinematic-instantaneous.conf`` and
``movingbase-instantaneous.conf``; gnssatt ``--motion moving``), filtered (RTKLIB's Kalman filter,
``kinematic-continuous.conf``; gnssatt ``--filter kinematic``) and static (``static-continuous.conf``;
``--motion static``), with ``--method lambda``; each number of frequencies (``-f N`` / ``--frequencies N``)
and system set (``pos1-navsys`` in a conf copy / ``--systems``) the files hold; base position ``-r`` /
``--base-position`` from the base file's header.

``--threads N``: the engine's threads (``RAYON_NUM_THREADS`` of the gnssatt runs; ``rnx2rtkp`` runs on one).
RTKLIB: ``--rnx2rtkp PATH``, or built from ``--rtklib-src DIR`` (``DIR/build.sh``) into the output folder;
its confs are read from ``DIR/conf`` and written, modified, into the output folder (the peer folder is never
edited). Without ``--rtklib-src`` only gnssatt runs, and the table says RTKLIB was skipped.

gnssatt: ``gnssatt attitude`` of this interpreter's package (its console script beside ``sys.executable``,
else ``python -m gnssatt``), run as a user runs it (subprocess: interpreter start, import, reading, solving,
CSV and plot written). Options it lacks (``--frequencies``, ``--base-position``...)
are detected from ``gnssatt attitude --help``; runs that need a missing one are skipped and say so.
``--known-length``: gnssatt's single-epoch runs also get ``--baseline-length``, the reference's length.

Metrics per tool and run: fix rate (RTKLIB Q=1, gnssatt ``fixed``) over the session's epochs; wrong fixes
(fixed epochs whose baseline is more than ``--wrong-fix-m`` from the reference); time to first fix (first
fixed epoch less the first solved epoch of the run, s); median and 95th percentile
of the 3-D baseline error over fixed epochs and median over all solved epochs; wall time (median of
``--repeats``) and time per epoch. References: the truth for simulated data; for GEONET, RTKLIB's own static
L1+L2 fixed solution over the session (its last fixed epoch), or the header positions (metre level, no
wrong-fix count) without RTKLIB. Prints one markdown table and writes ``results.json`` into ``--out``.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
from collections.abc import Sequence
from pathlib import Path

# The parts live in the package beside this script (rtklib_bench/): the script is run by its path and the
# tests load it by its path, so its folder goes on the import path.
sys.path.insert(0, str(Path(__file__).resolve().parent))

from rtklib_bench.agreement import agreement
from rtklib_bench.comparison import compare, run_plan
from rtklib_bench.datasets import Dataset, cssrlib, geonet, rinex_header, simulated
from rtklib_bench.markdown import platform_table, table
from rtklib_bench.metrics import Reference, metrics, pair_solutions, platform_metrics
from rtklib_bench.platforms import PLATFORMS, PROFILES, compare_platforms
from rtklib_bench.rtklib import Rtklib, build_rtklib, navsys, write_conf
from rtklib_bench.runs import Settings, help_options
from rtklib_bench.solutions import Solutions, gpst_seconds, match_epochs, parse_gnssatt_csv, parse_pos

# Besides main: the parts tests/test_rtklib_compare.py and tests/test_sim_platforms.py take from the script
# (they load it by its path, as before its parts moved into rtklib_bench).
__all__ = [
    "Dataset",
    "Reference",
    "Solutions",
    "gpst_seconds",
    "help_options",
    "main",
    "match_epochs",
    "metrics",
    "navsys",
    "pair_solutions",
    "parse_gnssatt_csv",
    "parse_pos",
    "platform_metrics",
    "rinex_header",
    "run_plan",
    "table",
    "write_conf",
]

REPO = Path(__file__).resolve().parents[2]
DEFAULT_OUT = REPO / "out" / "rtklib_compare"


def _parser() -> argparse.ArgumentParser:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--rnx2rtkp", type=Path, default=None, help="RTKLIB rnx2rtkp binary (default: build it)")
    ap.add_argument("--rtklib-src", type=Path, default=None, help="RTKLIB 2.4.3 folder (build.sh, conf/)")
    ap.add_argument(
        "--datasets",
        default="geonet,sim",
        help="comma-separated: geonet, sim, cssrlib, car, ship, aircraft, platforms (= car,ship,aircraft) "
        "(default geonet,sim)",
    )
    ap.add_argument(
        "--profiles",
        default="gps_l1_ublox,geodetic",
        help="noise profiles of the simulated platforms (default gps_l1_ublox,geodetic)",
    )
    ap.add_argument(
        "--platform-duration-s",
        type=float,
        default=None,
        help="length of each simulated platform session, s (default: the preset's, car 60, ship and "
        "aircraft 120)",
    )
    ap.add_argument(
        "--cssrlib", type=Path, default=None, help="folder of the cssrlib 3034/SEPT pair (dataset cssrlib)"
    )
    ap.add_argument("--out", type=Path, default=DEFAULT_OUT, help=f"output folder (default {DEFAULT_OUT})")
    ap.add_argument("--repeats", type=int, default=1, help="runs per command; the median wall time is shown")
    ap.add_argument(
        "--sim-epochs", type=int, default=300, help="epochs of the simulated session (default 300)"
    )
    ap.add_argument("--seed", type=int, default=1, help="seed of the simulated session (default 1)")
    ap.add_argument(
        "--wrong-fix-m",
        type=float,
        default=0.05,
        help="a fixed epoch farther than this from the reference is a wrong fix, m (default 0.05)",
    )
    ap.add_argument(
        "--timeout-s", type=float, default=600.0, help="longest run of one command, s (default 600)"
    )
    ap.add_argument(
        "--known-length",
        action="store_true",
        help="gnssatt's single-epoch runs get --baseline-length: the reference's length (the truth, or "
        "RTKLIB's static solution for GEONET)",
    )
    ap.add_argument(
        "--threads",
        type=int,
        default=None,
        help="threads of gnssatt's engine (RAYON_NUM_THREADS of its runs; default: every CPU)",
    )
    return ap


def parse_args(argv: Sequence[str] | None) -> tuple[argparse.Namespace, list[str], list[str], list[str]]:
    """The command line checked: its arguments, the datasets, the simulated platforms and the profiles
    (``--threads`` sets ``RAYON_NUM_THREADS`` here, for every gnssatt run)."""
    ap = _parser()
    args = ap.parse_args(argv)
    if args.threads is not None:
        if args.threads < 1:
            ap.error(f"--threads: expected >= 1, got {args.threads}")
        os.environ["RAYON_NUM_THREADS"] = str(args.threads)
    names = [
        n.strip() for n in args.datasets.replace("platforms", ",".join(PLATFORMS)).split(",") if n.strip()
    ]
    if not names or any(n not in ("geonet", "sim", "cssrlib", *PLATFORMS) for n in names):
        ap.error(
            f"--datasets: expected geonet, sim, cssrlib, car, ship and/or aircraft, got {args.datasets!r}"
        )
    profiles = [p.strip() for p in args.profiles.split(",") if p.strip()]
    if not profiles or any(p not in PROFILES for p in profiles):
        ap.error(f"--profiles: expected {', '.join(PROFILES)}, got {args.profiles!r}")
    platforms = [n for n in names if n in PLATFORMS]
    names = [n for n in names if n not in PLATFORMS]
    if "cssrlib" in names and (args.cssrlib is None or args.rtklib_src is None):
        ap.error("--datasets cssrlib needs --cssrlib DIR and --rtklib-src DIR (RTKLIB is its reference)")
    if args.repeats < 1 or args.sim_epochs < 2 or not args.wrong_fix_m > 0 or not args.timeout_s > 0:
        ap.error("expected --repeats >= 1, --sim-epochs >= 2, --wrong-fix-m > 0 and --timeout-s > 0")
    if args.rnx2rtkp is not None and args.rtklib_src is None:
        ap.error("--rnx2rtkp needs --rtklib-src DIR for the confs in DIR/conf")
    return args, names, platforms, profiles


def run_datasets(
    names: Sequence[str], args: argparse.Namespace, rtk: Rtklib | None, out: Path, settings: Settings,
    report: dict[str, object],
) -> tuple[list[dict], list[str]]:  # fmt: skip
    """Compare both tools on each dataset of ``names`` (into ``report["datasets"]``); the rows of the
    table, and the text blocks of the datasets with a table of their own (cssrlib)."""
    all_rows, extra = [], []
    for name in names:
        if name == "cssrlib":
            assert rtk is not None
            ds = cssrlib(args.cssrlib)
            extra.append(
                f"{ds.description}:\n\n" + agreement(rtk, settings.options, ds, out / name, settings)
            )
            continue
        ds = geonet() if name == "geonet" else simulated(out / "sim-data", args.sim_epochs, args.seed)
        ref, rows = compare(ds, rtk, out / name, settings)
        report["datasets"][name] = {  # type: ignore[index]
            "description": ds.description,
            "bands": ds.bands,
            "reference": ref.description,
            "reference_enu_m": None if ref.time_s is not None else ref.enu_m.tolist(),
        }
        all_rows += rows
    return all_rows, extra


def main(argv: Sequence[str] | None = None) -> int:
    args, names, platforms, profiles = parse_args(argv)
    out = args.out.resolve()
    out.mkdir(parents=True, exist_ok=True)
    rtk = None if args.rtklib_src is None else build_rtklib(args.rtklib_src, args.rnx2rtkp, out)
    exe_help = subprocess.run(
        [sys.executable, "-m", "gnssatt", "attitude", "--help"], capture_output=True, text=True, check=True
    ).stdout
    options = help_options(exe_help)
    settings = Settings(options, args.repeats, args.wrong_fix_m, args.timeout_s, args.known_length)
    # The machine may be shared: the load beside the CPU count says how far wall times are inflated.
    threads = os.environ.get("RAYON_NUM_THREADS", "every CPU")
    load = os.getloadavg()[0]
    machine = f"{os.cpu_count()} CPUs, load average {load:.1f} at the start, gnssatt threads {threads}"
    report: dict[str, object] = {
        "machine": machine,
        "rtklib": None if rtk is None else str(rtk.binary),
        "gnssatt_options": sorted(options),
        "wrong_fix_m": args.wrong_fix_m,
        "repeats": args.repeats,
        "datasets": {},
    }
    all_rows, extra = run_datasets(names, args, rtk, out, settings, report)
    report["rows"] = all_rows
    platform_text = ""
    if platforms:
        described, p_rows = compare_platforms(
            platforms, profiles, rtk, out, settings, args.platform_duration_s, args.seed
        )
        report["platforms"] = {"sessions": described, "rows": p_rows}
        platform_text = platform_table(p_rows)
    text = table(all_rows)
    print(f"machine: {machine}; wall times: median of {args.repeats} run(s)")
    print("RTKLIB skipped (no --rtklib-src): gnssatt only\n" if rtk is None else "", end="")
    for name, d in report["datasets"].items():  # type: ignore[attr-defined]
        print(f"{name}: {d['description']}; reference: {d['reference']}")
    if all_rows:
        print()
        print(text)
    for block in extra:
        print("\n" + block)
    if platform_text:
        print("\nsimulated platforms:\n" + "\n".join(f"- {d}" for d in report["platforms"]["sessions"]))  # type: ignore[index]
        print("\n" + platform_text)
        (out / "platforms.md").write_text(platform_text + "\n")
    (out / "results.json").write_text(json.dumps(report, indent=1, default=str))
    (out / "table.md").write_text(text + "\n")
    print(f"\nwrote {out / 'results.json'} and {out / 'table.md'}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
