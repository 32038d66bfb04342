"""Records the Python prototype's ephemerides, light-time geometry, Klobuchar delays and single-point
positions, before the engine replaced it (issue 16): the frozen reference of
tests/test_gnss_prototype_reference.py.

Run from the repository root on commit c1b0832 (the prototype as ``attitude_from_rinex`` left it, the
fixture's ``commit``): ``python tests/data/prototype_reference.py`` writes
``tests/data/prototype_reference.json``. It cannot run after the commit that deleted the prototype
modules (``gnssatt.rinex.ephemeris``, ``iono``, ``spp``); it stays as the record of how the fixture was made.

Inputs, all shipped in the repository:

- ``ephemeris``: every record of every navigation file of tests/data, alone in its file (so that the
  prototype and the engine evaluate the same record), at reference time + -3000, -600, 0, 900, 3300 s
  (Keplerian) or -900, 0, 600, 1500 s (GLONASS). Unhealthy records are left out, except QZSS records
  flagged only on bit 0 (L6/LEX), given to the prototype as healthy (it treats any nonzero word as
  unhealthy; the engine masks that bit).
- ``transmit``: the same records at their reference time, seen from GEONET station 0759 (its header
  position) with a receiver clock of 1e-4 s: ``transmit_states`` (light time iterated, Sagnac rotation into
  the frame of reception).
- ``klobuchar``: ``klobuchar_delay_m`` with the simulator's coefficients on a grid of latitude, longitude,
  azimuth, elevation, time of day and carrier.
- ``spp``: ``single_point_positions`` of GEONET 0759 and 3040 (GPS C1 only, so single-frequency code with
  Klobuchar and T_GD like the engine; elevation mask 10 degrees).
"""

from __future__ import annotations

import dataclasses
import json
import subprocess
from pathlib import Path

import numpy as np

from gnssatt.data import geonet_dir
from gnssatt.rinex import read_nav, read_obs
from gnssatt.rinex.ephemeris import satellite_states, transmit_states
from gnssatt.rinex.iono import klobuchar_delay_m
from gnssatt.rinex.nav import GlonassEphemerides, KeplerEphemerides, RinexNav, gps_ns
from gnssatt.rinex.spp import single_point_positions
from gnssatt.sim.rinex_scenario import KLOBUCHAR

DATA = Path(__file__).resolve().parent
NAV_FILES = [
    "BRDM00DLR_R_20130010000_01D_MN.rnx",
    "BRDC00IGS_R_20201360000_01D_MN.rnx",
    "CBW100NLD_R_20210010000_01D_MN.rnx",
    "skydel_bds_c01_c06.rnx",
]
KEPLER_OFFSETS_S = (-3000, -600, 0, 900, 3300)
GLONASS_OFFSETS_S = (-900, 0, 600, 1500)
RECEIVER_CLOCK_S = 1e-4


def _one_kepler(nav: RinexNav, i: int, healthy: bool) -> RinexNav:
    k = nav.kepler
    s = slice(i, i + 1)
    fields = {n: v[s] for n, v in k.fields.items()}
    if healthy:
        fields["health"] = np.zeros(1)
    sub = KeplerEphemerides(k.sats[s], k.toc_ns[s], k.toe_ns[s], k.af[s], fields)
    empty = GlonassEphemerides(*(np.asarray(v)[:0] for v in dataclasses.astuple(nav.glonass)))
    return dataclasses.replace(nav, kepler=sub, glonass=empty)


def _one_glonass(nav: RinexNav, i: int) -> RinexNav:
    g = nav.glonass
    sub = GlonassEphemerides(*(np.asarray(v)[i : i + 1] for v in dataclasses.astuple(g)))
    k = nav.kepler
    empty = KeplerEphemerides(
        k.sats[:0], k.toc_ns[:0], k.toe_ns[:0], k.af[:0], {n: v[:0] for n, v in k.fields.items()}
    )
    return dataclasses.replace(nav, kepler=empty, glonass=sub)


