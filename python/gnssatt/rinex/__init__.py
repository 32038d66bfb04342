"""Recorded receiver data: RINEX reading and writing, broadcast ephemerides, between-receiver processing.

Time scale: GPST throughout (``datetime64[ns]`` labels, or integer nanoseconds since the GPS epoch).
Carrier phase in cycles with the RINEX sign (grows with range); see ``docs/conventions.md``.
"""

from gnssatt.rinex.ephemeris import satellite_states, transmit_states
from gnssatt.rinex.nav import GlonassEphemerides, KeplerEphemerides, RinexNav, gps_ns, read_nav
from gnssatt.rinex.obs import RinexObs, read_obs
from gnssatt.rinex.spp import PointSolution, single_point_positions

__all__ = [
    "GlonassEphemerides",
    "KeplerEphemerides",
    "PointSolution",
    "RinexNav",
    "RinexObs",
    "gps_ns",
    "read_nav",
    "read_obs",
    "satellite_states",
    "single_point_positions",
    "transmit_states",
]
