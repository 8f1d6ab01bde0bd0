"""Answer the paper's questions with the harness: sweet spot, corked bats, metal bats, audit.

    python -m experiments.findings

Writes findings.md (text, tables, the answers) and findings_*.png into the run directory
(results/ by python -m experiments.baselines). Every number is
computed here by the analytic model and, where it says so, confirmed by the three engines
(reference profile); numbers from the literature carry their reference.
"""

from __future__ import annotations

import argparse
import math
import sys
from dataclasses import replace
from pathlib import Path

import numpy as np
import pandas as pd

import adapters
import analytic
from analytic import (Bat, ImpactCase, SwingModel, batted_ball_speed, center_of_percussion,
                      corked_bat_paper, predict, predict_oblique_paper, presets, sweet_region,
                      sweet_spot, swing_for)
from analytic.dynamics import HingedSwing

from ._io import figure_png, provenance

R161, AL, BALL = presets.R161, presets.EASTON31, presets.BASEBALL
PITCH = presets.PAPER_PITCH_MPS
SWING = presets.PAPER_SWING
E = presets.E_WOOD
HANDS_M = 0.1                     # the paper's holding point, 0.1 m from the knob
MOUND_M = 18.44                   # 60 ft 6 in, pitching rubber to home plate
REACTION_S = 0.4                  # the paper's minimum reaction time
IN = 0.0254
FILLS = {"cork": 200.0, "rubber": 1100.0, "hollow": 0.0}
DEPTHS_IN = (6, 8, 10)
MODEL_LABEL = {"constant_force": "paper: u0 ~ 1/M, omega0 kept",
               "constant_torque": "constant torque: omega0 ~ I_knob^-1/2",
               "measured": "measured: omega0 ~ I_knob^-0.27"}
REFS = {
    "cross2009": "R. Cross, \"Mechanics of swinging a bat\", Am. J. Phys. 77, 36 (2009): the R161 "
                 "data (0.871 kg, 0.84 m, COM 0.56 m, J_cm 0.039 kg m^2), used by the paper.",
    "cross1998": "R. Cross, \"The sweet spot of a baseball bat\", Am. J. Phys. 66, 772 (1998); "
                 "his notes (physics.usyd.edu.au/~cross/baseball.html) put the sweet spot of a "
                 "major-league bat about 17 cm from the barrel end.",
    "russell": "D. A. Russell, \"The sweet spot of a hollow baseball or softball bat\", Kettering "
               "University (2004) (the paper's ref. [2]): a region about 5-7 in (12.7-17.8 cm) "
               "from the barrel end.",
    "crossbower": "R. Cross and R. Bower, \"Effects of swing-weight on swing speed and racket "
                  "power\", J. Sports Sci. 24, 23 (2006): swing speed ~ I^-n, n = 0.27 (0.25 "
                  "for softball bats).",
    "nathan2011": "A. M. Nathan, L. V. Smith, W. L. Faber, D. A. Russell, \"Corked bats, juiced "
                  "balls, and humidors: the physics of cheating in baseball\", Am. J. Phys. 79, "
                  "575 (2011): a corked bat does not hit the ball farther; in their tests the "
                  "ball came off the corked bat no faster than off the solid one.",
    "rules": "Official Baseball Rules (MLB): ball 5-5.25 oz, 9-9.25 in around (3.01); barrel at "
             "most 2.61 in (3.02); pitching rubber 60 ft 6 in (18.44 m) from home plate.",
    "bbcor": "NCAA/NFHS BBCOR standard (2011): non-wood bats may not exceed a ball-bat "
             "coefficient of restitution of 0.50, i.e. no livelier than wood.",
}


def md_table(df: pd.DataFrame, floatfmt: str = "{:.3f}") -> str:
    """A pandas frame as a GitHub markdown table."""
    def cell(v):
        if isinstance(v, float):
            return "n/a" if math.isnan(v) else floatfmt.format(v)
        return str(v)

    lines = ["| " + " | ".join(map(str, df.columns)) + " |",
             "|" + "---|" * len(df.columns)]
    lines += ["| " + " | ".join(cell(v) for v in row) + " |" for row in df.itertuples(index=False)]
    return "\n".join(lines)


_ENGINES: dict[str, adapters.Engine] = {}


def _engine(name: str) -> adapters.Engine:
    """One reference-profile engine per name for the whole report (closed in main)."""
    if name not in _ENGINES:
        _ENGINES[name] = adapters.load(name)
    return _ENGINES[name]


