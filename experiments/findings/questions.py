"""Sections 1-2 of findings.md, the paper's questions: the sweet spot and corked bats.

Each ``*_section`` returns its markdown, its charts (file name -> figure) and the numbers the
report's head and audit quote again; the numbers come from ``answers`` and ``metal``.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
import pandas as pd

from analytic import MEASURED_EXPONENT, center_of_percussion

from . import answers as A
from .inputs import INPUTS
from .located import sweet_engines_text
from .report import Section, md_table, pyplot

if TYPE_CHECKING:
    from matplotlib.figure import Figure

RUSSELL_CM = A.RUSSELL_CM
CORK_EXPONENTS = np.linspace(0.0, 1.0, 41)  # the cork chart's swing-speed exponents
_WOOD = INPUTS["wood_density_kgm3"]  # the hole's wood, its range quoted in section 2


# -- 1. sweet spot -------------------------------------------------------------------------------


def sweet_spot_section(engines: tuple[str, ...]) -> Section:
    """Section 1: where the sweet spot lies for swings from the hands, the sweet zone of one
    swing, the literature, and the sweet spot each engine's own data puts it at."""
    region = A.sweet_region_from_hands()
    table = A.sweet_spot_table()
    lo_cm, hi_cm = A.from_end_cm(A.R161, region.s_hi_m), A.from_end_cm(A.R161, region.s_lo_m)
    batting = A.batting_region_cm()
    text = "\n".join(
        [
            _sweet_model_text(region, table, lo_cm, hi_cm),
            _sweet_literature_text(table, lo_cm, hi_cm, batting),
            sweet_engines_text(engines),
            "![sweet spot region](findings_sweet_spot.png)\n",
        ]
    )
    widths_cm = [(hi - lo) * 100 for lo, hi in (A.zone(A.R161, sc) for sc in A.SCENARIOS)]
    return (
        text,
        {"findings_sweet_spot.png": _sweet_spot_figure(region)},
        {
            "region": (lo_cm, hi_cm),
            "batting": batting,
            "zone_cm": (min(widths_cm), max(widths_cm)),
            "best_cm": {
                sc.key: A.from_end_cm(A.R161, A.best_v1(A.R161, sc)[0]) for sc in A.SCENARIOS
            },
        },
    )


def _sweet_model_text(
    region: A.HandsRegion, table: pd.DataFrame, lo_cm: float, hi_cm: float
) -> str:
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


def _sweet_literature_text(
    table: pd.DataFrame, lo_cm: float, hi_cm: float, batting: tuple[float, float]
) -> str:
    """Our region against Cross's and Russell's, and the centre of percussion."""
    bat_lo, bat_hi = batting
    inside = max(0.0, min(bat_hi, RUSSELL_CM[1]) - max(bat_lo, RUSSELL_CM[0])) / (bat_hi - bat_lo)
    share, share_coarse = A.russell_share(fine=True), A.russell_share(fine=False)
    paper_zone = table.iloc[0]
    w = A.BATTING_OMEGAS_RADPS
    return f"""\
The literature: Cross's "about 17 cm from the barrel end" is from his notes [crossnotes]; his
1998 paper defines the sweet spot by the vibration node and the centre of percussion
[cross1998], not by v1. Russell puts it 12.7-17.8 cm from the end [russell]. The model's region
depends on the swing: the {lo_cm:.1f}-{hi_cm:.1f} cm above spans the paper's bat rates down to
12 rad/s, slower than any batting swing, and the slow swings put it farthest from the end. For
batting swings ({w[0]:.0f}-{w[-1]:.0f} rad/s, the MLB-like 48 rad/s +- 8, the bat turning about
the knob or the hands, pitches 35-47 m/s) the model puts it **{bat_lo:.1f}-{bat_hi:.1f} cm from
the end**, {inside:.0%} of that length inside Russell's range (the extremes are corner swings,
so the region does not depend on the grid); over the swings themselves, taken evenly in pitch,
rate and pivot, {share:.0%} put their sweet spot inside it (on a grid {A.SHARE_GRID_TEXT}; the
default grid gives {share_coarse:.0%}). The MLB-like swing's best point is
{table.iloc[1]["s* (cm from end)"]:.1f} cm. A rigid bat cannot settle where a batter *feels* the
sweet spot: that is set by the bat's vibrations (the node, the sting in the hands), which this
model does not have [nathan2000] (section 3c has them).
The centre of percussion for hands 0.1 m from the knob
({A.from_end_cm(A.R161, center_of_percussion(A.R161, A.HANDS_M)):.1f} cm from the end) falls in
the paper's swing's sweet zone ({paper_zone["1% zone (cm from end)"]} cm), but it is a different
spot (no jolt at the hands, not the largest v1).
"""


