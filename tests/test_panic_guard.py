"""The panic boundary of the Rust bindings (``rust/py/src/guard.rs``).

A panic, which the core is written never to raise, reaches Python as :class:`gnssatt.errors.InternalError`
(an ``Exception``), never as pyo3's ``PanicException`` (a ``BaseException`` that ``except Exception``
misses), whichever thread panicked; and every entry point of the bindings carries the guard.
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest

from gnssatt import _core
from gnssatt.errors import GnssattError, InternalError

BINDINGS = Path(__file__).resolve().parents[1] / "rust" / "py" / "src"


@pytest.mark.parametrize("in_worker", [False, True], ids=["calling-thread", "worker-thread"])
def test_a_panic_surfaces_as_internal_error(in_worker: bool) -> None:
    try:
        _core._panic_for_tests("index 7 out of bounds", in_worker=in_worker)
    except Exception as exc:  # the point: an ordinary `except Exception` catches it
        assert isinstance(exc, InternalError)
        assert isinstance(exc, GnssattError)
        assert "_panic_for_tests" in str(exc)
        assert "index 7 out of bounds" in str(exc)
    else:
        pytest.fail("the test hook returned without panicking")


def test_the_interpreter_goes_on_after_a_panic() -> None:
    with pytest.raises(InternalError):
        _core._panic_for_tests("first")
    # the module is usable afterwards, on both paths
    with pytest.raises(InternalError, match="second"):
        _core._panic_for_tests("second", in_worker=True)
    assert _core.lambda_bootstrap_success_rate(np.array([[0.01]])) == pytest.approx(1.0)


def test_every_entry_point_is_guarded() -> None:
    # `#[guard]` must stand directly above each `#[pyfunction]` and `#[pymethods]` of the bindings
    # (attributes between them are allowed); a new entry point without it fails here.
    entry = re.compile(r"^\s*#\[(?:pyo3::)?(pyfunction|pymethods)\]")
    unguarded, guarded = [], 0
    for path in sorted(BINDINGS.glob("*.rs")):
        lines = path.read_text().splitlines()
        for i, line in enumerate(lines):
            if entry.match(line):
                above = lines[i - 1].strip() if i else ""
                if above in ("#[guard]", "#[crate::guard::guard]"):
                    guarded += 1
                else:
                    unguarded.append(f"{path.name}:{i + 1}")
    assert unguarded == []
    assert guarded >= 40  # the scan saw the bindings (47 entry points and blocks when written)
