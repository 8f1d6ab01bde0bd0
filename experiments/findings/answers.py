"""The computations behind ``results/findings.md``: the paper's questions answered with numbers.

Each function returns numbers or tables (no prose, no plotting) so that tests can check the
physics they rest on; ``experiments.findings`` writes them up. The metal-bat answers are in
``experiments.findings.metal``. Everything here is a result of the rigid-bat impact model
(``analytic``) unless a function says it fires engines or uses the compliant ball
(``analytic.compliant``). Units: m, m/s, rad/s, kg, kg m^2, s, unless a column name says
otherwise (mm, cm, %).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np
import pandas as pd
from scipy import optimize

import adapters
from analytic import (
    MEASURED_EXPONENT,
    Bat,
    ImpactCase,
    Swing,
    SwingModel,
    batted_ball_speed,
    center_of_percussion,
    corked_bat_paper,
    hittable_sweet_spot,
    predict,
    predict_oblique_paper,
    presets,
    sweet_region,
    sweet_spot,
    sweet_zone,
    swing_for,
)
from analytic.cork import corked_bat

from ..core import firings, locate, tables
from ..core.fire import Job
from ..core.runner import Runner

R161, AL, BALL = presets.R161, presets.EASTON31, presets.BASEBALL
E = presets.E_WOOD
IN = 0.0254
HANDS_M = 0.1  # the paper's holding point, 0.1 m from the knob
RUSSELL_CM = (12.7, 17.8)  # Russell's sweet region, cm from the barrel end [russell]
PLATE_TO_RUBBER_M = 18.44  # 60 ft 6 in
PITCHER_AFTER_FOLLOW_THROUGH_M = 16.5  # where the pitcher releases the ball [mlbrelease]
REACTION_S = 0.4  # an assumed reaction time (a round figure, no source)
FILLS = {"cork": 200.0, "rubber": 1100.0, "hollow": 0.0}
#: The density of the wood a hole removes (kg/m^3): a 1 x 10 in hole took 2.9 oz (82 g) from
#: a wood bat [nathancork] (its range: ``inputs.INPUTS["wood_density_kgm3"]``)
HOLE_WOOD_KGM3 = 640.0
DEPTHS_IN = (6, 8, 10)
SWEET_ZONE_WITHIN = 0.01  # the sweet zone: v1 within 1% of the swing's best
NATHAN_Q_FROM_END_M = 6 * IN  # Nathan et al. measured q 6 in from the barrel end
HANDS_PITCHES_MPS = (35.0, 41.0, 47.0)  # pitches and bat rates of the swings from the hands
HANDS_OMEGAS_RADPS = np.linspace(12, 48, 37)
#: Batting swings: the MLB-like swing's 48 rad/s +- 8, turning about the knob (as measured
#: [nathan2011se]) or the hands; the paper's 12-48 rad/s reaches down to swings no batter hits with
BATTING_OMEGAS_RADPS = np.linspace(40, 56, 17)
BATTING_PIVOTS_M = (0.0, HANDS_M)


@dataclass(frozen=True, kw_only=True)
class Scenario:
    """A pitch and a swing: ``v0_mps`` the pitch, ``swing`` the bat's COM speed and rate (m/s,
    rad/s) on the R161; ``bat_speed_mps`` the bat's speed at its sweet spot (m/s)."""

    key: str
    label: str
    v0_mps: float
    swing: Swing

    @property
    def bat_speed_mps(self) -> float:
        s = hittable_sweet_spot(R161, BALL, self.v0_mps, self.swing.u0_mps, self.swing.omega0_radps)
        return self.swing.speed_at(s)


#: The paper's swing: u0 = 17.87 m/s, omega0 = 32 rad/s (about 45 mph at the sweet spot).
PAPER = Scenario(
    key="paper", label="paper's swing", v0_mps=presets.PAPER_PITCH_MPS, swing=presets.PAPER_SWING
)
#: A major-league swing: the bat turning about (near) the knob at 48 rad/s, about 70 mph at the
#: sweet spot, against a 40 m/s (90 mph) pitch.
MLB = Scenario(
    key="mlb",
    label="MLB-like swing about the knob",
    v0_mps=40.0,
    swing=Swing(u0_mps=48.0 * R161.com_from_knob_m, omega0_radps=48.0),
)
SCENARIOS = (PAPER, MLB)


