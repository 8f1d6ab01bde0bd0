"""Sections 1-3 of findings.md, the paper's questions: the sweet spot, corked bats, metal bats.

Each ``*_section`` returns its markdown, its charts (file name -> figure) and the numbers the
report's head and audit quote again; the numbers come from ``answers`` and ``metal``.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
import pandas as pd

from analytic import MEASURED_EXPONENT, SwingModel, batted_ball_speed, center_of_percussion

from . import answers as A
from . import metal as M
from .located import sweet_engines_text
from .report import Section, along_the_barrel, md_table, pyplot

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

RUSSELL_CM = (12.7, 17.8)   # Russell's sweet region, cm from the barrel end [russell]
CORK_EXPONENTS = np.linspace(0.0, 1.0, 41)  # the cork chart's swing-speed exponents
ROD_FRACTIONS_CHART = np.linspace(0.4, 1.2, 33)  # the metal chart's J_cm / uniform rod
MODELS = ("constant_force", "constant_torque", "measured")  # as the metal text names them


# -- 1. sweet spot -------------------------------------------------------------------------------

def sweet_spot_section(engines: tuple[str, ...]) -> Section:
    """Section 1: where the sweet spot lies for swings from the hands, the sweet zone of one
    swing, the literature, and the sweet spot each engine's own data puts it at."""
    region = A.sweet_region_from_hands()
    table = A.sweet_spot_table()
    lo_cm, hi_cm = A.from_end_cm(A.R161, region.s_hi_m), A.from_end_cm(A.R161, region.s_lo_m)
    text = "\n".join([_sweet_model_text(region, table, lo_cm, hi_cm),
                      _sweet_literature_text(table, lo_cm, hi_cm),
                      sweet_engines_text(engines),
                      "![sweet spot region](findings_sweet_spot.png)\n"])
    widths_cm = [(hi - lo) * 100 for lo, hi in (A.zone(A.R161, sc) for sc in A.SCENARIOS)]
    return text, {"findings_sweet_spot.png": _sweet_spot_figure(region)}, {
        "region": (lo_cm, hi_cm), "zone_cm": (min(widths_cm), max(widths_cm))}


def _sweet_model_text(region: A.HandsRegion, table: pd.DataFrame, lo_cm: float,
                      hi_cm: float) -> str:
    """The model's sweet spot, where it moves, and the sweet zone table."""
    return f"""## 1. Where is the sweet spot?

In the rigid-bat model the sweet spot (the impact point of largest batted-ball speed v1) lies
at s* = omega0 J k / (A + sqrt(A^2 + omega0^2 J k)) from the COM, A = v0 + u0,
k = (m + M)/(mM) (`analytic.sweet_spot`). For the R161 swung from the hands ({A.HANDS_M} m from
the knob, u0 = omega0 x {A.R161.com_from_knob_m - A.HANDS_M:.2f} m), pitches of 35-47 m/s and bat
rates of 12-48 rad/s, it moves between **{region.s_lo_m * 1e3:.0f} and {region.s_hi_m * 1e3:.0f} mm
from the COM, {lo_cm:.1f} to {hi_cm:.1f} cm from the barrel end**: toward the end when the bat
turns faster, toward the COM when the pitch or the bat's COM is faster; at omega0 = 0 it is
the COM.

For one swing, v1 stays within 1% of its best over a **sweet zone** several centimetres long:

{md_table(table, "{:.4g}")}
"""


def _sweet_literature_text(table: pd.DataFrame, lo_cm: float, hi_cm: float) -> str:
    """Our region against Cross's and Russell's, and the centre of percussion."""
    # the share of our region (lo_cm..hi_cm from the end) beyond Russell's far edge
    outside = (hi_cm - max(lo_cm, RUSSELL_CM[1])) / (hi_cm - lo_cm)
    paper_zone = table.iloc[0]
    return f"""\
The literature: Cross's "about 17 cm from the barrel end" is from his notes [crossnotes]; his
1998 paper defines the sweet spot by the vibration node and the centre of percussion
[cross1998], not by v1. Russell puts it 12.7-17.8 cm from the end [russell]: {outside:.0%} of our
{lo_cm:.1f}-{hi_cm:.1f} cm region lies farther from the end than his range, and only the fast
(MLB-like) swing brings the best point ({table.iloc[1]['s* (cm from end)']:.1f} cm) inside it. A
rigid bat cannot settle where a batter *feels* the sweet spot: that is set by the bat's
vibrations (the node, the sting in the hands), which this model does not have [nathan2000].
The centre of percussion for hands 0.1 m from the knob
({A.from_end_cm(A.R161, center_of_percussion(A.R161, A.HANDS_M)):.1f} cm from the end) falls in
the paper's swing's sweet zone ({paper_zone['1% zone (cm from end)']} cm), but it is a different
spot (no jolt at the hands, not the largest v1).
"""


