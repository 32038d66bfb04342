"""The cssrlib pair, which has no truth: gnssatt's single-epoch fixes against RTKLIB's epoch by epoch."""

from __future__ import annotations

import statistics
from pathlib import Path

import numpy as np

from .datasets import Dataset
from .rtklib import MODES, Rtklib, write_conf
from .runs import Settings, gnssatt_command, timed_run
from .solutions import match_epochs, parse_gnssatt_csv, parse_pos


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
