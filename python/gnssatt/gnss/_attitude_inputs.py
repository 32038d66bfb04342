"""The arguments of :func:`~gnssatt.gnss.attitude.attitude_from_rinex` that the engine's options
(``gnssatt._core.GnssOptions``) do not check themselves: the files, the system letters, the frequencies, the
numeric options' ranges, and whether the navigation file covers the observation days.
"""

from __future__ import annotations

from os import PathLike
from typing import Any

import numpy as np
from numpy.typing import NDArray

from gnssatt._arrays import path_text, scalar, shaped
from gnssatt.errors import InvalidInputError, InvalidTypeError, RinexError
from gnssatt.gnss._attitude_series import GPS_EPOCH, SYSTEMS
from gnssatt.rinex.nav import RinexNav
from gnssatt.rinex.obs import RinexObs

#: Largest search window and grid step, degrees.
MAX_WINDOW_DEG = 3600.0
MAX_STEP_DEG = 180.0


def obs_list(name: str, value: object) -> list[RinexObs | str | PathLike[str]]:
    if isinstance(value, str | PathLike | RinexObs) or not isinstance(value, list | tuple):
        raise InvalidTypeError(
            f"expected {name} as a list of observation files or RinexObs, got {type(value).__name__}"
        )
    for i, o in enumerate(value):
        if not isinstance(o, RinexObs):
            path_text(o, f"{name}[{i}]")
    if len(value) < 2:
        raise InvalidInputError(f"expected two or more {name} (antennas), got {len(value)}")
    return list(value)


def system_letters(value: object) -> str:
    if not isinstance(value, str):
        raise InvalidTypeError(f"expected systems as system letters such as 'GE', got {type(value).__name__}")
    if not value or any(ch not in SYSTEMS for ch in value):
        raise InvalidInputError(f"expected systems as letters among {SYSTEMS!r}, got {value!r}")
    return "".join(ch for ch in SYSTEMS if ch in value)


def frequency_slots(value: object) -> int:
    from gnssatt import _core

    top = int(_core.GNSS_MAX_FREQUENCIES)
    if value == "all":
        return top
    if isinstance(value, bool) or not isinstance(value, int | np.integer) or not 1 <= int(value) <= top:
        raise InvalidInputError(f"expected frequencies 1..{top} or 'all', got {value!r}")
    return int(value)


#: Longest validity of a broadcast record on either side of its reference time, s (BeiDou's 6 h in
#: ``max_age_s`` of ``rust/core/src/gnss/ephemeris/mod.rs``): beyond it from every epoch, no record can serve.
_LONGEST_EPHEMERIS_AGE_NS = 6 * 3600 * 1_000_000_000


def _among(values: NDArray[np.str_], wanted: tuple[str, ...]) -> NDArray[np.bool_]:
    """Which ``values`` are among ``wanted``: ``np.isin`` without its ``np.unique``, which loads numpy.ma
    (30-50 ms of a command-line start)."""
    ordered = np.sort(np.array(wanted, dtype=str))
    if not len(ordered) or not len(values):
        return np.zeros(len(values), dtype=bool)
    at = np.minimum(np.searchsorted(ordered, values), len(ordered) - 1)
    found: NDArray[np.bool_] = ordered[at] == values
    return found


def check_nav_covers(time_gpst_ns: NDArray[np.int64], sats: tuple[str, ...], nav: RinexNav) -> None:
    """Refuse, naming the navigation file and both time spans, when no broadcast record of a satellite of
    the session lies within the longest validity of any epoch (a navigation file of another day): the
    engine would otherwise report only that no satellite had an ephemeris."""
    k, g = nav.kepler, nav.glonass
    times = np.concatenate([k.toe_ns[_among(k.sats, sats)], g.tb_ns[_among(g.sats, sats)]]).astype(np.int64)
    epochs = np.sort(np.asarray(time_gpst_ns, dtype=np.int64))
    if len(times) and len(epochs):
        after = np.clip(np.searchsorted(epochs, times), 0, len(epochs) - 1)
        before = np.clip(after - 1, 0, len(epochs) - 1)
        nearest = np.minimum(np.abs(times - epochs[after]), np.abs(times - epochs[before]))
        if nearest.min() <= _LONGEST_EPHEMERIS_AGE_NS:
            return
    first, last = (GPS_EPOCH + np.array([epochs[0], epochs[-1]]).astype("timedelta64[ns]")).astype(
        "datetime64[s]"
    )
    if len(times):
        lo, hi = (GPS_EPOCH + np.array([times.min(), times.max()]).astype("timedelta64[ns]")).astype(
            "datetime64[s]"
        )
        span = f"its records of these satellites refer to {lo} to {hi} (GPST)"
    else:
        span = "it has no record of any of them"
    raise RinexError(
        nav.path,
        None,
        f"no broadcast ephemeris for the {len(sats)} satellites observed (systems "
        f"{''.join(dict.fromkeys(x[0] for x in sats))}) within 6 h of the "
        f"observation epochs {first} to {last} (GPST); {span}: expected the navigation file of the "
        "observation day",
    )


