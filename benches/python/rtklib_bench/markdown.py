"""The markdown tables: the datasets' (``RTKLIB | gnssatt`` side by side) and the platforms'."""

from __future__ import annotations


def _cell(x: float | int | None, fmt: str, scale: float = 1.0) -> str:
    return "-" if x is None else format(x * scale, fmt)


def _tool_cells(t: dict[str, object], notes: list[str], where: str) -> list[str]:
    """The six table cells of one tool's run; a note (why none, or a caveat) gets a numbered marker."""
    if t.get("same_as_above"):
        return ["〃"] * 7
    m = t["metrics"]
    note = str(t["note"])
    if isinstance(m, dict) and m["solved"] == 0:
        note = note or "no epoch solved"
    mark = ""
    if note:
        notes.append(f"{where}: {note}")
        mark = f" [{len(notes)}]"
    if not isinstance(m, dict):
        return [f"n/a{mark}"] + ["n/a"] * 6
    wall = t["median_wall_s"]
    per = None if wall is None else float(wall) / float(m["epochs"])  # type: ignore[arg-type]
    return [
        _cell(m["fix_rate"], ".1f", 100) + mark,
        _cell(m["wrong_fixes"], ".0f"),
        _cell(m.get("first_fix_s"), ".0f"),
        f"{_cell(m['error_fixed_median_m'], '.1f', 1e3)}/{_cell(m['error_fixed_p95_m'], '.1f', 1e3)}",
        _cell(m["error_all_median_m"], ".1f", 1e3),
        _cell(wall, ".2f"),  # type: ignore[arg-type]
        _cell(per, ".2f", 1e3),
    ]


def table(rows: list[dict[str, object]]) -> str:
    """One markdown table, ``RTKLIB | gnssatt`` side by side in each metric's column, then the notes."""
    lines = [
        "| data | mode | sys | f | fixed % R \\| g | wrong R \\| g | first fix s R \\| g "
        "| err fixed med/95 mm R \\| g | err all med mm R \\| g | wall s R \\| g | ms/epoch R \\| g |",
        "|" + "---|" * 11,
    ]
    notes: list[str] = []
    for row in rows:
        key = f"{row['dataset']} {row['mode']} {row['systems']} f{row['frequencies']}"
        rtk_cells = _tool_cells(row["rtklib"], notes, f"{key} RTKLIB")  # type: ignore[arg-type]
        our_cells = _tool_cells(row["gnssatt"], notes, f"{key} gnssatt")  # type: ignore[arg-type]
        pairs = [f"{a} \\| {b}" for a, b in zip(rtk_cells, our_cells, strict=True)]
        lines.append(
            f"| {row['dataset']} | {row['mode']} | {row['systems']} | {row['frequencies']} | "
            + " | ".join(pairs)
            + " |"
        )
    return "\n".join(lines + [""] + [f"[{i}] {n}" for i, n in enumerate(notes, 1)])


def platform_table(rows: list[dict[str, object]]) -> str:
    """Markdown table of the platform runs, one row per (platform, profile, tool, mode), then notes."""
    lines = [
        "| platform | profile | tool | mode | fixed % | wrong | first fix s | re-fix s "
        "| heading RMS fixed deg | heading RMS all deg | wall s |",
        "|" + "---|" * 11,
    ]
    notes: list[str] = []
    for r in rows:
        m = r.get("metrics")
        mark = ""
        if r.get("note"):
            notes.append(f"{r['platform']} {r['profile']} {r['tool']} {r['mode']}: {r['note']}")
            mark = f" [{len(notes)}]"
        if not isinstance(m, dict):
            cells = [f"n/a{mark}"] + ["n/a"] * 6
        else:
            refix = m["refix_s"]
            if m["outages"] == 0:
                refix_cell = "-"
            elif m["refix_missed"]:
                refix_cell = f"never ({m['refix_missed']}/{m['outages']})"
            else:
                refix_cell = _cell(refix, ".1f")
            cells = [
                _cell(m["fix_rate"], ".1f", 100) + mark,
                _cell(m["wrong_fixes"], ".0f"),
                _cell(m["first_fix_s"], ".1f"),
                refix_cell,
                _cell(m["heading_rms_fixed_deg"], ".3f"),
                _cell(m["heading_rms_all_deg"], ".2f"),
                _cell(r.get("wall_s"), ".2f"),  # type: ignore[arg-type]
            ]
        lines.append(
            f"| {r['platform']} | {r['profile']} | {r['tool']} | {r['mode']} | " + " | ".join(cells) + " |"
        )
    return "\n".join(lines + [""] + [f"[{i}] {n}" for i, n in enumerate(notes, 1)])
