"""Every quantitative claim of the findings, with the command that computes it, what it depends
on, and its source: the short answers quote these values and nothing else, the referee section
tabulates them, and tests/test_findings_claims.py recomputes them and checks every number the
README's findings section and findings.md's short answers quote against them.

A claim's value is a string, formatted as the text quotes it, so that a quoted number and the
computed one compare as text.
"""

from __future__ import annotations

from dataclasses import dataclass

import pandas as pd

from analytic import MEASURED_EXPONENT, WOOD_DENSITY_KGM3, ball
from analytic.cork import corked_bat

from . import answers as A
from . import carry as C
from . import metal as M
from .report import Stats, md_table, ranged

FINDINGS = "python -m experiments.findings"
#: White ash's specific gravity 0.55-0.67 [woodhandbook], as densities (kg/m^3).
WOOD_RANGE_KGM3 = (550.0, 670.0)
RIGID = "rigid-bat model (e, swing)"


@dataclass(frozen=True, kw_only=True)
class Claim:
    """One number the findings state: ``key``, what it is (``statement``), the ``value`` as
    quoted, the ``command`` (and function) that computes it, what it ``depends`` on, and its
    ``source`` (a reference key for an input, or 'computed')."""

    key: str
    statement: str
    value: str
    command: str
    depends: str
    source: str = "computed"


def _carry_change(key: str, bat: str, model: str, e: float = A.E) -> str:
    """The change in carry (m) of one bat's row of ``carry.bat_table``, signed, with its least
    and most over the drag and lift corners, in the figures that range allows."""
    t = C.bat_table(A.MLB if key == "mlb" else A.PAPER)
    r = t[(t.bat == bat) & (t["swing model"] == model) & (t.e == e)].iloc[0]
    lo, hi = (float(x) for x in r["change over spread (m)"].split(" to "))
    return ranged(float(r["change (m)"]), lo, hi, "+")


def _lively_carry() -> tuple[float, float]:
    """The least and most (m) that e = 0.55 or 0.60 adds to the aluminium bat's carry at
    e = 0.5, over the swing models and both swings (``carry.bat_table``)."""
    gains = []
    for sc in A.SCENARIOS:
        t = C.bat_table(sc)
        al = t[t.bat == M.ALUMINIUM].set_index(["swing model", "e"])["carry (m)"]
        gains += [al[(m, e)] - al[(m, A.E)] for m, e in al.index if e != A.E]
    return min(gains), max(gains)


def input_claims() -> list[Claim]:
    """The inputs every answer rests on, with their sources."""
    return [
        Claim(
            key="input.e",
            statement="ball-bat COR of the rigid model (wood; BBCOR's cap)",
            value="0.5",
            command="analytic.presets.E_WOOD",
            depends="-",
            source="[ncaa] [nathan2000]",
        ),
        Claim(
            key="input.n",
            statement="measured swing-speed exponent, speed ~ I_knob^-n",
            value=f"{MEASURED_EXPONENT}",
            command="analytic.MEASURED_EXPONENT",
            depends="-",
            source="[crossbower]",
        ),
        Claim(
            key="input.torque",
            statement="constant-torque swing exponent",
            value="0.5",
            command="analytic.SwingModel.CONSTANT_TORQUE",
            depends="-",
            source="mechanics",
        ),
        Claim(
            key="input.cork",
            statement="the cork fill: a 1 in hole 10 in deep",
            value="1 x 10 in",
            command="answers.CORK_1x10",
            depends="-",
            source="the paper; [nathan2011]",
        ),
        Claim(
            key="input.equal",
            statement="metal bat of the R161's length at drop -3",
            value="33 in, 30 oz",
            command="metal.EQUAL_BAT",
            depends="-",
            source="[cross2009] length; [ncaa] drop",
        ),
        Claim(
            key="input.russell",
            statement="Russell's sweet region (cm from the end)",
            value="12.7-17.8",
            command="-",
            depends="-",
            source="[russell]",
        ),
        Claim(
            key="input.cor",
            statement="the ball's COR at 85 ft/s (MLB's band's centre)",
            value=f"{ball.COR_LAW.cor_ref:.3f}",
            command="analytic.ball.COR_LAW",
            depends="-",
            source="[mlbcor]",
        ),
        Claim(
            key="input.cor_exponent",
            statement="the COR's fall with speed, e ~ v^-p: p "
            "(assumed; no speed-resolved data read)",
            value="{:g}-{:g}".format(*ball.EXPONENT_RANGE),
            command="analytic.ball.COR_LAWS",
            depends="-",
            source="assumption; 1/4 [johnson1985]",
        ),
        Claim(
            key="input.wood",
            statement="the R161's wood density (kg/m^3), beam fit",
            value=f"{WOOD_DENSITY_KGM3:.0f}",
            command="analytic.WOOD_DENSITY_KGM3",
            depends="the profile's assumed barrel and knob",
            source="computed; [woodhandbook]",
        ),
    ]