def engine_v1(bat: Bat, s_m: float, u0: float, w0: float, e: float = E) -> dict[str, float]:
    """v1 in each engine (reference profile) for one impact; NaN where it fails."""
    case = ImpactCase(bat=bat, ball=BALL, s_m=s_m, v0_mps=PITCH, u0_mps=u0, omega0_radps=w0, e=e)
    out = {}
    for name in adapters.names():
        res = _engine(name).simulate(case)
        out[name] = res.v1_mps if res.ok else math.nan
    return out


def hittable_sweet_spot(bat: Bat, u0: float, w0: float, v0: float = PITCH) -> float:
    """The sweet spot, or the nearer end of the capsule's cylinder if it lies beyond."""
    return analytic.hittable_sweet_spot(bat, BALL, v0, u0, w0)


def v1_at(bat: Bat, s: float, u0: float, w0: float, e: float = E, v0: float = PITCH) -> float:
    return float(batted_ball_speed(bat, BALL, s, v0_mps=v0, u0_mps=u0, omega0_radps=w0, e=e))


# -- 1. sweet spot -------------------------------------------------------------------------------

def engine_argmax(name: str, bat: Bat, v0: float, u0: float, w0: float) -> float:
    """Sweet spot located from engine data alone: a 41-point grid over the bat, then a 0.5 mm
    grid across the best coarse cell, then a parabola through the best fine point and its two
    neighbours. A failed impact never counts as the maximum."""
    eng = _engine(name)

    def v1s(ss):
        outs = [eng.simulate(ImpactCase(bat=bat, ball=BALL, s_m=float(x), v0_mps=v0, u0_mps=u0,
                                        omega0_radps=w0, e=E)) for x in ss]
        return np.array([o.v1_mps if o.ok else -math.inf for o in outs])

    coarse = np.linspace(bat.s_min_m, bat.s_max_m, 41)
    i = int(np.argmax(v1s(coarse)))
    lo, hi = coarse[max(i - 1, 0)], coarse[min(i + 1, 40)]
    fine = np.arange(lo, hi + 1e-12, 5e-4)
    v = v1s(fine)
    j = int(np.clip(np.argmax(v), 1, len(fine) - 2))
    y0, y1, y2 = v[j - 1], v[j], v[j + 1]
    shift = 0.5 * (y0 - y2) / (y0 - 2 * y1 + y2)
    return float(fine[j] + shift * 5e-4)


