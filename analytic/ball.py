"""A realistic baseball: Hertz's pulse with a COR that falls with impact speed.

A Hunt-Crossley contact's restitution depends on a = d v0 alone (``compliant``), so one
dissipation d fixes e at one speed only, and ``compliant.BASEBALL_HERTZ`` (e = 0.5 at 40 m/s)
falls too steeply: 0.61 at 25.9 m/s, 0.39 at 60. ``RealisticBall`` instead takes e from a
power law (``CorLaw``) and, per impact, the Hunt-Crossley d that gives that e at the impact's
closing speed: the COR-speed curve with a Hertz pulse shape (a phenomenological ball, not a
model of its core). ``HystereticBall`` has the same e(v) on a wall from a rate-independent
loss (``compliant.Hysteretic``): the two differ only where the contact's rate matters (a
yielding bat).

The speed dependence is an assumption. The published statements (``COR_DATA``) are one test
speed, MLB's 85 ft/s, and a qualitative "about 0.5" at 40-60 m/s; the fall with speed is
reported [sawicki2003] [shenoy2001], but no speed-resolved table of it could be read. So
``COR_LAW`` is a central choice through MLB's centre and Nathan's 0.5, and ``COR_LAWS`` the
range every number resting on it carries: MLB's band at 85 ft/s times an exponent from 0 (no
fall) to 1/4 (elastic-plastic impact [johnson1985]).

Sources by key: mlbcor (MLB's ball specification), msnbc2003 (D. Ropeik, "Squeezing the
'juice' out of baseballs", msnbc.com, 2003: the UMass Lowell Baseball Research Center's MLB
balls), nathan2000 (A. M. Nathan, Am. J. Phys. 68, 979 (2000)), ncaa (the NCAA BBCOR
standard, 2011), johnson1985 (K. L. Johnson, Contact Mechanics, CUP (1985), ch. 11),
sawicki2003 (G. S. Sawicki, M. Hubbard, W. J. Stronge, Am. J. Phys. 71, 1152 (2003),
abstract), shenoy2001 (M. M. Shenoy, L. V. Smith, J. T. Axtell, Composite Structures 52, 397
(2001), abstract).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from . import checks, compliant
from .compliant import BASEBALL_HERTZ, HuntCrossley, Hysteretic, hunt_crossley_dissipation
from .model import Ball, Bat, ImpactCase
from .presets import BASEBALL

#: Kinds of COR statement: a ball fired at a rigid wall, or at a stationary bat.
KINDS = ("ball-wall", "ball-bat")
#: The power law's reference speed (m/s): 85 ft/s, MLB's test speed [mlbcor].
SPEED_REF_MPS = 25.9


@dataclass(frozen=True, kw_only=True)
class CorPoint:
    """One published statement of a ball's COR: ``cor`` (1) within +- ``half_width`` (1, the
    statement's own range: a tolerance band, or how precisely it was given) at ``speed_mps``
    (m/s), ``kind`` (one of KINDS), ``source`` (a reference key) and ``note``. A
    ``qualitative`` statement ("about 0.5 at 40-60 m/s") is no measurement: it spans
    ``speed_mps`` +- ``speed_half_width_mps`` and has no error bar (``half_width`` 0)."""

    speed_mps: float
    cor: float
    half_width: float
    kind: str
    source: str
    note: str
    qualitative: bool = False
    speed_half_width_mps: float = 0.0

    def __post_init__(self) -> None:
        checks.positive("speed_mps", self.speed_mps)
        checks.in_range("cor", self.cor, 0.0, 1.0, lo_open=True)
        checks.non_negative("half_width", self.half_width)
        if self.kind not in KINDS:
            raise ValueError(f"kind={self.kind!r} is unknown; allowed: {', '.join(KINDS)}")


#: What is published about an MLB ball's COR, by source key.
COR_DATA = (
    CorPoint(
        speed_mps=25.9,
        cor=0.546,
        half_width=0.032,
        kind="ball-wall",
        source="mlbcor",
        note="specification: 0.514-0.578 fired at 85 ft/s at northern white ash",
    ),
    CorPoint(
        speed_mps=25.9,
        cor=0.55,
        half_width=0.005,
        kind="ball-wall",
        source="msnbc2003",
        note="the same test: UMass Lowell's sample mean, given to two digits",
    ),
    CorPoint(
        speed_mps=50.0,
        cor=0.50,
        half_width=0.0,
        kind="ball-wall",
        source="nathan2000",
        note="'about 0.5' at 40-60 m/s: qualitative, no measurement; the central law is "
        "chosen to pass 0.5 at 50 m/s",
        qualitative=True,
        speed_half_width_mps=10.0,
    ),
    CorPoint(
        speed_mps=60.8,
        cor=0.50,
        half_width=0.0,
        kind="ball-bat",
        source="ncaa",
        note="BBCOR's cap at 136 mph on a still bat (its recoil and vibration in it)",
    ),
)


@dataclass(frozen=True, kw_only=True)
class CorLaw:
    """e(v) = ``cor_ref`` (v / ``speed_ref_mps``)^-``exponent``, capped at 1 (an elastic
    bounce; the cap is reached only far below the data). A power law: elastic-plastic impact
    gives e ~ v^-1/4 [johnson1985]. Exponents above 1 would make the rebound speed e v fall as
    the impact speed rises, so they are refused."""

    cor_ref: float
    speed_ref_mps: float
    exponent: float

    def __post_init__(self) -> None:
        checks.in_range("cor_ref", self.cor_ref, 0.0, 1.0, lo_open=True)
        checks.positive("speed_ref_mps", self.speed_ref_mps)
        checks.in_range("exponent", self.exponent, 0.0, 1.0)

    def cor(self, speed_mps: float) -> float:
        """The COR (1) of an impact closing at ``speed_mps`` (m/s, > 0)."""
        v = checks.positive("speed_mps", speed_mps)
        return min(1.0, self.cor_ref * (v / self.speed_ref_mps) ** -self.exponent)


def law_through(cor_ref: float, speed_mps: float, cor: float) -> CorLaw:
    """The power law with ``cor_ref`` at SPEED_REF_MPS that passes ``cor`` at ``speed_mps``."""
    exponent = math.log(cor_ref / cor) / math.log(speed_mps / SPEED_REF_MPS)
    return CorLaw(cor_ref=cor_ref, speed_ref_mps=SPEED_REF_MPS, exponent=exponent)


#: The central law, an assumption: MLB's centre at 85 ft/s, 0.546 [mlbcor], and Nathan's
#: "about 0.5" at the middle of 40-60 m/s [nathan2000]: e falls as v^-0.134 (0.516 at 40 m/s,
#: 0.489 at 60).
COR_LAW = law_through(0.546, 50.0, 0.50)
#: The exponents the range spans: no fall, and elastic-plastic impact's 1/4 [johnson1985].
EXPONENT_RANGE = (0.0, 0.25)
#: The range: MLB's band at 85 ft/s [mlbcor] times EXPONENT_RANGE, as its four corners. e(v)
#: is monotonic in both, so at every speed its extremes are corners.
COR_LAWS = tuple(
    CorLaw(cor_ref=c, speed_ref_mps=SPEED_REF_MPS, exponent=p)
    for c in (0.514, 0.578)
    for p in EXPONENT_RANGE
)


def cor_range(speed_mps: float) -> tuple[float, float]:
    """(least, largest) COR (1) of COR_LAWS at ``speed_mps`` (m/s)."""
    cors = [law.cor(speed_mps) for law in COR_LAWS]
    return min(cors), max(cors)


@dataclass(frozen=True, kw_only=True)
class CorBall:
    """A Hertz-shaped ball whose COR follows ``cor_law`` at every impact speed: ``stiffness``
    k (N/m^n), ``exponent`` n (1; 3/2 is Hertz's sphere). Its kinds differ only in the contact
    law ``at_speed`` resolves at the first touch's closing speed (kept through re-touches).
    Pass it wherever a contact law goes: ``compliant.law_for_impact`` resolves it."""

    stiffness: float
    exponent: float
    cor_law: CorLaw

    def __post_init__(self) -> None:
        checks.positive("stiffness", self.stiffness)
        checks.in_range("exponent", self.exponent, 1.0, 2.0)
        if not isinstance(self.cor_law, CorLaw):
            raise ValueError(f"cor_law={self.cor_law!r} is not a CorLaw; allowed: a CorLaw")

    def restitution(self, speed_mps: float) -> float:
        """The COR (1) of an impact closing at ``speed_mps`` (m/s)."""
        return self.cor_law.cor(speed_mps)


@dataclass(frozen=True, kw_only=True)
class RealisticBall(CorBall):
    """The rate-dependent ball: F = k x^n (1 + d x'), d set once per impact so that
    e(v0) = cor_law.cor(v0) exactly (``at_speed``)."""

    def at_speed(self, speed_mps: float) -> HuntCrossley:
        """The Hunt-Crossley law of one impact closing at ``speed_mps`` (m/s, > 0): the d for
        which a - ln(1 + a) = -e a - ln(1 - e a), a = d v0, holds with e = cor_law.cor(v0)."""
        d = hunt_crossley_dissipation(self.cor_law.cor(speed_mps), speed_mps)
        return HuntCrossley(stiffness=self.stiffness, exponent=self.exponent, dissipation_spm=d)


@dataclass(frozen=True, kw_only=True)
class HystereticBall(CorBall):
    """The rate-independent ball: per impact the ``compliant.Hysteretic`` law with e =
    cor_law.cor(v0). On a wall its e(v) is the realistic ball's; on a yielding bat its loss
    does not fall as the compression slows."""

    def at_speed(self, speed_mps: float) -> Hysteretic:
        """The hysteretic law of one impact closing at ``speed_mps`` (m/s, > 0)."""
        return Hysteretic(
            stiffness=self.stiffness,
            exponent=self.exponent,
            cor=self.cor_law.cor(checks.positive("speed_mps", speed_mps)),
        )


#: A wall: so heavy and so hard to turn that the reduced mass is the ball's.
WALL = Bat(
    name="wall",
    length_m=1.0,
    radius_m=0.03,
    mass_kg=1e12,
    com_from_knob_m=0.5,
    inertia_cm_kgm2=1e12,
)


#: The kinds of ball a COR law makes: the rate-dependent (Hunt-Crossley) and the rate-
#: independent (hysteretic) one.
BALL_KINDS = {"hunt-crossley": RealisticBall, "hysteretic": HystereticBall}


#: What a contact time measures: how long the force lasts ("force"), or how long until the
#: gap between ball and wall closes again ("gap"). They differ for the hysteretic ball, whose
#: force vanishes at the residual overlap x_r = (1 - e^2) x_max, which then closes at the
#: rebound speed e v; a Hunt-Crossley ball lets go where its overlap closes (1 - d e v > 0
#: there: d e v is 0.58-0.84 over COR_LAWS at 10-80 m/s), so both are one time for it.
CONTACT_DEFINITIONS = ("force", "gap")


def wall_contact_s(
    law: CorBall, speed_mps: float, definition: str = "force", ball: Ball = BASEBALL
) -> float:
    """The contact time (s) of ``ball`` under ``law`` on a rigid wall at ``speed_mps`` by
    ``definition`` (CONTACT_DEFINITIONS): the force's duration, plus for "gap" the time
    x_r / (e v) the residual overlap x_r of a hysteretic ball takes to close at its rebound
    speed."""
    checks.choice("definition", definition, CONTACT_DEFINITIONS)
    case = ImpactCase(bat=WALL, ball=ball, s_m=0.0, v0_mps=speed_mps, e=0.5)
    out = compliant.predict(case, law)
    if definition == "force" or not isinstance(law, HystereticBall):
        return out.contact_duration_s
    e = law.restitution(speed_mps)
    return out.contact_duration_s + (1.0 - e * e) * out.peak_penetration_m / (e * speed_mps)


def wall_stiffness(
    cor_law: CorLaw,
    ball: Ball,
    *,
    duration_s: float,
    speed_mps: float,
    exponent: float = 1.5,
    kind: str = "hunt-crossley",
    definition: str = "force",
) -> float:
    """The stiffness k (N/m^n) with which ``ball`` (of ``kind``, BALL_KINDS) on a rigid wall at
    ``speed_mps`` stays in contact ``duration_s`` (by ``definition``, CONTACT_DEFINITIONS).
    x'' = -(k/m) x^n (1 + d x') scales with x* = (m v^2/k)^(1/(n+1)), t* = x*/v, leaving
    X'' = -X^n (1 + a X'), a = d v (the hysteretic law scales alike, with no a): at fixed a
    either duration goes as k^(-1/(n+1)), so one integration at a trial k gives k exactly (two
    passes for roundoff)."""
    make = BALL_KINDS[checks.choice("kind", kind, tuple(BALL_KINDS))]
    k = 1e8
    for _ in range(2):
        trial = make(stiffness=k, exponent=exponent, cor_law=cor_law)
        t = wall_contact_s(trial, speed_mps, definition, ball)
        k *= (t / duration_s) ** (exponent + 1.0)
    return k


#: The contact time both balls are calibrated to: 0.7 ms on a wall at 40 m/s (0.6-1 ms
#: measured [nathan2000]).
CONTACT_S, CONTACT_SPEED_MPS = 0.7e-3, 40.0


def ball_of(
    cor_law: CorLaw,
    kind: str = "hunt-crossley",
    ball: Ball | None = None,
    definition: str = "force",
):
    """A ball of ``kind`` (BALL_KINDS) with ``cor_law``, Hertz's exponent and the stiffness
    for which it stays CONTACT_S on a wall at CONTACT_SPEED_MPS (``wall_stiffness``), the
    contact time read by ``definition`` (CONTACT_DEFINITIONS)."""
    k = wall_stiffness(
        cor_law,
        ball or BASEBALL,
        duration_s=CONTACT_S,
        speed_mps=CONTACT_SPEED_MPS,
        kind=kind,
        definition=definition,
    )
    return BALL_KINDS[kind](stiffness=k, exponent=1.5, cor_law=cor_law)


#: The default realistic baseball: COR_LAW's restitution, Hertz's exponent and the stiffness
#: for which it stays 0.7 ms on a wall at 40 m/s (``ball_of``, re-derived by the tests). On
#: the wall it then lasts 0.75 ms at 25.9 m/s and 0.65 ms at 60 m/s, and at 40 m/s peaks at
#: 31 kN and 6.7 mm compression.
REALISTIC_BALL = RealisticBall(stiffness=42873266.67825176, exponent=1.5, cor_law=COR_LAW)
#: The rate-independent ball with the same e(v) and contact time on a wall (``ball_of``): its
#: unloading curve is steeper than its loading, so it is softer on loading, 23 kN and 12.6 mm
#: at 40 m/s.
HYSTERETIC_BALL = HystereticBall(stiffness=16411436.516395548, exponent=1.5, cor_law=COR_LAW)
#: The same hysteretic ball with 0.7 ms read as the time until the gap closes
#: (``ball_of(..., definition="gap")``): the residual overlap left when its force lets go
#: closes 0.45 ms later, so it is 3.4 times stiffer. Both readings fit "contact 0.6-1 ms"
#: [nathan2000]; the findings carry both.
HYSTERETIC_BALL_GAP = HystereticBall(stiffness=56487310.41803272, exponent=1.5, cor_law=COR_LAW)

#: Laws a sweep can put beside the rigid answer, by name: the realistic ball (the default),
#: the rate-independent one, and the single-d Hertz law the first supersedes.
LAWS = {"ball": REALISTIC_BALL, "hysteretic": HYSTERETIC_BALL, "hertz": BASEBALL_HERTZ}

__all__ = [
    "BALL_KINDS",
    "CONTACT_DEFINITIONS",
    "COR_DATA",
    "CorBall",
    "COR_LAW",
    "COR_LAWS",
    "CorLaw",
    "CorPoint",
    "HYSTERETIC_BALL",
    "HYSTERETIC_BALL_GAP",
    "HystereticBall",
    "LAWS",
    "REALISTIC_BALL",
    "RealisticBall",
    "ball_of",
    "cor_range",
    "law_through",
    "wall_contact_s",
    "wall_stiffness",
]
