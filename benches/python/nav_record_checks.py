"""Agreement of broadcast-record positions with independent references, on the real records of tests/data.

Prints the numbers quoted in the README (section on broadcast navigation records):

- GLONASS R01, R02 (BRDM00DLR 2013-01-01): records 30 min apart, each propagated 15 min to the midpoint;
  distance between the two positions.
- BeiDou C02-C05 (GEO) and C06 (IGSO) of a Skydel scenario against the simulator's truth of the same run
  (tests/data/skydel_bds_truth.csv; transmission time = PSR satellite time - clock correction, GPST).
- What the GEO check rejects: C02 with GPS omega_E instead of CGCS2000, with a 14 s BDT/GPST slip, and
  with the MEO formula (no -5 deg tilt, omega_E folded into Omega).
- Why C01 cannot be checked: the only C01 truth available comes from a second Skydel run
  (Iono-Klob_tropo-Saast) whose GEO satellites carry other ephemerides and clocks; its clock column is
  compared with the record's clock, and that run's C02 with the C02 record.

Run: PYTHONPATH=python python benches/python/nav_record_checks.py
"""

from __future__ import annotations

import csv
import dataclasses
from pathlib import Path

import numpy as np

from gnssatt.rinex import ephemeris, read_nav
from gnssatt.rinex.ephemeris import satellite_states
from gnssatt.rinex.nav import RinexNav, gps_ns

DATA = Path(__file__).resolve().parents[2] / "tests" / "data"
BRDM = DATA / "BRDM00DLR_R_20130010000_01D_MN.rnx"
SKYDEL = DATA / "skydel_bds_c01_c06.rnx"
TRUTH = DATA / "skydel_bds_truth.csv"
T_SKYDEL_NS = int(gps_ns(np.array([np.datetime64("2023-01-08T12:00:00", "ns")]))[0])  # TOW 43200


def glonass_midpoints() -> None:
    nav = read_nav(BRDM)
    g = nav.glonass
    for sat in ("R01", "R02"):
        a, b = np.flatnonzero(g.sats == sat)
        mid = int((g.tb_ns[a] + g.tb_ns[b]) // 2)
        # satellite_states picks the nearer record; a 1 ns nudge forces each one
        pa, *_ = satellite_states(nav, [sat], mid - 1, 1e-9)
        pb, *_ = satellite_states(nav, [sat], mid + 1, -1e-9)
        d = np.linalg.norm(pa - pb)
        print(f"{sat}: two records 30 min apart, propagated to their midpoint, differ by {d:.3f} m")


def truth_rows() -> list[dict[str, str]]:
    with TRUTH.open() as f:
        return list(csv.DictReader(line for line in f if not line.startswith("#")))


def distance(nav: RinexNav, sat: str, row: dict[str, str], extra_s: float = 0.0) -> tuple[float, float]:
    """Distance to the row's ECEF truth (m) and our clock minus the row's clock correction (s)."""
    clock = float(row["clock_correction_s"])
    dt = (float(row["psr_satellite_time_ms"]) - float(row["elapsed_ms"])) * 1e-3 - clock + extra_s
    pos, clk, _, ok = satellite_states(nav, [sat], T_SKYDEL_NS, dt)
    assert ok[0], sat
    truth = np.array([float(row[k]) for k in ("ecef_x_m", "ecef_y_m", "ecef_z_m")])
    return float(np.linalg.norm(pos[0] - truth)), float(clk[0] - clock)


def skydel() -> None:
    nav = read_nav(SKYDEL)
    rows = truth_rows()
    same = {r["sat"]: r for r in rows if r["run"] == "Iono-none_tropo-none"}
    other = {r["sat"]: r for r in rows if r["run"] == "Iono-Klob_tropo-Saast"}
    for sat, row in same.items():
        d, dclk = distance(nav, sat, row)
        print(f"{sat}: {d:.3e} m from Skydel truth (same run); clock minus Skydel's: {dclk:+.2e} s")

    row = same["C02"]
    omega = ephemeris._OMEGA["C"]
    ephemeris._OMEGA["C"] = ephemeris._OMEGA["G"]  # private table, restored below
    try:
        d, _ = distance(nav, "C02", row)
    finally:
        ephemeris._OMEGA["C"] = omega
    print(f"C02 with GPS omega_E: {d:.3f} m")
    print(f"C02 with a 14 s BDT/GPST slip: {distance(nav, 'C02', row, 14.0)[0] / 1e3:.1f} km")
    # the C02 record under a non-GEO id gets the MEO/IGSO formula
    sats = nav.kepler.sats.copy()
    sats[sats == "C02"] = "C20"
    meo = dataclasses.replace(nav, kepler=dataclasses.replace(nav.kepler, sats=sats))
    print(f"C02 by the MEO formula: {distance(meo, 'C20', row)[0] / 1e3:.0f} km")

    for sat in ("C01", "C02"):
        d, dclk = distance(nav, sat, other[sat])
        af0 = nav.kepler.af[np.flatnonzero(nav.kepler.sats == sat)[0], 0]
        print(
            f"{sat} vs the other run's truth: {d / 1e3:.3f} km; that run's clock correction "
            f"{float(other[sat]['clock_correction_s']):.3e} s, the record's af0 {af0:.3e} s"
        )


def main() -> None:
    glonass_midpoints()
    skydel()


if __name__ == "__main__":
    main()