def sweet_spot_section():
    d = R161.com_from_knob_m - HANDS_M
    end = R161.s_barrel_end_m
    omegas = np.linspace(12, 47, 36)
    pitches = (35.0, 41.0, 47.0)
    region = sweet_region(R161, BALL, v0_range_mps=(35.0, 47.0), u0_range_mps=(12 * d, 47 * d),
                          omega0_range_radps=(12.0, 47.0))
    # u0 and omega0 tied by the swing from the hands: scan the tied pairs
    grid_s = np.array([[sweet_spot(R161, BALL, v, w * d, w) for w in omegas] for v in pitches])
    s_lo, s_hi = float(grid_s.min()), float(grid_s.max())
    paper_region = sweet_region(R161, BALL, v0_range_mps=(40.2, 46.9),
                                u0_range_mps=(0.0, 17.87), omega0_range_radps=(12.0, 32.0))
    cops = {h: center_of_percussion(R161, h) for h in (0.1, 0.15)}
    cases = {"paper's swing (u0 17.87, omega0 32)": (PITCH, SWING.u0_mps, SWING.omega0_radps),
             "from the hands, omega0 32": (PITCH, 32 * d, 32.0),
             "from the hands, omega0 45 (MLB)": (40.0, 45 * d, 45.0)}
    rows = []
    for label, (v0, u0, w0) in cases.items():
        s_star = sweet_spot(R161, BALL, v0, u0, w0)
        located = {n: engine_argmax(n, R161, v0, u0, w0) for n in adapters.names()}
        rows.append({"swing": label, "v0 m/s": v0, "u0 m/s": u0, "omega0 rad/s": w0,
                     "s* from COM (mm)": s_star * 1e3,
                     "s* from barrel end (cm)": (end - s_star) * 100,
                     **{f"{n} offset (mm)": (located[n] - s_star) * 1e3 for n in located}})
    table = pd.DataFrame(rows)
    worst = float(table[[c for c in table.columns if "offset" in c]].abs().max().max())
    text = f"""## 1. Where is the sweet spot?

The sweet spot (the impact point of largest batted-ball speed v1) lies at
s* = omega0 J k / (A + sqrt(A^2 + omega0^2 J k)) from the COM, A = v0 + u0, k = (m + M)/(mM)
(`analytic.sweet_spot`). For the R161 swung from the hands ({HANDS_M} m from the knob, so
u0 = omega0 x {d:.2f} m) over realistic ranges (pitch 35-47 m/s, bat 12-47 rad/s) it moves
between **{s_lo * 1e3:.0f} and {s_hi * 1e3:.0f} mm from the COM**, i.e.
**{(end - s_hi) * 100:.1f} to {(end - s_lo) * 100:.1f} cm from the barrel end**: a region
{(s_hi - s_lo) * 1e3:.0f} mm long, not a point. It moves toward the barrel end when the bat
turns faster and toward the COM when the pitch or the bat's COM is faster (ds*/dA < 0,
ds*/domega0 > 0); with no rotation it is the COM. The same formula over the box of independent
u0 in [{12 * d:.1f}, {47 * d:.1f}] m/s gives {region.s_min_m * 1e3:.0f}-{region.s_max_m * 1e3:.0f} mm.

The centre of percussion for hands at 0.10 m / 0.15 m from the knob is
{cops[0.1] * 1e3:.1f} / {cops[0.15] * 1e3:.1f} mm from the COM
({(end - cops[0.1]) * 100:.1f} / {(end - cops[0.15]) * 100:.1f} cm from the barrel end): inside the
sweet region, but it is a different spot (zero shock at the hands, not largest v1).
Literature: Cross puts the sweet spot of a major-league bat about 17 cm from the barrel end
[cross1998], Russell 5-7 in = 12.7-17.8 cm [russell]; our region
({(end - s_hi) * 100:.1f}-{(end - s_lo) * 100:.1f} cm) overlaps both, and the COP
({(end - cops[0.1]) * 100:.1f} cm) sits near Russell's upper end.

Located from engine data alone (41-point grid, then 0.5 mm grid and a parabola; reference
profile), all three engines put the sweet spot within **{worst * 1e3:.1f} um** of theory (target
1 mm):

{md_table(table, "{:.4g}")}

![sweet spot region](findings_sweet_spot.png)
"""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(8, 5))
    for v, row in zip(pitches, grid_s):
        ax.plot(omegas, (end - row) * 100, label=f"sweet spot, pitch {v:g} m/s")
    ax.axhspan(5 * 2.54, 7 * 2.54, color="0.88", zorder=0, label="Russell: 5-7 in from the end")
    ax.axhspan(16.5, 17.5, facecolor="none", edgecolor="0.55", hatch="///", lw=0, zorder=1,
               label="Cross: about 17 cm (drawn 16.5-17.5)")
    for h, s in cops.items():
        ax.axhline((end - s) * 100, ls=(0, (6, 2, 1, 2)), lw=2, zorder=3,
                   color="tab:purple" if h == 0.1 else "tab:brown",
                   label=f"COP, hands {h} m from the knob: {(end - s) * 100:.1f} cm")
    ax.set_xlabel("bat angular speed omega0 (rad/s); u0 = omega0 x 0.46 m (swing from the hands)")
    ax.set_ylabel("distance from the barrel end (cm)")
    ax.set_title("R161: sweet spot (max v1) vs swing and pitch speed; e does not move it",
                 fontsize=10)
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    return text, {"findings_sweet_spot.png": fig}, {"region_mm": (s_lo * 1e3, s_hi * 1e3),
                                                     "paper_region": paper_region,
                                                     "cop_mm": cops[0.1] * 1e3}


# -- 2. corked bats ------------------------------------------------------------------------------

def corked_bats() -> dict[tuple[str, int], tuple[Bat, Bat]]:
    out = {}
    for fill, rho in FILLS.items():
        for depth in DEPTHS_IN:
            kw = dict(hole_radius_m=0.5 * IN, hole_depth_m=depth * IN, fill_density_kgm3=rho,
                      wood_density_kgm3=640.0)
            out[(fill, depth)] = (R161.corked(**kw), corked_bat_paper(R161, **kw))
    return out


def model_v1(bat: Bat, model: SwingModel) -> tuple[float, float, float, float]:
    """(u0, omega0, s at the sweet spot, v1 there) for ``bat`` under ``model``."""
    sw = swing_for(bat, model=model, reference_bat=R161, reference=SWING)
    s = hittable_sweet_spot(bat, sw.u0_mps, sw.omega0_radps)
    return sw.u0_mps, sw.omega0_radps, s, v1_at(bat, s, sw.u0_mps, sw.omega0_radps)


