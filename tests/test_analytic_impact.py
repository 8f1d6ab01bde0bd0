"""The planar impact model against conservation laws, the 3D impulse and its own closed forms.

Tolerances: every quantity below comes from a handful of float64 operations on inputs of order 1,
so rounding leaves a relative error of a few units of EPS = 2.2e-16; sums of momenta cancel, so we
compare them with an absolute tolerance scaled by the largest term (TOL_REL * scale).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from scipy import optimize

from analytic import (
    ImpactCase,
    RigidBody3D,
    batted_ball_speed,
    center_of_percussion,
    collision_efficiency,
    impulse_3d,
    predict,
    predict_oblique_paper,
    presets,
    sweet_region,
    sweet_spot,
    sweet_zone,
)

from .conftest import EPS, cases

TOL_REL = 1e3 * EPS  # ~2e-13: a few dozen roundings, each amplified by at most ~10 by cancellation

R161, BALL = presets.R161, presets.BASEBALL


def _positions(case: ImpactCase) -> tuple[np.ndarray, np.ndarray]:
    """Bat COM at the origin; the ball's centre touching the barrel surface at s."""
    return np.zeros(2), np.array([case.s_m, case.bat.radius_m + case.ball.radius_m])


def _velocities(case: ImpactCase, out=None) -> tuple[np.ndarray, np.ndarray, float]:
    """(ball velocity, bat COM velocity, bat omega) in the (x along bat, y toward ball) frame."""
    if out is None:
        ball = np.array([case.v0_mps * math.sin(case.theta_rad), -case.v0n_mps])
        bat = np.array([case.u0_mps * math.sin(case.phi_rad), case.u0n_mps])
        return ball, bat, case.omega0_radps
    return (
        np.array([out.v1_t_mps, out.v1_mps]),
        np.array([out.u1_t_mps, out.u1_mps]),
        out.omega1_radps,
    )


def _impulse_3d(case: ImpactCase):
    """The impact by the general 3D impulse (EQ 141), an independent formula: the planar code
    is not called. The bat's tensor is diag(J_axial, J, J)."""
    bat, ball = case.bat, case.ball
    bv, cv, w = _velocities(case)
    a = RigidBody3D(
        mass_kg=ball.mass_kg,
        inertia_kgm2=np.eye(3) * ball.inertia_kgm2,
        velocity_mps=[bv[0], bv[1], 0.0],
    )
    b = RigidBody3D(
        mass_kg=bat.mass_kg,
        inertia_kgm2=np.diag([bat.axial_inertia_kgm2, bat.inertia_cm_kgm2, bat.inertia_cm_kgm2]),
        velocity_mps=[cv[0], cv[1], 0.0],
        omega_radps=[0.0, 0.0, w],
    )
    return impulse_3d(
        a,
        b,
        r_a_m=[0.0, -ball.radius_m, 0.0],
        r_b_m=[case.s_m, bat.radius_m, 0.0],
        normal=[0.0, 1.0, 0.0],
        e=case.e,
    )


def _v1_3d(case: ImpactCase) -> float:
    """The ball's normal velocity after the impact from the general 3D impulse."""
    return float(_impulse_3d(case).a.velocity_mps[1])


@given(cases(oblique=True))
def test_linear_momentum_conserved(case):
    # m v_ball + M v_bat is the same before and after (both components).
    m, M = case.ball.mass_kg, case.bat.mass_kg
    out = predict(case)
    b0, c0, _ = _velocities(case)
    b1, c1, _ = _velocities(case, out)
    p0, p1 = m * b0 + M * c0, m * b1 + M * c1
    scale = m * case.v0_mps + M * abs(case.u0_mps) + out.impulse_ns
    np.testing.assert_allclose(p1, p0, rtol=0, atol=TOL_REL * scale)


@given(cases(oblique=True), st.floats(-2.0, 2.0), st.floats(-2.0, 2.0))
def test_angular_momentum_conserved_about_any_point(case, qx, qy):
    # L_Q = sum (r - Q) x m v + J omega, z component, is unchanged by the impulse pair.
    m, M, J = case.ball.mass_kg, case.bat.mass_kg, case.bat.inertia_cm_kgm2
    q = np.array([qx, qy])
    r_bat, r_ball = _positions(case)
    out = predict(case)

    def cross(a, b):
        return a[0] * b[1] - a[1] * b[0]

    def L(ball_v, bat_v, w):
        return cross(r_ball - q, m * ball_v) + cross(r_bat - q, M * bat_v) + J * w

    L0, L1 = L(*_velocities(case)), L(*_velocities(case, out))
    scale = (m * case.v0_mps + M * abs(case.u0_mps) + out.impulse_ns) * (
        3.0 + abs(case.s_m)
    ) + J * abs(case.omega0_radps)
    assert abs(L1 - L0) <= TOL_REL * scale


