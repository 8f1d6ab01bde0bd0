"""Section 4 of findings.md: the ball as it really is. Its COR against impact speed, an assumed
power law through the published statements with the range it carries (``analytic.ball``), the
realistic ball's contact on a still bat, and how far rigid theory at e = 0.5 lies from it along
the barrel for both swings, over that range.
"""

from __future__ import annotations

from dataclasses import replace
from typing import TYPE_CHECKING

import numpy as np
import pandas as pd

from analytic import ImpactCase, ball, compliant, predict

from . import answers as A
from .report import Section, along_the_barrel, md_table, pyplot

if TYPE_CHECKING:
    from matplotlib.figure import Figure

LAW = ball.REALISTIC_BALL
#: the impact speeds of the realistic ball's table (m/s)
BALL_SPEEDS_MPS = (10.0, 20.0, 25.9, 30.0, 40.0, 50.0, 60.0, 70.0, 80.0)
#: impact points along the barrel for each of the COR law's corner laws: their extremes (at
#: the barrel's ends) match 41 points' to 0.003 m/s, at half the cost
CORNER_POINTS = 21
#: the MLB specification's band at 25.9 m/s [mlbcor]
MLB_BAND = (0.514, 0.578)
#: the ball section's table of rigid theory against the realistic ball, as the text has it
BALL_COLUMNS = (
    "swing",
    "rigid (e = 0.5) - realistic v1, along the barrel (m/s)",
    "the same over the COR law's range (m/s)",
    "of which finite contact time (m/s)",
    "ball's COR at the closing speed",
    "contact (ms)",
    "bat turns (mrad)",
)


def cor_data_table() -> pd.DataFrame:
    """The published statements, each against the central law."""
    law = LAW.cor_law
    return pd.DataFrame(
        [
            {
                "impact speed (m/s)": p.speed_mps,
                "COR": p.cor,
                "+-": p.half_width if not p.qualitative else float("nan"),
                "kind": p.kind,
                "qualitative": p.qualitative,
                "source": f"[{p.source}]",
                "what it is": p.note,
                "central law": law.cor(p.speed_mps),
            }
            for p in ball.COR_DATA
        ]
    )


def ball_cor_curve(speeds_mps: tuple[float, ...] = BALL_SPEEDS_MPS) -> pd.DataFrame:
    """The realistic ball against a still R161 at its COM: COR, contact time, peak force and
    compression against impact speed (integrated, ``compliant.predict``)."""
    rows = []
    for v in speeds_mps:
        out = compliant.predict(ImpactCase(bat=A.R161, ball=A.BALL, s_m=0.0, v0_mps=v, e=A.E), LAW)
        rows.append(
            {
                "impact speed (m/s)": v,
                "COR": LAW.restitution(v),
                "COR, old Hertz law": compliant.BASEBALL_HERTZ.restitution(v),
                "contact time (ms)": out.contact_duration_s * 1e3,
                "peak force (kN)": out.peak_force_n / 1e3,
                "compression (mm)": out.peak_penetration_m * 1e3,
            }
        )
    return pd.DataFrame(rows)


def rigid_vs_compliant(sc: A.Scenario, points: int = 41, law: ball.CorBall = LAW) -> pd.DataFrame:
    """Along the R161's barrel half for one swing: rigid v1 (e = 0.5), the realistic ball's
    (``law``'s) v1, rigid v1 at the ball's own COR at that closing speed, contact time and the
    bat's turn."""
    rows = []
    for s in np.linspace(0.0, A.R161.s_max_m, points):
        case = ImpactCase(
            bat=A.R161,
            ball=A.BALL,
            s_m=float(s),
            v0_mps=sc.v0_mps,
            u0_mps=sc.swing.u0_mps,
            omega0_radps=sc.swing.omega0_radps,
            e=A.E,
        )
        out = compliant.predict(case, law)
        e_law = law.restitution(case.closing_speed_mps)
        rows.append(
            {
                "s_m": float(s),
                "closing_mps": case.closing_speed_mps,
                "e_law": e_law,
                "v1_rigid_mps": predict(case).v1_mps,
                "v1_compliant_mps": out.v1_mps,
                "v1_rigid_at_e_law_mps": predict(replace(case, e=e_law)).v1_mps,
                "contact_s": out.contact_duration_s,
                "bat_turn_rad": out.bat_turn_rad,
            }
        )
    return pd.DataFrame(rows)


