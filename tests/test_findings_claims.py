"""Every number the findings quote is traced to the command that computes it.

The claims (``experiments.findings.referee``) are read from the referee table of a fresh
``python -m experiments.findings`` run (``conftest.findings_run``, once per test run), then:
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

ROOT = Path(__file__).resolve().parents[1]
README_SECTION = "## What the findings show"
#: The findings' short answers: from their bold heading to the next blank line.
SHORT_ANSWERS = re.compile(r"\*\*Short answers\*\*.*?\n\n", re.S)

pytestmark = pytest.mark.xdist_group("findings")


def _referee(text: str) -> dict[str, str]:
    """Claim key -> value as quoted, from a findings.md's referee table."""
    table = text.split("## Referee", 1)[1].split("\n## ", 1)[0]
    return {
        m.group(2): m.group(1).strip()
        for m in re.finditer(r"^\| [^|]+ \| ([^|]+) \| `([^`]+)` \|", table, re.M)
    }


@pytest.fixture(scope="module")
def fresh(findings_run) -> str:
    return (findings_run / "findings.md").read_text()


@pytest.fixture(scope="module")
def claims(fresh) -> dict[str, str]:
    got = _referee(fresh)
    assert len(got) > 20  # the table was read, not an empty match
    return got


def _strike(text: str, claims: dict[str, str]) -> str:
    """``text`` with every claim value struck out, the longest first (so that 0.52 goes
    before 0.5 can leave a stray 2)."""
    for value in sorted(set(claims.values()), key=len, reverse=True):
        text = text.replace(value, " ")
    return text


def test_every_readme_findings_number_is_a_claim(claims):
    readme = (ROOT / "README.md").read_text()
    assert README_SECTION in readme
    section = readme.split(README_SECTION, 1)[1].split("\n## ", 1)[0]
    prose = re.sub(r"\]\([^)]*\)", "]", section)  # link targets are paths, not numbers
    prose = re.sub(r"\b[A-Za-z_]+\d\w*", " ", prose)  # names with digits: R161, v1
    left = _strike(prose, claims)
    assert not re.search(r"\d", left), [
        line for line in left.splitlines() if re.search(r"\d", line)
    ]


def test_findings_md_quotes_what_the_command_computes(claims, fresh):
    committed = (ROOT / "results" / "findings.md").read_text()
    assert _referee(committed) == claims
    assert SHORT_ANSWERS.search(committed).group(0) == SHORT_ANSWERS.search(fresh).group(0)


def test_a_changed_number_is_caught(claims):
    # the check above cannot pass vacuously: a README sentence quoting a value one unit off in
    # its last digit leaves a digit behind
    value = claims["cork.n027.paper"]
    i = max(i for i, ch in enumerate(value) if ch.isdigit())  # its last digit, one unit off
    wrong = value[:i] + str((int(value[i]) + 1) % 10) + value[i + 1 :]
    assert re.search(r"\d", _strike(f"corking changes the speed by {wrong} m/s", claims))
    assert not re.search(r"\d", _strike(f"corking changes the speed by {value} m/s", claims))
