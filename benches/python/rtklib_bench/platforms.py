"""Simulated moving platforms (``gnssatt.sim.platforms``): RTKLIB's kinematic and moving-base modes
against gnssatt's single-epoch, filtered and attitude runs on the same files, heading from the antenna
pair."""

from __future__ import annotations

import statistics
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from .metrics import pair_solutions, platform_metrics
from .rtklib import Rtklib, navsys, write_conf
from .runs import Settings, gnssatt_head, timed_run
from .solutions import gpst_seconds, parse_gnssatt_csv, parse_pos

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
    head = gnssatt_head()
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
