"""Compliant contact: the impact under a continuous normal force law, and its closed forms.

Impulse theory is the limit of a rigid contact. A soft contact (MuJoCo's, Drake's) and a real
ball last a finite time, during which the bat turns and moves. ``predict(case, law)`` integrates
the two bodies under a force law (``LinearSpringDamper``, ``HuntCrossley``, or a law resolved
once per impact at its closing speed, ``ImpactLaw``: ``analytic.ball.REALISTIC_BALL``) until
the force returns to zero.

A contact whose normal overlap x obeys x'' + 2 zeta w x' + w^2 x = 0 (Kelvin-Voigt, in the
contact's own coordinate) bounces with a coefficient of restitution that depends on the damping
ratio zeta alone: the contact ends when its force k x + b x' returns to zero, before x does.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Protocol

import numpy as np
from scipy import integrate, optimize

from . import checks
from .collide import _geometry, first_touch, outcome_fields
from .model import ImpactCase, Outcome


def restitution_of_damping_ratio(zeta: float) -> float:
    """e of a linear spring-damper contact released when its force reaches zero (any zeta >= 0).

    x'' + 2 zeta w x' + w^2 x = 0 from x = 0, x' = -v: the force k x + b x' first vanishes at
    w_d t = pi - arctan(2 zeta sqrt(1 - zeta^2) / (1 - 2 zeta^2)), where x'/v = -e with
        e = exp(-zeta/sqrt(1 - zeta^2) * (pi - arctan(2 zeta sqrt(1-zeta^2)/(1 - 2 zeta^2))))
    (T. Schwager and T. Poeschel, Phys. Rev. E 57, 650 (1998); the familiar exp(-zeta pi /
    sqrt(1-zeta^2)) assumes release at x = 0 and gives e too large.)
    """
    if zeta < 1.0:  # atan2 carries the formula through zeta = 1/sqrt 2 (their second case)
        root = math.sqrt(1.0 - zeta * zeta)
        return math.exp(-zeta / root * (math.pi - math.atan2(2 * zeta * root, 1 - 2 * zeta * zeta)))
    if zeta == 1.0:  # critically damped: the limit of both sides
        return math.exp(-2.0)
    s = math.sqrt(zeta * zeta - 1.0)  # overdamped: the same released at zero force
    return math.exp(-zeta / s * math.atanh(2 * zeta * s / (2 * zeta * zeta - 1)))


def damping_ratio_for(e: float) -> float:
    """Inverse of ``restitution_of_damping_ratio`` (zeta for a target e in (0, 1])."""
    checks.in_range("e", e, 0.0, 1.0, lo_open=True)
    if e == 1.0:
        return 0.0
    # e falls from 1 (zeta = 0) through e^-2 (critical) towards 0: bracket by doubling
    hi = 1.0
    while restitution_of_damping_ratio(hi) > e:
        hi *= 2.0
    return optimize.brentq(
        lambda z: restitution_of_damping_ratio(z) - e,
        0.0,
        hi,
        xtol=1e-15,
        rtol=4 * np.finfo(float).eps,
    )


# --- the two bodies under a normal force law -------------------------------------------------


@dataclass(frozen=True, kw_only=True)
class LinearSpringDamper:
    """Kelvin-Voigt contact: F = k x + c x' while positive (N), x the overlap (m), x' its rate
    (m/s); ``stiffness_npm`` k (N/m), ``damping_nspm`` c (N s/m). MuJoCo's soft contact is this
    law in the contact's own acceleration space."""

    stiffness_npm: float
    damping_nspm: float

    def __post_init__(self) -> None:
        checks.positive("stiffness_npm", self.stiffness_npm)
        checks.non_negative("damping_nspm", self.damping_nspm)

    def force_n(self, x_m: float, rate_mps: float, m_eff_kg: float = 1.0) -> float:
        return self.stiffness_npm * x_m + self.damping_nspm * rate_mps

    def release_value(self, x_m: float, rate_mps: float, m_eff_kg: float = 1.0) -> float:
        """Crosses zero, linearly in time, where the contact lets go."""
        return self.force_n(x_m, rate_mps)


