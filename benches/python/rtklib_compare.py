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
import csv
import json
import os
import re
import statistics
import subprocess
import sys
import time
from collections.abc import Callable, Sequence
from dataclasses import asdict, dataclass, field
from functools import partial
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

REPO = Path(__file__).resolve().parents[2]
DEFAULT_OUT = REPO / "out" / "rtklib_compare"
GPS_EPOCH = np.datetime64("1980-01-06T00:00:00", "ns")
SECONDS_PER_WEEK = 604800.0
#: Two labels closer than this are one epoch (RTKLIB 2.4.3's DTTOL; GEONET labels of one epoch differ by
#: up to 9 ms between the two receivers).
EPOCH_TOLERANCE_S = 0.025
#: ``pos1-navsys`` bit of each RINEX system letter (RTKLIB's SYS_* values).
NAVSYS_BITS = {"G": 1, "R": 4, "E": 8, "J": 16, "C": 32}
#: RTKLIB mode name -> (conf file, gnssatt --motion, gnssatt --filter or None).
MODES = {
    "single-epoch": ("kinematic-instantaneous.conf", "moving", None),
    "moving-base": ("movingbase-instantaneous.conf", "moving", None),
    "filtered": ("kinematic-continuous.conf", "moving", "kinematic"),
    "static": ("static-continuous.conf", "static", None),
}


# ---------------------------------------------------------------------------------------------------------
# Parsing (tested in tests/test_rtklib_compare.py without RTKLIB)


@dataclass(frozen=True)
class Solutions:
    """Per-epoch baselines of one tool's run.

    Attributes
    ----------
    time_s
        (n,) GPST seconds since 1980-01-06 of the epochs with a solution.
    enu_m
        (n, 3) baseline rover - base, East-North-Up at the base, m.
    fixed
        (n,) True where the tool reports fixed ambiguities.
    enu_source
        How ``enu_m`` was obtained (``"pos"``, ``"csv"``, or ``"angles x reference length"``).
    """

    time_s: NDArray[np.float64]
    enu_m: NDArray[np.float64]
    fixed: NDArray[np.bool_]
    enu_source: str


def gpst_seconds(times: NDArray[np.datetime64]) -> NDArray[np.float64]:
    """GPST labels (``datetime64``) -> seconds since the GPS epoch."""
    return (np.asarray(times, dtype="datetime64[ns]") - GPS_EPOCH).astype(np.int64) / 1e9


def match_epochs(times_s: NDArray[np.float64], grid_s: NDArray[np.float64]) -> NDArray[np.int64]:
    """Index in ``grid_s`` of the label within ``EPOCH_TOLERANCE_S`` of each of ``times_s``, -1 where none."""
    t, grid = np.asarray(times_s, dtype=np.float64), np.asarray(grid_s, dtype=np.float64)
    if grid.size == 0:
        return np.full(t.shape, -1, dtype=np.int64)
    order = np.argsort(grid)
    g = grid[order]
    hi = np.clip(np.searchsorted(g, t), 0, g.size - 1)
    lo = np.clip(hi - 1, 0, g.size - 1)
    near = np.where(np.abs(g[lo] - t) < np.abs(g[hi] - t), lo, hi)
    return np.where(np.abs(g[near] - t) <= EPOCH_TOLERANCE_S, order[near], -1)


def parse_pos(path: Path) -> Solutions:
    """Read an RTKLIB ``.pos`` written with ``out-solformat=enu`` and ``out-timeform=tow``.

    Rows are ``week tow e n u Q ns sde sdn sdu sden sdnu sdue age ratio``; ``%`` lines are headers.
    """
    rows = []
    for line in Path(path).read_text().splitlines():
        if not line.strip() or line.startswith("%"):
            continue
        f = line.split()
        if len(f) < 6:
            raise ValueError(f"{path}: expected 'week tow e n u Q ...' (ENU, tow), got {line!r}")
        rows.append(
            (float(f[0]) * SECONDS_PER_WEEK + float(f[1]), float(f[2]), float(f[3]), float(f[4]), int(f[5]))
        )
    a = np.array(rows, dtype=np.float64).reshape(-1, 5)
    return Solutions(a[:, 0], a[:, 1:4], a[:, 4] == 1, "pos")


def parse_gnssatt_csv(path: Path, reference_length_m: float) -> Solutions:
    """Read a ``gnssatt attitude`` baseline-mode CSV.

    Uses ``east_m``, ``north_m``, ``up_m`` when the CSV has them; otherwise rebuilds the baseline from
    ``azimuth_deg`` (from North towards East) and ``elevation_deg`` at ``reference_length_m`` (so only the
    direction error is measured; ``enu_source`` says so). Epochs with empty or NaN angles are not solved.
    """
    with open(path, newline="") as fh:
        rows = list(csv.DictReader(fh))
    cols = set(rows[0]) if rows else set()
    have_enu = {"east_m", "north_m", "up_m"} <= cols
    times, enu, fixed = [], [], []
    for r in rows:
        if have_enu:
            v = [_float(r["east_m"]), _float(r["north_m"]), _float(r["up_m"])]
        else:
            az, el = np.radians(_float(r["azimuth_deg"])), np.radians(_float(r["elevation_deg"]))
            v = list(
                reference_length_m * np.array([np.cos(el) * np.sin(az), np.cos(el) * np.cos(az), np.sin(el)])
            )
        if not np.all(np.isfinite(v)):
            continue
        times.append(np.datetime64(r["time_gpst"], "ns"))
        enu.append(v)
        fixed.append(r["fixed"].strip().lower() in ("1", "true"))
    t = gpst_seconds(np.array(times, dtype="datetime64[ns]"))
    e = np.array(enu, dtype=np.float64).reshape(-1, 3)
    return Solutions(t, e, np.array(fixed, dtype=bool), "csv" if have_enu else "angles x reference length")


