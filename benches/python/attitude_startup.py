"""Wall time of a short recorded session from the command line against RTKLIB's ``rnx2rtkp`` on the same
files, and where gnssatt's start-up goes: the interpreter alone, the imports the command makes before its
first epoch, and the whole command.

    python benches/python/attitude_startup.py DATA [--rnx2rtkp PATH [--conf DIR]] [--before DIR] [--starts 11]

DATA: the GEONET pair's folder (``../shared/data/rtklib_geonet_0759_3040``: 0759 as reference, 3040 as
rover, 120 epochs, GPS L1 + L2). The gnssatt command is the one of ``docs/examples/recorded_data.md``
(``gnssatt attitude --obs 07590920.05o --obs 30400920.05o --nav 07590920.05n --motion moving --frequencies
2``) with ``--no-plot``; RTKLIB's is the one of ``../shared/peers/README.md`` (``kinematic-instantaneous``,
``-f 2``), the peer built with its ``build.sh``. Each start is a fresh process; the commands alternate so
that a load change hits all alike; medians are printed with the difference to RTKLIB. The Python commands
run with bytecode caching on (``PYTHONDONTWRITEBYTECODE`` removed; the warm-up start writes the
``__pycache__`` files), as an installed package runs: pip compiles a wheel's modules when it installs it.

Besides the command of the comparison (``--no-plot``), the rows are the floor every start pays (the
interpreter, numpy: the engine's results are numpy arrays), the command as a user types it, which also
writes the plot (matplotlib), and with ``--before DIR`` the same command run from another checkout's
``python/`` folder (``PYTHONPATH=DIR``; its ``gnssatt/_core*.so`` built or copied there), without and with
the plot, so that a change is measured against its base in the same alternation.
"""

from __future__ import annotations

import argparse
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

#: What ``gnssatt attitude`` imports before it reads the first file.
IMPORTS = "import gnssatt.cli, gnssatt.gnss.attitude, gnssatt.gnss.session_input"


_ENV = {k: v for k, v in os.environ.items() if k != "PYTHONDONTWRITEBYTECODE"}


def wall_cpu_s(cmd: list[str], cwd: str, env: dict[str, str]) -> tuple[float, float]:
    """Wall and CPU (user + system) seconds of one run of ``cmd``: on a loaded machine the CPU time
    is the steadier measure of the work a start does."""
    r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    subprocess.run(cmd, cwd=cwd, check=True, capture_output=True, env=env)
    wall = time.perf_counter() - t0
    r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    return wall, (r1.ru_utime - r0.ru_utime) + (r1.ru_stime - r0.ru_stime)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("data", type=Path)
    ap.add_argument("--rnx2rtkp", type=Path, help="RTKLIB 2.4.3's rnx2rtkp (../shared/peers build.sh)")
    ap.add_argument("--conf", type=Path, default=Path("../shared/peers/rtklib-2.4.3/conf"), help="its conf/")
    ap.add_argument("--before", type=Path, help="another checkout's python/ folder, run as the reference")
    ap.add_argument("--starts", type=int, default=11)
    args = ap.parse_args()
    if args.starts < 7:
        ap.error(f"--starts must be >= 7 for a stable median, got {args.starts}")
    d = args.data.resolve()
    gnssatt = [sys.executable, "-m", "gnssatt.cli", "attitude", "--obs", str(d / "07590920.05o")]
    gnssatt += ["--obs", str(d / "30400920.05o"), "--nav", str(d / "07590920.05n")]
    gnssatt += ["--motion", "moving", "--frequencies", "2", "--out", "startup.csv"]
    commands = {
        "python -c pass": [sys.executable, "-c", "pass"],
        "python -c 'import numpy'": [sys.executable, "-c", "import numpy"],
        "imports before the first epoch": [sys.executable, "-c", IMPORTS],
        "gnssatt attitude": [*gnssatt, "--no-plot"],
        "gnssatt attitude, with the plot (the default)": gnssatt,
    }
    before = f"gnssatt attitude, PYTHONPATH={args.before}"
    before_plot = f"gnssatt attitude, with the plot, PYTHONPATH={args.before}"
    if args.before:
        commands[before] = [*gnssatt, "--no-plot"]
        commands[before_plot] = gnssatt
    if args.rnx2rtkp:
        conf = args.conf.resolve() / "kinematic-instantaneous.conf"
        files = [str(d / f) for f in ("30400920.05o", "07590920.05o", "07590920.05n", "30400920.05n")]
        commands["rnx2rtkp"] = [
            str(args.rnx2rtkp.resolve()), "-k", str(conf), "-f", "2",
            "-r", "-3976219.5082", "3382372.5671", "3652512.9849", "-o", "startup.pos", *files,
        ]  # fmt: skip
    envs = dict.fromkeys(commands, _ENV)
    if args.before:
        envs[before] = envs[before_plot] = _ENV | {"PYTHONPATH": str(args.before.resolve())}
    times: dict[str, list[tuple[float, float]]] = {k: [] for k in commands}
    with tempfile.TemporaryDirectory() as folder:
        for name, cmd in commands.items():  # warm the file cache, write the bytecode
            wall_cpu_s(cmd, folder, envs[name])
        for _ in range(args.starts):
            for name, cmd in commands.items():
                times[name].append(wall_cpu_s(cmd, folder, envs[name]))
    med = {
        k: (statistics.median(t[0] for t in v), statistics.median(t[1] for t in v)) for k, v in times.items()
    }
    ref = med.get("rnx2rtkp")
    print(
        f"| command ({args.starts} starts, medians) | wall s | minus rnx2rtkp s | CPU s | minus rnx2rtkp s |"
    )
    print("|---|---:|---:|---:|---:|")
    for name, (wall, cpu) in med.items():
        dw, dc = ("", "") if ref is None else (f"{wall - ref[0]:+.3f}", f"{cpu - ref[1]:+.3f}")
        print(f"| {name} | {wall:.3f} | {dw} | {cpu:.3f} | {dc} |")


if __name__ == "__main__":
    main()
