"""Each engine's contact semantics, pinned by tiny tests: what plays the role of e, and how."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import integrate

import adapters
from adapters.mujoco import damping_ratio_for, restitution_of_damping_ratio
from analytic import Ball, ImpactCase, presets

from .conftest import EPS

R161, BALL = presets.R161, presets.BASEBALL


def _central_e(engine, v0=40.0, e=0.5, bat=R161) -> float:
    """Measured e of a central impact (s = 0: no rotation): separation / approach speed."""
    out = engine.simulate(ImpactCase(bat=bat, ball=BALL, s_m=0.0, v0_mps=v0, e=e))
    return (out.v1_mps - out.u1_mps) / v0


def test_pymunk_restitution_is_the_product_of_elasticities():
    # Chipmunk: arbiter e = e_a * e_b. Two equal discs head on: v_sep = 0.6 * 0.5 * v_app.
    import pymunk

    space = pymunk.Space()
    bodies = []
    for x, v, el in ((-1.0, 1.0, 0.6), (1.0, -1.0, 0.5)):
        body = pymunk.Body(1.0, 1.0)
        body.position, body.velocity = (x, 0.0), (v, 0.0)
        shape = pymunk.Circle(body, 0.5)
        shape.elasticity, shape.friction = el, 0.0
        space.add(body, shape)
        bodies.append(body)
    for _ in range(200):
        space.step(0.01)
    v_sep = bodies[1].velocity.x - bodies[0].velocity.x
    assert v_sep == pytest.approx(0.3 * 2.0, rel=1e3 * EPS)


def test_pybullet_restitution_is_the_product_and_has_a_threshold():
    # Bullet combines the two bodies' restitution as their product: bat 0.6 x ball 0.5 = 0.3
    # (a min rule would give 0.5). Below restitutionVelocityThreshold it drops restitution to
    # zero: a 40 m/s impact under a 50 m/s threshold is perfectly inelastic (separation 0).
    import pybullet as pb

    eng = adapters.load("pybullet")
    assert _central_e(eng) == pytest.approx(0.5, abs=1e4 * EPS)
    pb.changeDynamics(eng._bat, -1, restitution=0.6, physicsClientId=eng._client)
    assert _central_e(eng) == pytest.approx(0.3, abs=1e4 * EPS)
    eng.close()
    slow = adapters.load("pybullet", restitution_velocity_threshold=50.0)
    assert _central_e(slow) == pytest.approx(0.0, abs=1e4 * EPS)
    slow.close()


def test_mujoco_impulse_mode_gives_e_exactly():
    # solref = (0, -(1+e)/dt): one Euler step reverses the normal velocity by (1+e) v_n.
    eng = adapters.load("mujoco")
    for e in (0.0, 0.3, 0.5, 1.0):
        assert _central_e(eng, e=e) == pytest.approx(e, abs=1e4 * EPS)


def test_spring_damper_restitution_formula_against_ode():
    # Integrate x'' = -2 zeta x' - x from x = 0, x' = -1 until the force x + 2 zeta x' returns to
    # zero; e = final speed. rtol 1e-12 in solve_ivp bounds the comparison at ~1e-10.
    for zeta in (0.05, 0.2553, 0.5):
        def rhs(t, y, z=zeta):
            return [y[1], -2 * z * y[1] - y[0]]

        def released(t, y, z=zeta):
            return y[0] + 2 * z * y[1] if t > 1e-9 else -1.0

        released.terminal, released.direction = True, 1
        sol = integrate.solve_ivp(rhs, (0, 10), [0.0, -1.0], events=released, rtol=1e-12,
                                  atol=1e-14)
        e_ode = sol.y_events[0][0][1]
        assert restitution_of_damping_ratio(zeta) == pytest.approx(e_ode, rel=1e-9)
    assert damping_ratio_for(0.5) == pytest.approx(0.2553, abs=1e-4)  # ENGINE_NOTES' measurement


@pytest.mark.parametrize("w,dt", [(3000.0, 1e-5), (3000.0, 1e-6)])
def test_mujoco_soft_calibration_is_independent_of_speed_and_mass(w, dt):
    # Soft mode: x'' = -b x' - k x in the contact's normal coordinate, whatever the masses, so
    # the measured e is the target up to the Euler discretization error, first order in w*dt
    # (measured coefficient ~1/6; we allow w*dt/2), and does not change with speed or mass.
    eng = adapters.load("mujoco", contact_model="soft", soft_omega_radps=w, dt_s=dt)
    heavy = R161.__class__(**{**R161.__dict__, "name": "heavy", "mass_kg": 3.0})
    measured = [_central_e(eng, v0=v, bat=bat) for v in (5.0, 40.0, 80.0) for bat in (R161, heavy)]
    assert np.all(np.abs(np.array(measured) - 0.5) <= w * dt / 2)
    assert np.ptp(measured) <= 1e-9 + w * dt * 1e-3  # independent of speed and effective mass
