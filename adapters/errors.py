"""An engine's error model: what the judge needs to know of an engine to say how far from the
answer that applies its impact may land, and which answer applies.

The base class states an exact rigid-impulse engine in float64; an engine overrides what its
contact does otherwise. Each method takes the settings the impact was fired with (``s``), since
most of these errors follow from them (a soft contact's law from its stiffness, a regulariser's
bias from its impedance). Settings carry the knobs alone; this is where the judge's questions
about them are answered.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from enum import Enum

import numpy as np


class ContactReference(str, Enum):
    """The continuous model an engine's contact converges to as its time step shrinks."""

    RIGID_IMPULSE = "rigid impulse"  #: Newton's restitution law, instantaneous (analytic.predict)
    LINEAR_SPRING_DAMPER = "linear spring-damper"  #: x'' = -b x' - k x in the contact coordinate
    #: F = k x^n (1 + d x'): a penalty force with Hunt-Crossley dissipation (analytic.compliant)
    HUNT_CROSSLEY = "Hunt-Crossley"


@dataclass(frozen=True, kw_only=True)
class ErrorModel:
    """``precision``: the float type the engine computes in ("float64" or "float32").
    ``host_rounding``: its kernels are compiled for the host's CPU (XLA), whose instruction set
    orders the rounding: a committed baseline is reproduced bit for bit only where it was made.
    ``friction_defect``/``chain_defect``/``gradient_defect``: a measured failure of its
    friction at impact, of its segmented bat, or of its own derivative through an impact, that
    no setting removes ('' for none): the tests then pin that the engine still misses theory
    there, and the report quotes it. The methods: what its contact
    does with settings ``s``."""

    precision: str = "float64"
    host_rounding: bool = False
    friction_defect: str = ""
    chain_defect: str = ""
    gradient_defect: str = ""

    def __post_init__(self) -> None:
        if self.precision not in ("float64", "float32"):
            raise ValueError(f"precision={self.precision!r} is unknown; allowed: float64, float32")

    @property
    def eps(self) -> float:
        """Unit roundoff of the engine's float type (2.2e-16 for float64, 1.2e-7 for float32)."""
        return float(np.finfo(self.precision).eps)

    def contact_reference(self, s) -> ContactReference:
        """The continuous model the contact converges to as the step shrinks."""
        return ContactReference.RIGID_IMPULSE

    def contact_law(self, s, e: float):
        """The continuous contact law (``analytic.compliant``) the contact converges to at
        restitution ``e``, or None for a rigid contact."""
        return None

    def law_restitution_error(self, s, dt_over_contact: float) -> float:
        """The relative error of the restitution a step of ``dt_over_contact`` contact times
        leaves in a compliant contact (its leading term; the judge allows a multiple of it).
        Semi-implicit Euler through a spring-damper: (pi/3) dt/t_c (measured -5.0e-3 for MuJoCo
        at w = 3000 rad/s, dt = 1e-5 s, against 5.2e-3 from the formula)."""
        return math.pi / 3.0 * dt_over_contact

    def untuned_contact_s(self, s) -> float | None:
        """How long a contact lasts when the engine's contact is not tuned to any model (its
        own soft constraint, say), for estimating a run's cost; None: as long as in the model
        it converges to."""
        return None

    def mapping_error_rel(self, s) -> float:
        """The relative error the engine's mapping of e leaves in a contact's impulse (a known
        bias of the mapping, not a precision); 0 for an exact mapping."""
        return 0.0

    def solve_conditioning(self, s) -> float:
        """How much the engine's contact solve amplifies its rounding (a condition number): a
        stiff regulariser's solve in float32 loses that many ulps; 1 for a well-posed one."""
        return 1.0

    def collision_slide_m(self, s, bat) -> float:
        """How far along the bat's axis (m) the engine's collision routine may put the contact
        foot from the true closest point (a bias of its own, not a precision), which the judge
        adds to the foot's slide; 0 for an exact routine."""
        return 0.0

    def speculative_margin_m(self, s) -> float:
        """The gap (m) below which the engine already solves a contact (speculative contact):
        such a contact is solved from the geometry at the start of the step that closes it, up
        to a whole step early; 0 for engines that see a contact once the bodies overlap."""
        return 0.0

    def friction_law(self, s) -> str:
        """The frictional impulse law (``analytic.friction.LAWS``) the contact converges to as
        its step shrinks: an impulse engine's 'one_step' (Newton's restitution and Coulomb's
        cone on the total impulse), or a convex solver's 'relaxed' one (a slide leaves faster
        by mu times its final slip)."""
        return "one_step"

    def friction_mapping_error_rel(self, s) -> float:
        """The share of a slip the engine's friction mapping leaves where Coulomb's law would
        stop it within the step (a regularised friction row); 0 for an exact one."""
        return 0.0

    def friction_cone(self, s) -> str:
        """How the engine's contact approximates Coulomb's cone with these settings, in words
        (tables and the friction study record it); '' for an engine without friction."""
        return ""
