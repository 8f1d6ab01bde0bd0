"""Fired impacts as the harness hands them on (``experiments.core.fired``): ``gather`` makes one
column per outcome field with row i the i-th fired impact, whatever parts (lists of ``Fired``,
``FiredBlock``s) they came in, concatenated in order; ``Gathered.outcomes`` gives back the
outcomes as fired (every field, the row's engine and settings); a batch the engine did not
fire (``NotFired``) is rows with its status, ``ended`` saying why, and NaN for every number
it would have measured. Rows come from the cheapest real single-world engine (none named)."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

import adapters
from analytic import ImpactCase, presets
from experiments.core import Job, Physics, fire_jobs
from experiments.core.fired import (
    FLOAT_FIELDS,
    FiredBlock,
    FiredSeq,
    NotFired,
    gather,
    unmeasured,
)

from .conftest import EPS, cheapest

ENGINE = cheapest(batched=False)
SETTINGS = adapters.settings_for(ENGINE)
#: The columns ``Gathered`` documents besides FLOAT_FIELDS.
OTHER = (
    "physics",
    "steps",
    "ended",
    "wall_s",
    "release_omega_analytic_radps",
    "release_angle_analytic_rad",
)


#: The float fields an unmeasured row knows without the engine: the case's closing speed, and
#: no contact.
KNOWN = ("closing_speed_mps", "contact_duration_s")


def _case(s_m: float) -> ImpactCase:
    return ImpactCase(
        bat=presets.R161,
        ball=presets.BASEBALL,
        s_m=s_m,
        v0_mps=40.0,
        u0_mps=10.0,
        omega0_radps=20.0,
        e=0.5,
    )


@pytest.fixture(scope="module")
def fired() -> list:
    """Four impacts along the barrel, two time steps, fired once: a list of ``Fired``."""
    coarse = dataclasses.replace(SETTINGS, dt_s=2.0 * SETTINGS.dt_s)
    jobs = [
        Job(engine=ENGINE, settings=(SETTINGS, coarse)[i % 2], case=_case(0.05 * i))
        for i in range(4)
    ]
    return list(fire_jobs(jobs))


def _same(a, b) -> bool:
    """Two values equal, NaN equal to NaN (a field nothing measured)."""
    both_nan = isinstance(a, float) and isinstance(b, float) and math.isnan(a) and math.isnan(b)
    return both_nan or a == b


def _assert_same_outcome(got, want, wall: bool = True) -> None:
    """Every field equal (``wall``: the wall time too; a block's is the batch's share)."""
    for f in dataclasses.fields(want):
        if f.name == "wall_s" and not wall:
            continue
        a, b = getattr(got, f.name), getattr(want, f.name)
        assert _same(a, b), (f.name, a, b)


def _block(rows: list) -> FiredBlock:
    """``rows`` as one batch's block of columns, as a batched engine hands them on."""
    g = gather(rows)
    cols = {k: g.cols[k] for k in (*FLOAT_FIELDS, *OTHER) if k != "wall_s"}
    return FiredBlock(
        g.cases, cols, engine=ENGINE, settings=g.settings, wall_s=float(g.cols["wall_s"][0])
    )


def test_columns_hold_each_fired_impact_in_order(fired):
    # column k, row i = field k of the i-th impact's outcome (its case and settings beside it)
    g = gather(fired)
    assert set(g.cols) == {*FLOAT_FIELDS, *OTHER}
    assert all(len(v) == len(fired) for v in g.cols.values())
    assert g.cases == [f.case for f in fired] and g.engines == [ENGINE] * len(fired)
    assert g.settings == [f.outcome.settings for f in fired]
    for i, f in enumerate(fired):
        for k in (*FLOAT_FIELDS, "steps", "ended", "wall_s"):
            assert _same(g.cols[k][i], getattr(f.outcome, k)), (k, i)
        assert g.cols["physics"][i] == f.outcome.physics.value
        assert _same(g.cols["release_omega_analytic_radps"][i], f.release_omega_radps)
    assert g.distinct is None  # (known only for one batch's block)


