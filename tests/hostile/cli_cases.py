"""Bad command lines for ``gnssatt`` (run as ``python -m gnssatt.cli``): each must end with exit status 2
and a message, never a traceback, within the hang limit."""

from __future__ import annotations

import os
import subprocess
import sys
import time
from dataclasses import dataclass
from pathlib import Path

from . import outcomes as oc
from .worker import HANG_S


@dataclass(frozen=True)
class CliCase:
    label: str
    argv: tuple[str, ...]


def cases(obs: tuple[Path, ...], nav: Path, bad_obs: Path, folder: Path) -> list[CliCase]:
    """``obs``/``nav``: valid files; ``bad_obs``: a mutated observation file; ``folder``: scratch space."""
    o = [str(p) for p in obs]
    att = ("attitude", "--nav", str(nav), *(a for p in o for a in ("--obs", p)))
    unwritable = "/proc/gnssatt-hostile/out.csv"
    return [
        CliCase("no arguments", ()),
        CliCase("unknown command", ("frobnicate",)),
        CliCase("attitude without files", ("attitude",)),
        CliCase(
            "missing nav file", ("attitude", "--nav", "/nonexistent/x.24n", "--obs", o[0], "--obs", o[1])
        ),
        CliCase(
            "missing obs file", ("attitude", "--nav", str(nav), "--obs", "/nonexistent/x.24o", "--obs", o[1])
        ),
        CliCase("a folder as obs", ("attitude", "--nav", str(nav), "--obs", str(folder), "--obs", o[1])),
        CliCase("one obs file", ("attitude", "--nav", str(nav), "--obs", o[0])),
        CliCase("mutated obs file", ("attitude", "--nav", str(nav), "--obs", str(bad_obs), "--obs", o[1])),
        CliCase("unwritable --out", (*att, "--out", unwritable)),
        CliCase("--out is a folder", (*att, "--out", str(folder))),
        CliCase("--elevation-mask nan", (*att, "--elevation-mask", "nan")),
        CliCase("--elevation-mask 1e999", (*att, "--elevation-mask", "1e999")),
        CliCase("--elevation-mask abc", (*att, "--elevation-mask", "abc")),
        CliCase("--elevation-mask 95", (*att, "--elevation-mask", "95")),
        CliCase("--window -5", (*att, "--window", "-5")),
        CliCase("--window nan", (*att, "--window", "nan")),
        CliCase("--baseline-length 0", (*att, "--baseline-length", "0")),
        CliCase("--baselines garbage", (*att, "--baselines", "1,2")),
        CliCase("--method unknown", (*att, "--method", "telepathy")),
        CliCase("--systems X", (*att, "--systems", "X")),
        CliCase("reproduce unknown experiment", ("reproduce", "no-such-experiment")),
        CliCase("reproduce --runs -1", ("reproduce", "--runs", "-1", "--no-progress", "matrix-method")),
        CliCase("reproduce --runs 0", ("reproduce", "--runs", "0", "--no-progress", "matrix-method")),
        CliCase(
            "reproduce --runs 10**12", ("reproduce", "--runs", str(10**12), "--no-progress", "matrix-method")
        ),
        CliCase(
            "reproduce --out unwritable", ("reproduce", "--runs", "1", "--out", unwritable, "matrix-method")
        ),
    ]


def run_case(case: CliCase, hang_s: float = HANG_S) -> tuple[str, str, float]:
    """(outcome, detail, seconds): exit 2 with a one-line message and no traceback is ``refused-ok``."""
    env = {**os.environ, "PYTHONFAULTHANDLER": "", "MPLBACKEND": "Agg"}
    start = time.perf_counter()
    try:
        proc = subprocess.run(
            [sys.executable, "-m", "gnssatt.cli", *case.argv],
            capture_output=True,
            text=True,
            timeout=hang_s + 5.0,  # interpreter start and imports, about 2 s on a loaded machine
            env=env,
        )
    except subprocess.TimeoutExpired:
        return oc.HANG, f"no exit in {hang_s + 5.0:.0f} s", time.perf_counter() - start
    seconds = time.perf_counter() - start
    err = proc.stderr.strip()
    last = err.splitlines()[-1] if err else ""
    if proc.returncode < 0:
        return oc.ABORT, f"killed by signal {-proc.returncode}", seconds
    if "Traceback" in err or "PanicException" in err or "panicked" in err:
        return (oc.PANIC if "panic" in err.lower() else oc.WRONG), f"traceback: {last[:160]}", seconds
    if proc.returncode == 0:
        return oc.ACCEPTED_INVALID, f"exit 0: {proc.stdout.strip()[-160:]}", seconds
    if proc.returncode != 2 or not err:
        return oc.WRONG, f"exit {proc.returncode}: {last[:160]}", seconds
    return oc.REFUSED, last[:160], seconds
