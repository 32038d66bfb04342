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