def test_parts_are_read_and_gathered_as_one_sequence_in_order(fired):
    # a list, a block and a list again: the sequence is their concatenation, and so are the
    # columns, row for row
    parts = [fired[:1], _block(fired[1:3]), fired[3:]]
    seq = FiredSeq(parts)
    assert len(seq) == len(fired)
    assert [f.case for f in seq] == [f.case for f in fired]
    assert [seq[i].case for i in range(-1, len(fired))] == [
        fired[-1].case,
        *(f.case for f in fired),
    ]
    g, alone = gather(seq), gather(fired)
    for k in (*FLOAT_FIELDS, *OTHER):
        if k != "wall_s":  # (a block's wall time is the batch's share, one for all its rows)
            assert all(map(_same, g.cols[k].tolist(), alone.cols[k].tolist())), k
    assert seq + fired[:1] is not seq and len(seq + fired[:1]) == len(fired) + 1


def test_outcomes_round_trip_the_fired_outcomes(fired):
    # Gathered.outcomes(rows) gives the outcomes as fired, in the order asked, each with its
    # row's engine and settings; a block gives back the same outcomes a row at a time
    g = gather(FiredSeq([_block(fired[:2]), fired[2:]]))
    rows = [3, 0, 2, 1]
    for i, got in zip(rows, g.outcomes(rows)):
        _assert_same_outcome(got, fired[i].outcome, wall=i >= 2)
    block = _block(fired)
    for i, f in enumerate(fired):
        _assert_same_outcome(block[i].outcome, f.outcome, wall=False)
        assert block[i].case is f.case


def test_a_blocks_distinct_cases_are_kept():
    # one batch's distinct cases (``placement.distinct_cases``) travel with its columns
    rows = list(fire_jobs([Job(engine=ENGINE, settings=SETTINGS, case=_case(0.1))] * 3))
    block = _block(rows)
    block.distinct = (np.array([0]), np.array([0, 0, 0]))
    g = gather(FiredSeq([block]))
    assert g.distinct is block.distinct


def test_unmeasured_rows_say_why_and_measure_nothing():
    # a batch the engine did not fire: each job a row with the failure's status and reason,
    # NaN where a measurement would be, no steps and no contact; the closing speed is the
    # case's own, v0n + u0n + omega0 s (known without the engine)
    cases = [_case(0.0), _case(0.1)]
    failure = NotFired(Physics.TIMEOUT, "timeout: no result within 3 s")
    rows = unmeasured(ENGINE, cases, [SETTINGS] * 2, None, failure.physics, failure.why, wall_s=1.5)
    assert [r.case for r in rows] == cases and str(failure) == failure.why
    for r, c in zip(rows, cases):
        o, closing = r.outcome, c.v0n_mps + c.u0n_mps + c.omega0_radps * c.s_m
        assert o.physics is Physics.TIMEOUT and o.ended == failure.why and not o.sound
        assert all(math.isnan(getattr(o, k)) for k in FLOAT_FIELDS if k not in KNOWN)
        assert o.closing_speed_mps == pytest.approx(closing, rel=4 * EPS)
        assert o.steps == 0 and o.contact_duration_s == 0.0
    g = gather(rows)
    assert list(g.cols["physics"]) == [Physics.TIMEOUT.value] * 2
    assert list(g.cols["ended"]) == [failure.why] * 2
    for got, r in zip(g.outcomes([0, 1]), rows):
        _assert_same_outcome(got, r.outcome)


def test_nothing_fired_gathers_empty_columns():
    # no impacts: every documented column, of length 0
    g = gather(FiredSeq([]))
    assert set(g.cols) == {*FLOAT_FIELDS, *OTHER}
    assert all(len(v) == 0 for v in g.cols.values()) and g.cases == [] and g.outcomes([]) == []
