"""Agreement of broadcast-record positions with independent references, on the real records of tests/data.

Prints the numbers quoted in docs/results/recorded_data.md (broadcast navigation records):

- GLONASS R01, R02 (BRDM00DLR 2013-01-01): records 30 min apart, each propagated 15 min to the midpoint;
  distance between the two positions.
- BeiDou C02-C05 (GEO) and C06 (IGSO) of a Skydel scenario against the simulator's truth of the same run
  (tests/data/skydel_bds_truth.csv; transmission time = PSR satellite time - clock correction, GPST).
- What the GEO check rejects: C02 with GPS omega_E instead of CGCS2000, with a 14 s BDT/GPST slip, and
  with the MEO formula (no -5 deg tilt, omega_E folded into Omega).

Positions are the engine's (``_core.gnss_satellite_states``); the GPS omega_E case moves the record's
Omega0 by ``-(omega_GPS - omega_BDS) toe_sow``, the term by which the constant enters the GEO node (the
other, the ``R_z(omega_e t_k)`` rotation, changes by ``(omega_GPS - omega_BDS) t_k r``: 1 mm here; the
Python prototype, which swapped the constant itself, printed 2.652 m where this prints 2.653 m).

Run: PYTHONPATH=python python benches/python/nav_record_checks.py
"""

from __future__ import annotations

import csv
from pathlib import Path

import numpy as np

from gnssatt import _core
from gnssatt.rinex import read_nav
from gnssatt.rinex.nav import NavInput, gps_ns, nav_input

DATA = Path(__file__).resolve().parents[2] / "tests" / "data"
BRDM = DATA / "BRDM00DLR_R_20130010000_01D_MN.rnx"
SKYDEL = DATA / "skydel_bds_c01_c06.rnx"
TRUTH = DATA / "skydel_bds_truth.csv"
T_SKYDEL_NS = int(gps_ns(np.array([np.datetime64("2023-01-08T12:00:00", "ns")]))[0])  # TOW 43200
#: Earth rotation rates of IS-GPS-200 and BDS-SIS-ICD (CGCS2000), rad/s; BDT - GPST, ns; a week, ns.
OMEGA_GPS, OMEGA_BDS = 7.2921151467e-5, 7.292115e-5
BDT_NS, WEEK_NS = -14 * 10**9, 604_800 * 10**9


def satellite_states(
    nav: NavInput, sats: list[str], t_ns: int, offset_s: float = 0.0
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The engine's positions (ECEF of the instant), clocks and validity at GPST ``t_ns`` + ``offset_s``."""
    n = len(sats)
    t = np.full(n, t_ns, dtype=np.int64)
    off = np.full(n, offset_s)
    s = _core.gnss_satellite_states(
        _core.Navigation(kepler=nav.kepler, glonass=nav.glonass), sats, t, offset_s=off
    )
    return s.position_m, s.clock_s, s.valid


def _alone(nav: NavInput, table: str, row: int) -> NavInput:
    """``nav`` with only record ``row`` of ``table``."""
    one = {k: v[row : row + 1] for k, v in getattr(nav, table).items()}
    return NavInput(one if table == "kepler" else {}, one if table == "glonass" else {}, None, None)


def glonass_midpoints() -> None:
    nav = nav_input(read_nav(BRDM))
    g = nav.glonass
    for sat in ("R01", "R02"):
        a, b = np.flatnonzero(g["sat"] == sat)
        mid = int((g["tb_gpst_ns"][a] + g["tb_gpst_ns"][b]) // 2)
        # each record alone, propagated to the midpoint
        pa, *_ = satellite_states(_alone(nav, "glonass", int(a)), [sat], mid)
        pb, *_ = satellite_states(_alone(nav, "glonass", int(b)), [sat], mid)
        d = np.linalg.norm(pa - pb)
        print(f"{sat}: two records 30 min apart, propagated to their midpoint, differ by {d:.3f} m")


def truth_rows() -> list[dict[str, str]]:
    with TRUTH.open() as f:
        return list(csv.DictReader(line for line in f if not line.startswith("#")))


def distance(nav: NavInput, sat: str, row: dict[str, str], extra_s: float = 0.0) -> tuple[float, float]:
    """Distance to the row's ECEF truth (m) and our clock minus the row's clock correction (s)."""
    clock = float(row["clock_correction_s"])
    dt = (float(row["psr_satellite_time_ms"]) - float(row["elapsed_ms"])) * 1e-3 - clock + extra_s
    pos, clk, ok = satellite_states(nav, [sat], T_SKYDEL_NS, dt)
    assert ok[0], sat
    truth = np.array([float(row[k]) for k in ("ecef_x_m", "ecef_y_m", "ecef_z_m")])
    return float(np.linalg.norm(pos[0] - truth)), float(clk[0] - clock)


def skydel() -> None:
    nav = nav_input(read_nav(SKYDEL))
    k = nav.kepler
    rows = truth_rows()
    same = {r["sat"]: r for r in rows if r["run"] == "Iono-none_tropo-none"}
    other = {r["sat"]: r for r in rows if r["run"] == "Iono-Klob_tropo-Saast"}
    for sat, row in same.items():
        d, dclk = distance(nav, sat, row)
        print(f"{sat}: {d:.3e} m from Skydel truth (same run); clock minus Skydel's: {dclk:+.2e} s")

    row = same["C02"]
    c02 = int(np.flatnonzero(k["sat"] == "C02")[0])
    toe_sow = ((int(k["toe_gpst_ns"][c02]) + BDT_NS) % WEEK_NS) * 1e-9
    gps_omega = {**k, "omega0": k["omega0"].copy()}
    gps_omega["omega0"][c02] -= (OMEGA_GPS - OMEGA_BDS) * toe_sow
    d, _ = distance(NavInput(gps_omega, {}, None, None), "C02", row)
    print(f"C02 with GPS omega_E: {d:.3f} m")
    print(f"C02 with a 14 s BDT/GPST slip: {distance(nav, 'C02', row, 14.0)[0] / 1e3:.1f} km")
    # the C02 record under a non-GEO id gets the MEO/IGSO formula
    sats = k["sat"].copy()
    sats[sats == "C02"] = "C20"
    meo = NavInput({**k, "sat": sats}, {}, None, None)
    print(f"C02 by the MEO formula: {distance(meo, 'C20', row)[0] / 1e3:.0f} km")

    for sat in ("C01", "C02"):
        d, dclk = distance(nav, sat, other[sat])
        af0 = k["af"][np.flatnonzero(k["sat"] == sat)[0], 0]
        print(
            f"{sat} vs the other run's truth: {d / 1e3:.3f} km; that run's clock correction "
            f"{float(other[sat]['clock_correction_s']):.3e} s, the record's af0 {af0:.3e} s"
        )


def main() -> None:
    glonass_midpoints()
    skydel()


if __name__ == "__main__":
    main()