def _float(text: str) -> float:
    try:
        return float(text)
    except ValueError:
        return float("nan")


def help_options(help_text: str) -> frozenset[str]:
    """Long options (``--name``) that a ``--help`` text offers."""
    return frozenset(re.findall(r"(?<![\w-])--[a-z][a-z0-9-]*", help_text))


def write_conf(source: Path, target: Path, overrides: dict[str, str]) -> None:
    """Copy an RTKLIB conf with ``key = value`` lines replaced (or appended when absent)."""
    out, seen = [], set()
    for line in source.read_text().splitlines():
        key = line.split("=", 1)[0].strip() if "=" in line and not line.lstrip().startswith("#") else None
        if key in overrides:
            out.append(f"{key:<19}={overrides[key]}")
            seen.add(key)
        else:
            out.append(line)
    out += [f"{k:<19}={v}" for k, v in overrides.items() if k not in seen]
    target.write_text("\n".join(out) + "\n")


def navsys(systems: str) -> int:
    """``pos1-navsys`` value of system letters, e.g. ``"GE"`` -> 9."""
    return sum(NAVSYS_BITS[s] for s in dict.fromkeys(systems))


def rinex_header(path: Path) -> tuple[NDArray[np.float64] | None, dict[str, int]]:
    """APPROX POSITION XYZ (m; None when absent or zero) and the number of carrier-phase bands per system.

    RINEX 3/4: from ``SYS / # / OBS TYPES`` (continuation lines included); RINEX 2: from
    ``# / TYPES OF OBSERV`` for the file's system (``M``: G, R and E).
    """
    pos, file_sys, last_sys = None, "G", "G"
    bands: dict[str, set[str]] = {}
    with open(path) as fh:
        for line in fh:
            label = line[60:].strip()
            if label == "RINEX VERSION / TYPE":
                file_sys = line[40:41].strip() or "G"
            elif label == "APPROX POSITION XYZ":
                xyz = np.array([float(x) for x in line[:42].split()])
                pos = xyz if np.any(xyz != 0.0) else None
            elif label == "SYS / # / OBS TYPES":
                last_sys = line[0] if line[0] != " " else last_sys
                codes = [c for c in line[7:60].split() if c.startswith("L")]
                bands.setdefault(last_sys, set()).update(c[1] for c in codes)
            elif label == "# / TYPES OF OBSERV":
                codes = [c for c in line[6:60].split() if c.startswith("L")]
                for s in "GRE" if file_sys == "M" else file_sys:
                    bands.setdefault(s, set()).update(c[1] for c in codes)
            elif label == "END OF HEADER":
                break
    return pos, {s: len(b) for s, b in bands.items() if b}


@dataclass(frozen=True)
class Reference:
    """Reference baseline: ``enu_m`` (3,) for every epoch, or per epoch keyed by ``time_s``."""

    enu_m: NDArray[np.float64]
    time_s: NDArray[np.float64] | None
    description: str
    judges_fixes: bool  # False when only good to metres: no wrong-fix count

    def at(self, time_s: NDArray[np.float64]) -> NDArray[np.float64]:
        """(n, 3) reference at the epochs ``time_s`` (NaN rows where it has none)."""
        if self.time_s is None:
            return np.broadcast_to(self.enu_m, (len(time_s), 3)).copy()
        i = match_epochs(time_s, self.time_s)
        return np.where((i >= 0)[:, None], self.enu_m[np.maximum(i, 0)], np.nan)


def metrics(
    sol: Solutions, ref: Reference, n_epochs: int, wrong_fix_m: float
) -> dict[str, float | int | None]:
    """Fix rate over ``n_epochs``, wrong fixes, and 3-D baseline error statistics (m).

    Epochs the reference lacks are left out of the errors and wrong fixes (``unreferenced`` counts them);
    ``wrong_fixes`` is None when the reference cannot judge fixes; statistics of an empty set are None.
    """
    known = np.all(np.isfinite(ref.at(sol.time_s)), axis=1)
    err = np.linalg.norm(sol.enu_m[known] - ref.at(sol.time_s[known]), axis=1)
    fixed_err = err[sol.fixed[known]]
    first_fix = sol.time_s[sol.fixed][0] - sol.time_s[0] if sol.fixed.any() else None
    return {
        "epochs": n_epochs,
        "solved": len(sol.time_s),
        "fixed": int(sol.fixed.sum()),
        "fix_rate": float(sol.fixed.sum()) / n_epochs if n_epochs else None,
        "wrong_fixes": int(np.sum(fixed_err > wrong_fix_m)) if ref.judges_fixes else None,
        "first_fix_s": None if first_fix is None else float(first_fix),
        "unreferenced": int(np.sum(~known)),
        "error_fixed_median_m": _pct(fixed_err, 50),
        "error_fixed_p95_m": _pct(fixed_err, 95),
        "error_all_median_m": _pct(err, 50),
    }