def cork_section():
    bats = corked_bats()
    wood = {m: model_v1(R161, m)[3] for m in SwingModel}
    props, speeds, checks = [], [], []
    for (fill, depth), (exact, paper) in bats.items():
        props.append({"fill": fill, "depth (in)": depth,
                      "dM (g)": (exact.mass_kg - R161.mass_kg) * 1e3,
                      "dCOM (mm)": (exact.com_from_knob_m - R161.com_from_knob_m) * 1e3,
                      "J_cm exact (kg m^2)": exact.inertia_cm_kgm2,
                      "J_cm paper (kg m^2)": paper.inertia_cm_kgm2,
                      "paper - exact (%)": (paper.inertia_cm_kgm2 / exact.inertia_cm_kgm2 - 1) * 100,
                      "I_knob change (%)": (exact.inertia_knob_kgm2 / R161.inertia_knob_kgm2 - 1) * 100})
        fixed_s = hittable_sweet_spot(exact, SWING.u0_mps, SWING.omega0_radps)
        row = {"fill": fill, "depth (in)": depth,
               "same swing": v1_at(exact, fixed_s, SWING.u0_mps, SWING.omega0_radps)}
        for m in SwingModel:
            u0, w0, s, v1 = model_v1(exact, m)
            row[MODEL_LABEL[m.value]] = v1
            if depth == 10:
                eng = engine_v1(exact, s, u0, w0)
                checks.append({"bat": f"{fill} 1x10 in", "model": m.value, "analytic v1": v1,
                               **{f"{n} - analytic": eng[n] - v1 for n in eng}})
        speeds.append(row)
    props, speeds, checks = pd.DataFrame(props), pd.DataFrame(speeds), pd.DataFrame(checks)
    wood_row = pd.DataFrame([{"fill": "none (wood)", "depth (in)": 0,
                              "same swing": wood[SwingModel.CONSTANT_FORCE],
                              **{MODEL_LABEL[m.value]: wood[m] for m in SwingModel}}])
    speeds = pd.concat([wood_row, speeds], ignore_index=True)
    cork10 = speeds[(speeds.fill == "cork") & (speeds["depth (in)"] == 10)].iloc[0]
    deltas = {m: cork10[MODEL_LABEL[m.value]] - wood[m] for m in SwingModel}
    worst = float(checks[[c for c in checks.columns if "analytic" in c and "-" in c]].abs().max().max())
    text = f"""## 2. Does corking help, and why is it banned?

A 1 in (25.4 mm) hole 6, 8 or 10 in deep drilled into the barrel end and filled with cork
(200 kg/m^3), rubber (1100 kg/m^3) or left hollow, in wood of 640 kg/m^3
(`analytic.corked_bat`, exact: the cylinder's own r^2/4 + h^2/12 and parallel axes about the new
COM). The paper's formula (`corked_bat_paper`) adds (M + dM) R^2 where it must subtract it and drops
dM r^2/4, so its J_cm is too large by 2 (M + dM) R^2 - dM r^2/4:

{md_table(props, "{:.4g}")}

Batted-ball speed at each bat's sweet spot (m/s; pitch 46.9 m/s, e = 0.5), with the same swing as
the wood bat and under each swing model carried over from the paper's R161 swing
(u0 = 17.87 m/s, omega0 = 32 rad/s):

{md_table(speeds, "{:.2f}")}

- **Same swing**: corking always lowers v1 (less mass behind the impact), as the paper found.
- **Paper's model** (u0 ~ 1/M at fixed omega0): the lighter bat's COM is faster and the 1 x 10 in
  cork bat gains {deltas[SwingModel.CONSTANT_FORCE]:+.2f} m/s, the paper's verdict.
- **Constant torque** (omega0 ~ I_knob^-1/2): {deltas[SwingModel.CONSTANT_TORQUE]:+.2f} m/s.
- **Measured scaling** (omega0 ~ I_knob^-0.27, [crossbower]): {deltas[SwingModel.MEASURED]:+.2f} m/s.

The evidence supports the measured model: swing speed follows the swing weight with n = 0.25-0.27
[crossbower], not the mass with n = 1, and the one controlled experiment found that a corked
bat does not hit the ball farther [nathan2011]. **Verdict: corking does not raise the batted-ball
speed** (it lowers it by {-deltas[SwingModel.MEASURED]:.2f} m/s for a 1 x 10 in cork fill under
the measured scaling); what it buys is a lighter, quicker bat ({(bats[('cork', 10)][0].inertia_knob_kgm2 / R161.inertia_knob_kgm2 - 1) * 100:.1f}% swing weight)
that a batter can start later and control better. MLB bans it as an illegal alteration of the
bat; the physics says the batter gains control, not distance. Only the paper's 1/M model makes
corking pay, and that model is the one the data reject.

All three engines reproduce these v1 values (reference profile, 1 x 10 in holes; engine -
analytic, m/s): worst {worst:.1e} m/s.

{md_table(checks, "{:.3g}")}

![corked bats](findings_cork.png)
"""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 3, figsize=(14, 4.5), sharey=True, layout="constrained")
    for ax, m in zip(axes, SwingModel):
        for fill in FILLS:
            d = speeds[speeds.fill == fill]
            ax.plot([0, *d["depth (in)"]], [wood[m], *d[MODEL_LABEL[m.value]]], "o-", label=fill)
        ax.axhline(wood[m], color="k", lw=0.8, ls=":")
        ax.set_title(MODEL_LABEL[m.value], fontsize=9)
        ax.set_xlabel("hole depth (in), 1 in diameter")
        ax.grid(alpha=0.3)
    axes[0].set_ylabel("v1 at the sweet spot (m/s)")
    axes[0].legend(title="fill", fontsize=8)
    fig.suptitle("Corked R161: batted-ball speed under each swing model (dotted: the solid bat)",
                 fontsize=10)
    return text, {"findings_cork.png": fig}, {"deltas": deltas, "bats": bats}


