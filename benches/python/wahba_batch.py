"""Batch Wahba through gnssatt.wahba against a Python loop over scipy's Rotation.align_vectors.

Times, in one run, 10^6 epochs of 3 vector pairs through the batch API (each method) and a scipy loop over a
subset (timed on --loop-epochs epochs and scaled linearly to 10^6, which the script says), and prints medians
and the ratio. Threads: RAYON_NUM_THREADS.
"""

from __future__ import annotations

import argparse
import os
import time

import numpy as np
from scipy.spatial.transform import Rotation

import gnssatt


def median_time(fn, reps: int) -> float:  # type: ignore[no-untyped-def]
    times = []
    for _ in range(reps):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return float(np.median(times))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--epochs", type=int, default=1_000_000)
    parser.add_argument("--pairs", type=int, default=3)
    parser.add_argument("--loop-epochs", type=int, default=5_000)
    parser.add_argument("--reps", type=int, default=3)
    args = parser.parse_args()
    rng = np.random.default_rng(0)
    truth = Rotation.random(args.epochs, random_state=rng)
    ref = rng.standard_normal((args.epochs, args.pairs, 3))
    ref /= np.linalg.norm(ref, axis=-1, keepdims=True)
    body = np.einsum("eij,ekj->eki", truth.inv().as_matrix(), ref) + 1e-3 * rng.standard_normal(ref.shape)
    print(f"machine: {os.cpu_count()} CPUs; {args.epochs} epochs x {args.pairs} vector pairs")
    for method in ("svd", "davenport", "quest"):
        t = median_time(lambda m=method: gnssatt.wahba(body, ref, method=m), args.reps)
        print(f"gnssatt.wahba(method={method!r}): {t * 1e3:9.1f} ms  ({t / args.epochs * 1e9:.0f} ns/epoch)")
        if method == "svd":
            t_svd = t
    n = args.loop_epochs
    t_loop = median_time(lambda: [Rotation.align_vectors(ref[e], body[e]) for e in range(n)], args.reps)
    scaled = t_loop * args.epochs / n
    print(
        f"scipy align_vectors loop: {t_loop * 1e3:.1f} ms for {n} epochs, "
        f"scaled to {args.epochs}: {scaled:.1f} s"
    )
    print(f"ratio scipy loop / gnssatt svd batch: {scaled / t_svd:.0f}x")


if __name__ == "__main__":
    main()