def _pct(x: NDArray[np.float64], q: float) -> float | None:
    return float(np.percentile(x, q)) if x.size else None


# ---------------------------------------------------------------------------------------------------------
# Running the tools


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


@dataclass(frozen=True)
class Dataset:
    """Files of one comparison: base (reference antenna) and rover observations, navigation, truth."""

    name: str
    base_obs: Path
    rover_obs: Path
    nav: tuple[Path, ...]
    n_epochs: int
    base_position_m: NDArray[np.float64] | None
    bands: dict[str, int]  # carrier bands per system present in both files
    truth: Reference | None  # None: reference from RTKLIB's static solution (GEONET)
    description: str


def dataset(
    name: str, base: Path, rover: Path, nav: tuple[Path, ...], truth: Reference | None, description: str
) -> Dataset:
    """A :class:`Dataset` with the epochs common to both files (read by ``gnssatt.rinex.read_obs``, outside
    any timing), the base's header position and the carrier bands both headers list per system."""
    from gnssatt.rinex import read_obs

    pos_b, bands_b = rinex_header(base)
    _, bands_r = rinex_header(rover)
    t_base, t_rover = (gpst_seconds(read_obs(p).time) for p in (base, rover))
    n_epochs = int(np.sum(match_epochs(t_base, t_rover) >= 0))
    bands = {s: min(n, bands_r[s]) for s, n in bands_b.items() if s in bands_r}
    return Dataset(name, base, rover, nav, n_epochs, pos_b, bands, truth, description)


def geonet() -> Dataset:
    """The GEONET pair shipped in ``gnssatt.data``, base 0759; the reference comes from RTKLIB later."""
    from gnssatt.data import geonet_dir

    d = geonet_dir()
    return dataset(
        "geonet",
        d / "07590920.05o",
        d / "30400920.05o",
        (d / "07590920.05n", d / "30400920.05n"),
        None,
        "GEONET 0759 -> 3040 (3.3 km, RINEX 2.10, 30 s), base at its header position",
    )


def simulated(folder: Path, n_epochs: int, seed: int) -> Dataset:
    """A static 1 m baseline (heading 30 degrees) of ``n_epochs`` at 1 s: every system and frequency of
    ``simulate_gnss_rinex`` (GRECJ, 3 slots), or GPS L1 from ``simulate_rinex_array`` where the simulator
    has only that."""
    from gnssatt.sim import rinex_scenario as scenario

    folder.mkdir(parents=True, exist_ok=True)
    ants = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]])
    euler = np.tile([30.0, 0.0, 0.0], (n_epochs, 1))
    if hasattr(scenario, "simulate_gnss_rinex"):
        sim = scenario.simulate_gnss_rinex(folder, ants, euler, systems="GRECJ", frequencies=3, rng=seed)
    else:
        sim = scenario.simulate_rinex_array(folder, ants, euler, seed=seed)
    truth = Reference(sim.baselines_enu_m[:, 0, :], gpst_seconds(sim.time), "simulation truth", True)
    return dataset(
        "sim",
        sim.obs_paths[0],
        sim.obs_paths[1],
        (sim.nav_path,),
        truth,
        f"simulated static 1 m baseline, {n_epochs} epochs at 1 s, seed {seed} "
        f"({len(sim.sats)} satellites of {''.join(dict.fromkeys(s[0] for s in sim.sats))})",
    )


def cssrlib(folder: Path) -> Dataset:
    """The real kinematic pair of ``folder`` (``cssrlib_3034_sept_2021265``), unmodified: base 3034 (Trimble),
    rover SEPT (Septentrio mosaic-X5), one navigation file; no truth."""
    return dataset(
        "cssrlib",
        folder / "3034265G.21O",
        folder / "SEPT265G.21O",
        (folder / "SEPT2650.21P",),
        None,
        "cssrlib 3034 -> SEPT (5.3 km, moving rover, RINEX 3.04, 1 s), base at 3034's header position",
    )


