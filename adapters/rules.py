"""How an engine combines the two bodies' values of a contact property: restitution and
friction (an ``EngineRecord`` names its rules; tests pin them on the engine)."""

from __future__ import annotations

import math
from enum import Enum


class RestitutionRule(str, Enum):
    """How an engine turns the two bodies' restitution values into the contact's e."""

    PRODUCT = "product"  #: e = e_bat * e_ball
    MAX = "max"  #: e = max(e_bat, e_ball)
    MEAN = "mean"  #: e = (e_bat + e_ball) / 2
    MIN = "min"  #: e = min(e_bat, e_ball)
    MAPPED = "mapped"  #: no restitution parameter: the adapter maps e onto other knobs

    def combine(self, bat: float, ball: float) -> float:
        """The contact's e from the two bodies' values (not defined for MAPPED)."""
        if self is RestitutionRule.MAPPED:
            raise ValueError("a mapped restitution has no per-body values to combine")
        return {
            "product": bat * ball,
            "max": max(bat, ball),
            "mean": 0.5 * (bat + ball),
            "min": min(bat, ball),
        }[self.value]


class FrictionRule(str, Enum):
    """How an engine turns the two bodies' friction coefficients into the contact's mu."""

    PRODUCT = "product"  #: mu = mu_bat * mu_ball
    MAX = "max"  #: mu = max(mu_bat, mu_ball)
    MEAN = "mean"  #: mu = (mu_bat + mu_ball) / 2
    MIN = "min"  #: mu = min(mu_bat, mu_ball)
    GEOMETRIC = "geometric"  #: mu = sqrt(mu_bat mu_ball)
    HARMONIC = "harmonic"  #: mu = 2 mu_bat mu_ball / (mu_bat + mu_ball)

    def combine(self, bat: float, ball: float) -> float:
        """The contact's mu from the two bodies' values."""
        if self is FrictionRule.HARMONIC:
            return 0.0 if bat + ball == 0.0 else 2.0 * bat * ball / (bat + ball)
        return {
            "product": bat * ball,
            "max": max(bat, ball),
            "mean": 0.5 * (bat + ball),
            "min": min(bat, ball),
            "geometric": math.sqrt(bat * ball),
        }[self.value]

    def per_body(self, mu: float) -> tuple[float, float]:
        """(bat, ball) values that this rule combines into ``mu``: the same value on both
        bodies for every rule but the product (bat mu, ball 1), which it equals too."""
        return (mu, 1.0) if self is FrictionRule.PRODUCT else (mu, mu)
