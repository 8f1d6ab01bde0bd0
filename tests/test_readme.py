"""The README guides rather than reports: at most 250 lines, every file it links exists, every
command it lists runs (``--help``), and its engines table says what the records say."""

from __future__ import annotations

import importlib
import pkgutil
import re

import pytest

import adapters
from experiments.core.io import ROOT
from experiments.report import readme

README = (ROOT / "README.md").read_text()
MAX_LINES = 250


def _table(heading: str) -> list[list[str]]:
    """The rows of the first markdown table after ``heading``, cells stripped."""
    lines = README.split(heading, 1)[1].splitlines()
    start = next(i for i, line in enumerate(lines) if line.startswith("|"))
    block = []
    for line in lines[start:]:
        if not line.startswith("|"):
            break
        block.append([c.strip() for c in line.strip("|").split("|")])
    return block[2:]


def test_short_enough_to_read():
    assert README.count("\n") <= MAX_LINES


def test_every_linked_file_exists():
    links = re.findall(r"\]\(([^)#]+)(?:#[^)]*)?\)", README)
    assert links
    assert [p for p in links if not (ROOT / p).exists()] == []


@pytest.mark.parametrize("row", _table("## The commands in brief"), ids=lambda r: r[0])
def test_every_listed_command_runs(row, capsys):
    for name in re.findall(r"`(\w+)", row[0]):
        module = importlib.import_module(f"experiments.{name}")
        with pytest.raises(SystemExit) as exit_:
            module.main(["--help"])
        assert exit_.value.code == 0 and "usage:" in capsys.readouterr().out


def test_the_engines_table_is_the_one_the_results_give():
    """Every number in it comes from results/ (``experiments.report.readme``): a results
    regeneration that moves one without the README following fails here."""
    block = README.split(readme.BEGIN, 1)[1].split(readme.END, 1)[0].strip()
    assert block == readme.engines_table(ROOT / "results")
    built_in = {m.name for m in pkgutil.iter_modules(adapters.__path__) if m.ispkg}
    assert {row[0] for row in _table(readme.BEGIN)} == built_in