def carried_swing(
    bat: Bat, sc: Scenario, model: SwingModel | str, exponent: float = MEASURED_EXPONENT
) -> Swing:
    """The swing a batter gives ``bat`` if he gives the R161 the scenario's swing."""
    return swing_for(bat, model=model, reference_bat=R161, reference=sc.swing, exponent=exponent)


def same_swing(bat: Bat, sc: Scenario) -> Swing:
    """The scenario's swing with the batter's motion unchanged: the bat turns about the same
    axis at the same rate, so a COM that moved moves at its new distance from the axis (the
    swing-speed models' n = 0 limit), not at the R161's COM speed."""
    return carried_swing(bat, sc, SwingModel.MEASURED, exponent=0.0)


def best_v1(
    bat: Bat, sc: Scenario, swing: Swing | None = None, e: float = E
) -> tuple[float, float]:
    """(s of the bat's best hittable point, v1 there) for this swing (the scenario's by default)."""
    sw = swing or sc.swing
    s = hittable_sweet_spot(bat, BALL, sc.v0_mps, sw.u0_mps, sw.omega0_radps)
    return s, v1_at(bat, s, sc.v0_mps, sw, e)


def v1_at(bat: Bat, s_m: float, v0_mps: float, swing: Swing, e: float = E) -> float:
    """v1 (m/s) off ``bat`` hit at s (m from its COM) by this pitch and swing."""
    return float(
        batted_ball_speed(
            bat, BALL, s_m, v0_mps=v0_mps, u0_mps=swing.u0_mps, omega0_radps=swing.omega0_radps, e=e
        )
    )


# -- 1. the sweet spot ---------------------------------------------------------------------------


@dataclass(frozen=True, kw_only=True)
class HandsRegion:
    """Where the sweet spot moves for swings from the hands (u0 = omega0 d): ``grid_s_m``
    [pitch, omega] over ``pitches_mps`` x ``omegas_radps``; its extent ``s_lo_m``..``s_hi_m``."""

    pitches_mps: tuple[float, ...]
    omegas_radps: np.ndarray
    grid_s_m: np.ndarray
    s_lo_m: float
    s_hi_m: float


def sweet_region_from_hands(
    pitches_mps: tuple[float, ...] = HANDS_PITCHES_MPS,
    omegas_radps: np.ndarray = HANDS_OMEGAS_RADPS,
) -> HandsRegion:
    """The sweet spot over a grid of pitches and bat rates, swung from the hands."""
    d = R161.com_from_knob_m - HANDS_M
    grid = np.array(
        [[sweet_spot(R161, BALL, v, w * d, w) for w in omegas_radps] for v in pitches_mps]
    )
    return HandsRegion(
        pitches_mps=tuple(pitches_mps),
        omegas_radps=np.array(omegas_radps),
        grid_s_m=grid,
        s_lo_m=float(grid.min()),
        s_hi_m=float(grid.max()),
    )


def batting_region_cm() -> tuple[float, float]:
    """(nearest, farthest) sweet spot from the barrel end (cm) over batting swings: pitches
    HANDS_PITCHES_MPS, rates BATTING_OMEGAS_RADPS, the bat turning about BATTING_PIVOTS_M."""
    s = [
        sweet_spot(R161, BALL, v, w * (R161.com_from_knob_m - p), w)
        for p in BATTING_PIVOTS_M
        for v in HANDS_PITCHES_MPS
        for w in BATTING_OMEGAS_RADPS
    ]
    return from_end_cm(R161, max(s)), from_end_cm(R161, min(s))