def ball_section() -> Section:
    """Section 4: the ball's COR law and its range, its contact, and rigid theory against it."""
    data, cor = cor_data_table(), ball_cor_curve()
    runs = {sc.key: rigid_vs_compliant(sc) for sc in A.SCENARIOS}
    corners = {
        sc.key: [rigid_vs_compliant(sc, CORNER_POINTS, ball.ball_of(c)) for c in ball.COR_LAWS]
        for sc in A.SCENARIOS
    }
    summary = {k: {**_summary(r), **_range(corners[k])} for k, r in runs.items()}
    law = LAW.cor_law
    regime = (
        min(r["closing lo"] for r in summary.values()),
        max(r["closing hi"] for r in summary.values()),
    )
    stats = {
        **summary,
        "cor_25.9": law.cor(25.9),
        "cor_60": law.cor(60.0),
        "cor_60_range": ball.cor_range(60.0),
        "exponent": law.exponent,
        "regime_mps": regime,
        "regime_cor": (law.cor(regime[1]), law.cor(regime[0])),
        "regime_range": (ball.cor_range(regime[1])[0], ball.cor_range(regime[0])[1]),
    }
    text = "\n".join(
        [
            _law_text(data, cor, stats),
            _table_text(summary),
            _verdict_text(summary),
            "![the realistic ball](findings_ball.png)\n",
        ]
    )
    return text, {"findings_ball.png": _figure(data, cor, runs, corners)}, stats


def _summary(r: pd.DataFrame) -> dict[str, float]:
    """The extremes of one swing's ``rigid_vs_compliant`` table (m/s, ms, mrad)."""
    diff = r.v1_rigid_mps - r.v1_compliant_mps
    return {
        "diff lo": float(diff.min()),
        "diff hi": float(diff.max()),
        "finite-time max": float((r.v1_rigid_at_e_law_mps - r.v1_compliant_mps).abs().max()),
        "e lo": float(r.e_law.min()),
        "e hi": float(r.e_law.max()),
        "closing lo": float(r.closing_mps.min()),
        "closing hi": float(r.closing_mps.max()),
        "t lo": float(r.contact_s.min() * 1e3),
        "t hi": float(r.contact_s.max() * 1e3),
        "turn": float(r.bat_turn_rad.max() * 1e3),
    }


def _range(corners: list[pd.DataFrame]) -> dict[str, float]:
    """The rigid-minus-realistic extremes over the COR law's corner laws (m/s)."""
    diffs = [r.v1_rigid_mps - r.v1_compliant_mps for r in corners]
    return {
        "range lo": float(min(d.min() for d in diffs)),
        "range hi": float(max(d.max() for d in diffs)),
    }


def _law_text(data: pd.DataFrame, cor: pd.DataFrame, stats: dict) -> str:
    """The published statements, the assumed law and its range, the realistic ball's contact."""
    law, lo60, hi60 = LAW.cor_law, *stats["cor_60_range"]
    (v_lo, v_hi), (e_lo, e_hi), (r_lo, r_hi) = (
        stats["regime_mps"],
        stats["regime_cor"],
        stats["regime_range"],
    )
    return f"""## 4. The ball as it really is

Every answer above takes the ball-bat COR as 0.5 whatever the speed and the contact as
instantaneous. A baseball's COR falls as the impact speed rises [sawicki2003] [shenoy2001], and
the contact lasts about 0.6-1 ms [nathan2000], during which the bat turns. What is published
about a major-league ball's COR is one test speed and one qualitative statement:

{md_table(data.drop(columns="qualitative"), "{:.4g}")}

No table of the COR against speed could be read, so **the speed dependence is an assumption**:
a power law e(v) = e_ref (v / 25.9 m/s)^-p through MLB's centre and Nathan's 0.5 at 50 m/s,
**e_ref = {law.cor_ref:.3f}, p = {law.exponent:.3f}** (`analytic.ball.COR_LAW`), and its range,
MLB's band {MLB_BAND[0]}-{MLB_BAND[1]} at 25.9 m/s [mlbcor] times p from 0 (no fall) to 1/4
(elastic-plastic impact [johnson1985]) (`COR_LAWS`). At 60 m/s that is **{law.cor(60.0):.3f}
({lo60:.2f}-{hi60:.2f})**; at the two swings' closing speeds, {v_lo:.0f}-{v_hi:.0f} m/s,
**{e_lo:.3f}-{e_hi:.3f} ({r_lo:.2f}-{r_hi:.2f})**. The BBCOR cap, 0.50 at 60.8 m/s on a still
bat [ncaa], includes the bat's recoil and vibration: shown, not used.
The realistic ball (`analytic.ball.REALISTIC_BALL`, the default of `--law`) is a Hertz contact
whose damping is set at each impact's closing speed so that it bounces with exactly this e, its
stiffness set for 0.7 ms on a wall at 40 m/s. On a still R161 at its COM (beside it the
single-damping Hertz law it replaces, whose COR fell too fast: 0.61 at 25.9 m/s, 0.39 at 60):

{md_table(cor, "{:.3f}")}
"""


def _table_text(summary: dict[str, dict[str, float]]) -> str:
    """Rigid theory against the realistic ball, one row per swing."""
    head = ["| " + " | ".join(BALL_COLUMNS) + " |", "|" + "---|" * len(BALL_COLUMNS)]
    rows = [
        f"| {label} | {r['diff lo']:+.2f} to {r['diff hi']:+.2f} | "
        f"{r['range lo']:+.1f} to {r['range hi']:+.1f} | {r['finite-time max']:.3f} | "
        f"{r['e lo']:.3f}-{r['e hi']:.3f} | "
        f"{r['t lo']:.2f}-{r['t hi']:.2f} | {r['turn']:.1f} |"
        for label, r in (("paper's", summary["paper"]), ("MLB-like", summary["mlb"]))
    ]
    return (
        "Along the barrel (COM to end), rigid theory with e = 0.5 against the realistic "
        "ball:\n\n" + "\n".join(head + rows) + "\n"
    )


