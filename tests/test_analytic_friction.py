"""Coulomb friction at impact (analytic.friction): the limits it must reach, checked by hand."""

from __future__ import annotations

import math
import re
from dataclasses import replace

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from analytic import ImpactCase, RigidBody3D, impulse_3d, predict, presets
from analytic.friction import frictional_impulse, predict_friction

from .conftest import EPS, examples
from .test_analytic_impulse3d import bodies, vec

BALL = presets.BASEBALL
M, R = BALL.mass_kg, BALL.radius_m
#: The integrator's tolerance is 1e-13 relative and its events are found to rounding:
#: 1e-9 relative is the issue's bar, with four orders to spare.
TOL_REL = 1e-9


def ball(v, w=(0.0, 0.0, 0.0)) -> RigidBody3D:
    return RigidBody3D(
        mass_kg=M,
        inertia_kgm2=BALL.inertia_kgm2 * np.eye(3),
        velocity_mps=np.array(v, float),
        omega_radps=np.array(w, float),
    )


#: A bat of huge mass and inertia: a wall (its velocity change is ~1e-17 of the ball's).
WALL = RigidBody3D(mass_kg=1e16, inertia_kgm2=1e16 * np.eye(3))


def on_wall(vn: float, vt: float, e: float, mu: float, spin: float = 0.0):
    """A ball at normal speed vn and tangential speed vt (along x) onto a wall y = 0."""
    return frictional_impulse(
        ball([vt, -vn, 0.0], [0.0, 0.0, spin]),
        WALL,
        r_a_m=[0.0, -R, 0.0],
        r_b_m=[0.0, 0.0, 0.0],
        normal=[0.0, 1.0, 0.0],
        e=e,
        mu=mu,
    )


@given(
    vn=st.floats(1.0, 60.0),
    vt=st.floats(1.0, 40.0),
    e=st.floats(0.0, 1.0),
    frac=st.floats(0.01, 0.99),
)
def test_small_mu_on_a_wall_slides_throughout(vn, vt, e, frac):
    # A ball sliding all through the impact (mu below the limit 2 vt / (7 (1 + e) vn) where
    # the slip would stop) loses mu (1 + e) vn of tangential speed and gains the spin
    # 5 mu (1 + e) vn / (2 r) (Stronge sec. 4.2: the friction impulse is mu times the normal
    # impulse (1 + e) m vn; I = 2/5 m r^2).
    mu = frac * 2.0 * vt / (7.0 * (1.0 + e) * vn)
    out = on_wall(vn, vt, e, mu)
    assert [p[0] for p in out.phases] == ["slip"]
    assert out.a.velocity_mps[0] == pytest.approx(vt - mu * (1 + e) * vn, rel=TOL_REL)
    assert -out.a.omega_radps[2] == pytest.approx(5 * mu * (1 + e) * vn / (2 * R), rel=TOL_REL)
    assert out.a.velocity_mps[1] == pytest.approx(e * vn, rel=TOL_REL)


@given(
    vn=st.floats(1.0, 60.0),
    vt=st.floats(1.0, 40.0),
    e=st.floats(0.0, 1.0),
    extra=st.floats(1.01, 100.0),
)
def test_large_mu_on_a_wall_leaves_rolling(vn, vt, e, extra):
    # Above that limit the contact point stops and sticks: the ball leaves rolling,
    # v_t = 5/7 of its incoming value and omega = -v_t / r (angular momentum about the contact
    # point is conserved: m vt r = m v r + 2/5 m r^2 omega, with v = -omega r).
    mu = extra * 2.0 * vt / (7.0 * (1.0 + e) * vn)
    out = on_wall(vn, vt, e, mu)
    assert [p[0] for p in out.phases] == ["slip", "stick"]
    assert out.a.velocity_mps[0] == pytest.approx(5 / 7 * vt, rel=TOL_REL)
    assert out.a.omega_radps[2] == pytest.approx(-5 / 7 * vt / R, rel=TOL_REL)


def test_a_spinning_ball_that_rolls_already_sticks_at_once():
    # A ball already rolling (its contact point v_t + omega_z r = 0, r_A = -r y) feels no
    # friction on a wall: only the normal impulse acts, and it leaves as it came along x.
    vt = 10.0
    out = on_wall(30.0, vt, 0.5, mu=0.5, spin=-vt / R)
    assert [p[0] for p in out.phases] == ["stick"]
    assert out.a.velocity_mps[0] == pytest.approx(vt, rel=TOL_REL)
    assert out.a.omega_radps[2] == pytest.approx(-vt / R, rel=TOL_REL)