#: The finer grid of batting swings the share inside Russell's range is quoted on (pivots x
#: pitches x rates); refining it further moves the share by under 1% (tests).
SHARE_GRID = (np.linspace(0.0, HANDS_M, 5), np.linspace(35.0, 47.0, 13), np.linspace(40, 56, 33))
SHARE_GRID_TEXT = "of 5 pivots x 13 pitches x 33 rates"


def russell_share(fine: bool = True, grid=None) -> float:
    """The share of batting swings (evenly over pivot, pitch and rate) whose sweet spot lies in
    Russell's range, on SHARE_GRID (``fine``), the default grid or ``grid``."""
    pivots, pitches, rates = grid or (
        SHARE_GRID if fine else (BATTING_PIVOTS_M, HANDS_PITCHES_MPS, BATTING_OMEGAS_RADPS)
    )
    cm = np.array(
        [
            from_end_cm(R161, sweet_spot(R161, BALL, v, w * (R161.com_from_knob_m - p), w))
            for p in pivots
            for v in pitches
            for w in rates
        ]
    )
    return float(np.mean((cm >= RUSSELL_CM[0]) & (cm <= RUSSELL_CM[1])))


def zone(bat: Bat, sc: Scenario, within: float = SWEET_ZONE_WITHIN) -> tuple[float, float]:
    """The stretch of one swing's bat where v1 is within ``within`` of its best (m from the COM),
    clipped to the hittable cylinder (``analytic.sweet_zone``, closed form)."""
    z = sweet_zone(
        bat,
        BALL,
        v0_mps=sc.v0_mps,
        u0_mps=sc.swing.u0_mps,
        omega0_radps=sc.swing.omega0_radps,
        e=E,
        fraction=1 - within,
    )
    return max(z.s_min_m, bat.s_min_m), min(z.s_max_m, bat.s_max_m)


def from_end_cm(bat: Bat, s_m: float) -> float:
    """Distance of the point s (m from the COM) from the barrel end, in cm."""
    return (bat.s_barrel_end_m - s_m) * 100


def sweet_spot_table() -> pd.DataFrame:
    """Per scenario: the sweet spot, the sweet zone and the COP, from the COM and from the end."""
    rows = []
    cop = center_of_percussion(R161, HANDS_M)
    for sc in SCENARIOS:
        s, v1 = best_v1(R161, sc)
        lo, hi = zone(R161, sc)
        rows.append(
            {
                "swing": sc.label,
                "pitch (m/s)": sc.v0_mps,
                "bat speed at s* (m/s)": sc.bat_speed_mps,
                "s* (mm from COM)": s * 1e3,
                "s* (cm from end)": from_end_cm(R161, s),
                "v1 at s* (m/s)": v1,
                "1% zone (mm from COM)": f"{lo * 1e3:.0f} to {hi * 1e3:.0f}",
                "1% zone (cm from end)": f"{from_end_cm(R161, hi):.1f} to "
                f"{from_end_cm(R161, lo):.1f}",
                "COP, hands 0.1 m (cm from end)": from_end_cm(R161, cop),
            }
        )
    return pd.DataFrame(rows)


# -- 2. corked bats ------------------------------------------------------------------------------


def corked_bats() -> dict[tuple[str, int], tuple[Bat, Bat]]:
    """(fill, depth in inches) -> (exact corked R161, the paper's), 1 in holes in wood of
    HOLE_WOOD_KGM3."""
    out = {}
    for fill, rho in FILLS.items():
        for depth in DEPTHS_IN:
            kw = dict(
                hole_radius_m=0.5 * IN,
                hole_depth_m=depth * IN,
                fill_density_kgm3=rho,
                wood_density_kgm3=HOLE_WOOD_KGM3,
            )
            out[(fill, depth)] = (corked_bat(R161, **kw), corked_bat_paper(R161, **kw))
    return out


CORK_1x10 = corked_bat(R161, wood_density_kgm3=HOLE_WOOD_KGM3)  # a 1 x 10 in cork fill


