"""Bad command lines: exit status 2 and a one-line message, never a traceback (a representative subset;
``benches/python/hostile_inputs.py`` runs them all)."""

from __future__ import annotations

import pytest

from . import cli_cases, scenario
from . import outcomes as oc
from .conftest import report

SUBSET = (
    "missing nav file",
    "a folder as obs",
    "unwritable --out",
    "--elevation-mask nan",
    "--window -5",
    "reproduce --runs 10**12",
)


def all_cases() -> list[cli_cases.CliCase]:
    s = scenario.rinex_array()
    bad = scenario.folder() / "cut.24o"
    text = s.obs_paths[0].read_bytes()
    bad.write_bytes(text[: len(text) * 2 // 3 + 7])
    return cli_cases.cases(s.obs_paths, s.nav_path, bad, scenario.folder())


@pytest.mark.slow
@pytest.mark.parametrize("label", SUBSET)
def test_cli_refuses_without_traceback(label: str) -> None:
    (case,) = [c for c in all_cases() if c.label == label]
    outcome, detail, _ = cli_cases.run_case(case)
    bad = [] if outcome == oc.REFUSED else [f"gnssatt {' '.join(case.argv)}: {outcome}: {detail}"]
    assert not bad, report(bad)
