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

_SESSION = "gnssatt.gnss.session_input.session_input (observations on common epochs and signals)"
_SOLVE = (
    "gnssatt.gnss.attitude.attitude_from_rinex (motion='static' or 'moving'; baselines, fixed flags, sigmas)"
)
_ENGINE = (
    "gnssatt.gnss.attitude.attitude_from_rinex, which evaluates them in the engine (the evaluations "
    "themselves: gnssatt._core.gnss_satellite_states and gnss_transmit_states on "
    "gnssatt.rinex.nav.nav_input(...).navigation())"
)
#: Names of the Python prototype of the observation engine, deleted after the engine reproduced its results
#: (issue 16; tests/test_gnss_prototype_reference.py): what replaces each.
_REMOVED = {
    "Aligned": _SESSION,
    "align_receivers": _SESSION,
    "carrier_frequency_hz": "gnssatt.rinex.signals.slot_frequency_hz",
    "EpochBaselines": _SOLVE,
    "StaticBaseline": _SOLVE,
    "epoch_baselines": _SOLVE,
    "static_baseline": _SOLVE,
    "satellite_states": _ENGINE,
    "transmit_states": _ENGINE,
    "PointSolution": _SOLVE + " (the engine's single-point positions position the receivers)",
    "single_point_positions": _SOLVE + " (the engine's single-point positions position the receivers)",
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
    """Import a re-exported name on first access (PEP 562) and cache it in the package; a name of the
    deleted prototype raises ImportError saying what replaces it (ImportError, not AttributeError, so that
    ``from gnssatt.rinex import name`` shows the message)."""
    if name in _REMOVED:
        raise ImportError(
            f"gnssatt.rinex.{name} belonged to the Python prototype of the observation engine, removed in "
            f"favour of the Rust engine; use {_REMOVED[name]}",
            name=name,
        )
    if name not in _EXPORTS:  # a name that moved out (attitude_from_rinex ...), with a warning, or none
        from gnssatt._moved import moved_attribute

        return moved_attribute(__name__, name)
    value = getattr(importlib.import_module(f"{__name__}.{_EXPORTS[name]}"), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))
