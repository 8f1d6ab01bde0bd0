"""Section 3b of findings.md: the answers in metres (how far the ball goes), and its chart.

``carry_section`` returns its markdown, its chart (file name -> figure) and the numbers it quotes;
the numbers come from ``experiments.findings.carry``.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import pandas as pd

from analytic.ball import COR_LAW
from analytic.flight import (
    DRAG_SPREAD,
    FT_M,
    LIFT_SPREAD,
    RELEASE_TO_PLATE_M,
    RPM_RADPS,
    carry_range_m,
)

from . import carry as C
from . import metal as M
from . import ranges as R
from .answers import (
    MLB,
    PAPER,
    PITCHER_AFTER_FOLLOW_THROUGH_M,
    R161,
    REACTION_S,
    SCENARIOS,
    E,
    Scenario,
    from_end_cm,
)
from .report import Section, md_table, pyplot

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

CHART = "findings_carry.png"
CHART_UNDERCUTS_M = (0.01, 0.02, 0.03)  # the chart's curves (rows of the carry grid)
BAT_COLUMNS = [
    "bat",
    "swing model",
    "e",
    "undercut (cm)",
    "v1 (m/s)",
    "launch (deg)",
    "backspin (rpm)",
    "carry (m)",
    "carry range (m)",
    "change (m)",
    "change (ft)",
    "change over spread (m)",
]


def carry_section() -> Section:
    """Section 3b: the distance sweet spot, fastball or curveball, corking and metal bats in
    metres, and the reaction-time argument with drag."""
    text = "\n".join(
        [
            _intro_text(),
            _sweet_text(),
            _pitch_text(),
            _bats_text(),
            _reaction_text(),
            f"![carry along the barrel]({CHART})\n",
        ]
    )
    stats = {
        sc.key: {"best": C.sweet_spots(sc).best, "speed_s_m": C.sweet_spots(sc).speed_s_m}
        for sc in SCENARIOS
    }
    return text, {CHART: _carry_figure()}, stats


def ft(metres: float) -> str:
    """A length in metres as feet, rounded to the foot."""
    return f"{C.feet(metres):.0f} ft"


def rpm(radps: float) -> int:
    """A spin in rad/s as whole rpm."""
    return round(radps / RPM_RADPS)


def mu_spread(sc: Scenario) -> dict[str, float]:
    """Over ``carry.mu_scan``: the least and most mu at which the slip stops within the impact,
    the carry's spread (m) over them, and what a ball sliding throughout (the smallest mu) loses
    against mu = MU_BALL_BAT (m)."""
    scan = C.mu_scan(sc)
    grip = scan[scan["slip stops"]]
    at_mu = float(scan.loc[scan.mu == C.MU_BALL_BAT, "carry (m)"].iloc[0])
    slide = float(scan.mu.iloc[0])
    return {
        "mu_lo": float(grip.mu.min()),
        "mu_hi": float(grip.mu.max()),
        "spread_m": float(grip["carry (m)"].max() - grip["carry (m)"].min()),
        "mu_slide": slide,
        "slide_loss_m": at_mu - float(scan["carry (m)"].iloc[0]),
        "slide_best_change_m": C.best_point(C.hit_of(sc, mu=slide)).carry_m - at_mu,
    }


def _intro_text() -> str:
    """What is flown, from what impact, with which constants."""
    return f"""## 3b. How far does the ball go?

