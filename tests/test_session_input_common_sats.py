"""``session_input`` refuses files that share no satellite with carrier phase at their common epochs (the
refusal now raised by its ``_common_sats``; before, by a check after it)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from gnssatt.errors import RinexError
from gnssatt.gnss.session_input import session_input
from gnssatt.rinex import read_obs, write_obs
from gnssatt.rinex.obs import RinexObs

T0 = np.datetime64("2024-03-01T10:00:00", "ns")


def _write(path: Path, sats: list[str]) -> RinexObs:
    t = T0 + np.arange(3) * np.timedelta64(1, "s")
    obs = {c: 2.0e7 + np.arange(3 * len(sats), dtype=float).reshape(3, len(sats)) for c in ("C1C", "L1C")}
    write_obs(path, t, sats, obs, approx_position_m=(1.0, 2.0, 3.0))
    return read_obs(path)


def test_files_with_disjoint_satellites_are_refused(tmp_path: Path) -> None:
    a = _write(tmp_path / "a.obs", ["G01", "G02"])
    b = _write(tmp_path / "b.obs", ["G03", "G04"])
    with pytest.raises(RinexError, match="no satellite of systems 'G' with carrier phase in every file"):
        session_input([a, b], systems="G", frequencies=1)


def test_one_shared_satellite_is_enough(tmp_path: Path) -> None:
    a = _write(tmp_path / "a.obs", ["G01", "G02"])
    b = _write(tmp_path / "b.obs", ["G02", "G04"])
    assert session_input([a, b], systems="G", frequencies=1).sats == ("G02",)
