"""Swing-speed models: how fast a batter swings a bat, given how fast he swings a reference bat.

All three keep the reference swing's instantaneous centre of rotation fixed relative to the knob
and scale the whole velocity field by one factor (except the paper's, which scales u0 only):
    u0 = k (u0_ref + omega0_ref (x_cm - x_cm_ref)),   omega0 = k omega0_ref
- ``constant_force`` (the paper, eq. 8.1.5): a constant hand force F gives u0 proportional to
  1/M; the paper keeps omega0 fixed, and so does this model: u0 = u0_ref M_ref/M.
- ``constant_torque``: a constant torque over a fixed swing angle does work tau*dtheta =
  I_knob omega^2/2, so k = (I_ref/I)^(1/2).
- ``measured``: swing speed scales as I^-n with n = 0.27 for swing weights above 0.03 kg m^2
  (R. Cross and R. Bower, "Effects of swing-weight on swing speed and racket power",
  J. Sports Sci. 24(1), 23-30 (2006); they cite n = 0.25 for softball bats, 0.26 for golf clubs).
"""

from __future__ import annotations

from dataclasses import dataclass
from enum import Enum

from . import checks
from .model import Bat

MEASURED_EXPONENT = 0.27  #: n in swing speed ~ I^-n (Cross & Bower 2006, J. Sports Sci. 24, 23)


class SwingModel(str, Enum):
    """Named swing-speed models (see the module docstring)."""

    CONSTANT_FORCE = "constant_force"
    CONSTANT_TORQUE = "constant_torque"
    MEASURED = "measured"


@dataclass(frozen=True, kw_only=True)
class Swing:
    """A bat's motion just before impact: COM speed ``u0_mps`` (m/s), ``omega0_radps`` (rad/s)."""

    u0_mps: float
    omega0_radps: float

    def speed_at(self, s_m: float) -> float:
        """Speed of the bat point at s from the COM, u0 + omega0 s (m/s)."""
        return self.u0_mps + self.omega0_radps * s_m


def swing_for(
    bat: Bat,
    *,
    model: SwingModel | str,
    reference_bat: Bat,
    reference: Swing,
    pivot_from_knob_m: float = 0.0,
    exponent: float = MEASURED_EXPONENT,
) -> Swing:
    """The swing a batter gives ``bat`` under ``model`` if he gives ``reference_bat`` ``reference``.

    I is taken about ``pivot_from_knob_m`` (the knob by default, the usual 'swing weight').
    """
    model = SwingModel(model)
    checks.in_range("exponent", exponent, 0.0, 2.0)
    if model is SwingModel.CONSTANT_FORCE:
        return Swing(
            u0_mps=reference.u0_mps * reference_bat.mass_kg / bat.mass_kg,
            omega0_radps=reference.omega0_radps,
        )
    power = 0.5 if model is SwingModel.CONSTANT_TORQUE else exponent
    ratio = reference_bat.inertia_about(pivot_from_knob_m) / bat.inertia_about(pivot_from_knob_m)
    k = ratio**power
    shift = bat.com_from_knob_m - reference_bat.com_from_knob_m
    return Swing(
        u0_mps=k * (reference.u0_mps + reference.omega0_radps * shift),
        omega0_radps=k * reference.omega0_radps,
    )
