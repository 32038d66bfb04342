"""The house counts of issue 29, for a before/after note: lines per layer, functions over 80 lines (Python
and Rust), files over 800 lines, duplicate pairs (the ``duplicates`` tool, where it is installed) and the
number of tests in the fast loop and in the full suite (``pytest --collect-only``).

A function's length is counted from its ``def`` / ``fn`` line to its last line, docstring and comments
included (Python: the :mod:`ast` end line; Rust: the brace that closes the body, found by counting braces
outside strings, characters and comments). Lines are physical lines, blank ones included.

Run from the repository root: ``python benches/python/house_counts.py [--no-tests] [--no-duplicates]``.
Compare two revisions by running it in a checkout of each (``git worktree add /tmp/before REV``). The
tests' times are not measured here (they depend on the load): ``time python -m pytest -n auto -m "not
slow" -q`` and ``time python -m pytest -n auto -q``.
"""

from __future__ import annotations

import argparse
import ast
import re
import shutil
import subprocess
import sys
from collections import Counter
from pathlib import Path

ROOT = Path.cwd()
LONG_FUNCTION = 80
LONG_FILE = 800
_RUST_FN = re.compile(r"^\s*(pub(\([^)]*\))?\s+)?((const|async|unsafe|extern\s+\"C\")\s+)*fn\s+(\w+)")


def tracked(*patterns: str) -> list[Path]:
    out = subprocess.run(["git", "ls-files", *patterns], capture_output=True, text=True, check=True).stdout
    return [ROOT / p for p in out.split()]


def layer(path: Path) -> str:
    """``python/gnssatt/<first part>``, ``rust/<crate>/src/<first part>``, or the top folder."""
    parts = path.relative_to(ROOT).parts
    if parts[:2] == ("python", "gnssatt") and len(parts) > 3:
        return "/".join(parts[:3])
    if parts[:2] == ("python", "gnssatt"):
        return "python/gnssatt (modules)"
    if parts[0] == "rust" and len(parts) > 4 and parts[2] == "src":
        return "/".join(parts[:4])
    if parts[0] == "rust":
        return "/".join(parts[:2]) + " (files)"
    return parts[0]


def python_functions(path: Path) -> list[tuple[str, int]]:
    tree = ast.parse(path.read_text(encoding="utf-8"))
    return [
        (
            f"{path.relative_to(ROOT)}:{node.lineno} {node.name}",
            (node.end_lineno or node.lineno) - node.lineno + 1,
        )
        for node in ast.walk(tree)
        if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef)
    ]


def _strip_rust(line: str, in_block: int) -> tuple[str, int]:
    """The line without comments, strings and characters (braces inside them do not count)."""
    out, i = [], 0
    while i < len(line):
        if in_block:
            if line.startswith("*/", i):
                in_block, i = in_block - 1, i + 2
            elif line.startswith("/*", i):
                in_block, i = in_block + 1, i + 2
            else:
                i += 1
        elif line.startswith("//", i):
            break
        elif line.startswith("/*", i):
            in_block, i = 1, i + 2
        elif line[i] == '"':
            j = i + 1
            while j < len(line) and line[j] != '"':
                j += 2 if line[j] == "\\" else 1
            i = j + 1
        elif line[i] == "'" and re.match(r"'(\\.|[^\\'])'", line[i:]):
            i += len(re.match(r"'(\\.|[^\\'])'", line[i:]).group(0))  # type: ignore[union-attr]
        else:
            out.append(line[i])
            i += 1
    return "".join(out), in_block


def rust_functions(path: Path) -> list[tuple[str, int]]:
    lines = path.read_text(encoding="utf-8").splitlines()
    code, block = [], 0
    for line in lines:
        stripped, block = _strip_rust(line, block)
        code.append(stripped)
    found = []
    for start, line in enumerate(code):
        m = _RUST_FN.match(line)
        if not m:
            continue
        depth, opened = 0, False
        for end in range(start, len(code)):
            text = code[end]
            if not opened and ";" in text and "{" not in text:  # a declaration without a body
                break
            depth += text.count("{") - text.count("}")
            opened = opened or "{" in text
            if opened and depth <= 0:
                found.append((f"{path.relative_to(ROOT)}:{start + 1} {m.group(5)}", end - start + 1))
                break
    return found


def test_count(marker: str | None) -> int:
    cmd = [sys.executable, "-m", "pytest", "--collect-only", "-q", "-p", "no:cacheprovider"]
    if marker:
        cmd += ["-m", marker]
    out = subprocess.run(cmd, capture_output=True, text=True).stdout
    m = re.search(r"(\d+)(?:/\d+)? tests? (?:collected|selected)", out)
    return int(m.group(1)) if m else -1


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--no-tests", action="store_true", help="skip the pytest collection (slow)")
    parser.add_argument("--no-duplicates", action="store_true", help="skip the duplicates tool")
    args = parser.parse_args()

    py = [p for p in tracked("*.py") if p.exists()]
    rs = [p for p in tracked("*.rs") if p.exists()]
    per_layer: Counter[str] = Counter()
    long_files = []
    for p in py + rs:
        n = len(p.read_text(encoding="utf-8").splitlines())
        per_layer[layer(p)] += n
        if n > LONG_FILE:
            long_files.append((str(p.relative_to(ROOT)), n))
    print("lines per layer")
    for name, n in sorted(per_layer.items()):
        print(f"  {n:7d}  {name}")
    lib_py = [p for p in py if p.relative_to(ROOT).parts[0] == "python"]
    lib_rs = [p for p in rs if p.relative_to(ROOT).parts[0] == "rust" and "src" in p.parts]
    for lang, fns in (
        ("Python (python/)", [f for p in lib_py for f in python_functions(p)]),
        ("Rust (rust/*/src)", [f for p in lib_rs for f in rust_functions(p)]),
        ("Python tests and benches", [f for p in py if p not in lib_py for f in python_functions(p)]),
    ):
        long = sorted((f for f in fns if f[1] > LONG_FUNCTION), key=lambda f: -f[1])
        print(f"functions over {LONG_FUNCTION} lines, {lang}: {len(long)} of {len(fns)}")
        for name, n in long:
            print(f"  {n:5d}  {name}")
    print(f"files over {LONG_FILE} lines: {len(long_files)}")
    for name, n in sorted(long_files, key=lambda f: -f[1]):
        print(f"  {n:5d}  {name}")
    if not args.no_duplicates and shutil.which("duplicates"):
        out = subprocess.run(["duplicates", "--seconds", "120"], capture_output=True, text=True).stdout
        print(f"duplicates (whole tree): {out.splitlines()[0] if out else '?'}")
    if not args.no_tests:
        print(f"tests: fast loop (-m 'not slow') {test_count('not slow')}, full {test_count(None)}")


if __name__ == "__main__":
    main()
