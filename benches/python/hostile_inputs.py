"""Count the outcomes of hostile input over the whole public API (issue 15).

Runs every inventory entry (``tests/hostile/inventory.py``) x fixed mutation category, ``--examples``
hypothesis draws per function, every numeric array argument broadcast to a leading axis of 10^6 and 10^7
rows (the batch-size dimension, ``--batch-rows``), ``--rinex-mutations`` byte flips / truncations per
RINEX file (plus every field edit), LAMBDA against the independent search on ill-conditioned
covariances, and the bad command lines; prints outcome counts per category and per module, then one line
per contract failure.

    python benches/python/hostile_inputs.py [--examples N] [--seed S] [--rinex-mutations N]

Hostile calls run in a worker subprocess (restarted after an abort or a hang; the hang limit is 10 s).
"""

from __future__ import annotations

import argparse
import sys
import time
from collections import Counter, defaultdict
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "tests"))

from hostile import cli_cases, harness, scenario
from hostile import inventory as inv
from hostile import outcomes as oc
from hostile import rinex_mutations as rm
from hostile.test_lambda_reference import judge
from hostile.test_properties import run_drawn
from hostile.worker import Job, Pool
from references import lambda_reference as ref


def rinex_records(pool: Pool, n_random: int, seed: int) -> list[harness.Record]:
    s = scenario.rinex_array()
    out = []
    for i, m in enumerate(rm.file_mutants(rm.default_sources(s.obs_paths[0], s.nav_path), n_random, seed)):
        path = scenario.folder() / f"mutant-{i}-{m.source}"
        path.write_bytes(m.text)
        a = pool.run(
            Job(
                m.reader,
                kwargs={"path": path},
                names=(path.name,),
                must_refuse=m.must_refuse,
                nan_output_ok=True,
            )
        )
        out.append(
            harness.Record("rinex files", m.reader, m.source, m.category, m.label, a.outcome, a.detail)
        )
    return out


def lambda_records(pool: Pool, n_cases: int, seed: int) -> list[harness.Record]:
    rng = np.random.default_rng(seed)
    out = []
    for k in range(n_cases):
        n = int(rng.integers(2, 65))
        cond = float(10 ** rng.uniform(0, 8))
        outcome, detail = judge(pool, ref.make_case(seed * 100_000 + k, n, cond))
        if outcome != "skip":
            label = f"n={n} cond={cond:.1e} seed={seed * 100_000 + k}"
            out.append(
                harness.Record("lambda", "gnssatt.lambda_ils", "-", "lambda-ils", label, outcome, detail)
            )
    return out


def cli_records() -> list[harness.Record]:
    s = scenario.rinex_array()
    bad = scenario.folder() / "cut.24o"
    text = s.obs_paths[0].read_bytes()
    bad.write_bytes(text[: len(text) * 2 // 3 + 7])
    out = []
    for case in cli_cases.cases(s.obs_paths, s.nav_path, bad, scenario.folder()):
        outcome, detail, _ = cli_cases.run_case(case)
        out.append(
            harness.Record(
                "cli", "gnssatt " + " ".join(case.argv)[:60], "-", "cli", case.label, outcome, detail
            )
        )
    return out


def table(records: list[harness.Record], key: str) -> str:
    counts: dict[str, Counter[str]] = defaultdict(Counter)
    for r in records:
        counts[getattr(r, key)][r.outcome] += 1
    cols = [o for o in oc.ORDER if any(c[o] for c in counts.values())]
    head = f"| {key} | calls | " + " | ".join(cols) + " |"
    rows = [head, "|" + "---|" * (len(cols) + 2)]
    for name in sorted(counts):
        c = counts[name]
        rows.append(f"| {name} | {sum(c.values())} | " + " | ".join(str(c[o]) for o in cols) + " |")
    total = Counter(r.outcome for r in records)
    rows.append(f"| all | {len(records)} | " + " | ".join(str(total[o]) for o in cols) + " |")
    return "\n".join(rows)


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--examples", type=int, default=20, help="hypothesis draws per function (default 20)")
    p.add_argument(
        "--seed",
        type=int,
        default=15,
        help="seed of the hypothesis draws, RINEX mutations and LAMBDA cases (default 15)",
    )
    p.add_argument("--rinex-mutations", type=int, default=10, help="random mutations of each kind per file")
    p.add_argument("--lambda-cases", type=int, default=40, help="random LAMBDA problems (default 40)")
    p.add_argument(
        "--batch-rows",
        default="1e6,1e7",
        help="leading axes of the batch-size dimension, comma-separated (default 1e6,1e7)",
    )
    p.add_argument("--only", default="", help="run only entries whose name contains this text")
    p.add_argument(
        "--skip", default="", help="comma-separated parts to skip: fixed,hypothesis,batch,rinex,lambda,cli"
    )
    args = p.parse_args()
    skip = set(filter(None, args.skip.split(",")))
    names = [n for n in sorted(inv.ENTRIES) if args.only in n]
    pool = Pool()
    records: list[harness.Record] = []
    start = time.perf_counter()
    try:
        if "fixed" not in skip:
            records += harness.run_fixed(pool, names)
            print(
                f"fixed categories: {len(records)} calls, {time.perf_counter() - start:.0f} s",
                file=sys.stderr,
            )
        if "hypothesis" not in skip and args.examples > 0:
            for name in names:
                if inv.ENTRIES[name].build():  # a function without arguments has nothing to draw
                    records += run_drawn(pool, name, args.examples, args.seed)
            print(f"+ hypothesis: {len(records)} calls, {time.perf_counter() - start:.0f} s", file=sys.stderr)
        if "batch" not in skip:
            rows = [int(float(x)) for x in args.batch_rows.split(",") if x]
            records += harness.run_batch(pool, names, rows)
            print(
                f"+ batch sizes: {len(records)} calls, {time.perf_counter() - start:.0f} s", file=sys.stderr
            )
        if "rinex" not in skip:
            records += rinex_records(pool, args.rinex_mutations, args.seed)
        if "lambda" not in skip:
            records += lambda_records(pool, args.lambda_cases, args.seed)
        if "cli" not in skip:
            records += cli_records()
    finally:
        pool.close()
    fails = harness.failures(records)
    print(
        f"# hostile inputs: {len(records)} calls in {time.perf_counter() - start:.0f} s, "
        f"{pool.restarts} worker restarts, {len(fails)} contract failures\n"
    )
    print("## Outcomes per category\n")
    print(table(records, "category"))
    print("\n## Outcomes per module\n")
    print(table(records, "module"))
    print("\n## Contract failures\n")
    for r in sorted(fails, key=lambda r: (r.module, r.function, r.param, r.category)):
        print(f"- {r.line()}")
    return 1 if fails else 0


if __name__ == "__main__":
    raise SystemExit(main())