def sweet_claims(sweet: Stats, flex: Stats | None) -> list[Claim]:
    """Where the sweet spot lies and how far its ball carries."""
    cmd = f"{FINDINGS} (section 1, answers.batting_region_cm / best_v1)"
    out = [
        Claim(
            key="sweet.batting",
            statement="sweet spot, batting swings (cm from the end)",
            value="{:.1f}-{:.1f}".format(*sweet["batting"]),
            command=cmd,
            depends="bat rate 40-56 rad/s, pivot knob or hands, pitch 35-47 m/s; not e",
        ),
        Claim(
            key="sweet.all",
            statement="sweet spot, the paper's rates 12-48 rad/s (cm)",
            value="{:.1f}-{:.1f}".format(*sweet["region"]),
            command=cmd,
            depends="the slow 12 rad/s end sets the far edge",
        ),
    ]
    for sc in A.SCENARIOS:
        best = C.sweet_spots(sc).best
        out += [
            Claim(
                key=f"sweet.{sc.key}",
                statement=f"best point, {sc.label} (cm)",
                value=f"{sweet['best_cm'][sc.key]:.1f}",
                command=cmd,
                depends="swing, pitch; not e",
            ),
            Claim(
                key=f"carry.{sc.key}",
                statement=f"longest carry, {sc.label} (m; range: C_D +-10%, C_L +-20%)",
                value=ranged(best.carry_m, *C.best_carry_range_m(sc)),
                command=f"{FINDINGS} (section 3b)",
                depends="undercut, e, spin, drag, lift",
                source="computed; drag and lift [nathancalc]",
            ),
            Claim(
                key=f"carry.wide.{sc.key}",
                statement=f"best undercut, 30 mm / 2.61 in barrel, {sc.label} (cm)",
                value=f"{100 * best.undercut_m:.2f} / "
                f"{100 * C.wide_barrel_best(sc).undercut_m:.2f}",
                command=f"{FINDINGS} (section 3b)",
                depends="the contact radius",
                source="computed; [rules]",
            ),
        ]
    share_cmd = f"{FINDINGS} (section 1, answers.russell_share)"
    out += [
        Claim(
            key="sweet.share",
            statement="batting swings whose sweet spot is in Russell's range (fine grid)",
            value=f"{A.russell_share():.0%}",
            command=share_cmd,
            depends=f"the grid: the default one gives {A.russell_share(fine=False):.0%}",
        )
    ]
    gains = [
        C.pitch_optima(sc).curveball.carry_m - C.pitch_optima(sc).fastball.carry_m
        for sc in A.SCENARIOS
    ]
    out += [
        Claim(
            key="curve.gain",
            statement="curveball carry over fastball (m): spin independence to rigid rolling",
            value=f"0 to {max(gains):+.1f}",
            command=f"{FINDINGS} (section 3b)",
            depends="outgoing spin's dependence on incoming",
            source="[nathan2012] [crossnathan2006]; rolling computed",
        )
    ]
    return out + (_flex_claims(flex) if flex else [])


def _flex_claims(flex: Stats) -> list[Claim]:
    """The flexible bat's: its first mode's node, its speed peak, its sign against the rigid."""
    m, cmd = flex["models"], f"{FINDINGS} (section 3c, flex_models)"
    return [
        Claim(
            key="flex.node",
            statement="beam: first mode's barrel node (cm)",
            value=f"{m['node_cm'][0]:.1f}",
            command=cmd,
            depends="robust: not the ball, E +-20% moves it < 0.1 cm",
            source="computed; E, G [woodhandbook]",
        ),
        Claim(
            key="flex.peak",
            statement="beam: speed peak over two ball models (cm)",
            value="{:.0f}-{:.0f}".format(*m["peak_cm"]),
            command=cmd,
            depends="the ball's law (rate-dependent or not); E +-20%: 1 cm",
        ),
        Claim(
            key="flex.sign",
            statement="beam minus rigid bat at the peak (m/s), two ball models",
            value="{:+.1f} to {:+.1f}".format(*m["beam_minus_rigid"]),
            command=cmd,
            depends="the ball's law",
        ),
    ]