def _records(receiver: np.ndarray) -> tuple[list[dict], list[dict]]:
    states, transmits = [], []
    for name in NAV_FILES:
        nav = read_nav(DATA / name)
        cases = []
        for i in range(len(nav.kepler)):
            sat, health = str(nav.kepler.sats[i]), float(nav.kepler.fields["health"][i])
            if health != 0 and not (sat[0] == "J" and health == 1):
                continue
            cases.append(
                (
                    "kepler",
                    i,
                    sat,
                    _one_kepler(nav, i, health != 0),
                    int(nav.kepler.toe_ns[i]),
                    KEPLER_OFFSETS_S,
                )
            )
        for i in range(len(nav.glonass)):
            sat = str(nav.glonass.sats[i])
            cases.append(
                ("glonass", i, sat, _one_glonass(nav, i), int(nav.glonass.tb_ns[i]), GLONASS_OFFSETS_S)
            )
        for table, i, sat, one, ref, offsets in cases:
            for dt in offsets:
                t = ref + dt * 10**9
                p, c, _, ok = satellite_states(one, [sat], t)
                assert ok[0], (name, sat, dt)
                states.append(
                    {"file": name, "table": table, "record": i, "sat": sat, "t_gpst_ns": t,
                     "position_m": p[0].tolist(), "clock_s": float(c[0])}
                )  # fmt: skip
            p, c, _, ok = transmit_states(one, [sat], ref, receiver, receiver_clock_s=RECEIVER_CLOCK_S)
            assert ok[0], (name, sat)
            transmits.append(
                {"file": name, "table": table, "record": i, "sat": sat, "t_rx_gpst_ns": ref,
                 "position_m": p[0].tolist(), "clock_s": float(c[0])}
            )  # fmt: skip
    return states, transmits


def _klobuchar() -> dict:
    grid = np.array(
        [
            (lat, lon, az, el, t, f)
            for lat in (-70.0, 0.0, 35.7, 80.0)
            for lon in (-150.0, 36.2, 139.7)
            for az in (0.0, 250.0)
            for el in (5.0, 30.0, 89.0)
            for t in (0.0, 50400.0, 72000.0)
            for f in (1575.42e6, 1176.45e6)
        ]
    )
    lat, lon, az, el, t, f = grid.T
    delay = np.array(
        [
            float(
                klobuchar_delay_m(
                    KLOBUCHAR[:4], KLOBUCHAR[4:], *np.radians([la, lo, a, e]), s, frequency_hz=fr
                )
            )
            for la, lo, a, e, s, fr in grid
        ]
    )
    return {
        "coefficients": list(KLOBUCHAR),
        "lat_deg": lat.tolist(),
        "lon_deg": lon.tolist(),
        "azimuth_deg": az.tolist(),
        "elevation_deg": el.tolist(),
        "gps_seconds_of_day": t.tolist(),
        "frequency_hz": f.tolist(),
        "delay_m": delay.tolist(),
    }


def _spp() -> dict:
    out = {}
    d = geonet_dir()
    for station in ("0759", "3040"):
        obs = read_obs(d / f"{station}0920.05o")
        nav = read_nav(d / f"{station}0920.05n")
        c1_only = dataclasses.replace(obs, obs_types={"G": tuple(c for c in obs.obs_types["G"] if c != "P2")})
        sol = single_point_positions(c1_only, nav, elevation_mask_deg=10.0)
        out[station] = {
            "time_gpst_ns": gps_ns(sol.time).astype(np.int64).tolist(),
            "position_m": [None if not np.isfinite(p).all() else p.tolist() for p in sol.position_ecef_m],
            "satellites": sol.n_sats.tolist(),
        }
    return out


def main() -> None:
    receiver = read_obs(geonet_dir() / "07590920.05o").approx_position_m
    states, transmits = _records(receiver)
    out = {
        "command": "python tests/data/prototype_reference.py",
        "commit": subprocess.run(["git", "rev-parse", "HEAD"], capture_output=True, text=True).stdout.strip(),
        "receiver_m": receiver.tolist(),
        "receiver_clock_s": RECEIVER_CLOCK_S,
        "ephemeris": states,
        "transmit": transmits,
        "klobuchar": _klobuchar(),
        "spp": _spp(),
    }
    path = Path(__file__).with_suffix(".json")
    path.write_text(json.dumps(out, indent=0) + "\n")
    print(f"wrote {path}")


if __name__ == "__main__":
    main()
