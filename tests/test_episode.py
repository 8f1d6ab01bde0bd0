"""The impact episode (``experiments.core.episode``): a batch of worlds stepped from their start
states until each impact is over, as ``analytic.collide`` ends the rigid one, on the cheapest
real single-world engine (no engine named):

- a ball that meets the barrel leaves as rigid theory says (v1 within the judge's derived
  tolerance of ``collide``'s) and its episode ends 'separated', on the side it came from;
- a ball that passes clear of the bat ends 'missed' with no contact and its velocity kept;
- where rigid theory is still in contact after ``max_contact_s`` (e = 0, the ball riding the
  bat: ``collide`` ends 'time_limit'), the episode ends at the budget, after max_contact_s;
- in a batch each world ends its own way at its own step, bit for bit as alone;
- ``run_episode`` steps until its task says the episode is over, or the steps run out.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

import adapters
from adapters import Scene
from analytic import ImpactCase, collide, presets
from experiments.core import geometry as g
from experiments.core.endings import LABELS, Ending, Physics, classify
from experiments.core.episode import Coast, Recorder, SimOutcome, run_episode, step_episodes
from experiments.core.fired import unmeasured
from experiments.core.hosting import hosted
from experiments.core.judge import output_tolerance
from experiments.core.placement import start_state

from .conftest import cheapest

ENGINE = cheapest(batched=False)
SETTINGS = adapters.settings_for(ENGINE)
ERRORS = adapters.record(ENGINE).errors
BAT, BALL = presets.R161, presets.BASEBALL
#: Where a ball that misses is put, along the bat's axis (m): beyond the barrel's end cap
#: (s_max + r_bat) by more than the ball's radius, so it flies past without touching.
MISS_X_M = 0.8


def _case(s_m: float, e: float = 0.5) -> ImpactCase:
    return ImpactCase(bat=BAT, ball=BALL, s_m=s_m, v0_mps=40.0, u0_mps=10.0, omega0_radps=20.0, e=e)


def _world(settings: adapters.Settings, e: float, n: int = 1):
    """The engine holding the scene in ``n`` worlds, as the episode steps it."""
    return hosted(ENGINE, settings).batch(Scene(bat=BAT, ball=BALL, e=e, mu=0.0), n)


def _missing(state):
    """``state`` with the ball moved along the axis past the bat's end (``MISS_X_M``)."""
    return state._replace(**{adapters.STATE_FIELDS[g.BALL_X]: MISS_X_M})


class _Counter:
    """A world that only counts its steps."""

    def __init__(self) -> None:
        self.steps = 0

    def step(self) -> None:
        self.steps += 1


def test_sim_outcome_is_sound_only_with_physics_sound():
    # ``sound`` is the physical outcome ``sound`` and nothing else: a verdict is not its to say
    (row,) = unmeasured(ENGINE, [_case(0.1)], [SETTINGS], None, Physics.ERROR, "why", 0.0)
    assert isinstance(row.outcome, SimOutcome)
    for physics in Physics:
        outcome = dataclasses.replace(row.outcome, physics=physics)
        assert outcome.sound is (physics is Physics.SOUND)
    with pytest.raises(dataclasses.FrozenInstanceError):
        row.outcome.v1_mps = 1.0  # a record, never changed in place


def test_run_episode_runs_out_its_steps_and_stops_when_its_task_says():
    # a Coast never ends: max_steps steps; a Recorder reads the world after every one of them
    world, reads = _Counter(), []
    assert run_episode(world, Coast(), 7) == 7 and world.steps == 7
    assert run_episode(world, Recorder(lambda w: reads.append(w.steps)), 5) == 5
    assert reads == [8, 9, 10, 11, 12]

    class OverAtThree(Coast):
        def over(self, step: int, world) -> bool:
            return step == 3

    world = _Counter()
    assert run_episode(world, OverAtThree(), 100) == 3 and world.steps == 3


