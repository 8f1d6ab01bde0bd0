"""The headline numbers over the joint range of their inputs (``inputs.spread``): the best
carries, the curveball's gain, the cork's and the metal bat's changes, the beam's node.

Each function here is one number as a function of the inputs it depends on (keywords named as
in ``inputs.INPUTS``), and ``*_spread`` carries it over their range. A carry is re-optimised
at every point of the range: the best point is searched afresh wherever the impact changes
(e, the pitch's spin, the bat), and the undercut (Brent, bounded, 0.2 mm) wherever the flight
does (drag, lift, the batted spin), at the speed sweet spot (the carry is flat along the barrel
there: the two sweet spots lie within 2 mm, section 3b). Units: m, m/s, cm where named.
"""

from __future__ import annotations

from dataclasses import replace
from functools import cache

from scipy import optimize

from analytic import Bat, SwingModel, beam, presets
from analytic.cork import corked_bat
from analytic.flight import NATHAN_2008, fly

from . import answers as A
from . import carry as C
from . import metal as M
from .inputs import Spread, spread

#: The undercut search's half-width about the central best undercut (m) and its tolerance:
#: the best undercut over every input stays within 1.2-2.3 cm (measured); the carry is flat
#: at its best (about 50 m/cm^2 of curvature), so 0.2 mm leaves it within 2 cm.
UNDERCUT_HALF_M, UNDERCUT_XATOL_M = 0.009, 2e-4
CARRY_INPUTS = ("e", "spin_share", "spin_boost", "drag_scale", "lift_scale")
CURVE_INPUTS = ("spin_share", "spin_boost", "drag_scale", "lift_scale")
CORK_INPUTS = ("wood_density_kgm3", "e")
CORK_CARRY_INPUTS = ("wood_density_kgm3", "e", "drag_scale", "lift_scale")
METAL_INPUTS = ("metal_com_fraction", "metal_rod_fraction", "e")
#: Beam elements of the node's profile check: 60 put the node within 0.02 mm of 160's (the
#: flex command's), at a sixth of the cost.
NODE_ELEMENTS = 60
PROFILE_INPUTS = ("knob_radius_m", "handle_end_m", "barrel_radius_m", "taper_exponent")


def _spin(spin: tuple[float, float, float], share: float) -> tuple[float, float, float]:
    """A pitch's spin with only ``share`` of it handed on by the impact."""
    return tuple(share * w for w in spin)


@cache
def best_carry_m(
    hit: C.Hit,
    at: tuple[float, float] | None = None,
    drag_scale: float = 1.0,
    lift_scale: float = 1.0,
    spin_boost: float = 1.0,
) -> float:
    """The longest carry (m) of ``hit`` with C_D and C_L scaled and the batted backspin times
    ``spin_boost``: the hit's own best point (``carry.best_point``) when ``at`` is None and
    the flight is Nathan's, else the best undercut within UNDERCUT_HALF_M of ``at``'s (s,
    undercut), at its s (the hit's own best point's when ``at`` is None)."""
    if at is None:
        best = C.best_point(hit)
        if (drag_scale, lift_scale, spin_boost) == (1.0, 1.0, 1.0):
            return best.carry_m
        at = (best.s_m, best.undercut_m)
    aero = NATHAN_2008.scaled(drag=drag_scale, lift=lift_scale)
    s_m, d0 = at

    def carry(d: float) -> float:
        launch = C.launch_of(hit, s_m, d)
        launch = replace(launch, backspin_radps=launch.backspin_radps * spin_boost)
        return fly(launch, aero=aero, samples=2, rtol=C.FLIGHT_RTOL).carry_m

    res = optimize.minimize_scalar(
        lambda d: -carry(float(d)),
        bounds=(max(0.0, d0 - UNDERCUT_HALF_M), d0 + UNDERCUT_HALF_M),
        method="bounded",
        options={"xatol": UNDERCUT_XATOL_M},
    )
    return float(-res.fun)


def _around(hit: C.Hit, central: C.Hit) -> tuple[float, float] | None:
    """Where to search ``hit``'s best undercut: its own best point if it is the central hit
    (None), else about the central hit's."""
    if hit == central:
        return None
    best = C.best_point(central)
    return (best.s_m, best.undercut_m)


@cache
def carry_spread(sc: A.Scenario) -> Spread:
    """The R161's longest fastball carry (m) over e, the spin handed on and its boost, drag and
    lift."""

    central = C.hit_of(sc)

    def f(e, spin_share, spin_boost, drag_scale, lift_scale):
        hit = C.hit_of(sc, e=e, spin_radps=_spin(C.FASTBALL, spin_share))
        return best_carry_m(hit, _around(hit, central), drag_scale, lift_scale, spin_boost)

    return spread(f, CARRY_INPUTS)


@cache
def curve_spread(sc: A.Scenario) -> Spread:
    """How much farther (m) the best-hit curveball carries than the best-hit fastball at the
    same speed, over the spin handed on (0: both leave alike), its boost, drag and lift."""

    centrals = [C.hit_of(sc, spin_radps=pitch) for pitch in (C.FASTBALL, C.CURVEBALL)]

    def f(spin_share, spin_boost, drag_scale, lift_scale):
        fast, curve = (
            best_carry_m(
                h := C.hit_of(sc, spin_radps=_spin(c.spin_radps, spin_share)),
                _around(h, c),
                drag_scale,
                lift_scale,
                spin_boost,
            )
            for c in centrals
        )
        return curve - fast

    return spread(f, CURVE_INPUTS)