@given(cases(oblique=True))
def test_energy_conserved_at_e1_and_loss_formula(case):
    # dKE = (1 - e^2)/2 * mu * v_c^2 with 1/mu = 1/m + 1/M + s^2/J (zero at e = 1).
    m, M, J, s = case.ball.mass_kg, case.bat.mass_kg, case.bat.inertia_cm_kgm2, case.s_m
    out = predict(case)
    mu = 1.0 / (1.0 / m + 1.0 / M + s * s / J)
    expected = 0.5 * (1.0 - case.e**2) * mu * case.closing_speed_mps**2
    assert out.energy_lost_j == pytest.approx(expected, rel=0, abs=TOL_REL * out.ke_before_j)
    if case.e == 1.0:
        assert out.ke_after_j == pytest.approx(out.ke_before_j, rel=TOL_REL)


@given(cases(oblique=True))
def test_restitution_law_at_contact_point(case):
    # Newton: normal separation speed = e * closing speed, at the contact point.
    out = predict(case)
    separation = out.v1_mps - (out.u1_mps + out.omega1_radps * case.s_m)
    scale = case.closing_speed_mps + case.v0_mps + abs(case.u0_mps)
    assert separation == pytest.approx(case.e * case.closing_speed_mps, abs=TOL_REL * scale)


@given(cases(oblique=True))
def test_planar_model_equals_3d_impulse(case):
    # EQ 141 with the bat's tensor diag(J_axial, J, J) reduces to P = (1+e) v_c/(1/m+1/M+s^2/J).
    res = _impulse_3d(case)
    w = case.omega0_radps
    out = predict(case)
    scale = case.v0_mps + abs(case.u0_mps) + abs(w) * (1 + abs(case.s_m)) + out.impulse_ns
    assert res.j_ns == pytest.approx(out.impulse_ns, abs=TOL_REL * scale)
    atol = TOL_REL * scale
    np.testing.assert_allclose(res.a.velocity_mps, [out.v1_t_mps, out.v1_mps, 0], atol=atol)
    np.testing.assert_allclose(res.b.velocity_mps, [out.u1_t_mps, out.u1_mps, 0], atol=atol)
    np.testing.assert_allclose(res.b.omega_radps, [0, 0, out.omega1_radps], atol=atol * 1e2)


@given(cases())
def test_collision_efficiency_form(case):
    # q is the batted speed per unit pitch speed off a bat at rest (Cross): measured with the
    # general 3D impulse on the same bat at rest, v1 = q v0; then the moving bat obeys
    # v1 = q v0 + (1 + q)(u0 + omega0 s) (a change of frame along the normal).
    at_rest = ImpactCase(bat=case.bat, ball=case.ball, s_m=case.s_m, v0_mps=case.v0_mps, e=case.e)
    q_measured = _v1_3d(at_rest) / case.v0_mps
    q = float(collision_efficiency(case.bat, case.ball, case.s_m, case.e))
    assert q == pytest.approx(q_measured, rel=0, abs=TOL_REL * 10)
    assert predict(case).q == pytest.approx(q_measured, rel=0, abs=TOL_REL * 10)
    v1 = q_measured * case.v0_mps + (1 + q_measured) * (case.u0_mps + case.omega0_radps * case.s_m)
    scale = case.v0_mps + abs(case.u0_mps) + abs(case.omega0_radps * case.s_m)
    assert _v1_3d(case) == pytest.approx(v1, abs=TOL_REL * 10 * scale)


def test_vectorized_equals_pointwise():
    # The vectorized v1 over an array against the general 3D impulse point by point (an
    # independent formula); both are a few dozen float operations: 1e3 EPS relative.
    s = np.linspace(R161.s_min_m, R161.s_max_m, 57)
    v = batted_ball_speed(R161, BALL, s, v0_mps=46.9, u0_mps=17.87, omega0_radps=32.0, e=0.5)
    ref = [
        _v1_3d(
            ImpactCase(
                bat=R161,
                ball=BALL,
                s_m=float(x),
                v0_mps=46.9,
                u0_mps=17.87,
                omega0_radps=32.0,
                e=0.5,
            )
        )
        for x in s
    ]
    np.testing.assert_allclose(v, ref, rtol=1e3 * EPS, atol=1e3 * EPS * 46.9)


