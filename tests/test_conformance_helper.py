"""``experiments.core.conformance``: the conformance suite as a plug-in author's pytest cases,
on a record that is not registered (the toy plug-in's, as its author would before packaging
it). Every check that applies passes on the toy; its twin whose batted ball is 1% too fast
fails the checks that measure v1 against theory, declared here as expected failures with
their reason (strict: a declared failure that passes fails the test)."""

from __future__ import annotations

import sys

import pytest

import adapters
from experiments.core.conformance import parametrize_with_checks, record_of

from .conftest import PLUGIN

sys.path.insert(0, str(PLUGIN.parent))
import toy_engine  # noqa: E402 - the plug-in's module, from its own folder

#: What a 1% faster ball fails, and why: each compares v1 (or the energy it carries) with
#: theory far inside 1%.
FAULTY_FAILS = {
    name: "v1 1% too fast"
    for name in (
        "restitution",
        "still_bat",
        "energy_at_e1",
        "swinging_bat",
        "corked_bat",
        "oblique",
    )
}


@parametrize_with_checks([toy_engine.ToyEngine])
def test_the_toy_plugin_conforms(engine, check):
    check(engine)


@parametrize_with_checks([toy_engine.FAULTY], expected_failures=FAULTY_FAILS)
def test_its_faulty_twin_fails_what_it_should(engine, check):
    check(engine)


def test_nothing_is_left_registered_and_a_non_engine_is_named():
    assert toy_engine.RECORD.name not in adapters.names()
    with pytest.raises(TypeError, match="is not an engine"):
        record_of(42)


def test_the_interface_page_names_every_member():
    # the one page a plug-in author reads lists every member of both forms
    doc = adapters.interface.__doc__
    for cls in (adapters.Engine, adapters.BatchedEngine):
        members = {n for n in vars(cls) if not n.startswith("_")} | {"record"}
        missing = sorted(m for m in members if f"``{m}``" not in doc)
        assert not missing, f"{cls.__name__}: {missing} not on the interface page"