def cork_claims(cork: Stats) -> list[Claim]:
    """What the 1 x 10 in cork fill gains or loses, in m/s (with its range over ash's densities)
    and in metres of carry (over the drag and lift corners)."""
    v = cork["verdicts"]
    cmd = f"{FINDINGS} (section 2, answers.cork_verdicts; carry: section 3b)"
    by_wood = [
        A.cork_verdicts(corked_bat(A.R161, wood_density_kgm3=rho)) for rho in WOOD_RANGE_KGM3
    ]
    dep = f"{RIGID}; wood {WOOD_RANGE_KGM3[0]:.0f}-{WOOD_RANGE_KGM3[1]:.0f} kg/m^3 [woodhandbook]"

    def gain(i: int, column: str) -> str:
        lo, hi = sorted(float(w[column].iloc[i]) for w in by_wood)
        return ranged(float(v[column].iloc[i]), lo, hi, "+")

    cork_bat, out = "R161, 1 x 10 in cork", []
    for i, sc in enumerate(A.SCENARIOS):
        row, k = v.iloc[i], sc.key
        out += [
            Claim(
                key=f"cork.n027.{k}",
                statement=f"cork v1 change at n = 0.27, {sc.label} (range: ash's density)",
                value=gain(i, "gain at n = 0.27 (m/s)"),
                command=cmd,
                depends=dep,
            ),
            Claim(
                key=f"cork.n05.{k}",
                statement=f"cork v1 change at n = 0.5, {sc.label}",
                value=gain(i, "gain at n = 0.5 (m/s)"),
                command=cmd,
                depends=dep,
            ),
            Claim(
                key=f"cork.even.{k}",
                statement=f"cork break-even n, {sc.label}",
                value=f"{row['break-even n']:.2f}",
                command=cmd,
                depends=f"{dep}: moves it < 0.002",
            ),
            Claim(
                key=f"cork.same.{k}",
                statement=f"cork, same swing (n = 0), {sc.label}",
                value=gain(i, "gain, same swing (n = 0, m/s)"),
                command=cmd,
                depends=dep,
            ),
            Claim(
                key=f"cork.carry027.{k}",
                statement=f"cork carry change, n = 0.27, {sc.label}",
                value=_carry_change(k, cork_bat, "measured"),
                command=cmd,
                depends=f"{RIGID}, drag and lift",
            ),
            Claim(
                key=f"cork.carry05.{k}",
                statement=f"cork carry change, n = 0.5, {sc.label}",
                value=_carry_change(k, cork_bat, "constant_torque"),
                command=cmd,
                depends=f"{RIGID}, drag and lift",
            ),
        ]
    return out


def metal_claims(metal: Stats) -> list[Claim]:
    """The metal bat at the paper's pairing, at equal length, and livelier."""
    cmd = f"{FINDINGS} (section 3, metal.bbcor_table / metal_table; carry: section 3b)"
    dep = f"{RIGID}, metal J_cm and COM (unsourced)"
    out = []
    for sc in A.SCENARIOS:
        k, b = sc.key, metal["bbcor"][sc.key]
        eq = b[b["metal bat"] == "33 in, 30 oz"].iloc[0]
        pair = M.gain_over_wood(metal["tables"][k], "measured")
        out += [
            Claim(
                key=f"metal.equal027.{k}",
                statement=f"33 in 30 oz metal - R161, n = 0.27, {sc.label}",
                value=f"{eq['gain over wood, measured (m/s)']:+.2f}",
                command=cmd,
                depends=dep,
            ),
            Claim(
                key=f"metal.equal05.{k}",
                statement=f"33 in 30 oz metal - R161, n = 0.5, {sc.label}",
                value=f"{eq['gain over wood, constant_torque (m/s)']:+.2f}",
                command=cmd,
                depends=dep,
            ),
            Claim(
                key=f"metal.pair027.{k}",
                statement=f"paper's 31 in metal - R161, n = 0.27, {sc.label}",
                value=f"{pair:+.2f}",
                command=cmd,
                depends=dep,
            ),
            Claim(
                key=f"metal.carry027.{k}",
                statement=f"33 in metal carry change, n = 0.27, {sc.label}",
                value=_carry_change(k, M.EQUAL_LENGTH, "measured"),
                command=cmd,
                depends=f"{dep}, drag and lift",
            ),
            Claim(
                key=f"metal.carry05.{k}",
                statement=f"33 in metal carry change, n = 0.5, {sc.label}",
                value=_carry_change(k, M.EQUAL_LENGTH, "constant_torque"),
                command=cmd,
                depends=f"{dep}, drag and lift",
            ),
            Claim(
                key=f"metal.match.{k}",
                statement=f"metal J_cm for wood's sweet spot, n = 0.27, {sc.label} (% of a rod)",
                value=f"{metal['match'][(k, 'measured')]:.0%}",
                command=cmd,
                depends="rigid model without a COR varying along the barrel",
            ),
        ]
    out += [
        Claim(
            key="metal.lively",
            statement="what e = 0.55-0.60 adds (what-if) (m/s)",
            value="{:.1f}-{:.1f}".format(*metal["lively"]),
            command=cmd,
            depends="e is an input here; BBCOR caps it at 0.50 [ncaa]",
        ),
        Claim(
            key="metal.lively_carry",
            statement="what e = 0.55-0.60 adds to the carry (what-if) (m)",
            value="{:.0f}-{:.0f}".format(*_lively_carry()),
            command=cmd,
            depends="e is an input here; drag and lift",
        ),
    ]
    return out


