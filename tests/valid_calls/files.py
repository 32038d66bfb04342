"""Valid calls of the file readers and writers and the sessions: ``gnssatt.rinex``, ``gnss``, ``data``."""

from __future__ import annotations

from functools import cache
from typing import Any

import numpy as np
from hostile import scenario as s
from scipy.spatial.transform import Rotation

from gnssatt import sim

from .spec import Arg, Call


@cache
def _attitude_series() -> Any:
    """A solved series of the shared RINEX array (the NMEA writers' input)."""
    from gnssatt.gnss.attitude import attitude_from_rinex

    a = s.rinex_array()
    return attitude_from_rinex(list(a.obs_paths), a.nav_path, method="lambda", systems="G")


def _obs() -> list[Any]:
    return list(s.rinex_read()["obs"])


CALLS: dict[str, Call] = {
    # --- gnssatt.rinex ---
    "gnssatt.rinex.read_obs": Call(
        lambda: {"path": s.rinex_array().obs_paths[0]}, nan_output="missing observations are NaN"
    ),
    "gnssatt.rinex.read_nav": Call(
        lambda: {"path": s.rinex_array().nav_path}, nan_output="absent header Klobuchar coefficients are NaN"
    ),
    "gnssatt.gnss.attitude.attitude_from_rinex": Call(
        lambda: {
            "observations": list(s.rinex_array().obs_paths),
            "nav": s.rinex_array().nav_path,
            "method": "auto",
            "systems": "G",
            "elevation_mask_deg": 10.0,
        },
        nan_output="epochs without a solution are NaN, flagged in the series",
    ),
    "gnssatt.gnss.nmea.nmea_sentences": Call(lambda: {"series": _attitude_series()}),
    "gnssatt.gnss.nmea.write_nmea": Call(
        lambda: {
            "path": s.folder() / "written.nmea",
            "series": _attitude_series(),
        }
    ),
    "gnssatt.position_from_rinex": Call(
        lambda: {
            "obs": s.rinex_array().obs_paths[0],
            "nav": s.rinex_array().nav_path,
            "systems": "G",
            "frequencies": 1,
            "elevation_mask_deg": 10.0,
        },
        nan_output="epochs without a solution are NaN, flagged in the series",
    ),
    "gnssatt.rinex.gps_ns": Call(lambda: {"time": np.array(["2024-03-01T10:00:00"], dtype="datetime64[ns]")}),
    "gnssatt.rinex.write_nav_from_constellation": Call(
        lambda: {
            "path": s.folder() / "written.24n",
            "constellation": s.gps(),
            "epoch_gpst": np.datetime64("2024-03-01T10:00:00", "ns"),
            "start_s": 60.0,
            "span_s": 7200.0,
            "clock_bias_s": np.full(len(s.gps()), 1e-5),
            "klobuchar": np.array(
                [1.1176e-08, 7.4506e-09, -5.9605e-08, -5.9605e-08, 9.0112e04, 0.0, -1.9661e05, -6.5536e04]
            ),
        }
    ),
    "gnssatt.rinex.write_obs": Call(
        lambda: {
            "path": s.folder() / "written.24o",
            "time": np.array(["2024-03-01T10:00:00", "2024-03-01T10:00:01"], dtype="datetime64[ns]"),
            "sats": ["G01", "G02"],
            "observations": {"C1C": np.array([[2.1e7, 2.2e7], [2.1e7 + 1, np.nan]])},
            "approx_position_m": (1.0, 2.0, 3.0),
            "marker_name": "SIM",
            "glonass_channels": {"R01": 1, "R02": -4},
        },
        args={"observations": Arg(nonfinite_ok=True), "marker_name": Arg(free_text=True)},
    ),
    "gnssatt.sim.rinex_scenario.simulate_rinex_array": Call(
        lambda: {
            "folder": s.folder(),
            "antennas_body_m": np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]]),
            "euler_gost_deg": np.zeros((2, 3)),
            "interval_s": 1.0,
            "rng": 1,
            "n_sats": 5,
        },
        args={"n_sats": Arg(count=True)},
    ),
    "gnssatt.sim.rinex_scenario.gnss_constellation": Call(lambda: {"systems": "GRE", "lon_deg": 36.2}),
    "gnssatt.sim.rinex_scenario.simulate_gnss_rinex": Call(
        lambda: {
            "folder": s.folder(),
            "antennas_body_m": np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]]),
            "euler_gost_deg": np.array([-40.0, 5.0, 3.0]),
            "systems": "GC",
            "frequencies": 2,
            "n_epochs": 2,
            "interval_s": 1.0,
            "start_s": 0.0,
            "rng": 1,
            "receiver_clock_s": np.array([1e-5, -2e-5]),
            "code_sigma_m": 0.3,
            "phase_sigma_m": 0.002,
            "doppler_sigma_hz": 0.05,
            "elevation_min_deg": 10.0,
            "slips": [],  # a valid slip names a satellite the mutated geometry may not keep
            "lat_deg": 50.0,
            "lon_deg": 36.2,
            "height_m": 150.0,
            "n_sats": 8,
            "file_names": ("hostile{i}.rnx", "hostile_nav.rnx"),
            "atmosphere": True,
        },
        args={"n_epochs": Arg(count=True), "n_sats": Arg(count=True)},
    ),
    "gnssatt.rinex.nav.nav_input": Call(
        lambda: {"nav": s.rinex_read()["nav"]},
        nan_output="group delays, fit interval and data source are NaN where a system has none",
    ),
    "gnssatt.gnss.session_input.session_input": Call(
        lambda: {
            "observations": _obs(),
            "systems": "G",
            "frequencies": 1,
            "nav": s.rinex_read()["nav"],
        },
        nan_output="absent observations (slots, satellites, epochs) are NaN",
    ),
    "gnssatt.gnss.session_input.epochs_gpst_ns": Call(lambda: {"obs": _obs()[0], "leaps": 18}),
    "gnssatt.rinex.signals.choose_signals": Call(lambda: {"obs": _obs()[0], "system": "G"}),
    "gnssatt.rinex.signals.slot_bands": Call(lambda: {"system": "C", "version": 3.02}),
    "gnssatt.rinex.signals.slot_frequency_hz": Call(
        lambda: {"system": "R", "slot": 1, "glonass_channel": -3}
    ),
    "gnssatt.sim.atmosphere.niell_mapping": Call(
        lambda: {
            "lat_rad": 0.8,
            "height_m": 150.0,
            "elevation_rad": np.array([0.2, 1.0]),
        }
    ),
    "gnssatt.sim.atmosphere.saastamoinen_zenith_m": Call(lambda: {"lat_rad": 0.8, "height_m": 150.0}),
    "gnssatt.sim.atmosphere.troposphere_delay_m": Call(
        lambda: {
            "lat_rad": 0.8,
            "height_m": 150.0,
            "elevation_rad": np.array([0.2, 1.0]),
        }
    ),
    "gnssatt.sim.rinex_scenario.write_array_rinex": Call(
        lambda: {
            "folder": s.folder(),
            "measurements": sim.simulate_array(
                s.geometry(), Rotation.identity(), sim.equilateral_triangle(1.0), np.full(8, 0.19), s.rng()
            ),
            "t_s": np.arange(3.0),
            "constellation": s.gps(),
            "sat_ids": list(s.geometry().ids),
            "receiver": s.GROUND,
        }
    ),
}