def agreement(rtk: Rtklib, gnssatt_options: frozenset[str], ds: Dataset, folder: Path, opts: Settings) -> str:
    """gnssatt single-epoch (``--motion moving --method lambda --systems GE --frequencies all``) against
    RTKLIB ``kinematic-instantaneous`` (``pos1-navsys=45``: the G, R, E, C bits; the files hold G, E, J,
    ``-f 3``), both with the base at its header position: fixed counts and the 3-D difference of the
    baselines at the epochs both fix. A markdown table."""
    folder.mkdir(parents=True, exist_ok=True)
    conf = rtk.conf_dir / "kinematic-instantaneous-navsys45.conf"
    write_conf(
        rtk.conf_src / MODES["single-epoch"][0],
        conf,
        {"pos1-navsys": "45", "out-solformat": "enu", "out-timeform": "tow"},
    )
    pos = folder / "rtklib-kinematic-instantaneous-45-f3.pos"
    cmd = [str(rtk.binary), "-k", str(conf), "-f", "3"]
    if ds.base_position_m is not None:
        cmd += ["-r", *(f"{x:.4f}" for x in ds.base_position_m)]
    cmd += ["-o", str(pos), str(ds.rover_obs), str(ds.base_obs), *map(str, ds.nav)]
    r_wall, r_fail = timed_run(cmd, pos, opts.repeats, opts.timeout_s)
    out = folder / "gnssatt-moving-GE-all.csv"
    ours, why = gnssatt_command(ds, "moving", "GE", 3, out, gnssatt_options)
    if ours is None or r_fail:
        return f"cssrlib agreement not measured: {why or r_fail}"
    g_wall, g_fail = timed_run(ours, out, opts.repeats, opts.timeout_s)
    if g_fail:
        return f"cssrlib agreement not measured: gnssatt {g_fail}"
    theirs = parse_pos(pos)
    mine = parse_gnssatt_csv(out, 1.0)
    i = match_epochs(mine.time_s, theirs.time_s)
    both = (i >= 0) & mine.fixed & np.where(i >= 0, theirs.fixed[np.maximum(i, 0)], False)
    diff = np.linalg.norm(mine.enu_m[both] - theirs.enu_m[i[both]], axis=1)
    stat = (lambda f: f"{f(diff) * 1e3:.1f}") if diff.size else (lambda f: "-")
    return "\n".join(
        [
            "| epochs | RTKLIB fixed | gnssatt fixed | both fixed | difference median mm | difference max mm "
            "| both fixed > 5 cm apart | wall s RTKLIB \\| gnssatt |",
            "|" + "---|" * 8,
            f"| {ds.n_epochs} | {int(theirs.fixed.sum())} | {int(mine.fixed.sum())} | {int(both.sum())} "
            f"| {stat(np.median)} | {stat(np.max)} | {int(np.sum(diff > 0.05))} "
            f"| {statistics.median(r_wall):.2f} \\| {statistics.median(g_wall):.2f} |",
            "",
            "RTKLIB: " + " ".join(cmd),
            "gnssatt: " + " ".join(ours),
        ]
    )


class Rtklib:
    """``rnx2rtkp`` with the peer's confs: modified copies go to ``conf_dir``."""

    def __init__(self, binary: Path, conf_src: Path, conf_dir: Path) -> None:
        self.binary, self.conf_src, self.conf_dir = binary, conf_src, conf_dir
        conf_dir.mkdir(parents=True, exist_ok=True)

    def command(self, ds: Dataset, mode: str, systems: str, freqs: int, out: Path) -> list[str]:
        conf_name = MODES[mode][0]
        conf = self.conf_dir / f"{Path(conf_name).stem}-{systems}.conf"
        write_conf(
            self.conf_src / conf_name,
            conf,
            {"pos1-navsys": str(navsys(systems)), "out-solformat": "enu", "out-timeform": "tow"},
        )
        cmd = [str(self.binary), "-k", str(conf), "-f", str(freqs)]
        if ds.base_position_m is not None:
            cmd += ["-r", *(f"{x:.4f}" for x in ds.base_position_m)]
        return [*cmd, "-o", str(out), str(ds.rover_obs), str(ds.base_obs), *map(str, ds.nav)]


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
    exe = Path(sys.executable).with_name("gnssatt")
    cmd = [str(exe)] if exe.exists() else [sys.executable, "-m", "gnssatt"]
    cmd += ["attitude", "--obs", str(ds.base_obs), "--obs", str(ds.rover_obs)]
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


# ---------------------------------------------------------------------------------------------------------
# The comparison


def run_plan(ds: Dataset) -> list[tuple[str, int]]:
    """(systems, frequencies) to compare: GPS alone, every CDMA system (GLONASS's FDMA is a case of its
    own), every system of both files; each with 1 .. all bands (at most 3)."""
    present = "".join(s for s in "GRECJ" if s in ds.bands)
    sets = list(
        dict.fromkeys(x for x in ("G" if "G" in ds.bands else "", present.replace("R", ""), present) if x)
    )
    return [(s, f) for s in sets for f in range(1, min(3, max(ds.bands[x] for x in s)) + 1)]


def geonet_reference(ds: Dataset, rtk: Rtklib | None, folder: Path, opts: Settings) -> Reference:
    """RTKLIB's static L1+L2 (all bands) fixed solution over the session; header positions without RTKLIB."""
    if rtk is not None:
        out = folder / "reference-static.pos"
        cmd = rtk.command(ds, "static", "G", max(ds.bands.values()), out)
        _, why = timed_run(cmd, out, 1, opts.timeout_s)
        if not why:
            sol = parse_pos(out)
            if sol.fixed.any():
                enu = sol.enu_m[np.flatnonzero(sol.fixed)[-1]]
                return Reference(
                    enu, None, "RTKLIB static-continuous, GPS, all bands, last fixed epoch", True
                )
    pos_b, _ = rinex_header(ds.base_obs)
    pos_r, _ = rinex_header(ds.rover_obs)
    if pos_b is None or pos_r is None:
        raise SystemExit(f"{ds.name}: no RTKLIB reference and no header positions")
    lat, lon = _geodetic(pos_b)
    enu = _enu_rotation(lat, lon) @ (pos_r - pos_b)
    return Reference(enu, None, "header positions (good to metres: wrong fixes not counted)", False)


def _geodetic(xyz: NDArray[np.float64]) -> tuple[float, float]:
    """WGS-84 geodetic latitude and longitude (rad) of an ECEF point, by Bowring's iteration."""
    a, f = 6378137.0, 1 / 298.257223563
    e2 = f * (2 - f)
    p = float(np.hypot(xyz[0], xyz[1]))
    lat = np.arctan2(xyz[2], p * (1 - e2))
    for _ in range(5):
        n = a / np.sqrt(1 - e2 * np.sin(lat) ** 2)
        lat = np.arctan2(xyz[2] + e2 * n * np.sin(lat), p)
    return float(lat), float(np.arctan2(xyz[1], xyz[0]))