def _sweet_spot_figure(region: A.HandsRegion) -> Figure:
    """The sweet spot against bat rate and pitch, with the literature's and one swing's."""
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(8.5, 6.4), layout="constrained")
    for v, row in zip(region.pitches_mps, region.grid_s_m):
        ax.plot(region.omegas_radps, A.from_end_cm(A.R161, row),
                label=f"sweet spot, swing from the hands, pitch {v:g} m/s")
    ax.axhspan(*RUSSELL_CM, color="0.88", zorder=0, label="Russell: 5-7 in from the end")
    ax.axhspan(16.5, 17.5, facecolor="none", edgecolor="0.55", hatch="///", lw=0, zorder=1,
               label="Cross's notes: about 17 cm (drawn 16.5-17.5)")
    cop = A.from_end_cm(A.R161, center_of_percussion(A.R161, A.HANDS_M))
    ax.axhline(cop, ls=(0, (6, 2, 1, 2)), lw=2, color="tab:purple", zorder=3,
               label=f"COP, hands 0.1 m from the knob: {cop:.1f} cm")
    for sc, marker in zip(A.SCENARIOS, ("o", "s")):
        lo, hi = A.zone(A.R161, sc)
        best = A.from_end_cm(A.R161, A.best_v1(A.R161, sc)[0])
        ax.errorbar([sc.swing.omega0_radps], [best],
                    yerr=[[best - A.from_end_cm(A.R161, hi)], [A.from_end_cm(A.R161, lo) - best]],
                    fmt=marker, color="k", capsize=4, zorder=4,
                    label=f"{sc.label} (pitch {sc.v0_mps:g} m/s): best point, 1% zone")
    ax.set_xlabel("bat angular speed omega0 (rad/s)")
    ax.set_ylabel("distance from the barrel end (cm)")
    ax.set_title("R161, rigid-bat model: sweet spot vs swing and pitch speed (e does not move it)",
                 fontsize=10)
    fig.legend(fontsize=7.5, loc="outside lower center", ncol=2)
    ax.grid(alpha=0.3)
    return fig


# -- 2. corked bats ------------------------------------------------------------------------------

def cork_section() -> Section:
    """Section 2: the corked bats, when corking pays, and the model against Nathan's q."""
    verdicts = A.cork_verdicts()
    q = A.nathan_q_check()
    text = "\n".join([_cork_bats_text(verdicts), _cork_verdict_text(verdicts),
                      _cork_speeds_text(), _cork_measurement_text(q),
                      "![cork gain against the swing-speed exponent](findings_cork.png)\n"])
    return text, {"findings_cork.png": _cork_figure()}, {"verdicts": verdicts, "q": q}


def _cork_bats_text(verdicts: pd.DataFrame) -> str:
    """The corked bats' properties and the break-even exponents."""
    paper, mlb = verdicts.iloc[0], verdicts.iloc[1]
    return f"""## 2. Does corking help?

A 1 in (25.4 mm) hole 6, 8 or 10 in deep drilled into the barrel end and filled with cork
(200 kg/m^3), rubber (1100 kg/m^3) or left hollow, in wood of 640 kg/m^3 (`analytic.corked_bat`:
the hole's own r^2/4 + h^2/12 and parallel axes about the new COM):

{md_table(A.cork_properties(), "{:.4g}")}

A corked bat is lighter, so with the same swing it always hits slower (less mass behind the
ball). Whether the batter gains depends on how much faster he swings the lighter bat. With
swing speed ~ I_knob^-n (I about the knob; the batter's effort carried over from the solid R161),
the 1 x 10 in cork bat **breaks even at n = {paper['break-even n']:.3f} for the paper's swing
and n = {mlb['break-even n']:.3f} for an MLB-like swing** (rotation about the knob at
{A.MLB.swing.omega0_radps:g} rad/s, {A.MLB.v0_mps:g} m/s pitch); corking pays only above it:

{md_table(verdicts, "{:.3f}")}
"""


