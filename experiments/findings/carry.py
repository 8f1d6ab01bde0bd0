"""How far the batted ball goes (carry, m): the findings' answers turned from ball speed into
distance, for ``results/findings.md``.

Numbers only (no prose, no plotting), like ``answers`` and ``metal``. One impact is Routh's
frictional impulse in 3-D (``analytic.predict_friction``: the bat swung level, the ball's centre
``undercut`` above the bat's axis, the pitch spinning) and its ball is flown through air
(``analytic.flight``: Nathan's drag and lift, from 0.9 m up). Impact frame: x along the bat,
y toward the outfield, z up; spin +x is backspin for the batted ball, so a fastball's own
backspin arrives as -x and a curveball's topspin as +x. Units: m, m/s, rad/s, s, unless a
column name says otherwise (cm, deg, rpm, ft).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from functools import cache

import numpy as np
import pandas as pd
from scipy import optimize

from analytic import Bat, ImpactCase, Swing, SwingModel, hittable_sweet_spot, predict_friction
from analytic.flight import (
    DRAG_SPREAD,
    FT_M,
    LIFT_SPREAD,
    NATHAN_2008,
    RELEASE_TO_PLATE_M,
    RPM_RADPS,
    Launch,
    batted_ball_launch,
    carry_range_m,
    fly,
    time_to_travel,
)

from . import metal as M
from .answers import (
    AL,
    BALL,
    PITCHER_AFTER_FOLLOW_THROUGH_M,
    R161,
    REACTION_S,
    CORK_1x10,
    E,
    Scenario,
    carried_swing,
    from_end_cm,
)

#: Ball-bat Coulomb friction. ASSUMED 0.5: Cross & Nathan (Am. J. Phys. 74, 896 (2006)) found
#: the ball-bat sliding friction above 0.5 in their low-speed (~4 m/s) scattering experiment (as
#: a public design note citing them summarises it; the paper's own table was not read here).
#: It hardly matters: Sawicki, Hubbard & Stronge (Am. J. Phys. 71, 1152 (2003), abstract):
#: "Post-impact conditions are found to be independent of the ball-bat coefficient of
#: friction"; ``mu_scan`` shows the same here once the slip stops within the impact.
MU_BALL_BAT = 0.5
#: The coefficients ``mu_scan`` tries: from a ball that slides throughout to one that grips.
MU_SCAN = (0.05, 0.1, 0.2, 0.5, 1.0, 3.0)
#: A four-seam fastball's backspin (rpm): the 2016 MLB average, 2,264 rpm over 255,000 pitches
#: (M. Petriello, "Why spin rate matters for fastballs", MLB.com, 3 Jan 2017; Statcast).
FASTBALL_SPIN_RPM = 2264.0
#: A curveball's topspin (rpm): the 2024 Statcast mean release spin of 47,579 curveballs,
#: 2,569 rpm at 79.4 mph (statcast_2024_grouped.csv of TJStats' "pitch_plot_select" space on
#: huggingface.co, a grouping of Baseball Savant's pitch data). Taken as pure topspin (a real
#: curveball's axis tilts) and at the scenario's pitch speed, so that only the spin differs.
CURVEBALL_SPIN_RPM = 2569.0
FASTBALL = (-FASTBALL_SPIN_RPM * RPM_RADPS, 0.0, 0.0)
CURVEBALL = (CURVEBALL_SPIN_RPM * RPM_RADPS, 0.0, 0.0)
#: Sawicki et al.'s optima as Hubbard gave them to Popular Mechanics (D. Coburn, "Baseball
#: Physics: Anatomy of a Home Run", 18 Dec 2009, p. 2): a 94 mph fastball flies 442 ft, a 78 mph
#: curveball 455 ft, the fastball leaving the bat 3 mph faster. Their optimal undercuts and bat
#: angles could not be read from an accessible copy of the paper.
SAWICKI_FASTBALL_FT, SAWICKI_CURVEBALL_FT = 442.0, 455.0
SAWICKI_FASTBALL_MPH, SAWICKI_CURVEBALL_MPH = 94.0, 78.0
SAWICKI_EXIT_GAP_MPH = 3.0
#: Kensrud, Nathan & Smith, Am. J. Phys. 85, 503 (2017), abstract: a ball gripping the bat leaves
#: with "a spin that was up to 40% greater than would be obtained by rolling contact of rigid
#: bodies".
KENSRUD_EXTRA_SPIN = 0.40
#: The carry grid: impact points from the COM to the barrel's end x undercuts of 0-4 cm.
GRID_S_POINTS = 15
GRID_UNDERCUTS_M = tuple(round(float(d), 12) for d in np.linspace(0.0, 0.04, 17))
ROW_UNDERCUTS_M = (0.0, 0.01, 0.02, 0.03, 0.04)  # where the longest carry's s is located
START_UNDERCUT_M = 0.02  # where the search for the best point starts (the grid's best is near)
#: Search tolerances: 0.1 mm in s and undercut, 1 mm in carry (the carry is flat at its best),
#: from a first simplex 1 cm along s and 4 mm along the undercut.
XATOL_M, FATOL_M, STEPS_M = 1e-4, 1e-3, (0.01, 0.004)
#: For the other bats, started from the R161's best undercut: 0.5 mm, from 4 mm and 1 mm steps
#: (half the evaluations; tried on the aluminium bat, e = 0.55, measured swing, its best carry
#: came within 0.3 mm of the finer search's).
BAT_XATOL_M, BAT_STEPS_M = 5e-4, (0.004, 0.001)
#: Relative tolerances of the frictional impulse's and the flight's integrations: a carry to
#: about 1e-7 of itself (10 um), a hundred times finer than FATOL_M, at a third of the cost of
#: the impulse's default (rounding) and the flight's.
IMPULSE_RTOL, FLIGHT_RTOL = 1e-9, 1e-8


@dataclass(frozen=True, kw_only=True)
class Hit:
    """How a ball is hit, except where: the bat and its swing, the pitch (speed ``v0_mps``, spin
    ``spin_radps`` in the impact frame), the COR ``e`` and the friction ``mu``."""

    bat: Bat
    swing: Swing
    v0_mps: float
    e: float = E
    mu: float = MU_BALL_BAT
    spin_radps: tuple[float, float, float] = FASTBALL

    def case(self, s_m: float, undercut_m: float) -> ImpactCase:
        """The impact at s (m from the COM) with the ball's centre ``undercut_m`` above the axis."""
        return ImpactCase(
            bat=self.bat,
            ball=BALL,
            s_m=s_m,
            v0_mps=self.v0_mps,
            u0_mps=self.swing.u0_mps,
            omega0_radps=self.swing.omega0_radps,
            e=self.e,
            mu=self.mu,
            undercut_m=undercut_m,
            spin_radps=self.spin_radps,
        )

    @property
    def speed_sweet_spot_m(self) -> float:
        """s of the largest batted-ball speed (m from the COM; frictionless, level)."""
        return hittable_sweet_spot(
            self.bat, BALL, self.v0_mps, self.swing.u0_mps, self.swing.omega0_radps
        )