@settings(max_examples=examples(60))
@given(bodies(), bodies(), vec, vec, vec, st.floats(0.0, 1.0))
def test_mu_zero_is_the_frictionless_impulse(a, b, r_a, r_b, n, e):
    # mu = 0: P = j n with j from EQ 141 (impulse_3d), to the integrator's tolerance.
    assume(np.linalg.norm(n) >= 0.1)
    n = n / np.linalg.norm(n)
    assume(n @ (a.point_velocity(r_a) - b.point_velocity(r_b)) <= -0.1)
    want = impulse_3d(a, b, r_a_m=r_a, r_b_m=r_b, normal=n, e=e)
    got = frictional_impulse(a, b, r_a_m=r_a, r_b_m=r_b, normal=n, e=e, mu=0.0)
    np.testing.assert_allclose(
        got.impulse_ns, want.j_ns * n, rtol=TOL_REL, atol=TOL_REL * abs(want.j_ns)
    )


@settings(max_examples=examples(60))
@given(bodies(), bodies(), vec, vec, vec, st.floats(0.0, 1.0), st.floats(0.0, 2.0))
def test_energy_never_grows(a, b, r_a, r_b, n, e, mu):
    # Energetic restitution with Coulomb friction dissipates for any bodies, contact and mu
    # (Stronge sec. 5.4): kinetic energy after <= before, up to the integrator's tolerance.
    assume(np.linalg.norm(n) >= 0.1)
    n = n / np.linalg.norm(n)
    assume(n @ (a.point_velocity(r_a) - b.point_velocity(r_b)) <= -0.1)
    try:
        out = frictional_impulse(a, b, r_a_m=r_a, r_b_m=r_b, normal=n, e=e, mu=mu)
    except ArithmeticError:  # a jam (the normal impulse cannot stop it): not an impact
        assume(False)
    before = a.kinetic_energy_j() + b.kinetic_energy_j()
    after = out.a.kinetic_energy_j() + out.b.kinetic_energy_j()
    assert after <= before * (1 + TOL_REL)


def swing_case(s: float, theta: float, e: float, **friction) -> ImpactCase:
    return ImpactCase(
        bat=presets.R161,
        ball=BALL,
        s_m=s,
        v0_mps=46.9,
        u0_mps=17.87,
        omega0_radps=32.0,
        e=e,
        theta_rad=theta,
        **friction,
    )


@given(s=st.floats(-0.3, 0.25), theta=st.floats(-0.6, 0.6), e=st.floats(0.0, 1.0))
def test_mu_zero_on_the_bat_is_the_planar_model(s, theta, e):
    # predict_friction at mu = 0 and no undercut: the planar impulse (analytic.impact.predict),
    # v1 = -v0n + P/m and the tangential velocity kept, to rounding (a 3x3 solve: 1e3 eps).
    case = swing_case(s, theta, e)
    want, got = predict(case), predict_friction(case)
    assert got.v1_mps == pytest.approx(want.v1_mps, rel=1e3 * EPS, abs=1e3 * EPS * 50)
    assert got.vt1_mps == pytest.approx(want.v1_t_mps, abs=1e3 * EPS * 50)
    assert got.ball_spin_radps == (0.0, 0.0, 0.0)


@given(
    s=st.floats(-0.3, 0.25),
    theta=st.floats(-0.6, 0.6),
    e=st.floats(0.0, 1.0),
    mu=st.floats(0.0, 0.05),
)
def test_a_slide_throughout_on_the_bat_has_its_closed_form(s, theta, e, mu):
    # While the ball slides along the bat's axis in one direction s^ the whole time, dv/dp is
    # constant, k = n.K(n - mu s^) (K the collision matrix), and the energetic end is
    # p = (1 + e) p_c with p_c = -v_n0 / k (W_c = -v_n0^2 / 2k, then W - W_c = k (p - p_c)^2
    # / 2 = e^2 v_n0^2 / 2k): P = (1 + e)(-v_n0 / k)(n - mu s^), worked out by hand here.
    from analytic.friction import collision_matrix

    case = swing_case(s, theta, e, mu=mu)
    assume(abs(case.theta_rad) > 0.05)
    out = predict_friction(case)
    assume([p[0] for p in out.phases] == ["slip"])
    bat = case.bat
    n = np.array([0.0, 1.0, 0.0])
    a = ball([case.v0_mps * math.sin(theta), -case.v0n_mps, 0.0])
    b = RigidBody3D(
        mass_kg=bat.mass_kg,
        inertia_kgm2=np.diag([bat.axial_inertia_kgm2, bat.inertia_cm_kgm2, bat.inertia_cm_kgm2]),
        velocity_mps=np.array([0.0, case.u0_mps, 0.0]),
        omega_radps=np.array([0.0, 0.0, case.omega0_radps]),
    )
    r_a, r_b = -R * n, np.array([s, bat.radius_m, 0.0])
    v0 = a.point_velocity(r_a) - b.point_velocity(r_b)
    slip = np.array([math.copysign(1.0, v0[0]), 0.0, 0.0])
    k = n @ collision_matrix(a, b, r_a, r_b) @ (n - mu * slip)
    want = (1 + e) * (-(n @ v0) / k) * (n - mu * slip)
    np.testing.assert_allclose(out.impulse_ns, want, rtol=TOL_REL, atol=TOL_REL * 10)


