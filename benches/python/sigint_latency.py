"""How long a long Rust call takes to stop after SIGINT (the latency tests/test_limits.py no longer asserts).

Starts a child that runs 2.8e7 RK4 steps of the tumble propagator (several seconds uninterrupted), sends it
SIGINT after 0.3 s and prints the delay from the signal to the child's KeyboardInterrupt, next to the time
the call takes uninterrupted (the reference in the same script). CLOCK_MONOTONIC is system-wide on Linux,
so the child's clock reading is comparable with ours.

    python benches/python/sigint_latency.py
"""

from __future__ import annotations

import signal
import subprocess
import sys
import textwrap
import time

CHILD = textwrap.dedent(
    """
    import signal, sys, time
    from gnssatt.attitude import dynamics as tumble

    signal.signal(signal.SIGINT, signal.default_int_handler)
    print("ready", flush=True)
    start = time.monotonic()
    try:
        tumble.propagate_axes([0.7, 1.1, -2.0, 0.01, -0.01, 0.01], [1.4e6], step_s=0.05)
        print("finished", time.monotonic() - start, flush=True)
    except KeyboardInterrupt:
        print("interrupted", time.monotonic(), flush=True)
    """
)


def run(interrupt: bool) -> str:
    child = subprocess.Popen([sys.executable, "-c", CHILD], stdout=subprocess.PIPE, text=True)
    assert child.stdout is not None
    child.stdout.readline()
    sent = 0.0
    if interrupt:
        time.sleep(0.3)
        sent = time.monotonic()
        child.send_signal(signal.SIGINT)
    out, _ = child.communicate(timeout=600)
    word, value = out.split()[:2]
    if word == "interrupted":
        return f"stopped {float(value) - sent:.3f} s after SIGINT"
    return f"finished uninterrupted in {float(value):.3f} s"


if __name__ == "__main__":
    print("interrupted:", run(True))
    print("reference:  ", run(False))
