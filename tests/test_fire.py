"""Firing impacts in this process (``experiments.core.fire.fire_jobs``), on the cheapest real
single-world engine (no engine named): one row per job, in the jobs' order, each with its own
settings; a job's outcome is the one it gets fired alone, bit for bit, whatever batch it was
stepped in; what the engine measures obeys its definitions

    impulse = m (v1 + v0n),   v1 = q v0n + (1 + q) V,  V = u0n + omega0 s,
    KE_before = (m v0^2 + M u0^2 + J omega0^2) / 2,

and the ball leaves as rigid theory says (``analytic.predict``, within the judge's tolerance).
An impact the harness cannot place is the caller's error (raised); one the engine cannot do is
a row that says so.
"""

from __future__ import annotations

import dataclasses
import math

import pytest

import adapters
from analytic import ImpactCase, collide, predict, presets
from experiments.core import Job, Physics, fire_jobs
from experiments.core.fire import CaseError
from experiments.core.judge import output_tolerance

from .conftest import EPS, cheapest

ENGINE = cheapest(batched=False)
SETTINGS = adapters.settings_for(ENGINE)
ERRORS = adapters.record(ENGINE).errors
BAT, BALL = presets.R161, presets.BASEBALL
#: Relative rounding of a measured quantity recombined from its own definition: a handful of
#: float64 operations, each within eps.
DEFINITION_REL = 8 * EPS


def _case(s_m: float, **kw) -> ImpactCase:
    return ImpactCase(
        bat=BAT, ball=BALL, s_m=s_m, v0_mps=40.0, u0_mps=10.0, omega0_radps=20.0, e=0.5, **kw
    )


def _grid(n: int) -> list[ImpactCase]:
    """n impacts along the barrel (s from 0 to 0.2 m), one impulse each in rigid theory."""
    return [_case(0.2 * i / (n - 1)) for i in range(n)]


def _fields(outcome) -> dict:
    """An outcome's fields but its wall time, NaN as None (NaN != NaN)."""
    d = dataclasses.asdict(outcome)
    del d["wall_s"]
    return {k: None if isinstance(v, float) and math.isnan(v) else v for k, v in d.items()}


def test_one_row_per_job_in_order_with_its_settings():
    # jobs of two time steps interleaved, in no order along the bat: row i is job i (its case
    # object, engine and settings), and its contact lasts a whole number of its own steps
    coarse = dataclasses.replace(SETTINGS, dt_s=2.0 * SETTINGS.dt_s)
    cases = _grid(6)
    order = [3, 0, 5, 1, 4, 2]
    jobs = [
        Job(engine=ENGINE, settings=(SETTINGS, coarse)[k % 2], case=cases[i])
        for k, i in enumerate(order)
    ]
    fired = fire_jobs(jobs)
    assert len(fired) == len(jobs)
    for job, row in zip(jobs, fired):
        assert row.case is job.case
        assert row.outcome.engine == ENGINE and row.outcome.settings == job.settings
        steps = row.outcome.contact_duration_s / job.settings.dt_s
        assert steps >= 1 and steps == pytest.approx(round(steps), abs=1e-9)


def test_each_row_leaves_as_rigid_theory_says():
    # a single frictionless impulse on the barrel (collide: one impact): the engine's v1
    # within the judge's derived tolerance of the closed form's (``judge.output_tolerance``)
    fired = fire_jobs([Job(engine=ENGINE, settings=SETTINGS, case=c) for c in _grid(4)])
    for row in fired:
        assert collide(row.case).impacts == 1
        assert row.outcome.sound, row.outcome.ended
        want = predict(row.case).v1_mps
        tol = output_tolerance(row.case, SETTINGS, ERRORS, "v1_mps")
        assert abs(row.outcome.v1_mps - want) <= tol, (row.outcome.v1_mps, want, tol)