def cork_properties() -> pd.DataFrame:
    """Per corked bat: its mass, COM and inertia changes, exact against the paper's formula."""
    rows = []
    for (fill, depth), (exact, paper) in corked_bats().items():
        rows.append(
            {
                "fill": fill,
                "depth (in)": depth,
                "dM (g)": (exact.mass_kg - R161.mass_kg) * 1e3,
                "dCOM (mm)": (exact.com_from_knob_m - R161.com_from_knob_m) * 1e3,
                "J_cm exact (kg m^2)": exact.inertia_cm_kgm2,
                "J_cm paper (kg m^2)": paper.inertia_cm_kgm2,
                "paper - exact (%)": (paper.inertia_cm_kgm2 / exact.inertia_cm_kgm2 - 1) * 100,
                "I_knob change (%)": (exact.inertia_knob_kgm2 / R161.inertia_knob_kgm2 - 1) * 100,
            }
        )
    return pd.DataFrame(rows)


def cork_gain(corked: Bat, sc: Scenario, exponent: float, e: float = E) -> float:
    """v1 at the corked bat's best point minus the solid bat's (m/s) when swing speed scales as
    omega0 ~ I_knob^-exponent (the batter's effort carried over from the R161), both at e."""
    sw = carried_swing(corked, sc, SwingModel.MEASURED, exponent)
    return best_v1(corked, sc, sw, e)[1] - best_v1(R161, sc, e=e)[1]


def break_even_exponent(corked: Bat, sc: Scenario, e: float = E) -> float:
    """The exponent n of omega0 ~ I_knob^-n at which corking neither gains nor loses v1 (a
    lighter bat must be swung that much faster to make up for its lost mass)."""
    return float(optimize.brentq(lambda n: cork_gain(corked, sc, n, e), 0.0, 2.0, xtol=1e-10))


def cork_verdicts(corked: Bat = CORK_1x10) -> pd.DataFrame:
    """Per scenario: the break-even exponent and the gain at n = 0.27 (measured), 0.5 (constant
    torque), under the paper's u0 ~ 1/M and under its own log spiral's u0 ~ M^-1/2."""
    rows = []
    for sc in SCENARIOS:
        wood = best_v1(R161, sc)[1]
        spiral = {
            p: best_v1(
                corked,
                sc,
                Swing(
                    u0_mps=sc.swing.u0_mps * (R161.mass_kg / corked.mass_kg) ** p,
                    omega0_radps=sc.swing.omega0_radps,
                ),
            )[1]
            - wood
            for p in (1.0, 0.5)
        }
        rows.append(
            {
                "swing": sc.label,
                "break-even n": break_even_exponent(corked, sc),
                "gain at n = 0.27 (m/s)": cork_gain(corked, sc, MEASURED_EXPONENT),
                "gain at n = 0.5 (m/s)": cork_gain(corked, sc, 0.5),
                "gain, u0 ~ 1/M (paper, m/s)": spiral[1.0],
                "gain, u0 ~ M^-1/2 (its log spiral, m/s)": spiral[0.5],
                "gain, same swing (n = 0, m/s)": best_v1(corked, sc, same_swing(corked, sc))[1]
                - wood,
            }
        )
    return pd.DataFrame(rows)


def cork_speeds(sc: Scenario) -> pd.DataFrame:
    """v1 at each bat's best point under each swing model (m/s), the solid bat first."""
    rows = []
    bats = [("none (wood)", 0, R161)] + [(f, d, b[0]) for (f, d), b in corked_bats().items()]
    for fill, depth, bat in bats:
        row = {
            "fill": fill,
            "depth (in)": depth,
            "same swing (n = 0)": best_v1(bat, sc, same_swing(bat, sc))[1],
        }
        for m in SwingModel:
            row[m.value] = best_v1(bat, sc, carried_swing(bat, sc, m))[1]
        rows.append(row)
    return pd.DataFrame(rows)


def collision_efficiency(bat: Bat, s_m: float, e: float = E) -> float:
    """q = (e - r)/(1 + r), r = m (1/M + s^2/J): the batted-ball speed per unit pitch speed off a
    still, free bat (what a cannon test measures)."""
    return predict(ImpactCase(bat=bat, ball=BALL, s_m=s_m, v0_mps=40.0, e=e)).q


