"""The one protocol of answers (``experiments.core.answers``): each kind gives a v1 and a
tolerance per impact (NaN: it does not apply); the first kind that applies holds the impact,

    ok          if physics = sound and |v1 - v1_answer| <= tol and the answer's other outputs fit,
    inaccurate  if physics = sound and not,
    unjudged    if physics = sound and no kind applies,
    physics     otherwise (a failure stays what it is).

The numbers below are made up by hand: the rule is arithmetic, not physics."""

from __future__ import annotations

import math

import numpy as np

from experiments.core import Physics, Status
from experiments.core.answers import Held, Reference, held_to

SOUND, NAN = Physics.SOUND.value, math.nan


def _kinds(tol_rigid, tol_law, within=True) -> list[Held]:
    return [
        Held(reference=Reference.RIGID, v1_mps=np.full(4, 10.0), tol_mps=np.array(tol_rigid)),
        Held(
            reference=Reference.LAW,
            v1_mps=np.full(4, 11.0),
            tol_mps=np.array(tol_law),
            within=within,
        ),
    ]


def test_the_first_kind_that_applies_holds_the_impact():
    # rows: rigid applies (ok at 0.5 off), rigid applies (1.5 off: inaccurate, though the law
    # would take it), only the law applies (ok), none applies (unjudged)
    v1 = np.array([10.5, 11.5, 11.5, 11.5])
    got = held_to([SOUND] * 4, v1, _kinds([1.0, 1.0, NAN, NAN], [NAN, 1.0, 1.0, NAN]))
    assert list(got.status) == [Status.OK, Status.INACCURATE, Status.OK, Status.UNJUDGED]
    assert list(got.reference) == [Reference.RIGID, Reference.RIGID, Reference.LAW, Reference.NONE]
    np.testing.assert_array_equal(got.err_mps, [0.5, 1.5, 0.5, NAN])
    np.testing.assert_array_equal(got.tol_mps, [1.0, 1.0, 1.0, NAN])


def test_a_failure_stays_what_it_is_and_other_outputs_count():
    v1 = np.array([10.0, 11.0, 11.0, NAN])
    physics = [Physics.TUNNELLED.value, SOUND, SOUND, Physics.NON_FINITE.value]
    within = np.array([True, False, True, True])  # row 1: v1 fits, another output does not
    got = held_to(physics, v1, _kinds([NAN] * 4, [1.0] * 4, within))
    assert list(got.status) == [Status.TUNNELLED, Status.INACCURATE, Status.OK, Status.NON_FINITE]
    # every failure's word is a verdict's too (``Status``), so none is lost on the way
    assert {p.value for p in Physics} - {SOUND} <= {s.value for s in Status}
