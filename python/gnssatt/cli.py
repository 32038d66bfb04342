"""The ``gnssatt`` command: ``gnssatt reproduce ...`` runs the source papers' experiments;
``gnssatt attitude ...`` processes recorded RINEX data of antennas on one platform;
``gnssatt position ...`` gives the code position of one receiver at every epoch of a file (the help texts
are plain text: ``gnssatt --help``).

Every failure is one line on stderr, ``gnssatt: error: ...``, naming what was wrong with the command-line
option names, and exit status 2 (130 after Ctrl-C); no traceback is printed.
"""

from __future__ import annotations

import argparse
import os
import re
import sys
import time
import warnings
from collections.abc import Callable, Sequence
from pathlib import Path
from types import ModuleType
from typing import Any

__all__ = ["main"]

#: Library parameter names as the command line spells them, for messages raised below the CLI.
#: (Only names that are not also plain words of other messages, and never inside RINEX messages.)
_OPTION_NAMES = {
    "window_deg": "--window",
    "step_deg": "--step",
    "elevation_mask_deg": "--elevation-mask",
    "min_success_rate": "--min-success-rate",
    "ratio_threshold": "--ratio-threshold",
    "max_failure_rate": "--max-failure-rate",
    "base_position_m": "--base-position",
    "baseline_length_m": "--baseline-length",
    "n_trials": "--runs",
    "seed": "--seed",
}
_OPTION_PATTERN = re.compile(r"(?<![-\w])(" + "|".join(_OPTION_NAMES) + r")\b")


def _integer(minimum: int) -> Callable[[str], int]:
    """An argparse type: an integer >= ``minimum`` (checked before any work starts)."""

    def parse(text: str) -> int:
        try:
            value = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"expected an integer >= {minimum}, got {text!r}") from None
        if value < minimum:
            raise argparse.ArgumentTypeError(f"expected an integer >= {minimum}, got {value}")
        return value

    return parse


def _real(minimum: float, maximum: float) -> Callable[[str], float]:
    """An argparse type: a finite number in ``[minimum, maximum]``."""

    def parse(text: str) -> float:
        try:
            value = float(text)
        except ValueError:
            raise argparse.ArgumentTypeError(
                f"expected a number in [{minimum}, {maximum}], got {text!r}"
            ) from None
        if not minimum <= value <= maximum:
            raise argparse.ArgumentTypeError(f"expected a number in [{minimum}, {maximum}], got {value}")
        return value

    return parse


def _systems(text: str) -> str:
    """An argparse type: system letters among GRECJ."""
    if not text or any(ch not in "GRECJ" for ch in text):
        raise argparse.ArgumentTypeError(f"expected system letters among GRECJ, such as GE, got {text!r}")
    return text


class _UsageError(Exception):
    """A command line that argparse or a check here refuses."""


class _Parser(argparse.ArgumentParser):
    def error(self, message: str) -> None:  # type: ignore[override]
        # argparse would print the usage and exit; main prints one line instead
        raise _UsageError(message)


def _one_line(exc: BaseException) -> str:
    """The error message on one line, library parameter names replaced by the CLI's option names."""
    from gnssatt.errors import GnssattError, InternalError, RinexError

    text = " ".join(str(exc).split()) or type(exc).__name__
    if not isinstance(exc, RinexError | _UsageError):
        text = _OPTION_PATTERN.sub(lambda m: _OPTION_NAMES[m.group(1)], text)
    if isinstance(exc, OSError) and exc.filename is not None:
        return f"{exc.filename}: {exc.strerror or text}"
    if isinstance(exc, InternalError):
        return f"internal error, please report it with the command line: {text}"
    if isinstance(exc, GnssattError | ValueError | _UsageError):
        return text
    return f"unexpected {type(exc).__name__}, please report it with the command line: {text}"


