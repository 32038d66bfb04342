"""Recorded receiver data: RINEX reading and writing only. Attitude or baseline direction from recorded files
through the Rust observation engine is :func:`gnssatt.gnss.attitude.attitude_from_rinex`.

Time scale: GPST throughout (``datetime64[ns]`` labels, or integer nanoseconds since the GPS epoch).
Carrier phase in cycles with the RINEX sign (grows with range); see ``docs/conventions.md``.
"""

import importlib
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from gnssatt.rinex.nav import GlonassEphemerides, KeplerEphemerides, RinexNav, gps_ns, read_nav
    from gnssatt.rinex.obs import RinexObs, read_obs
    from gnssatt.rinex.writer import write_nav_from_constellation, write_obs

# Names imported on first access (PEP 562): `gnssatt attitude` needs only the reader and the engine, not
# the writer or the simulator it serves.
_EXPORTS = {
    "GlonassEphemerides": "nav",
    "KeplerEphemerides": "nav",
    "RinexNav": "nav",
    "gps_ns": "nav",
    "read_nav": "nav",
    "RinexObs": "obs",
    "read_obs": "obs",
    "write_nav_from_constellation": "writer",
    "write_obs": "writer",
}

__all__ = [
    "GlonassEphemerides",
    "KeplerEphemerides",
    "RinexNav",
    "RinexObs",
    "gps_ns",
    "read_nav",
    "read_obs",
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
