"""Every code block of the README, and of the results pages its results moved to, works as printed.

Python and shell blocks run verbatim, each in a fresh subprocess in an empty folder; the README's
install-and-run blocks (those starting with ``pip install``) are what ``.ci/run`` runs, so they must appear
there word for word (the README's "Developing" blocks are checked against the project's settings
instead), except the main job: the quick ``reproduce --all`` took 16 minutes on the shared 2-core
machine, too long for CI, and is run by hand before a release. The results pages (``docs/results/*.md``)
hold the reproduction results that were in the README; their shell and Python blocks (the recorded-data
command) run the same way.
"""

from __future__ import annotations

import os
import shlex
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
RESULTS = sorted((ROOT / "docs" / "results").glob("*.md"))


def fenced_blocks(text: str) -> list[tuple[str, str]]:
    """``(info, code)`` of every fenced block (info: what follows the opening backticks, e.g. ``bash`` or a
    MyST directive such as ``{image} file.png``), the code with a final newline."""
    blocks, info, code = [], None, []
    for line in text.splitlines(keepends=True):
        if info is None and line.startswith("```"):
            info, code = line[3:].strip(), []
        elif info is not None and line.rstrip("\n") == "```":
            blocks.append((info, "".join(code)))
            info = None
        elif info is not None:
            code.append(line)
    assert info is None, "unclosed code block"
    return blocks


def section(text: str, heading: str) -> str:
    """The text of the README's ``## heading`` section, up to the next ``## `` heading."""
    start = text.index(f"\n## {heading}\n")
    end = text.find("\n## ", start + 1)
    return text[start : end if end != -1 else len(text)]


README = (ROOT / "README.md").read_text()
BLOCKS = fenced_blocks(README)
#: The developer loop (a virtual environment in the clone, an incremental build): checked against the
#: project's settings below, not run here, where it would build the extension a second time.
DEVELOP = fenced_blocks(section(README, "Developing"))
INSTALLS = [code for lang, code in BLOCKS if lang == "bash" and code.startswith("pip install")]
RUNS = [
    ("README", lang, code) for lang, code in BLOCKS if code not in INSTALLS and (lang, code) not in DEVELOP
] + [
    (page.stem, lang, code)
    for page in RESULTS
    for lang, code in fenced_blocks(page.read_text())
    if lang in ("bash", "python")
]
MAIN_JOB = "pip install . && gnssatt reproduce --all --out out\n"


def test_blocks_are_python_or_bash() -> None:
    assert len(BLOCKS) >= 5
    assert {lang for lang, _ in BLOCKS} <= {"python", "bash"}


def test_the_developer_loop_names_what_the_project_defines() -> None:
    tomllib = pytest.importorskip("tomllib")  # Python 3.11+
    code = "".join(c for _, c in DEVELOP)
    cargo = tomllib.loads((ROOT / "Cargo.toml").read_text())
    project = tomllib.loads((ROOT / "pyproject.toml").read_text())
    assert "maturin develop --profile quick --extras test,dev" in code
    assert "quick" in cargo["profile"] and "dev" in project["project"]["optional-dependencies"]
    assert 'python -m pytest -n auto -m "not slow"' in code
    assert any(m.startswith("slow:") for m in project["tool"]["pytest"]["ini_options"]["markers"])


def test_install_blocks_are_what_ci_runs() -> None:
    ci_lines = {line.strip() for line in (ROOT / ".ci" / "run").read_text().splitlines()}
    assert MAIN_JOB in INSTALLS
    checked = [code for code in INSTALLS if code != MAIN_JOB]
    assert len(checked) >= 2  # the test command and the wheel build
    for code in checked:
        assert code.strip() in ci_lines, code


def _launchers(folder: Path) -> dict[str, str]:
    """Environment with ``python`` and ``gnssatt`` on PATH: this interpreter and its ``gnssatt.cli:main``."""
    folder.mkdir()
    exe = shlex.quote(sys.executable)
    scripts = {
        "python": f'exec {exe} "$@"',
        "gnssatt": f'exec {exe} -c "import sys; from gnssatt.cli import main; sys.exit(main())" "$@"',
    }
    for name, body in scripts.items():
        path = folder / name
        path.write_text(f"#!/bin/sh\n{body}\n")
        path.chmod(0o755)
    return {**os.environ, "PATH": f"{folder}{os.pathsep}{os.environ.get('PATH', '')}"}


def test_results_pages_keep_the_recorded_data_command() -> None:
    # The README's recorded-data command moved with its results: it must still run here.
    assert any("gnssatt attitude" in code for page, _, code in RUNS if page == "recorded_data")


@pytest.mark.slow
@pytest.mark.parametrize(
    ("page", "lang", "code"), RUNS, ids=[f"{page}-{i}-{lang}" for i, (page, lang, _) in enumerate(RUNS)]
)
def test_block_runs_verbatim(page: str, lang: str, code: str, tmp_path: Path) -> None:
    env = _launchers(tmp_path / "bin")
    work = tmp_path / "work"
    work.mkdir()
    if lang == "python":
        # As a script file, as a user pastes it: process-pool workers re-import it.
        (work / "block.py").write_text(code)
        cmd = [sys.executable, "block.py"]
    else:
        cmd = ["bash", "-e", "-o", "pipefail", "-c", code]
    res = subprocess.run(cmd, cwd=work, env=env, capture_output=True, text=True, timeout=600)
    assert res.returncode == 0, f"{res.stdout[-3000:]}\n{res.stderr[-3000:]}"
