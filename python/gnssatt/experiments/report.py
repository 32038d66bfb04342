"""The common output of every experiment: one JSON document and a printed comparison table."""

from __future__ import annotations

import json
import math
import subprocess
from pathlib import Path
from typing import Any

__all__ = ["format_table", "results_page", "write_report"]

#: The results page of each experiment whose name does not give it.
_PAGES = {"recorded-methods": "recorded_data"}


def results_page(experiment: str) -> str:
    """The results page that explains ``experiment``'s numbers, as a path in the repository."""
    return f"docs/results/{_PAGES.get(experiment, experiment.replace('-', '_'))}.md"


def _commit() -> str | None:
    """The git commit of the source tree this package runs from, or None (an installed wheel, no git)."""
    package = Path(__file__).resolve().parents[1]
    try:
        top = subprocess.run(
            ["git", "rev-parse", "--show-toplevel", "HEAD"],
            cwd=package,
            capture_output=True,
            text=True,
            timeout=10,
            check=True,
        ).stdout.split()
    except (OSError, subprocess.SubprocessError):
        return None
    # Only the checkout that holds this very package: a wheel installed into a virtual environment inside
    # some other clone must not report that clone's commit.
    if len(top) != 2 or Path(top[0]).resolve() / "python" / "gnssatt" != package:
        return None
    return top[1]


def _verdict(paper: Any, measured: Any, factor: float | None, why_missing: str | None) -> str:
    if why_missing is not None:
        return "not computed"
    if paper is None:
        return "no paper number"
    if isinstance(paper, str):
        return "see results page"
    if measured is None or factor is None:
        return "not judged"
    p, m = float(paper), float(measured)
    if not (math.isfinite(m) and p > 0 and m > 0):
        return "differs"
    return "agrees" if p / factor <= m <= p * factor else "differs"


def write_report(
    out: Path,
    experiment: str,
    paper: dict[str, Any],
    measured: dict[str, Any],
    runs: int,
    seed: int,
    *,
    tolerance: dict[str, float] | None = None,
    unavailable: dict[str, str] | None = None,
) -> dict[str, Any]:
    """Write ``out/<experiment>.json`` and return it.

    Parameters
    ----------
    out
        Folder of the report (created if missing).
    experiment
        The experiment's name, e.g. ``"matrix-method"``.
    paper
        The paper's numbers by quantity (names carry their unit, ``heading_rms_deg``); ``None`` where the
        paper gives none, a string where it states a conclusion without numbers.
    measured
        The measured numbers by quantity.
    runs, seed
        Monte Carlo runs and the root random seed that produced ``measured``.
    tolerance
        For a quantity compared with the paper: the factor within which measured agrees with paper
        (``paper / f <= measured <= paper * f``); the experiment says why that factor where it passes
        it, and ``docs/results/index.md`` lists them.
    unavailable
        For a quantity left ``None`` because an optional extra is missing: what to install.

    Returns
    -------
    dict
        ``{"experiment", "paper", "measured", "tolerance", "verdict", "unavailable", "runs", "seed",
        "version", "commit", "results_page"}``: ``verdict`` per quantity (``agrees``, ``differs``, ``no
        paper number``, ``see results page``, ``not judged``, ``not computed``); ``commit`` the git commit
        of the source checkout, or None for an installed package; NaN and infinities as ``null``.
    """
    from gnssatt._core import __version__

    tolerance, unavailable = tolerance or {}, unavailable or {}
    names = list(dict.fromkeys([*paper, *measured]))
    doc = {
        "experiment": experiment,
        "paper": _json_safe(paper),
        "measured": _json_safe(measured),
        "tolerance": tolerance,
        "verdict": {
            n: _verdict(paper.get(n), measured.get(n), tolerance.get(n), unavailable.get(n)) for n in names
        },
        "unavailable": unavailable,
        "runs": runs,
        "seed": seed,
        "version": __version__,
        "commit": _commit(),
        "results_page": results_page(experiment),
    }
    out.mkdir(parents=True, exist_ok=True)
    (out / f"{experiment}.json").write_text(json.dumps(doc, indent=2, allow_nan=False) + "\n")
    return doc


def _json_safe(value: Any) -> Any:
    """``value`` with every NaN or infinity replaced by ``None`` (JSON ``null``), recursively.

    A statistic of a study can be undefined (no fix in any run, a run count of one): JSON has no NaN, and
    strict readers refuse Python's ``NaN`` token, so such a value is written as ``null``.
    """
    if isinstance(value, dict):
        return {k: _json_safe(v) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return [_json_safe(v) for v in value]
    if isinstance(value, float) and not math.isfinite(value):
        return None
    return value


def _fmt(value: Any, missing: str = "-") -> str:
    if value is None:
        return missing
    if isinstance(value, float):
        return "nan" if math.isnan(value) else f"{value:.4g}"
    return str(value)


def format_table(doc: dict[str, Any]) -> str:
    """A plain-text table of every quantity: paper, measured, tolerance and verdict (only measured where
    ``paper`` is empty), then where the numbers are explained."""
    names = list(dict.fromkeys([*doc["paper"], *doc["measured"]]))
    unavailable = doc.get("unavailable", {})
    tolerance = doc.get("tolerance", {})
    verdict = doc.get("verdict", {})
    rows = [("quantity", "paper", "measured", "tolerance", "verdict")] + [
        (
            n,
            _fmt(doc["paper"].get(n)),
            unavailable[n] if n in unavailable else _fmt(doc["measured"].get(n), "undefined"),
            f"x{tolerance[n]:g}" if n in tolerance else "-",
            "" if verdict.get(n) == "no paper number" else verdict.get(n, ""),
        )
        for n in names
    ]
    if not doc["paper"]:
        rows = [(r[0], r[2]) for r in rows]
    widths = [max(len(r[i]) for r in rows) for i in range(len(rows[0]))]
    lines = [f"{doc['experiment']}  (runs={doc['runs']}, seed={doc['seed']})"]
    for k, r in enumerate(rows):
        lines.append(
            "  ".join(
                c.ljust(w) if i in (0, 4) else c.rjust(w)
                for i, (c, w) in enumerate(zip(r, widths, strict=True))
            ).rstrip()
        )
        if k == 0:
            lines.append("  ".join("-" * w for w in widths))
    if doc["paper"]:
        lines.append("tolerance: the factor within which measured agrees with the paper")
    lines.append(f"why these numbers: {doc.get('results_page', results_page(doc['experiment']))}")
    return "\n".join(lines)
