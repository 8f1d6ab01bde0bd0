"""One impact's verdict (``experiments.core.verdicts.judge``): the table's judgement for one
impact, with any error model. The velocity tolerance of a single impulse is (``judge``)

    tol = [(ROUND_OPS + SOLVE_SAFETY cond) eps + mapping + tilt^2] (v0 + |u0| + |omega0| L)
          + (the contact seen late) + (a lingering contact),

so an error model that changes only the precision moves it by (ROUND_OPS + SOLVE_SAFETY
cond) (eps' - eps) (v0 + |u0| + |omega0| L), and nothing else."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

import adapters
from analytic import presets
from experiments.core import Job, Physics, fire_jobs, firings, tables
from experiments.core.judge import Status
from experiments.core.terms import ROUND_OPS, SOLVE_SAFETY
from experiments.core.verdicts import Reference, judge, judge_columns

#: The cheapest float64 single-world engine (records only: the tests name no engine).
ENGINE = min(
    (
        n
        for n in adapters.available()
        if not adapters.record(n).batched and adapters.record(n).errors.precision == "float64"
    ),
    key=lambda n: adapters.record(n).cost.step_cost_s,
)


@pytest.fixture(scope="module")
def fired():
    """The paper's swing at s = 0.1 m, fired once."""
    case = firings.Firing(
        bat=presets.R161,
        s_m=(0.1,),
        v0_mps=presets.PAPER_PITCH_MPS,
        u0_mps=presets.PAPER_SWING.u0_mps,
        omega0_radps=presets.PAPER_SWING.omega0_radps,
        e=presets.E_WOOD,
    ).cases()[0]
    (f,) = fire_jobs([Job(engine=ENGINE, settings=adapters.settings_for(ENGINE), case=case)])
    return f


def test_one_impact_is_judged_as_its_table_row(fired):
    row = tables.table([fired], "").iloc[0]
    got = judge(fired.case, fired.outcome)
    assert got.status == Status.OK == row.status and got.reference == "rigid theory"
    assert got.v1_tol_mps == row.v1_tol_mps and got.v1_err_mps == row.v1_abs_err_mps


def test_another_precision_moves_the_tolerance_by_its_rounding_term_alone(fired):
    case, settings = fired.case, fired.outcome.settings
    errors = adapters.record(ENGINE).errors
    single = dataclasses.replace(errors, precision="float32")
    base, loose = judge(case, fired.outcome), judge(case, fired.outcome, single)
    speed = case.v0_mps + abs(case.u0_mps) + abs(case.omega0_radps) * case.bat.length_m
    eps64, eps32 = np.finfo(np.float64).eps, np.finfo(np.float32).eps
    want = (ROUND_OPS + SOLVE_SAFETY * errors.solve_conditioning(settings)) * (eps32 - eps64)
    assert loose.v1_tol_mps - base.v1_tol_mps == pytest.approx(want * speed, rel=1e-9)
    # and the engine's record is what judges it again once the call is over
    assert judge(case, fired.outcome) == base


@pytest.mark.parametrize("share,status", [(0.5, Status.OK), (2.0, Status.INACCURATE)])
def test_an_outcome_off_by_a_share_of_its_tolerance(fired, share, status):
    # v1 moved by half its tolerance is still ok; by twice it, inaccurate
    tol = judge(fired.case, fired.outcome).v1_tol_mps
    off = dataclasses.replace(fired.outcome, v1_mps=fired.outcome.v1_mps + share * tol)
    assert judge(fired.case, off).status == status


