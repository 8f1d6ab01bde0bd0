"""Every number the findings quote is traced to the command that computes it.

The claims (``experiments.findings.referee``) are recomputed here from the same functions
``python -m experiments.findings`` calls (every section but the engines', about two minutes),
then:
- the README's findings section may quote claim values only: once each value is struck out, no
  digit may remain, so a number that no longer matches what the command computes fails;
- results/findings.md's referee table must hold the values computed now (it is not stale), and
  its short answers must be the text the claims make now.
Values compare as the text quotes them (rounded as printed), so the tolerance is the printed
precision.
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from experiments.findings import referee
from experiments.findings.ball import ball_section
from experiments.findings.flex_text import flex_section
from experiments.findings.metal_text import metal_section
from experiments.findings.questions import cork_section, sweet_spot_section

ROOT = Path(__file__).resolve().parents[1]
README_SECTION = "## What the findings show"


@pytest.fixture(scope="module")
def claims() -> list[referee.Claim]:
    sweet = sweet_spot_section(())[2]
    return referee.collect(sweet, cork_section()[2], metal_section()[2], ball_section()[2],
                           flex_section()[2])


def _strike(text: str, claims: list[referee.Claim]) -> str:
    """``text`` with every claim value struck out, the longest first (so that 0.52 goes
    before 0.5 can leave a stray 2)."""
    for value in sorted({c.value for c in claims}, key=len, reverse=True):
        text = text.replace(value, " ")
    return text


def test_every_readme_findings_number_is_a_claim(claims):
    readme = (ROOT / "README.md").read_text()
    assert README_SECTION in readme
    section = readme.split(README_SECTION, 1)[1].split("\n## ", 1)[0]
    prose = re.sub(r"\]\([^)]*\)", "]", section)  # link targets are paths, not numbers
    prose = re.sub(r"\b[A-Za-z_]+\d\w*", " ", prose)  # names with digits: R161, v1
    left = _strike(prose, claims)
    assert not re.search(r"\d", left), [line for line in left.splitlines()
                                         if re.search(r"\d", line)]


def test_findings_md_quotes_what_the_command_computes(claims):
    text = (ROOT / "results" / "findings.md").read_text()
    table = text.split("## Referee", 1)[1].split("\n## ", 1)[0]
    quoted = {m.group(2): m.group(1) for m in
              re.finditer(r"^\| [^|]+ \| ([^|]+) \| `([^`]+)` \|", table, re.M)}
    assert {c.key: c.value for c in claims} == quoted
    assert referee.short_answers_text(claims) in text


def test_a_changed_number_is_caught(claims):
    # the check above cannot pass vacuously: a README sentence quoting a value one unit off in
    # its last digit leaves a digit behind
    c = next(c for c in claims if c.key == "cork.n027.paper")
    wrong = c.value[:-1] + str((int(c.value[-1]) + 1) % 10)
    assert re.search(r"\d", _strike(f"corking changes the speed by {wrong} m/s", claims))
    assert not re.search(r"\d", _strike(f"corking changes the speed by {c.value} m/s", claims))