@given(
    s=st.floats(-0.3, 0.25),
    undercut=st.floats(-0.06, 0.06),
    e=st.floats(0.0, 1.0),
    mu=st.floats(0.0, 1.0),
    spin=vec,
)
def test_undercut_hits_lose_energy_and_spin_the_ball_backward(s, undercut, e, mu, spin):
    # Any undercut, spin and mu: energy never grows; with friction and no incoming spin, a
    # ball whose centre is above the swing plane (+z) leaves upward with backspin (+x: the
    # friction on its underside drags it backward), below it with topspin.
    case = swing_case(s, 0.0, e, mu=mu, undercut_m=undercut)
    out = predict_friction(replace(case, spin_radps=tuple(spin * 100)))
    assert out.ke_after_j <= out.ke_before_j * (1 + TOL_REL)
    plain = predict_friction(case)
    if mu > 0.01 and abs(undercut) > 0.005:
        assert np.sign(plain.backspin_radps) == np.sign(undercut)
        assert np.sign(plain.launch_rad) == np.sign(undercut)


@pytest.mark.parametrize(
    "kwargs,piece",
    [
        ({"mu": -0.1}, "mu=-0.1 is out of range"),
        ({"mu": 0.5, "undercut_m": 0.2}, "undercut_m=0.2 is out of range"),
        ({"mu": 0.5, "spin_radps": (1.0, math.nan, 0.0)}, "spin_radps[1]=nan is not finite"),
        ({"mu": 0.5, "spin_radps": (1.0, 2.0)}, "spin_radps=(1.0, 2.0) has 2 components"),
    ],
)
def test_bad_input_is_named(kwargs, piece):
    with pytest.raises(ValueError, match=re.escape(piece)):
        predict_friction(swing_case(0.1, 0.0, 0.5, **kwargs))


def test_an_unknown_restitution_hypothesis_is_named():
    with pytest.raises(ValueError, match="hypothesis='newton' is unknown"):
        predict_friction(swing_case(0.1, 0.0, 0.5, mu=0.5), hypothesis="newton")


@given(s=st.floats(-0.3, 0.25), undercut=st.floats(-0.05, 0.05), e=st.floats(0.0, 1.0))
def test_a_gripping_ball_leaves_without_sliding(s, undercut, e):
    # mu = 2 grips every hit on the R161: the contact points end the impact with no relative
    # tangential velocity, v_ball + w_ball x r_A = v_bat + w_bat x r_B along the tangent plane
    # (to the straight step taken into rest: NEAR = 1e-7 of the closing speed, 1e-6 here).
    case = swing_case(s, 0.3, e, mu=2.0, undercut_m=undercut)
    out = predict_friction(case)
    assert out.phases[-1][0] == "stick"
    reach = case.bat.radius_m + R
    n = np.array([0.0, math.sqrt(reach**2 - undercut**2), undercut]) / reach
    r_a, r_b = -R * n, np.array([s, 0.0, 0.0]) + case.bat.radius_m * n
    rel = (
        np.array(out.ball_velocity_mps)
        + np.cross(out.ball_spin_radps, r_a)
        - np.array(out.bat_velocity_mps)
        - np.cross(out.bat_omega_radps, r_b)
    )
    tangential = rel - (rel @ n) * n
    assert np.linalg.norm(tangential) <= 1e-6 * case.closing_speed_mps


def one_step_on_wall(vn, vt, e, mu, relaxed=False):
    """``one_step_impulse`` for a ball at normal speed vn and tangential speed vt (along x)
    onto a wall y = 0."""
    from analytic.friction import one_step_impulse

    return one_step_impulse(
        ball([vt, -vn, 0.0]),
        WALL,
        r_a_m=[0.0, -R, 0.0],
        r_b_m=[0.0, 0.0, 0.0],
        normal=[0.0, 1.0, 0.0],
        e=e,
        mu=mu,
        relaxed=relaxed,
    )


