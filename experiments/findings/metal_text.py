"""Section 3 of findings.md: metal bats against wood, at the paper's pairing, at equal length and
at BBCOR's drop -3, the unknown J_cm and COM, and what the rules cap. The numbers come from
``metal``."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
import pandas as pd

from analytic import SwingModel, batted_ball_speed

from . import answers as A
from . import metal as M
from . import ranges as R
from .inputs import INPUTS, Spread
from .report import Section, along_the_barrel, md_table, pyplot

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

ROD_FRACTIONS_CHART = np.linspace(0.4, 1.6, 49)  # the metal chart's J_cm / uniform rod
MODELS = ("constant_force", "constant_torque", "measured")  # as the metal text names them


# -- 3. metal vs wood ----------------------------------------------------------------------------


def metal_section() -> Section:
    """Section 3: wood against the paper's aluminium bat, metal bats of wood's length and at
    BBCOR's drop -3, the unknown J_cm and COM, and why the rules restrict metal bats."""
    tables = {sc.key: M.metal_table(sc) for sc in A.SCENARIOS}
    bbcor = {sc.key: M.bbcor_table(sc) for sc in A.SCENARIOS}
    match = {
        (sc.key, m.value): M.fraction_matching_wood_sweet_spot(sc, m)
        for sc in A.SCENARIOS
        for m in SwingModel
    }
    lively = {e: M.lively_gain(tables.values(), e) for e in (0.55, 0.60)}
    text = "\n".join(
        [
            _metal_bats_text(tables),
            _metal_findings_text(tables, bbcor, lively),
            _metal_inertia_text(match),
            _metal_rules_text(bbcor),
        ]
    )
    gains = [M.gain_over_wood(t, m.value) for t in tables.values() for m in SwingModel]
    return (
        text,
        {"findings_metal.png": _metal_figure(match)},
        {
            "tables": tables,
            "bbcor": bbcor,
            "match": match,
            "max_gain": max(gains),
            "lively": (lively[0.55][0], lively[0.60][1]),
        },
    )


def _below(table: pd.DataFrame) -> list[str]:
    """The aluminium cases whose ball reaches the pitcher within the reaction time (drag on)."""
    out = []
    for _, row in table.iterrows():
        for col in table.columns:
            if col.startswith("t to 16.5 m") and row[col] < A.REACTION_S and row["bat"] != M.WOOD:
                out.append(
                    f"aluminium at {col.split(', ')[1][:-4]} ({row['swing model']}, "
                    f"{row[col]:.3f} s)"
                )
    return out


def _metal_bats_text(tables: dict[str, pd.DataFrame]) -> str:
    """The aluminium bat's data and the two bats under each swing model."""
    al_frac, r161_frac = M.uniform_rod_fraction(A.AL), M.uniform_rod_fraction(A.R161)
    return f"""## 3. Why are metal bats restricted?

The paper's Easton 31 in, 28 oz aluminium bat: 0.794 kg, COM at 60% of its length (assumed: no
source gives it) and J_cm = 0.0205 kg m^2, which is the paper's "70 lb in^2" converted. That is
**{al_frac:.0%} of a uniform rod** of its length and mass, where the wooden R161 is at
{r161_frac:.0%}; the figure may be garbled by the text extraction, which drops every "2" (28 oz
reads "8 ounces", 42.59 reads "4.59"). Every result below is a rigid-bat model result and
depends on the swing model (n), this J_cm and COM, the swing and e.

The two bats under each swing model (v1 at each bat's best point; the ball's time, with drag
(`flight.time_to_travel`), to a pitcher 16.5 m from the plate, about where his hand released
the pitch [mlbrelease]). e = 0.55 and 0.60 are what-if values, not measurements: they bracket
the e = 0.576 that the paper's 42.59 m/s needs (section 5); a certified bat today is capped at
0.50 [ncaa]:

paper's swing (pitch {A.PAPER.v0_mps} m/s):

{md_table(tables["paper"], "{:.3f}")}

MLB-like swing (pitch {A.MLB.v0_mps:g} m/s):

{md_table(tables["mlb"], "{:.3f}")}
"""


