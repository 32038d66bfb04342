"""The parsing and metrics of ``benches/python/rtklib_compare.py`` on hand-written files (no RTKLIB
needed), so that the comparison cannot silently misread either tool's output."""

from __future__ import annotations

import importlib.util
import sys
from pathlib import Path

import numpy as np
import pytest

SCRIPT = Path(__file__).resolve().parents[1] / "benches" / "python" / "rtklib_compare.py"


@pytest.fixture(scope="module")
def rc():  # type: ignore[no-untyped-def]
    spec = importlib.util.spec_from_file_location("rtklib_compare", SCRIPT)
    assert spec is not None and spec.loader is not None
    mod = importlib.util.module_from_spec(spec)
    sys.modules["rtklib_compare"] = mod  # dataclasses look their module up
    spec.loader.exec_module(mod)
    yield mod
    del sys.modules["rtklib_compare"]


# Rows as rnx2rtkp 2.4.3 writes them (out-solformat=enu, out-timeform=tow), CRLF line ends included. The epoch
# 2005-04-02 00:00:00 GPST is week 1316, 518400 s: RTKLIB's own header line for the GEONET files says so.
POS = (
    "% program   : RTKLIB ver.2.4.3\r\n"
    "% obs start : 2005/04/02 00:00:00.0 GPST (week1316 518400.0s)\r\n"
    "%  GPST          e-baseline(m)  n-baseline(m)  u-baseline(m)   Q  ns   sde(m)   sdn(m)   sdu(m)  sden(m)"
    "  sdnu(m)  sdue(m) age(s)  ratio\r\n"
    "1316 518400.000       953.6750     -3196.1387         4.6556   1   7   0.0044   0.0058   0.0136   0.0022"
    "  -0.0055  -0.0047   0.00   24.9\r\n"
    "1316 518430.000       953.7750     -3196.1387         4.6556   1   7   0.0044   0.0058   0.0136   0.0022"
    "  -0.0055  -0.0047   0.00    3.5\r\n"
    "1316 518460.000       954.6750     -3195.1387         5.6556   2   6   0.0400   0.0500   0.1000   0.0022"
    "  -0.0055  -0.0047   0.00    1.2\r\n"
)
REF_ENU = np.array([953.6750, -3196.1387, 4.6556])


def test_pos_rows_times_and_fix_flags(rc, tmp_path):  # type: ignore[no-untyped-def]
    path = tmp_path / "a.pos"
    path.write_bytes(POS.encode())
    sol = rc.parse_pos(path)
    start = rc.gpst_seconds(np.array(["2005-04-02T00:00:00"], dtype="datetime64[ns]"))[0]
    np.testing.assert_array_equal(sol.time_s, start + np.array([0.0, 30.0, 60.0]))
    np.testing.assert_allclose(sol.enu_m[1], [953.7750, -3196.1387, 4.6556])
    np.testing.assert_array_equal(sol.fixed, [True, True, False])


def test_gps_epoch_seconds_match_rtklib_week_and_tow(rc):  # type: ignore[no-untyped-def]
    t = rc.gpst_seconds(np.array(["2005-04-02T00:00:00"], dtype="datetime64[ns]"))[0]
    assert t == 1316 * 604800 + 518400


def test_pos_metrics_count_the_wrong_fix(rc, tmp_path):  # type: ignore[no-untyped-def]
    path = tmp_path / "a.pos"
    path.write_text(POS)
    ref = rc.Reference(REF_ENU, None, "hand", True)
    m = rc.metrics(rc.parse_pos(path), ref, 4, 0.05)
    # epoch 2 is fixed 0.1 m East of the reference: a wrong fix; epoch 3 (float) is sqrt(3) m off.
    assert (m["epochs"], m["solved"], m["fixed"], m["wrong_fixes"]) == (4, 3, 2, 1)
    assert m["fix_rate"] == pytest.approx(0.5)
    assert m["error_fixed_median_m"] == pytest.approx(0.05, abs=1e-9)  # median of 0 and 0.1
    assert m["error_fixed_p95_m"] == pytest.approx(0.095, abs=1e-9)  # linear between 0 and 0.1
    assert m["error_all_median_m"] == pytest.approx(0.1, abs=1e-9)


def test_reference_that_cannot_judge_fixes_counts_none(rc, tmp_path):  # type: ignore[no-untyped-def]
    path = tmp_path / "a.pos"
    path.write_text(POS)
    m = rc.metrics(rc.parse_pos(path), rc.Reference(REF_ENU, None, "header", False), 3, 0.05)
    assert m["wrong_fixes"] is None and m["fixed"] == 2


