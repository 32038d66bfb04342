"""The ``gnssatt`` command: ``gnssatt reproduce ...`` runs the source papers' experiments;
``gnssatt attitude ...`` processes recorded RINEX data of antennas on one platform."""

from __future__ import annotations

import argparse
import sys
import time
from collections.abc import Sequence
from pathlib import Path

__all__ = ["main"]


def _reproduce(args: argparse.Namespace) -> int:
    from gnssatt.experiments import EXPERIMENTS, get

    if args.list:
        width = max(map(len, EXPERIMENTS))
        for exp in EXPERIMENTS.values():
            print(f"{exp.name.ljust(width)}  {exp.summary}  (default runs {exp.default_runs})")
        return 0
    if args.all == bool(args.names):
        print("gnssatt reproduce: give experiment names, --all, or --list", file=sys.stderr)
        return 2
    try:
        chosen = list(EXPERIMENTS.values()) if args.all else [get(n) for n in args.names]
    except KeyError as exc:
        print(f"gnssatt reproduce: {exc.args[0]}", file=sys.stderr)
        return 2
    for exp in chosen:
        runs = args.runs or (exp.quick_runs if args.all else exp.default_runs)
        t0 = time.perf_counter()
        print(f"\n=== {exp.name}: {runs} runs, seed {args.seed}")
        exp.run(runs=runs, seed=args.seed, out=args.out, executor=None, progress=not args.no_progress)
        print(f"({time.perf_counter() - t0:.1f} s; outputs in {args.out})")
    return 0


def _attitude(args: argparse.Namespace) -> int:
    import numpy as np

    from gnssatt.errors import GnssattError
    from gnssatt.plots import attitude_series
    from gnssatt.rinex.attitude import attitude_from_rinex

    try:
        baselines = None
        if args.baselines is not None:
            try:
                baselines = np.atleast_2d(np.loadtxt(args.baselines, ndmin=2))
            except (OSError, ValueError) as exc:
                print(f"gnssatt attitude: {args.baselines}: cannot read baselines: {exc}", file=sys.stderr)
                return 2
        series = attitude_from_rinex(
            args.obs,
            args.nav,
            baselines,
            method=args.method,
            motion=args.motion,
            continuity=args.continuity,
            window_deg=args.window,
            baseline_length_m=args.baseline_length,
            systems=args.systems,
            elevation_mask_deg=args.elevation_mask,
        )
    except GnssattError as exc:
        print(f"gnssatt attitude: {exc}", file=sys.stderr)
        return 2
    args.out.parent.mkdir(parents=True, exist_ok=True)
    series.to_csv(args.out)
    png = attitude_series(series, args.out.with_suffix(".png"))
    print(series.summary())
    print(f"wrote {args.out} and {png}")
    return 0


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="gnssatt", description=__doc__)
    sub = parser.add_subparsers(dest="command", required=True)
    rep = sub.add_parser("reproduce", help="run the source papers' experiments")
    rep.add_argument("names", nargs="*", help="experiment names (see --list)")
    rep.add_argument("--list", action="store_true", help="list the experiments")
    rep.add_argument("--all", action="store_true", help="run every experiment with quick defaults")
    rep.add_argument("--runs", type=int, default=None, help="Monte Carlo runs (default: per experiment)")
    rep.add_argument("--seed", type=int, default=2026, help="root random seed (default 2026)")
    rep.add_argument("--out", type=Path, default=Path("out"), help="output folder (default ./out)")
    rep.add_argument("--no-progress", action="store_true", help="hide progress bars")
    att = sub.add_parser("attitude", help="attitude or baseline direction from RINEX files")
    att.add_argument(
        "--obs",
        action="append",
        required=True,
        type=Path,
        help="observation file, once per antenna; the first is the reference",
    )
    att.add_argument("--nav", action="append", required=True, type=Path, help="navigation file(s)")
    att.add_argument(
        "--baselines",
        type=Path,
        default=None,
        help="text file of (n_ant - 1) rows 'x y z' (body frame, m); omit for two antennas",
    )
    att.add_argument(
        "--out", type=Path, default=Path("results.csv"), help="CSV output (plot: same name .png)"
    )
    att.add_argument(
        "--method",
        choices=("auto", "ml", "lambda"),
        default="auto",
        help="ml: ambiguity-function grid per epoch; lambda: LAMBDA-fixed double differences (attitude "
        "mode: per epoch, constrained by the baselines); auto: lambda beyond 100 m, else ml",
    )
    att.add_argument(
        "--motion",
        choices=("static", "moving"),
        default="static",
        help="baseline mode with lambda: static fixes the session's ambiguities once, moving fixes each "
        "epoch (attitude mode is always per epoch)",
    )
    att.add_argument(
        "--continuity",
        action="store_true",
        help="per-epoch lambda: hold fixed ambiguities along arcs without cycle slips",
    )
    att.add_argument(
        "--window",
        type=float,
        default=None,
        metavar="DEG",
        help="ml: search +/- DEG around the previous epoch's solution (default: the whole domain)",
    )
    att.add_argument(
        "--baseline-length",
        type=float,
        default=None,
        metavar="M",
        help="ml in baseline mode: baseline length, m (default: from the lambda solution)",
    )
    att.add_argument("--systems", default="G", help="satellite systems to use (default G)")
    att.add_argument("--elevation-mask", type=float, default=10.0, help="degrees (default 10)")
    args = parser.parse_args(argv)
    if args.command == "attitude":
        return _attitude(args)
    if args.runs is not None and args.runs < 1:
        parser.error("--runs must be >= 1")
    return _reproduce(args)


if __name__ == "__main__":
    raise SystemExit(main())
