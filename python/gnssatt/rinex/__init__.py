"""Recorded receiver data: RINEX reading and writing, broadcast ephemerides, between-receiver processing.

Time scale: GPST throughout (``datetime64[ns]`` labels, or integer nanoseconds since the GPS epoch).
Carrier phase in cycles with the RINEX sign (grows with range); see ``docs/conventions.md``.
"""

from gnssatt.rinex.align import Aligned, align_receivers, carrier_frequency_hz
from gnssatt.rinex.attitude import AttitudeSeries, attitude_from_rinex
from gnssatt.rinex.baseline import EpochBaselines, StaticBaseline, epoch_baselines, static_baseline
from gnssatt.rinex.ephemeris import satellite_states, transmit_states
from gnssatt.rinex.nav import GlonassEphemerides, KeplerEphemerides, RinexNav, gps_ns, read_nav
from gnssatt.rinex.obs import RinexObs, read_obs
from gnssatt.rinex.spp import PointSolution, single_point_positions
from gnssatt.rinex.writer import write_nav_from_constellation, write_obs

__all__ = [
    "Aligned",
    "AttitudeSeries",
    "EpochBaselines",
    "GlonassEphemerides",
    "KeplerEphemerides",
    "PointSolution",
    "RinexNav",
    "RinexObs",
    "StaticBaseline",
    "align_receivers",
    "attitude_from_rinex",
    "carrier_frequency_hz",
    "epoch_baselines",
    "gps_ns",
    "read_nav",
    "read_obs",
    "satellite_states",
    "single_point_positions",
    "static_baseline",
    "transmit_states",
    "write_nav_from_constellation",
    "write_obs",
]
