"""How an episode ended and the physical outcome that follows (``experiments.core.endings``):
each ``Ending`` code has its label, and ``classify`` applies the README's table in order,

    non_finite/jumped -> non_finite, contact_flag -> error, passed (or the budget spent without a
    contact) -> tunnelled, missed -> no_contact, budget -> no_separation, ball beyond the axis
    (side <= 0) -> tunnelled, deeper than r_ball + r_bat -> penetration,
    KE1 > KE0 (1 + allowance) -> energy_gained, else sound,

the first rule that holds deciding, alike for one world (Python floats) and for a batch (numpy).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import adapters
from experiments.core import geometry as g
from experiments.core.endings import LABELS, Ending, Physics, classify
from experiments.core.judge import energy_allowance

from .conftest import cheapest

#: r_ball + r_bat of the classified impacts (m): any positive reach will do.
REACH_M = 0.07
#: A relative energy gain taken as rounding (the rule's own parameter; ``judge`` derives it).
ALLOWANCE = 1e-6
#: A sound episode's end: separated, on its side of the axis, shallow, energy lost.
SOUND = dict(ended=Ending.SEPARATED, first=2, peak_m=1e-9, side_m=0.05, ke0=100.0, ke1=30.0)


def _one(**changes) -> Physics:
    """The physical outcome of one world (Python floats) with ``SOUND``'s values but ``changes``."""
    k = {**SOUND, **changes}
    got = classify(
        g.SCALARS,
        k["ended"],
        k["first"],
        k["peak_m"],
        k["side_m"],
        REACH_M,
        k["ke0"],
        k["ke1"],
        ALLOWANCE,
    )
    return Physics(got)


def test_codes_are_small_integers_and_none_is_falsy():
    # codes index LABELS and are compared in numpy: distinct small non-negative integers, and
    # NONE ("not yet") the only false one, so `if ended` reads "it has ended"
    codes = [int(e) for e in Ending]
    assert codes == list(range(len(Ending)))
    assert [bool(e) for e in Ending] == [e is not Ending.NONE for e in Ending]


def test_labels_spell_each_ending_and_index_by_array():
    # LABELS[code] is the ending's name in lower case ('' for NONE); an array of codes gives
    # an array of labels in the same order, as a table's column
    for e in Ending:
        assert LABELS[e] == ("" if e is Ending.NONE else e.name.lower())
    codes = np.array([Ending.SEPARATED, Ending.NONE, Ending.PASSED])
    assert list(LABELS[codes]) == ["separated", "", "passed"]


@pytest.mark.parametrize(
    "changes,status",
    [
        ({}, Physics.SOUND),
        ({"ended": Ending.LEFT_CYLINDER}, Physics.SOUND),
        ({"ended": Ending.NON_FINITE}, Physics.NON_FINITE),
        ({"ended": Ending.JUMPED}, Physics.NON_FINITE),
        ({"ended": Ending.CONTACT_FLAG}, Physics.ERROR),
        ({"ended": Ending.PASSED, "first": -1}, Physics.TUNNELLED),
        ({"ended": Ending.BUDGET, "first": -1}, Physics.TUNNELLED),
        ({"ended": Ending.MISSED, "first": -1}, Physics.NO_CONTACT),
        ({"ended": Ending.BUDGET}, Physics.NO_SEPARATION),
        ({"side_m": -0.01}, Physics.TUNNELLED),
        ({"side_m": 0.0}, Physics.TUNNELLED),
        ({"peak_m": 1.5 * REACH_M}, Physics.PENETRATION),
        ({"ke1": 101.0}, Physics.ENERGY_GAINED),
    ],
)
def test_each_rule_gives_its_status(changes, status):
    # one rule of the table at a time, on an otherwise sound episode
    assert _one(**changes) is status


