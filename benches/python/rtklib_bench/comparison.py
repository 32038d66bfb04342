"""The comparison of one dataset: its run plan, its reference, and both tools' runs in every mode."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import asdict
from functools import partial
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from .datasets import Dataset, rinex_header
from .metrics import Reference, metrics
from .rtklib import MODES, Rtklib
from .runs import Settings, Timed, gnssatt_command, timed_run
from .solutions import Solutions, parse_gnssatt_csv, parse_pos


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