def corked(rho: float) -> Bat:
    """The 1 x 10 in cork R161 in wood of ``rho`` (kg/m^3)."""
    return corked_bat(A.R161, wood_density_kgm3=rho)


@cache
def cork_spreads(sc: A.Scenario) -> dict[str, Spread]:
    """The 1 x 10 in cork's v1 change (m/s) at n = 0.27, 0.5 and 0 (the same swing), its
    break-even n, over the wood's density and e; its carry change (m) at n = 0.27 over those,
    drag and lift (the batted spin boost moves every ball alike: ``test_findings_ranges``)."""

    def gain(n: float):
        return lambda wood_density_kgm3, e: A.cork_gain(corked(wood_density_kgm3), sc, n, e)

    def same(wood_density_kgm3, e):
        bat = corked(wood_density_kgm3)
        return A.best_v1(bat, sc, A.same_swing(bat, sc), e)[1] - A.best_v1(A.R161, sc, e=e)[1]

    def hit(bat: Bat, e: float) -> C.Hit:
        return C.hit_of(sc, bat, A.carried_swing(bat, sc, SwingModel.MEASURED), e=e)

    centrals = (hit(A.CORK_1x10, A.E), C.hit_of(sc))

    def carry(wood_density_kgm3, e, drag_scale, lift_scale):
        hits = (hit(corked(wood_density_kgm3), e), C.hit_of(sc, e=e))
        cork, wood = (
            best_carry_m(h, _around(h, c), drag_scale, lift_scale)
            for h, c in zip(hits, centrals, strict=True)
        )
        return cork - wood

    return {
        "n027": spread(gain(0.27), CORK_INPUTS),
        "n05": spread(gain(0.5), CORK_INPUTS),
        "same": spread(same, CORK_INPUTS),
        "even": spread(
            lambda wood_density_kgm3, e: A.break_even_exponent(corked(wood_density_kgm3), sc, e),
            CORK_INPUTS,
        ),
        "carry027": spread(carry, CORK_CARRY_INPUTS),
    }


def metal_gain(
    sc: A.Scenario, length_in: float, model: str, com: float, rod: float, e: float
) -> float:
    """v1 at a drop -3 metal bat's best point minus the R161's (m/s), both at e, the swing
    carried over by ``model``, the metal bat's COM and J_cm as fractions."""
    bat = M.bbcor_bat(length_in, com_fraction=com, rod_fraction=rod)
    return A.best_v1(bat, sc, A.carried_swing(bat, sc, model), e)[1] - A.best_v1(A.R161, sc, e=e)[1]


@cache
def metal_spreads(sc: A.Scenario) -> dict[str, Spread]:
    """The metal bats against the R161 over their COM, J_cm and e: the 33 in one at n = 0.27
    and 0.5, the paper's 31 in one at n = 0.27 and 0.5, and the share of the 31 in bat's loss
    its shorter length explains (1 - 33 in's / 31 in's) under each."""
    out = {}
    for key, model in (("027", SwingModel.MEASURED), ("05", SwingModel.CONSTANT_TORQUE)):

        def equal(metal_com_fraction, metal_rod_fraction, e, model=model):
            return metal_gain(sc, 33, model, metal_com_fraction, metal_rod_fraction, e)

        def pair(metal_com_fraction, metal_rod_fraction, e, model=model):
            return metal_gain(sc, 31, model, metal_com_fraction, metal_rod_fraction, e)

        def share(metal_com_fraction, metal_rod_fraction, e, equal=equal, pair=pair):
            args = (metal_com_fraction, metal_rod_fraction, e)
            return 1.0 - equal(*args) / pair(*args)

        out[f"equal{key}"] = spread(equal, METAL_INPUTS)
        out[f"pair{key}"] = spread(pair, METAL_INPUTS)
        if key == "027":  # at constant torque the 31 in bat's loss is too small to share out
            out[f"length{key}"] = spread(share, METAL_INPUTS)
    return out


def node_cm(knob_radius_m, handle_end_m, barrel_radius_m, taper_exponent) -> float:
    """The first bending mode's barrel node (cm from the end) of the R161 fitted with this
    profile (``beam.fit_profile``: its mass, COM and J_cm held), Timoshenko, handbook ash."""
    profile, wood = beam.fit_profile(
        presets.R161,
        knob_radius_m=knob_radius_m,
        knob_length_m=0.012,
        handle_end_m=handle_end_m,
        barrel_radius_m=barrel_radius_m,
        taper_exponent=taper_exponent,
        wood=presets.ASH,
    )
    b = beam.Beam(profile=profile, wood=wood, shear=True, elements=NODE_ELEMENTS)
    return 100 * b.modes(1).barrel_node_from_tip_m(0)


@cache
def node_spread() -> Spread:
    """The node over the profile's assumed shape (a scale of E and G cannot move it: the mode
    shape of K - w^2 M is unchanged when K is scaled)."""
    return spread(node_cm, PROFILE_INPUTS)
