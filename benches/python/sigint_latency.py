"""How long each long call takes to stop after SIGINT (the latency tests/test_limits.py no longer asserts).

For each call a child process sets it up, prints ``ready``, runs it; the parent sends SIGINT ``--after``
seconds later and prints the delay from the signal to the child's ``KeyboardInterrupt`` (the child reads
CLOCK_MONOTONIC, system-wide on Linux, so its reading is comparable with ours), or how long the call ran
when it finished first. The reference in the same script is the tumble propagator's 2.8e7 RK4 steps, whose
loop polls the interrupt flag every 1024 steps. Calls:

- ``tumble``: ``propagate_axes`` over 1.4e6 s at 0.05 s steps (the reference);
- ``ml_series``: ``ml_attitude_series`` of 800 epochs at step 3 deg (29 ms an epoch, under its work limit);
- ``lambda_batch``: ``lambda_ils_batch`` of 20,000 problems of 24 ambiguities;
- ``position``: ``position_from_rinex`` on a simulated 2-antenna GRECJ session of ``--epochs`` epochs;
- ``attitude``: ``attitude_from_rinex`` on the same session (LAMBDA per epoch);
- ``montecarlo``: ``montecarlo.run`` of 10^6 trials of ``ml_attitude`` in this process.

    python benches/python/sigint_latency.py [--only ml_series,lambda_batch] [--epochs 2000] [--after 1]
        [--main-only]

By default the signal goes to the child's process group, as a terminal's Ctrl-C does; ``--main-only``
sends it to the child process alone (``kill -INT pid``), which a process pool's workers do not see.
"""

from __future__ import annotations

import argparse
import os
import signal
import subprocess
import sys
import tempfile
import textwrap
import time

PRELUDE = """
import signal, sys, time
import numpy as np
signal.signal(signal.SIGINT, signal.default_int_handler)
TRIAL = '''
import numpy as np
from gnssatt import ml_attitude, sim
from gnssatt.rotation import rotation_from_euler
los = sim.random_los(1, 6, min_elevation_deg=15.0)
b = sim.equilateral_triangle(1.0, plane="xz")[1:]
sd = -2 * np.pi / 0.19 * (rotation_from_euler([30.0, 10.0, -5.0]).apply(b) @ los.T)
def trial(rng):
    return ml_attitude(sd + rng.normal(0.0, 0.05, sd.shape), los, b, 0.19).euler_gost_deg
'''
"""

SETUP = {
    "tumble": (
        "from gnssatt.attitude import dynamics as tumble",
        "tumble.propagate_axes([0.7, 1.1, -2.0, 0.01, -0.01, 0.01], [1.4e6], step_s=0.05)",
    ),
    "ml_series": (
        """
from gnssatt import ml_attitude_series, sim
from gnssatt.rotation import rotation_from_euler
los = sim.random_los(1, 6, min_elevation_deg=15.0)
b = sim.equilateral_triangle(1.0, plane="xz")[1:]
sd = -2 * np.pi / 0.19 * (rotation_from_euler([30.0, 10.0, -5.0]).apply(b) @ los.T)
sd = np.array(np.broadcast_to(sd, (800, 2, 6)))
""",
        "ml_attitude_series(sd, los, b, 0.19, step_deg=3.0)",
    ),
    "lambda_batch": (
        """
from gnssatt import lambda_ils_batch
rng = np.random.default_rng(1)
n, k = 24, 20000
a = rng.standard_normal((n, n))
q = a @ a.T / n + 0.1 * np.eye(n)
z = rng.normal(0.0, 3.0, (k, n))
""",
        "lambda_ils_batch(z, q)",
    ),
    "position": (
        "import gnssatt\nobs, nav = sys.argv[1], sys.argv[2]",
        "gnssatt.position_from_rinex(obs, nav)",
    ),
    "attitude": (
        "from gnssatt.gnss.attitude import attitude_from_rinex\nobs, nav = sys.argv[1:3], sys.argv[3]",
        "attitude_from_rinex(obs, nav, motion='static')",
    ),
    "montecarlo": (
        """
import pathlib, tempfile
from gnssatt import montecarlo
# the trial is pickled to the worker processes: it lives in a module of its own
folder = tempfile.mkdtemp()
pathlib.Path(folder, "sigint_trial.py").write_text(TRIAL)
sys.path.insert(0, folder)
from sigint_trial import trial
""",
        "montecarlo.run(trial, 1_000_000, seed=1, progress=False)",
    ),
}


