"""One worker subprocess for the whole hostile session (``hostile.worker.Pool``)."""

from __future__ import annotations

from collections.abc import Iterator

import pytest

from .worker import Pool


@pytest.fixture(scope="session")
def pool() -> Iterator[Pool]:
    p = Pool()
    yield p
    p.close()


def report(failures: list[str]) -> str:
    return f"{len(failures)} contract failure(s):\n" + "\n".join(failures)