def _writable(option: str, path: Path, *, folder: bool) -> None:
    """Refuse an output path that cannot be written before the work starts (not after it)."""
    target = path if folder else path.parent
    if not folder and not target.is_dir():
        # a file goes into a folder that exists: a mistyped folder is refused, not created
        what = "is not a folder" if target.exists() else "does not exist"
        raise _UsageError(f"{option} {path}: {target} {what}")
    try:
        target.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise _UsageError(f"{option} {path}: cannot create folder {target}: {exc.strerror or exc}") from exc
    if not folder and path.is_dir():
        raise _UsageError(f"{option} {path}: is a folder, expected a file name")
    if not os.access(target, os.W_OK):
        raise _UsageError(f"{option} {path}: folder {target} is not writable")


#: ``gnssatt reproduce``'s root seed when ``--seed`` is not given.
_DEFAULT_SEED = 2026


def _reproduce(args: argparse.Namespace) -> int:
    from gnssatt.experiments import EXPERIMENTS, get

    if args.list:
        # --list runs nothing: an option of a run given with it would change nothing
        given = [
            option
            for option, used in (
                ("experiment names", bool(args.names)),
                ("--all", args.all),
                ("--runs", args.runs is not None),
                ("--seed", args.seed is not None),
                ("--out", args.out is not None),
                ("--no-progress", args.no_progress),
            )
            if used
        ]
        if given:
            raise _UsageError(
                f"reproduce --list lists the experiments and runs none: {', '.join(given)} would change "
                "nothing; leave them out, or leave out --list"
            )
        width = max(map(len, EXPERIMENTS))
        for exp in EXPERIMENTS.values():
            print(f"{exp.name.ljust(width)}  {exp.summary}  (default runs {exp.default_runs})")
        return 0
    if args.all == bool(args.names):
        raise _UsageError("reproduce: give experiment names, --all, or --list")
    unknown = [n for n in args.names if n not in EXPERIMENTS]
    if unknown:
        raise _UsageError(f"reproduce: unknown experiment {unknown[0]!r}; known: {', '.join(EXPERIMENTS)}")
    chosen = list(EXPERIMENTS.values()) if args.all else [get(n) for n in args.names]
    args.seed = _DEFAULT_SEED if args.seed is None else args.seed
    args.out = Path("out") if args.out is None else args.out
    _writable("--out", args.out, folder=True)
    for exp in chosen:
        runs = args.runs or (exp.quick_runs if args.all else exp.default_runs)
        t0 = time.perf_counter()
        # Quick counts (--all) make every statistic noisier than the results pages', which use the default.
        quick = (
            f" (fewer than the default {exp.default_runs}: noisier statistics)"
            if runs < exp.default_runs
            else ""
        )
        print(f"\n=== {exp.name}: {runs} runs{quick}, seed {args.seed}")
        exp.run(runs=runs, seed=args.seed, out=args.out, executor=None, progress=not args.no_progress)
        print(f"({time.perf_counter() - t0:.1f} s; outputs in {args.out})")
    return 0


def _output_arguments(parser: argparse.ArgumentParser, default: str) -> None:
    """``--out`` (a CSV; the plot beside it) and ``--no-plot``, alike for ``attitude`` and ``position``."""
    parser.add_argument(
        "--out",
        type=Path,
        default=Path(default),
        help=f"CSV output; the plot goes to the same name .png (default {default} in the current folder)",
    )
    parser.add_argument(
        "--no-plot", action="store_true", help="write only the CSV (the plot costs about a second)"
    )


def _plot_path(out: Path) -> Path:
    """The plot's file, the CSV ``out`` with ``.png``, once ``out`` is known to be a writable CSV name."""
    png = out.with_suffix(".png")
    if png == out:
        raise _UsageError(f"--out {out}: expected a CSV file name (the plot goes to the same name .png)")
    _writable("--out", out, folder=False)
    return png


