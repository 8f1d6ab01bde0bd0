"""The frictional impact's derivatives (``analytic.friction_gradients``): the planar sliding
impact's closed form against Routh's integration (``friction.predict_friction``), its
complex-step derivatives against fourth-order differences of that integration, and the
frictionless limit against ``analytic.gradients``."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from analytic import friction_gradients as fg
from analytic import gradients, presets
from analytic.friction import RTOL
from analytic.model import ImpactCase

BAT, BALL = presets.R161, presets.BASEBALL
#: Oblique impacts that slide throughout (small mu; a still bat, then the paper's swing).
SLIDING = [
    dict(theta_rad=0.5, mu=0.02, v0_mps=40.0),
    dict(theta_rad=0.6, mu=0.1, v0_mps=40.0),
    dict(theta_rad=0.4, mu=0.03, v0_mps=40.0, u0_mps=17.87, omega0_radps=32.0),
    dict(theta_rad=-0.3, mu=0.05, v0_mps=30.0, s_m=-0.2),
]


def _case(**kw) -> ImpactCase:
    return ImpactCase(bat=BAT, ball=BALL, **({"s_m": 0.1, "e": 0.5} | kw))


@pytest.mark.parametrize("kw", SLIDING)
def test_the_sliding_closed_form_is_routh_integration(kw):
    # v1 = -v0 cos(theta) + p_f/m, vt1 = v0 sin(theta) - mu sigma p_f/m, p_f = (1+e)(-v_n0)/a:
    # the integration (tolerance 1e-13) ends where the formulas do, to 1e-11 m/s and rad/s
    case = _case(**kw)
    got = fg.sliding_fields(case)
    assert got["slides"]
    routh = fg._routh(case, "e", case.e)
    assert np.allclose([got[o] for o in fg.OUTPUTS], routh, rtol=0.0, atol=1e-10), routh


@pytest.mark.parametrize("kw", SLIDING)
def test_closed_form_derivatives_meet_routh_differences_to_1e9(kw):
    # every output x input: the complex step of the closed form against Richardson differences
    # of the integration, 1e-9 of the derivative; a derivative that vanishes (phi at 0) to the
    # differences' rounding, 10 RTOL times the output's scale (40 m/s, 4000 rad/s) over h
    case = _case(**kw)
    d = fg.friction_derivatives(case)
    assert d.closed_form
    for name in fg.INPUTS:
        want = fg.richardson(case, name)
        got = np.array([d.values[o][name] for o in fg.OUTPUTS])
        h = fg.DIFFERENCE_STEP * fg._scale(case, name)
        floor = 10 * RTOL * np.array([40.0, 40.0, 4000.0]) / h
        assert np.all(np.abs(got - want) <= 1e-9 * np.abs(want) + floor), (name, got, want)


def test_without_friction_the_closed_form_derivatives_are_the_planar_ones():
    # mu = 0, oblique: dv1/dx of the sliding closed form is analytic.gradients' for x in
    # s, v0, u0, omega0, e, both masses, J and the balance point (two independent closed
    # forms of the same impulse)
    kw = dict(theta_rad=0.3, mu=0.0, v0_mps=40.0, u0_mps=10.0, omega0_radps=20.0)
    d = fg.friction_derivatives(_case(**kw)).values["v1_mps"]
    planar = gradients.derivatives(
        BAT, BALL, s_m=0.1, v0_mps=40.0, u0_mps=10.0, omega0_radps=20.0, e=0.5, theta_rad=0.3
    )["v1_mps"]
    for name in (
        "s_m",
        "v0_mps",
        "u0_mps",
        "omega0_radps",
        "e",
        "ball_mass_kg",
        "bat_mass_kg",
        "bat_inertia_kgm2",
        "com_from_knob_m",
    ):
        assert d[name] == pytest.approx(float(planar[name]), rel=1e-12), name


def test_once_the_ball_sticks_its_speed_along_the_bat_no_longer_depends_on_mu():
    # at s = 0 (K_tn = -s r / J = 0: the normal impulse does not feel the friction) a ball that
    # stops slipping leaves with the slip at rest whatever mu is: dvt1/dmu = 0, to the
    # differences' rounding (1e-13 / 1e-3 of 40 m/s), while sliding it is -sigma p_f / m
    case = _case(s_m=0.0, theta_rad=0.3, mu=0.6, v0_mps=40.0)
    d = fg.friction_derivatives(case)
    assert not d.closed_form
    assert abs(d.values["vt1_mps"]["mu"]) < 1e-7
    sliding = fg.friction_derivatives(dataclasses.replace(case, mu=0.01))
    assert sliding.closed_form and sliding.values["vt1_mps"]["mu"] < -10.0
