"""Friction in every engine that sets it, pinned against closed forms: how two bodies' friction
combines, the ball-on-a-wall limits, and out-of-plane impacts that end with a status that
says what happened (never an error)."""

from __future__ import annotations

import math

import pytest

import adapters
from adapters import Scene
from analytic import Bat, ImpactCase, presets
from experiments.core import Job, Physics, Status, fire_jobs, table, terms
from experiments.core.hosting import Hosted
from experiments.core.placement import start_state

R161, BALL = presets.R161, presets.BASEBALL
FRICTION = [n for n in adapters.names() if adapters.record(n).can.friction_rule is not None]
SPATIAL = [n for n in FRICTION if not adapters.record(n).can.planar]
#: A bat a thousand kilograms heavy, with inertia to match: a wall to 1.5e-4 (m / M).
WALL = Bat(
    name="wall",
    length_m=0.84,
    radius_m=0.03,
    mass_kg=1e3,
    com_from_knob_m=0.42,
    inertia_cm_kgm2=1e3,
    inertia_axial_kgm2=1e3,
)
#: The wall's own difference from an immovable one: the ball's velocities move by m / M.
WALL_REL = BALL.mass_kg / WALL.mass_kg


def _sliding_mu(name: str, bat: float, ball: float) -> float:
    """The contact's mu measured on a sliding impact with the bodies' own values set by hand:
    the ball at 20 m/s and theta = 0.8 rad onto the resting wall, e = 0 (no restitution pass
    to carry less friction than the compression), slides throughout for any mu up to 0.29
    (2 tan(theta) / 7), so its velocity turns by dv_t = -mu dv_n exactly."""
    st = adapters.settings_for(name, **adapters.record(name).studies.friction_rule_overrides)
    case = ImpactCase(bat=WALL, ball=BALL, s_m=0.0, v0_mps=20.0, theta_rad=0.8, e=0.0, mu=0.1)
    host = Hosted(name, st)
    try:
        batch = host.batch(Scene(bat=WALL, ball=BALL, e=0.0, mu=0.1), 1)
        host.adapter.set_body_friction(bat=bat, ball=ball)
        start = start_state(case, st)[0]
        batch.set_state(batch.xp.stack([start]))
        touched = False
        for _ in range(st.approach_steps + round(0.01 / st.dt_s)):  # at most 10 ms
            batch.step()
            touching = bool(batch.any_contact())
            if touched and not touching:
                break
            touched |= touching
        end = batch.xp.row(batch.read(), 0)
    finally:
        host.close()
    dvt, dvn = end[2] - start.ball_vx_mps, end[3] - start.ball_vy_mps
    return -dvt / dvn


@pytest.mark.parametrize("name", FRICTION)
def test_body_frictions_combine_as_the_record_says(name):
    # Set by hand, bat 0.1 and ball 0.15 make mu = 0.015 (product), 0.15 (max), 0.125
    # (mean), 0.1 (min), 0.1225 (geometric) or 0.12 (harmonic): rules 2.5e-3 apart at least,
    # measured to rounding (ROUND_OPS eps: 1.2e-3 in float32) plus the wall's finite mass.
    want = adapters.record(name).can.friction_rule.combine(0.1, 0.15)
    got = _sliding_mu(name, 0.1, 0.15)
    assert got == pytest.approx(
        want, abs=terms.ROUND_OPS * adapters.record(name).eps + WALL_REL * want
    )


def _on_wall(name: str, mu: float):
    """The ball at 20 m/s and 0.5 rad onto the resting wall at s = 0, e = 0.5, judged."""
    case = ImpactCase(bat=WALL, ball=BALL, s_m=0.0, v0_mps=20.0, theta_rad=0.5, e=0.5, mu=mu)
    job = Job(engine=name, settings=adapters.settings_for(name), case=case)
    return table(fire_jobs([job]), "reference").iloc[0]


EXACT = [n for n in FRICTION if not adapters.record(n).errors.friction_defect]
DEFECTIVE = [n for n in FRICTION if adapters.record(n).errors.friction_defect]
RIGID = [
    n for n in EXACT if adapters.contact_reference(n) is adapters.ContactReference.RIGID_IMPULSE
]


@pytest.mark.parametrize("name", EXACT)
def test_a_ball_slides_on_a_wall_by_coulombs_ratio(name):
    # mu = 0.05 slides throughout (below 2 v_t / (7 (1 + e) v_n) = 0.145): whatever the
    # normal law (Newton's, a convex solver's relaxed one, a compliant contact's own e), the
    # friction is mu times the normal force at every instant, so the ball's tangential velocity
    # changes by -mu times its normal one: dv_t = -mu dv_n, to rounding of the speeds, the
    # wall's finite mass and the normal a collision routine tilts by its own bias (its slide
    # over r1 + r2: that share of dv_n leaks into the tangent).
    row = _on_wall(name, 0.05)
    vn, vt = 20.0 * math.cos(0.5), 20.0 * math.sin(0.5)
    dvn, dvt = row.v1_engine_mps + vn, row.vt1_engine_mps - vt
    tilt = adapters.record(name).errors.collision_slide_m(adapters.settings_for(name), WALL) / (
        WALL.radius_m + BALL.radius_m
    )
    allowed = (
        terms.ROUND_OPS * adapters.record(name).eps * 20.0 + WALL_REL * abs(dvt) + tilt * abs(dvn)
    )
    assert dvt == pytest.approx(-0.05 * dvn, abs=allowed)


