"""Single-receiver code positions of the real corpus's same-day station pairs, gnssatt beside RTKLIB 2.4.3.

    python benches/python/position_compare.py CORPUS_DIR [--rtklib DIR] [--out DIR]

CORPUS_DIR is ``../shared/data/rinex_corpus_georust`` (README there); its same-day observation and
navigation files of one station: ESBC00DNK 2020-177 (RINEX 3 mixed navigation), KMS300DNK 2022-159 (RINEX 4
navigation), NYA100NOR 2024-124 (RINEX 3 GN + EN + CN). For GPS alone and for every system:

- gnssatt: ``gnssatt position --obs F --nav N ... --no-plot`` of this interpreter's package, run as a user
  runs it (subprocess: interpreter start, import, reading, solving, CSV written);
- RTKLIB: ``rnx2rtkp`` single mode (``pos1-posmode=single``, broadcast ionosphere, Saastamoinen troposphere,
  elevation mask 10 deg, ``pos1-navsys`` 1 or 61, ECEF output), built from ``--rtklib DIR`` (``DIR/build.sh``)
  into the output folder.

Both read the same files, decompressed into the output folder first (RTKLIB 2.4.3 reads neither Hatanaka nor
gzip without external tools; gnssatt reads both, but decompressing in Python would dominate its time).

Per run: epochs solved of the file's epochs, distance of the per-axis median position from the header's
``APPROX POSITION XYZ``, the distance between the two tools' medians, and wall time. Prints a markdown table.
"""

from __future__ import annotations

import argparse
import csv
import gzip
import shutil
import subprocess
import sys
import time
from collections.abc import Sequence
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parents[2]
DEFAULT_OUT = REPO / "out" / "position_compare"
#: station -> (observation file, navigation files), paths in the corpus.
PAIRS = {
    "ESBC00DNK 2020-177": (
        "CRNX/V3/ESBC00DNK_R_20201770000_01D_30S_MO.crx.gz",
        ["NAV/V3/ESBC00DNK_R_20201770000_01D_MN.rnx.gz"],
    ),
    "KMS300DNK 2022-159": (
        "CRNX/V3/KMS300DNK_R_20221591000_01H_30S_MO.crx",
        ["NAV/V4/KMS300DNK_R_20221591000_01H_MN.rnx.gz"],
    ),
    "NYA100NOR 2024-124": (
        "CRNX/V3/NYA100NOR_S_20241240000_01D_30S_MO.crx.gz",
        [f"NAV/V3/NYA100NOR_S_20241240000_01D_{k}N.rnx.gz" for k in "GEC"],
    ),
}
#: Runs: label -> (gnssatt --systems, RTKLIB pos1-navsys: 1 GPS, 4 GLONASS, 8 Galileo, 16 QZSS, 32 BeiDou).
SYSTEM_SETS = {"GPS": ("G", 1), "all": ("GRECJ", 61)}
RTKLIB_CONF = """pos1-posmode       =single
pos1-frequency     =l1
pos1-elmask        =10
pos1-ionoopt       =brdc
pos1-tropopt       =saas
pos1-sateph        =brdc
pos1-navsys        ={navsys}
out-solformat      =xyz
out-timesys        =gpst
"""


def header_position(rinex: Path) -> np.ndarray:
    """APPROX POSITION XYZ of an uncompressed observation file."""
    with rinex.open(errors="replace") as f:
        for line in f:
            if "APPROX POSITION XYZ" in line[60:]:
                return np.array([float(v) for v in line[:60].split()[:3]])
            if "END OF HEADER" in line[60:]:
                break
    return np.full(3, np.nan)


def decompress(source: Path, folder: Path) -> Path:
    """``source`` as plain RINEX in ``folder``: Hatanaka (``.crx``, ``.crx.gz``) and gzip undone."""
    import hatanaka

    name = source.name.removesuffix(".gz").replace(".crx", ".rnx")
    target = folder / name
    if not target.exists():
        if ".crx" in source.name:
            target.write_bytes(hatanaka.decompress(source.read_bytes()))
        elif source.suffix == ".gz":
            target.write_bytes(gzip.decompress(source.read_bytes()))
        else:
            shutil.copyfile(source, target)
    return target


