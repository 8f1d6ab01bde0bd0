"""One conformance suite for every registered engine, ids = engine and check: each check of
``experiments.core.check_engine`` (the one a plug-in author runs) that applies to the engine's
reference contact, run as its own test.

Each check states the equation it holds the engine to (its docstring) and takes its tolerance
from ``experiments.core.judge`` (rounding at the engine's float precision, the slide of the
contact foot while the turning bat is first seen ``overlap_m`` deep, a compliant contact's
first-order restitution error): checks against closed form only, since each engine within its
bound of theory puts any two within twice that of each other.
"""

from __future__ import annotations

import pytest

import adapters
from experiments.core import check

#: The checks every engine passes in the fast tier (`make test`); the rest run in `make
#: test-all`. A compliant contact's law stands in for the rigid bat's closed forms.
ESSENTIALS = (
    "mass_read_back",
    "restitution",
    "still_bat",
    "swinging_bat",
    "stateless",
    "law_conformance",
)
CASES = [
    pytest.param(
        name,
        c,
        id=f"{name}-{c}",
        marks=pytest.mark.essential if c in ESSENTIALS else pytest.mark.full,
    )
    for name in adapters.names()
    for c in check.applicable(name)
]


@pytest.mark.parametrize("name,check_name", CASES)
def test_engine_conforms(name, check_name):
    result = check.run_check(name, check_name)
    assert result.passed, result.detail


def test_every_engine_is_checked_against_the_answer_its_contact_converges_to():
    # rigid contacts get the closed-form checks, compliant ones their law's; both get the rest
    for name in adapters.names():
        got = set(check.applicable(name))
        rigid = adapters.contact_reference(name) is adapters.ContactReference.RIGID_IMPULSE
        assert ("still_bat" in got) == rigid and ("law_conformance" in got) == (not rigid)
        assert {"mass_read_back", "stateless", "bad_settings_rejected"} <= got
