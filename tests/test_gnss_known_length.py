"""A known antenna separation in baseline mode (``baseline_length_m``, ``--baseline-length``): the
length-constrained fix of ``rust/core/src/gnss/rtk/known_length.rs``, checked against a simulated truth and
against RTKLIB 2.4.3's static solution of the shipped GEONET pair; bad lengths refused by name."""

from __future__ import annotations

import warnings
from functools import cache
from pathlib import Path

import numpy as np
import pytest

from gnssatt.cli import main
from gnssatt.data import geonet_dir
from gnssatt.errors import InvalidInputError
from gnssatt.gnss.attitude import AttitudeSeries, attitude_from_rinex

#: RTKLIB 2.4.3's static L1+L2 solution of the GEONET pair, ENU at the base's header position, m
#: (benches/python/rtklib_compare.py; the same reference as benches/python/success_rate_gate.py).
GEONET_REFERENCE_ENU_M = np.array([953.6732, -3196.1396, 4.6497])
GEONET_BASE_M = (-3976219.5082, 3382372.5671, 3652512.9849)


@cache
def _geonet_l1(length_m: float | None) -> AttitudeSeries:
    d = geonet_dir()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return attitude_from_rinex(
            [d / "07590920.05o", d / "30400920.05o"],
            [d / "07590920.05n", d / "30400920.05n"],
            method="lambda",
            motion="moving",
            systems="G",
            frequencies=1,
            base_position_m=GEONET_BASE_M,
            baseline_length_m=length_m,
        )


@pytest.mark.slow
def test_geonet_l1_single_epoch_with_the_length_fixes_only_right() -> None:
    """GPS L1 single epochs (7 satellites) with the length of RTKLIB's static L1+L2 solution: without it the
    gate fixes few (20 of 120 measured, with the noise scale on code and phase together), with it more (28
    measured; RTKLIB's instantaneous mode 24 %); every fix either way within 5 cm of RTKLIB's static solution
    (a wrong L1 integer moves a 3.3 km baseline by centimetres to decimetres), the constrained ones also
    within 1 cm of the length given."""
    length = float(np.linalg.norm(GEONET_REFERENCE_ENU_M))
    plain, known = _geonet_l1(None), _geonet_l1(length)
    assert known.solved.all() and len(known.time) == 120
    plain_fixed = plain.fixed.astype(bool)
    plain_err = np.linalg.norm(plain.baselines_enu_m[plain_fixed, 0] - GEONET_REFERENCE_ENU_M, axis=1)
    assert np.all(plain_err < 0.05), plain_err
    fixed = known.fixed.astype(bool)
    assert fixed.sum() > plain_fixed.sum(), (fixed.sum(), plain_fixed.sum())
    assert fixed.sum() >= 20, fixed.sum()
    err = np.linalg.norm(known.baselines_enu_m[fixed, 0] - GEONET_REFERENCE_ENU_M, axis=1)
    assert np.all(err < 0.05), err
    lengths = np.linalg.norm(known.baselines_enu_m[fixed, 0], axis=1)
    assert np.all(np.abs(lengths - length) < 0.01), lengths - length


@pytest.mark.slow
@pytest.mark.parametrize("length_m", [1.0, 3.0])
def test_simulated_known_length_fixes_are_right_and_on_the_sphere(tmp_path: Path, length_m: float) -> None:
    """Simulated single epochs of GPS + Galileo L1 (simulate_gnss_rinex: troposphere, broadcast ionosphere,
    code 0.3 m, phase 2 mm; 6 GPS and 7 Galileo satellites) with the true antenna distance, end to end
    through the files and the engine: as many epochs fixed as without the length (all 30 both ways,
    measured), every fix within 5 cm of the truth and its length within 1 cm of the one given (a
    constrained fix is put on the sphere, to the length's 2 mm sigma). With GPS L1 alone the simulator has
    6-7 satellites and neither way fixes an epoch at the defaults (docs/observation_engine.md)."""
    from gnssatt.sim.rinex_scenario import simulate_gnss_rinex

    sim = simulate_gnss_rinex(
        tmp_path, np.array([[0.0, 0, 0], [length_m, 0, 0]]), [30, 0, 0], systems="GE", frequencies=1,
        n_epochs=30, interval_s=60.0, start_s=7200.0, rng=3,
    )  # fmt: skip
    truth = np.asarray(sim.baselines_enu_m)[:, 0, :]
    runs = {}
    for given in (None, length_m):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            runs[given] = attitude_from_rinex(
                list(sim.obs_paths), sim.nav_path, method="lambda", motion="moving", systems="GE",
                frequencies=1, baseline_length_m=given,
            )  # fmt: skip
    known = runs[length_m]
    fixed = known.fixed.astype(bool)
    assert fixed.sum() >= max(runs[None].fixed.sum(), 25)
    assert np.all(np.linalg.norm(known.baselines_enu_m[fixed, 0] - truth[fixed], axis=1) < 0.05)
    assert np.all(np.abs(np.linalg.norm(known.baselines_enu_m[fixed, 0], axis=1) - length_m) < 0.01)


@pytest.mark.parametrize(
    ("length", "says"),
    [
        (0.0, "--baseline-length"),
        (-1.0, "--baseline-length"),
        ([1.0, 2.0], "expected baseline_length_m of shape (n_ant - 1,)"),
        (float("nan"), "baseline_length_m"),
    ],
)
def test_bad_lengths_are_refused_by_name(length: object, says: str) -> None:
    d = geonet_dir()
    with pytest.raises(InvalidInputError) as info:
        attitude_from_rinex(
            [d / "07590920.05o", d / "30400920.05o"], d / "07590920.05n", baseline_length_m=length
        )
    assert says in str(info.value)


def test_cli_option_range_and_attitude_mode_conflict(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    d = geonet_dir()
    argv = ["attitude", "--obs", str(d / "07590920.05o"), "--obs", str(d / "30400920.05o"), "--nav",
            str(d / "07590920.05n"), "--out", str(tmp_path / "r.csv"), "--no-plot"]  # fmt: skip
    assert main([*argv, "--baseline-length", "0"]) == 2
    assert (
        "argument --baseline-length: expected a number in [0.01, 10000.0], got 0.0" in capsys.readouterr().err
    )
    body = tmp_path / "body.txt"
    body.write_text("1 0 0\n0 0 1\n")
    three = [*argv[:5], "--obs", str(d / "30400920.05o"), *argv[5:]]
    assert main([*three, "--baselines", str(body), "--baseline-length", "1", "1"]) == 2
    assert "--baseline-length" in capsys.readouterr().err