def test_per_epoch_reference_matches_by_time(rc, tmp_path):  # type: ignore[no-untyped-def]
    path = tmp_path / "a.pos"
    path.write_text(POS)
    sol = rc.parse_pos(path)
    # a reference at the second epoch only, equal to its solution: no error there; the others are left out
    ref = rc.Reference(sol.enu_m[1:2].copy(), sol.time_s[1:2], "truth", True)
    m = rc.metrics(sol, ref, 3, 0.05)
    assert (m["fixed"], m["wrong_fixes"], m["unreferenced"]) == (2, 0, 2)
    assert m["error_fixed_median_m"] == 0.0 and m["error_all_median_m"] == 0.0
    np.testing.assert_array_equal(ref.at(sol.time_s + 0.02)[1], sol.enu_m[1])  # within RTKLIB's DTTOL
    assert np.isnan(ref.at(sol.time_s + 0.03)[1]).all()


def test_epochs_match_within_the_tolerance(rc):  # type: ignore[no-untyped-def]
    # GEONET labels of one epoch differ by up to 9 ms between the receivers; 30 s apart are other epochs
    grid = np.array([60.0, 0.0, 30.009])
    got = rc.match_epochs(np.array([0.0, 30.0, 59.98, 45.0, 90.0]), grid)
    np.testing.assert_array_equal(got, [1, 2, 0, -1, -1])
    np.testing.assert_array_equal(rc.match_epochs(np.array([1.0]), np.array([])), [-1])


# Today's baseline-mode CSV: angles only. Baseline (3, 4, 0) m is azimuth atan2(3, 4) = 36.869898 degrees.
CSV_ANGLES = (
    "time_gpst,azimuth_deg,elevation_deg,method,fixed,satellites\n"
    "2024-03-01T10:00:00.000,36.869898,0.000000,lambda,1,7\n"
    "2024-03-01T10:00:01.000,nan,nan,lambda,0,3\n"
    "2024-03-01T10:00:02.000,36.869898,90.000000,lambda,0,7\n"
)
# The engine's CSV (issue 16): east/north/up columns, fixed as 1/0.
CSV_ENU = (
    "time_gpst,azimuth_deg,elevation_deg,method,fixed,satellites,east_m,north_m,up_m,length_m\n"
    "2024-03-01T10:00:00.000,36.869898,0.000000,lambda,1,7,3.0,4.0,0.0,5.0\n"
    "2024-03-01T10:00:01.000,,,lambda,0,0,,,,\n"
    "2024-03-01T10:00:02.000,36.869898,0.000000,lambda,0,7,3.2,4.0,0.0,5.1\n"
)


def test_csv_from_angles_at_the_reference_length(rc, tmp_path):  # type: ignore[no-untyped-def]
    path = tmp_path / "a.csv"
    path.write_text(CSV_ANGLES)
    sol = rc.parse_gnssatt_csv(path, 5.0)
    assert sol.enu_source == "angles x reference length"
    t0 = rc.gpst_seconds(np.array(["2024-03-01T10:00:00"], dtype="datetime64[ns]"))[0]
    np.testing.assert_array_equal(sol.time_s, [t0, t0 + 2.0])  # the NaN epoch is not solved
    np.testing.assert_allclose(sol.enu_m, [[3.0, 4.0, 0.0], [0.0, 0.0, 5.0]], atol=1e-5)
    np.testing.assert_array_equal(sol.fixed, [True, False])


def test_csv_with_enu_columns_uses_them(rc, tmp_path):  # type: ignore[no-untyped-def]
    path = tmp_path / "a.csv"
    path.write_text(CSV_ENU)
    sol = rc.parse_gnssatt_csv(path, 1000.0)  # the length must not be used
    assert sol.enu_source == "csv"
    np.testing.assert_allclose(sol.enu_m, [[3.0, 4.0, 0.0], [3.2, 4.0, 0.0]])
    m = rc.metrics(sol, rc.Reference(np.array([3.0, 4.0, 0.0]), None, "", True), 3, 0.05)
    assert (m["solved"], m["fixed"], m["wrong_fixes"]) == (2, 1, 0)
    assert m["error_all_median_m"] == pytest.approx(0.1)


def test_help_options_and_navsys(rc):  # type: ignore[no-untyped-def]
    text = (
        "usage: gnssatt attitude [-h] --obs OBS\n  --base-position X Y Z  ECEF\n  --frequencies {1,2,3,all}"
    )
    assert rc.help_options(text) == {"--obs", "--base-position", "--frequencies"}
    assert rc.navsys("G") == 1 and rc.navsys("GRECJ") == 61 and rc.navsys("GE") == 9


