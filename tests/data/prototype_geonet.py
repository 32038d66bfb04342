"""Records the Python prototype's results on the shipped GEONET pair, before the engine replaced it.

Run from the repository root at commit 7b709a6 (the prototype ``attitude_from_rinex`` on ``rinex/align``,
``baseline``, ``epoch_lambda``): ``python tests/data/prototype_geonet.py`` writes
``tests/data/prototype_geonet.json``, which tests/test_gnss_attitude.py and
tests/test_gnss_prototype_reference.py compare the engine with. It cannot run after the commit that deleted
those modules; it stays as the record of how the fixture was made.
The prototype uses GPS L1 only, code 0.5 m and phase 3 mm without elevation weights, no troposphere, the
base at its own code solution.
"""

from __future__ import annotations

import json
import subprocess
from pathlib import Path

import numpy as np

from gnssatt.data import geonet_dir
from gnssatt.gnss.attitude import attitude_from_rinex
from gnssatt.rinex import read_nav, read_obs
from gnssatt.rinex.align import align_receivers
from gnssatt.rinex.baseline import static_baseline
from gnssatt.rinex.epoch_lambda import epoch_lambda


def _list(a: np.ndarray) -> list:
    return [None if not np.isfinite(x) else round(float(x), 6) for x in np.asarray(a, dtype=float).ravel()]


def main() -> None:
    d = geonet_dir()
    obs = [read_obs(d / "07590920.05o"), read_obs(d / "30400920.05o")]
    nav = read_nav(d / "07590920.05n")
    al = align_receivers(obs, nav, systems="G", elevation_mask_deg=10.0)
    sb = static_baseline(al)
    el = epoch_lambda(al, None)
    out: dict = {
        "command": "python tests/data/prototype_geonet.py",
        "commit": subprocess.run(["git", "rev-parse", "HEAD"], capture_output=True, text=True).stdout.strip(),
        "signals": "GPS L1 (C1, L1), elevation mask 10 deg",
        "static": {
            "baseline_enu_m": _list(sb.baseline_enu_m),
            "baseline_ecef_m": _list(sb.baseline_ecef_m),
            "fixed": bool(sb.fixed),
            "ratio": round(float(sb.ratio), 4),
            "ambiguities": len(sb.arcs),
        },
        "moving": {
            "fixed_epochs": int(el.fixed.sum()),
            "epochs": len(el.fixed),
            "baselines_enu_m": [_list(b) for b in el.baselines_enu_m[:, 0]],
            "fixed": [int(f) for f in el.fixed],
        },
    }
    for motion in ("static", "moving"):
        s = attitude_from_rinex(obs, nav, method="lambda", motion=motion, systems="G")
        out[motion]["time_gpst"] = [str(t) for t in s.time]
        out[motion]["angles_deg"] = [_list(a) for a in s.angles_deg]
        out[motion]["satellites"] = [int(x) for x in s.satellites]
    path = Path(__file__).with_suffix(".json")
    path.write_text(json.dumps(out, indent=1) + "\n")
    print(f"wrote {path}")


if __name__ == "__main__":
    main()
