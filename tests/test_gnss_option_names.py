"""The names of ``motion``, ``method`` and ``filter`` come from one table in the bindings
(``rust/py/src/gnss_options.rs``, exported as ``_core.GNSS_MOTIONS`` / ``GNSS_METHODS`` / ``GNSS_FILTERS``):
the CLI offers exactly those, and the Python API's types name the same; its ``--frequencies`` are 1 to
``_core.GNSS_MAX_FREQUENCIES`` (issue 29)."""

from __future__ import annotations

from typing import get_args

import pytest

from gnssatt import _core
from gnssatt.cli import main
from gnssatt.errors import InvalidInputError
from gnssatt.gnss.attitude import FilterName, MethodName, MotionName

TABLES = {
    "motion": (_core.GNSS_MOTIONS, MotionName),
    "method": (_core.GNSS_METHODS, MethodName),
    "filter": (_core.GNSS_FILTERS, FilterName),
}


def test_the_tables_are_the_documented_names() -> None:
    # written out: the names are the API (docs/observation_engine.md), not whatever the table holds
    assert _core.GNSS_MOTIONS == ("static", "moving")
    assert _core.GNSS_METHODS == ("auto", "ml", "lambda")
    assert _core.GNSS_FILTERS == ("static", "kinematic", "velocity")


@pytest.mark.parametrize("option", TABLES)
def test_python_types_name_the_engines_table(option: str) -> None:
    names, literal = TABLES[option]
    assert get_args(literal) == names


@pytest.mark.parametrize("option", TABLES)
def test_every_name_is_accepted(option: str) -> None:
    for name in TABLES[option][0]:
        assert "GnssOptions" in repr(_core.GnssOptions(**{option: name}))


@pytest.mark.parametrize(
    ("option", "message"),
    [
        ("motion", "expected motion 'static' or 'moving', got \"walking\""),
        ("method", "expected method 'auto', 'ml' or 'lambda', got \"walking\""),
        ("filter", "--filter: expected 'static', 'kinematic' or 'velocity', got \"walking\""),
    ],
)
def test_unknown_name_is_refused_naming_the_choices(option: str, message: str) -> None:
    with pytest.raises(InvalidInputError) as info:
        _core.GnssOptions(**{option: "walking"})
    assert str(info.value) == message


@pytest.mark.parametrize("option", TABLES)
def test_cli_offers_the_engines_names(option: str, capsys: pytest.CaptureFixture[str]) -> None:
    argv = ["attitude", "--obs", "a.o", "--obs", "b.o", "--nav", "n.n", f"--{option}", "walking"]
    assert main(argv) == 2
    offered = ", ".join(f"'{name}'" for name in TABLES[option][0])
    expected = f"argument --{option}: invalid choice: 'walking' (choose from {offered})"
    assert expected in capsys.readouterr().err


@pytest.mark.parametrize("command", ["attitude", "position"])
def test_cli_frequencies_are_the_engines_slots(command: str, capsys: pytest.CaptureFixture[str]) -> None:
    assert _core.GNSS_MAX_FREQUENCIES == 3  # L1, L2, L5 and their kin (docs/observation_engine.md)
    assert main([command, "--obs", "a.o", "--nav", "n.n", "--frequencies", "4"]) == 2
    expected = "argument --frequencies: invalid choice: '4' (choose from '1', '2', '3', 'all')"
    assert expected in capsys.readouterr().err