def _cork_verdict_text(verdicts: pd.DataFrame) -> str:
    """What corking gains or loses under each swing-speed scaling."""
    paper, mlb = verdicts.iloc[0], verdicts.iloc[1]
    loss_paper, loss_mlb = -paper["gain at n = 0.27 (m/s)"], -mlb["gain at n = 0.27 (m/s)"]
    torque_paper, torque_mlb = paper["gain at n = 0.5 (m/s)"], mlb["gain at n = 0.5 (m/s)"]
    force = paper["gain, u0 ~ 1/M (paper, m/s)"]
    spiral = paper["gain, u0 ~ M^-1/2 (its log spiral, m/s)"]
    return f"""\
- Measured swings give n = 0.25-0.27 [crossbower]: **in the rigid-bat model with e = 0.5 and
  n = {MEASURED_EXPONENT}, corking lowers the batted-ball speed** by {loss_paper:.2f} m/s
  (paper's swing) and {loss_mlb:.2f} m/s (MLB-like swing).
- Constant torque (n = 0.5) is close to break-even for the paper's swing
  ({torque_paper:+.2f} m/s) and gains {torque_mlb:+.2f} m/s for the MLB-like swing.
- The paper's own assumption, u0 ~ 1/M at a fixed omega0, gives {force:+.2f} m/s;
  its log spiral, which gives u0 ~ M^-1/2 (section 5), gives {spiral:+.2f} m/s.
"""


def _cork_speeds_text() -> str:
    """v1 of every bat under every swing model, for both swings."""
    speeds = {sc.key: A.cork_speeds(sc) for sc in A.SCENARIOS}
    return f"""\
v1 at each bat's best point under each swing model (m/s; constant_force is the paper's u0 ~ 1/M,
constant_torque n = 0.5, measured n = {MEASURED_EXPONENT}):

paper's swing (pitch {A.PAPER.v0_mps} m/s):

{md_table(speeds['paper'], "{:.2f}")}

MLB-like swing (pitch {A.MLB.v0_mps:g} m/s):

{md_table(speeds['mlb'], "{:.2f}")}
"""


def _cork_measurement_text(q: dict[str, float]) -> str:
    """The model's collision efficiency ``q`` against Nathan et al.'s cannon measurement."""
    solid, corked = q["solid"], q["corked"]
    return f"""\
A direct check of the model against measurement: Nathan et al. fired balls at stationary bats
and measured the collision efficiency q = 0.214 for a solid and 0.193 for a corked bat
[nathan2011] (their bats, not the R161). The model's q = (e - r)/(1 + r), 6 in from the barrel
end, e = 0.5: **{solid:.3f} solid, {corked:.3f} corked** (1 x 10 in cork): the same drop of
about 10%. They argued about swing speed from swing-weight scaling; they did not measure how
far the ball goes, and theirs is one study among several.
"""


def _cork_figure() -> Figure:
    """The cork bat's v1 gain against the swing-speed exponent, with its break-even points."""
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(8, 4.8))
    ns = CORK_EXPONENTS
    for sc, color in zip(A.SCENARIOS, ("tab:blue", "tab:red")):
        ax.plot(ns, A.v1_gain_curve(A.CORK_1x10, sc, ns), color=color,
                label=f"{sc.label} (pitch {sc.v0_mps:g} m/s)")
        n0 = A.break_even_exponent(A.CORK_1x10, sc)
        ax.plot([n0], [0.0], "o", color=color, mfc="none")
        ax.annotate(f"break-even n = {n0:.2f}", (n0, 0.0), textcoords="offset points",
                    xytext=(8, -14) if sc is A.PAPER else (-100, 8), fontsize=8, color=color)
    ax.axhline(0.0, color="k", lw=0.8)
    ax.axvspan(0.25, 0.27, color="0.85", label="measured n = 0.25-0.27 (Cross & Bower)")
    ax.axvline(0.5, color="0.4", ls=":", label="constant torque, n = 0.5")
    ax.set_xlabel("swing-speed exponent n (swing speed ~ I_knob^-n)")
    ax.set_ylabel("v1 gain of the 1 x 10 in cork bat (m/s)")
    ax.set_title("Rigid-bat model, e = 0.5: corking pays only above the break-even exponent",
                 fontsize=10)
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    return fig


# -- 3. metal vs wood ----------------------------------------------------------------------------