@dataclass(frozen=True, kw_only=True)
class HuntCrossley:
    """Hunt-Crossley contact: F = k x^n (1 + d x') while positive (N); ``stiffness`` k
    (N/m^n), ``exponent`` n (1; 3/2 is Hertz's sphere), ``dissipation_spm`` d (s/m). Its
    restitution falls with the impact speed v0: a - ln(1 + a) = -e a - ln(1 - e a), a = d v0
    (``hunt_crossley_restitution``). Drake's point contact is this law with n = 1."""

    stiffness: float
    exponent: float
    dissipation_spm: float

    def __post_init__(self) -> None:
        checks.positive("stiffness", self.stiffness)
        checks.in_range("exponent", self.exponent, 1.0, 2.0)
        checks.non_negative("dissipation_spm", self.dissipation_spm)

    def force_n(self, x_m: float, rate_mps: float, m_eff_kg: float = 1.0) -> float:
        return self.stiffness * x_m**self.exponent * (1.0 + self.dissipation_spm * rate_mps)

    def release_value(self, x_m: float, rate_mps: float, m_eff_kg: float = 1.0) -> float:
        """F / x^(n-1): zero where F is, but crossing linearly in time at x = 0 (F ~ x^n
        would make the release instant ill-conditioned)."""
        return self.stiffness * x_m * (1.0 + self.dissipation_spm * rate_mps)

    def restitution(self, speed_mps: float) -> float:
        """e of an impact closing at ``speed_mps`` (``hunt_crossley_restitution``)."""
        return hunt_crossley_restitution(self.dissipation_spm, speed_mps)

    def at_speed(self, speed_mps: float) -> HuntCrossley:
        """This law, whatever the closing speed (its d is fixed): as ``ImpactLaw``'s."""
        return self


@dataclass(frozen=True, kw_only=True)
class ContactSpaceSpringDamper:
    """A spring-damper in the contact's own acceleration space, whatever the masses: the force
    is m_eff (w^2 x + 2 zeta w x'), m_eff = 1/(1/m + 1/M + s^2/J) at the current contact point,
    so that the part of x'' the force makes is -w^2 x - 2 zeta w x'. MuJoCo's soft contact
    (solref = (-w^2, -2 zeta w), constant impedance, exact diagonals) is this law: MuJoCo's
    constraint acceleration is J qacc, without the turning bat's J' qdot, so the latter stays
    in x'' (measured: MuJoCo converges to this law, not to one that also cancels J' qdot).
    ``omega_radps`` w (rad/s), ``damping_ratio`` zeta (1); released at zero force."""

    omega_radps: float
    damping_ratio: float

    def __post_init__(self) -> None:
        checks.positive("omega_radps", self.omega_radps)
        checks.non_negative("damping_ratio", self.damping_ratio)

    def force_n(self, x_m: float, rate_mps: float, m_eff_kg: float = 1.0) -> float:
        w = self.omega_radps
        return m_eff_kg * (w * w * x_m + 2 * self.damping_ratio * w * rate_mps)

    def release_value(self, x_m: float, rate_mps: float, m_eff_kg: float = 1.0) -> float:
        return self.force_n(x_m, rate_mps, m_eff_kg)


@dataclass(frozen=True, kw_only=True)
class Hysteretic:
    """A rate-independent hysteretic contact: on first loading F = k x^n; below the deepest
    overlap so far, x_m (``peak_m``: the integrator carries it), unloading and reloading follow
    one curve, F = k x_m^n ((x - x_r) / (x_m - x_r))^n, zero below x_r = (1 - e^2) x_m. The force
    depends on the overlap and its history, never on its rate. On a rigid wall the unloading
    gives back (x_m - x_r) / x_m = e^2 of the loading's work: restitution ``cor`` e at every
    speed. ``stiffness`` k (N/m^n), ``exponent`` n (3/2: Hertz's sphere). Only
    ``compliant.predict`` and ``flexible.predict`` carry the peak."""

    stiffness: float
    exponent: float
    cor: float

    def __post_init__(self) -> None:
        checks.positive("stiffness", self.stiffness)
        checks.in_range("exponent", self.exponent, 1.0, 2.0)
        checks.in_range("cor", self.cor, 0.0, 1.0, lo_open=True)

    def force_n(
        self, x_m: float, rate_mps: float, m_eff_kg: float = 1.0, peak_m: float = 0.0
    ) -> float:
        top = max(peak_m, x_m)
        rest = (1.0 - self.cor**2) * top
        if x_m <= rest:
            return 0.0
        return self.stiffness * top**self.exponent * ((x_m - rest) / (top - rest)) ** self.exponent

    def release_value(
        self, x_m: float, rate_mps: float, m_eff_kg: float = 1.0, peak_m: float = 0.0
    ) -> float:
        """x - x_r: positive while loading (e^2 x), zero where the force is."""
        return x_m - (1.0 - self.cor**2) * max(peak_m, x_m)


