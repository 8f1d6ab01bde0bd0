"""Compliant contact: closed forms of a linear spring-damper contact released at zero force.

A contact whose normal overlap x obeys x'' + 2 zeta w x' + w^2 x = 0 (Kelvin-Voigt, in the
contact's own coordinate) bounces with a coefficient of restitution that depends on the damping
ratio zeta alone: the contact ends when its force k x + b x' returns to zero, before x does.
"""

from __future__ import annotations

import math

import numpy as np
from scipy import optimize

from . import _checks


def restitution_of_damping_ratio(zeta: float) -> float:
    """e of a linear spring-damper contact released when its force reaches zero (zeta < 1/sqrt 2).

    x'' + 2 zeta w x' + w^2 x = 0 from x = 0, x' = -v: the force k x + b x' first vanishes at
    w_d t = pi - arctan(2 zeta sqrt(1 - zeta^2) / (1 - 2 zeta^2)), where x'/v = -e with
        e = exp(-zeta/sqrt(1 - zeta^2) * (pi - arctan(2 zeta sqrt(1-zeta^2)/(1 - 2 zeta^2))))
    (T. Schwager and T. Poeschel, Phys. Rev. E 57, 650 (1998); the familiar exp(-zeta pi /
    sqrt(1-zeta^2)) assumes release at x = 0 and gives e too large.)
    """
    root = math.sqrt(1.0 - zeta * zeta)
    return math.exp(-zeta / root * (math.pi - math.atan2(2 * zeta * root, 1 - 2 * zeta * zeta)))


def damping_ratio_for(e: float) -> float:
    """Inverse of ``restitution_of_damping_ratio`` (zeta for a target e in (0, 1])."""
    _checks.in_range("e", e, 0.0, 1.0, lo_open=True)
    if e == 1.0:
        return 0.0
    return optimize.brentq(lambda z: restitution_of_damping_ratio(z) - e, 0.0, 1 / math.sqrt(2) - 1e-12,
                           xtol=1e-15, rtol=4 * np.finfo(float).eps)
