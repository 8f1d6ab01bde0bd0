"""What to fire: one bat and ball, one motion, a grid of impact points (``Firing``), and the
grid itself (``grid``). A firing gives its cases and its jobs for an engine; the runner fires
them, the judge (``verdicts``) judges them, the table lays them out."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

import adapters
from analytic import Bat, ImpactCase, presets
from analytic.dynamics import HingedSwing

from .fire import Jobs


@dataclass(frozen=True, kw_only=True)
class Firing:
    """What to fire: one bat and ball, one motion, a grid of s. Units: m, m/s, rad/s, rad."""

    bat: Bat
    s_m: tuple[float, ...]
    v0_mps: float
    u0_mps: float
    omega0_radps: float
    e: float
    theta_rad: float = 0.0
    hands_from_knob_m: float = 0.1
    #: Swing the bat about the hands in the engine before each impact (u0, omega0 then come from
    #: the swing; ``u0_mps`` and ``omega0_radps`` are its nominal values).
    swing: HingedSwing | None = None
    #: Friction and the third dimension, as ``ImpactCase`` takes them (0: frictionless, planar).
    mu: float = 0.0
    undercut_m: float = 0.0
    spin_radps: tuple[float, float, float] = (0.0, 0.0, 0.0)

    def case(self, s_m: float) -> ImpactCase:
        """The impact at one grid point (validates every field)."""
        return ImpactCase(
            bat=self.bat,
            ball=presets.BASEBALL,
            s_m=s_m,
            v0_mps=self.v0_mps,
            u0_mps=self.u0_mps,
            omega0_radps=self.omega0_radps,
            e=self.e,
            theta_rad=self.theta_rad,
            hands_from_knob_m=self.hands_from_knob_m,
            mu=self.mu,
            undercut_m=self.undercut_m,
            spin_radps=self.spin_radps,
        )

    def cases(self) -> list[ImpactCase]:
        return [self.case(s) for s in self.s_m]

    def jobs(self, engine: str, settings: adapters.Settings) -> Jobs:
        """One job per grid point for an engine."""
        return Jobs(engine=engine, settings=settings, cases=self.cases(), swing=self.swing)


def grid(
    bat: Bat, points: int, s_min_m: float | None = None, s_max_m: float | None = None
) -> tuple[float, ...]:
    """``points`` evenly spaced impact points over the bat's hittable length (or a part of it)."""
    lo = bat.s_min_m if s_min_m is None else s_min_m
    hi = bat.s_max_m if s_max_m is None else s_max_m
    if points < 2:
        raise ValueError(f"points={points} is too few; allowed: points >= 2")
    for name, value in (("s_min", lo), ("s_max", hi)):
        if not bat.s_min_m - 1e-12 <= value <= bat.s_max_m + 1e-12:
            raise ValueError(
                f"{name}={value:g} m is off the bat '{bat.name}'; allowed: "
                f"{bat.s_min_m:.4f} <= s <= {bat.s_max_m:.4f} m (the capsule's "
                "cylinder, from the COM)"
            )
    if not lo < hi:
        raise ValueError(f"s_min={lo:g} >= s_max={hi:g}; allowed: s_min < s_max")
    return tuple(float(x) for x in np.linspace(lo, hi, points))
