"""Derivatives of the frictional impact (``friction.predict_friction``, Routh's method): the
ball's normal speed v1, its speed along the bat vt1 and its spin about z, with respect to the
impact point, the speeds, the angles, e, mu, both masses, J and the balance point (the impact
held where it is on the bat, as in ``gradients``).

In the swing plane, while the contact points slip one way throughout (Stronge, Impact
Mechanics, sec. 4.2-4.3), the impact has a closed form. With the impact frame's t along the bat
and n toward the ball, the contact points r_ball = (0, -R), r_bat = (s, r) (R, r the radii),
the relative velocity of the points changes with the impulse P = (P_t, P_n) on the ball as
    dv = K dP,  K_tt = 1/m + 1/M + R^2/I + r^2/J,  K_nn = 1/m + 1/M + s^2/J,  K_tn = -s r / J.
Slipping at sign sigma = sgn v_t0, dP/dp = (-mu sigma, 1): compression ends at p_c = -v_n0 / a,
a = K_nn - mu sigma K_tn, and both Poisson's and the energetic hypothesis end the impact at
p_f = (1 + e) p_c. It slides throughout while sigma v_t(p_f) > 0, v_t(p) = v_t0 + (K_tn - mu
sigma K_tt) p. Then
    v1 = -v0 cos(theta) + p_f / m,  vt1 = v0 sin(theta) - mu sigma p_f / m,
    spin1 = w0_ball - R mu sigma p_f / I.
Its derivatives are taken by a complex step of these formulas (exact to rounding: no
subtraction). Where the slip stops (the ball rolls off: once stuck, the friction needed is
below mu and vt1 no longer depends on mu), turns, or leaves the plane, Routh's method has no
closed form: fourth-order central differences (Richardson) of its integration, converged to
``friction.RTOL``.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from .friction import predict_friction
from .model import ImpactCase

OUTPUTS = ("v1_mps", "vt1_mps", "spin1_radps")
INPUTS = (
    "s_m",
    "v0_mps",
    "theta_rad",
    "u0_mps",
    "phi_rad",
    "omega0_radps",
    "e",
    "mu",
    "ball_mass_kg",
    "bat_mass_kg",
    "bat_inertia_kgm2",
    "com_from_knob_m",
)
#: The inputs that are the bodies' (the rest are the case's own fields).
BODY_INPUTS = {
    "ball_mass_kg": ("ball", "mass_kg"),
    "bat_mass_kg": ("bat", "mass_kg"),
    "bat_inertia_kgm2": ("bat", "inertia_cm_kgm2"),
    "com_from_knob_m": ("bat", "com_from_knob_m"),
}
#: The complex step (of each input's scale): no subtraction, so any small step is exact.
COMPLEX_STEP = 1e-30
#: The central differences' step (of each input's scale) in the numerical regime: the
#: rounding term RTOL/h and the truncation h^4 balance near 1e-3.
DIFFERENCE_STEP = 1e-3


@dataclasses.dataclass(frozen=True, kw_only=True)
class FrictionDerivatives:
    """``values[output][input]``; ``closed_form``: whether the impact slides throughout in the
    plane (complex step of the closed form) or not (differences of Routh's integration)."""

    values: dict
    closed_form: bool


def value_of(case: ImpactCase, name: str) -> float:
    """Input ``name`` of ``case`` (a field of the case, or of its bat or ball)."""
    if name in BODY_INPUTS:
        body, field = BODY_INPUTS[name]
        return getattr(getattr(case, body), field)
    return getattr(case, name)


def _scale(case: ImpactCase, name: str) -> float:
    """The size an input's step is measured against."""
    fixed = {
        "s_m": case.bat.length_m,
        "com_from_knob_m": case.bat.length_m,
        "theta_rad": 1.0,
        "phi_rad": 1.0,
        "e": 1.0,
        "mu": 1.0,
    }
    if name in fixed:
        return fixed[name]
    value = abs(value_of(case, name))
    return value if name in BODY_INPUTS else max(value, 1.0)


def _inputs(case: ImpactCase) -> dict:
    return {k: value_of(case, k) for k in INPUTS}


def moved(case: ImpactCase, name: str, x: float) -> ImpactCase:
    """``case`` with input ``name`` at ``x``; the balance point moved with the impact held
    where it is on the bat (s, from the COM, falls as much as the COM moves)."""
    if name not in BODY_INPUTS:
        return dataclasses.replace(case, **{name: x})
    body, field = BODY_INPUTS[name]
    out = dataclasses.replace(
        case, **{body: dataclasses.replace(getattr(case, body), **{field: x})}
    )
    if name == "com_from_knob_m":
        out = dataclasses.replace(out, s_m=case.s_m - (x - case.bat.com_from_knob_m))
    return out


def sliding_fields(case: ImpactCase, **x) -> dict:
    """The planar sliding impact's outputs (module docstring) at ``case`` with inputs ``x``
    (any of INPUTS; complex allowed), and ``slides``: whether it slides throughout."""
    v = _inputs(case) | x
    bat, ball = case.bat, case.ball
    m, M, J = v["ball_mass_kg"], v["bat_mass_kg"], v["bat_inertia_kgm2"]
    R, r = ball.radius_m, bat.radius_m
    inertia = 0.4 * m * R * R  # a uniform sphere's (``model.Ball``)
    s = v["s_m"] - (v["com_from_knob_m"] - bat.com_from_knob_m)
    w_ball = case.spin_radps[2]
    k_tt = 1 / m + 1 / M + R * R / inertia + r * r / J
    k_nn, k_tn = 1 / m + 1 / M + s * s / J, -s * r / J
    v_t0 = (
        v["v0_mps"] * np.sin(v["theta_rad"])
        + w_ball * R
        - v["u0_mps"] * np.sin(v["phi_rad"])
        + v["omega0_radps"] * r
    )
    v_n0 = -(
        v["v0_mps"] * np.cos(v["theta_rad"])
        + v["u0_mps"] * np.cos(v["phi_rad"])
        + v["omega0_radps"] * s
    )
    sigma = math.copysign(1.0, np.real(v_t0))
    a = k_nn - v["mu"] * sigma * k_tn
    p_f = (1 + v["e"]) * -v_n0 / a
    v_t_end = v_t0 + (k_tn - v["mu"] * sigma * k_tt) * p_f
    slides = bool(
        np.real(v_t0) != 0
        and np.real(a) > 0
        and sigma * np.real(v_t_end) > 0
        and not case.out_of_plane
    )
    return {
        "v1_mps": -v["v0_mps"] * np.cos(v["theta_rad"]) + p_f / m,
        "vt1_mps": v["v0_mps"] * np.sin(v["theta_rad"]) - v["mu"] * sigma * p_f / m,
        "spin1_radps": w_ball - R * v["mu"] * sigma * p_f / inertia,
        "slides": slides,
    }


def _routh(case: ImpactCase, name: str, x: float) -> np.ndarray:
    out = predict_friction(moved(case, name, x))
    return np.array([out.ball_velocity_mps[1], out.ball_velocity_mps[0], out.ball_spin_radps[2]])


def richardson(case: ImpactCase, name: str) -> np.ndarray:
    """The outputs' derivative along ``name`` by Richardson's fourth-order central difference of
    Routh's integration: (4 D(h/2) - D(h)) / 3, h = DIFFERENCE_STEP of the input's scale."""
    x, h = value_of(case, name), DIFFERENCE_STEP * _scale(case, name)

    def central(k: float) -> np.ndarray:
        return (_routh(case, name, x + k) - _routh(case, name, x - k)) / (2 * k)

    return (4 * central(h / 2) - central(h)) / 3


def friction_derivatives(case: ImpactCase) -> FrictionDerivatives:
    """d output / d input for every OUTPUTS x INPUTS at ``case`` (module docstring)."""
    values: dict = {o: {} for o in OUTPUTS}
    closed = sliding_fields(case)["slides"]
    for name in INPUTS:
        x, h = value_of(case, name), _scale(case, name)
        if closed:
            got = sliding_fields(case, **{name: x + 1j * COMPLEX_STEP * h})
            d = {o: float(np.imag(got[o])) / (COMPLEX_STEP * h) for o in OUTPUTS}
        else:
            d = dict(zip(OUTPUTS, map(float, richardson(case, name))))
        for o in OUTPUTS:
            values[o][name] = d[o]
    return FrictionDerivatives(values=values, closed_form=closed)
