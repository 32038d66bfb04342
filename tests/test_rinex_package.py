"""``gnssatt.rinex``'s public names: each name of ``__all__`` resolves, and each name of the deleted Python
prototype (issue 16) fails at import with a message naming what replaces it."""

from __future__ import annotations

import importlib

import pytest

import gnssatt.rinex as rinex


@pytest.mark.parametrize("name", rinex.__all__)
def test_public_names_resolve(name: str) -> None:
    assert getattr(rinex, name) is not None and name in dir(rinex)


@pytest.mark.parametrize(
    ("name", "replacement"),
    [
        ("align_receivers", "session_input"),
        ("Aligned", "session_input"),
        ("carrier_frequency_hz", "slot_frequency_hz"),
        ("static_baseline", "attitude_from_rinex"),
        ("StaticBaseline", "attitude_from_rinex"),
        ("epoch_baselines", "attitude_from_rinex"),
        ("EpochBaselines", "attitude_from_rinex"),
        ("satellite_states", "gnss_satellite_states"),
        ("transmit_states", "gnss_transmit_states"),
        ("single_point_positions", "attitude_from_rinex"),
        ("PointSolution", "attitude_from_rinex"),
    ],
)
def test_prototype_names_say_what_replaces_them(name: str, replacement: str) -> None:
    with pytest.raises(
        ImportError, match=rf"gnssatt\.rinex\.{name} belonged to the Python prototype.*{replacement}"
    ):
        exec(f"from gnssatt.rinex import {name}", {})  # the import statement itself is tested
    with pytest.raises(ImportError, match=replacement):
        getattr(rinex, name)
    assert name not in rinex.__all__


@pytest.mark.parametrize("module", ["spp", "ephemeris", "align", "epoch_lambda", "baseline", "iono"])
def test_prototype_modules_are_gone(module: str) -> None:
    with pytest.raises(ModuleNotFoundError):
        importlib.import_module(f"gnssatt.rinex.{module}")


def test_unknown_names_stay_attribute_errors() -> None:
    assert not hasattr(rinex, "no_such_name")