ContactLaw = LinearSpringDamper | HuntCrossley | ContactSpaceSpringDamper | Hysteretic


def force_of(law, x_m: float, rate_mps: float, m_eff_kg: float, peak_m: float) -> float:
    """``law``'s force (N), given the deepest overlap so far where the law has a memory (a
    ``Hysteretic`` one): every other law keeps the plain ``force_n(x, x', m_eff)``."""
    if isinstance(law, Hysteretic):
        return law.force_n(x_m, rate_mps, m_eff_kg, peak_m)
    return law.force_n(x_m, rate_mps, m_eff_kg)


def release_of(law, x_m: float, rate_mps: float, m_eff_kg: float, peak_m: float) -> float:
    """``law.release_value`` as ``force_of`` calls ``force_n``."""
    if isinstance(law, Hysteretic):
        return law.release_value(x_m, rate_mps, m_eff_kg, peak_m)
    return law.release_value(x_m, rate_mps, m_eff_kg)


def peak_rate(x_m: float, rate_mps: float, peak_m: float) -> float:
    """d(peak)/dt of the deepest overlap so far: the overlap's rate while it is the deepest."""
    return rate_mps if rate_mps > 0.0 and x_m >= peak_m else 0.0


class ImpactLaw(Protocol):
    """A law whose force depends on the impact: resolved once, at the closing speed of the
    first touch, into a ``ContactLaw`` (``at_speed``); ``restitution`` is its e there."""

    def at_speed(self, speed_mps: float) -> ContactLaw: ...

    def restitution(self, speed_mps: float) -> float: ...


def law_for_impact(law: ContactLaw | ImpactLaw, closing_mps: float) -> ContactLaw:
    """The force law of one impact closing at ``closing_mps`` (m/s): ``law.at_speed`` where
    the law has one (its dissipation set from the closing speed), else the law itself."""
    at_speed = getattr(law, "at_speed", None)
    if at_speed is None:
        return law
    return at_speed(checks.positive("closing_mps", closing_mps))


#: Superseded by ``analytic.ball.REALISTIC_BALL`` (whose COR follows its power law at every
#: speed); kept for comparison. A baseball against a rigid surface as a Hertz contact with
#: hysteresis (Hunt-Crossley, n = 3/2) and one dissipation, calibrated to two figures: e = 0.5
#: at 40 m/s (the ball-bat regime's COR, about 0.5 at 40-60 m/s [nathan2000]: A. M. Nathan,
#: Am. J. Phys. 68, 979 (2000)) and a contact time of 0.7 ms at 40 m/s (0.6-1 ms measured,
#: same source). Its e depends on d v0 alone and so falls too steeply: 0.61 at 25.9 m/s (MLB's
#: specification is 0.546 +- 0.032 at 85 ft/s [mlbcor]) and 0.39 at 60 m/s; a peak force of
#: 32 kN and a 6.6 mm deformation at 40 m/s. tests/test_analytic_compliant.py re-derives both
#: calibration figures by integration.
BASEBALL_HERTZ = HuntCrossley(
    stiffness=43593574.039150596, exponent=1.5, dissipation_spm=0.03581876333178441
)


def hunt_crossley_restitution(dissipation_spm: float, speed_mps: float) -> float:
    """e of a Hunt-Crossley contact hit at ``speed_mps``: the root in (0, 1/a) of
    a - ln(1 + a) = -e a - ln(1 - e a), a = d v0 (from m u du / (1 + d u) = -k x^n dx
    integrated over the whole contact; independent of k, n and the mass)."""
    a = dissipation_spm * speed_mps
    if a < 1e-8:  # e = 1 - 2a/3 + O(a^2), exact to float precision; the root-find cancels here
        return 1.0 - 2.0 * a / 3.0
    lhs = a - math.log1p(a)
    # in u = -ln(1 - e a) > 0: exp(-u) - 1 + u = lhs, one root in [0, lhs + 1] (bracketed to
    # lhs + 2: at lhs + 1 the sign can round away when exp(-u) underflows against 1)
    u = optimize.brentq(
        lambda u: math.expm1(-u) + u - lhs,
        0.0,
        lhs + 2.0,
        xtol=1e-300,
        rtol=4 * np.finfo(float).eps,
    )
    return -math.expm1(-u) / a


