"""The multi-epoch filter on the real moving rover against RTKLIB's single-epoch fixes, epoch by epoch.

Usage: ``python benches/python/filter_rover_compare.py --cssrlib DIR --rtklib-pos FILE [--filters ...]``.
``DIR`` is ``../shared/data/cssrlib_3034_sept_2021265`` (a Septentrio rover on a vehicle 5.3 km from GEONET
3034; no truth published), ``FILE`` the ``rtklib-kinematic-instantaneous-45-f3.pos`` that
``benches/python/rtklib_compare.py --datasets cssrlib`` writes (RTKLIB 2.4.3 ``kinematic-instantaneous``,
``pos1-navsys=45``, ``-f 3``, ``out-timeform=tow``). For gnssatt single epochs (``motion="moving"``) and
each ``filter=`` model (``attitude_from_rinex`` with the options of that script's cssrlib command: LAMBDA,
10 deg mask, GPS + Galileo, three frequencies, base at 3034's header position) prints the epochs fixed, the
epochs both tools fix, the median and largest distance between their baselines there and how many are more
than 5 cm apart, and the wall time. Measured numbers: ``docs/rtklib_comparison.md``.
"""

from __future__ import annotations

import argparse
import time
import warnings
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from gnssatt.gnss.attitude import attitude_from_rinex

BASE_M = (-3959403.8133, 3385705.8562, 3667525.8580)
APART_M = 0.05
GPS_EPOCH = np.datetime64("1980-01-06T00:00:00", "ms")


def rtklib_fixed(pos: Path) -> dict[np.datetime64, NDArray[np.float64]]:
    """GPST epoch (ms) -> ENU baseline of RTKLIB's fixed epochs (``Q`` 1) in a ``.pos`` of week and TOW."""
    out: dict[np.datetime64, NDArray[np.float64]] = {}
    for line in pos.read_text().splitlines():
        if line.startswith("%") or not line.strip():
            continue
        f = line.split()
        if int(f[5]) != 1:
            continue
        ms = int(f[0]) * 7 * 86_400_000 + round(float(f[1]) * 1000)
        out[GPS_EPOCH + np.timedelta64(ms, "ms")] = np.array([float(f[2]), float(f[3]), float(f[4])])
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--cssrlib", type=Path, required=True, help="folder of the cssrlib pair")
    ap.add_argument("--rtklib-pos", type=Path, required=True, help="RTKLIB kinematic-instantaneous .pos")
    ap.add_argument("--filters", nargs="+", default=["none", "kinematic", "velocity", "static"])
    a = ap.parse_args()
    warnings.simplefilter("ignore")
    rt = rtklib_fixed(a.rtklib_pos)
    obs = [a.cssrlib / "3034265G.21O", a.cssrlib / "SEPT265G.21O"]
    nav = a.cssrlib / "SEPT2650.21P"
    print(f"RTKLIB kinematic-instantaneous: {len(rt)} fixed")
    print(
        "| gnssatt | epochs | fixed | both fixed | apart median mm | apart max mm | > 5 cm apart | wall s |"
    )
    print("|---|---|---|---|---|---|---|---|")
    for name in a.filters:
        model = None if name == "none" else name
        kw: dict[str, str] = {"motion": "moving"} if model is None else {"filter": model}
        t0 = time.perf_counter()
        s = attitude_from_rinex(
            obs, nav, method="lambda", elevation_mask_deg=10, systems="GE", frequencies=3,
            base_position_m=BASE_M, **kw,  # type: ignore[arg-type]
        )  # fmt: skip
        wall = time.perf_counter() - t0
        fixed = s.fixed.astype(bool)
        d = np.array(
            [
                np.linalg.norm(s.baselines_enu_m[k, 0] - rt[t])
                for k, t in enumerate(s.time.astype("datetime64[ms]"))
                if fixed[k] and t in rt
            ]
        )
        label = "single epoch" if model is None else f"filter={model}"
        med = f"{np.median(d) * 1e3:.1f}" if d.size else "-"
        mx = f"{d.max() * 1e3:.1f}" if d.size else "-"
        print(
            f"| {label} | {len(fixed)} | {int(fixed.sum())} | {d.size} | {med} | {mx} | "
            f"{int((d > APART_M).sum())} | {wall:.2f} |"
        )


if __name__ == "__main__":
    main()