def metal_section() -> Section:
    """Section 3: wood against the paper's aluminium bat, its unknown J_cm and COM, and why
    the rules restrict metal bats."""
    tables = {sc.key: M.metal_table(sc) for sc in A.SCENARIOS}
    match = {sc.key: M.fraction_matching_wood_sweet_spot(sc) for sc in A.SCENARIOS}
    lively = {e: M.lively_gain(tables.values(), e) for e in (0.55, 0.60)}
    text = "\n".join([_metal_bats_text(tables), _metal_findings_text(tables, lively),
                      _metal_inertia_text(match), _metal_rules_text()])
    gains = [M.gain_over_wood(t, m.value) for t in tables.values() for m in SwingModel]
    return text, {"findings_metal.png": _metal_figure(match)}, {
        "tables": tables, "match": match, "max_gain": max(gains),
        "lively": (lively[0.55][0], lively[0.60][1])}


def _below(table: pd.DataFrame) -> list[str]:
    """The aluminium cases whose ball reaches the pitcher within the reaction time."""
    out = []
    for _, row in table.iterrows():
        for col in table.columns:
            if col.startswith("t to 16.5 m") and row[col] < A.REACTION_S \
                    and row["bat"] != M.WOOD:
                out.append(f"aluminium at {col.split(', ')[1][:-4]} ({row['swing model']})")
    return out


def _metal_bats_text(tables: dict[str, pd.DataFrame]) -> str:
    """The aluminium bat's data and the two bats under each swing model."""
    al_frac, r161_frac = M.uniform_rod_fraction(A.AL), M.uniform_rod_fraction(A.R161)
    return f"""## 3. Why are metal bats restricted?

The paper's Easton 31 in, 28 oz aluminium bat: 0.794 kg, COM at 60% of its length (assumed: no
source gives it) and J_cm = 0.0205 kg m^2, which is the paper's "70 lb in^2" converted. That is
**{al_frac:.0%} of a uniform rod** of its length and mass, where the wooden R161 is at
{r161_frac:.0%}; the figure may be garbled by the text extraction, which drops every "2" (28 oz
reads "8 ounces", 42.59 reads "4.59"). Every result below is a rigid-bat model result for this
one pairing.

The two bats under each swing model (v1 at each bat's best point; the ball's time to a pitcher
16.5 m away, where he stands after his follow-through [ncaa]):

paper's swing (pitch {A.PAPER.v0_mps} m/s):

{md_table(tables['paper'], "{:.3f}")}

MLB-like swing (pitch {A.MLB.v0_mps:g} m/s):

{md_table(tables['mlb'], "{:.3f}")}
"""


def _metal_findings_text(tables: dict[str, pd.DataFrame],
                         lively: dict[float, tuple[float, float]]) -> str:
    """What lightness, liveliness and reaction time say about the aluminium bat."""
    paper, mlb = (" / ".join(f"{M.gain_over_wood(tables[k], m):+.2f}" for m in MODELS)
                  for k in ("paper", "mlb"))
    e55, e60 = ("{:.1f}-{:.1f}".format(*lively[e]) for e in (0.55, 0.60))
    paper_below = ", ".join(_below(tables["paper"])) or "no bat"
    mlb_below, cells = len(_below(tables["mlb"])), M.aluminium_times(tables["mlb"])
    wood_t = tables["mlb"].iloc[0]["t to 16.5 m, e=0.50 (s)"]
    return f"""\
- **At equal e = 0.5 lightness alone gains little or loses**: aluminium minus wood is
  {paper} m/s (paper's swing; u0 ~ 1/M, constant torque, measured
  n = 0.27) and {mlb} m/s (MLB-like swing).
- A livelier collision gains more: e = 0.55 adds {e55} m/s and e = 0.60
  {e60} m/s over the aluminium bat at e = 0.50 (every model, both swings).
- Reaction time: with the paper's swing, {paper_below} reach the pitcher
  in less than {A.REACTION_S} s; with the MLB-like swing {mlb_below} of the {cells} aluminium cases
  (3 models x 3 e) do (the wood bat too: {wood_t:.3f} s).
"""