def _write(
    args: argparse.Namespace,
    series: Any,
    png: Path,
    caught: list[warnings.WarningMessage],
    plot: Callable[[ModuleType], object],
    notes: Sequence[str] = (),
    also_written: Sequence[Path] = (),
) -> int:
    """Write the CSV and (unless ``--no-plot``) the plot, then the warnings ``caught`` one line each on
    stderr, the summary, the ``notes`` and what was written (the files ``also_written`` already were)."""
    series.to_csv(args.out)
    if not args.no_plot:
        # matplotlib costs about a second: imported only when the plot is wanted
        from gnssatt import plots

        plot(plots)
    for w in caught:
        print(f"gnssatt: warning: {' '.join(str(w.message).split())}", file=sys.stderr)
    print(series.summary())
    for note in notes:
        print(note)
    print(f"wrote {args.out}" if args.no_plot else f"wrote {args.out} and {png}")
    for path in also_written:
        print(f"wrote {path}")
    return 0


def _attitude(args: argparse.Namespace) -> int:
    import numpy as np

    from gnssatt.gnss.attitude import attitude_from_rinex

    png = _plot_path(args.out)
    if args.nmea is not None:
        _writable("--nmea", args.nmea, folder=False)
    baselines = None
    if args.baselines is not None:
        if not args.baselines.is_file():
            what = "is not a file" if args.baselines.exists() else "does not exist"
            raise _UsageError(f"--baselines {args.baselines}: {what}")
        try:
            baselines = np.atleast_2d(np.loadtxt(args.baselines, ndmin=2))
        except (OSError, ValueError) as exc:
            raise _UsageError(
                f"--baselines {args.baselines}: cannot read rows 'x y z': {_one_line(exc)}"
            ) from exc
    with warnings.catch_warnings(record=True) as caught:
        # the library's warnings (a system dropped from a file, the engine's) become one line each, below
        warnings.simplefilter("always")
        series = attitude_from_rinex(
            args.obs,
            args.nav,
            baselines,
            method=args.method,
            motion=args.motion,
            continuity=args.continuity,
            filter=args.filter,
            rigid=args.rigid,
            systems=args.systems,
            frequencies=args.frequencies if args.frequencies == "all" else int(args.frequencies),
            elevation_mask_deg=args.elevation_mask,
            min_success_rate=args.min_success_rate,
            ratio_threshold=args.ratio_threshold,
            max_failure_rate=args.max_failure_rate,
            base_position_m=args.base_position,
            step_deg=args.step,
            window_deg=args.window,
            baseline_length_m=args.baseline_length,
        )
    if args.nmea is not None:
        from gnssatt.gnss.nmea import write_nmea

        write_nmea(args.nmea, series)
    static = args.motion == "static" or (
        args.motion is None and baselines is None and not args.continuity and args.filter is None
    )
    notes = [series.combined_baseline().summary()] if static and np.any(series.fixed == 1) else []
    data = " -> ".join(Path(o).name for o in args.obs)
    return _write(
        args,
        series,
        png,
        caught,
        lambda plots: plots.attitude_series(series, png, data=data),
        notes=notes,
        also_written=[] if args.nmea is None else [args.nmea],
    )


def _frequency_choices() -> tuple[str, ...]:
    """``--frequencies``: 1 to the engine's most frequency slots, or all."""
    from gnssatt import _core

    return (*(str(n) for n in range(1, _core.GNSS_MAX_FREQUENCIES + 1)), "all")


