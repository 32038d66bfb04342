"""Running the tools: timed subprocess runs, the options ``gnssatt attitude`` offers, and its command
line for one run."""

from __future__ import annotations

import re
import statistics
import subprocess
import sys
import time
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from .datasets import Dataset


def help_options(help_text: str) -> frozenset[str]:
    """Long options (``--name``) that a ``--help`` text offers."""
    return frozenset(re.findall(r"(?<![\w-])--[a-z][a-z0-9-]*", help_text))


@dataclass(frozen=True)
class Settings:
    """Command-line settings every run shares."""

    options: frozenset[str]  # of `gnssatt attitude --help`
    repeats: int
    wrong_fix_m: float
    timeout_s: float
    known_length: bool = False


@dataclass
class Timed:
    """One tool's run: command, median wall time, and the metrics or why there are none."""

    command: list[str]
    wall_s: list[float] = field(default_factory=list)
    metrics: dict[str, float | int | None] | None = None
    enu_source: str = ""
    note: str = ""

    @property
    def median_wall_s(self) -> float | None:
        return statistics.median(self.wall_s) if self.wall_s else None


def timed_run(cmd: Sequence[str], output: Path, repeats: int, timeout_s: float) -> tuple[list[float], str]:
    """Run ``cmd`` ``repeats`` times (output file removed first); wall times and, on failure, why.

    A run longer than ``timeout_s`` is stopped and reported as a failure (no hang of the comparison).
    """
    walls = []
    for _ in range(repeats):
        output.unlink(missing_ok=True)
        t0 = time.perf_counter()
        try:
            proc = subprocess.run(list(cmd), capture_output=True, text=True, check=False, timeout=timeout_s)
        except subprocess.TimeoutExpired:
            return walls, f"stopped after {timeout_s:g} s (--timeout-s)"
        wall = time.perf_counter() - t0
        if proc.returncode != 0 or not output.exists():
            tail = (proc.stderr.strip().splitlines() or ["no output"])[-1]
            return walls, f"exit {proc.returncode}: {tail[:200]}"
        walls.append(wall)
    return walls, ""


def gnssatt_head() -> list[str]:
    """How a user starts this interpreter's gnssatt: its console script beside ``sys.executable``, else
    ``python -m gnssatt``."""
    exe = Path(sys.executable).with_name("gnssatt")
    return [str(exe)] if exe.exists() else [sys.executable, "-m", "gnssatt"]


def gnssatt_command(
    ds: Dataset,
    motion: str,
    systems: str,
    freqs: int,
    out: Path,
    options: frozenset[str],
    known_length_m: float | None = None,
    filter_model: str | None = None,
) -> tuple[list[str] | None, str]:
    """The ``gnssatt attitude`` command of one run, or None and why (an option this version lacks);
    ``known_length_m``: single epochs get ``--baseline-length`` (the reference's length);
    ``filter_model``: ``--filter`` with this process model."""
    cmd = [*gnssatt_head(), "attitude", "--obs", str(ds.base_obs), "--obs", str(ds.rover_obs)]
    for n in ds.nav:
        cmd += ["--nav", str(n)]
    cmd += ["--method", "lambda", "--motion", motion, "--elevation-mask", "10", "--out", str(out)]
    if "--no-plot" in options:  # RTKLIB writes no plot either: time both to the solution file
        cmd += ["--no-plot"]
    if systems != "G":
        if "--systems" not in options:
            return None, "no --systems"
        cmd += ["--systems", systems]
    elif "--systems" in options:
        cmd += ["--systems", "G"]
    if filter_model is not None:
        if "--filter" not in options:
            return None, "no --filter"
        cmd += ["--filter", filter_model]
    elif known_length_m is not None and motion == "moving":
        if "--baseline-length" not in options:
            return None, "no --baseline-length"
        cmd += ["--baseline-length", f"{known_length_m:.4f}"]
    if "--frequencies" in options:
        cmd += ["--frequencies", str(freqs)]
    elif freqs != 1:
        return None, "no --frequencies (band 1 only)"
    if ds.base_position_m is not None and "--base-position" in options:
        return [*cmd, "--base-position", *(f"{x:.4f}" for x in ds.base_position_m)], ""
    return cmd, "base from its code solution (no --base-position)"
