"""The experiments' JSON report: strict JSON even when a statistic is undefined."""

from __future__ import annotations

import json
import math

from gnssatt.experiments.report import write_report


def test_nan_and_inf_statistics_are_written_as_null(tmp_path):
    doc = write_report(
        tmp_path,
        "demo",
        {"rms_deg": 0.5, "bias_deg": None},
        {"rms_deg": math.nan, "by_axis": [1.0, math.inf, -math.inf], "nested": {"x": math.nan}},
        runs=1,
        seed=0,
    )
    text = (tmp_path / "demo.json").read_text()
    # strict parsing: Python's json refuses NaN/Infinity tokens with parse_constant raising
    loaded = json.loads(text, parse_constant=lambda token: (_ for _ in ()).throw(ValueError(token)))
    assert loaded["measured"] == {"rms_deg": None, "by_axis": [1.0, None, None], "nested": {"x": None}}
    assert loaded["paper"] == {"rms_deg": 0.5, "bias_deg": None}
    assert doc["measured"]["rms_deg"] is None


def test_an_unknown_experiment_is_a_value_error_naming_the_parameter_and_the_known_names():
    import pytest

    from gnssatt.errors import InvalidInputError, UnknownNameError
    from gnssatt.experiments import EXPERIMENTS, get

    with pytest.raises(UnknownNameError) as info:
        get("matrix method")
    message = str(info.value)
    # a ValueError of the package (the house rule) that still answers ``except KeyError`` (a look-up)
    assert isinstance(info.value, InvalidInputError) and isinstance(info.value, KeyError)
    # str() reads as a sentence, not as KeyError's quoted repr
    assert message.startswith("name: unknown experiment 'matrix method'")
    assert all(name in message for name in EXPERIMENTS)


def test_each_quantity_gets_a_tolerance_and_a_verdict(tmp_path):
    from gnssatt.experiments.report import format_table

    doc = write_report(
        tmp_path,
        "matrix-method",
        {"a_deg": 1.0, "b_deg": None, "c": "close (no numbers)", "d_deg": 2.0, "e_deg": 1.0, "f_deg": 1.0},
        {"a_deg": 5.0, "b_deg": 3.0, "c": 1.0, "d_deg": 2.1, "e_deg": None, "f_deg": 0.4},
        runs=3,
        seed=1,
        tolerance={"a_deg": 2.0, "d_deg": 1.1, "f_deg": 2.0},
        unavailable={"e_deg": "needs the igrf extra"},
    )
    assert doc["verdict"] == {
        "a_deg": "differs",  # 5 > 1 x 2
        "b_deg": "no paper number",
        "c": "see results page",
        "d_deg": "agrees",  # 2 / 1.1 <= 2.1 <= 2 x 1.1
        "e_deg": "not computed",
        "f_deg": "differs",  # 0.4 < 1 / 2
    }
    table = format_table(doc)
    header = table.splitlines()[1].split()
    assert header == ["quantity", "paper", "measured", "tolerance", "verdict"]
    assert "needs the igrf extra" in table and "x1.1" in table
    assert table.splitlines()[-1] == "why these numbers: docs/results/matrix_method.md"


def test_the_commit_is_the_checkouts_or_none(tmp_path):
    import re
    from pathlib import Path

    import gnssatt.experiments.report as report

    doc = write_report(tmp_path, "demo", {}, {"x": 1.0}, runs=1, seed=0)
    package = Path(report.__file__).resolve().parents[1]
    root = Path(__file__).resolve().parents[1]
    in_checkout = package == root / "python" / "gnssatt" and (root / ".git").exists()
    if in_checkout:
        assert re.fullmatch("[0-9a-f]{40}", doc["commit"])
    else:  # an installed wheel: no commit rather than that of a checkout it happens to sit in
        assert doc["commit"] is None