def _verdict_text(summary: dict[str, dict[str, float]]) -> str:
    """What the difference is made of, and what it means for the answers above."""
    lo = min(r["diff lo"] for r in summary.values())
    hi = max(r["diff hi"] for r in summary.values())
    r_lo = min(r["range lo"] for r in summary.values())
    r_hi = max(r["range hi"] for r in summary.values())
    finite = max(r["finite-time max"] for r in summary.values())
    turn = max(r["turn"] for r in summary.values())
    return f"""\
Rigid theory at e = 0.5 lies **{lo:+.1f} to {hi:+.1f} m/s** from the realistic ball along the
barrel under the central law, where the COR at 50-80 m/s is a little below 0.5, and
**{r_lo:+.0f} to {r_hi:+.0f} m/s** over the law's range: the sign itself rests on the assumed
speed dependence. Almost all of it
is the COR: rigid theory at the ball's own COR comes within {finite:.3f} m/s of the
integrated contact, though the bat turns by up to {turn:.0f} mrad meanwhile. So the rigid
answers above (sweet spot, corking, metal) hold as comparisons at one e, and their absolute
speeds are high by the amount the ball's COR at the closing speed falls below 0.5; with a COR
that falls faster or slower they move with it (`python -m experiments.sweep --reference
compliant` puts both along any bat; `--law hysteretic` the rate-independent ball,
`--law hertz` the superseded law).
"""


def _figure(
    data: pd.DataFrame,
    cor: pd.DataFrame,
    runs: dict[str, pd.DataFrame],
    corners: dict[str, list[pd.DataFrame]],
) -> Figure:
    """The statements, the central law and its range; rigid against realistic v1 along the
    barrel, the realistic ball's band over the range."""
    plt = pyplot()
    law = LAW.cor_law
    fig, (ax, ax2) = plt.subplots(1, 2, figsize=(14, 5.2), layout="constrained")
    v = np.linspace(8.0, 82.0, 300)
    ax.fill_between(
        v,
        *zip(*[ball.cor_range(x) for x in v]),
        color="tab:blue",
        alpha=0.15,
        label="assumed range: MLB band x p = 0..1/4",
    )
    ax.plot(
        v,
        [law.cor(x) for x in v],
        "-",
        color="tab:blue",
        label=f"central law: {law.cor_ref:.3f} (v/25.9)^-{law.exponent:.3f}",
    )
    ax.plot(
        cor["impact speed (m/s)"],
        cor["COR, old Hertz law"],
        "--",
        color="0.5",
        label="old Hertz law (superseded)",
    )
    for kind, marker, color in (("ball-wall", "o", "k"), ("ball-bat", "D", "tab:red")):
        d = data[(data.kind == kind) & ~data.qualitative]
        ax.errorbar(
            d["impact speed (m/s)"],
            d["COR"],
            yerr=d["+-"],
            fmt=marker,
            color=color,
            capsize=4,
            label=f"measured / specified, {kind}" + (" (not used)" if kind == "ball-bat" else ""),
        )
    for p in (q for q in ball.COR_DATA if q.qualitative):
        lo, hi = p.speed_mps - p.speed_half_width_mps, p.speed_mps + p.speed_half_width_mps
        ax.plot([lo, hi], [p.cor, p.cor], ":", color="k", lw=2.5, label="qualitative statement")
        ax.annotate(
            f"'about {p.cor:g}' at {lo:g}-{hi:g} m/s [{p.source}]:\nqualitative, not a "
            "measurement;\nthe central law is chosen through it",
            (p.speed_mps, p.cor),
            xytext=(lo - 8, p.cor + 0.13),
            fontsize=7.5,
            arrowprops={"arrowstyle": "-", "color": "0.4"},
        )
    ax.set_xlabel("impact speed (m/s)")
    ax.set_ylabel("coefficient of restitution")
    ax.set_title("baseball COR vs impact speed: statements, assumed law and range", fontsize=9)
    ax.legend(fontsize=7.5)
    ax.grid(alpha=0.3)
    for sc, color in zip(A.SCENARIOS, ("tab:blue", "tab:red")):
        r = runs[sc.key]
        d = A.from_end_cm(A.R161, r.s_m)
        ax2.plot(d, r.v1_rigid_mps, "-", color=color, label=f"{sc.label}: rigid, e = 0.5")
        ax2.plot(d, r.v1_compliant_mps, "--", color=color, label=f"{sc.label}: realistic ball")
        v1 = np.array([c.v1_compliant_mps for c in corners[sc.key]])
        ax2.fill_between(
            A.from_end_cm(A.R161, corners[sc.key][0].s_m),
            v1.min(axis=0),
            v1.max(axis=0),
            color=color,
            alpha=0.12,
            label=f"{sc.label}: over the COR law's range",
        )
    along_the_barrel(ax2, "rigid theory vs the realistic ball along the barrel")
    return fig