# -- 3. metal vs wood ----------------------------------------------------------------------------

def metal_section():
    es = (0.50, 0.55, 0.60)
    rows, checks = [], []
    for m in SwingModel:
        for label, bat in (("R161 wood", R161), ("Easton 31 in aluminium", AL)):
            sw = swing_for(bat, model=m, reference_bat=R161, reference=SWING)
            s = hittable_sweet_spot(bat, sw.u0_mps, sw.omega0_radps)
            row = {"swing model": m.value, "bat": label, "u0 m/s": sw.u0_mps,
                   "omega0 rad/s": sw.omega0_radps}
            for e in (es if bat is AL else (0.50,)):
                v1 = v1_at(bat, s, sw.u0_mps, sw.omega0_radps, e=e)
                row[f"v1 at e={e:.2f}"] = v1
                row[f"time to mound at e={e:.2f} (s)"] = MOUND_M / v1
            if bat is AL:
                eng = engine_v1(bat, s, sw.u0_mps, sw.omega0_radps)
                v1 = row["v1 at e=0.50"]
                checks.append({"model": m.value, "analytic v1": v1,
                               **{f"{n} - analytic": eng[n] - v1 for n in eng}})
            rows.append(row)
    table = pd.DataFrame(rows)
    checks = pd.DataFrame(checks)
    worst = float(checks[[c for c in checks.columns if "-" in c]].abs().max().max())

    def v(model, bat, e="0.50"):
        return float(table[(table["swing model"] == model) & (table.bat == bat)][f"v1 at e={e}"].iloc[0])

    def shifted(frac: float) -> float:
        """v1 at the sweet spot, measured model, e = 0.5, with the assumed COM moved."""
        bat = replace(AL, com_from_knob_m=frac * AL.length_m)
        return model_v1(bat, SwingModel.MEASURED)[3] - model_v1(R161, SwingModel.MEASURED)[3]

    sens = {f: shifted(f) for f in (0.55, 0.60, 0.65)}

    text = f"""## 3. Why are metal bats banned?

The Easton 31 in, 28 oz aluminium bat (0.794 kg, J_cm 0.0205 kg m^2 as the paper gives it; COM
at 60% of the length, assumed) against the R161, both carried over from the paper's R161 swing,
and with a livelier ball-bat collision for the hollow metal barrel (the trampoline effect: an
effective e above wood's 0.50; BBCOR now caps it at 0.50 [bbcor]). Time to the mound = 18.44 m /
v1 [rules] (no drag, as the paper assumes).

{md_table(table, "{:.3f}")}

- At the same e = 0.50, the aluminium bat hits **{v('constant_force', 'Easton 31 in aluminium') - v('constant_force', 'R161 wood'):+.2f} m/s**
  under the paper's model, **{v('constant_torque', 'Easton 31 in aluminium') - v('constant_torque', 'R161 wood'):+.2f}** under constant torque and
  **{v('measured', 'Easton 31 in aluminium') - v('measured', 'R161 wood'):+.2f}** under the measured scaling: a lighter bat alone does not make it
  more dangerous. Its small J_cm puts its sweet spot close to its COM, where a light bat has
  little effective mass.
- What makes a metal bat livelier is the **trampoline effect**: at e = 0.55 it gains
  {v('measured', 'Easton 31 in aluminium', '0.55') - v('measured', 'Easton 31 in aluminium'):+.2f} m/s and at e = 0.60
  {v('measured', 'Easton 31 in aluminium', '0.60') - v('measured', 'Easton 31 in aluminium'):+.2f} m/s (measured model), which moves the
  ball to the mound in {MOUND_M / v('measured', 'Easton 31 in aluminium', '0.60'):.3f} s
  instead of {MOUND_M / v('measured', 'R161 wood'):.3f} s. That is why the rules cap the ball-bat
  COR (BBCOR 0.50) rather than the bat's mass; MLB keeps wood.
- The aluminium bat's COM is assumed (no source gives it): at 55%, 60% or 65% of the length the
  measured-model difference to wood is {sens[0.55]:+.2f}, {sens[0.60]:+.2f} or {sens[0.65]:+.2f} m/s;
  the conclusion (no gain from lightness at equal e) holds across that range.
- The pitcher's reaction time: all of these times stay above the paper's 0.4 s threshold for a
  46.9 m/s pitch; only a livelier collision (e near 0.6) brings the time close to it.

All three engines reproduce the aluminium bat's v1 (e = 0.50; engine - analytic, m/s): worst
{worst:.1e} m/s.

{md_table(checks, "{:.3g}")}

![metal vs wood](findings_metal.png)
"""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 3, figsize=(14, 4.5), sharey=True, layout="constrained")
    for ax, m in zip(axes, SwingModel):
        for bat, color in ((R161, "tab:brown"), (AL, "tab:gray")):
            sw = swing_for(bat, model=m, reference_bat=R161, reference=SWING)
            s = np.linspace(bat.s_min_m + 0.25, bat.s_max_m, 200)
            dist = (bat.s_barrel_end_m - s) * 100
            for e, ls in ((0.5, "-"), (0.6, "--")) if bat is AL else ((0.5, "-"),):
                ax.plot(dist, batted_ball_speed(bat, BALL, s, v0_mps=PITCH, u0_mps=sw.u0_mps,
                                                omega0_radps=sw.omega0_radps, e=e), ls,
                        color=color, label=f"{'aluminium' if bat is AL else 'R161 wood'}, e = {e}")
        ax.set_title(MODEL_LABEL[m.value], fontsize=9)
        ax.set_xlabel("impact point, distance from the barrel end (cm)")
        ax.invert_xaxis()
        ax.grid(alpha=0.3)
    axes[0].set_ylabel("batted-ball speed v1 (m/s)")
    axes[0].legend(fontsize=8)
    fig.suptitle("Wood vs aluminium along the barrel under each swing model, pitch 46.9 m/s",
                 fontsize=10)
    return text, {"findings_metal.png": fig}, {"table": table}


