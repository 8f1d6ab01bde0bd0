"""The answers an impact can be held to, one small protocol for every kind, and the verdict
that follows (``held_to``).

Each kind of answer gives, for every impact it is asked about, the v1 it holds the engine to and
the tolerance (m/s) worked out from its named terms (``terms``); a NaN tolerance where it does
not apply (a soft engine asked for the rigid impulse) or judges nothing (a step too coarse for
the law's bound). Kinds are asked in order, the first that applies holds the impact:

- ``rigid theory``: ``analytic.collide``'s whole episode (``judge.tolerances``);
- ``its own contact law``: a soft engine's declared law (``judge.soft_judgement``);
- ``frictional impulse``: with friction or out of the swing plane, the one-step law the engine
  declares, its other outputs judged too (``friction_judge``);
- ``segmented bat``: the linear chain's exit speed (``chain``).

A derivative is judged against its closed form by ``gradients`` in its own words (a zero, an
exploding or a biased gradient are not a v1's), the shared ones spelled as ``Status``'s.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from enum import StrEnum

import numpy as np

from .endings import Physics
from .judge import Status


class Reference(StrEnum):
    """The answer an impact was held to (module docstring); ``none``: no answer applied."""

    RIGID = "rigid theory"
    LAW = "its own contact law"
    FRICTIONAL = "frictional impulse"
    SEGMENTED = "segmented bat"
    NONE = "none"


@dataclass(frozen=True, kw_only=True)
class Held:
    """What one kind of answer holds impacts to: per impact the v1 (m/s) and the tolerance
    (m/s; NaN where the answer does not apply or judges nothing), and whether the impact's
    other outputs this answer judges are within theirs (``within``; True for v1 alone)."""

    reference: Reference
    v1_mps: np.ndarray
    tol_mps: np.ndarray
    within: np.ndarray | bool = True


@dataclass(frozen=True, kw_only=True)
class Judged:
    """Every impact's verdict (``Status`` values), the answer that held it (``Reference``
    values), v1 off that answer and its tolerance (m/s; NaN where none applied)."""

    status: np.ndarray
    reference: np.ndarray
    err_mps: np.ndarray
    tol_mps: np.ndarray


def held_to(physics, v1_mps, kinds: Sequence[Held]) -> Judged:
    """The verdict on each impact (arrays, one value per impact) from its physical outcome
    (``Physics`` values), its v1 and the kinds of answer in order: a failure stays what it is;
    a sound impact is ``ok`` within the tolerance of the first kind that applies (and its other
    outputs within theirs), ``inaccurate`` outside, ``unjudged`` where none applies."""
    v1 = np.asarray(v1_mps, dtype=float)
    n = len(v1)
    which = np.full(n, len(kinds), dtype=np.intp)
    value, tol, within = np.full(n, np.nan), np.full(n, np.nan), np.ones(n, dtype=bool)
    for k in range(len(kinds) - 1, -1, -1):  # (the first kind that applies is written last)
        h = kinds[k]
        on = ~np.isnan(h.tol_mps)
        if not on.any():
            continue
        which = np.where(on, k, which)
        value, tol = np.where(on, h.v1_mps, value), np.where(on, h.tol_mps, tol)
        within = np.where(on, h.within, within)
    err = np.abs(v1 - value)
    with np.errstate(invalid="ignore"):
        fits = (err <= tol) & within
    judged = _JUDGED[np.where(which < len(kinds), np.where(fits, 0, 1), 2)]
    status = np.array(physics, dtype=object)  # a failure stays what it is
    np.copyto(status, judged, where=status == Physics.SOUND.value)
    names = np.array([*(h.reference.value for h in kinds), Reference.NONE.value], dtype=object)
    return Judged(status=status, reference=names[which], err_mps=err, tol_mps=tol)


#: ``held_to``'s judgements by code, as Python strings (pandas reads numpy's own slowly).
_JUDGED = np.array([Status.OK.value, Status.INACCURATE.value, Status.UNJUDGED.value], dtype=object)