def nathan_q_check() -> dict[str, float]:
    """q of the solid and the 1 x 10 in corked R161, 6 in from each one's barrel end, e = 0.5."""
    return {
        name: collision_efficiency(bat, bat.s_barrel_end_m - NATHAN_Q_FROM_END_M)
        for name, bat in (("solid", R161), ("corked", CORK_1x10))
    }


def paper_cork_inertia_if_subtracted(bat: Bat = CORK_1x10) -> float:
    """Relative error of the paper's J' (%) had it subtracted (M + dM) R^2: only the dropped
    dM r^2/4 of the hole's own cylinder remains."""
    dm = bat.mass_kg - R161.mass_kg
    return -dm * (0.5 * IN) ** 2 / 4 / bat.inertia_cm_kgm2 * 100


# -- engines -------------------------------------------------------------------------------------


def engine_checks(runner: Runner, engines: tuple[str, ...]) -> pd.DataFrame:
    """The model's headline impacts fired in every engine (reference profile): the 1 x 10 in
    cork bat and the aluminium bat at their best points under each swing model, both swings.
    A tidy table (``tables.table``): each row judged against the answer its engine's contact
    converges to (rigid theory, or the engine's own contact law)."""
    jobs, labels = check_jobs(engines)
    table = tables.table(runner.fire(jobs), "reference").drop(columns=["bat"])
    meta = pd.DataFrame(
        [lab for _ in engines for lab in labels], columns=["swing", "bat", "swing model"]
    )
    return pd.concat([meta, table], axis=1)


def check_jobs(engines: tuple[str, ...]) -> tuple[list[Job], list[tuple[str, str, str]]]:
    """``engine_checks``' jobs, engine by engine, and each case's (swing, bat, model)."""
    cases, labels = [], []
    for sc in SCENARIOS:
        for name, bat in (("1x10 in cork", CORK_1x10), ("aluminium", AL)):
            for m in SwingModel:
                sw = carried_swing(bat, sc, m)
                s, _ = best_v1(bat, sc, sw)
                cases.append(
                    ImpactCase(
                        bat=bat,
                        ball=BALL,
                        s_m=s,
                        v0_mps=sc.v0_mps,
                        u0_mps=sw.u0_mps,
                        omega0_radps=sw.omega0_radps,
                        e=E,
                    )
                )
                labels.append((sc.label, name, m.value))
    return [
        Job(engine=n, settings=adapters.settings_for(n), case=c) for n in engines for c in cases
    ], labels


def sweet_spot_jobs(engines: tuple[str, ...]) -> list[Job]:
    """An impact at the analytic sweet spot of each swing, per engine: what
    ``engine_sweet_spots`` searches near."""
    out = []
    for sc in SCENARIOS:
        s_star = sweet_spot(R161, BALL, sc.v0_mps, sc.swing.u0_mps, sc.swing.omega0_radps)
        case = ImpactCase(
            bat=R161,
            ball=BALL,
            s_m=s_star,
            v0_mps=sc.v0_mps,
            u0_mps=sc.swing.u0_mps,
            omega0_radps=sc.swing.omega0_radps,
            e=E,
        )
        out += [Job(engine=n, settings=adapters.settings_for(n), case=case) for n in engines]
    return out


def engine_sweet_spots(engines: tuple[str, ...]) -> pd.DataFrame:
    """The sweet spot located from each engine's data alone (bounded Brent search on v1(s),
    reference profile) for both swings, against the analytic one (mm)."""
    rows = []
    for sc in SCENARIOS:
        s_star = sweet_spot(R161, BALL, sc.v0_mps, sc.swing.u0_mps, sc.swing.omega0_radps)
        firing = firings.Firing(
            bat=R161,
            s_m=(s_star,),
            v0_mps=sc.v0_mps,
            u0_mps=sc.swing.u0_mps,
            omega0_radps=sc.swing.omega0_radps,
            e=E,
        )
        bracket = (max(R161.s_min_m, s_star - 0.05), min(R161.s_max_m, s_star + 0.05))
        row = {"swing": sc.label, "s* analytic (mm from COM)": s_star * 1e3}
        for n in engines:
            got = locate.locate_sweet_spot(n, adapters.settings_for(n), firing, bracket)
            row[f"{n} - analytic (mm)"] = (got - s_star) * 1e3
        rows.append(row)
    return pd.DataFrame(rows)


