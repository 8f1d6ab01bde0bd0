"""How an impact's episode ended: the loop's ending (``Ending``) and the engine's physical
outcome that follows (``Physics``, decided by ``classify``). Whether a sound outcome matched
the answer that applies is the judge's word, not this one (``judge.Status``).

The stepper keeps each world's ending as a small integer: numpy compares and picks those in
microseconds, where an array of strings costs tens of microseconds an operation on 1e4 worlds
(measured: 55 against 7 us a ``where``). Tables and outcomes show its label (``LABELS``).
"""

from __future__ import annotations

import enum

import numpy as np


class Physics(enum.StrEnum):
    """The engine's physical outcome of an episode, decided when the firing ends: ``sound``,
    or what went wrong. A member is its value as a string, as ``judge.Status``'s are; each word
    but ``sound`` is also a verdict (a failure stays what it is when judged)."""

    SOUND = "sound"  #: none of the failures below: v1 is a measurement the judge can hold
    TUNNELLED = "tunnelled"  #: the ball's centre ended beyond the bat's axis: it passed
    NO_CONTACT = "no_contact"  #: no contact seen when due, and the ball did not pass either
    #: NaN or inf in the state, a failure the engine reported (a blow-up it caught, a solver
    #: that gave up), or a state that jumped (a silent reset)
    NON_FINITE = "non_finite"
    ENERGY_GAINED = "energy_gained"  #: kinetic energy after > before (beyond rounding)
    PENETRATION = "penetration"  #: deeper than r_ball + r_bat at some step
    NO_SEPARATION = "no_separation"  #: the episode outlasted the settings' max_contact_s
    UNSUPPORTED = "unsupported"  #: the engine cannot do what the impact needs (a swing)
    #: the engine raised, exited, or its adapter broke its contract (a contact flag its own
    #: geometry denies, a state of the wrong shape); ``ended`` says which
    ERROR = "error"
    TIMEOUT = "timeout"  #: the engine gave no result within its wall-clock limit (a hang)


class Ending(enum.IntEnum):
    """How an episode ended (``episode``'s module docstring); ``NONE``: not yet."""

    NONE = 0
    NON_FINITE = 1
    JUMPED = 2
    PASSED = 3
    MISSED = 4
    BUDGET = 5
    LEFT_CYLINDER = 6
    SEPARATED = 7
    #: the adapter said the bodies touch while its own state had them apart by more than
    #: ``terms.FLAG_REACHES`` reaches: its contact flag is wrong, nothing it measures is sound
    CONTACT_FLAG = 8


#: Each ending's label ('' for NONE), as Python strings, indexed by code: ``LABELS[codes]`` is
#: an array of them for an array of codes, one string for one code.
LABELS = np.array([e.name.lower() if e else "" for e in Ending], dtype=object)


def classify(xp, ended, first, peak_m, side_m, reach_m: float, ke0, ke1, allowance: float):
    """The physical outcome (``Physics`` value) of each episode (``episode``'s module
    docstring) from its ending (``Ending`` codes), in the namespace ``xp``: every physical
    outcome is decided here, the first rule that holds. ``allowance``: the relative energy
    gain that is rounding (``judge.energy_allowance``)."""
    rules = (
        ((ended == Ending.NON_FINITE) | (ended == Ending.JUMPED), Physics.NON_FINITE),
        (ended == Ending.CONTACT_FLAG, Physics.ERROR),
        ((ended == Ending.PASSED) | ((ended == Ending.BUDGET) & (first < 0)), Physics.TUNNELLED),
        (ended == Ending.MISSED, Physics.NO_CONTACT),
        (ended == Ending.BUDGET, Physics.NO_SEPARATION),
        (side_m <= 0.0, Physics.TUNNELLED),
        (peak_m > reach_m, Physics.PENETRATION),
        (ke1 > ke0 * (1.0 + allowance), Physics.ENERGY_GAINED),
    )
    return xp.select([c for c, _ in rules], [s.value for _, s in rules], Physics.SOUND.value)
