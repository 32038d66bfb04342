"""Checks of the engine's results against what :func:`~gnssatt.gnss.attitude.attitude_from_rinex` was asked
(a known length the fixes contradict, grid options or ``method="ml"`` that changed nothing) and the
baseline-mode rule for a baseline too short to have a direction, with the warnings they issue.
"""

from __future__ import annotations

import warnings
from dataclasses import replace
from typing import Any

import numpy as np

from gnssatt.errors import ConvergenceError, GnssattWarning, InvalidInputError
from gnssatt.gnss._attitude_series import AttitudeSeries, series_from_session

#: Baseline mode: a baseline shorter than this, m, has no direction (its azimuth and elevation are NaN, with
#: a :class:`ZeroBaselineWarning`). Two antennas' phase centres stand at least their diameter (several cm)
#: apart, and the known-length option takes no length below it either; a solution this short means one
#: antenna seen twice (the same file, or two receivers on one antenna splitter: a zero-baseline test), where
#: the fixed baseline is the receivers' noise, mm, and its direction is arbitrary (atan2 of zeros).
MIN_DIRECTION_BASELINE_M = 0.01


class EngineWarning(GnssattWarning):
    """Something the observation engine says a user should know (a base position far from the code
    solution, a system without ephemerides, ...); also kept in :attr:`AttitudeSeries.warnings`."""


class ZeroBaselineWarning(EngineWarning):
    """Baseline mode: the baseline solved is shorter than :data:`MIN_DIRECTION_BASELINE_M` at some epochs,
    whose azimuth and elevation are therefore NaN (the baseline itself is kept)."""


#: A known baseline length is refused when the fixed solutions measure a length further from it than
#: ``KNOWN_LENGTH_TOLERANCE_M + KNOWN_LENGTH_TOLERANCE_RELATIVE x length``: fixed double differences give
#: the length to millimetres, and the engine's grid needs it to 1 % (``docs/observation_engine.md``).
KNOWN_LENGTH_TOLERANCE_M = 0.01
KNOWN_LENGTH_TOLERANCE_RELATIVE = 1e-3


#: Epochs of the probe that checks ``baseline_length_m`` before a longer session runs: the first ones,
#: solved without the length (LAMBDA alone). The GEONET pair of ``tests/test_option_effects.py`` (3.3 km,
#: 30 s epochs) fixes from its first epoch, so a contradicted length is refused after these instead of the
#: whole session; a probe that fixes none of them leaves the check to the session.
KNOWN_LENGTH_PROBE_EPOCHS = 30


def probe_known_lengths(
    lengths_m: list[float],
    si: Any,
    navigation: Any,
    modes: dict[str, Any],
    opts: dict[str, Any],
) -> None:
    """:func:`check_known_lengths` on the first :data:`KNOWN_LENGTH_PROBE_EPOCHS` epochs solved without
    the known length, before the session runs. A probe that fixes nothing, or fails, decides nothing: the
    session's own check (and its own errors) follow."""
    from gnssatt import _core

    free = {k: v for k, v in opts.items() if k not in ("baseline_lengths_m", "step_deg", "window_deg")}
    try:
        probe = _core.gnss_run(
            si.observations(slice(0, KNOWN_LENGTH_PROBE_EPOCHS)),
            navigation,
            _core.GnssOptions(**modes, method="lambda", filter=None, **free),
        )
    except (InvalidInputError, ConvergenceError):
        return
    first = f"the first {KNOWN_LENGTH_PROBE_EPOCHS} epochs (solved without the length, before the session)"
    check_known_lengths(lengths_m, series_from_session(probe, si.signal_codes), first)


def check_known_lengths(lengths_m: list[float], series: AttitudeSeries, epochs: str) -> None:
    """Refuses ``baseline_length_m`` where the epochs fixed by LAMBDA measure another length (the engine
    uses the known length only where it helps, so a wrong one left the result unchanged); ``epochs`` says
    which epochs were looked at in the message."""
    rows = series.solved & (series.fixed == 1) & (series.method == "lambda")
    if not np.any(rows):
        return  # nothing measured the length independently
    measured = np.median(np.linalg.norm(series.baselines_enu_m[rows], axis=2), axis=0)
    for r, (given, got) in enumerate(zip(lengths_m, measured, strict=True)):
        if abs(got - given) > KNOWN_LENGTH_TOLERANCE_M + KNOWN_LENGTH_TOLERANCE_RELATIVE * given:
            raise InvalidInputError(
                f"baseline_length_m: rover {r + 1} is given as {given:.4g} m, but {int(np.sum(rows))} "
                f"fixed epochs of {epochs} measure {got:.4f} m (median): give the measured length or none"
            )


def check_grid_options(names: list[str], series: AttitudeSeries) -> None:
    """Refuses ``step_deg`` and ``window_deg`` where the likelihood grid solved no epoch: with method
    ``"auto"`` it runs only on epochs LAMBDA left unfixed (and within 100 m in baseline mode), so the
    options changed nothing."""
    if names and not np.any(series.method == "ml"):
        raise InvalidInputError(
            f"{' and '.join(names)} set the likelihood grid, which solved none of the {len(series.method)} "
            "epochs (method 'auto' runs it only where LAMBDA fixed nothing, and in baseline mode within "
            "100 m): they changed nothing; leave them out, or use method 'ml'"
        )


def check_method(method: str, series: AttitudeSeries) -> None:
    """Refuses ``method="ml"`` where the likelihood grid solved no epoch or failed (the engine then keeps
    the double-difference solution, which ``method="ml"`` did not ask for)."""
    if method != "ml":
        return
    failed = [w for w in series.warnings if "likelihood grid failed" in w]
    if failed or not np.any(series.method == "ml"):
        reason = "; ".join(failed) or "; ".join(w for w in series.warnings if "grid" in w) or "no epoch"
        raise InvalidInputError(
            f"method 'ml': the likelihood grid solved {int(np.sum(series.method == 'ml'))} of "
            f"{len(series.method)} epochs ({reason}): use method 'auto' or 'lambda', or a coarser step_deg "
            "or a window_deg"
        )


def undirected(series: AttitudeSeries, paths: list[str]) -> AttitudeSeries:
    """Baseline mode: azimuth and elevation NaN (with a :class:`ZeroBaselineWarning`) where the baseline is
    shorter than :data:`MIN_DIRECTION_BASELINE_M`, instead of the angles of a vector of noise."""
    if series.mode != "baseline":
        return series
    length = np.linalg.norm(series.baselines_enu_m[:, 0, :], axis=1)
    short = length < MIN_DIRECTION_BASELINE_M
    if not short.any():
        return series
    message = (
        f"baseline shorter than {MIN_DIRECTION_BASELINE_M} m at {int(short.sum())} of {len(short)} epochs "
        f"(longest {float(length[short].max()):.4f} m) between {paths[0]} and {paths[1]}: one antenna seen "
        "twice (the same file, or a zero-baseline receiver test); azimuth and elevation are undefined there "
        "and set to NaN, the baselines are kept"
    )
    warnings.warn(message, ZeroBaselineWarning, stacklevel=3)
    angles = series.angles_deg.copy()
    sigmas = series.angle_sigmas_deg.copy()
    angles[short] = np.nan
    sigmas[short] = np.nan
    return replace(series, angles_deg=angles, angle_sigmas_deg=sigmas, warnings=(*series.warnings, message))
