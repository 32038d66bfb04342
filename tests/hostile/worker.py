"""Hostile calls run in a worker subprocess, so that an abort or a hang costs a restart, not the run.

The parent (:class:`Pool`) sends jobs as length-prefixed pickles on the worker's stdin and waits for each
answer with a timeout; a worker that dies by a signal gives ``abort``, one that does not answer in time is
killed and gives ``hang``; either way a fresh worker takes the next job. The worker writes its answers to a
duplicate of its stdout and points file descriptors 0-2 at /dev/null, so nothing the library prints can
corrupt the channel.
"""

from __future__ import annotations

import dataclasses
import inspect
import os
import pickle
import select
import signal
import struct
import subprocess
import sys
import time
import warnings
from dataclasses import dataclass
from pathlib import Path
from typing import Any, BinaryIO

import numpy as np
from valid_calls import resolve

from . import outcomes as oc

TESTS_DIR = Path(__file__).resolve().parents[1]
HANG_S = 10.0  # the contract: no call on hostile input runs longer than this
_HEADER = struct.Struct("<Q")


@dataclass(frozen=True)
class Job:
    """One call: ``entry``'s valid arguments with ``param`` replaced.

    ``mutant`` (category, index) names a fixed mutation, recomputed in the worker; otherwise ``value`` is
    the replacement. ``kwargs`` replaces the valid arguments altogether (RINEX files, LAMBDA cases), with
    ``names`` the words an input error must contain and ``nan_output_ok`` whether the result may hold NaN
    (for an entry, the entry says); ``want_result`` returns the result (pickled). ``batch_rows`` replaces
    ``param`` by its valid value's first row (or its one 3-vector) broadcast to that many rows, zero-stride
    (the batch-size dimension)."""

    function: str
    entry: str | None = None
    param: str | None = None
    mutant: tuple[str, int] | None = None
    value: Any = None
    kwargs: dict[str, Any] | None = None
    names: tuple[str, ...] = ()
    must_refuse: bool = False
    nan_output_ok: bool = False
    want_result: bool = False
    batch_rows: int = 0


@dataclass
class Answer:
    outcome: str
    detail: str = ""
    result: Any = None
    seconds: float = 0.0


def fixed_mutants(entry_name: str, param: str) -> list[Any]:
    """The fixed mutants of one argument of an inventory entry (same list in parent and worker)."""
    from . import inventory as inv
    from . import mutations as mu

    entry = inv.ENTRIES[entry_name]
    fn = resolve(entry_name)
    valid = entry.build()[param]
    default = inspect.signature(fn).parameters[param].default
    arg = entry.arg(param)
    out = mu.mutants(
        valid,
        param=param,
        counts=arg.count,
        work=arg.work,
        nonfinite_ok=arg.nonfinite_ok,
        none_ok=mu.none_ok(param, default),
        free_text=arg.free_text,
    )
    if arg.complex_ok:  # documented complex input: the finite complex mutants are valid
        out = [dataclasses.replace(m, must_refuse=False) if m.category == "complex" else m for m in out]
    return out


def _execute(job: Job) -> Answer:
    from . import inventory as inv

    fn = resolve(job.function)
    names = job.names
    must_refuse = job.must_refuse
    must_accept, propagates = False, ""
    if job.kwargs is not None:
        kwargs = dict(job.kwargs)
    else:
        assert job.entry is not None
        kwargs = inv.ENTRIES[job.entry].build()
        if job.param is not None:
            if job.batch_rows:
                # the batch-size dimension: the valid argument's first row, broadcast (zero-stride) to
                # batch_rows rows; made here, so nothing of the batch's size crosses the pipe
                valid = np.asarray(kwargs[job.param])
                if valid.shape == (3,):  # one vector: a batch of them is (rows, 3)
                    value = np.broadcast_to(valid, (job.batch_rows, 3))
                else:  # a batch already: its first row, repeated
                    value = np.broadcast_to(valid[:1], (job.batch_rows, *valid.shape[1:]))
            elif job.mutant is not None:
                cat, index = job.mutant
                m = [m for m in fixed_mutants(job.entry, job.param) if m.category == cat][index]
                value, must_refuse = m.value, m.must_refuse
                must_accept, propagates = m.must_accept, m.propagates
            else:
                value = job.value
            # a file argument may be named by its path (a RinexError names the file, not the parameter)
            is_path = isinstance(kwargs[job.param], os.PathLike) and isinstance(value, str | os.PathLike)
            names = (job.param, *((str(value),) if is_path and str(value) else ()))
            kwargs[job.param] = value
    start = time.perf_counter()
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            result = fn(**kwargs)
    except BaseException as exc:  # PanicException derives from BaseException
        seconds = time.perf_counter() - start
        if isinstance(exc, SystemExit | KeyboardInterrupt) and not oc.is_panic(exc):
            return Answer(oc.WRONG, oc.describe(exc), seconds=seconds)
        if propagates:  # user code's own error must come out unchanged
            ok = type(exc).__name__ == propagates
            return Answer(oc.REFUSED if ok else oc.WRONG, oc.describe(exc), seconds=seconds)
        outcome = oc.classify_exception(exc, names)
        if must_accept and outcome in (oc.REFUSED, oc.UNNAMED):
            outcome = oc.REFUSED_VALID
        return Answer(outcome, oc.describe(exc), seconds=seconds)
    seconds = time.perf_counter() - start
    nan_ok, nan_fields = job.nan_output_ok, frozenset[str]()
    if job.entry is not None:  # an inventory entry says which outputs may be non-finite
        entry = inv.ENTRIES[job.entry]
        nan_ok, nan_fields = entry.nan_output is not None, entry.nan_fields
    outcome, detail = oc.classify_result(
        result, must_refuse=must_refuse, nan_output_ok=nan_ok, nan_fields=nan_fields
    )
    return Answer(outcome, detail, result if job.want_result else None, seconds)