def numeric_options(
    method: str,
    filter: str | None,
    *,
    elevation_mask_deg: float | None,
    min_success_rate: float | None,
    ratio_threshold: float | None,
    max_failure_rate: float | None,
    base_position_m: Any,
    step_deg: float | None,
    window_deg: float | None,
) -> tuple[dict[str, Any], list[str]]:
    """The numeric options given (not None), each checked against its range, keyed by the engine's option
    names, and the grid options among them (``step_deg``, ``window_deg``), refused where ``method`` or
    ``filter`` never runs the likelihood grid."""
    opts: dict[str, Any] = {}
    if elevation_mask_deg is not None:
        opts["elevation_mask_deg"] = scalar(
            "elevation_mask_deg", elevation_mask_deg, minimum=-90.0, maximum=90.0
        )
    if min_success_rate is not None:
        opts["min_success_rate"] = scalar("min_success_rate", min_success_rate, minimum=0.0, maximum=1.0)
    if ratio_threshold is not None:
        opts["ratio_threshold"] = scalar("ratio_threshold", ratio_threshold, minimum=1.0)
    if max_failure_rate is not None:
        opts["max_failure_rate"] = scalar("max_failure_rate", max_failure_rate, minimum=0.0, maximum=0.1)
    if base_position_m is not None:
        opts["base_position_m"] = shaped("base_position_m", base_position_m, "(3,)", (3,))
    if step_deg is not None:
        opts["step_deg"] = scalar("step_deg", step_deg, minimum=0.0, maximum=MAX_STEP_DEG, strict=True)
    if window_deg is not None:
        opts["window_deg"] = scalar(
            "window_deg", window_deg, minimum=0.0, maximum=MAX_WINDOW_DEG, strict=True
        )
    grid_options: list[str] = [n for n in ("step_deg", "window_deg") if n in opts]
    if grid_options and (method == "lambda" or filter is not None):
        # the engine runs the likelihood grid with method ml or auto and without a filter only: these
        # options would change nothing
        without = "method 'lambda'" if method == "lambda" else f"filter {filter!r}"
        raise InvalidInputError(
            f"{' and '.join(grid_options)} set the likelihood grid, which {without} never runs: leave "
            "them out, or use method 'ml' or 'auto'"
        )
    return opts, grid_options


def antenna_options(n_rover: int, baselines: Any, baseline_length_m: Any) -> dict[str, Any]:
    """The engine's options of the antennas' geometry: ``baseline_lengths_m`` (one per rover) and
    ``body_baselines_m`` ((n_rover, 3), attitude mode, three or more antennas), each checked against the
    number of rovers; two antennas need no baselines, more need them."""
    opts: dict[str, Any] = {}
    if baseline_length_m is not None:
        lengths = shaped("baseline_length_m", np.atleast_1d(baseline_length_m), "(n_ant - 1,)", (n_rover,))
        opts["baseline_lengths_m"] = [float(v) for v in lengths]
    if baselines is not None:
        b = shaped("baselines", baselines, "(n_ant - 1, 3)", (n_rover, 3))
        if n_rover < 2:
            raise InvalidInputError(
                "attitude mode needs three or more antennas; for two, omit the baselines (baseline mode)"
            )
        opts["body_baselines_m"] = b
    elif n_rover != 1:
        raise InvalidInputError(f"expected baselines ({n_rover}, 3) for {n_rover + 1} antennas, got none")
    return opts
