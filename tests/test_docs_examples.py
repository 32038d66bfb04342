"""The worked examples of the documentation (``docs/examples/``) run, print what their pages show, draw
labelled figures, and compute what an independent method computes."""

from __future__ import annotations

import contextlib
import functools
import io
import itertools
import re
import runpy
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from scipy.stats import chi2

EXAMPLES = Path(__file__).resolve().parents[1] / "docs" / "examples"
PAGES = {
    "lambda_fix.py": "lambda.md",
    "matrix_method.py": "matrix_method.md",
    "ml_grid.py": "ml_grid.md",
    "magnetometer_yaw.py": "magnetometer_yaw.md",
    "gyro_gnss.py": "gyro_gnss.md",
    "orbit_filter.py": "orbit_filter.md",
    "tumbling_fit.py": "tumbling_fit.md",
    "recorded_data.py": "recorded_data.md",
}
# Examples whose page draws a figure in the docs build (``.. plot::``), from the script's ``figure(found)``.
PLOTTED = tuple(PAGES)


@functools.cache
def _run(script: str) -> tuple[dict[str, Any], str, dict[str, Any]]:
    """The script's namespace, what its ``main()`` printed and what it returned: each example runs once per
    test session (its ``__main__`` block only adds the figure, which the docs build draws)."""
    example = runpy.run_path(str(EXAMPLES / script), run_name="docs_example")
    printed = io.StringIO()
    with contextlib.redirect_stdout(printed):
        found = example["main"]()
    return example, printed.getvalue(), found


def _page_output(page: Path) -> str:
    """The ``text`` block of an example page: the output the page claims the script prints."""
    blocks = re.findall(r"^```text\n(.*?)^```", page.read_text(), flags=re.MULTILINE | re.DOTALL)
    assert len(blocks) == 1, page
    return blocks[0]


def test_every_example_has_a_page() -> None:
    assert sorted(PAGES) == sorted(p.name for p in EXAMPLES.glob("*.py"))
    for script in PLOTTED:
        assert f".. plot:: examples/{script}" in (EXAMPLES / PAGES[script]).read_text()


@pytest.mark.slow
@pytest.mark.parametrize("script", sorted(PAGES))
def test_page_shows_the_scripts_output(script: str) -> None:
    _, printed, _ = _run(script)
    assert printed == _page_output(EXAMPLES / PAGES[script])


# A unit after a comma ("time, s"; "NEES, dimensionless"), optionally followed by a remark in parentheses.
UNIT = re.compile(r", (deg|deg/h|deg/s|s|min|m|mm|m/s|nT|rad|cycles\^2|count|dimensionless)( \(.*\))?$")
# A tick label that is a number (matplotlib writes minus signs as U+2212).
NUMBER = re.compile(r"[\u2212\-+]?[\d.]+(e[\u2212\-+]?\d+)?")


@pytest.mark.slow
@pytest.mark.parametrize("script", PLOTTED)
def test_figure_has_a_title_and_units_on_every_axis(script: str) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    example, _, found = _run(script)
    fig = example["figure"](found)
    try:
        fig.canvas.draw()  # tick labels exist once drawn
        assert fig.get_suptitle()
        for ax in fig.axes:
            assert ax.get_title(), script
            assert UNIT.search(ax.get_ylabel()), ax.get_ylabel()
            # Shared x axes carry the label on the bottom panel only; an axis of named categories (bars of
            # candidates) is labelled but has no unit.
            ticks = [t.get_text() for t in ax.get_xticklabels() if t.get_text()]
            categories = bool(ticks) and not any(NUMBER.fullmatch(t) for t in ticks)
            if ax.get_subplotspec().is_last_row():
                assert ax.get_xlabel(), script
            if ax.get_xlabel() and not categories:
                assert UNIT.search(ax.get_xlabel()), ax.get_xlabel()
            # Every series is named in a legend, unless the axis' categories name them.
            legend = ax.get_legend()
            assert categories or (legend is not None and legend.get_texts()), script
    finally:
        plt.close(fig)


def test_lambda_example_is_the_brute_force_ils_solution() -> None:
    example, _, found = _run("lambda_fix.py")
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
    _, _, found = _run("matrix_method.py")
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
    _, _, found = _run("recorded_data.py")
    fixed, error_mm = found["fixed"], found["error_mm"]
    # RTKLIB's static L1 + L2 solution is the reference nobody here computed: a wrong integer moves an epoch
    # by decimetres (an L1 cycle is 19 cm), so every fixed epoch within 5 cm of it is a right fix.
    assert fixed.sum() >= 0.9 * fixed.size
    assert np.all(error_mm[fixed] < 50.0)


def test_ml_grid_errors_follow_the_small_noise_covariance() -> None:
    _, _, found = _run("ml_grid.py")
    errors, sandwich, bound = found["errors"], found["sandwich"], found["bound"]
    n = len(errors)
    # No lobe jump: the main lobe of a 0.71 m array at L1 is about 15 deg wide; the largest error is 0.83 deg.
    assert np.max(np.linalg.norm(errors, axis=1)) < np.radians(3.0)
    # Unbiased: each component's mean within 4 standard errors of zero.
    assert np.all(np.abs(errors.mean(axis=0)) < 4.0 * np.sqrt(np.diag(sandwich) / n))
    # The trace of the sample covariance against the sandwich's. For Gaussian errors the sample trace has
    # the relative spread sqrt(2 sum(l^2) / n) / sum(l) (l the eigenvalues): allow four of them.
    eig = np.linalg.eigvalsh(sandwich)
    spread = np.sqrt(2.0 * np.sum(eig**2) / n) / np.sum(eig)
    ratio = np.trace(errors.T @ errors / n) / np.trace(sandwich)
    assert abs(ratio - 1.0) < 4.0 * spread, (ratio, spread)
    # The prediction obeys the Cramer-Rao bound (sandwich - bound positive semi-definite).
    assert np.linalg.eigvalsh(sandwich - bound).min() > -1e-12 * np.trace(bound)