def test_the_columns_judge_name_the_answer_each_impact_was_held_to():
    # frictionless and planar, a rigid float64 engine is held to rigid theory (|v1 - v1_rigid|
    # within its tolerance); with friction (mu = 0.3), to the frictional impulse it declares;
    # the verdicts are the table's, which only lays them out
    base = firings.Firing(
        bat=presets.R161,
        s_m=firings.grid(presets.R161, 3),
        v0_mps=presets.PAPER_PITCH_MPS,
        u0_mps=0.0,
        omega0_radps=0.0,
        e=presets.E_WOOD,
    )
    jobs = [
        Job(engine=ENGINE, settings=adapters.settings_for(ENGINE), case=c)
        for firing in (base, dataclasses.replace(base, mu=0.3, theta_rad=0.3))
        for c in firing.cases()
    ]
    fired = fire_jobs(jobs)
    v = judge_columns(fired)
    rows = tables.table(fired, "")
    assert list(v.reference) == [Reference.RIGID] * 3 + [Reference.FRICTIONAL] * 3
    assert list(v.status) == list(rows.status)
    rigid = v.reference == Reference.RIGID
    assert np.array_equal(v.err_mps[rigid], rows.v1_abs_err_mps[rigid])
    assert np.array_equal(v.tol_mps[~rigid], rows.v1_law_tol_mps[~rigid])
    assert (v.err_mps <= v.tol_mps).all(), (v.err_mps, v.tol_mps)


def test_two_words_for_two_things_a_verdict_is_the_outcome_when_it_was_not_sound(fired):
    # The physical outcome (endings.Physics) and the verdict (Status) are two vocabularies:
    # the verdict of a sound outcome is one of ok / inaccurate / unjudged, and of any other its
    # outcome's own word; so Status = {ok, inaccurate, unjudged} + (Physics - {sound}).
    judged = {Status.OK, Status.INACCURATE, Status.UNJUDGED}
    failures = {p.value for p in Physics} - {Physics.SOUND.value}
    assert {s.value for s in Status} == {s.value for s in judged} | failures
    assert Physics.SOUND.value not in {s.value for s in Status}
    for physics in Physics:
        out = dataclasses.replace(fired.outcome, physics=physics)
        got = judge(fired.case, out).status
        assert got in judged if physics is Physics.SOUND else got.value == physics.value
    # and the table lays both out, each in its own column
    row = tables.table([fired], "").iloc[0]
    assert (row.physics, row.status) == (Physics.SOUND.value, Status.OK.value)


def test_single_impulse_derivatives_are_each_cases_own(monkeypatch):
    # v1(s) = -v0n + (1 + e) v_c / (m (1/m + 1/M + s^2/J)), v_c = v0n + u0n + omega0 s
    # (``impact.predict``): the judge's single impulse is it at s, and its slope a central
    # difference over FD_STEP_M = 1 um, off |dv1/ds| (``analytic.gradients``) by its
    # rounding, eps |v1| / h ~ 1e-8 1/s against slopes of 10-100 1/s (truncation,
    # h^2/6 |v1'''|, is far below): 1e-7 relative. Kept per case (``judge._DERIVED``): any
    # order, any repeat and a full cache emptied give each case the same bits as alone.
    from analytic import ImpactCase, gradients, impact
    from experiments.core import judge as judging

    bat, ball = presets.R161, presets.BASEBALL
    cases = [
        ImpactCase(bat=bat, ball=ball, s_m=s, v0_mps=v0, u0_mps=u0, omega0_radps=w, e=e)
        for s, v0, u0, w, e in [(0.1, 40.0, 27.0, 50.0, 0.5), (-0.2, 30.0, 0.0, 0.0, 0.3)]
    ]
    alone = [judging.derivatives([c]) for c in cases]
    for c, (v1, slope, _) in zip(cases, alone):
        assert v1[0] == pytest.approx(impact.predict(c).v1_mps, rel=1e-14)
        exact = gradients.derivatives(
            bat,
            ball,
            s_m=c.s_m,
            v0_mps=c.v0_mps,
            u0_mps=c.u0_mps,
            omega0_radps=c.omega0_radps,
            e=c.e,
        )["v1_mps"]["s_m"]
        assert slope[0] == pytest.approx(abs(float(exact)), rel=1e-7)
    monkeypatch.setattr(judging, "CACHED_CASES", 3)  # the next call empties the cache
    mixed = judging.derivatives([cases[1], cases[0], cases[1], cases[1]])
    for got, k in zip(np.array(mixed).T, (1, 0, 1, 1)):
        assert list(got) == [float(a[0]) for a in alone[k]]
