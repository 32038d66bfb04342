"""LAMBDA per problem against RTKLIB 2.4.3's C ``lambda()``, on the same covariances and float vectors.

    python benches/python/lambda_rtklib.py --rtklib-src ../shared/peers/rtklib-2.4.3 [--sizes 4,6,...,40]
        [--draws 64] [--repeats 7] [--out DIR]

The covariances are those of ``benches/lambda_geometry.rs`` (a short static baseline, 5 epochs 2 s apart,
3 mm phase and 30 cm code at zenith; one frequency up to n = 10 and for odd n, two above), rebuilt here in
numpy, with ``--draws`` float vectors ``N + e``, ``e ~ N(0, Q)``, per n. Both sides are asked for the two
best candidates (what RTKLIB's ratio test uses) of every draw.

- RTKLIB: ``lambda()`` from ``--rtklib-src/src/lambda.c`` and ``rtkcmn.c``, linked into a small timing
  program written here (``HARNESS``, our code; RTKLIB's is only compiled, never copied) with ``cc -O3``; it
  times the loop over the draws ``--repeats`` times and prints the per-call median, and the integers it found.
- gnssatt core: ``gnssatt.lambda_ils_batch`` on the same draws with one thread (``RAYON_NUM_THREADS=1`` in
  a subprocess, set before the pool starts) and one covariance per problem (``(k, n, n)``, all equal), per
  problem: the Rust core's decorrelation, checks, search and recomputed norms, with the intake paid once
  per batch (what RTKLIB's ``lambda()`` does per call).
- gnssatt shared: the same batch with the one ``(n, n)`` covariance, decorrelated once for all the draws.
- gnssatt per call: ``gnssatt.lambda_ils`` from Python, one call per draw: what a loop over problems pays.

Times are the CPU time of the timing process (``CLOCK_PROCESS_CPUTIME_ID``, ``time.process_time``), not wall
time: on a shared machine the other jobs then count far less (they still share caches and cores). Each repeat
loops over the draws for at least 20 ms of CPU time. The integers of both tools are compared draw by draw
(they must agree: both are exact ILS; a disagreement is printed). Prints one markdown table (medians in
microseconds, ratios gnssatt / RTKLIB: below 1 is faster) and writes ``lambda_rtklib.json`` into ``--out``.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

REPO = Path(__file__).resolve().parents[2]
DEFAULT_OUT = REPO / "out" / "lambda_rtklib"
WAVELENGTHS_M = (0.190_293_672_798_365, 0.244_210_213_424_568, 0.254_828_048_790_854)

# Our timing program: reads the problems, calls RTKLIB's lambda() on each, prints medians and integers.
HARNESS = r"""
#include <stdio.h>
#include <stdlib.h>
#include <time.h>
int lambda(int n, int m, const double *a, const double *Q, double *F, double *s);
static double now(void) {
    struct timespec t; clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t); return t.tv_sec + 1e-9 * t.tv_nsec;
}
static int by_value(const void *x, const void *y) {
    double a = *(const double *)x, b = *(const double *)y; return (a > b) - (a < b);
}
int main(int argc, char **argv) {
    FILE *f = fopen(argv[1], "rb"); int repeats = atoi(argv[2]); int n, k;
    if (!f || fread(&n, sizeof n, 1, f) != 1 || fread(&k, sizeof k, 1, f) != 1) return 2;
    double *Q = malloc(sizeof(double) * n * n), *a = malloc(sizeof(double) * n * k);
    double *F = malloc(sizeof(double) * n * 2 * k), s[2], *times = malloc(sizeof(double) * repeats);
    if (fread(Q, sizeof(double), n * n, f) != (size_t)(n * n)) return 2;
    if (fread(a, sizeof(double), n * k, f) != (size_t)(n * k)) return 2;
    for (int r = 0; r < repeats; r++) {
        /* enough loops over the draws for about 20 ms per repeat */
        int loops = 1; double t0, t1;
        for (;;) {
            t0 = now();
            for (int l = 0; l < loops; l++) for (int i = 0; i < k; i++)
                if (lambda(n, 2, a + n * i, Q, F + 2 * n * i, s)) return 3;
            t1 = now();
            if (t1 - t0 > 0.02) break;
            loops *= 2;
        }
        times[r] = (t1 - t0) / (loops * (double)k);
    }
    qsort(times, repeats, sizeof(double), by_value);
    printf("%.6e\n", times[repeats / 2]);
    for (int i = 0; i < k; i++) {
        for (int j = 0; j < n; j++) printf("%.0f ", F[2 * n * i + j]);
        printf("\n");
    }
    return 0;
}
"""

# The gnssatt core side, run in a subprocess so that the thread count is fixed before rayon starts.
CORE_TIMER = r"""
import sys, time, numpy as np, gnssatt
data = np.load(sys.argv[1]); repeats = int(sys.argv[2])
q, a = data["q"], data["a"]
times = []
each = np.ascontiguousarray(np.broadcast_to(q, (len(a), *q.shape)))
for cov in (each, q):
    times = []
    for _ in range(repeats):
        loops = 1
        while True:
            t0 = time.process_time()
            for _ in range(loops):
                out = gnssatt.lambda_ils_batch(a, cov, candidates=2)
            t1 = time.process_time()
            if t1 - t0 > 0.02:
                break
            loops *= 2
        times.append((t1 - t0) / (loops * len(a)))
    print(f"{sorted(times)[len(times) // 2]:.6e}")
    np.save(sys.argv[3] + (".each.npy" if cov is each else ".shared.npy"), out.fixed[:, 0, :])