Every answer above is a batted-ball speed; a reader asks how far. Here each ball is hit by the
R161 swung level (the swing plane horizontal), the ball's centre an **undercut** D above the
bat's axis at contact, and flown: Routh's frictional impact in 3-D (`analytic.predict_friction`,
e = {E}, ball-bat friction mu = {C.MU_BALL_BAT}, an assumption that hardly matters: see below)
on a pitch arriving with a four-seam fastball's **backspin of {C.FASTBALL_SPIN_RPM:.0f} rpm**
(the 2016 MLB average [statcast]), then Nathan's drag and lift from 0.9 m up (`analytic.flight`
[nathancalc], still air at 1.194 kg/m^3). Carry is the distance to the landing point. A
headline carry is quoted over the joint range of the inputs it depends on (the referee
section's table: e, the share of the pitch's spin the impact hands on, the batted spin over
rigid rolling's, C_D +-{DRAG_SPREAD:.0%} [adair], C_L +-{LIFT_SPREAD:.0%}), its best point
re-optimised at every point of that range (`ranges.carry_spread`); the tables' "carry range"
columns are over drag and lift alone (`flight.carry_range_m`), to compare rows.
"""


def _sweet_rows() -> pd.DataFrame:
    """Per swing: the speed sweet spot beside the distance sweet spot and its ball."""
    rows = []
    for sc in SCENARIOS:
        ss, b = C.sweet_spots(sc), C.sweet_spots(sc).best
        lo, hi = carry_range_m(b.launch)
        rows.append(
            {
                "swing": sc.label,
                "speed sweet spot (cm from end)": from_end_cm(R161, ss.speed_s_m),
                "distance sweet spot (cm from end)": from_end_cm(R161, b.s_m),
                "best undercut (cm)": b.undercut_m * 100,
                "v1 (m/s)": b.launch.speed_mps,
                "launch (deg)": math.degrees(b.launch.launch_rad),
                "backspin (rpm)": rpm(b.launch.backspin_radps),
                "carry (m)": b.carry_m,
                "carry (ft)": round(C.feet(b.carry_m)),
                "carry range (m)": f"{lo:.1f}-{hi:.1f}",
                "carry at the speed sweet spot (m)": ss.at_speed_spot_m,
            }
        )
    return pd.DataFrame(rows)


def _undercut_rows(sc: Scenario) -> pd.DataFrame:
    """One swing's longest carry at each undercut of ``carry.ROW_UNDERCUTS_M``."""
    return pd.DataFrame(
        [
            {
                "undercut (cm)": b.undercut_m * 100,
                "best point (cm from end)": from_end_cm(R161, b.s_m),
                "launch (deg)": math.degrees(b.launch.launch_rad),
                "backspin (rpm)": rpm(b.launch.backspin_radps),
                "carry (m)": b.carry_m,
            }
            for b in C.sweet_spots(sc).rows
        ]
    )


def _sweet_text() -> str:
    """The distance sweet spot against the speed sweet spot, and what the undercut does."""
    p, m = C.sweet_spots(PAPER), C.sweet_spots(MLB)
    shift = [abs(ss.best.s_m - ss.speed_s_m) * 1e3 for ss in (p, m)]
    lost = [(ss.best.carry_m - ss.at_speed_spot_m) * 100 for ss in (p, m)]
    rows = {sc.key: [b.s_m for b in C.sweet_spots(sc).rows] for sc in SCENARIOS}
    span = [(max(r) - min(r)) * 100 for r in rows.values()]
    level = p.rows[0]
    mp, mm = mu_spread(PAPER), mu_spread(MLB)
    sp = {sc.key: R.carry_spread(sc) for sc in SCENARIOS}
    at_law = {sc.key: central_law_carry(sc) for sc in SCENARIOS}
    wides = [C.wide_barrel_best(sc) for sc in (PAPER, MLB)]
    wide = [100 * w.undercut_m for w in wides]
    carry = [(w.carry_m, b.best.carry_m) for w, b in zip(wides, (p, m), strict=True)]
    return f"""**The distance sweet spot is the speed sweet spot.** The longest carry comes from
the same point of the barrel as the fastest ball, to within {shift[0]:.1f} mm (paper's swing) and
{shift[1]:.1f} mm (MLB-like): hitting the speed sweet spot with the best undercut loses
{lost[0]:.1f} cm and {lost[1]:.1f} cm of carry. What decides the distance is the undercut. The
best ball flies **{sp["paper"].text()} m** off the paper's swing and **{sp["mlb"].text()} m** off
the MLB-like one, over e, the spin handed on and its boost, drag and lift, moved most by the
{sp["mlb"].driver} (e at its ends alone: {_ends(sp["paper"], "e")} m and {_ends(sp["mlb"], "e")}
m). At e = {E} (the central value, the rigid model's); at the central COR law's e at the
closing speed ({at_law["paper"][0]:.3f} and {at_law["mlb"][0]:.3f}, section 4) the best balls
fly {at_law["paper"][1]:.1f} m and {at_law["mlb"][1]:.1f} m. The table's figures are the
central model's:

{md_table(_sweet_rows(), "{:.4g}")}

The longest carry at each undercut (its best point moves by at most {span[0]:.1f} cm, paper's
swing, and {span[1]:.1f} cm, MLB-like): hit square (D = 0) a fastball leaves at
{math.degrees(level.launch.launch_rad):.1f} deg with
{-level.launch.backspin_radps / RPM_RADPS:.0f} rpm of topspin, its own backspin turned over by
friction, and is a {level.carry_m:.0f} m grounder.

paper's swing:

{md_table(_undercut_rows(PAPER), "{:.4g}")}

MLB-like swing:

{md_table(_undercut_rows(MLB), "{:.4g}")}

The best undercut depends on the bat's radius: with an undercut D the contact normal tilts by
asin(D / (r_ball + r_bat)). On the widest legal barrel, 2.61 in [rules], instead of the
model's 30 mm the best undercut is {wide[0]:.2f} cm instead of {p.best.undercut_m * 100:.2f}
(paper's swing) and {wide[1]:.2f} instead of {m.best.undercut_m * 100:.2f} cm (MLB-like), the
carry the same to {max(abs(w - c) for w, c in carry):.2f} m.

Friction: from mu = {mp["mu_lo"]:g} to {mp["mu_hi"]:g} the best carry changes by
{mp["spread_m"] * 1e3:.1f} mm (paper's swing) and {mm["spread_m"] * 1e3:.1f} mm (MLB-like), for
the slip stops within the impact and the ball leaves rolling on the bat, as Sawicki et al. found
("post-impact conditions ... independent of the ball-bat coefficient of friction"
[sawicki2003]). A ball that slides throughout (mu = {mp["mu_slide"]:g}) is another ball: hit
at mu = {C.MU_BALL_BAT}'s best point it loses {mp["slide_loss_m"]:.2f} m and
{mm["slide_loss_m"]:.2f} m, but with its own best point and undercut re-optimised its carry
changes by {mp["slide_best_change_m"]:+.2f} m and {mm["slide_best_change_m"]:+.2f} m (paper's,
MLB-like swing).
"""


def _ends(sp, key: str) -> str:
    """A spread's value at one input's two ends, the others central (m)."""
    lo, hi = next((lo, hi) for k, lo, hi in sp.ends if k == key)
    return f"{lo:.1f}-{hi:.1f}"


def central_law_carry(sc: Scenario) -> tuple[float, float]:
    """(e, the longest carry in m) at the central COR law's e at the closing speed of the
    R161's speed sweet spot."""
    e = COR_LAW.cor(sc.v0_mps + sc.bat_speed_mps)
    return e, C.best_point(C.hit_of(sc, e=e)).carry_m


def _pitch_rows() -> pd.DataFrame:
    """Per swing and pitch: the best point and its ball."""
    rows = []
    for sc in SCENARIOS:
        po = C.pitch_optima(sc)
        for name, b in (("fastball", po.fastball), ("curveball", po.curveball)):
            rows.append(
                {
                    "swing": sc.label,
                    "pitch": name,
                    "best undercut (cm)": b.undercut_m * 100,
                    "best point (cm from end)": from_end_cm(R161, b.s_m),
                    "v1 (m/s)": b.launch.speed_mps,
                    "launch (deg)": math.degrees(b.launch.launch_rad),
                    "backspin (rpm)": rpm(b.launch.backspin_radps),
                    "carry (m)": b.carry_m,
                    "carry (ft)": round(C.feet(b.carry_m)),
                }
            )
    return pd.DataFrame(rows)


def _pitch_text() -> str:
    """Hubbard's curveball argument on a level swing, beside Sawicki et al.'s result."""
    p, m = C.pitch_optima(PAPER), C.pitch_optima(MLB)
    gain = [po.curveball.carry_m - po.fastball.carry_m for po in (p, m)]
    cu = {sc.key: R.curve_spread(sc) for sc in SCENARIOS}
    theirs = (C.SAWICKI_CURVEBALL_FT - C.SAWICKI_FASTBALL_FT) * FT_M
    return f"""**Fastball or curveball.** A curveball arrives with topspin
({C.CURVEBALL_SPIN_RPM:.0f} rpm, the 2024 Statcast mean [statcast]; here at the same pitch speed
as the fastball, so that only the spin differs), which is already turning the way a batted
ball's backspin does. Hit at the fastball's best point, it leaves with
**{p.curveball_spin_at_fastballs_rpm:.0f} rpm of backspin against the fastball's
{p.fastball_spin_rpm:.0f} rpm** (paper's swing; {m.curveball_spin_at_fastballs_rpm:.0f} against
{m.fastball_spin_rpm:.0f} rpm MLB-like): Hubbard's argument.
That ball climbs too steeply, so the curveball's best undercut is smaller,
**{p.curveball.undercut_m * 100:.2f} cm against {p.fastball.undercut_m * 100:.2f} cm**
(MLB-like: {m.curveball.undercut_m * 100:.2f} against {m.fastball.undercut_m * 100:.2f} cm), and
in this model it carries {gain[0]:+.1f} m ({C.feet(gain[0]):+.0f} ft) and {gain[1]:+.1f} m
({C.feet(gain[1]):+.0f} ft) farther (the table). That rests on rigid rolling, which hands the
incoming topspin on in full; it is neither bound. Measured outgoing spin is nearly independent
of the incoming spin [nathan2012] [crossnathan2006]: then the two pitches leave alike and carry
the same. A real ball also grips and stretches on the bat, leaving with up to
{C.KENSRUD_EXTRA_SPIN:.0%} more spin than rolling gives [kensrud2017], which can push a steep
ball's carry either way. Over the
share of the pitch's spin handed on (0-1), that extra spin (0-{C.KENSRUD_EXTRA_SPIN:.0%}), drag
and lift, each pitch's best point re-optimised, **the curveball's gain is {cu["paper"].text("+")}
m (paper's swing) and {cu["mlb"].text("+")} m (MLB-like)**, moved most by the
{cu["paper"].driver} and the {cu["mlb"].driver} (`ranges.curve_spread`):

{md_table(_pitch_rows(), "{:.4g}")}

Sawicki et al. reach the same verdict [sawicki2003]: optimally hit, a
{C.SAWICKI_CURVEBALL_MPH:.0f} mph curveball carries {C.SAWICKI_CURVEBALL_FT:.0f} ft and a
{C.SAWICKI_FASTBALL_MPH:.0f} mph fastball {C.SAWICKI_FASTBALL_FT:.0f} ft ({theirs:+.1f} m),
though the fastball leaves the bat {C.SAWICKI_EXIT_GAP_MPH:.0f} mph faster, in Hubbard's numbers
[popmech2009] (their optimal undercuts and swing angles were not available to this report).
Their model differs from this one: the bat swings upward at an angle chosen with the undercut
(here the swing is level, so the undercut alone sets the launch angle), the pitch arrives
descending at an angle set by its speed (here horizontally), e falls with the closing speed
(here e = {E} throughout), and their curveball is slower than their fastball (here the same
speed).
"""


def _bats_text() -> str:
    """Corked and aluminium bats at their best points, in metres and feet."""
    t = {sc.key: C.bat_table(sc) for sc in SCENARIOS}

    def change(key: str, bat: str, model: str, e: float = E) -> str:
        r = t[key][(t[key].bat == bat) & (t[key]["swing model"] == model) & (t[key].e == e)]
        return f"{r['change (m)'].iloc[0]:+.1f} m ({r['change (ft)'].iloc[0]:+.0f} ft)"

    cork, al = "R161, 1 x 10 in cork", M.ALUMINIUM
    width, smaller, n = spread_widths(t.values())
    return f"""**Corked and metal bats in metres.** Each bat at its own best point and undercut
(the swings carried over from the R161 as in sections 2 and 3). The 1 x 10 in cork changes the
carry by {change("paper", cork, "measured")} under the measured swing scaling n = 0.27 (paper's
swing; {change("mlb", cork, "measured")} MLB-like) and by {change("paper", cork, "constant_force")}
under the paper's u0 ~ 1/M ({change("mlb", cork, "constant_force")}). The aluminium bat at equal
e = 0.5 changes it by {change("paper", al, "measured")} (measured) to
{change("paper", al, "constant_force")} (u0 ~ 1/M), and at e = 0.60 by
{change("paper", al, "measured", 0.60)} to {change("paper", al, "constant_force", 0.60)}; the
metal bat of the R161's length at drop -3 (33 in, 30 oz, e = 0.5) by
{change("paper", M.EQUAL_LENGTH, "measured")} (measured) to
{change("paper", M.EQUAL_LENGTH, "constant_torque")} (constant torque), MLB-like
{change("mlb", M.EQUAL_LENGTH, "measured")} to {change("mlb", M.EQUAL_LENGTH, "constant_torque")}.
Each
carry's range over the drag and lift spread is {width[0]:.0f}-{width[1]:.0f} m wide, and
{smaller} of the {n} changes are smaller than their own carry's range; but the spread moves every
bat's ball alike, and the change itself, recomputed at each corner of the spread, keeps its sign
and nearly its size (last column):

paper's swing:

{md_table(_bat_rows(t["paper"]), "{:.4g}")}

MLB-like swing:

{md_table(_bat_rows(t["mlb"]), "{:.4g}")}
"""


def spread_widths(tables) -> tuple[tuple[float, float], int, int]:
    """Over ``carry.bat_table`` frames: the least and most width (m) of a carry's range over the
    drag/lift spread, and how many of the bats' changes are smaller than their own range's
    width, out of how many."""
    widths, smaller, n = [], 0, 0
    for t in tables:
        for _, r in t.iterrows():
            lo, hi = (float(x) for x in r["carry range (m)"].split("-"))
            widths.append(hi - lo)
            if r.bat != M.WOOD:
                n += 1
                smaller += abs(r["change (m)"]) < hi - lo
    return (min(widths), max(widths)), smaller, n


def _bat_rows(t: pd.DataFrame) -> pd.DataFrame:
    """A ``carry.bat_table`` as the text shows it: whole rpm and feet."""
    t = t[BAT_COLUMNS].copy()
    t["backspin (rpm)"] = t["backspin (rpm)"].round().astype(int)
    t["change (ft)"] = t["change (ft)"].round().astype(int)
    return t


def _reaction_text() -> str:
    """Section 3's '< 0.4 s' cases recomputed with drag, and the pitch's own time."""
    s = {sc.key: C.reaction_summary(sc) for sc in SCENARIOS}
    pt = {sc.key: C.pitch_time(sc) for sc in SCENARIOS}
    p, m = s["paper"], s["mlb"]
    return f"""**Reaction time, with drag.** Section 3 times the batted ball over the
{PITCHER_AFTER_FOLLOW_THROUGH_M} m to the pitcher with drag; at its exit speed alone it would
arrive up to {max(p["drag_adds_max_s"], m["drag_adds_max_s"]) * 1e3:.0f} ms sooner
(`flight.time_to_travel`, no spin: the least drag). Of the aluminium balls that would beat the
assumed {REACTION_S} s without drag,
**{p["al_below_drag"]} of {p["al_below_no_drag"]} (paper's swing) and {m["al_below_drag"]} of
{m["al_below_no_drag"]} (MLB-like) still do** (of
{p["al_cases"]} and {m["al_cases"]} cases); the wood ball takes {p["wood_t_drag_s"]:.3f} s
(paper's swing,
{p["wood_t_no_drag_s"]:.3f} s without drag) and {m["wood_t_drag_s"]:.3f} s (MLB-like,
{m["wood_t_no_drag_s"]:.3f} s). The pitch itself, released {RELEASE_TO_PLATE_M:.1f} m from the
plate [mlbrelease] with the fastball's backspin, must leave the hand at
{pt["paper"]["release_mps"]:.1f} m/s to arrive at {PAPER.v0_mps} m/s, and takes
{pt["paper"]["t_drag_s"]:.3f} s ({pt["mlb"]["release_mps"]:.1f} m/s and
{pt["mlb"]["t_drag_s"]:.3f} s for the {MLB.v0_mps:g} m/s pitch): the batter sees the pitch for
{pt["paper"]["t_drag_s"]:.3f} s where the pitcher sees the wood ball for
{p["wood_t_drag_s"]:.3f} s (paper's swing; MLB-like {pt["mlb"]["t_drag_s"]:.3f} and
{m["wood_t_drag_s"]:.3f} s).
"""


def _carry_figure() -> Figure:
    """Carry against the impact point for a few undercuts, both swings, sweet spots marked."""
    plt = pyplot()
    fig, axes = plt.subplots(1, 2, figsize=(13, 4.8), layout="constrained")
    for ax, sc in zip(axes, SCENARIOS):
        _carry_panel(ax, sc)
    fig.suptitle(
        f"R161 swung level, fastball with {C.FASTBALL_SPIN_RPM:.0f} rpm backspin, "
        f"e = {E}, mu = {C.MU_BALL_BAT}: carry along the barrel",
        fontsize=10,
    )
    return fig


def _carry_panel(ax: Axes, sc: Scenario) -> None:
    """One swing's carry curves, its speed sweet spot and its distance sweet spot."""
    grid, ss = C.carry_grid(C.hit_of(sc)), C.sweet_spots(sc)
    x = from_end_cm(R161, grid.s_m)
    for d, color in zip(CHART_UNDERCUTS_M, ("tab:blue", "tab:green", "tab:orange")):
        i = int(abs(grid.undercut_m - d).argmin())
        ax.plot(x, grid.carry_m[i], "o-", ms=3, color=color, label=f"undercut {d * 100:g} cm")
        b = next(r for r in ss.rows if abs(r.undercut_m - d) < 1e-12)
        ax.plot([from_end_cm(R161, b.s_m)], [b.carry_m], "D", color=color, mfc="none", ms=7)
    ax.axvline(
        from_end_cm(R161, ss.speed_s_m),
        color="k",
        ls="--",
        lw=1,
        label=f"speed sweet spot, {from_end_cm(R161, ss.speed_s_m):.1f} cm",
    )
    b = ss.best
    ax.plot(
        [from_end_cm(R161, b.s_m)],
        [b.carry_m],
        "*",
        color="tab:red",
        ms=15,
        zorder=5,
        label=f"distance sweet spot: {from_end_cm(R161, b.s_m):.1f} cm, undercut "
        f"{b.undercut_m * 100:.2f} cm, {b.carry_m:.1f} m",
    )
    ax.plot([], [], "D", color="0.3", mfc="none", label="longest carry at each undercut")
    ax.invert_xaxis()
    ax.set_xlabel("impact point, distance from the barrel end (cm)")
    ax.set_ylabel("carry (m)")
    ax.secondary_yaxis("right", functions=(C.feet, lambda f: f * FT_M)).set_ylabel("carry (ft)")
    ax.set_title(f"{sc.label}, pitch {sc.v0_mps:g} m/s", fontsize=9)
    ax.legend(fontsize=7.5, loc="upper center", bbox_to_anchor=(0.5, -0.14), ncol=2)
    ax.grid(alpha=0.3)