def _metal_inertia_text(match: dict[str, float]) -> str:
    """Where the aluminium bat's sweet spot lies as its unknown J_cm and COM vary."""
    al_frac, r161_frac = M.uniform_rod_fraction(A.AL), M.uniform_rod_fraction(A.R161)
    scans = {sc.key: M.metal_inertia_scan(sc) for sc in A.SCENARIOS}
    scan0 = scans["paper"].iloc[0]
    com = M.al_com_sensitivity(A.PAPER)
    return f"""**The unknown J_cm decides where the metal bat's sweet spot lies.** At the paper's
J_cm ({al_frac:.0%} of a rod) it is {scan0['sweet spot (cm from end)']:.1f} cm from the end against
wood's {scan0["wood's (cm from end)"]:.1f} cm; Crisco et al. measured the sweet spot the same
distance from the tip on wood and metal bats and credit metal's higher speeds to faster swings
and a livelier collision [crisco2002]. The larger J_cm, the nearer the model comes to that: the
paper's 50% is the value the measurement supports least. Equal distances would take
**{match['paper']:.0%} (paper's swing) or {match['mlb']:.0%} (MLB-like swing) of a uniform rod**,
more than any bat with a tapering handle has (the R161: {r161_frac:.0%}): with a COM at 60%, no
plausible J_cm reproduces the measurement in a rigid-bat model, whose sweet spot is not the one
a batter feels [nathan2000]. Over a plausible range:

paper's swing:

{md_table(scans['paper'], "{:.3f}")}

MLB-like swing:

{md_table(scans['mlb'], "{:.3f}")}

The assumed COM matters as much: at 55%, 60% or 65% of the length the measured-model difference
to wood (paper's swing) is {com[0.55]:+.2f}, {com[0.60]:+.2f} or {com[0.65]:+.2f} m/s.
"""


def _metal_rules_text() -> str:
    """What the rules cap, and the chart."""
    return """\
**Why the rules restrict metal bats.** NCAA and high-school rules cap the ball-bat COR at 0.50
(BBCOR), slightly above the best wood bats, and keep beside it a length-to-weight limit (-3) and
a moment-of-inertia rule (about a point 6 in from the knob) [ncaa]: both the liveliness and the
swing weight are limited. MLB's wood-only rule is a different rule, not a BBCOR one [rules].

![metal vs wood](findings_metal.png)
"""


def _metal_figure(match: dict[str, float]) -> Figure:
    """v1 along the barrel of wood and aluminium, and the aluminium sweet spot against J_cm."""
    plt = pyplot()
    fig, axes = plt.subplots(1, 2, figsize=(13, 4.6), layout="constrained")
    _metal_barrel_panel(axes[0], match)
    _metal_inertia_panel(axes[1])
    fig.suptitle("Wood vs the paper's aluminium bat in the rigid-bat model", fontsize=10)
    return fig


def _metal_barrel_panel(ax: Axes, match: dict[str, float]) -> None:
    """v1 along the barrel for wood and aluminium (two J_cm), the paper's swing carried over."""
    sc = A.PAPER
    for bat, color, label in ((A.R161, "tab:brown", M.WOOD),
                              (A.AL, "tab:gray", "aluminium, J_cm 50% of a rod"),
                              (M.aluminium_with(match["paper"]), "tab:cyan",
                               f"aluminium, J_cm {match['paper']:.0%} of a rod")):
        sw = A.carried_swing(bat, sc, SwingModel.MEASURED)
        s = np.linspace(bat.s_min_m + 0.25, bat.s_max_m, 200)
        for e, ls in (((0.5, "-"), (0.6, "--")) if bat is A.AL else ((0.5, "-"),)):
            ax.plot(A.from_end_cm(bat, s), batted_ball_speed(
                bat, A.BALL, s, v0_mps=sc.v0_mps, u0_mps=sw.u0_mps,
                omega0_radps=sw.omega0_radps, e=e), ls, color=color, label=f"{label}, e = {e}")
    along_the_barrel(ax, "paper's swing carried over with n = 0.27")


def _metal_inertia_panel(ax: Axes) -> None:
    """The aluminium sweet spot against its J_cm, against wood's, for both swings."""
    fr = ROD_FRACTIONS_CHART
    for sc, color in zip(A.SCENARIOS, ("tab:blue", "tab:red")):
        bats = [M.aluminium_with(f) for f in fr]
        ax.plot(fr * 100, [A.from_end_cm(b, A.best_v1(b, sc)[0]) for b in bats],
                color=color, label=f"aluminium, {sc.label}")
        ax.axhline(A.from_end_cm(A.R161, A.best_v1(A.R161, sc)[0]), color=color, ls=":",
                   label=f"R161 wood, {sc.label}")
    ax.axvline(M.uniform_rod_fraction(A.AL) * 100, color="k", lw=0.8, ls="--",
               label="paper's J_cm (70 lb in^2)")
    ax.set_xlabel("aluminium J_cm, % of a uniform rod of its length and mass")
    ax.set_ylabel("sweet spot, distance from the barrel end (cm)")
    ax.set_title("where the metal bat's sweet spot lies depends on its J_cm", fontsize=9)
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
