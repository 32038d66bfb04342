"""RTKLIB's side: its conf copies (``pos1-navsys`` and the output format set) and ``rnx2rtkp`` commands."""

from __future__ import annotations

import subprocess
from pathlib import Path
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from .datasets import Dataset

#: ``pos1-navsys`` bit of each RINEX system letter (RTKLIB's SYS_* values).
NAVSYS_BITS = {"G": 1, "R": 4, "E": 8, "J": 16, "C": 32}
#: RTKLIB mode name -> (conf file, gnssatt --motion, gnssatt --filter or None).
MODES = {
    "single-epoch": ("kinematic-instantaneous.conf", "moving", None),
    "moving-base": ("movingbase-instantaneous.conf", "moving", None),
    "filtered": ("kinematic-continuous.conf", "moving", "kinematic"),
    "static": ("static-continuous.conf", "static", None),
}


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


def build_rtklib(src: Path, binary: Path | None, out: Path) -> Rtklib:
    """``binary``, or ``rnx2rtkp`` built by ``src/build.sh`` into ``out/rtklib``, with the confs of
    ``src/conf`` (modified copies into ``out/confs``)."""
    if binary is None:
        build = subprocess.run(
            ["bash", str(src / "build.sh"), str(out / "rtklib")],
            capture_output=True,
            text=True,
            check=True,
        )
        binary = Path(build.stdout.strip().splitlines()[-1])
    return Rtklib(binary.resolve(), src / "conf", out / "confs")