def v1_gain_curve(corked: Bat, sc: Scenario, exponents: np.ndarray) -> np.ndarray:
    """``cork_gain`` over a range of exponents (m/s), for the chart."""
    return np.array([cork_gain(corked, sc, float(n)) for n in exponents])


# -- 5. the paper's numbers, for the audit -------------------------------------------------------


def audit_numbers() -> dict[str, float]:
    """Every number the audit of the paper quotes (m, m/s, rad, kg m^2, s, %)."""
    sw = PAPER.swing
    light = replace(BALL, mass_kg=0.14)  # the paper's "0.14 kg" ball
    ranges = dict(
        v0_range_mps=(40.2, 46.9), u0_range_mps=(0.0, 17.87), omega0_range_radps=(12.0, 32.0)
    )
    region = sweet_region(R161, BALL, **ranges)
    region_light = sweet_region(R161, light, **ranges)
    oblique = ImpactCase(
        bat=R161,
        ball=BALL,
        s_m=0.1,
        v0_mps=PAPER.v0_mps,
        u0_mps=sw.u0_mps,
        omega0_radps=sw.omega0_radps,
        e=E,
        theta_rad=math.radians(20),
    )
    out = predict(oblique)
    al = carried_swing(AL, PAPER, SwingModel.CONSTANT_FORCE)
    al_s, al_v1 = best_v1(AL, PAPER, al)
    wood_v1 = best_v1(R161, PAPER)[1]
    s_light = hittable_sweet_spot(R161, light, PAPER.v0_mps, sw.u0_mps, sw.omega0_radps)
    wood_v1_light = float(
        batted_ball_speed(
            R161,
            light,
            s_light,
            v0_mps=PAPER.v0_mps,
            u0_mps=sw.u0_mps,
            omega0_radps=sw.omega0_radps,
            e=E,
        )
    )
    e_needed = optimize.brentq(lambda e: v1_at(AL, al_s, PAPER.v0_mps, al, e) - 42.59, 0.0, 1.0)

    def al_short(inertia: float) -> float:
        bat = replace(AL, inertia_cm_kgm2=inertia)
        return best_v1(bat, PAPER, al)[1] - 42.59

    exact, paper = corked_bats()[("cork", 10)]
    return {
        "cop_m": center_of_percussion(R161, HANDS_M),
        "region_max_m": region.s_max_m,
        "region_min_m": region.s_min_m,
        "region_light_max_m": region_light.s_max_m,
        "oblique_theta1_rad": out.theta1_rad,
        "oblique_speed_mps": out.ball_speed_mps,
        "oblique_paper_v1_mps": predict_oblique_paper(oblique).v1_mps,
        "cork_J_paper": paper.inertia_cm_kgm2,
        "cork_J_exact": exact.inertia_cm_kgm2,
        "cork_J_if_subtracted_pct": paper_cork_inertia_if_subtracted(exact),
        "pivot_from_knob_m": R161.com_from_knob_m - sw.u0_mps / sw.omega0_radps,
        "hands_u0_mps": sw.omega0_radps * (R161.com_from_knob_m - HANDS_M),
        "al_u0_mps": al.u0_mps,
        "al_v1_mps": al_v1,
        "wood_v1_mps": wood_v1,
        "wood_v1_light_ball_mps": wood_v1_light,
        "e_needed": e_needed,
        "J_ratio_needed": optimize.brentq(al_short, AL.inertia_cm_kgm2, 50 * AL.inertia_cm_kgm2)
        / AL.inertia_cm_kgm2,
        "t_al_s": PLATE_TO_RUBBER_M / al_v1,
        "t_wood_s": PLATE_TO_RUBBER_M / wood_v1,
    }
