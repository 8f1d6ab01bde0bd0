"""Closed-form derivatives of the planar frictionless impact (``impact.predict``) with respect to
every input: what an engine's gradient through the impact is judged against.

With v0n = v0 cos(theta), u0n = u0 cos(phi), v_c = v0n + u0n + omega0 s, D = 1/m + 1/M + s^2/J:
    P = (1 + e) v_c / D,   v1 = -v0n + P/m,   u1 = u0n - P/M,   omega1 = omega0 - P s / J.
The impulse's partial derivatives, each input alone varied:
    dP/ds  = [(1 + e) omega0 D - (1 + e) v_c 2 s / J] / D^2
    dP/dv0 = (1 + e) cos(theta) / D     dP/du0 = (1 + e) cos(phi) / D     dP/domega0 = (1 + e) s / D
    dP/de  = v_c / D
    dP/dm  = P / (D m^2)    dP/dM = P / (D M^2)    dP/dJ = P s^2 / (D J^2)
and the outputs' follow by the chain rule, with the explicit terms (P/m^2 in dv1/dm, ...).
The balance point: the impact fixed on the bat (its distance from the knob), the COM moved
toward the barrel by dx, so s = x_impact - x_com falls by dx (J about the COM held):
d/dx_com = -d/ds. At the sweet spot (``impact.sweet_spot``) dv1/ds = 0. With friction (the
tangential speed and spin, and mu): ``friction_gradients``.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from .impact import _bodies, _speeds
from .model import Ball, Bat

#: The inputs, as the derivatives name them.
INPUTS = (
    "s_m",
    "v0_mps",
    "u0_mps",
    "omega0_radps",
    "e",
    "ball_mass_kg",
    "bat_mass_kg",
    "bat_inertia_kgm2",
    "com_from_knob_m",
)
#: The outputs differentiated.
OUTPUTS = ("v1_mps", "u1_mps", "omega1_radps", "impulse_ns")


def normal_fields(m, M, J, s, v0n, u0n, w0, e) -> dict:
    """The normal-direction outcome (``impact.predict``'s formulas, no checks): arithmetic
    only, so that it takes complex numbers (complex-step differentiation) as well as arrays."""
    P = (1.0 + e) * (v0n + u0n + w0 * s) / (1.0 / m + 1.0 / M + s * s / J)
    return {
        "v1_mps": -v0n + P / m,
        "u1_mps": u0n - P / M,
        "omega1_radps": w0 - P * s / J,
        "impulse_ns": P,
    }


def derivatives(
    bat: Bat,
    ball: Ball,
    *,
    s_m: ArrayLike,
    v0_mps: ArrayLike,
    u0_mps: ArrayLike = 0.0,
    omega0_radps: ArrayLike = 0.0,
    e: ArrayLike = 0.5,
    theta_rad: ArrayLike = 0.0,
    phi_rad: ArrayLike = 0.0,
) -> dict:
    """d output / d input for every OUTPUTS x INPUTS (module docstring), broadcast over the
    arrays given: ``out["v1_mps"]["s_m"]`` is dv1/ds (1/s)."""
    _bodies(bat, ball)
    m, M, J = ball.mass_kg, bat.mass_kg, bat.inertia_cm_kgm2
    s = np.asarray(s_m, dtype=float)
    v0, u0, w0 = _speeds(v0_mps, u0_mps, omega0_radps)
    e = np.asarray(e, dtype=float)
    ct, cp = np.cos(np.asarray(theta_rad, float)), np.cos(np.asarray(phi_rad, float))
    vc = v0 * ct + u0 * cp + w0 * s
    D = 1.0 / m + 1.0 / M + s * s / J
    P = (1.0 + e) * vc / D
    dP = {
        "s_m": ((1.0 + e) * w0 * D - (1.0 + e) * vc * 2.0 * s / J) / D**2,
        "v0_mps": (1.0 + e) * ct / D,
        "u0_mps": (1.0 + e) * cp / D,
        "omega0_radps": (1.0 + e) * s / D,
        "e": vc / D,
        "ball_mass_kg": P / (D * m * m),
        "bat_mass_kg": P / (D * M * M),
        "bat_inertia_kgm2": P * s * s / (D * J * J),
    }
    dP["com_from_knob_m"] = -dP["s_m"]
    zero = np.zeros_like(P)
    v1 = {k: d / m for k, d in dP.items()}
    v1["v0_mps"] = v1["v0_mps"] - ct
    v1["ball_mass_kg"] = v1["ball_mass_kg"] - P / (m * m)
    u1 = {k: -d / M for k, d in dP.items()}
    u1["u0_mps"] = u1["u0_mps"] + cp
    u1["bat_mass_kg"] = u1["bat_mass_kg"] + P / (M * M)
    w1 = {k: -d * s / J for k, d in dP.items()}
    w1["omega0_radps"] = w1["omega0_radps"] + 1.0
    w1["s_m"] = w1["s_m"] - P / J
    w1["com_from_knob_m"] = w1["com_from_knob_m"] + P / J
    w1["bat_inertia_kgm2"] = w1["bat_inertia_kgm2"] + P * s / (J * J)
    out = {"v1_mps": v1, "u1_mps": u1, "omega1_radps": w1, "impulse_ns": dP}
    return {
        o: {k: np.broadcast_to(d + zero, P.shape) for k, d in g.items()} for o, g in out.items()
    }