@pytest.mark.parametrize(
    "changes,status",
    [
        # a blow-up says nothing about where the ball is or what energy it has
        (
            {"ended": Ending.NON_FINITE, "side_m": -1.0, "peak_m": 1.0, "ke1": 1e9},
            Physics.NON_FINITE,
        ),
        # a contact flag its geometry denies: the adapter's error, whatever the state says
        ({"ended": Ending.CONTACT_FLAG, "side_m": -1.0, "ke1": 1e9}, Physics.ERROR),
        # a ball beyond the axis is deeper than the reach: it passed, not penetrated
        ({"side_m": -0.01, "peak_m": 2.0 * REACH_M}, Physics.TUNNELLED),
        # too deep and too energetic: the penetration is the cause, named first
        ({"peak_m": 2.0 * REACH_M, "ke1": 1e9}, Physics.PENETRATION),
        # still touching at the budget while having gained energy: no_separation
        ({"ended": Ending.BUDGET, "ke1": 1e9}, Physics.NO_SEPARATION),
    ],
)
def test_the_first_rule_that_holds_wins(changes, status):
    assert _one(**changes) is status


def test_a_depth_of_exactly_the_reach_is_not_penetration():
    # penetration is deeper than r_ball + r_bat (strict): a centre on the axis line is allowed
    assert _one(peak_m=REACH_M) is Physics.SOUND
    assert _one(peak_m=math.nextafter(REACH_M, math.inf)) is Physics.PENETRATION


@pytest.mark.parametrize("ke0", [1e-3, 1.0, 137.0])
def test_energy_allowance_boundary(ke0):
    # KE1 > KE0 (1 + allowance) is a gain; KE1 equal to that bound is rounding (ok): the first
    # float above it is energy_gained, the bound itself and anything below ok
    bound = ke0 * (1.0 + ALLOWANCE)
    assert _one(ke0=ke0, ke1=bound) is Physics.SOUND
    assert _one(ke0=ke0, ke1=math.nextafter(bound, math.inf)) is Physics.ENERGY_GAINED
    assert _one(ke0=ke0, ke1=ke0) is Physics.SOUND  # energy kept (e = 1)


def test_an_engines_allowance_lets_rounding_through_and_flags_a_real_gain():
    # with an engine's own allowance (``judge.energy_allowance``), a gain of its float eps
    # (rounding of one step) is ok, and +1% (the defects the rule is for) is energy_gained
    name = cheapest(batched=False)
    errors = adapters.record(name).errors
    allowance = energy_allowance(errors, adapters.settings_for(name))
    assert errors.eps < allowance < 0.01

    def status(ke1: float) -> Physics:
        return Physics(
            classify(g.SCALARS, Ending.SEPARATED, 2, 0.0, 0.05, REACH_M, 1.0, ke1, allowance)
        )

    assert status(1.0 + errors.eps) is Physics.SOUND
    assert status(1.01) is Physics.ENERGY_GAINED


def test_a_batch_is_classified_as_each_world_alone():
    # the same rules over numpy arrays (a batch of worlds) give each world the status it gets
    # alone in Python floats
    worlds = [
        {},
        {"ended": Ending.NON_FINITE},
        {"ended": Ending.PASSED, "first": -1},
        {"ended": Ending.BUDGET, "first": -1},
        {"ended": Ending.MISSED, "first": -1},
        {"ended": Ending.BUDGET},
        {"side_m": -0.01},
        {"peak_m": 2.0 * REACH_M},
        {"ke1": 101.0},
        {"ended": Ending.CONTACT_FLAG},
    ]
    rows = [{**SOUND, **w} for w in worlds]

    def col(k: str) -> np.ndarray:
        return np.array([r[k] for r in rows])

    got = classify(
        g.ARRAYS,
        col("ended"),
        col("first"),
        col("peak_m"),
        col("side_m"),
        REACH_M,
        col("ke0"),
        col("ke1"),
        ALLOWANCE,
    )
    assert [Physics(s) for s in got] == [_one(**w) for w in worlds]
    assert len(set(got)) == 8  # (every status classify gives is among them)
