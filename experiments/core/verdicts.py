"""One judge over columns: ``judge_columns(fired, error_models)`` gives every fired impact's
verdict, the answer it was held to, its error and its tolerance, as arrays, in one pass; it is
called where a firing ends, before any table (``tables.table`` lays its columns out).
``judge(case, outcome, error_model)`` is the same function on columns of length one.

The answer an impact is held to, the first that applies, each kind through the one protocol
of ``answers`` (``Held``: its v1 and tolerance, NaN where it does not apply), the verdict from
``answers.held_to``:

- ``rigid theory``: an engine whose contact is the rigid impulse, frictionless and in the
  swing plane: ``analytic.collide``'s whole episode, tolerance ``judging.tolerances``;
- ``its own contact law``: a soft engine's declared law (``judging.soft_judgement``);
- ``frictional impulse``: with friction or out of the swing plane, the one-step law the engine
  declares (``friction_judge``), every added output judged too;
- ``none``: no answer applies (the verdict is ``unjudged`` for a sound impact).

A verdict is ``ok`` within the tolerance, ``inaccurate`` outside, and a failure of the episode
(tunnelled, non-finite, ...) stays what it is. Error models (``error_models``: engine name ->
``adapters.ErrorModel``) replace an engine's record's for one call: a study or a test can ask
what another precision or contact law would allow. The answers and tolerances are worked out
once per distinct impact (``_distinct``), not per row.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

import adapters
from analytic import CollisionEpisode, ImpactCase

from . import friction_judge
from . import judge as judging
from .answers import Held, Reference, held_to
from .episode import SimOutcome
from .fire import Fired
from .fired import Gathered, gather
from .judge import Status

#: Engine name -> the error model its impacts are judged with, in place of its record's.
ErrorModels = Mapping[str, adapters.ErrorModel]


@dataclass(frozen=True, kw_only=True)
class Verdicts:
    """Every impact's judgement, one array entry per impact in order. ``status``: the verdict
    (``Status`` values); ``reference``: the answer it was held to (``Reference`` values);
    ``err_mps`` and ``tol_mps``: v1 off that answer and the tolerance (m/s; NaN where none
    applies). ``answers``: the answers' own columns, as the table lays them out (rigid episode,
    single impulse, contact law, friction outputs; ``tables.COLUMNS`` names and units)."""

    status: np.ndarray
    reference: np.ndarray
    err_mps: np.ndarray
    tol_mps: np.ndarray
    answers: dict[str, np.ndarray | list]


@dataclass(frozen=True, kw_only=True)
class Verdict:
    """One impact's ``Verdicts``: its status, the answer it was held to (``reference``), the
    engine's v1 off it and the tolerance (m/s; NaN where unjudged)."""

    status: Status
    reference: str
    v1_err_mps: float
    v1_tol_mps: float


class FiredBy(NamedTuple):
    """Who fired an impact (its engine, with which settings): all of its outcome that the
    answers for its v1 and their tolerances read (``judge.errors_of``, ``judge.rigid``, ...)."""

    engine: str
    settings: adapters.Settings


def judge(
    case: ImpactCase, outcome: SimOutcome, error_model: adapters.ErrorModel | None = None
) -> Verdict:
    """The verdict on one fired impact, its tolerances from ``error_model`` (default: its
    engine's record's): ``judge_columns`` on columns of length one."""
    models = {} if error_model is None else {outcome.engine: error_model}
    v = judge_columns([Fired(case, outcome, math.nan, math.nan)], models)
    return Verdict(
        status=Status(v.status[0]),
        reference=str(v.reference[0]),
        v1_err_mps=float(v.err_mps[0]),
        v1_tol_mps=float(v.tol_mps[0]),
    )


