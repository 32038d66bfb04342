"""The worked examples of the documentation (``docs/examples/``) run, print what their pages show, and
compute what an independent method computes."""

from __future__ import annotations

import itertools
import re
import runpy
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

EXAMPLES = Path(__file__).resolve().parents[1] / "docs" / "examples"


def _page_output(page: Path) -> str:
    """The ``text`` block of an example page: the output the page claims the script prints."""
    blocks = re.findall(r"^```text\n(.*?)^```", page.read_text(), flags=re.MULTILINE | re.DOTALL)
    assert len(blocks) == 1, page
    return blocks[0]


@pytest.mark.parametrize(
    ("script", "page"),
    [
        ("lambda_fix.py", "lambda.md"),
        ("matrix_method.py", "matrix_method.md"),
        ("recorded_data.py", "recorded_data.md"),
    ],
)
def test_page_shows_the_scripts_output(script: str, page: str) -> None:
    res = subprocess.run(
        [sys.executable, str(EXAMPLES / script)], capture_output=True, text=True, timeout=120
    )
    assert res.returncode == 0, res.stderr
    assert res.stdout == _page_output(EXAMPLES / page)


def test_lambda_example_is_the_brute_force_ils_solution() -> None:
    example = runpy.run_path(str(EXAMPLES / "lambda_fix.py"), run_name="docs_example")
    found = example["main"]()
    a, q = example["FLOAT"], example["COVARIANCE"]
    # Every integer vector within 6 cycles of the rounded float one. Outside that box |a - z| > 6, so the
    # squared norm r @ inv(Q) @ r >= |r|^2 / lambda_max(Q) > 36 / 12.9 = 2.8 exceeds the second best's: the
    # two best lie inside.
    assert np.max(np.linalg.eigvalsh(q)) < 36 / found["norms"][1]
    centre = np.rint(a).astype(np.int64)
    grid = np.array(list(itertools.product(range(-6, 7), repeat=3))) + centre
    r = a - grid
    norms = np.einsum("ij,ij->i", r, np.linalg.solve(q, r.T).T)
    best = np.argsort(norms)[:2]
    np.testing.assert_array_equal(found["fixed"], grid[best])
    np.testing.assert_allclose(found["norms"], norms[best], rtol=1e-12)
    # The example's point: rounding is not the ILS solution.
    assert not np.array_equal(found["rounded"], grid[best[0]])
    # The decorrelating transformation is unimodular and leaves the integer lattice as it was.
    z = found["z"]
    assert round(abs(np.linalg.det(z))) == 1


def test_matrix_method_example_recovers_the_attitude_it_was_built_from() -> None:
    example = runpy.run_path(str(EXAMPLES / "matrix_method.py"), run_name="docs_example")
    found = example["main"]()
    # Noise-free range differences are b_i . (A s_j) exactly: the attitude is the truth to rounding.
    truth = found["exact_truth"].as_matrix()
    np.testing.assert_allclose(found["exact"].rotation.as_matrix(), truth, atol=1e-12)
    # 2 mm on a 1 m baseline is 0.11 deg per range difference; with this seed the worst of 200 trials is off
    # by 0.45 deg (svd) and 0.35 deg (ml). A wrong or mirrored solution is tens of degrees off: 1.2 deg (ten
    # times the per-difference angle) separates the two.
    for errors in found["errors"].values():
        assert len(errors) == 200
        assert max(errors) < 1.2


def test_recorded_data_fixes_agree_with_rtklib() -> None:
    example = runpy.run_path(str(EXAMPLES / "recorded_data.py"), run_name="docs_example")
    found = example["main"]()
    fixed, error_mm = found["fixed"], found["error_mm"]
    # RTKLIB's static L1 + L2 solution is the reference nobody here computed: a wrong integer moves an epoch
    # by decimetres (an L1 cycle is 19 cm), so every fixed epoch within 5 cm of it is a right fix.
    assert fixed.sum() >= 0.9 * fixed.size
    assert np.all(error_mm[fixed] < 50.0)
