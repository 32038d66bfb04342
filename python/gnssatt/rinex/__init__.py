"""Recorded receiver data: RINEX reading and writing, broadcast ephemerides, between-receiver processing.

Time scale: GPST throughout (``datetime64[ns]`` labels, or integer nanoseconds since the GPS epoch).
Carrier phase in cycles with the RINEX sign (grows with range); see ``docs/conventions.md``.
"""

import importlib
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from gnssatt.rinex.align import Aligned, align_receivers, carrier_frequency_hz
    from gnssatt.rinex.attitude import AttitudeSeries, attitude_from_rinex
    from gnssatt.rinex.baseline import EpochBaselines, StaticBaseline, epoch_baselines, static_baseline
    from gnssatt.rinex.ephemeris import satellite_states, transmit_states
    from gnssatt.rinex.nav import GlonassEphemerides, KeplerEphemerides, RinexNav, gps_ns, read_nav
    from gnssatt.rinex.obs import RinexObs, read_obs
    from gnssatt.rinex.spp import PointSolution, single_point_positions
    from gnssatt.rinex.writer import write_nav_from_constellation, write_obs

# Names imported on first access (PEP 562): `gnssatt attitude` needs only the reader and the engine, not
# the Python prototype modules (align, spp, ephemeris, baseline) or the simulator they import (0.8 s).
_EXPORTS = {
    "Aligned": "align",
    "align_receivers": "align",
    "carrier_frequency_hz": "align",
    "AttitudeSeries": "attitude",
    "attitude_from_rinex": "attitude",
    "EpochBaselines": "baseline",
    "StaticBaseline": "baseline",
    "epoch_baselines": "baseline",
    "static_baseline": "baseline",
    "satellite_states": "ephemeris",
    "transmit_states": "ephemeris",
    "GlonassEphemerides": "nav",
    "KeplerEphemerides": "nav",
    "RinexNav": "nav",
    "gps_ns": "nav",
    "read_nav": "nav",
    "RinexObs": "obs",
    "read_obs": "obs",
    "PointSolution": "spp",
    "single_point_positions": "spp",
    "write_nav_from_constellation": "writer",
    "write_obs": "writer",
}

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


def __getattr__(name: str) -> Any:
    """Import a re-exported name on first access (PEP 562) and cache it in the package."""
    if name not in _EXPORTS:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    value = getattr(importlib.import_module(f"{__name__}.{_EXPORTS[name]}"), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))