def hit_of(sc: Scenario, bat: Bat = R161, swing: Swing | None = None, **kw) -> Hit:
    """The scenario's pitch and swing (or ``swing``) on ``bat``; ``kw`` overrides Hit's rest."""
    return Hit(bat=bat, swing=swing or sc.swing, v0_mps=sc.v0_mps, **kw)


@cache
def launch_of(hit: Hit, s_m: float, undercut_m: float) -> Launch:
    """The batted ball's launch: Routh's frictional impulse, then the ball's speed, angle, spin."""
    out = predict_friction(hit.case(s_m, undercut_m), rtol=IMPULSE_RTOL)
    return batted_ball_launch(out.ball_velocity_mps, out.ball_spin_radps)


@cache
def carry_m(hit: Hit, s_m: float, undercut_m: float) -> float:
    """How far the ball carries (m, to the ground) hit at (s, undercut)."""
    return fly(launch_of(hit, s_m, undercut_m), samples=2, rtol=FLIGHT_RTOL).carry_m


@dataclass(frozen=True, kw_only=True)
class Grid:
    """Carry (m) over ``s_m`` (m from the COM) x ``undercut_m``: ``carry_m[undercut, s]``."""

    s_m: np.ndarray
    undercut_m: np.ndarray
    carry_m: np.ndarray

    def best(self) -> tuple[float, float, float]:
        """(s, undercut, carry) of the longest carry on the grid."""
        i, j = np.unravel_index(int(np.argmax(self.carry_m)), self.carry_m.shape)
        return float(self.s_m[j]), float(self.undercut_m[i]), float(self.carry_m[i, j])