def _fixing_options(parser: argparse.ArgumentParser) -> None:
    """How the integers are fixed: the method, static or moving, held along arcs, the acceptance tests."""
    from gnssatt import _core

    fixing = parser.add_argument_group("ambiguity fixing")
    fixing.add_argument(
        "--method",
        choices=_core.GNSS_METHODS,
        default="auto",
        help="ml: ambiguity-function grid per epoch; lambda: LAMBDA-fixed double differences (attitude "
        "mode: constrained by the baselines); auto: lambda beyond 100 m, else ml (default auto)",
    )
    fixing.add_argument(
        "--motion",
        choices=_core.GNSS_MOTIONS,
        default=None,
        help="static fixes the session's ambiguities once, moving fixes each epoch (default: static for two "
        "antennas, moving with --baselines or --continuity)",
    )
    fixing.add_argument(
        "--continuity",
        action="store_true",
        help="moving mode: hold fixed ambiguities along arcs without cycle slips while they agree with "
        "each epoch's data, with --baselines too (implies --motion moving; refused with --motion static)",
    )
    fixing.add_argument(
        "--min-success-rate",
        type=_real(0.0, 1.0),
        default=None,
        metavar="P",
        help="smallest bootstrapped success rate of the ambiguities fixed; fewer are fixed (partial fixing) "
        f"when the full set falls short (default {_core.GNSS_DEFAULT_MIN_SUCCESS_RATE})",
    )
    fixing.add_argument(
        "--ratio-threshold",
        type=_real(1.0, 1e6),
        default=None,
        metavar="R",
        help=f"ratio-test threshold (default {_core.GNSS_DEFAULT_RATIO_THRESHOLD})",
    )
    fixing.add_argument(
        "--max-failure-rate",
        type=_real(0.0, 0.1),
        default=None,
        metavar="P",
        help="below the success-rate gate, still fix a set whose ratio passes the fixed-failure-rate test "
        f"for this probability of a wrong fix; 0: off (default {_core.GNSS_DEFAULT_MAX_FAILURE_RATE})",
    )


def _filter_options(parser: argparse.ArgumentParser) -> None:
    """The multi-epoch Kalman filter of each baseline and its rigid-body length."""
    from gnssatt import _core

    kalman = parser.add_argument_group("multi-epoch filter")
    kalman.add_argument(
        "--filter",
        choices=_core.GNSS_FILTERS,
        default=None,
        help="a multi-epoch Kalman filter of each baseline with this process model (static; "
        "kinematic: random walk, each epoch from its own data and the carried ambiguities; velocity: "
        "constant velocity), fixing on its covariance and holding the integers (with --baselines: the "
        "filtered baselines fixed together under the body baselines); the CSV's state column says "
        "fixed, held or float (implies --motion moving)",
    )
    kalman.add_argument(
        "--rigid",
        action="store_true",
        help="with --filter: both antennas are on one rigid body (a moving base on the vehicle), so the "
        "baseline length is constant; the filter learns it from its fixes and refuses a fix whose length "
        "disagrees (not for a rover moving against a static base)",
    )


def _signal_options(parser: argparse.ArgumentParser) -> None:
    """Which signals the engine uses: systems, frequency slots, the elevation mask."""
    from gnssatt import _core

    signals = parser.add_argument_group("signals")
    signals.add_argument(
        "--systems",
        type=_systems,
        default="GRECJ",
        help="satellite systems, letters among GRECJ (default GRECJ: all in both files)",
    )
    signals.add_argument(
        "--frequencies",
        choices=_frequency_choices(),
        default="all",
        help="frequency slots per system: 1 L1/G1/E1/B1I, 2 adds L2/G2/E5b/B2I, 3 adds L5/G3/E5a/B3I "
        "(default all)",
    )
    signals.add_argument(
        "--elevation-mask",
        type=_real(-90.0, 90.0),
        default=None,
        metavar="DEG",
        help=f"at the reference antenna, degrees (default {_core.GNSS_DEFAULT_ELEVATION_MASK_DEG:g})",
    )


def _grid_options(parser: argparse.ArgumentParser) -> None:
    """The ambiguity-function grid of ``--method ml``."""
    grid = parser.add_argument_group("ml grid")
    grid.add_argument(
        "--window",
        type=float,
        default=None,
        metavar="DEG",
        help="ml: search +/- DEG around the previous epoch's solution (default: the whole domain)",
    )
    grid.add_argument(
        "--step",
        type=float,
        default=None,
        metavar="DEG",
        help="ml: grid step (default: eq. (15) of Bunyaeva et al.)",
    )