def child_code(name: str) -> str:
    setup, call = SETUP[name]
    body = f"""
{textwrap.dedent(setup)}
print("ready", flush=True)
start = time.monotonic()
try:
    {call}
    print("finished", time.monotonic() - start, flush=True)
except KeyboardInterrupt:
    print("interrupted", time.monotonic(), flush=True)
"""
    return PRELUDE + body


def run(name: str, args: list[str], after_s: float, main_only: bool) -> str:
    # a session of its own, so that its process group holds the child and its workers alone (a terminal's
    # Ctrl-C signals the foreground group; os.killpg on a child of our own group signalled nothing)
    child = subprocess.Popen(
        [sys.executable, "-c", child_code(name), *args],
        stdout=subprocess.PIPE,
        text=True,
        start_new_session=True,
    )
    assert child.stdout is not None
    if child.stdout.readline().strip() != "ready":
        child.wait()
        return f"setup failed (exit {child.returncode})"
    time.sleep(after_s)
    sent = time.monotonic()
    if main_only:
        os.kill(child.pid, signal.SIGINT)
    else:
        os.killpg(child.pid, signal.SIGINT)
    try:
        out, _ = child.communicate(timeout=120)
    except subprocess.TimeoutExpired:
        os.killpg(child.pid, signal.SIGKILL)
        child.communicate()
        return "no exit 120 s after SIGINT (killed)"
    stopped = time.monotonic()
    words = out.split()
    if words[:1] == ["interrupted"]:
        return f"{float(words[1]) - sent:.3f} s after SIGINT (exit after {stopped - sent:.3f} s)"
    if words[:1] == ["finished"]:
        return f"finished in {float(words[1]):.3f} s, before SIGINT took effect"
    late = f"{stopped - sent:.3f} s after SIGINT"
    return f"exit {child.returncode} {late} without KeyboardInterrupt: {out[-200:]!r}"


def session(folder: str, epochs: int) -> tuple[list[str], str]:
    import numpy as np

    from gnssatt.sim.rinex_scenario import simulate_gnss_rinex

    ant = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]])
    s = simulate_gnss_rinex(folder, ant, np.zeros((epochs, 3)), n_epochs=epochs, rng=1)
    return [str(p) for p in s.obs_paths], str(s.nav_path)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--only", default=",".join(SETUP), help="comma-separated calls (default all)")
    parser.add_argument("--epochs", type=int, default=2000, help="epochs of the simulated RINEX session")
    parser.add_argument("--after", type=float, default=1.0, help="seconds from ready to SIGINT (default 1)")
    parser.add_argument(
        "--main-only",
        action="store_true",
        help="signal the child process alone, not its process group (its pool's workers go unsignalled)",
    )
    args = parser.parse_args()
    names = [n for n in args.only.split(",") if n]
    print("| call | Ctrl-C |")
    print("|---|---|")
    with tempfile.TemporaryDirectory() as folder:
        obs: list[str] = []
        nav = ""
        if {"position", "attitude"} & set(names):
            obs, nav = session(folder, args.epochs)
        for name in names:
            extra = {"position": [*obs[:1], nav], "attitude": [*obs, nav]}.get(name, []) if obs else []
            print(f"| {name} | {run(name, extra, args.after, args.main_only)} |", flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