@cache
def carry_grid(hit: Hit) -> Grid:
    """Carry over GRID_S_POINTS impact points from the COM to the barrel's end x
    GRID_UNDERCUTS_M."""
    s = np.linspace(0.0, hit.bat.s_max_m, GRID_S_POINTS)
    d = np.array(GRID_UNDERCUTS_M)
    return Grid(
        s_m=s,
        undercut_m=d,
        carry_m=np.array([[carry_m(hit, float(x), float(u)) for x in s] for u in d]),
    )


@dataclass(frozen=True, kw_only=True)
class Best:
    """The longest carry and where: s (m from the COM), undercut (m), carry (m), the launch."""

    s_m: float
    undercut_m: float
    carry_m: float
    launch: Launch


def _best(hit: Hit, s_m: float, undercut_m: float) -> Best:
    return Best(
        s_m=s_m,
        undercut_m=undercut_m,
        carry_m=carry_m(hit, s_m, undercut_m),
        launch=launch_of(hit, s_m, undercut_m),
    )


@cache
def best_point(
    hit: Hit,
    undercut_m: float = START_UNDERCUT_M,
    xatol_m: float = XATOL_M,
    steps_m: tuple[float, float] = STEPS_M,
) -> Best:
    """The (s, undercut) of the longest carry: Nelder-Mead from the speed sweet spot at
    ``undercut_m`` (the carry is smooth and single-peaked there: ``carry_grid``), to ``xatol_m``
    and FATOL_M from a first simplex ``steps_m`` (s, undercut) wide."""
    bat = hit.bat
    x0 = np.array([hit.speed_sweet_spot_m, undercut_m])
    res = optimize.minimize(
        lambda x: -carry_m(hit, float(x[0]), float(x[1])),
        x0,
        method="Nelder-Mead",
        bounds=[(bat.s_min_m, bat.s_max_m), (0.0, 0.9 * (bat.radius_m + BALL.radius_m))],
        options={
            "xatol": xatol_m,
            "fatol": FATOL_M,
            "initial_simplex": [x0, x0 + [steps_m[0], 0.0], x0 + [0.0, steps_m[1]]],
        },
    )
    return _best(hit, float(res.x[0]), float(res.x[1]))


def best_s_at(hit: Hit, undercut_m: float) -> Best:
    """The impact point of the longest carry at one undercut: Brent's bounded search between the
    grid's neighbours of its best point on that row (every grid row is single-peaked)."""
    s = np.linspace(0.0, hit.bat.s_max_m, GRID_S_POINTS)
    row = [carry_m(hit, float(x), undercut_m) for x in s]
    j = int(np.argmax(row))
    lo, hi = float(s[max(j - 1, 0)]), float(s[min(j + 1, len(s) - 1)])
    res = optimize.minimize_scalar(
        lambda x: -carry_m(hit, float(x), undercut_m),
        bounds=(lo, hi),
        method="bounded",
        options={"xatol": XATOL_M / 10},
    )
    return _best(hit, float(res.x), undercut_m)


@dataclass(frozen=True, kw_only=True)
class SweetSpots:
    """One swing's speed sweet spot (m from the COM) beside its distance sweet spot (``best``),
    the carry hit at the speed sweet spot with the best undercut (m), and the longest carry's
    point at each of ROW_UNDERCUTS_M (``rows``)."""

    speed_s_m: float
    best: Best
    at_speed_spot_m: float
    rows: tuple[Best, ...]


@cache
def sweet_spots(sc: Scenario) -> SweetSpots:
    """Where the R161 hits the scenario's fastball farthest, beside where it hits it fastest."""
    hit = hit_of(sc)
    best = best_point(hit)
    return SweetSpots(
        speed_s_m=hit.speed_sweet_spot_m,
        best=best,
        at_speed_spot_m=carry_m(hit, hit.speed_sweet_spot_m, best.undercut_m),
        rows=tuple(best_s_at(hit, d) for d in ROW_UNDERCUTS_M),
    )


#: The widest legal barrel, 2.61 in across (MLB Official Baseball Rules 3.02(a)), as a capsule
#: radius (m): the contact radius against the model's 30 mm.
WIDEST_BARREL_RADIUS_M = 0.5 * 2.61 * 0.0254