def _sweet_spot_figure(region: A.HandsRegion) -> Figure:
    """The sweet spot against bat rate and pitch, with the literature's and one swing's."""
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(8.5, 6.4), layout="constrained")
    for v, row in zip(region.pitches_mps, region.grid_s_m):
        ax.plot(
            region.omegas_radps,
            A.from_end_cm(A.R161, row),
            label=f"sweet spot, swing from the hands, pitch {v:g} m/s",
        )
    ax.axhspan(*RUSSELL_CM, color="0.88", zorder=0, label="Russell: 5-7 in from the end")
    ax.axhspan(
        16.5,
        17.5,
        facecolor="none",
        edgecolor="0.55",
        hatch="///",
        lw=0,
        zorder=1,
        label="Cross's notes: about 17 cm (drawn 16.5-17.5)",
    )
    cop = A.from_end_cm(A.R161, center_of_percussion(A.R161, A.HANDS_M))
    ax.axhline(
        cop,
        ls=(0, (6, 2, 1, 2)),
        lw=2,
        color="tab:purple",
        zorder=3,
        label=f"COP, hands 0.1 m from the knob: {cop:.1f} cm",
    )
    for sc, marker in zip(A.SCENARIOS, ("o", "s")):
        lo, hi = A.zone(A.R161, sc)
        best = A.from_end_cm(A.R161, A.best_v1(A.R161, sc)[0])
        ax.errorbar(
            [sc.swing.omega0_radps],
            [best],
            yerr=[[best - A.from_end_cm(A.R161, hi)], [A.from_end_cm(A.R161, lo) - best]],
            fmt=marker,
            color="k",
            capsize=4,
            zorder=4,
            label=f"{sc.label} (pitch {sc.v0_mps:g} m/s): best point, 1% zone",
        )
    ax.set_xlabel("bat angular speed omega0 (rad/s)")
    ax.set_ylabel("distance from the barrel end (cm)")
    ax.set_title(
        "R161, rigid-bat model: sweet spot vs swing and pitch speed (e does not move it)",
        fontsize=10,
    )
    fig.legend(fontsize=7.5, loc="outside lower center", ncol=2)
    ax.grid(alpha=0.3)
    return fig


# -- 2. corked bats ------------------------------------------------------------------------------


def cork_section() -> Section:
    """Section 2: the corked bats, when corking pays, and the model against Nathan's q."""
    verdicts = A.cork_verdicts()
    q = A.nathan_q_check()
    text = "\n".join(
        [
            _cork_bats_text(verdicts),
            _cork_verdict_text(verdicts),
            _cork_speeds_text(),
            _cork_measurement_text(q),
            "![cork gain against the swing-speed exponent](findings_cork.png)\n",
        ]
    )
    return text, {"findings_cork.png": _cork_figure()}, {"verdicts": verdicts, "q": q}


def _cork_bats_text(verdicts: pd.DataFrame) -> str:
    """The corked bats' properties and the break-even exponents."""
    paper, mlb = verdicts.iloc[0], verdicts.iloc[1]
    return f"""## 2. Does corking help?

A 1 in (25.4 mm) hole 6, 8 or 10 in deep drilled into the barrel end and filled with cork
(200 kg/m^3), rubber (1100 kg/m^3) or left hollow, in wood of {A.HOLE_WOOD_KGM3:.0f} kg/m^3
(a 1 x 10 in hole took 2.9 oz, 82 g, from a wood bat [nathancork]; its range,
{_WOOD.low:.0f}-{_WOOD.high:.0f} kg/m^3, runs from the R161's beam fit, section 3c, to ash at 12%
moisture [woodhandbook]; `analytic.corked_bat`: the hole's own r^2/4 + h^2/12 and parallel
axes about the new COM):

{md_table(A.cork_properties(), "{:.4g}")}

A corked bat is lighter, so with the same swing (the bat turning about the same axis at the
same rate: n = 0 below) it always hits slower (less mass behind the ball, its COM nearer the
axis). Whether the batter gains depends on how much faster he swings the lighter bat. With
swing speed ~ I_knob^-n (I about the knob; the batter's effort carried over from the solid R161),
the 1 x 10 in cork bat **breaks even at n = {paper["break-even n"]:.3f} for the paper's swing
and n = {mlb["break-even n"]:.3f} for an MLB-like swing** (rotation about the knob at
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

{md_table(speeds["paper"], "{:.2f}")}

MLB-like swing (pitch {A.MLB.v0_mps:g} m/s):

{md_table(speeds["mlb"], "{:.2f}")}
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
        ax.plot(
            ns,
            A.v1_gain_curve(A.CORK_1x10, sc, ns),
            color=color,
            label=f"{sc.label} (pitch {sc.v0_mps:g} m/s)",
        )
        n0 = A.break_even_exponent(A.CORK_1x10, sc)
        ax.plot([n0], [0.0], "o", color=color, mfc="none")
        ax.annotate(
            f"break-even n = {n0:.2f}",
            (n0, 0.0),
            textcoords="offset points",
            xytext=(8, -14) if sc is A.PAPER else (-100, 8),
            fontsize=8,
            color=color,
        )
    ax.axhline(0.0, color="k", lw=0.8)
    ax.axvspan(0.25, 0.27, color="0.85", label="measured n = 0.25-0.27 (Cross & Bower)")
    ax.axvline(0.5, color="0.4", ls=":", label="constant torque, n = 0.5")
    ax.set_xlabel("swing-speed exponent n (swing speed ~ I_knob^-n)")
    ax.set_ylabel("v1 gain of the 1 x 10 in cork bat (m/s)")
    ax.set_title(
        "Rigid-bat model, e = 0.5: corking pays only above the break-even exponent", fontsize=10
    )
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    return fig
