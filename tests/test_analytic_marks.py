"""The sweet spot and COP of the answer that applies (``analytic.marks``): the closed forms where
the whole rigid episode is one impulse, the episode's own where it is not, none where no answer
is whole; and the closed-form sweet spot wherever the bat turns into the ball."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from analytic import (
    ImpactCase,
    batted_ball_speed,
    center_of_percussion,
    collide,
    episode_cop_mark,
    episode_sweet_spot_mark,
    presets,
    sweet_spot,
)
from analytic.marks import JUMP_STEP_M, NO_REFERENCE, SINGLE_IMPULSE, WHOLE_EPISODE

R161, BALL = presets.R161, presets.BASEBALL
SWING = presets.PAPER_SWING
#: The engines' episode budget (adapters.Settings.max_contact_s), which the sweep's marks use.
BUDGET_S = 0.1


def _case(**change) -> ImpactCase:
    return ImpactCase(
        **{
            **dict(
                bat=R161,
                ball=BALL,
                s_m=0.0,
                v0_mps=presets.PAPER_PITCH_MPS,
                u0_mps=SWING.u0_mps,
                omega0_radps=SWING.omega0_radps,
                e=0.5,
            ),
            **change,
        }
    )


def test_one_impulse_keeps_the_closed_forms_exactly():
    # At e = 0.5 the paper's swing is one impulse wherever it hits near the marks: the marks
    # are the closed forms, bit for bit (s* = omega0 J k / (A + R), s_cop = J / (M d)).
    case = _case()
    spot = episode_sweet_spot_mark(case, max_episode_s=BUDGET_S)
    cop = episode_cop_mark(case, max_episode_s=BUDGET_S)
    assert (spot.reference, cop.reference) == (SINGLE_IMPULSE, SINGLE_IMPULSE)
    assert spot.s_m == sweet_spot(R161, BALL, case.v0_mps, case.u0_mps, case.omega0_radps)
    assert cop.s_m == center_of_percussion(R161, case.hands_from_knob_m)


def test_a_plastic_episode_has_its_own_cop():
    # At e = 0 the ball rides the turning bat (sustained contact), and the hand point's
    # velocity change at the end of the episode, du + domega d, crosses zero elsewhere: the
    # mark is a crossing of collide's hand_dv (it changes sign JUMP_STEP_M either side, far
    # beyond the root's 1e-12 m), 3.9 mm from the single impulse's J / (M d).
    case = _case(e=0.0)
    cop = episode_cop_mark(case, max_episode_s=BUDGET_S)
    assert cop.reference == WHOLE_EPISODE

    def hand(s: float) -> float:
        return collide(replace(case, s_m=s), max_episode_s=BUDGET_S).hand_dv_mps

    assert hand(cop.s_m - JUMP_STEP_M) < 0.0 < hand(cop.s_m + JUMP_STEP_M)
    single = center_of_percussion(R161, case.hands_from_knob_m)
    assert 3.5e-3 < single - cop.s_m < 4.5e-3
    episode = collide(replace(case, s_m=cop.s_m), max_episode_s=BUDGET_S)
    assert episode.sustained_contact_s > 0.0 and episode.ended != "time_limit"


def test_a_plastic_episode_has_its_own_sweet_spot():
    # The whole episode's v1 peaks at its mark: no point of an independent grid (2 mm over
    # the cylinder) beats it by more than the ODE's tolerance on a speed of ~50 m/s.
    case = _case(e=0.0)
    spot = episode_sweet_spot_mark(case, max_episode_s=BUDGET_S)
    assert spot.reference == WHOLE_EPISODE

    def v1(s: float) -> float:
        return collide(replace(case, s_m=s), max_episode_s=BUDGET_S).v1_mps

    grid = np.arange(R161.s_min_m, R161.s_max_m, 2e-3)
    assert v1(spot.s_m) >= max(map(v1, grid)) - 1e-9 * 50.0


def test_an_episode_cut_at_the_budget_is_no_reference():
    # A still bat at e = 0: near the COP the ball stays on the bat past the 0.1 s budget, so
    # the rigid answer there is cut, not over (and an engine's impact there is not sound):
    # no COP to compare with, and why.
    cop = episode_cop_mark(_case(e=0.0, u0_mps=0.0, omega0_radps=0.0), max_episode_s=BUDGET_S)
    assert cop.reference == NO_REFERENCE and math.isnan(cop.s_m)
    assert "still in contact at the 0.1 s budget" in cop.why


def test_a_ball_at_rest_hit_again_and_again_has_no_cop():
    # A bat turning into a ball at rest (v0 = u0 = 0) catches it up again and again over the
    # barrel: the episode's hand-point change never crosses zero on the cylinder.
    cop = episode_cop_mark(_case(v0_mps=0.0, u0_mps=0.0, s_m=0.1), max_episode_s=BUDGET_S)
    assert cop.reference == NO_REFERENCE and "does not cross zero" in cop.why


@pytest.mark.parametrize(
    "v0, u0, omega0", [(0.0, 0.0, 32.0), (0.0, -4.0, 32.0), (10.0, 0.0, -32.0), (46.9, 17.87, 32.0)]
)
def test_the_sweet_spot_wherever_the_bat_turns_into_the_ball(v0, u0, omega0):
    # dv1/ds = 0 at s* = (-A + sqrt(A^2 + omega0^2 J k)) / omega0 for either sign of
    # A = v0 + u0 (a bat turning into a ball at rest: A = 0), where the closing speed is
    # sqrt(A^2 + omega0^2 J k) > 0: the argmax of v1 on a 1 um grid around it. (On a bat of
    # the R161's M and J made 2 m long: s* may lie past the R161's barrel end.)
    s_star = sweet_spot(R161, BALL, v0, u0, omega0)
    s = s_star + np.linspace(-1e-3, 1e-3, 2001)
    long = replace(R161, name="long", length_m=2.0, com_from_knob_m=1.0)
    v1 = batted_ball_speed(long, BALL, s, v0_mps=v0, u0_mps=u0, omega0_radps=omega0)
    assert abs(s[int(np.argmax(v1))] - s_star) <= 1e-6
