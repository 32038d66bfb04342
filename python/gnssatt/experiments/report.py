"""The common output of every experiment: one JSON document and a printed comparison table."""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any

__all__ = ["format_table", "write_report"]


def write_report(
    out: Path, experiment: str, paper: dict[str, Any], measured: dict[str, Any], runs: int, seed: int
) -> dict[str, Any]:
    """Write ``out/<experiment>.json`` as ``{"experiment", "paper", "measured", "runs", "seed"}``.

    Quantity names carry their unit (``heading_rms_deg``); a quantity the paper does not give is ``None``
    in ``paper``.
    """
    doc = {
        "experiment": experiment,
        "paper": _json_safe(paper),
        "measured": _json_safe(measured),
        "runs": runs,
        "seed": seed,
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


def _fmt(value: Any) -> str:
    if value is None:
        return "-"
    if isinstance(value, float):
        return "nan" if math.isnan(value) else f"{value:.4g}"
    return str(value)


def format_table(doc: dict[str, Any]) -> str:
    """A plain-text table of every quantity, paper next to measured (no paper column where ``paper`` is
    empty)."""
    names = list(dict.fromkeys([*doc["paper"], *doc["measured"]]))
    rows = [("quantity", "paper", "measured")] + [
        (n, _fmt(doc["paper"].get(n)), _fmt(doc["measured"].get(n))) for n in names
    ]
    if not doc["paper"]:
        rows = [(r[0], r[2]) for r in rows]
    widths = [max(len(r[i]) for r in rows) for i in range(len(rows[0]))]
    lines = [f"{doc['experiment']}  (runs={doc['runs']}, seed={doc['seed']})"]
    for k, r in enumerate(rows):
        lines.append(
            "  ".join(
                c.ljust(w) if i == 0 else c.rjust(w) for i, (c, w) in enumerate(zip(r, widths, strict=True))
            )
        )
        if k == 0:
            lines.append("  ".join("-" * w for w in widths))
    return "\n".join(lines)
