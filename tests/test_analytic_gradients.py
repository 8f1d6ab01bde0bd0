"""The closed-form derivatives of the impact (``analytic.gradients``) against differentiation of
the closed form itself: a complex step (exact to round-off: Im f(x + i h) / h, no cancellation)
for every output and input, and, the issue's bar, dv1/ds against a central difference of the
public ``batted_ball_speed`` to 1e-6 relative; and dv1/ds = 0 at the sweet spot."""

from __future__ import annotations

import numpy as np
import pytest

from analytic import gradients, impact, presets

BAT, BALL = presets.R161, presets.BASEBALL
S = np.linspace(-0.4, BAT.s_barrel_end_m - 0.01, 9)  # room for a difference step
SWINGS = [
    dict(v0_mps=46.9, u0_mps=17.87, omega0_radps=32.0, e=0.5),  # the paper's swing
    dict(v0_mps=40.0, u0_mps=0.0, omega0_radps=0.0, e=0.0),  # still bat, plastic
    dict(
        v0_mps=30.0,
        u0_mps=10.0,
        omega0_radps=-20.0,
        e=1.0,  # elastic, oblique
        theta_rad=0.3,
        phi_rad=-0.2,
    ),
]
H = 1e-30  # complex step: no subtraction, so any small step is exact to round-off


def _fields(inputs: dict, swing: dict) -> dict:
    """``normal_fields`` at these inputs (complex where one is stepped)."""
    c = np.cos(swing.get("theta_rad", 0.0)), np.cos(swing.get("phi_rad", 0.0))
    return gradients.normal_fields(
        inputs["ball_mass_kg"],
        inputs["bat_mass_kg"],
        inputs["bat_inertia_kgm2"],
        inputs["s_m"] - inputs["com_from_knob_m"],
        inputs["v0_mps"] * c[0],
        inputs["u0_mps"] * c[1],
        inputs["omega0_radps"],
        inputs["e"],
    )


def _inputs(swing: dict) -> dict:
    # s measured from the COM: the impact held on the bat while the COM moves (x_com = 0 here)
    return {
        "s_m": S.astype(complex),
        "v0_mps": swing["v0_mps"],
        "u0_mps": swing["u0_mps"],
        "omega0_radps": swing["omega0_radps"],
        "e": swing["e"],
        "ball_mass_kg": BALL.mass_kg,
        "bat_mass_kg": BAT.mass_kg,
        "bat_inertia_kgm2": BAT.inertia_cm_kgm2,
        "com_from_knob_m": 0.0,
    }


@pytest.mark.parametrize("swing", SWINGS, ids=["paper swing", "still plastic", "oblique"])
def test_every_derivative_is_the_complex_step_of_the_closed_form(swing):
    got = gradients.derivatives(BAT, BALL, s_m=S, **swing)
    for name in gradients.INPUTS:
        stepped = _inputs(swing)
        stepped[name] = stepped[name] + 1j * H
        want = {k: np.imag(v) / H for k, v in _fields(stepped, swing).items()}
        for out in gradients.OUTPUTS:
            # 1e-9 of the largest value over the grid: a derivative that passes through zero
            # (dv1/ds at the sweet spot) is judged on its scale, not on its own size
            scale = np.max(np.abs(want[out])) + 1e-300
            np.testing.assert_allclose(
                got[out][name], want[out], rtol=0, atol=1e-9 * scale, err_msg=f"d{out}/d{name}"
            )


def test_the_differentiated_form_is_the_one_predict_uses():
    # normal_fields repeats predict_arrays' formulas without its checks: equal to round-off,
    # a few ulps of the largest value (v1 = -v0n + P/m cancels near its zero)
    swing = SWINGS[0]
    real = {k: np.real(v) for k, v in _fields(_inputs(swing), swing).items()}
    ref = impact.predict_arrays(BAT, BALL, s_m=S, **swing)
    for out in gradients.OUTPUTS:
        ulp = np.finfo(float).eps * np.max(np.abs(ref[out]))
        np.testing.assert_allclose(real[out], ref[out], rtol=0, atol=8 * ulp)


def test_dv1_ds_matches_a_central_difference_of_batted_ball_speed():
    # central difference, h = 1e-4 m: truncation ~ h^2 |v1'''| / 6 and rounding ~ eps |v1| / h
    # are both below 1e-8 of dv1/ds away from its zero (the sweet spot, left 3 cm clear)
    swing = SWINGS[0]
    star = impact.sweet_spot(BAT, BALL, swing["v0_mps"], swing["u0_mps"], swing["omega0_radps"])
    s = S[np.abs(S - star) > 0.03]
    h = 1e-4
    fd = (
        impact.batted_ball_speed(BAT, BALL, s + h, **swing)
        - impact.batted_ball_speed(BAT, BALL, s - h, **swing)
    ) / (2 * h)
    got = gradients.derivatives(BAT, BALL, s_m=s, **swing)["v1_mps"]["s_m"]
    np.testing.assert_allclose(got, fd, rtol=1e-6)


@pytest.mark.parametrize("swing", SWINGS[:1] + SWINGS[2:], ids=["paper swing", "oblique"])
def test_dv1_ds_vanishes_at_the_sweet_spot(swing):
    # the sweet spot is the root of dv1/ds (impact.sweet_spot's closed form): zero there, to
    # 1e-12 of the slope's scale (1 + e) |omega0| / (1 + m/M), and of opposite signs either side
    args = {k: swing.get(k, 0.0) for k in ("theta_rad", "phi_rad")}
    star = impact.sweet_spot(
        BAT, BALL, swing["v0_mps"], swing["u0_mps"], swing["omega0_radps"], **args
    )
    d = gradients.derivatives(BAT, BALL, s_m=np.array([star - 0.05, star, star + 0.05]), **swing)[
        "v1_mps"
    ]["s_m"]
    scale = (1 + swing["e"]) * abs(swing["omega0_radps"]) / (1 + BALL.mass_kg / BAT.mass_kg)
    assert abs(d[1]) <= 1e-12 * scale
    assert d[0] * d[2] < 0
