"""``gnssatt.rinex``'s public names: each name of ``__all__`` resolves, and each name of the deleted Python
prototype (issue 16) fails at import with a message naming what replaces it."""

from __future__ import annotations

import importlib

import pytest

import gnssatt.rinex as rinex


@pytest.mark.parametrize("name", rinex.__all__)
def test_public_names_resolve(name: str) -> None:
    assert getattr(rinex, name) is not None and name in dir(rinex)


@pytest.mark.parametrize("name", ["align_receivers", "static_baseline", "satellite_states", "PointSolution"])
def test_prototype_names_are_gone(name: str) -> None:
    # the deleted Python prototype of the observation engine (CHANGELOG.md): an ordinary ImportError
    with pytest.raises(ImportError, match=name):
        exec(f"from gnssatt.rinex import {name}", {})
    assert name not in rinex.__all__


@pytest.mark.parametrize("module", ["spp", "ephemeris", "align", "epoch_lambda", "baseline", "iono"])
def test_prototype_modules_are_gone(module: str) -> None:
    with pytest.raises(ModuleNotFoundError):
        importlib.import_module(f"gnssatt.rinex.{module}")


def test_unknown_names_stay_attribute_errors() -> None:
    assert not hasattr(rinex, "no_such_name")