def _metal_findings_text(
    tables: dict[str, pd.DataFrame],
    bbcor: dict[str, pd.DataFrame],
    lively: dict[float, tuple[float, float]],
) -> str:
    """What length, lightness, liveliness and reaction time say about the metal bat."""
    paper, mlb = (
        " / ".join(f"{M.gain_over_wood(tables[k], m):+.2f}" for m in MODELS)
        for k in ("paper", "mlb")
    )
    same = {k: bbcor[k][bbcor[k]["metal bat"] == "33 in, 30 oz"].iloc[0] for k in bbcor}
    eq = {
        k: " / ".join(f"{same[k][f'gain over wood, {m} (m/s)']:+.2f}" for m in MODELS) for k in same
    }
    e55, e60 = ("{:.1f}-{:.1f}".format(*lively[e]) for e in (0.55, 0.60))
    rng = {sc.key: R.metal_spreads(sc) for sc in A.SCENARIOS}
    share = {k: r["length027"] for k, r in rng.items()}
    below = _below(tables["paper"])
    paper_below = ", ".join(below) or "no case"
    mlb_below, cells = len(_below(tables["mlb"])), M.aluminium_times(tables["mlb"])
    wood_t = tables["mlb"].iloc[0]["t to 16.5 m, e=0.50 (s)"]
    return f"""\
- **At equal e = 0.5 the paper's comparison is partly one of length**: its 31 in aluminium
  bat minus the 33 in R161 is {paper} m/s (paper's swing; u0 ~ 1/M, constant torque, measured
  n = 0.27) and {mlb} m/s (MLB-like swing). A metal bat of the R161's length at BBCOR's
  drop -3 (33 in, 30 oz, the same proportions) gives {eq["paper"]} m/s (paper's swing) and
  {eq["mlb"]} m/s (MLB-like). So at n = 0.27 the shorter length explains
  {_percent(share["paper"])} / {_percent(share["mlb"])} of the 31 in bat's loss (as a share, 1 minus
  the 33 in bat's loss over the 31 in bat's; over the unsourced COM, J_cm and e, moved most by
  the {share["paper"].driver}): under the measured scaling most of it is lightness; "mostly
  length" holds only at constant torque, where the loss is small. Over the metal bat's COM
  ({_com}) and J_cm ({_rod}) and e, the 33 in bat's change is {rng["paper"]["equal027"].text("+")}
  / {rng["mlb"]["equal027"].text("+")} m/s at n = 0.27 and {rng["paper"]["equal05"].text("+")} /
  {rng["mlb"]["equal05"].text("+")} m/s at constant torque (`ranges.metal_spreads`).
- A livelier collision gains more: e = 0.55 adds {e55} m/s and e = 0.60
  {e60} m/s over the aluminium bat at e = 0.50 (every model, both swings).
- Reaction time, an assumed 0.4 s (a round figure, not a sourced threshold; the times are in
  the tables): with the paper's swing {len(below)} cases reach the pitcher
  sooner ({paper_below}); with the MLB-like
  swing {mlb_below} of the {cells} aluminium cases (3 models x 3 e) do, and so does the wood
  bat's ball ({wood_t:.3f} s): at these speeds the threshold separates swings, not bats.
"""


_COM, _ROD = INPUTS["metal_com_fraction"], INPUTS["metal_rod_fraction"]
_com = f"{_COM.low:.0%}-{_COM.high:.0%} of its length"
_rod = f"{_ROD.low:.0%}-{_ROD.high:.0%} of a rod's"


def _percent(sp: Spread) -> str:
    """A share's spread quoted in percent: ``central% (low%-high%)``."""
    return f"{sp.central:.0%} ({sp.low:.0%}-{sp.high:.0%})"


def _metal_inertia_text(match: dict[tuple[str, str], float]) -> str:
    """Where the aluminium bat's sweet spot lies as its unknown J_cm and COM vary."""
    al_frac, r161_frac = M.uniform_rod_fraction(A.AL), M.uniform_rod_fraction(A.R161)
    scans = {sc.key: M.metal_inertia_scan(sc) for sc in A.SCENARIOS}
    scan0 = scans["paper"].iloc[0]
    com = M.al_com_sensitivity(A.PAPER)
    need = {k: " / ".join(f"{match[(k, m)]:.0%}" for m in MODELS) for k in ("paper", "mlb")}
    return f"""**The unknown J_cm decides where the metal bat's sweet spot lies.** At the paper's
J_cm ({al_frac:.0%} of a rod) it is {scan0["sweet spot (cm from end)"]:.1f} cm from the end against
wood's {scan0["wood's (cm from end)"]:.1f} cm (each bat swung as the measured n = 0.27 carries
the swing over). Crisco et al. measured the sweet spot the same distance from the tip on wood and
metal bats [crisco2002]. In this rigid model equal distances would take a J_cm of
**{need["paper"]} of a uniform rod** (paper's swing; u0 ~ 1/M, constant torque, measured) and
{need["mlb"]} (MLB-like), with the COM at 60%: more than a bat with a tapering handle has (the
R161: {r161_frac:.0%}). This does not single out a J_cm: the model's sweet spot is the point of
largest v1 with one e everywhere, while a real bat's COR and vibrations vary along the barrel
(section 3c), which a rigid model does not have [nathan2000]. Over a plausible range (sweet spot
and gains with the swing carried over by each model):

paper's swing:

{md_table(scans["paper"], "{:.3f}")}

MLB-like swing:

{md_table(scans["mlb"], "{:.3f}")}

The assumed COM matters as much: at 55%, 60% or 65% of the length the measured-model difference
to wood (paper's swing) is {com[0.55]:+.2f}, {com[0.60]:+.2f} or {com[0.65]:+.2f} m/s.
"""