def gnssatt_run(obs: Path, navs: list[Path], systems: str, out: Path) -> tuple[np.ndarray, int, float, str]:
    """Median ECEF position (NaN if none), epochs solved and wall time of ``gnssatt position``."""
    exe = Path(sys.executable).with_name("gnssatt")
    cmd = [str(exe)] if exe.exists() else [sys.executable, "-m", "gnssatt"]
    cmd += ["position", "--obs", str(obs), "--out", str(out), "--systems", systems, "--no-plot"]
    for n in navs:
        cmd += ["--nav", str(n)]
    t0 = time.perf_counter()
    run = subprocess.run(cmd, capture_output=True, text=True, timeout=600)
    wall = time.perf_counter() - t0
    if run.returncode != 0:
        return np.full(3, np.nan), 0, wall, run.stderr.strip().splitlines()[-1]
    with out.open() as f:
        rows = list(csv.DictReader(f))
    xyz = np.array([[float(r[k]) for k in ("x_m", "y_m", "z_m")] for r in rows if int(r["satellites"]) > 0])
    med = np.median(xyz, axis=0) if len(xyz) else np.full(3, np.nan)
    return med, len(xyz), wall, ""


def rtklib_run(
    binary: Path, obs: Path, navs: list[Path], navsys: int, folder: Path
) -> tuple[np.ndarray, int, float, str]:
    """Median ECEF position, epochs solved and wall time of ``rnx2rtkp`` single mode."""
    conf = folder / f"single_{navsys}.conf"
    conf.write_text(RTKLIB_CONF.format(navsys=navsys))
    out = folder / f"{obs.stem}_{navsys}.pos"
    cmd = [str(binary), "-k", str(conf), "-o", str(out), str(obs), *map(str, navs)]
    t0 = time.perf_counter()
    run = subprocess.run(cmd, capture_output=True, text=True, timeout=600)
    wall = time.perf_counter() - t0
    rows = []
    if out.exists():
        for line in out.read_text().splitlines():
            if line and not line.startswith("%"):
                parts = line.split()
                rows.append([float(v) for v in parts[2:5]])
    xyz = np.array(rows)
    med = np.median(xyz, axis=0) if len(xyz) else np.full(3, np.nan)
    note = "" if len(xyz) else (run.stderr.strip().splitlines() or ["no solution"])[-1][:80]
    return med, len(xyz), wall, note


def epochs_in(obs: Path) -> int:
    """Epoch lines of a RINEX 3/4 observation file."""
    with obs.open(errors="replace") as f:
        return sum(1 for line in f if line.startswith(">"))


def _m(x: float) -> str:
    return "-" if not np.isfinite(x) else f"{x:.2f}"


def main(argv: Sequence[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("corpus", type=Path, help="the rinex_corpus_georust folder")
    ap.add_argument("--rtklib", type=Path, default=None, help="RTKLIB 2.4.3 source folder with build.sh")
    ap.add_argument("--out", type=Path, default=DEFAULT_OUT, help="work folder")
    args = ap.parse_args(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    binary = None
    if args.rtklib is not None:
        build = subprocess.run(
            [str(args.rtklib / "build.sh"), str(args.out / "rtklib")],
            capture_output=True,
            text=True,
            check=True,
        )
        binary = Path(build.stdout.strip().splitlines()[-1])
    print(
        "| station | systems | epochs | gnssatt solved | gnssatt to header (m) | gnssatt time (s) "
        "| RTKLIB solved | RTKLIB to header (m) | RTKLIB time (s) | gnssatt to RTKLIB (m) |"
    )
    print("|---|---|---|---|---|---|---|---|---|---|")
    notes = []
    for station, (obs_rel, nav_rel) in PAIRS.items():
        obs_src = args.corpus / obs_rel
        navs_src = [args.corpus / n for n in nav_rel]
        obs = decompress(obs_src, args.out)
        navs = [decompress(n, args.out) for n in navs_src]
        head = header_position(obs)
        n_ep = epochs_in(obs)
        for label, (systems, navsys) in SYSTEM_SETS.items():
            g_med, g_n, g_t, g_note = gnssatt_run(obs, navs, systems, args.out / f"{obs.stem}_{systems}.csv")
            if g_note:
                notes.append(f"gnssatt {station} {label}: {g_note}")
            if binary is not None:
                r_med, r_n, r_t, r_note = rtklib_run(binary, obs, navs, navsys, args.out)
                if r_note:
                    notes.append(f"RTKLIB {station} {label}: {r_note}")
                r_cells = [str(r_n), _m(float(np.linalg.norm(r_med - head))), f"{r_t:.2f}"]
                between = _m(float(np.linalg.norm(g_med - r_med)))
            else:
                r_cells, between = ["skipped"] * 3, "-"
            print(
                f"| {station} | {label} | {n_ep} | {g_n} | {_m(float(np.linalg.norm(g_med - head)))} "
                f"| {g_t:.2f} | {' | '.join(r_cells)} | {between} |"
            )
    for note in notes:
        print(f"\n{note}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
