"""How an impact's episode ended (``Ending``), and the status that follows (``classify``).

The stepper keeps each world's ending as a small integer: numpy compares and picks those in
microseconds, where an array of strings costs tens of microseconds an operation on 1e4 worlds
(measured: 55 against 7 us a ``where``). Tables and outcomes show its label (``LABELS``).
"""

from __future__ import annotations

import enum

import numpy as np

from .judge import Status


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
    """The status value of each episode (``episode``'s module docstring) from its ending
    (``Ending`` codes), in the namespace ``xp``: every physical verdict is made here, the first
    rule that holds. ``allowance``: the relative energy gain that is rounding
    (``judge.energy_allowance``)."""
    rules = (
        ((ended == Ending.NON_FINITE) | (ended == Ending.JUMPED), Status.NON_FINITE),
        (ended == Ending.CONTACT_FLAG, Status.ERROR),
        ((ended == Ending.PASSED) | ((ended == Ending.BUDGET) & (first < 0)), Status.TUNNELLED),
        (ended == Ending.MISSED, Status.NO_CONTACT),
        (ended == Ending.BUDGET, Status.NO_SEPARATION),
        (side_m <= 0.0, Status.TUNNELLED),
        (peak_m > reach_m, Status.PENETRATION),
        (ke1 > ke0 * (1.0 + allowance), Status.ENERGY_GAINED),
    )
    return xp.select([c for c, _ in rules], [s.value for _, s in rules], Status.OK.value)