def _read(stream: BinaryIO) -> Any:
    head = stream.read(_HEADER.size)
    if len(head) < _HEADER.size:
        raise EOFError
    (n,) = _HEADER.unpack(head)
    return pickle.loads(stream.read(n))


def _write(stream: BinaryIO, obj: Any) -> None:
    data = pickle.dumps(obj)
    stream.write(_HEADER.pack(len(data)) + data)
    stream.flush()


def main(prewarm: bool = True) -> None:
    """Worker loop: answer jobs until stdin closes. ``prewarm`` builds every valid example first, so that
    no job's time limit pays for the shared scenario (simulated RINEX files, orbits)."""
    inp = os.fdopen(os.dup(0), "rb")
    out = os.fdopen(os.dup(1), "wb")
    null = os.open(os.devnull, os.O_RDWR)
    for fd in (0, 1, 2):
        os.dup2(null, fd)
    from . import inventory as inv
    from . import scenario

    # hostile text values ("abc") reach file-writing functions as relative paths: keep them out of the tree
    os.chdir(scenario.folder())
    if prewarm:
        shared = (scenario.rinex_read, scenario.phases, scenario.spaceborne, scenario.gyro)
        for build in shared:
            build()
        for entry in inv.ENTRIES.values():
            entry.build()
    _write(out, "ready")
    while True:
        try:
            job = _read(inp)
        except EOFError:
            return
        try:
            answer = _execute(job)
        except Exception as exc:  # a fault of the harness itself (e.g. an unpicklable value)
            answer = Answer(oc.HARNESS, oc.describe(exc))
        try:
            _write(out, answer)
        except (pickle.PicklingError, TypeError, AttributeError) as exc:
            _write(out, Answer(answer.outcome, f"{answer.detail} (result not picklable: {exc})"))


class Pool:
    """One worker subprocess at a time, restarted after an abort or a hang."""

    def __init__(self, hang_s: float = HANG_S, *, prewarm: bool = True) -> None:
        self.hang_s = hang_s
        self.prewarm = prewarm
        self.proc: subprocess.Popen[bytes] | None = None
        self.restarts = 0

    def _start(self) -> subprocess.Popen[bytes]:
        code = (
            f"import sys; sys.path.insert(0, {str(TESTS_DIR)!r}); "
            f"from hostile.worker import main; main({self.prewarm})"
        )
        env = {**os.environ, "PYTHONFAULTHANDLER": ""}
        proc = subprocess.Popen(
            [sys.executable, "-c", code], stdin=subprocess.PIPE, stdout=subprocess.PIPE, env=env
        )
        assert proc.stdout is not None
        ready, _, _ = select.select([proc.stdout], [], [], 300.0)
        if not ready or _read(proc.stdout) != "ready":
            proc.kill()
            raise RuntimeError("hostile worker did not start")
        return proc

    def run(self, job: Job) -> Answer:
        if self.proc is None:
            self.proc = self._start()
        proc = self.proc
        assert proc.stdin is not None and proc.stdout is not None
        start = time.perf_counter()
        try:
            _write(proc.stdin, job)
            ready, _, _ = select.select([proc.stdout], [], [], self.hang_s)
            if ready:
                return _read(proc.stdout)
            died = False
        except (BrokenPipeError, EOFError):
            died = True
        elapsed = time.perf_counter() - start
        self.proc = None
        self.restarts += 1
        try:
            # the pipe closes a moment before the process is reaped: wait for its status
            rc = proc.wait(timeout=5.0) if died else None
        except subprocess.TimeoutExpired:
            rc = None
        if rc is None:
            proc.kill()
            proc.wait()
            return Answer(oc.HANG, f"no answer in {self.hang_s:.0f} s", seconds=elapsed)
        what = f"killed by {signal.Signals(-rc).name}" if rc < 0 else f"exited with status {rc}"
        return Answer(oc.ABORT, what, seconds=elapsed)

    def close(self) -> None:
        if self.proc is not None:
            assert self.proc.stdin is not None
            self.proc.stdin.close()
            try:
                self.proc.wait(timeout=10)
            except subprocess.TimeoutExpired:
                self.proc.kill()
                self.proc.wait()
            self.proc = None