@given(
    vn=st.floats(1.0, 60.0),
    vt=st.floats(1.0, 40.0),
    e=st.floats(0.0, 1.0),
    frac=st.floats(0.01, 0.99),
)
def test_the_one_step_law_slides_on_a_wall_as_routh(vn, vt, e, frac):
    # On a wall the collision matrix does not couple the normal and the tangent, so the one-step
    # law meets Routh's limits: a slide throughout drops v_t by mu (1 + e) v_n; relaxed, the
    # normal exit speed gains mu times the final slip s' = v_t - (7/2) mu dv_n, so
    # dv_n = ((1 + e) v_n + mu v_t) / (1 + (7/2) mu^2) (worked out by hand), dv_t = -mu dv_n.
    mu = frac * 2.0 * vt / (7.0 * (1.0 + e) * vn)
    plain = one_step_on_wall(vn, vt, e, mu)
    assert plain.phases[0][0] == "slip"
    assert plain.a.velocity_mps[0] == pytest.approx(vt - mu * (1 + e) * vn, rel=TOL_REL)
    assert plain.a.velocity_mps[1] == pytest.approx(e * vn, rel=TOL_REL)
    relaxed = one_step_on_wall(vn, vt, e, mu, relaxed=True)
    dvn = ((1 + e) * vn + mu * vt) / (1 + 3.5 * mu * mu)
    slip = vt - 3.5 * mu * dvn
    assume(slip > 1e-6 * vt)  # (a slide that just stops is a stick: the plain law's case)
    assert relaxed.a.velocity_mps[1] == pytest.approx(dvn - vn, rel=TOL_REL, abs=TOL_REL * vn)
    assert relaxed.a.velocity_mps[0] == pytest.approx(vt - mu * dvn, rel=TOL_REL)


@given(
    vn=st.floats(1.0, 60.0),
    vt=st.floats(1.0, 40.0),
    e=st.floats(0.0, 1.0),
    extra=st.floats(1.01, 100.0),
    relaxed=st.booleans(),
)
def test_the_one_step_law_grips_on_a_wall(vn, vt, e, extra, relaxed):
    # Above the sliding limit the one step sticks (the total impulse inside the cone): the ball
    # leaves rolling, v_t = 5/7 of its incoming value, the normal exit speed e v_n (a stick
    # has no slip for the relaxation to add).
    mu = extra * 2.0 * vt / (7.0 * (1.0 + e) * vn)
    out = one_step_on_wall(vn, vt, e, mu, relaxed)
    assert out.phases[0][0] == "stick"
    assert out.a.velocity_mps[0] == pytest.approx(5 / 7 * vt, rel=TOL_REL)
    assert out.a.velocity_mps[1] == pytest.approx(e * vn, rel=TOL_REL)


@given(s=st.floats(-0.3, 0.25), undercut=st.floats(-0.05, 0.05), e=st.floats(0.0, 1.0), spin=vec)
def test_the_laws_without_friction_are_the_frictionless_impulse(s, undercut, e, spin):
    # mu = 0: every law is EQ 141's impulse along the (tilted) normal, whatever the spin.
    case = swing_case(s, 0.0, e, undercut_m=undercut, spin_radps=tuple(spin * 100))
    want = predict_friction(case)
    for law in ("one_step", "relaxed"):
        got = predict_friction(case, law=law)
        np.testing.assert_allclose(
            got.impulse_ns,
            want.impulse_ns,
            rtol=TOL_REL,
            atol=TOL_REL * np.linalg.norm(want.impulse_ns),
        )


def test_the_laws_without_friction_hold_a_hit_on_a_still_bats_com():
    # mu = 0, an undercut ball on a still bat's COM (the slide search found no direction
    # there): the impulse is EQ 141's along the tilted normal, P.n = (1 + e) m_eff |v_n|,
    # with Routh's law (a frictionless integration) as the independent answer.
    case = ImpactCase(
        bat=presets.R161, ball=presets.BASEBALL, s_m=0.0, v0_mps=40.0, e=0.5, undercut_m=0.01
    )
    want = predict_friction(case)
    for law in ("one_step", "relaxed"):
        got = predict_friction(case, law=law)
        np.testing.assert_allclose(
            got.impulse_ns,
            want.impulse_ns,
            rtol=TOL_REL,
            atol=TOL_REL * np.linalg.norm(want.impulse_ns),
        )
