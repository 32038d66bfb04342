"""Receivers whose epoch labels differ (clocks not steered to the whole second): ``session_input`` moves each
file's code and phase onto the first file's labels, so that the engine computes every receiver's satellite
geometry at the instant it really sampled. Checked on the shipped GEONET pair (0759 -> 3040, labels up to
9 ms apart), against RTKLIB's static L1 + L2 solution, which nobody here wrote."""

from __future__ import annotations

from functools import cache

import numpy as np

from gnssatt.data import geonet_dir
from gnssatt.gnss.attitude import attitude_from_rinex
from gnssatt.gnss.session_input import session_input
from gnssatt.rinex import read_nav, read_obs

#: RTKLIB 2.4.3 static L1 + L2 solution of the pair (issue 16), ENU at the base, m.
RTKLIB_STATIC_ENU_M = np.array([953.6732, -3196.1396, 4.6497])


@cache
def _files() -> tuple[list, object]:
    d = geonet_dir()
    return [read_obs(d / "07590920.05o"), read_obs(d / "30400920.05o")], read_nav(d / "07590920.05n")


def test_files_with_equal_labels_are_left_unchanged() -> None:
    obs, _ = _files()
    s = session_input([obs[0], obs[0]], systems="G", frequencies=2)
    for a in (s.code_m, s.phase_cycles):
        np.testing.assert_array_equal(a[1], a[0])


def test_phase_minus_code_is_invariant_under_the_move() -> None:
    # lambda phase - code does not depend on the label (c delta - lambda f delta = 0): slip detectors on it
    # see the same series whichever file comes first.
    obs, _ = _files()
    ab = session_input(obs, systems="G", frequencies=1)
    ba = session_input(obs[::-1], systems="G", frequencies=1)
    lam = 299_792_458.0 / 1575.42e6
    mp_ab = lam * ab.phase_cycles[1, ..., 0] - ab.code_m[1, ..., 0]
    mp_ba = lam * ba.phase_cycles[0, ..., 0] - ba.code_m[0, ..., 0]
    ok = np.isfinite(mp_ab) & np.isfinite(mp_ba)
    assert ok.sum() > 500
    np.testing.assert_allclose(mp_ab[ok], mp_ba[ok], atol=1e-6)
    # and the moved code differs from the file's by c times the label difference (up to 9 ms: 2700 km)
    assert np.nanmax(np.abs(ab.code_m[1] - ba.code_m[0])) > 1e6


def test_static_l1_fixes_the_geonet_pair_at_rtklibs_baseline() -> None:
    # Without the move the rover's geometry was computed up to 9 ms off its sampling instant: the
    # double-difference phases drifted by ~35 L1 cycles over the hour and no epoch fixed (ratio 1.002).
    obs, nav = _files()
    s = attitude_from_rinex(obs, nav, method="lambda", motion="static", systems="G", frequencies=1)
    # Measured 118 of 120: epochs 57 and 59 hold a one-epoch arc of G08 (12 deg, loss of lock flagged at
    # the base) whose float is 0.4 cycles off an integer.
    assert np.asarray(s.fixed).sum() >= 118
    assert np.min(s.ratio) > 5.0
    # 3.3 km, L1 only vs RTKLIB's L1 + L2: measured 7 mm horizontal, 8 mm vertical apart.
    d = np.median(s.baselines_enu_m[:, 0], axis=0) - RTKLIB_STATIC_ENU_M
    assert np.hypot(d[0], d[1]) < 0.02 and abs(d[2]) < 0.03, d
