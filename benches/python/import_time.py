"""Cold-start cost of ``import gnssatt`` against its floor, ``import numpy, scipy.spatial.transform``.

    python benches/python/import_time.py [--starts 11]

Each start is a fresh interpreter (``python -c``), so nothing is cached in ``sys.modules``; the import is
timed inside it with ``time.perf_counter`` (interpreter start-up excluded). The two statements alternate so
that a load change on the machine hits both alike. Prints the median of each and the differences. A third
statement, ``from gnssatt import matrix_attitude``, shows what the first use of an estimator adds (its
module and what it needs load lazily then).
"""

from __future__ import annotations

import argparse
import statistics
import subprocess
import sys

FLOOR = "numpy + scipy.spatial.transform"
STATEMENTS = {
    "gnssatt": "import gnssatt",
    FLOOR: "import numpy, scipy.spatial.transform",
    "gnssatt.matrix_attitude": "from gnssatt import matrix_attitude",
}


def cold_import_s(statement: str) -> float:
    """Seconds one fresh interpreter spends on ``statement``."""
    code = f"import time; t0 = time.perf_counter(); {statement}; print(time.perf_counter() - t0)"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    return float(out.stdout)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--starts", type=int, default=11, help="fresh interpreters per statement (>= 7)")
    args = ap.parse_args()
    if args.starts < 7:
        ap.error(f"--starts must be >= 7 for a stable median, got {args.starts}")
    for statement in STATEMENTS.values():
        cold_import_s(statement)  # fills the OS file cache once; not counted
    times: dict[str, list[float]] = {label: [] for label in STATEMENTS}
    for _ in range(args.starts):
        for label, statement in STATEMENTS.items():
            times[label].append(cold_import_s(statement))
    med = {label: statistics.median(t) for label, t in times.items()}
    for label, m in med.items():
        print(f"{STATEMENTS[label]}: median {1e3 * m:.0f} ms over {args.starts} cold starts")
    for label in ("gnssatt", "gnssatt.matrix_attitude"):
        print(f"{label} - {FLOOR}: {1e3 * (med[label] - med[FLOOR]):+.0f} ms")


if __name__ == "__main__":
    main()