@pytest.mark.parametrize(
    "v0,u0,w0",
    [
        (46.9, 17.87, 32.0),
        (40.2, 0.0, 32.0),
        (35.0, 10.0, 12.0),
        (46.9, 17.87, 47.0),
        (40.0, 5.0, -20.0),
    ],
)
def test_sweet_spot_is_numerical_argmax(v0, u0, w0):
    # s* from omega0 s^2 + 2 A s - omega0 J k = 0 must be where v1(s) peaks. The peak is flat:
    # a rounding change dv ~ 8 EPS |v1| shifts the argmax by sqrt(2 dv / |v1''|), which bounds
    # how well any numerical maximizer can place it; xatol of the search adds to that.
    def f(s):
        return -float(batted_ball_speed(R161, BALL, s, v0_mps=v0, u0_mps=u0, omega0_radps=w0))

    s_star = sweet_spot(R161, BALL, v0, u0, w0)
    found = optimize.minimize_scalar(
        f, bounds=(-0.5, 0.27), method="bounded", options={"xatol": 1e-10}
    )
    h = 1e-3
    curvature = abs(f(s_star + h) - 2 * f(s_star) + f(s_star - h)) / h**2
    tol = math.sqrt(2 * 8 * EPS * abs(f(s_star)) / curvature) + 1e-9
    assert found.x == pytest.approx(s_star, abs=tol)


def test_sweet_spot_at_com_without_rotation():
    # omega0 = 0: v1 = -v0 + (1+e) A / (m k + m s^2/J) is even in s, so it peaks at s = 0. A
    # bounded numerical search over the bat must find it there, to the flat peak's rounding
    # width sqrt(2 * 8 EPS |v1| / |v1''|) (as in test_sweet_spot_is_numerical_argmax).
    def f(s):
        return -float(batted_ball_speed(R161, BALL, s, v0_mps=46.9, u0_mps=17.87, omega0_radps=0.0))

    found = optimize.minimize_scalar(
        f, bounds=(R161.s_min_m, R161.s_max_m), method="bounded", options={"xatol": 1e-10}
    )
    h = 1e-3
    curvature = abs(f(h) - 2 * f(0.0) + f(-h)) / h**2
    assert found.x == pytest.approx(
        0.0, abs=math.sqrt(2 * 8 * EPS * abs(f(0.0)) / curvature) + 1e-9
    )
    assert sweet_spot(R161, BALL, 46.9, 17.87, 0.0) == pytest.approx(found.x, abs=1e-7)


@given(st.floats(35.0, 47.0), st.floats(0.0, 17.87), st.floats(12.0, 47.0))
def test_sweet_region_contains_every_sweet_spot(v0, u0, w0):
    # The region's ends are s* at corners of the speed box; s* is monotone, so any s* inside.
    region = sweet_region(
        R161,
        BALL,
        v0_range_mps=(35.0, 47.0),
        u0_range_mps=(0.0, 17.87),
        omega0_range_radps=(12.0, 47.0),
    )
    s = sweet_spot(R161, BALL, v0, u0, w0)
    assert region.s_min_m - 1e-15 <= s <= region.s_max_m + 1e-15
    assert region.s_min_m == pytest.approx(sweet_spot(R161, BALL, 47.0, 17.87, 12.0), rel=4 * EPS)
    assert region.s_max_m == pytest.approx(sweet_spot(R161, BALL, 35.0, 0.0, 47.0), rel=4 * EPS)


def test_sweet_zone_ends_are_at_the_fraction():
    # v1(s) = fraction * max v1 at both roots of the quadratic, with the sweet spot between.
    zone = sweet_zone(
        R161, BALL, v0_mps=46.9, u0_mps=17.87, omega0_radps=32.0, e=0.5, fraction=0.98
    )
    s_star = sweet_spot(R161, BALL, 46.9, 17.87, 32.0)
    v = batted_ball_speed(
        R161,
        BALL,
        [zone.s_min_m, s_star, zone.s_max_m],
        v0_mps=46.9,
        u0_mps=17.87,
        omega0_radps=32.0,
        e=0.5,
    )
    np.testing.assert_allclose(v[[0, 2]], 0.98 * v[1], rtol=TOL_REL)
    assert zone.s_min_m < s_star < zone.s_max_m