# -- 4. audit ------------------------------------------------------------------------------------

def audit_section(sweet: dict, cork: dict, metal: dict) -> str:
    from scipy import optimize

    end = R161.s_barrel_end_m
    pr = sweet["paper_region"]
    case = ImpactCase(bat=R161, ball=BALL, s_m=0.1, v0_mps=PITCH, u0_mps=SWING.u0_mps,
                      omega0_radps=SWING.omega0_radps, e=E, theta_rad=math.radians(20))
    out = predict(case)
    exact, paper = cork["bats"][("cork", 10)]
    wood_v1 = model_v1(R161, SwingModel.CONSTANT_FORCE)[3]
    al = swing_for(AL, model=SwingModel.CONSTANT_FORCE, reference_bat=R161, reference=SWING)
    al_s = hittable_sweet_spot(AL, al.u0_mps, al.omega0_radps)
    al_v1 = v1_at(AL, al_s, al.u0_mps, al.omega0_radps)
    light = replace(BALL, mass_kg=0.14)  # the paper's "0.14 kg" ball
    s_light = analytic.hittable_sweet_spot(R161, light, PITCH, SWING.u0_mps, SWING.omega0_radps)
    wood_v1_light = float(batted_ball_speed(R161, light, s_light, v0_mps=PITCH,
                                            u0_mps=SWING.u0_mps, omega0_radps=SWING.omega0_radps,
                                            e=E))
    region_light = sweet_region(R161, light, v0_range_mps=(40.2, 46.9), u0_range_mps=(0.0, 17.87),
                                omega0_range_radps=(12.0, 32.0))
    e_needed = optimize.brentq(lambda e: v1_at(AL, al_s, al.u0_mps, al.omega0_radps, e=e) - 42.59,
                               0.0, 1.0)

    def al_v1_with(inertia: float) -> float:
        bat = replace(AL, inertia_cm_kgm2=inertia)
        return v1_at(bat, hittable_sweet_spot(bat, al.u0_mps, al.omega0_radps), al.u0_mps,
                     al.omega0_radps) - 42.59

    j_ratio = optimize.brentq(al_v1_with, AL.inertia_cm_kgm2, 50 * AL.inertia_cm_kgm2) \
        / AL.inertia_cm_kgm2
    d_pivot = SWING.u0_mps / SWING.omega0_radps
    hands_u0 = SWING.omega0_radps * HingedSwing(torque_nm=1.0, hands_from_knob_m=HANDS_M).arm_m(R161)
    paper_oblique = predict_oblique_paper(case)
    rows = [
        ("COP: s - d = J/(M d) for a pivot at the hands (eq. 5.2.2)",
         "reproduced",
         f"formula right; R161, hands 0.1 m: COP {sweet['cop_mm']:.1f} mm from the COM, "
         f"{(end - sweet['cop_mm'] / 1e3) * 100:.1f} cm from the end. The paper's own bat table "
         "(0.055 / 0.057 m) lost its data in the text and cannot be rechecked."),
        ("Sweet spot at most 0.118 m from the COM (v_r 40.2-64.77 m/s, omega0 12-32 rad/s)",
         "reproduced within 5 mm",
         f"{pr.s_max_m * 1e3:.1f} mm with a 0.145 kg ball, {region_light.s_max_m * 1e3:.1f} mm with "
         f"the paper's 0.14 kg: at most {(end - pr.s_max_m) * 100:.1f} cm from the barrel end, so "
         "not the end, as the paper says; its 0.118 m matches neither ball exactly"),
        ("The sweet spot is a region, not a point", "reproduced",
         f"{pr.s_min_m * 1e3:.0f}-{pr.s_max_m * 1e3:.0f} mm over the paper's ranges; "
         f"{sweet['region_mm'][0]:.0f}-{sweet['region_mm'][1]:.0f} mm for swings from the hands, "
         "pitch 35-47 m/s, 12-47 rad/s"),
        ("omega0 = 0 puts the sweet spot at the COM; faster pitches move it toward the COM",
         "reproduced", "s* = 0 exactly at omega0 = 0; ds*/dA < 0 (tests check both)"),
        ("Oblique impact: the ball leaves at its incoming angle theta", "corrected",
         f"frictionless: the tangential velocity is kept and the normal one reversed with e, so "
         f"theta = 20 deg leaves at {math.degrees(out.theta1_rad):.1f} deg (s = 0.1 m, the "
         f"paper's swing) with {out.ball_speed_mps:.2f} m/s; the paper's eq. 6.4.2 gives "
         f"{paper_oblique.v1_mps:.2f} m/s at 20 deg, adding a tangential impulse "
         "m(v0+v1) r sin theta that a frictionless contact cannot give"),
        ("Corked bat: J' = J + (M + dM) R^2 + dJ0 (eq. 7.1.4)", "corrected",
         f"parallel axes about the new COM subtract (M + dM) R^2, and the cylinder's own dM r^2/4 "
         f"is missing: for 1 x 10 in cork the paper's J' is {paper.inertia_cm_kgm2:.5f} vs exact "
         f"{exact.inertia_cm_kgm2:.5f} kg m^2 ({(paper.inertia_cm_kgm2 / exact.inertia_cm_kgm2 - 1) * 100:+.2f}%)"),
        ("'Corking enhances the sweet spot effect' (batted speed up)", "corrected",
         f"true only under its u0 ~ 1/M swing ({cork['deltas'][SwingModel.CONSTANT_FORCE]:+.2f} m/s "
         f"for 1 x 10 in cork); under the measured swing-weight scaling it costs "
         f"{cork['deltas'][SwingModel.MEASURED]:+.2f} m/s, in line with experiment [nathan2011]"),
        ("u0 = 17.87 m/s and omega0 = 32 rad/s chosen independently", "corrected",
         f"together they mean the bat turns about a point {(R161.com_from_knob_m - d_pivot) * 1e3:.1f} mm "
         f"from the knob; a swing from the hands ({HANDS_M} m) at 32 rad/s gives u0 = "
         f"{hands_u0:.2f} m/s "
         "(`python -m experiments.sweep --swing` simulates it)"),
        ("Metal 42.59 m/s vs wood 38.57 m/s at the sweet spot", "not reproduced",
         f"with the paper's own data and swing (u0 = {al.u0_mps:.2f} m/s for the "
         f"{AL.mass_kg:.3f} kg bat, "
         f"omega0 = 32 rad/s, e = 0.5): aluminium {al_v1:.2f}, wood {wood_v1:.2f} m/s (the "
         f"paper's 0.14 kg ball gives {wood_v1_light:.2f} for wood, near its 38.57). Reaching "
         f"42.59 needs e = {e_needed:.3f} for the metal bat (a trampoline effect the paper never "
         f"states) or a J_cm {j_ratio:.1f} times the stated 70 lb in^2"),
        ("Time to the pitcher 0.433 s (metal) vs 0.478 s (wood)", "corrected",
         f"18.44 m / v1: {MOUND_M / al_v1:.3f} s vs {MOUND_M / wood_v1:.3f} s with our v1; the "
         "paper's times follow from its v1 values, which do not follow from its bat data"),
        ("A lighter bat is swung faster, so metal bats are more dangerous", "corrected",
         "with the same e the aluminium bat is no faster off the bat under the swing-weight "
         "models; the danger is the livelier (higher-e) collision, which is what BBCOR limits"),
    ]
    table = pd.DataFrame(rows, columns=["the paper's claim", "verdict", "our value and why"])
    return "## 4. Audit of the paper\n\n" + md_table(table) + "\n"