def _enu_rotation(lat: float, lon: float) -> NDArray[np.float64]:
    sl, cl, sp, cp = np.sin(lon), np.cos(lon), np.sin(lat), np.cos(lat)
    return np.array([[-sl, cl, 0.0], [-sp * cl, -sp * sl, cp], [cp * cl, cp * sl, sp]])


@dataclass(frozen=True)
class Settings:
    """Command-line settings every run shares."""

    options: frozenset[str]  # of `gnssatt attitude --help`
    repeats: int
    wrong_fix_m: float
    timeout_s: float
    known_length: bool = False


def measure(
    run: Timed, output: Path, read: Callable[[Path], Solutions], ref: Reference, ds: Dataset, opts: Settings
) -> Timed:
    """Time ``run.command`` (it writes ``output``), then read ``output`` and fill in the metrics."""
    run.wall_s, failed = timed_run(run.command, output, opts.repeats, opts.timeout_s)
    if failed:
        run.note = failed
    else:
        sol = read(output)
        run.metrics, run.enu_source = metrics(sol, ref, ds.n_epochs, opts.wrong_fix_m), sol.enu_source
    return run


def compare(ds: Dataset, rtk: Rtklib | None, folder: Path, opts: Settings) -> tuple[Reference, list[dict]]:
    """Every run of ``run_plan(ds)`` by both tools; one row per (systems, frequencies, RTKLIB mode)."""
    folder.mkdir(parents=True, exist_ok=True)
    ref = ds.truth or geonet_reference(ds, rtk, folder, opts)
    # Length for a CSV without east/north/up (today's): the reference's, so only direction errors count.
    length = float(np.median(np.linalg.norm(np.atleast_2d(ref.enu_m), axis=1)))
    rows: list[dict] = []
    for systems, freqs in run_plan(ds):
        # gnssatt per (--motion, --filter): the moving run serves both single-epoch modes
        ours: dict[tuple[str, str | None], Timed] = {}
        for mode, (_, motion, filter_model) in MODES.items():
            theirs = Timed([], note="RTKLIB skipped (no --rtklib-src)")
            if rtk is not None:
                pos = folder / f"rtklib-{mode}-{systems}-f{freqs}.pos"
                theirs = measure(
                    Timed(rtk.command(ds, mode, systems, freqs, pos)), pos, parse_pos, ref, ds, opts
                )
            key = (motion, filter_model)
            same = key in ours
            if not same:
                tag = motion if filter_model is None else f"filter-{filter_model}"
                out = folder / f"gnssatt-{tag}-{systems}-f{freqs}.csv"
                known = length if opts.known_length else None
                cmd, why = gnssatt_command(ds, motion, systems, freqs, out, opts.options, known, filter_model)
                ours[key] = Timed(cmd or [], note=why)
                if cmd is not None:
                    read = partial(parse_gnssatt_csv, reference_length_m=length)
                    measure(ours[key], out, read, ref, ds, opts)
            rows.append(
                {
                    "dataset": ds.name,
                    "mode": mode,
                    "systems": systems,
                    "frequencies": freqs,
                    "rtklib": asdict(theirs) | {"median_wall_s": theirs.median_wall_s},
                    "gnssatt": asdict(ours[key])
                    | {"median_wall_s": ours[key].median_wall_s, "same_as_above": same},
                }
            )
    return ref, rows


def _cell(x: float | int | None, fmt: str, scale: float = 1.0) -> str:
    return "-" if x is None else format(x * scale, fmt)


def _tool_cells(t: dict[str, object], notes: list[str], where: str) -> list[str]:
    """The six table cells of one tool's run; a note (why none, or a caveat) gets a numbered marker."""
    if t.get("same_as_above"):
        return ["〃"] * 7
    m = t["metrics"]
    note = str(t["note"])
    if isinstance(m, dict) and m["solved"] == 0:
        note = note or "no epoch solved"
    mark = ""
    if note:
        notes.append(f"{where}: {note}")
        mark = f" [{len(notes)}]"
    if not isinstance(m, dict):
        return [f"n/a{mark}"] + ["n/a"] * 6
    wall = t["median_wall_s"]
    per = None if wall is None else float(wall) / float(m["epochs"])  # type: ignore[arg-type]
    return [
        _cell(m["fix_rate"], ".1f", 100) + mark,
        _cell(m["wrong_fixes"], ".0f"),
        _cell(m.get("first_fix_s"), ".0f"),
        f"{_cell(m['error_fixed_median_m'], '.1f', 1e3)}/{_cell(m['error_fixed_p95_m'], '.1f', 1e3)}",
        _cell(m["error_all_median_m"], ".1f", 1e3),
        _cell(wall, ".2f"),  # type: ignore[arg-type]
        _cell(per, ".2f", 1e3),
    ]


