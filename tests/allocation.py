"""How much memory a call allocates, the measure of "refused before the work" in the limit tests: a refusal is
a check and allocates nothing of the work's size, where doing the work (or copying its inputs) would.
Counted with tracemalloc, which sees numpy's buffers; never timed."""

from __future__ import annotations

import tracemalloc
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass


@dataclass
class Peak:
    """The most memory traced at once inside the block, bytes (set when the block ends)."""

    bytes: int = 0


@contextmanager
def traced_peak() -> Iterator[Peak]:
    """Trace allocations inside the block; the yielded :class:`Peak` holds their peak once it ends."""
    peak = Peak()
    tracemalloc.start()
    try:
        yield peak
    finally:
        peak.bytes = tracemalloc.get_traced_memory()[1]
        tracemalloc.stop()