def build_parser() -> argparse.ArgumentParser:
    from . import _cli

    p = _cli.Parser(prog="python -m experiments.findings", description=__doc__.splitlines()[0])
    _cli.add_output(p)
    return p


def main(argv: list[str] | None = None) -> int:
    from . import _cli

    return _cli.run_command(build_parser(), argv, "findings", produce)


def produce(args: argparse.Namespace) -> tuple[dict[str, bytes], str]:
    """The report and its charts."""
    sweet_text, sweet_figs, sweet = sweet_spot_section()
    cork_text, cork_figs, cork = cork_section()
    metal_text, metal_figs, metal = metal_section()
    audit = audit_section(sweet, cork, metal)
    refs = "## References\n\n" + "\n".join(f"- [{k}] {v}" for k, v in REFS.items()) + "\n"
    prov = provenance()
    head = f"""# Findings: the paper's questions answered by the harness

Generated by `python -m experiments.findings` (commit {prov['commit'][:10]}). R161 and ball as in
`analytic.presets` [cross2009] [rules]; pitch 46.9 m/s and the paper's swing (u0 = 17.87 m/s,
omega0 = 32 rad/s), e = 0.5, unless stated. Engine checks use the reference profile.

**Short answers.** The sweet spot is a region about {(R161.s_barrel_end_m - sweet['region_mm'][1] / 1e3) * 100:.0f}-{(R161.s_barrel_end_m - sweet['region_mm'][0] / 1e3) * 100:.0f} cm
from the barrel end that moves with the swing and pitch. Corking does not raise the batted-ball
speed under the swing scaling that measurements support ({cork['deltas'][SwingModel.MEASURED]:+.2f} m/s for a 1 x 10 in cork fill);
it only pays under the paper's u0 ~ 1/M assumption. Metal bats are dangerous through a livelier
collision (higher effective e), not through lightness; hence the BBCOR 0.50 cap. The paper's
corking inertia, oblique-impact angle, metal-bat speeds and reaction times are wrong (section 4).

"""
    import matplotlib.pyplot as plt

    figs = {**sweet_figs, **cork_figs, **metal_figs}
    files = {name: figure_png(fig) for name, fig in figs.items()}
    for fig in figs.values():
        plt.close(fig)
    body = head + "\n".join([sweet_text, cork_text, metal_text, audit, refs])
    files["findings.md"] = body.encode()
    for eng in _ENGINES.values():
        eng.close()
    _ENGINES.clear()
    return files, f"findings.md and {len(figs)} charts"


if __name__ == "__main__":
    sys.exit(main())