def table(rows: list[dict[str, object]]) -> str:
    """One markdown table, ``RTKLIB | gnssatt`` side by side in each metric's column, then the notes."""
    lines = [
        "| data | mode | sys | f | fixed % R \\| g | wrong R \\| g | first fix s R \\| g "
        "| err fixed med/95 mm R \\| g | err all med mm R \\| g | wall s R \\| g | ms/epoch R \\| g |",
        "|" + "---|" * 11,
    ]
    notes: list[str] = []
    for row in rows:
        key = f"{row['dataset']} {row['mode']} {row['systems']} f{row['frequencies']}"
        rtk_cells = _tool_cells(row["rtklib"], notes, f"{key} RTKLIB")  # type: ignore[arg-type]
        our_cells = _tool_cells(row["gnssatt"], notes, f"{key} gnssatt")  # type: ignore[arg-type]
        pairs = [f"{a} \\| {b}" for a, b in zip(rtk_cells, our_cells, strict=True)]
        lines.append(
            f"| {row['dataset']} | {row['mode']} | {row['systems']} | {row['frequencies']} | "
            + " | ".join(pairs)
            + " |"
        )
    return "\n".join(lines + [""] + [f"[{i}] {n}" for i, n in enumerate(notes, 1)])


# ---------------------------------------------------------------------------------------------------------
# Simulated moving platforms (gnssatt.sim.platforms): RTKLIB's kinematic and moving-base modes against
# gnssatt's single-epoch, filtered and attitude runs on the same files, heading from the antenna pair

#: Platforms and noise profiles compared (``gnssatt.sim.car`` / ``ship`` / ``aircraft``; profiles of
#: ``gnssatt.sim.NOISE_PROFILES``), and each profile's systems and frequency slots.
PLATFORMS = ("car", "ship", "aircraft")
PROFILES = {"gps_l1_ublox": ("G", 1), "geodetic": ("GRECJ", 3)}
#: RTKLIB runs on a platform: name -> (conf, pos2-armode, moving base). The kinematic ones process each
#: antenna against the static base (``-r`` its true position) and difference the two solutions (fixed where
#: both are); the moving-base ones take antenna 0 as the base of antenna 1.
PLATFORM_RTKLIB = {
    "kinematic-instantaneous": ("kinematic-instantaneous.conf", "instantaneous", False),
    "kinematic-continuous": ("kinematic-continuous.conf", "continuous", False),
    "kinematic-fix-and-hold": ("kinematic-continuous.conf", "fix-and-hold", False),
    "movingbase-instantaneous": ("movingbase-instantaneous.conf", "instantaneous", True),
    "movingbase-continuous": ("movingbase-instantaneous.conf", "continuous", True),
    "movingbase-fix-and-hold": ("movingbase-instantaneous.conf", "fix-and-hold", True),
}
#: gnssatt runs on a platform: name -> (extra options, antennas).
PLATFORM_GNSSATT = {
    "single-epoch": ([], 2),
    "filter-kinematic": (["--filter", "kinematic", "--rigid"], 2),
    "filter-velocity": (["--filter", "velocity", "--rigid"], 2),
    "attitude-3-antennas": ([], 3),
    "attitude-3-filter-velocity": (["--filter", "velocity"], 3),
}


@dataclass(frozen=True)
class PlatformSession:
    """One simulated platform's files and the truth the metrics need."""

    name: str
    profile: str
    obs: tuple[Path, ...]  # antennas 0, 1, 2
    base: Path
    nav: Path
    base_ecef_m: NDArray[np.float64]
    baselines_file: Path  # body-frame lever arms of antennas 1 and 2 from antenna 0
    time_s: NDArray[np.float64]  # GPST seconds of every epoch of the session
    pair_enu_m: NDArray[np.float64]  # (n, 3) antenna 1 - antenna 0, ENU at antenna 0
    pair_base_enu_m: NDArray[np.float64]  # (n, 3) the same in ENU at the static base
    outage_ends_s: tuple[float, ...]  # GPST seconds
    description: str


def platform_session(
    name: str, profile: str, folder: Path, duration_s: float | None, seed: int
) -> PlatformSession:
    """Simulate ``name`` (three antennas, a static base) with the noise ``profile`` into ``folder``."""
    from gnssatt import sim

    folder.mkdir(parents=True, exist_ok=True)
    preset = {"car": sim.car, "ship": sim.ship, "aircraft": sim.aircraft}[name]
    kwargs: dict[str, object] = {} if duration_s is None else {"duration_s": duration_s}
    run = preset(folder, n_antennas=3, noise=profile, rng=seed, **kwargs)  # type: ignore[operator]
    lever = {"car": ((1.2, 0.0, 0.0), (0.0, 0.0, 0.9)), "ship": ((4.0, 0.0, 0.0), (0.0, 0.0, 3.0))}
    rel = lever.get(name, ((3.0, 0.0, 0.0), (0.0, 0.0, 4.5)))
    bl = folder / "baselines.txt"
    bl.write_text("".join(f"{x} {y} {z}\n" for x, y, z in rel))
    t = gpst_seconds(run.time)
    span = float(t[-1] - t[0] + (t[1] - t[0] if len(t) > 1 else 0.0))
    n_sys = "".join(dict.fromkeys(s[0] for s in run.sats))
    lengths = np.linalg.norm(run.baselines_enu_m[0], axis=1)
    return PlatformSession(
        name, profile, run.obs_paths, run.base_path, run.nav_path, run.base_ecef_m, bl, t,
        run.baselines_enu_m[:, 0], run.rover_enu_m[:, 1] - run.rover_enu_m[:, 0],
        tuple(float(t[0] + e) for e in run.outage_ends_s),
        f"{name}, {profile}: {len(t)} epochs over {span:.0f} s, {len(run.sats)} satellites ({n_sys}), "
        f"antennas {lengths[0]:.1f} m and {lengths[1]:.1f} m from antenna 0, seed {seed}",
    )  # fmt: skip