def wide_barrel_best(sc: Scenario) -> Best:
    """The longest carry's point on an R161 with the widest legal barrel: with an undercut the
    contact normal tilts by asin(D / (r_ball + r_bat)), so the best undercut grows with r_bat."""
    return best_point(hit_of(sc, bat=replace(R161, radius_m=WIDEST_BARREL_RADIUS_M)))


def best_carry_range_m(sc: Scenario) -> tuple[float, float]:
    """The longest carry's (least, most) over the drag and lift corners (m)."""
    return carry_range_m(sweet_spots(sc).best.launch)


def mu_scan(sc: Scenario, mus: tuple[float, ...] = MU_SCAN) -> pd.DataFrame:
    """Carry at the distance sweet spot as the friction varies (m), and whether the slip stops
    within the impact (then only its short sliding start depends on mu)."""
    best = sweet_spots(sc).best
    rows = []
    for mu in mus:
        hit = hit_of(sc, mu=mu)
        out = predict_friction(hit.case(best.s_m, best.undercut_m))
        rows.append(
            {
                "mu": mu,
                "carry (m)": carry_m(hit, best.s_m, best.undercut_m),
                "slip stops": any(kind == "stick" for kind, _ in out.phases),
            }
        )
    return pd.DataFrame(rows)


@dataclass(frozen=True, kw_only=True)
class PitchOptimum:
    """The fastball's and the curveball's best points on one swing, and the backspin (rpm) each
    leaves with when both are hit at the fastball's best point."""

    fastball: Best
    curveball: Best
    fastball_spin_rpm: float
    curveball_spin_at_fastballs_rpm: float


@cache
def pitch_optima(sc: Scenario) -> PitchOptimum:
    """Hubbard's question on a level swing: a fastball (backspin) or a curveball (topspin)."""
    fast, curve = hit_of(sc), hit_of(sc, spin_radps=CURVEBALL)
    fb = best_point(fast)
    same = launch_of(curve, fb.s_m, fb.undercut_m)
    return PitchOptimum(
        fastball=fb,
        curveball=best_point(curve),
        fastball_spin_rpm=fb.launch.backspin_radps / RPM_RADPS,
        curveball_spin_at_fastballs_rpm=same.backspin_radps / RPM_RADPS,
    )


# -- corked and metal bats, in metres --------------------------------------------------------


def corner_carries(launch: Launch) -> np.ndarray:
    """Carry (m) at the four corners C_D (1 +- DRAG_SPREAD) x C_L (1 +- LIFT_SPREAD)."""
    return np.array(
        [
            fly(
                launch,
                aero=NATHAN_2008.scaled(drag=1 + i * DRAG_SPREAD, lift=1 + j * LIFT_SPREAD),
                samples=2,
            ).carry_m
            for i in (-1, 1)
            for j in (-1, 1)
        ]
    )


def bat_hits(sc: Scenario) -> list[tuple[str, str, Hit]]:
    """(bat, swing model, hit): the solid R161, the 1 x 10 in cork R161 under each swing model,
    the paper's aluminium bat under each swing model at each of its e (``metal.METAL_ES``), and
    the metal bat of the R161's length at drop -3 (e = 0.5) under each swing model."""
    out = [(M.WOOD, "same swing", hit_of(sc))]
    for model in SwingModel:
        out.append(
            (
                "R161, 1 x 10 in cork",
                model.value,
                hit_of(sc, CORK_1x10, carried_swing(CORK_1x10, sc, model)),
            )
        )
    for model in SwingModel:
        sw = carried_swing(AL, sc, model)
        out += [(M.ALUMINIUM, model.value, hit_of(sc, AL, sw, e=e)) for e in M.METAL_ES]
    for model in SwingModel:
        out.append(
            (
                M.EQUAL_LENGTH,
                model.value,
                hit_of(sc, M.EQUAL_BAT, carried_swing(M.EQUAL_BAT, sc, model)),
            )
        )
    return out


