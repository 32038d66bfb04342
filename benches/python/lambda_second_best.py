"""Does the independent LLL + Schnorr-Euchner solver find issue 31's second-best integers within LAMBDA's
own node budget? (It is what ``ConvergenceError only where an independent solver also needs more than the
budget`` asks.)

    python benches/python/lambda_second_best.py [--sizes 45:1e6,50:1e8]

For each (n, condition) it draws issue 31's problem (``tests/references/lambda_reference.make_case`` with
seed 31000 + n, ``Q = (q * (0.05 * logspace(0, -log10(cond), n))) @ q.T``, float vector from N(z, Q)),
asks ``gnssatt.lambda_ils`` for the two best candidates, and gives the reference the same node budget
(``NODES_PER_AMBIGUITY * n``). It prints, per problem, whether each certified its answer and the CPU time.
The reference is pure Python: about 6 us a node, so 2 to 3 minutes a problem at n = 45-50.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "tests"))

from references import lambda_reference as ref

import gnssatt
from gnssatt.ambiguity import NODES_PER_AMBIGUITY
from gnssatt.errors import ConvergenceError


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", default="45:1e6,50:1e8", help="n:condition pairs, comma separated")
    args = parser.parse_args()
    print("| n | condition | budget (nodes) | gnssatt m = 2 | reference m = 2 | reference CPU s |")
    print("|---|---|---|---|---|---|")
    for item in args.sizes.split(","):
        n_text, cond_text = item.split(":")
        n, cond = int(n_text), float(cond_text)
        case = ref.make_case(31_000 + n, n, cond, scale=0.05, centred=False)
        budget = NODES_PER_AMBIGUITY * n
        try:
            gnssatt.lambda_ils(case.a, case.q, candidates=2)
            ours = "certified"
        except ConvergenceError:
            ours = "node cap reached"
        start = time.process_time()
        sol = ref.reference_ils(case.a, case.q, 2, budget)
        spent = time.process_time() - start
        theirs = f"certified in {sol.nodes} nodes" if sol is not None else "budget exhausted"
        print(f"| {n} | {cond:.0e} | {budget:.3g} | {ours} | {theirs} | {spent:.0f} |", flush=True)


if __name__ == "__main__":
    main()