def judge_columns(
    fired: Sequence[Fired] | Gathered,
    error_models: ErrorModels | None = None,
    spin_columns: bool = False,
) -> Verdicts:
    """Every impact of ``fired`` judged (module docstring); ``spin_columns``: the friction
    columns even where no impact has friction (a flight needs them)."""
    g = fired if isinstance(fired, Gathered) else gather(fired)
    c = g.cols
    rep, inv = _distinct(g)
    cases = [g.cases[i] for i in rep]
    # of an outcome, v1's answers read only who fired it: no outcome made from the columns
    outs = [FiredBy(engine=g.engines[i], settings=g.settings[i]) for i in rep]
    errors = [judging.errors_of(o, error_models) for o in outs]
    rigid = [judging.rigid(k, o.settings.max_contact_s) for k, o in zip(cases, outs)]
    law = np.array(
        [judging.soft_judgement(k, o, e) for k, o, e in zip(cases, outs, errors)]
    ).reshape(-1, 2)
    single = judging.derivatives(cases)  # (the single impulse's v1 is its first)
    judged = (
        judging.tolerances(
            cases, outs, errors, c["release_omega_analytic_radps"][rep], rigid, single
        ),
        law,
        single[0],
    )
    judged = tuple(x[inv] for x in judged)  # (each row's, from its distinct impact's)
    plain = all(k.frictionless_planar for k in cases)
    each_rigid = [] if plain and not spin_columns else [rigid[k] for k in inv]
    extra, tol, law, impulse, within, frictional = _with_friction(
        g, judged, each_rigid, [errors[k] for k in inv] if each_rigid else [], plain, spin_columns
    )
    ref = {
        k: np.array([getattr(r, k) for r in rigid])[inv]
        for k in ("v1_mps", "u1_mps", "omega1_radps", "hand_dv_mps")
    }
    v1 = c["v1_mps"]
    err, law_err = np.abs(v1 - ref["v1_mps"]), np.abs(v1 - law[:, 0])
    nan = np.full(len(v1), math.nan)
    held = held_to(
        c["physics"],
        v1,
        (
            Held(reference=Reference.RIGID, v1_mps=ref["v1_mps"], tol_mps=tol),
            Held(
                reference=Reference.LAW,
                v1_mps=law[:, 0],
                tol_mps=np.where(frictional, nan, law[:, 1]),
            ),
            Held(
                reference=Reference.FRICTIONAL,
                v1_mps=law[:, 0],
                tol_mps=np.where(frictional, law[:, 1], nan),
                within=within,
            ),
        ),
    )
    answers = {
        "v1_analytic_mps": ref["v1_mps"],
        "v1_abs_err_mps": err,
        "v1_tol_mps": tol,
        "v1_impulse_mps": impulse,
        "rigid_episodes": rigid,
        "rows": inv,
        "v1_law_mps": law[:, 0],
        "v1_law_err_mps": law_err,
        "v1_law_tol_mps": law[:, 1],
        "u1_analytic_mps": ref["u1_mps"],
        "omega1_analytic_radps": ref["omega1_radps"],
        "hand_dv_analytic_mps": ref["hand_dv_mps"],
        **extra,
    }
    return Verdicts(
        status=held.status,
        reference=held.reference,
        err_mps=held.err_mps,
        tol_mps=held.tol_mps,
        answers=answers,
    )


def _with_friction(
    g: Gathered,
    judged,
    rigid: list[CollisionEpisode],
    errors: list[adapters.ErrorModel],
    plain: bool,
    spin_columns: bool,
):
    """With friction or out of the swing plane (or ``spin_columns``): the columns
    ``friction_judge`` adds to every row of ``g`` (their rigid answers ``rigid``, error models
    ``errors``); where a frictional answer applies, v1 judged against the one-step law as
    against a contact law (rigid tolerance NaN, ``law`` from the one-step law) with Routh's
    impulse as its single impulse; whether every added output is within its tolerance; and
    which rows a frictional answer judged. ``judged``: tol, law, impulse, returned as given
    (and no columns) where every case is ``plain``."""
    tol, law, impulse = judged
    n = len(tol)
    if plain and not spin_columns:
        return {}, tol, law, impulse, np.ones(n, dtype=bool), np.zeros(n, dtype=bool)
    cases = g.cases
    extra, v1_law, within = friction_judge.columns(
        cases, g.outcomes(range(len(cases))), errors, rigid
    )
    each = np.array([c.frictionless_planar for c in cases])
    v1 = np.array([r.v1_mps for r in rigid])
    return (
        extra,
        np.where(each, tol, math.nan),
        np.where(each[:, None], law, v1_law),
        np.where(each, impulse, v1),
        within,
        ~each,
    )


def _distinct(g: Gathered) -> tuple[np.ndarray, np.ndarray]:
    """The rows of ``g`` judged alike: one per distinct case, settings, engine and analytic
    release (the judgement depends on nothing else), as (a row of each, each row's index
    into them). Cases count as one when they are the same object, settings when equal. Each key
    column is coded by ``np.unique`` and the codes combined column by column (compacted
    again after each, so that they stay below the row count): no Python loop over rows."""
    n = len(g.cases)
    if n <= 1:
        return np.arange(n, dtype=np.intp), np.arange(n, dtype=np.intp)
    release = g.cols["release_omega_analytic_radps"]
    columns = [
        np.fromiter(map(id, g.cases), dtype=np.int64, count=n)
        if g.distinct is None
        else g.distinct[1]
    ]
    if g.settings.count(g.settings[0]) < n:  # (equal settings judge alike; C speed)
        columns.append(np.fromiter(map(id, g.settings), dtype=np.int64, count=n))
    if g.engines.count(g.engines[0]) < n:
        columns.append(np.asarray(g.engines))
    if not np.isnan(release).all():
        columns.append(release)
    if len(columns) == 1 and g.distinct is not None:  # (the cases alone: known)
        return g.distinct
    key = columns[0]
    for column in columns[1:]:
        key = np.unique(key, return_inverse=True)[1].reshape(-1)
        codes = np.unique(column, return_inverse=True)[1].reshape(-1)
        key = key * (int(codes.max()) + 1) + codes
    _, rep, inv = np.unique(key, return_index=True, return_inverse=True)
    return rep.astype(np.intp), inv.reshape(-1).astype(np.intp)
