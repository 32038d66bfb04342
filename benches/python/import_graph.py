"""The import graph of the Python package, unit by unit and layer by layer, as mermaid text.

    python benches/python/import_graph.py            # print it
    python benches/python/import_graph.py --write    # replace the graph in docs/architecture.md

Drawn from the same ``ast`` walk and layer table (``LAYERS``) as ``tests/test_import_layers.py``, which
also checks that the page shows the current graph. Arrows point from importer to imported unit; imports of
``errors`` and of the shared internals (``_arrays``, ``_core``), which nearly
every unit makes, are left out to keep the picture readable.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "tests"))

import test_import_layers as layers  # noqa: E402

BEGIN = "<!-- import graph: begin -->"
END = "<!-- import graph: end -->"
UBIQUITOUS = ("errors", *layers.SHARED_INTERNALS)


def _node(unit: str) -> str:
    return "pkg" if unit == "__init__" else "u" + unit.strip("_").replace(".", "_")


def mermaid() -> str:
    """The graph as mermaid text in a plain-text fence (Sphinx has no mermaid lexer and builds with -W): one
    subgraph per layer (base at the bottom), one node per unit."""
    lines = ["```text", "flowchart BT"]
    for name, units in layers.LAYERS:
        lines.append(f"  subgraph {name}")
        lines += [f'    {_node(u)}["{"gnssatt" if u == "__init__" else u}"]' for u in units]
        lines.append("  end")
    arrows = sorted(
        {
            (layers.unit(a), layers.unit(b))
            for a, b in layers.edges()
            if layers.unit(a) != layers.unit(b) and layers.unit(b) not in UBIQUITOUS
        }
    )
    lines += [f"  {_node(a)} --> {_node(b)}" for a, b in arrows]
    lines.append("```")
    return "\n".join(lines)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--write", action="store_true", help="replace the graph in docs/architecture.md")
    args = ap.parse_args()
    graph = mermaid()
    if not args.write:
        print(graph)
        return
    doc = layers.DOC
    text = doc.read_text()
    start, end = text.index(BEGIN) + len(BEGIN), text.index(END)
    doc.write_text(text[:start] + "\n" + graph + "\n" + text[end:])


if __name__ == "__main__":
    main()