def hunt_crossley_dissipation(e: float, speed_mps: float) -> float:
    """The dissipation d (s/m) with which a Hunt-Crossley contact hit at ``speed_mps`` bounces
    with restitution ``e`` (the inverse of ``hunt_crossley_restitution``; e in (0, 1]). How an
    engine without a restitution parameter (Drake) is given one e at one stated speed: at other
    speeds its e follows the law."""
    checks.in_range("e", e, 0.0, 1.0, lo_open=True)
    checks.positive("speed_mps", speed_mps)
    if 1.0 - e < 1e-8:  # e = 1 - 2a/3 + O(a^2): exact to float precision here, where e(a) is flat
        return 1.5 * (1.0 - e) / speed_mps
    # e(a) falls from 1 at a = 0 towards 1/a: the root lies below a = 2/e + 1
    a = optimize.brentq(
        lambda a: hunt_crossley_restitution(a, 1.0) - e,
        0.0,
        2.0 / e + 1.0,
        xtol=1e-15,
        rtol=4 * np.finfo(float).eps,
    )
    return a / speed_mps


@dataclass(frozen=True, kw_only=True)
class CompliantOutcome(Outcome):
    """The outcome of a compliant impact (fields of ``Outcome``, when the force has returned to
    zero) and the contact itself: ``contact_duration_s`` (s), ``peak_force_n`` (N),
    ``peak_penetration_m`` (m) and ``bat_turn_rad`` (rad), how far the bat turned meanwhile."""

    contact_duration_s: float
    peak_force_n: float
    peak_penetration_m: float
    bat_turn_rad: float


#: solve_ivp tolerance of the compliant contact.
RTOL = 1e-12


def predict(case: ImpactCase, law: ContactLaw | ImpactLaw) -> CompliantOutcome:
    """The impact of ``case`` under a normal force ``law`` (frictionless): ball and free bat,
    planar, the bat turning and moving during the contact, integrated with solve_ivp (DOP853,
    rtol 1e-12) from the first touch until the force is back to zero. ``case.e`` is not used:
    the law sets the restitution (an ``ImpactLaw`` at the closing speed of the first touch).
    Frame and fields as ``analytic.predict``."""
    bat, ball = case.bat, case.ball
    m, M, J = ball.mass_kg, bat.mass_kg, bat.inertia_cm_kgm2
    reach = bat.radius_m + ball.radius_m
    y0 = first_touch(case)

    def state(z):
        """Overlap x, its rate and the reduced mass at the contact point."""
        d, tt, n = _geometry(z)
        s = float(d @ tt)
        x = reach - float(d @ n)
        rate = -(float((z[2:4] - z[6:8]) @ n) - z[9] * s)
        return x, rate, 1.0 / (1 / m + 1 / M + s * s / J), n, s

    law = law_for_impact(law, state(y0)[1])  # the overlap's rate at first touch: v_c
    y0 = np.append(y0, 0.0)  # z[10]: the deepest overlap so far (a hysteretic law's memory)

    def contact(z):
        x, rate, m_eff, n, s = state(z)
        return force_of(law, max(x, 0.0), rate, m_eff, z[10]), x, n, s, rate

    def rhs(t, z):
        f, x, n, s, rate = contact(z)
        f = max(f, 0.0) if x > 0.0 or t == 0.0 else 0.0
        a = f * n / m
        return [
            z[2],
            z[3],
            a[0],
            a[1],
            z[6],
            z[7],
            -f * n[0] / M,
            -f * n[1] / M,
            z[9],
            -f * s / J,
            peak_rate(x, rate, z[10]),
        ]

    def released(t, z):
        if t == 0.0:
            return 1.0
        x, rate, m_eff, _, _ = state(z)
        return release_of(law, x, rate, m_eff, z[10])

    released.terminal, released.direction = True, -1
    # a generous horizon: a Hertz contact of a baseball lasts about a millisecond
    sol = integrate.solve_ivp(
        rhs,
        (0.0, 1.0),
        y0,
        method="DOP853",
        rtol=RTOL,
        atol=RTOL * 1e-3 * (np.abs(y0).max() + 1.0),
        events=released,
        dense_output=False,
    )
    z = sol.y[:, -1]
    forces = [contact(sol.y[:, i]) for i in range(sol.y.shape[1])]
    return CompliantOutcome(
        **outcome_fields(case, y0[:10], z[:10]),
        contact_duration_s=float(sol.t[-1]),
        peak_force_n=max(max(f for f, *_ in forces), 0.0),
        peak_penetration_m=max(x for _, x, *_ in forces),
        bat_turn_rad=float(z[8]),
    )