"""


def geometry_covariance(n: int) -> NDArray[np.float64]:
    """The ambiguity block of a short static baseline's float covariance (``benches/lambda_geometry.rs``)."""
    freqs = 2 if n > 10 and n % 2 == 0 else 1
    sats = n // freqs + 1
    m = sats - 1
    normal = np.zeros((3 + n, 3 + n))
    for e in range(5):
        t = 2.0 * e
        j = np.arange(sats)
        az = 2.399_963 * j + 1.0e-4 * t
        sign = np.where(j % 2 == 0, 1.0, -1.0)
        el = np.radians(15.0 + 70.0 * np.modf(0.618_034 * j)[0]) + sign * 5.0e-5 * t
        los = np.stack([np.cos(el) * np.sin(az), np.cos(el) * np.cos(az), np.sin(el)], axis=1)
        r = int(np.argmax(el))
        others = [i for i in range(sats) if i != r]

        def dd_cov(
            sigma: float, r: int = r, others: list[int] = others, el: NDArray[np.float64] = el
        ) -> NDArray:
            var = 2.0 * (sigma / np.sin(el)) ** 2
            return var[r] + np.diag(var[others])

        g = los[others] - los[r]
        w_code = np.linalg.inv(dd_cov(0.3))
        for f in range(freqs):
            lam = WAVELENGTHS_M[f]
            w_phase = np.linalg.inv(dd_cov(0.003) / lam**2)
            a = np.zeros((m, 3 + n))
            a[:, :3] = g / lam
            a[:, 3 + f * m : 3 + (f + 1) * m] = np.eye(m)
            normal += a.T @ w_phase @ a
            c = np.zeros((m, 3 + n))
            c[:, :3] = g
            normal += c.T @ w_code @ c
    cov = np.linalg.inv(normal)
    q = cov[3:, 3:]
    return (q + q.T) / 2


def draws(q: NDArray[np.float64], k: int, seed: int) -> NDArray[np.float64]:
    rng = np.random.default_rng(seed)
    truth = np.round(rng.uniform(-1e6, 1e6, (k, q.shape[0])))
    return truth + rng.standard_normal((k, q.shape[0])) @ np.linalg.cholesky(q).T


def build_harness(src: Path, out: Path) -> Path:
    c = out / "lambda_harness.c"
    c.write_text(HARNESS)
    exe = out / "lambda_harness"
    s = src / "src"
    cmd = [
        "cc",
        "-O3",
        "-std=gnu99",
        "-w",
        f"-I{s}",
        "-DENAGLO",
        "-DENAQZS",
        "-DENAGAL",
        "-DENACMP",
        "-DNFREQ=3",
    ]
    subprocess.run(
        [*cmd, "-o", str(exe), str(c), str(s / "lambda.c"), str(s / "rtkcmn.c"), "-lm"], check=True
    )
    return exe