def _position(args: argparse.Namespace) -> int:
    from gnssatt.gnss.position import position_from_rinex

    png = _plot_path(args.out)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        series = position_from_rinex(
            args.obs,
            args.nav,
            systems=args.systems,
            frequencies=args.frequencies if args.frequencies == "all" else int(args.frequencies),
            elevation_mask_deg=args.elevation_mask,
        )
    return _write(args, series, png, caught, lambda plots: plots.position_series(series, png))


def _position_arguments(pos: argparse.ArgumentParser) -> None:
    pos.add_argument("--obs", required=True, type=Path, help="observation file")
    pos.add_argument("--nav", action="append", required=True, type=Path, help="navigation file(s)")
    _output_arguments(pos, "position.csv")
    pos.add_argument(
        "--systems",
        type=_systems,
        default="GRECJ",
        help="satellite systems, letters among GRECJ (default GRECJ: all the file has)",
    )
    pos.add_argument(
        "--frequencies",
        choices=_frequency_choices(),
        default="1",
        help="frequency slots a satellite's code may come from, its lowest used: 1 L1/G1/E1/B1I, 2 adds "
        "L2/G2/E5b/B2I, 3 adds L5/G3/E5a/B3I (default 1)",
    )
    pos.add_argument(
        "--elevation-mask",
        type=_real(-90.0, 90.0),
        default=10.0,
        metavar="DEG",
        help="degrees (default 10)",
    )


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command line ``argv`` (default ``sys.argv[1:]``); the exit status: 0, 2 on any failure
    (one line on stderr), 130 when interrupted."""
    try:
        return _main(argv)
    except KeyboardInterrupt:
        print("gnssatt: error: interrupted", file=sys.stderr)
        return 130
    except SystemExit as exc:  # --help
        return exc.code if isinstance(exc.code, int) else 0 if exc.code is None else 2
    except Exception as exc:
        print(f"gnssatt: error: {_one_line(exc)}", file=sys.stderr)
        return 2


_DESCRIPTION = """Attitude determination from GNSS signals and complementary sensors.

Every failure is one line on stderr, "gnssatt: error: ...", and exit status 2 (130 after Ctrl-C)."""

_EPILOG = """examples:
  gnssatt reproduce --all --out out
  gnssatt attitude --obs rover0.obs --obs rover1.obs --nav brdc.nav --out attitude.csv