def ball_claims(stats: Stats) -> list[Claim]:
    """The ball's COR over the assumed law's range, and how far rigid theory at e = 0.5 is from
    it."""
    cmd = f"{FINDINGS} (section 4, analytic.ball.COR_LAW, COR_LAWS)"
    lo = min(stats[k]["diff lo"] for k in ("paper", "mlb"))
    hi = max(stats[k]["diff hi"] for k in ("paper", "mlb"))
    r_lo = min(stats[k]["range lo"] for k in ("paper", "mlb"))
    r_hi = max(stats[k]["range hi"] for k in ("paper", "mlb"))
    e_lo, e_hi = stats["regime_cor"]
    dep, src = "the assumed speed dependence", "assumption through [mlbcor] [nathan2000]"
    return [
        Claim(
            key="ball.cor60",
            statement="the ball's COR at 60 m/s (range: COR_LAWS)",
            value=ranged(stats["cor_60"], *stats["cor_60_range"]),
            command=cmd,
            depends=dep,
            source=src,
        ),
        Claim(
            key="ball.regime",
            statement="the COR at the swings' closing speeds, {:.0f}-{:.0f} m/s (range)".format(
                *stats["regime_mps"]
            ),
            value="{:.2f}-{:.2f} ({:.2f}-{:.2f})".format(e_lo, e_hi, *stats["regime_range"]),
            command=cmd,
            depends=dep,
            source=src,
        ),
        Claim(
            key="ball.gap",
            statement="rigid (e = 0.5) minus realistic ball, along the barrel (m/s; over COR_LAWS)",
            value=f"{lo:+.1f} to {hi:+.1f} ({r_lo:+.0f} to {r_hi:+.0f})",
            command=cmd,
            depends=dep,
        ),
    ]


def paper_claims() -> list[Claim]:
    """The paper's reaction times, recomputed from its own numbers."""
    cmd = f"{FINDINGS} (section 5)"
    return [
        Claim(
            key=f"paper.t{v}",
            statement=f"18.44 m / {v} m/s (the paper's time, s)",
            value=f"{18.44 / v:.3f}",
            command=cmd,
            depends="the paper's speed",
            source="the paper",
        )
        for v in (42.59, 38.57)
    ]


def collect(
    sweet: Stats, cork: Stats, metal: Stats, ball: Stats, flex: Stats | None = None
) -> list[Claim]:
    """Every claim, inputs first."""
    return (
        input_claims()
        + sweet_claims(sweet, flex)
        + cork_claims(cork)
        + metal_claims(metal)
        + ball_claims(ball)
        + paper_claims()
    )


def value(claims: list[Claim], key: str) -> str:
    """The quoted value of one claim."""
    return next(c.value for c in claims if c.key == key)


