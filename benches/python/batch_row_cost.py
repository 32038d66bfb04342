"""Per-row cost of the batch entry points: the numbers behind the whole-call row limits of docs/limits.md.

Each numeric array argument of the hostile inventory's valid calls (``tests/hostile/inventory.py``) is
replaced by its first row (or its one 3-vector) broadcast zero-stride to ``--rows`` rows, as the batch-size
dimension of ``hostile_inputs.py`` does, and the call is timed in this process, with its peak of traced
memory (tracemalloc); a call refused (``WorkLimitError`` or a shape error) prints the refusal. Run it on
sizes under the limits (``--rows 1e6``) to measure a cost, above them (``--rows 1e7``) to see the refusals.

    python benches/python/batch_row_cost.py --rows 1e6 [--only wahba,triad]
"""

from __future__ import annotations

import argparse
import sys
import time
import tracemalloc
import warnings
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "tests"))

from hostile import harness
from hostile import inventory as inv


def timed(fn: object, kwargs: dict[str, object]) -> tuple[float, int, str]:
    tracemalloc.start()
    start = time.perf_counter()
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            fn(**kwargs)  # type: ignore[operator]
        what = "ok"
    except Exception as exc:
        what = f"{type(exc).__name__}: {str(exc)[:70]}"
    seconds = time.perf_counter() - start
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    return seconds, peak, what


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rows", type=float, default=1e6, help="leading axis of the batch (default 1e6)")
    parser.add_argument("--only", default="", help="comma-separated function names (last dotted part)")
    args = parser.parse_args()
    n = int(args.rows)
    only = {x for x in args.only.split(",") if x}
    print("| function | argument | rows | s | ns / row | peak MB | outcome |")
    print("|---|---|---|---|---|---|---|")
    for name in inv.ENTRIES:
        if only and name.split(".")[-1] not in only:
            continue
        fn = inv.resolve(name)
        for param in harness.batch_params(name):
            kwargs = inv.ENTRIES[name].build()
            valid = np.asarray(kwargs[param])
            rows = (n, 3) if valid.shape == (3,) else (n, *valid.shape[1:])
            kwargs[param] = np.broadcast_to(valid if valid.shape == (3,) else valid[:1], rows)
            seconds, peak, what = timed(fn, kwargs)
            cost = f"{seconds:.2f} | {seconds / n * 1e9:.0f} | {peak / 1e6:.0f}"
            print(f"| {name} | {param} | {n} | {cost} | {what} |", flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
