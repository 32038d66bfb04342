"""Metrics of one run against its reference: fix rate, wrong fixes, baseline and heading errors."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from .solutions import EPOCH_TOLERANCE_S, Solutions, match_epochs


@dataclass(frozen=True)
class Reference:
    """Reference baseline: ``enu_m`` (3,) for every epoch, or per epoch keyed by ``time_s``."""

    enu_m: NDArray[np.float64]
    time_s: NDArray[np.float64] | None
    description: str
    judges_fixes: bool  # False when only good to metres: no wrong-fix count

    def at(self, time_s: NDArray[np.float64]) -> NDArray[np.float64]:
        """(n, 3) reference at the epochs ``time_s`` (NaN rows where it has none)."""
        if self.time_s is None:
            return np.broadcast_to(self.enu_m, (len(time_s), 3)).copy()
        i = match_epochs(time_s, self.time_s)
        return np.where((i >= 0)[:, None], self.enu_m[np.maximum(i, 0)], np.nan)


def metrics(
    sol: Solutions, ref: Reference, n_epochs: int, wrong_fix_m: float
) -> dict[str, float | int | None]:
    """Fix rate over ``n_epochs``, wrong fixes, and 3-D baseline error statistics (m).

    Epochs the reference lacks are left out of the errors and wrong fixes (``unreferenced`` counts them);
    ``wrong_fixes`` is None when the reference cannot judge fixes; statistics of an empty set are None.
    """
    known = np.all(np.isfinite(ref.at(sol.time_s)), axis=1)
    err = np.linalg.norm(sol.enu_m[known] - ref.at(sol.time_s[known]), axis=1)
    fixed_err = err[sol.fixed[known]]
    first_fix = sol.time_s[sol.fixed][0] - sol.time_s[0] if sol.fixed.any() else None
    return {
        "epochs": n_epochs,
        "solved": len(sol.time_s),
        "fixed": int(sol.fixed.sum()),
        "fix_rate": float(sol.fixed.sum()) / n_epochs if n_epochs else None,
        "wrong_fixes": int(np.sum(fixed_err > wrong_fix_m)) if ref.judges_fixes else None,
        "first_fix_s": None if first_fix is None else float(first_fix),
        "unreferenced": int(np.sum(~known)),
        "error_fixed_median_m": _pct(fixed_err, 50),
        "error_fixed_p95_m": _pct(fixed_err, 95),
        "error_all_median_m": _pct(err, 50),
    }


def _pct(x: NDArray[np.float64], q: float) -> float | None:
    return float(np.percentile(x, q)) if x.size else None


def heading_deg(enu_m: NDArray[np.float64]) -> NDArray[np.float64]:
    """Azimuth of ENU vectors from North towards East, degrees."""
    return np.degrees(np.arctan2(enu_m[:, 0], enu_m[:, 1]))


def platform_metrics(
    sol: Solutions, time_s: NDArray[np.float64], truth_enu_m: NDArray[np.float64],
    outage_ends_s: Sequence[float], wrong_fix_m: float,
) -> dict[str, float | int | None]:  # fmt: skip
    """Fix rate over every epoch of the session (``time_s``, its truth ``truth_enu_m``), wrong fixes (a
    fixed baseline more than ``wrong_fix_m`` from the truth), time to first fix (the first fixed epoch
    less the session's first epoch, s), time to re-fix after each outage (its first fixed epoch at or
    after the outage's end less the end; the longest, None if one never re-fixes), and the RMS of the
    heading error over fixed and over all solved epochs (degrees)."""
    i = match_epochs(sol.time_s, time_s)
    known = i >= 0
    err = np.linalg.norm(sol.enu_m[known] - truth_enu_m[i[known]], axis=1)
    fixed = sol.fixed[known]
    t_fix = sol.time_s[known][fixed]
    dh = heading_deg(sol.enu_m[known]) - heading_deg(truth_enu_m[i[known]])
    dh = (dh + 180.0) % 360.0 - 180.0
    refix: list[float] = []
    for end in outage_ends_s:
        after = t_fix[t_fix >= end - EPOCH_TOLERANCE_S]
        refix.append(float(after[0] - end) if after.size else float("inf"))
    rms = lambda x: float(np.sqrt(np.mean(x**2))) if x.size else None  # noqa: E731
    return {
        "epochs": len(time_s),
        "solved": int(known.sum()),
        "fixed": int(fixed.sum()),
        "fix_rate": float(fixed.sum()) / len(time_s),
        "wrong_fixes": int(np.sum(err[fixed] > wrong_fix_m)),
        "first_fix_s": float(t_fix[0] - time_s[0]) if t_fix.size else None,
        "refix_s": (None if not refix or not np.isfinite(max(refix)) else max(refix)) if refix else None,
        "refix_missed": int(sum(not np.isfinite(x) for x in refix)),
        "outages": len(refix),
        "heading_rms_fixed_deg": rms(dh[fixed]),
        "heading_rms_all_deg": rms(dh),
    }


def pair_solutions(a: Solutions, b: Solutions) -> Solutions:
    """Antenna 1 - antenna 0 from two base -> antenna solutions: the epochs both have, fixed where both
    are."""
    i = match_epochs(b.time_s, a.time_s)
    ok = i >= 0
    return Solutions(
        b.time_s[ok], b.enu_m[ok] - a.enu_m[i[ok]], b.fixed[ok] & a.fixed[i[ok]], "pos pair difference"
    )
