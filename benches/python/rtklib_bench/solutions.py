"""Per-epoch baselines of either tool, read from its output file: RTKLIB's ``.pos`` and gnssatt's CSV,
matched epoch by epoch on GPST labels (tested in ``tests/test_rtklib_compare.py`` without RTKLIB)."""

from __future__ import annotations

import csv
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

GPS_EPOCH = np.datetime64("1980-01-06T00:00:00", "ns")
SECONDS_PER_WEEK = 604800.0
#: Two labels closer than this are one epoch (RTKLIB 2.4.3's DTTOL; GEONET labels of one epoch differ by
#: up to 9 ms between the two receivers).
EPOCH_TOLERANCE_S = 0.025


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