@pytest.mark.parametrize("pivot", [0.0, 0.1, 0.15, 0.3])
def test_cop_is_where_the_hands_feel_nothing(pivot):
    # s_cop = J/(M d) must be the root of dv_hand(s) = -P (1/M + s (x_h - x_cm)/J) for a free bat.
    def hand(s):
        return predict(
            ImpactCase(
                bat=R161,
                ball=BALL,
                s_m=s,
                v0_mps=40.0,
                u0_mps=10.0,
                omega0_radps=20.0,
                hands_from_knob_m=pivot,
            )
        ).hand_dv_mps

    root = optimize.brentq(hand, 0.0, R161.s_barrel_end_m, xtol=1e-15, rtol=4 * EPS)
    assert root == pytest.approx(center_of_percussion(R161, pivot), abs=1e-14)


@given(cases(oblique=True))
def test_oblique_keeps_tangential_and_uses_normal_parts(case):
    # Frictionless: tangential velocities unchanged; normal parts obey the normal-impact formula
    # with v0 -> v0 cos(theta), u0 -> u0 cos(phi).
    out = predict(case)
    normal = predict(
        ImpactCase(
            bat=case.bat,
            ball=case.ball,
            s_m=case.s_m,
            v0_mps=case.v0n_mps,
            u0_mps=case.u0n_mps,
            omega0_radps=case.omega0_radps,
            e=case.e,
        )
    )
    # (the tangential parts are checked against the 3D impulse in test_planar_model_equals_3d)
    scale = case.v0_mps + abs(case.u0_mps) + abs(case.omega0_radps) + out.impulse_ns
    assert out.v1_mps == pytest.approx(normal.v1_mps, abs=TOL_REL * scale)
    assert out.omega1_radps == pytest.approx(normal.omega1_radps, abs=TOL_REL * scale * 1e2)


@given(cases())
def test_paper_oblique_reduces_to_normal_at_theta0(case):
    # At theta = phi = 0 the paper's eq. 6.4.2 is eq. 6.2.1, the normal impact.
    paper = predict_oblique_paper(case)
    scale = case.v0_mps + abs(case.u0_mps) + abs(case.omega0_radps * case.s_m)
    assert paper.v1_mps == pytest.approx(predict(case).v1_mps, abs=TOL_REL * scale)


@given(cases(oblique=True))
def test_paper_oblique_solves_its_own_equations(case):
    # The paper's eq. 6.4.1 (ball leaving along its incoming line, moment arm r for the
    # tangential part), solved here as a 3x3 linear system for (v1, u1, omega1):
    #   m (v0 + v1)(s cos(th) + r sin(th)) = J (omega0 - omega1)
    #   M (u0n - u1) = m (v0 + v1) cos(th)
    #   v1 cos(th) - (u1 + omega1 s) = e (v0 cos(th) + u0n + omega0 s)
    m, M, J, s = case.ball.mass_kg, case.bat.mass_kg, case.bat.inertia_cm_kgm2, case.s_m
    r = case.bat.radius_m + case.ball.radius_m
    c, sn, v0, w0, u0n = (
        math.cos(case.theta_rad),
        math.sin(case.theta_rad),
        case.v0_mps,
        case.omega0_radps,
        case.u0n_mps,
    )
    arm = s * c + r * sn
    A = np.array([[m * arm, 0.0, J], [m * c, M, 0.0], [c, -1.0, -s]])
    b = np.array([J * w0 - m * v0 * arm, M * u0n - m * v0 * c, case.e * (v0 * c + u0n + w0 * s)])
    v1 = np.linalg.solve(A, b)[0]
    paper = predict_oblique_paper(case)
    scale = v0 + abs(case.u0_mps) + abs(w0) * (1 + abs(s))
    assert paper.v1_mps == pytest.approx(v1, abs=1e4 * EPS * scale)


def test_ball_does_not_keep_its_angle():
    # The paper says the ball leaves at its incoming angle; frictionless theory says
    # tan(theta1) = v0 sin(theta) / v1n, which equals tan(theta) only if v1n = v0 cos(theta).
    case = ImpactCase(
        bat=R161,
        ball=BALL,
        s_m=0.1,
        v0_mps=46.9,
        u0_mps=17.87,
        omega0_radps=32.0,
        e=0.5,
        theta_rad=math.radians(20),
    )
    out = predict(case)
    assert math.tan(out.theta1_rad) == pytest.approx(46.9 * math.sin(case.theta_rad) / out.v1_mps)
    assert abs(math.degrees(out.theta1_rad) - 20) > 1.0