def heading_deg(enu_m: NDArray[np.float64]) -> NDArray[np.float64]:
    """Azimuth of ENU vectors from North towards East, degrees."""
    return np.degrees(np.arctan2(enu_m[:, 0], enu_m[:, 1]))


def platform_metrics(
    sol: Solutions, time_s: NDArray[np.float64], truth_enu_m: NDArray[np.float64],
    outage_ends_s: Sequence[float], wrong_fix_m: float,
) -> dict[str, float | int | None]:  # fmt: skip
    """Fix rate over every epoch of the session (``time_s``, its truth ``truth_enu_m``), wrong fixes (a
    fixed baseline more than ``wrong_fix_m`` from the truth), time to first fix (the first fixed epoch
    less the session's first epoch, s), time to re-fix after each outage (its first fixed epoch at or
    after the outage's end less the end; the longest, None if one never re-fixes), and the RMS of the
    heading error over fixed and over all solved epochs (degrees)."""
    i = match_epochs(sol.time_s, time_s)
    known = i >= 0
    err = np.linalg.norm(sol.enu_m[known] - truth_enu_m[i[known]], axis=1)
    fixed = sol.fixed[known]
    t_fix = sol.time_s[known][fixed]
    dh = heading_deg(sol.enu_m[known]) - heading_deg(truth_enu_m[i[known]])
    dh = (dh + 180.0) % 360.0 - 180.0
    refix: list[float] = []
    for end in outage_ends_s:
        after = t_fix[t_fix >= end - EPOCH_TOLERANCE_S]
        refix.append(float(after[0] - end) if after.size else float("inf"))
    rms = lambda x: float(np.sqrt(np.mean(x**2))) if x.size else None  # noqa: E731
    return {
        "epochs": len(time_s),
        "solved": int(known.sum()),
        "fixed": int(fixed.sum()),
        "fix_rate": float(fixed.sum()) / len(time_s),
        "wrong_fixes": int(np.sum(err[fixed] > wrong_fix_m)),
        "first_fix_s": float(t_fix[0] - time_s[0]) if t_fix.size else None,
        "refix_s": (None if not refix or not np.isfinite(max(refix)) else max(refix)) if refix else None,
        "refix_missed": int(sum(not np.isfinite(x) for x in refix)),
        "outages": len(refix),
        "heading_rms_fixed_deg": rms(dh[fixed]),
        "heading_rms_all_deg": rms(dh),
    }


def pair_solutions(a: Solutions, b: Solutions) -> Solutions:
    """Antenna 1 - antenna 0 from two base -> antenna solutions: the epochs both have, fixed where both
    are."""
    i = match_epochs(b.time_s, a.time_s)
    ok = i >= 0
    return Solutions(
        b.time_s[ok], b.enu_m[ok] - a.enu_m[i[ok]], b.fixed[ok] & a.fixed[i[ok]], "pos pair difference"
    )


def rtklib_platform_runs(
    rtk: Rtklib, ps: PlatformSession, folder: Path, opts: Settings
) -> list[dict[str, object]]:
    """Every run of :data:`PLATFORM_RTKLIB` on ``ps``: metrics, commands and summed wall times."""
    systems, freqs = PROFILES[ps.profile]
    rows: list[dict[str, object]] = []
    for mode, (conf_name, armode, moving) in PLATFORM_RTKLIB.items():
        conf = rtk.conf_dir / f"{ps.name}-{ps.profile}-{mode}.conf"
        write_conf(
            rtk.conf_src / conf_name, conf,
            {"pos1-navsys": str(navsys(systems)), "pos2-armode": armode, "out-solformat": "enu",
             "out-timeform": "tow"},
        )  # fmt: skip
        base = [str(rtk.binary), "-k", str(conf), "-f", str(freqs)]
        pairs = [(ps.obs[1], ps.obs[0], [])] if moving else [
            (ps.obs[k], ps.base, ["-r", *(f"{x:.4f}" for x in ps.base_ecef_m)]) for k in (0, 1)
        ]  # fmt: skip
        sols, walls, cmds, why = [], 0.0, [], ""
        for k, (rover, ref, extra) in enumerate(pairs):
            out = folder / f"rtklib-{ps.name}-{ps.profile}-{mode}-{k}.pos"
            cmd = [*base, *extra, "-o", str(out), str(rover), str(ref), str(ps.nav)]
            wall, why = timed_run(cmd, out, opts.repeats, opts.timeout_s)
            cmds.append(cmd)
            if why:
                break
            walls += statistics.median(wall)
            sols.append(parse_pos(out))
        row: dict[str, object] = {"tool": "RTKLIB", "mode": mode, "commands": cmds, "note": why}
        if not why:
            sol = sols[0] if moving else pair_solutions(sols[0], sols[1])
            truth = ps.pair_enu_m if moving else ps.pair_base_enu_m
            row["metrics"] = platform_metrics(sol, ps.time_s, truth, ps.outage_ends_s, opts.wrong_fix_m)
            row["wall_s"] = walls
        rows.append(row)
    return rows


