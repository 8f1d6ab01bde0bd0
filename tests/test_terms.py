"""The judge's tolerance table: every term has its value and its reason in one place
(``experiments.core.terms``), and no part of the judge keeps a tolerance of its own."""

from __future__ import annotations

import ast
from pathlib import Path

from experiments.core import terms

CORE = Path(terms.__file__).parent
#: The judge's parts: they read their tolerances from ``terms``. A module constant of theirs
#: that is not a tolerance is named here with what it is.
JUDGES = ("judge.py", "friction_judge.py", "chain.py", "episode.py")
NOT_TOLERANCES = {"APPROACH_STEPS": "chain.py: free steps before the touch (set-up)"}


def _numeric_constants(path: Path) -> set[str]:
    tree = ast.parse(path.read_text(encoding="utf-8"))
    return {
        t.id
        for node in tree.body
        if isinstance(node, ast.Assign)
        and isinstance(node.value, ast.Constant)
        and type(node.value.value) in (int, float)
        for t in node.targets
        if isinstance(t, ast.Name) and t.id.isupper()
    }


def test_every_term_has_a_value_and_a_reason():
    declared = _numeric_constants(CORE / "terms.py")
    assert declared == set(terms.WHY), declared ^ set(terms.WHY)
    for name, value, why in terms.table():
        assert value > 0 and len(why) > 20, name


def test_no_part_of_the_judge_keeps_a_tolerance_of_its_own():
    for module in JUDGES:
        own = _numeric_constants(CORE / module) - set(NOT_TOLERANCES)
        assert not own, f"{module} declares {sorted(own)}: move them to terms.py with a reason"
