"""Shared hypothesis strategies and numeric constants for the tests."""

from __future__ import annotations

import math
import os

import numpy as np
from hypothesis import HealthCheck, settings
from hypothesis import strategies as st

from analytic import Ball, Bat, ImpactCase

os.environ["BATSIM_QUIET"] = "1"  # no progress lines in test output (subprocesses too)

settings.register_profile("ci", deadline=None, max_examples=200,
                          suppress_health_check=[HealthCheck.too_slow])
settings.load_profile("ci")

EPS = np.finfo(float).eps  # 2.2e-16: unit roundoff of float64


@st.composite
def bats(draw) -> Bat:
    """Physically plausible bats: J between 0.1 and 1 times a uniform rod's M L^2 / 12."""
    length = draw(st.floats(0.5, 1.2))
    mass = draw(st.floats(0.3, 2.0))
    return Bat(
        name="random",
        length_m=length,
        radius_m=draw(st.floats(0.02, 0.045)),
        mass_kg=mass,
        com_from_knob_m=draw(st.floats(0.35, 0.75)) * length,
        inertia_cm_kgm2=draw(st.floats(0.1, 1.0)) * mass * length**2 / 12,
    )


@st.composite
def cases(draw, oblique: bool = False) -> ImpactCase:
    """Random impacts that approach (closing speed > 1 m/s) on the hittable part of the bat."""
    bat = draw(bats())
    ball = Ball(name="random", mass_kg=draw(st.floats(0.05, 0.5)), radius_m=0.0366)
    s = draw(st.floats(bat.s_min_m, bat.s_max_m))
    v0 = draw(st.floats(1.0, 60.0))
    u0 = draw(st.floats(-5.0, 30.0))
    w0 = draw(st.floats(-50.0, 50.0))
    angle = st.floats(-1.2, 1.2) if oblique else st.just(0.0)
    theta, phi = draw(angle), draw(angle)
    closing = v0 * math.cos(theta) + u0 * math.cos(phi) + w0 * s
    if closing < 1.0:  # keep only impacts; hypothesis.assume would discard too many draws
        u0 += (1.0 - closing) / math.cos(phi) + draw(st.floats(0.0, 20.0))
    return ImpactCase(bat=bat, ball=ball, s_m=s, v0_mps=v0, u0_mps=u0, omega0_radps=w0,
                      e=draw(st.floats(0.0, 1.0)), theta_rad=theta, phi_rad=phi)