"gnssatt COMMAND --help" describes each command."""

_REPRODUCE = """Run the source papers' experiments as Monte Carlo studies. Each prints a table
of the paper's numbers against the measured ones, with the tolerance and the
verdict of each comparison, and writes OUT/NAME.json (with the package version
and git commit) and its plots. The results pages (docs/results/) explain every
number."""

_REPRODUCE_EPILOG = """examples:
  gnssatt reproduce --list
  gnssatt reproduce matrix-method --runs 5000 --seed 1 --out out
  gnssatt reproduce --all --out out        (every experiment, quick run counts)"""

_ATTITUDE = """Attitude (three or more antennas on one platform) or baseline direction (two
antennas) per epoch from recorded RINEX observation files, one per antenna, and
broadcast navigation files. Writes a CSV of the series and a plot of it, and
prints a summary."""

_ATTITUDE_EPILOG = """examples:
  gnssatt attitude --obs base.obs --obs rover.obs --nav brdc.nav --out baseline.csv
  gnssatt attitude --obs a0.obs --obs a1.obs --obs a2.obs --nav brdc.nav \\
      --baselines baselines.txt --out attitude.csv"""


def _reproduce_arguments(rep: argparse.ArgumentParser) -> None:
    rep.add_argument("names", nargs="*", help="experiment names (see --list)")
    rep.add_argument("--list", action="store_true", help="list the experiments")
    rep.add_argument("--all", action="store_true", help="run every experiment with quick defaults")
    rep.add_argument(
        "--runs", type=_integer(1), default=None, help="Monte Carlo runs (default: per experiment)"
    )
    rep.add_argument(
        "--seed", type=_integer(0), default=None, help=f"root random seed (default {_DEFAULT_SEED})"
    )
    rep.add_argument("--out", type=Path, default=None, help="output folder (default ./out)")
    rep.add_argument("--no-progress", action="store_true", help="hide progress bars")


def _attitude_arguments(att: argparse.ArgumentParser) -> None:
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
        "--baseline-length",
        type=_real(0.01, 1e4),
        nargs="+",
        default=None,
        metavar="M",
        help="known distance of each rover antenna from the first, m (two antennas: one value; baseline "
        "mode): the integers are fixed with this length constraint",
    )
    att.add_argument(
        "--base-position",
        type=float,
        nargs=3,
        default=None,
        metavar=("X", "Y", "Z"),
        help="surveyed ECEF position of the reference antenna, m (default: its code solution)",
    )
    _output_arguments(att, "results.csv")
    att.add_argument(
        "--nmea",
        type=Path,
        default=None,
        metavar="FILE",
        help="also write NMEA 0183 $GNHDT (true heading) and $PSAT,HPR (heading, pitch, roll, UTC) "
        "sentences per solved epoch to FILE (docs/observation_engine.md)",
    )
    _fixing_options(att)
    _filter_options(att)
    _signal_options(att)
    _grid_options(att)


_RAW = argparse.RawDescriptionHelpFormatter

#: Each command: its ``add_parser`` keywords, the function adding its arguments, the one running it.
_COMMANDS: dict[
    str, tuple[dict[str, Any], Callable[[argparse.ArgumentParser], None], Callable[[argparse.Namespace], int]]
] = {
    "reproduce": (
        {
            "help": "run the source papers' experiments",
            "description": _REPRODUCE,
            "epilog": _REPRODUCE_EPILOG,
            "formatter_class": _RAW,
        },
        _reproduce_arguments,
        _reproduce,
    ),
    "attitude": (
        {
            "help": "attitude or baseline direction from RINEX files",
            "description": _ATTITUDE,
            "epilog": _ATTITUDE_EPILOG,
            "formatter_class": _RAW,
        },
        _attitude_arguments,
        _attitude,
    ),
    "position": (
        {"help": "code position of one receiver at every epoch of a RINEX file"},
        _position_arguments,
        _position,
    ),
}


def _parser(command: str | None) -> _Parser:
    """The command line's parser; with ``command``, that command's only. argparse builds a help formatter for
    every argument it adds, start-up time for nothing when the others cannot be used: once a command's
    parser has the rest of the line, nothing shows the other commands (only the top-level help and its
    unknown-command error list them, and neither comes after a valid command)."""
    from gnssatt._core import __version__

    parser = _Parser(prog="gnssatt", description=_DESCRIPTION, epilog=_EPILOG, formatter_class=_RAW)
    parser.add_argument("--version", action="version", version=f"gnssatt {__version__}")
    sub = parser.add_subparsers(dest="command", required=True, parser_class=_Parser)
    for name, (keywords, arguments, _) in _COMMANDS.items():
        if command in (None, name):
            arguments(sub.add_parser(name, **keywords))
    return parser


def _main(argv: Sequence[str] | None) -> int:
    argv = sys.argv[1:] if argv is None else list(argv)
    # Only a command given first is known before parsing (the top-level options come before it).
    command = argv[0] if argv and argv[0] in _COMMANDS else None
    args = _parser(command).parse_args(argv)
    return _COMMANDS[args.command][2](args)


if __name__ == "__main__":
    raise SystemExit(main())