@pytest.mark.parametrize("name", RIGID)
def test_a_sliding_ball_on_a_wall(name):
    # With a rigid contact the slide ends as the engine's law says (status ok), and the ball
    # spins at 5 mu dv_n / (2 r) (I = 2 m r^2 / 5; Stronge sec. 4.2), dv_n its normal velocity
    # change: (1 + e) v_n under Newton's restitution (the one-step law, and Routh's), so the
    # tangential speed drops by mu (1 + e) v_n; a convex solver's relaxed law adds mu times
    # the final slip v_t - (7/2) mu dv_n to the normal exit speed: dv_n = ((1 + e) v_n + mu v_t)
    # / (1 + (7/2) mu^2). To the row's tolerance plus the wall's finite mass (m / M of each).
    row = _on_wall(name, 0.05)
    assert row.status == Status.OK.value, row.episode_end
    vn, vt, mu = 20.0 * math.cos(0.5), 20.0 * math.sin(0.5), 0.05
    dvn = 1.5 * vn
    if adapters.record(name).errors.friction_law(adapters.settings_for(name)) == "relaxed":
        dvn = (1.5 * vn + mu * vt) / (1.0 + 3.5 * mu * mu)
    drop = mu * dvn
    assert row.vt1_engine_mps == pytest.approx(vt - drop, abs=row.vt1_tol_mps + WALL_REL * vt)
    spin = 5 * drop / (2 * BALL.radius_m)
    assert -row.spin1_engine_radps == pytest.approx(spin, abs=row.spin1_tol_radps + WALL_REL * spin)


@pytest.mark.parametrize("name", RIGID)
def test_a_gripping_ball_leaves_a_wall_rolling(name):
    # mu = 1 stops the slip: the ball leaves rolling with v_t = 5/7 of its incoming value and
    # omega = -v_t / r (angular momentum about the contact point is conserved).
    row = _on_wall(name, 1.0)
    assert row.status == Status.OK.value, row.episode_end
    vt = 5 / 7 * 20.0 * math.sin(0.5)
    assert row.vt1_engine_mps == pytest.approx(vt, abs=row.vt1_tol_mps + WALL_REL * vt)
    assert -row.spin1_engine_radps * BALL.radius_m == pytest.approx(
        vt, abs=(row.spin1_tol_radps + WALL_REL * vt / BALL.radius_m) * BALL.radius_m
    )


@pytest.mark.parametrize("name", DEFECTIVE)
def test_a_declared_friction_defect_still_misses_the_wall(name):
    # An engine whose record declares a friction defect (``friction_defect``) misses one of
    # the wall's two limits (the slide, mu = 0.05; the grip, mu = 1) by more than its
    # tolerance: that row is 'inaccurate', its spin outside its tolerance of the law's. When
    # this fails the defect is gone: drop it from the record, and the wall tests above take the
    # engine.
    rows = [_on_wall(name, mu) for mu in (0.05, 1.0)]
    missed = [r for r in rows if r.status == Status.INACCURATE.value]
    assert missed, [r.status for r in rows]
    assert any(r.spin1_law_err_radps > r.spin1_tol_radps for r in missed)


@pytest.mark.parametrize("name", SPATIAL)
def test_undercut_hits_end_with_a_status_that_says_why(name):
    # Undercut 0 to 3 cm at mu = 0.5 on the paper's swing: every row measured (ok, or
    # inaccurate against the engine's own frictional law) or failed with a status that names
    # the failure; never an exception, and an ok row leaves with backspin of the undercut's sign.
    firing = [
        ImpactCase(
            bat=R161,
            ball=BALL,
            s_m=0.1,
            v0_mps=46.9,
            u0_mps=17.87,
            omega0_radps=32.0,
            e=0.5,
            mu=0.5,
            undercut_m=u,
        )
        for u in (0.0, 0.01, 0.02, 0.03)
    ]
    st = adapters.settings_for(name)
    rows = table(fire_jobs([Job(engine=name, settings=st, case=c) for c in firing]), "reference")
    assert not (rows.status == Status.ERROR.value).any(), list(rows.episode_end)
    ok = rows[(rows.status == Status.OK.value) & (rows.undercut_m > 0)]
    assert (ok.backspin1_engine_radps > 0).all()


@pytest.mark.parametrize("name", [n for n in adapters.names() if adapters.record(n).can.planar])
def test_a_planar_engine_refuses_an_undercut(name):
    # A 2-D engine cannot put the ball off the swing plane: 'unsupported', not a wrong answer.
    case = ImpactCase(bat=R161, ball=BALL, s_m=0.1, v0_mps=40.0, e=0.5, mu=0.5, undercut_m=0.01)
    fired = fire_jobs([Job(engine=name, settings=adapters.settings_for(name), case=case)])
    assert fired[0].outcome.physics is Physics.UNSUPPORTED