def gnssatt_platform_runs(ps: PlatformSession, folder: Path, opts: Settings) -> list[dict[str, object]]:
    """Every run of :data:`PLATFORM_GNSSATT` on ``ps`` (antenna 0 the moving base, no base position)."""
    systems, freqs = PROFILES[ps.profile]
    exe = Path(sys.executable).with_name("gnssatt")
    head = [str(exe)] if exe.exists() else [sys.executable, "-m", "gnssatt"]
    rows: list[dict[str, object]] = []
    for mode, (extra, n_ant) in PLATFORM_GNSSATT.items():
        out = folder / f"gnssatt-{ps.name}-{ps.profile}-{mode}.csv"
        cmd = [*head, "attitude"]
        for p in ps.obs[:n_ant]:
            cmd += ["--obs", str(p)]
        cmd += ["--nav", str(ps.nav), "--method", "lambda", "--motion", "moving", "--elevation-mask", "10"]
        cmd += ["--systems", systems, "--frequencies", str(freqs), "--out", str(out), *extra]
        if n_ant == 3:
            cmd += ["--baselines", str(ps.baselines_file)]
        missing = [o for o in (*extra[:1], "--no-plot", "--baselines") if o not in opts.options]
        row: dict[str, object] = {"tool": "gnssatt", "mode": mode, "commands": [cmd], "note": ""}
        if missing and missing != ["--no-plot"]:
            row["note"] = f"no {missing[0]}"
            rows.append(row)
            continue
        if "--no-plot" in opts.options:
            cmd.append("--no-plot")
        wall, why = timed_run(cmd, out, opts.repeats, opts.timeout_s)
        row["note"] = why
        if not why:
            sol = parse_gnssatt_csv(out, float(np.median(np.linalg.norm(ps.pair_enu_m, axis=1))))
            row["metrics"] = platform_metrics(
                sol, ps.time_s, ps.pair_enu_m, ps.outage_ends_s, opts.wrong_fix_m
            )
            row["wall_s"] = statistics.median(wall)
        rows.append(row)
    return rows


def platform_table(rows: list[dict[str, object]]) -> str:
    """Markdown table of the platform runs, one row per (platform, profile, tool, mode), then notes."""
    lines = [
        "| platform | profile | tool | mode | fixed % | wrong | first fix s | re-fix s "
        "| heading RMS fixed deg | heading RMS all deg | wall s |",
        "|" + "---|" * 11,
    ]
    notes: list[str] = []
    for r in rows:
        m = r.get("metrics")
        mark = ""
        if r.get("note"):
            notes.append(f"{r['platform']} {r['profile']} {r['tool']} {r['mode']}: {r['note']}")
            mark = f" [{len(notes)}]"
        if not isinstance(m, dict):
            cells = [f"n/a{mark}"] + ["n/a"] * 6
        else:
            refix = m["refix_s"]
            if m["outages"] == 0:
                refix_cell = "-"
            elif m["refix_missed"]:
                refix_cell = f"never ({m['refix_missed']}/{m['outages']})"
            else:
                refix_cell = _cell(refix, ".1f")
            cells = [
                _cell(m["fix_rate"], ".1f", 100) + mark,
                _cell(m["wrong_fixes"], ".0f"),
                _cell(m["first_fix_s"], ".1f"),
                refix_cell,
                _cell(m["heading_rms_fixed_deg"], ".3f"),
                _cell(m["heading_rms_all_deg"], ".2f"),
                _cell(r.get("wall_s"), ".2f"),  # type: ignore[arg-type]
            ]
        lines.append(
            f"| {r['platform']} | {r['profile']} | {r['tool']} | {r['mode']} | " + " | ".join(cells) + " |"
        )
    return "\n".join(lines + [""] + [f"[{i}] {n}" for i, n in enumerate(notes, 1)])


def compare_platforms(
    names: Sequence[str], profiles: Sequence[str], rtk: Rtklib | None, out: Path, opts: Settings,
    duration_s: float | None, seed: int,
) -> tuple[list[str], list[dict[str, object]]]:  # fmt: skip
    """Simulate every platform with every profile and run both tools; descriptions and rows."""
    described, rows = [], []
    for name in names:
        for profile in profiles:
            ps = platform_session(
                name, profile, out / "platform-data" / f"{name}-{profile}", duration_s, seed
            )
            described.append(ps.description)
            folder = out / "platforms"
            folder.mkdir(parents=True, exist_ok=True)
            runs = [] if rtk is None else rtklib_platform_runs(rtk, ps, folder, opts)
            runs += gnssatt_platform_runs(ps, folder, opts)
            rows += [{"platform": name, "profile": profile, **r} for r in runs]
    return described, rows


def main(argv: Sequence[str] | None = None) -> int:
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
    out = args.out.resolve()
    out.mkdir(parents=True, exist_ok=True)
    rtk = None
    if args.rtklib_src is not None:
        binary = args.rnx2rtkp
        if binary is None:
            build = subprocess.run(
                ["bash", str(args.rtklib_src / "build.sh"), str(out / "rtklib")],
                capture_output=True,
                text=True,
                check=True,
            )
            binary = Path(build.stdout.strip().splitlines()[-1])
        rtk = Rtklib(binary.resolve(), args.rtklib_src / "conf", out / "confs")
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
    all_rows = []
    extra = []
    for name in names:
        if name == "cssrlib":
            assert rtk is not None
            ds = cssrlib(args.cssrlib)
            extra.append(f"{ds.description}:\n\n" + agreement(rtk, options, ds, out / name, settings))
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