def _metal_rules_text(bbcor: dict[str, pd.DataFrame]) -> str:
    """What the rules cap: metal bats at the lengths BBCOR allows, and the chart."""
    return f"""\
**Why the rules restrict metal bats.** NCAA and high-school rules cap the ball-bat COR at 0.50
(BBCOR), slightly above the best wood bats, and keep beside it a length-to-weight limit (-3) and
a moment-of-inertia rule (about a point 6 in from the knob) [ncaa]: both the liveliness and the
swing weight are limited. MLB's wood-only rule is a different rule, not a BBCOR one [rules].
Metal bats at drop -3 (the paper's proportions, e = 0.5), v1 at the best point minus the R161's:

paper's swing:

{md_table(bbcor["paper"], "{:.3f}")}

MLB-like swing:

{md_table(bbcor["mlb"], "{:.3f}")}

At e = 0.5 every one of these legal metal bats hits slower than the R161 under the measured
scaling ({_span(bbcor, "measured")} m/s, the longer bats losing least) and within
{_span(bbcor, "constant_torque")} m/s of it under constant torque: with the COR capped near
wood's, length and swing weight alone move v1 less than a livelier collision would.

![metal vs wood](findings_metal.png)
"""


def _span(bbcor: dict[str, pd.DataFrame], model: str) -> str:
    """The least and most gain over wood of the BBCOR bats under one model, both swings."""
    gains = pd.concat([t[f"gain over wood, {model} (m/s)"] for t in bbcor.values()])
    return f"{gains.min():+.2f} to {gains.max():+.2f}"


def _metal_figure(match: dict[tuple[str, str], float]) -> Figure:
    """v1 along the barrel of wood and aluminium, and the aluminium sweet spot against J_cm."""
    plt = pyplot()
    fig, axes = plt.subplots(1, 2, figsize=(13, 4.6), layout="constrained")
    _metal_barrel_panel(axes[0], match)
    _metal_inertia_panel(axes[1])
    fig.suptitle("Wood vs the paper's aluminium bat in the rigid-bat model", fontsize=10)
    return fig


def _metal_barrel_panel(ax: Axes, match: dict[tuple[str, str], float]) -> None:
    """v1 along the barrel for wood and aluminium (two J_cm), the paper's swing carried over."""
    sc = A.PAPER
    for bat, color, label in (
        (A.R161, "tab:brown", M.WOOD),
        (A.AL, "tab:gray", "aluminium, J_cm 50% of a rod"),
        (
            M.aluminium_with(match[("paper", "measured")]),
            "tab:cyan",
            f"aluminium, J_cm {match[('paper', 'measured')]:.0%} of a rod",
        ),
    ):
        sw = A.carried_swing(bat, sc, SwingModel.MEASURED)
        s = np.linspace(bat.s_min_m + 0.25, bat.s_max_m, 200)
        for e, ls in ((0.5, "-"), (0.6, "--")) if bat is A.AL else ((0.5, "-"),):
            ax.plot(
                A.from_end_cm(bat, s),
                batted_ball_speed(
                    bat,
                    A.BALL,
                    s,
                    v0_mps=sc.v0_mps,
                    u0_mps=sw.u0_mps,
                    omega0_radps=sw.omega0_radps,
                    e=e,
                ),
                ls,
                color=color,
                label=f"{label}, e = {e}",
            )
    along_the_barrel(ax, "paper's swing carried over with n = 0.27")


def _metal_inertia_panel(ax: Axes) -> None:
    """The aluminium sweet spot against its J_cm, against wood's, for both swings."""
    fr = ROD_FRACTIONS_CHART
    for sc, color in zip(A.SCENARIOS, ("tab:blue", "tab:red")):
        bats = [M.aluminium_with(f) for f in fr]
        ax.plot(
            fr * 100,
            [
                A.from_end_cm(b, A.best_v1(b, sc, A.carried_swing(b, sc, SwingModel.MEASURED))[0])
                for b in bats
            ],
            color=color,
            label=f"aluminium, {sc.label}",
        )
        ax.axhline(
            A.from_end_cm(A.R161, A.best_v1(A.R161, sc)[0]),
            color=color,
            ls=":",
            label=f"R161 wood, {sc.label}",
        )
    ax.axvline(
        M.uniform_rod_fraction(A.AL) * 100,
        color="k",
        lw=0.8,
        ls="--",
        label="paper's J_cm (70 lb in^2)",
    )
    ax.set_xlabel("aluminium J_cm, % of a uniform rod of its length and mass")
    ax.set_ylabel("sweet spot, distance from the barrel end (cm)")
    ax.set_title("where the metal bat's sweet spot lies depends on its J_cm (n = 0.27)", fontsize=9)
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