def test_measured_quantities_obey_their_definitions():
    # impulse = m (v1 + v0n); v1 = q v0n + (1 + q) V; KE before from the planned start state
    (row,) = fire_jobs([Job(engine=ENGINE, settings=SETTINGS, case=_case(0.05))])
    c, o = row.case, row.outcome
    m, M, J = BALL.mass_kg, BAT.mass_kg, BAT.inertia_cm_kgm2
    V = c.u0n_mps + c.omega0_radps * c.s_m
    scale = abs(o.v1_mps) + c.v0n_mps + abs(V)
    assert abs(o.impulse_ns - m * (o.v1_mps + c.v0n_mps)) <= DEFINITION_REL * m * scale
    assert abs(o.q * c.v0n_mps + (1 + o.q) * V - o.v1_mps) <= DEFINITION_REL * scale
    ke0 = 0.5 * (m * c.v0_mps**2 + M * c.u0_mps**2 + J * c.omega0_radps**2)
    assert o.ke_before_j == pytest.approx(ke0, rel=DEFINITION_REL)
    assert o.closing_speed_mps == pytest.approx(c.closing_speed_mps, rel=DEFINITION_REL)
    assert 0.0 < o.ke_after_j < o.ke_before_j  # e = 0.5 < 1: energy lost


def test_a_job_fired_among_others_is_as_fired_alone():
    # a run long enough to be stepped on several adapters together (``Hosted.pool_size``)
    # gives every job the outcome it gets alone, bit for bit (a world's numbers do not depend
    # on its batch); only the wall time, shared out over the batch, differs
    jobs = [Job(engine=ENGINE, settings=SETTINGS, case=c) for c in _grid(200)]
    together = fire_jobs(jobs)
    for job, row in zip(jobs, together):
        (alone,) = fire_jobs([job])
        assert _fields(row.outcome) == _fields(alone.outcome), job.case.s_m


def test_tick_counts_every_job_and_no_jobs_fire_nothing():
    # progress: the counts passed to tick add up to the jobs fired; no jobs, no rows, no tick
    counts: list[int] = []
    jobs = [Job(engine=ENGINE, settings=SETTINGS, case=c) for c in _grid(5)]
    assert len(fire_jobs(jobs, tick=counts.append)) == 5
    assert sum(counts) == 5
    counts.clear()
    assert len(fire_jobs([], tick=counts.append)) == 0 and counts == []


def test_an_impact_the_harness_cannot_place_raises():
    # the contact first seen overlap_m deep after approach_steps steps needs
    # dt > overlap / (v_c approach_steps) (``placement.min_dt_s``): below it the bodies would
    # start inside each other, the caller's input error (CaseError, a ValueError naming dt_s),
    # never a row
    deep = dataclasses.replace(SETTINGS, overlap_m=1e-2)
    case = _case(0.1)
    assert SETTINGS.dt_s < deep.overlap_m / (case.closing_speed_mps * deep.approach_steps)
    with pytest.raises(CaseError, match="dt_s"):
        fire_jobs([Job(engine=ENGINE, settings=deep, case=case)])
    assert issubclass(CaseError, ValueError)


def test_a_planar_engine_leaves_an_impact_out_of_the_plane_unsupported():
    # an undercut ball leaves the swing plane: a planar engine cannot fire it, and says so in
    # its row (unsupported, no number), while the planar job beside it is fired as ever
    planar = sorted(
        (n for n in adapters.available() if adapters.record(n).can.planar),
        key=lambda n: adapters.record(n).cost.step_cost_s,
    )
    if not planar:
        pytest.skip("no planar engine installed")
    name = planar[0]
    settings = adapters.settings_for(name)
    jobs = [
        Job(engine=name, settings=settings, case=_case(0.1, undercut_m=0.01)),
        Job(engine=name, settings=settings, case=_case(0.1)),
    ]
    off, on = fire_jobs(jobs)
    assert off.outcome.physics is Physics.UNSUPPORTED and "plane" in off.outcome.ended
    assert math.isnan(off.outcome.v1_mps) and off.outcome.steps == 0
    assert on.outcome.sound
