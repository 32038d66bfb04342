"""The datasets compared: GEONET, the simulated static baseline and the cssrlib pair; their RINEX
headers' positions and carrier bands."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from .metrics import Reference
from .solutions import gpst_seconds, match_epochs


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