@cache
def bat_table(sc: Scenario) -> pd.DataFrame:
    """Per bat, swing model and e: its best point, the ball's launch, its carry with the range
    over the drag/lift spread (``flight.carry_range_m``), and the change from the solid R161's
    carry, as computed (m, ft) and its least and most over the spread's four corners (m)."""
    rows, wood, solid = [], None, sweet_spots(sc).best
    for bat, model, hit in bat_hits(sc):
        b = (
            solid
            if hit == hit_of(sc)
            else best_point(hit, solid.undercut_m, BAT_XATOL_M, BAT_STEPS_M)
        )
        corners = corner_carries(b.launch)
        wood = wood or (b.carry_m, corners)
        lo, hi = carry_range_m(b.launch)
        diff = corners - wood[1]
        rows.append(
            {
                "bat": bat,
                "swing model": model,
                "e": hit.e,
                "s (cm from end)": from_end_cm(hit.bat, b.s_m),
                "undercut (cm)": b.undercut_m * 100,
                "v1 (m/s)": b.launch.speed_mps,
                "launch (deg)": math.degrees(b.launch.launch_rad),
                "backspin (rpm)": b.launch.backspin_radps / RPM_RADPS,
                "carry (m)": b.carry_m,
                "carry range (m)": f"{lo:.1f}-{hi:.1f}",
                "change (m)": b.carry_m - wood[0],
                "change (ft)": feet(b.carry_m - wood[0]),
                "change over spread (m)": f"{diff.min():+.2f} to {diff.max():+.2f}",
            }
        )
    return pd.DataFrame(rows)


# -- reaction time, with drag ----------------------------------------------------------------


def release_speed_for(arrival_mps: float) -> float:
    """The release speed (m/s) of a fastball (FASTBALL_SPIN_RPM) that reaches the plate
    (RELEASE_TO_PLATE_M) at ``arrival_mps``."""
    w = FASTBALL_SPIN_RPM * RPM_RADPS
    return float(
        optimize.brentq(
            lambda v: time_to_travel(v, backspin_radps=w).arrival_speed_mps - arrival_mps,
            arrival_mps,
            1.5 * arrival_mps,
            xtol=1e-9,
        )
    )


@cache
def pitch_time(sc: Scenario) -> dict[str, float]:
    """The scenario's pitch (arriving at v0) from release to the plate: its release speed (m/s)
    and its time without and with drag (s)."""
    v = release_speed_for(sc.v0_mps)
    return {
        "release_mps": v,
        "t_no_drag_s": RELEASE_TO_PLATE_M / sc.v0_mps,
        "t_drag_s": time_to_travel(v, backspin_radps=FASTBALL_SPIN_RPM * RPM_RADPS).time_s,
    }


@cache
def reaction_times(sc: Scenario) -> pd.DataFrame:
    """Every batted ball of ``metal.metal_table`` (wood; aluminium at each e; each swing model)
    to the pitcher PITCHER_AFTER_FOLLOW_THROUGH_M away: distance / v1 (no drag)
    and with drag (``flight.time_to_travel``, no spin: the least drag, so the shortest time)."""
    table, rows = M.metal_table(sc), []
    for _, r in table.iterrows():
        for col in (c for c in table.columns if c.startswith("v1, e=")):
            if math.isnan(r[col]):
                continue
            v1 = float(r[col])
            t_drag, t_vacuum = M.time_to_pitcher_s(v1), PITCHER_AFTER_FOLLOW_THROUGH_M / v1
            rows.append(
                {
                    "swing model": r["swing model"],
                    "bat": r.bat,
                    "e": float(col.split("=")[1].split(" ")[0]),
                    "v1 (m/s)": v1,
                    "t, no drag (s)": t_vacuum,
                    "t, drag (s)": t_drag,
                    "below, no drag": t_vacuum < REACTION_S,
                    "below, drag": t_drag < REACTION_S,
                }
            )
    return pd.DataFrame(rows)


def feet(metres: float) -> float:
    """Metres in feet."""
    return metres / FT_M


def reaction_summary(sc: Scenario) -> dict[str, float]:
    """From ``reaction_times``: how many aluminium balls beat REACTION_S without and with drag,
    out of how many, and the wood ball's times (s)."""
    t = reaction_times(sc)
    al, wood = t[t.bat == M.ALUMINIUM], t[t.bat == M.WOOD].iloc[0]
    return {
        "al_below_no_drag": int(al["below, no drag"].sum()),
        "al_below_drag": int((al["below, no drag"] & al["below, drag"]).sum()),
        "al_cases": len(al),
        "wood_t_no_drag_s": float(wood["t, no drag (s)"]),
        "wood_t_drag_s": float(wood["t, drag (s)"]),
        "drag_adds_max_s": float((t["t, drag (s)"] - t["t, no drag (s)"]).max()),
    }