def test_an_impact_on_the_barrel_ends_separated_as_rigid_theory_leaves():
    # a frictionless impact at s = 0.1 m, e = 0.5: collide's one impulse, then free flight
    # apart; the engine's ball leaves with collide's v1 within the judge's tolerance (rounding
    # and the contact seen late: ``judge.single_impulse_tolerance``)
    case = _case(0.1)
    start, _ = start_state(case, SETTINGS)
    ep = step_episodes(_world(SETTINGS, case.e), BAT, BALL, SETTINGS, start)
    rigid = collide(case, max_episode_s=SETTINGS.max_contact_s)
    assert rigid.ended == "separated" and LABELS[ep.ended] == "separated"
    tol = output_tolerance(case, SETTINGS, ERRORS, "v1_mps")
    assert abs(ep.end[g.BALL_VY] - rigid.v1_mps) <= tol, (ep.end[g.BALL_VY], rigid.v1_mps, tol)
    # the contact was seen, no later than planned (``placement``: at step approach_steps),
    # and the ball ended on the side it came from, outside the bat
    assert 1 <= ep.first <= SETTINGS.approach_steps and ep.last >= ep.first
    assert ep.side_m > 0.0 and ep.peak_m < BAT.radius_m + BALL.radius_m
    assert ep.steps >= ep.last


def test_a_ball_clear_of_the_bat_is_missed_with_its_velocity_kept():
    # no contact when due and the ball still on its side: 'missed' -> no_contact; free flight
    # (no gravity in the scene) keeps its velocity to within the deflection a contact would
    # show (terms.DEFLECTED of its speed), here to a few float64 roundings of it
    start, _ = start_state(_case(0.1), SETTINGS)
    start = _missing(start)
    ep = step_episodes(_world(SETTINGS, 0.5), BAT, BALL, SETTINGS, start)
    assert LABELS[ep.ended] == "missed" and ep.first == ep.last == -1
    assert ep.side_m > 0.0
    speed = math.hypot(start[g.BALL_VX], start[g.BALL_VY])
    moved = math.hypot(ep.end[g.BALL_VX] - start[g.BALL_VX], ep.end[g.BALL_VY] - start[g.BALL_VY])
    assert moved <= 16 * ERRORS.eps * speed, moved
    status = classify(g.SCALARS, ep.ended, ep.first, ep.peak_m, ep.side_m, 0.07, 1.0, 1.0, 0.0)
    assert status == Physics.NO_CONTACT


def test_a_contact_longer_than_the_budget_ends_at_the_budget():
    # e = 0 at s = 0: the ball rides the bat, and rigid theory is still in contact after
    # max_contact_s (collide: 'time_limit'); the engine's episode ends at the budget, having
    # followed the contact for at least max_contact_s, and is classified no_separation
    settings = dataclasses.replace(SETTINGS, max_contact_s=200 * SETTINGS.dt_s)
    case = _case(0.0, e=0.0)
    assert collide(case, max_episode_s=settings.max_contact_s).ended == "time_limit"
    start, _ = start_state(case, settings)
    ep = step_episodes(_world(settings, 0.0), BAT, BALL, settings, start)
    assert LABELS[ep.ended] == "budget"
    assert ep.first >= 1 and (ep.steps - ep.first + 1) * settings.dt_s >= settings.max_contact_s
    reach = BAT.radius_m + BALL.radius_m
    status = classify(g.SCALARS, ep.ended, ep.first, ep.peak_m, ep.side_m, reach, 1.0, 1.0, 0.0)
    assert status == Physics.NO_SEPARATION


def test_each_world_of_a_batch_ends_its_own_way_as_alone():
    # three worlds of one scene (two impacts, one ball clear of the bat) stepped together end
    # each as it does stepped alone, at the same step, in the same state: bit for bit (the
    # harness's contract: a world's numbers do not depend on its batch)
    starts = [
        start_state(_case(0.1), SETTINGS)[0],
        _missing(start_state(_case(0.1), SETTINGS)[0]),
        start_state(_case(-0.2), SETTINGS)[0],
    ]
    alone = [step_episodes(_world(SETTINGS, 0.5), BAT, BALL, SETTINGS, s) for s in starts]
    batch = _world(SETTINGS, 0.5, n=len(starts))
    together = step_episodes(batch, BAT, BALL, SETTINGS, np.array(starts, dtype=float))
    assert list(together.ended) == [a.ended for a in alone]
    assert list(together.ended) == [Ending.SEPARATED, Ending.MISSED, Ending.SEPARATED]
    for i, a in enumerate(alone):
        assert (together.steps[i], together.first[i], together.last[i]) == (
            a.steps,
            a.first,
            a.last,
        )
        assert together.side_m[i] == a.side_m
        assert list(together.end[:, i]) == list(a.end), i