def test_conf_copy_replaces_and_appends_keys(rc, tmp_path):  # type: ignore[no-untyped-def]
    src = tmp_path / "in.conf"
    src.write_text("# pos1-navsys = 1 in a comment stays\npos1-elmask        =10\npos1-navsys        =1\n")
    dst = tmp_path / "out.conf"
    rc.write_conf(src, dst, {"pos1-navsys": "61", "out-solformat": "enu"})
    lines = dst.read_text().splitlines()
    assert lines[0].startswith("# pos1-navsys = 1")
    assert [ln.replace(" ", "") for ln in lines[1:]] == [
        "pos1-elmask=10",
        "pos1-navsys=61",
        "out-solformat=enu",
    ]


RINEX3_HEADER = (
    "     3.04           OBSERVATION DATA    M                   RINEX VERSION / TYPE\n"
    "  3314961.0949  2426184.7592  4862903.9444                  APPROX POSITION XYZ\n"
    "G   12 C1C L1C D1C S1C C2W L2W D2W S2W C5Q L5Q D5Q S5Q      SYS / # / OBS TYPES\n"
    "E   16 C1C L1C D1C S1C C5Q L5Q D5Q S5Q C7Q L7Q D7Q S7Q      SYS / # / OBS TYPES\n"
    "       C8Q L8Q D8Q S8Q                                      SYS / # / OBS TYPES\n"
    "R    4 C1C L1C D1C S1C                                      SYS / # / OBS TYPES\n"
    "                                                            END OF HEADER\n"
)
RINEX2_HEADER = (
    "     2.10           OBSERVATION DATA    G (GPS)             RINEX VERSION / TYPE\n"
    "        0.0000        0.0000        0.0000                  APPROX POSITION XYZ\n"
    "     4    L1    L2    C1    P2                              # / TYPES OF OBSERV\n"
    "                                                            END OF HEADER\n"
)


def test_rinex_headers_position_and_bands(rc, tmp_path):  # type: ignore[no-untyped-def]
    p3, p2 = tmp_path / "a.24o", tmp_path / "b.05o"
    p3.write_text(RINEX3_HEADER)
    p2.write_text(RINEX2_HEADER)
    pos, bands = rc.rinex_header(p3)
    np.testing.assert_array_equal(pos, [3314961.0949, 2426184.7592, 4862903.9444])
    assert bands == {"G": 3, "E": 4, "R": 1}  # E1, E5a, E5b, E5 (continuation line read)
    pos, bands = rc.rinex_header(p2)
    assert pos is None and bands == {"G": 2}


def test_table_puts_both_tools_side_by_side_with_notes(rc):  # type: ignore[no-untyped-def]
    m = {"epochs": 100, "solved": 100, "fixed": 99, "fix_rate": 0.99, "wrong_fixes": 0, "unreferenced": 0}
    m |= {"first_fix_s": 3.0}
    m |= {"error_fixed_median_m": 0.0021, "error_fixed_p95_m": 0.0089, "error_all_median_m": 0.0023}
    rtk = {"metrics": m, "note": "", "median_wall_s": 0.2}
    ours = {"metrics": None, "note": "no --frequencies (band 1 only)", "median_wall_s": None}
    row = {
        "dataset": "sim",
        "mode": "static",
        "systems": "G",
        "frequencies": 2,
        "rtklib": rtk,
        "gnssatt": ours,
    }
    lines = rc.table([row]).splitlines()
    assert lines[2] == (
        "| sim | static | G | 2 | 99.0 \\| n/a [1] | 0 \\| n/a | 3 \\| n/a | 2.1/8.9 \\| n/a | 2.3 \\| n/a "
        "| 0.20 \\| n/a | 2.00 \\| n/a |"
    )
    assert lines[-1] == "[1] sim static G f2 gnssatt: no --frequencies (band 1 only)"


def test_run_plan_gps_then_cdma_then_every_system(rc):  # type: ignore[no-untyped-def]
    def plan(bands):  # type: ignore[no-untyped-def]
        return rc.run_plan(rc.Dataset("x", Path("b"), Path("r"), (), 1, None, bands, None, ""))

    assert plan({"G": 2}) == [("G", 1), ("G", 2)]
    full = plan({"G": 3, "R": 2, "E": 3, "C": 3, "J": 3})
    assert [s for s, f in full if f == 1] == ["G", "GECJ", "GRECJ"]
    assert [f for s, f in full if s == "GRECJ"] == [1, 2, 3]
    assert plan({"G": 1, "R": 1}) == [("G", 1), ("GR", 1)]