def test_magnetometer_yaw_noise_follows_first_order_propagation() -> None:
    example, _, found = _run("magnetometer_yaw.py")
    assert found["exact_deg"] < 1e-9
    draws = example["DRAWS"]
    ratio = (found["sigma"] / found["predicted"]) ** 2
    # A sample variance of n Gaussian draws has the relative spread sqrt(2 / n) (7 % for 400): the mean of
    # the 72 independent ratios within 4 of its standard errors, each ratio within 5 of them.
    spread = np.sqrt(2.0 / draws)
    assert abs(ratio.mean() - 1.0) < 4.0 * spread / np.sqrt(ratio.size)
    assert np.all(np.abs(ratio - 1.0) < 5.0 * spread)
    # The point of the example: the polar passes are an order of magnitude worse.
    assert found["sigma"].max() > 10.0 * found["sigma"].min()


def test_gyro_gnss_settles_at_the_closed_form_steady_state() -> None:
    _, _, found = _run("gyro_gnss.py")
    _, after = found["closed_form"]
    final = np.diag(found["covariance"][-1])[:3]
    # Knowing the drift could only lower the variance: the closed form is a lower bound. The drift sigma
    # left at 600 s (0.75 deg/h = 3.6e-6 rad/s) over the filter's memory of about 10 fixes (gain
    # sqrt(q / r) = 0.1) adds about (3.6e-5 rad)^2, 2 % of the 7.2e-8 rad^2: allow 3 %.
    assert np.all(final >= after * (1.0 - 1e-9))
    assert np.all(final <= 1.03 * after)
    # The true errors: RMS over the second half and three axes. Consecutive errors are correlated over
    # about 10 fixes, so 300 s x 3 axes hold about 90 independent ones: a 7.5 % spread; allow 25 %.
    errors = found["errors"][found["steady"], :3]
    rms = np.sqrt(np.mean(errors**2))
    assert abs(rms / np.sqrt(after) - 1.0) < 0.25
    # Drift errors within 4 of the filter's sigmas at the end.
    drift_sigma = np.sqrt(np.diag(found["covariance"][-1])[3:])
    assert np.all(np.abs(found["errors"][-1, 3:]) < 4.0 * drift_sigma)


def test_orbit_filter_is_chi_square_consistent() -> None:
    example, _, found = _run("orbit_filter.py")
    runs = example["RUNS"]
    # Final-epoch NEES of independent runs: chi-square with 6 runs degrees of freedom for a consistent
    # filter (a linearised one, to within the linearisation error); two-sided 99.9 %.
    low, high = chi2.ppf([0.0005, 0.9995], 6 * runs)
    assert low < found["final_nees_sum"] < high
    # Innovations of a consistent filter are white: their normalised squares sum to chi-square(dof).
    low, high = chi2.ppf([0.0005, 0.9995], found["nis_dof"])
    assert low < found["nis_sum"] < high


def _brute_force_margin(visible: np.ndarray, invisible: np.ndarray, n: int = 200_000) -> np.ndarray:
    """The largest smallest signed margin ``min(min_V a . g, min_H -a . g)`` over ``n`` directions of a
    Fibonacci sphere (spacing sqrt(4 pi / n) = 0.45 deg), and the direction reaching it."""
    k = np.arange(n) + 0.5
    z = 1.0 - 2.0 * k / n
    phi = np.pi * (1.0 + np.sqrt(5.0)) * k
    r = np.sqrt(1.0 - z * z)
    a = np.column_stack([r * np.cos(phi), r * np.sin(phi), z])
    margin = np.min(a @ np.vstack([visible, -invisible]).T, axis=1)
    best = int(np.argmax(margin))
    return margin[best], a[best]


@pytest.mark.slow
def test_tumbling_fit_axes_are_the_brute_force_margin_optimum() -> None:
    import gnssatt
    from gnssatt.attitude import dynamics as tumble

    example, _, found = _run("tumbling_fit.py")
    signed = []
    for k in range(0, len(found["t"]), 30):
        visible, invisible = found["sets"][k]
        axis = found["measured"][k]
        margin = np.min(np.vstack([visible, -invisible]) @ axis)
        best_margin, best_axis = _brute_force_margin(visible, invisible)
        # No direction of the sphere does better than the library's axis (beyond the grid's resolution:
        # a margin is a cosine, so 0.45 deg of spacing moves it by at most 0.008), and the two agree.
        assert margin >= best_margin - 1e-3, k
        assert np.degrees(np.arccos(min(1.0, axis @ best_axis))) < 2.0, k
        signed.append(margin)
    assert min(signed) > 0.0  # every axis satisfies every visibility constraint
    # The fit's objective (sum of squared axis differences) is no worse than the true state's.
    t, measured = found["t"], found["measured"]
    model = gnssatt.TumbleModel.circular(example["ALTITUDE_M"])
    truth_cost = np.sum((tumble.propagate_axes(example["TRUTH"], t, model) - measured) ** 2)
    assert found["fit"].cost <= truth_cost * (1.0 + 1e-6)
    # Axes 7 deg off at single epochs pin the initial rates to a few hundredths of a deg/s.
    assert np.all(np.abs(found["rate_error_deg_s"]) < 0.1)