def time_rtklib(exe: Path, q: NDArray, a: NDArray, repeats: int, work: Path) -> tuple[float, NDArray]:
    path = work / "problems.bin"
    with path.open("wb") as f:
        np.array([q.shape[0], len(a)], dtype=np.int32).tofile(f)
        np.asfortranarray(q).ravel(order="F").tofile(f)
        a.astype(np.float64).tofile(f)
    out = subprocess.run([str(exe), str(path), str(repeats)], check=True, capture_output=True, text=True)
    lines = out.stdout.split("\n")
    fixed = np.array([[float(v) for v in line.split()] for line in lines[1 : 1 + len(a)]])
    return float(lines[0]), fixed.astype(np.int64)


def time_core(q: NDArray, a: NDArray, repeats: int, work: Path) -> tuple[float, float, NDArray, NDArray]:
    np.savez(work / "problems.npz", q=q, a=a)
    env = dict(os.environ, RAYON_NUM_THREADS="1")
    out = subprocess.run(
        [sys.executable, "-c", CORE_TIMER, str(work / "problems.npz"), str(repeats), str(work / "fixed")],
        check=True,
        capture_output=True,
        text=True,
        env=env,
    )
    each_s, shared_s = (float(v) for v in out.stdout.split())
    return each_s, shared_s, np.load(work / "fixed.each.npy"), np.load(work / "fixed.shared.npy")


def time_per_call(q: NDArray, a: NDArray, repeats: int) -> float:
    import gnssatt

    times = []
    for _ in range(repeats):
        loops = 1
        while True:
            t0 = time.process_time()
            for _ in range(loops):
                for row in a:
                    gnssatt.lambda_ils(row, q, candidates=2)
            t1 = time.process_time()
            if t1 - t0 > 0.02:
                break
            loops *= 2
        times.append((t1 - t0) / (loops * len(a)))
    return statistics.median(times)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--rtklib-src", type=Path, default=None, help="RTKLIB 2.4.3 folder (src/lambda.c)")
    ap.add_argument("--sizes", default=",".join(str(n) for n in range(4, 41, 2)), help="comma-separated n")
    ap.add_argument("--draws", type=int, default=64, help="float vectors per n (default 64)")
    ap.add_argument("--repeats", type=int, default=7, help="timed repeats; the median is shown (default 7)")
    ap.add_argument("--out", type=Path, default=DEFAULT_OUT, help=f"output folder (default {DEFAULT_OUT})")
    args = ap.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)
    sizes = [int(v) for v in args.sizes.split(",")]
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        work = Path(tmp)
        exe = build_harness(args.rtklib_src, work) if args.rtklib_src else None
        print(
            "| n | RTKLIB lambda() us | gnssatt core us | core / RTKLIB | shared Q us | shared / RTKLIB "
            "| lambda_ils us | call / RTKLIB |"
        )
        print("|---|---|---|---|---|---|---|---|")
        for n in sizes:
            q = geometry_covariance(n)
            a = draws(q, args.draws, 42 + n)
            core_s, shared_s, core_fixed, shared_fixed = time_core(q, a, args.repeats, work)
            call_s = time_per_call(q, a, args.repeats)
            row: dict[str, float | int | None] = {
                "n": n,
                "core_us": core_s * 1e6,
                "shared_us": shared_s * 1e6,
                "call_us": call_s * 1e6,
            }
            if exe is not None:
                rtk_s, rtk_fixed = time_rtklib(exe, q, a, args.repeats, work)
                row["rtklib_us"] = rtk_s * 1e6
                differ = np.any(rtk_fixed != core_fixed, axis=1) | np.any(rtk_fixed != shared_fixed, axis=1)
                row["disagreements"] = int(np.sum(differ))
            rows.append(row)
            rtk = row.get("rtklib_us")
            core, shared, call = (float(row[key] or 0) for key in ("core_us", "shared_us", "call_us"))
            ratios = [f"{v / rtk:.2f}" if rtk else "-" for v in (core, shared, call)]
            print(
                f"| {n} | {f'{rtk:.2f}' if rtk else 'skipped'} | {core:.2f} | {ratios[0]} "
                f"| {shared:.2f} | {ratios[1]} | {call:.2f} | {ratios[2]} |"
                + (f" {row['disagreements']} draws disagree" if row.get("disagreements") else ""),
                flush=True,
            )
    (args.out / "lambda_rtklib.json").write_text(json.dumps(rows, indent=1))


if __name__ == "__main__":
    main()