def referee_section(claims: list[Claim]) -> str:
    """Every claim with its command, what it depends on, and its source."""
    table = pd.DataFrame(
        [
            {
                "claim": c.statement,
                "value": c.value,
                "key": f"`{c.key}`",
                "command": c.command,
                "depends on": c.depends,
                "source": c.source,
            }
            for c in claims
        ]
    )
    return f"""## Referee: every number, its command, its sensitivity, its source

Every number the short answers (and the README's findings) quote is one of these;
`tests/test_findings_claims.py` recomputes them and fails when a quoted number no longer
matches. Model results are rigid-bat results at e = 0.5 unless the row says otherwise; an
engine's agreement with them (section 6) confirms the arithmetic, not the physics.

{md_table(table)}
"""


def short_answers_text(claims: list[Claim]) -> str:
    """One paragraph per question, quoting claims only (and the inputs they rest on)."""

    def v(key: str) -> str:
        return value(claims, key)

    return f"""**Short answers** (model results; the referee section gives each number's command,
what it depends on and its source):
- **Sweet spot**: in a rigid-bat model the best point moves with the swing: {v("sweet.batting")} cm
  from the barrel end for batting swings ({v("sweet.share")} of them inside Russell's
  {v("input.russell")} cm; the MLB-like swing: {v("sweet.mlb")} cm, its best ball carrying
  {v("carry.mlb")} m over the drag and lift spread); slower swings put it farther out
  ({v("sweet.all")} cm down to 12 rad/s; the paper's swing {v("sweet.paper")} cm,
  {v("carry.paper")} m). On a flexible R161 the first mode's node lies {v("flex.node")} cm from
  the end whatever the ball; the fastest point, {v("flex.peak")} cm, and whether the beam beats a
  rigid bat ({v("flex.sign")} m/s) depend on the ball's law (section 3c). A curveball carries
  {v("curve.gain")} m farther than a fastball at the same speed (section 3b).
- **Corking** ({v("input.cork")} cork fill, rigid model, e = {v("input.e")}): the answer depends
  on how much faster the lighter bat is swung (speed ~ I_knob^-n). At the measured
  n = {v("input.n")}, in wood of {v("input.wood")} kg/m^3 (ranges: ash's densities; carries:
  drag and lift), it changes v1 by {v("cork.n027.paper")} m/s (paper's swing; carry
  {v("cork.carry027.paper")} m) and {v("cork.n027.mlb")} m/s (MLB-like; {v("cork.carry027.mlb")} m);
  at constant torque (n = {v("input.torque")}) by {v("cork.n05.paper")} m/s
  ({v("cork.carry05.paper")} m) and {v("cork.n05.mlb")} m/s ({v("cork.carry05.mlb")} m). It pays
  only above n = {v("cork.even.paper")} (paper's swing) or {v("cork.even.mlb")} (MLB-like); with
  the same swing (n = 0) it changes v1 by {v("cork.same.paper")} / {v("cork.same.mlb")} m/s.
- **Metal bats** (rigid model; the metal bat's J_cm and COM are unsourced): at e = {v("input.e")}
  a metal bat of the R161's length at BBCOR's drop -3 ({v("input.equal")}) changes v1 by
  {v("metal.equal027.paper")} / {v("metal.equal027.mlb")} m/s at n = {v("input.n")} (paper's /
  MLB-like swing; carry {v("metal.carry027.paper")} / {v("metal.carry027.mlb")} m) and by
  {v("metal.equal05.paper")} / {v("metal.equal05.mlb")} m/s at constant torque (carry
  {v("metal.carry05.paper")} / {v("metal.carry05.mlb")} m); the paper's
  31 in bat's {v("metal.pair027.paper")} / {v("metal.pair027.mlb")} m/s is mostly its shorter
  length. A livelier collision gains more: what-if e = 0.55-0.60 adds {v("metal.lively")} m/s
  ({v("metal.lively_carry")} m of carry), and BBCOR caps e at 0.50 [ncaa].
- **The ball**: no speed-resolved COR could be read, so its fall with speed is an assumption:
  from {v("input.cor")} at 85 ft/s as v^-p, p = {v("input.cor_exponent")}, it is
  {v("ball.regime")} at the swings' closing speeds. Rigid theory at e = {v("input.e")} lies
  {v("ball.gap")} m/s above it along the barrel: the sign rests on the assumption (section 4).
- **The paper**: its corked-bat inertia cannot be checked (lost minus signs); its oblique
  rebound angle and its metal-bat speed do not follow from its data; its reaction times follow
  from its own speeds ({v("paper.t42.59")} and {v("paper.t38.57")} s) and inherit their errors;
  its v ~ F/M contradicts its own log spiral (section 5).
"""
