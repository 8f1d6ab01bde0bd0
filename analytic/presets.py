"""Reference bats, ball and swing, each with its source.

Unit conversions: 1 in = 0.0254 m, 1 oz = 0.028349523125 kg, 1 lb = 0.45359237 kg.
"""

from __future__ import annotations

import functools
from types import MappingProxyType

from . import checks
from .beam import ASH, Profile, Wood, fit_profile
from .model import Ball, Bat
from .swing import Swing

IN_M = 0.0254
OZ_KG = 0.028349523125
LB_KG = 0.45359237

#: Effective capsule radius of a wood bat (m). A barrel is at most 2.61 in (66.3 mm) across (MLB
#: Official Baseball Rules 3.02(a)) and tapers toward the handle; 60 mm is a round value for the
#: hitting zone that keeps the capsule's cylinder out to s = 0.25 m on the R161, the end of the
#: paper's range. For a head-on, frictionless hit in the swing plane v1 does not depend on it
#: (the normal meets the axis, no torque arm across it); with an undercut D the normal tilts by
#: asin(D / (r_ball + r_bat)), so the best undercut scales with it: 2.01 cm here, 2.10 cm on a
#: 2.61 in barrel (the MLB-like swing; findings section 3b).
WOOD_BARREL_RADIUS_M = 0.030

R161 = Bat(
    name="r161",
    length_m=0.84,
    radius_m=WOOD_BARREL_RADIUS_M,
    mass_kg=0.871,
    com_from_knob_m=0.56,
    inertia_cm_kgm2=0.039,
)
"""Louisville Slugger R161 wood bat: 0.871 kg, 0.84 m, COM 0.56 m from the knob,
J_cm = 0.039 kg m^2 (R. Cross, "Mechanics of swinging a bat", Am. J. Phys. 77, 36 (2009);
the values the paper uses in its section 6.3)."""

EASTON31 = Bat(
    name="easton31",
    length_m=31 * IN_M,
    radius_m=2.625 * IN_M / 2,
    mass_kg=28 * OZ_KG,
    com_from_knob_m=0.60 * 31 * IN_M,
    inertia_cm_kgm2=70 * LB_KG * IN_M**2,
)
"""Aluminium bat (Easton, the paper's section 9): 31 in (0.787 m), 28 oz (0.794 kg),
J_cm = 70 lb in^2 (0.0205 kg m^2), as the paper states them.
ASSUMED, not in the paper: the COM at 60% of the length from the knob (18.6 in; hollow metal
bats balance nearer the handle than wood, the R161's being at 67%) and a 2 5/8 in barrel."""

BATS = MappingProxyType({b.name: b for b in (R161, EASTON31)})
"""Bats by name (read-only)."""

HOLLOW = (EASTON31,)
"""Bats whose barrel is a metal shell, hollow already: there is no wood in it to drill and fill
(``analytic.cork`` refuses them)."""


def profile(bat: Bat):
    """The radius along ``bat`` (an ``analytic.beam.Profile``, m from the knob) where it is
    known: the R161's fitted profile (``r161_profile``: knob, handle, taper, barrel, with
    the preset's mass, COM and J_cm) for the R161; None for any other bat, whose capsule's
    radius is all that is known of it."""
    return _r161_profile() if bat == R161 else None


@functools.cache
def _r161_profile():
    return r161_profile()[0]


BASEBALL = Ball(name="baseball", mass_kg=0.145, radius_m=0.0366)
"""Official baseball: 5 to 5 1/4 oz (0.142-0.149 kg) and 9 to 9 1/4 in around (radius
0.0364-0.0373 m) (Official Baseball Rules 3.01); 0.145 kg and 0.0366 m as in DESIGN.md."""

PAPER_PITCH_MPS = 46.9
"""Fastest pitch the paper considers, 46.9 m/s (105 mph; its section 6.3)."""

PAPER_SWING = Swing(u0_mps=17.87, omega0_radps=32.0)
"""The paper's swing of the R161 (section 6.3): COM speed 17.87 m/s, 32 rad/s."""

E_WOOD = 0.5
"""Ball-bat coefficient of restitution against wood, and the BBCOR limit for other bats (0.50)."""


#: The R161 (``R161``: 0.871 kg, 0.84 m, COM 0.56 m, J_cm 0.039 kg m^2) as a profile.
#: Given: a 2.5 in (63.5 mm) barrel, a 1.7 in (43 mm), 12 mm knob, the handle out to 10 in
#: (0.254 m) and a flared taper (exponent 2), round values of a wood bat's (a barrel at most
#: 2.61 in: MLB Official Baseball Rules 3.02(a)). Solved for (``fit_profile``): the handle's
#: radius (14.5 mm), where the barrel starts (0.56 m) and ash's density (583 kg/m^3, inside
#: the handbook's 0.55-0.67 specific gravity of white ash). The modes are not fitted.
def r161_profile(wood: Wood = ASH) -> tuple[Profile, Wood]:
    """The R161's fitted profile and ``wood`` at the fitted density."""
    checks.instance("wood", wood, Wood)
    return fit_profile(
        R161,
        knob_radius_m=0.0215,
        knob_length_m=0.012,
        handle_end_m=0.254,
        barrel_radius_m=0.03175,
        taper_exponent=2.0,
        wood=wood,
    )
