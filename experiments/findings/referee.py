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

from analytic import MEASURED_EXPONENT, ball

from . import answers as A
from . import carry as C
from . import metal as M
from . import ranges as R
from .inputs import INPUTS, Spread, inputs_table, spread
from .report import Stats, md_table

FINDINGS = "python -m experiments.findings"
#: A number that rests on no input of ``inputs.INPUTS``.
NO_INPUT = "no uncertain input"


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
    moved_most: str = "-"


def _over(sp: Spread) -> str:
    """What a ranged claim depends on: its inputs, by key."""
    return "over " + ", ".join(f"`{k}`" for k in sp.inputs)


def _lively_carry() -> tuple[float, float]:
    """The least and most (m) that e = 0.55 or 0.60 adds to the aluminium bat's carry at
    e = 0.5, over the swing models and both swings (``carry.bat_table``)."""
    gains = []
    for sc in A.SCENARIOS:
        t = C.bat_table(sc)
        al = t[t.bat == M.ALUMINIUM].set_index(["swing model", "e"])["carry (m)"]
        gains += [al[(m, e)] - al[(m, A.E)] for m, e in al.index if e != A.E]
    return min(gains), max(gains)


def _input_claim(key: str, name: str, fmt: str, command: str) -> Claim:
    """An uncertain input as a claim: its central value and range (``inputs.INPUTS``)."""
    i = INPUTS[name]
    return Claim(
        key=key,
        statement=i.label,
        value=f"{fmt.format(i.central)} ({fmt.format(i.low)}-{fmt.format(i.high)})",
        command=command,
        depends="-",
        source=i.source,
    )


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
        _input_claim("input.wood", "wood_density_kgm3", "{:.0f}", "answers.HOLE_WOOD_KGM3"),
        _input_claim("input.metal_com", "metal_com_fraction", "{:.0%}", "metal.bbcor_bat"),
        _input_claim("input.metal_rod", "metal_rod_fraction", "{:.0%}", "metal.bbcor_bat"),
        Claim(
            key="input.whatif",
            statement="what-if e of a livelier (metal) collision",
            value="0.55-0.60",
            command="metal.METAL_ES",
            depends="-",
            source="what-if: brackets the 0.576 the paper's 42.59 m/s needs (section 5)",
        ),
    ]


def ranged_claim(key: str, statement: str, sp: Spread, command: str, sign: str = "", **kw) -> Claim:
    """A claim quoted as central (low-high) over the joint range of its inputs."""
    return Claim(
        key=key,
        statement=statement,
        value=sp.text(sign),
        command=command,
        depends=kw.pop("depends", _over(sp)),
        moved_most=sp.driver,
        **kw,
    )


def sweet_claims(sweet: Stats, flex: Stats | None) -> list[Claim]:
    """Where the sweet spot lies, how far its ball carries, the curveball's gain."""
    cmd = f"{FINDINGS} (section 1, answers.batting_region_cm / best_v1)"
    out = [
        Claim(
            key="sweet.batting",
            statement="sweet spot, batting swings (cm from the end)",
            value="{:.1f}-{:.1f}".format(*sweet["batting"]),
            command=cmd,
            depends=f"{NO_INPUT} (a region over bat rates 40-56 rad/s, pivot knob or hands, "
            "pitch 35-47 m/s; not e)",
        ),
        Claim(
            key="sweet.all",
            statement="sweet spot, the paper's rates 12-48 rad/s (cm)",
            value="{:.1f}-{:.1f}".format(*sweet["region"]),
            command=cmd,
            depends=f"{NO_INPUT} (a region; the slow 12 rad/s end sets the far edge)",
        ),
    ]
    carry_cmd = f"{FINDINGS} (section 3b, ranges.carry_spread)"
    for sc in A.SCENARIOS:
        best = C.sweet_spots(sc).best
        out += [
            Claim(
                key=f"sweet.{sc.key}",
                statement=f"best point, {sc.label} (cm)",
                value=f"{sweet['best_cm'][sc.key]:.1f}",
                command=cmd,
                depends=f"{NO_INPUT} (the swing and pitch; not e)",
            ),
            ranged_claim(
                f"carry.{sc.key}",
                f"longest carry, {sc.label} (m)",
                R.carry_spread(sc),
                carry_cmd,
                source="computed; [nathancalc] [adair] [kensrud2017] [nathan2012]",
            ),
            Claim(
                key=f"carry.wide.{sc.key}",
                statement=f"best undercut, 30 mm / 2.61 in barrel, {sc.label} (cm)",
                value=f"{100 * best.undercut_m:.2f} / "
                f"{100 * C.wide_barrel_best(sc).undercut_m:.2f}",
                command=f"{FINDINGS} (section 3b)",
                depends="the contact radius (an illustration at central inputs)",
                source="computed; [rules]",
            ),
            ranged_claim(
                f"curve.{sc.key}",
                f"best curveball's carry minus best fastball's, same speed, {sc.label} (m)",
                R.curve_spread(sc),
                f"{FINDINGS} (section 3b, ranges.curve_spread)",
                sign="+",
                source="computed; [nathan2012] [crossnathan2006] [kensrud2017]",
            ),
        ]
    share_cmd = f"{FINDINGS} (section 1, answers.russell_share)"
    out += [
        Claim(
            key="sweet.share",
            statement="batting swings whose sweet spot is in Russell's range (fine grid)",
            value=f"{A.russell_share():.0%}",
            command=share_cmd,
            depends=f"{NO_INPUT}; the grid: the default one gives "
            f"{A.russell_share(fine=False):.0%}",
        )
    ]
    return out + (_flex_claims(flex) if flex else [])


def _flex_claims(flex: Stats) -> list[Claim]:
    """The flexible bat's: its first mode's node, its speed peak, its sign against the rigid."""
    m, cmd = flex["models"], f"{FINDINGS} (section 3c, flex_models)"
    out = [
        ranged_claim(
            "flex.node",
            "beam: first mode's barrel node (cm)",
            flex["node"],
            f"{FINDINGS} (section 3c, ranges.node_spread)",
            depends=f"{_over(flex['node'])} (the assumed profile); not the ball; a scale of "
            "E and G cannot move it",
            source="computed; E, G [woodhandbook]",
        )
    ]
    for key in ("paper", "mlb"):
        out += [
            ranged_claim(
                f"flex.peak.{key}",
                f"beam: speed peak, {key} swing (cm from the end)",
                m["peak"][key],
                cmd,
                depends="the ball model and contact-time definition (3 balls); E +-20%: 1 cm",
            ),
            ranged_claim(
                f"flex.apart.{key}",
                f"beam: speed peak to node, {key} swing (cm)",
                m["apart"][key],
                cmd,
                depends="the ball model and contact-time definition (3 balls)",
            ),
            ranged_claim(
                f"flex.sign.{key}",
                f"beam minus rigid bat at the peak, {key} swing (m/s)",
                m["sign"][key],
                cmd,
                sign="+",
                depends="the ball model and contact-time definition (3 balls)",
            ),
        ]
    return out


def cork_claims(cork: Stats) -> list[Claim]:
    """What the 1 x 10 in cork fill gains or loses in m/s (over the wood's density and e) and
    in metres of carry (over those, drag and lift)."""
    cmd = f"{FINDINGS} (section 2, ranges.cork_spreads)"
    out = []
    for sc in A.SCENARIOS:
        sp, k = R.cork_spreads(sc), sc.key
        out += [
            ranged_claim(
                f"cork.n027.{k}",
                f"cork v1 change at n = 0.27, {sc.label} (m/s)",
                sp["n027"],
                cmd,
                "+",
            ),
            ranged_claim(
                f"cork.n05.{k}", f"cork v1 change at n = 0.5, {sc.label} (m/s)", sp["n05"], cmd, "+"
            ),
            ranged_claim(f"cork.even.{k}", f"cork break-even n, {sc.label}", sp["even"], cmd),
            ranged_claim(
                f"cork.same.{k}",
                f"cork, same swing (n = 0), {sc.label} (m/s)",
                sp["same"],
                cmd,
                "+",
            ),
            ranged_claim(
                f"cork.carry027.{k}",
                f"cork carry change, n = 0.27, {sc.label} (m)",
                sp["carry027"],
                cmd,
                "+",
            ),
        ]
    return out


def metal_claims(metal: Stats) -> list[Claim]:
    """The metal bats at equal length and at the paper's pairing, over their COM, J_cm and e;
    the share of the pairing's loss that length explains; livelier."""
    cmd = f"{FINDINGS} (section 3, ranges.metal_spreads)"
    out = []
    for sc in A.SCENARIOS:
        k, sp = sc.key, R.metal_spreads(sc)
        length = sp["length027"]
        out += [
            ranged_claim(
                f"metal.equal027.{k}",
                f"33 in 30 oz metal - R161, n = 0.27, {sc.label} (m/s)",
                sp["equal027"],
                cmd,
                "+",
            ),
            ranged_claim(
                f"metal.equal05.{k}",
                f"33 in 30 oz metal - R161, n = 0.5, {sc.label} (m/s)",
                sp["equal05"],
                cmd,
                "+",
            ),
            ranged_claim(
                f"metal.pair027.{k}",
                f"paper's 31 in metal - R161, n = 0.27, {sc.label} (m/s)",
                sp["pair027"],
                cmd,
                "+",
            ),
            ranged_claim(
                f"metal.pair05.{k}",
                f"paper's 31 in metal - R161, n = 0.5, {sc.label} (m/s)",
                sp["pair05"],
                cmd,
                "+",
            ),
            Claim(
                key=f"metal.length027.{k}",
                statement=f"share of the 31 in bat's loss its length explains, n = 0.27, "
                f"{sc.label}",
                value=f"{length.central:.0%} ({length.low:.0%}-{length.high:.0%})",
                command=cmd,
                depends=_over(length),
                moved_most=length.driver,
            ),
            Claim(
                key=f"metal.match.{k}",
                statement=f"metal J_cm for wood's sweet spot, n = 0.27, {sc.label} (% of a rod)",
                value=f"{metal['match'][(k, 'measured')]:.0%}",
                command=f"{FINDINGS} (section 3)",
                depends="an illustration at the central COM (60%); rigid model without a COR "
                "varying along the barrel",
            ),
        ]
    out += [
        Claim(
            key="metal.lively",
            statement="what e = 0.55-0.60 adds (what-if) (m/s)",
            value="{:.1f}-{:.1f}".format(*metal["lively"]),
            command=f"{FINDINGS} (section 3)",
            depends="a what-if over e itself (the span: swing models, both swings); BBCOR caps "
            "e at 0.50 [ncaa]",
        ),
        Claim(
            key="metal.lively_carry",
            statement="what e = 0.55-0.60 adds to the carry (what-if) (m)",
            value="{:.0f}-{:.0f}".format(*_lively_carry()),
            command=f"{FINDINGS} (section 3b)",
            depends="a what-if over e itself (the span: swing models, both swings), at central "
            "drag and lift",
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
    cor60 = spread(
        lambda cor_ref, cor_exponent: ball.CorLaw(
            cor_ref=cor_ref, speed_ref_mps=ball.SPEED_REF_MPS, exponent=cor_exponent
        ).cor(60.0),
        ("cor_ref", "cor_exponent"),
    )
    dep = "over `cor_ref`, `cor_exponent` (COR_LAWS: the corners)"
    src = "assumption through [mlbcor] [nathan2000]"
    return [
        ranged_claim(
            "ball.cor60",
            "the ball's COR at 60 m/s",
            cor60,
            cmd,
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
            moved_most=cor60.driver,
        ),
        Claim(
            key="ball.gap",
            statement="rigid (e = 0.5) minus realistic ball, along the barrel (m/s; over COR_LAWS)",
            value=f"{lo:+.1f} to {hi:+.1f} ({r_lo:+.0f} to {r_hi:+.0f})",
            command=cmd,
            depends=dep,
            moved_most=cor60.driver,
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
            depends=f"{NO_INPUT} (the paper's own speed and distance)",
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
                "moved most by": c.moved_most,
                "source": c.source,
            }
            for c in claims
        ]
    )
    return f"""## Referee: every number, its command, its sensitivity, its source

**The uncertain inputs** (`experiments.findings.inputs.INPUTS`): every ranged number below is
computed over the joint range of those it depends on (`inputs.spread`: every corner of their
box up to {len(R.CORK_CARRY_INPUTS)} inputs, else a fixed-seed Sobol sample of it, always with
each input's own two ends) and quoted as central (low-high), with the input whose ends move it
most. The central value is every input at its central value (the rigid model's e = 0.5).

{md_table(inputs_table())}

Every number the short answers (and the README's findings) quote is one of these;
`tests/test_findings_claims.py` recomputes them and fails when a quoted number no longer
matches. Model results are rigid-bat results unless the row says otherwise; an engine's
agreement with them (section 6) confirms the arithmetic, not the physics. "no uncertain input":
the number rests on none of the table's.

{md_table(table)}
"""


def short_answers_text(claims: list[Claim]) -> str:
    """One paragraph per question, quoting claims only (and the inputs they rest on)."""

    def v(key: str) -> str:
        return value(claims, key)

    def by(key: str) -> str:
        return next(c.moved_most for c in claims if c.key == key)

    return f"""**Short answers** (model results, each number central (low-high) over the joint range
of the uncertain inputs it depends on, or resting on none; the referee section gives the
inputs, each number's command, what moves it most and its source):
- **Sweet spot**: in a rigid-bat model the best point moves with the swing (no uncertain input
  moves it): {v("sweet.batting")} cm from the barrel end for batting swings ({v("sweet.share")}
  of them inside Russell's {v("input.russell")} cm; the MLB-like swing {v("sweet.mlb")} cm, the
  paper's {v("sweet.paper")} cm); slower swings put it farther out ({v("sweet.all")} cm). Its
  best ball carries {v("carry.mlb")} m (MLB-like) and {v("carry.paper")} m (paper's swing),
  moved most by the {by("carry.mlb")}. On a flexible R161 the first mode's node lies
  {v("flex.node")} cm from the end whatever the ball, moved only by the assumed profile. The
  fastest point, {v("flex.peak.paper")} / {v("flex.peak.mlb")} cm from the end
  ({v("flex.apart.paper")} / {v("flex.apart.mlb")} cm from the node), and the beam minus a
  rigid bat, {v("flex.sign.paper")} / {v("flex.sign.mlb")} m/s, turn on the ball's loss law and
  on what its contact time means (section 3c). A best-hit curveball carries {v("curve.paper")} /
  {v("curve.mlb")} m farther than a fastball at the same speed: none if the outgoing spin ignores
  the incoming, the most under rigid rolling, less with the extra spin of a gripping ball
  (section 3b).
- **Corking** ({v("input.cork")} cork fill, rigid model; over the wood's density,
  {v("input.wood")} kg/m^3, and e): at the measured n = {v("input.n")} it changes v1 by
  {v("cork.n027.paper")} m/s (paper's swing; carry {v("cork.carry027.paper")} m, over drag and lift
  too) and {v("cork.n027.mlb")} m/s (MLB-like; {v("cork.carry027.mlb")} m); at constant torque
  (n = {v("input.torque")}) by {v("cork.n05.paper")} / {v("cork.n05.mlb")} m/s. It pays only above
  n = {v("cork.even.paper")} (paper's swing) or {v("cork.even.mlb")} (MLB-like); with the same
  swing it changes v1 by {v("cork.same.paper")} / {v("cork.same.mlb")} m/s.
- **Metal bats** (rigid model; over e and the metal bat's unsourced COM, {v("input.metal_com")}
  of its length, and J_cm, {v("input.metal_rod")} of a rod's): one of the R161's length at
  BBCOR's length-to-weight limit ({v("input.equal")}) changes v1 by {v("metal.equal027.paper")} /
  {v("metal.equal027.mlb")} m/s at n = {v("input.n")} (paper's / MLB-like swing; moved most by
  the {by("metal.equal027.paper")}) and by {v("metal.equal05.paper")} / {v("metal.equal05.mlb")} m/s
  at constant torque. The paper's shorter aluminium bat's {v("metal.pair027.paper")} /
  {v("metal.pair027.mlb")} m/s at n = {v("input.n")} is {v("metal.length027.paper")} /
  {v("metal.length027.mlb")} its shorter length, the rest its lightness under the measured
  scaling; at constant torque ({v("metal.pair05.paper")} / {v("metal.pair05.mlb")} m/s) lightness
  alone hardly counts. A livelier collision gains more: what-if e = {v("input.whatif")} adds
  {v("metal.lively")} m/s ({v("metal.lively_carry")} m of carry), and BBCOR caps e at
  {v("input.e")} [ncaa].
- **The ball**: no speed-resolved COR could be read, so its fall with speed is an assumption:
  from {v("input.cor")} at MLB's test speed as v^-p, p = {v("input.cor_exponent")}, it is
  {v("ball.regime")} at the swings' closing speeds. Rigid theory at e = {v("input.e")} lies
  {v("ball.gap")} m/s above it along the barrel: the sign rests on the assumption (section 4).
- **The paper**: its corked-bat inertia cannot be checked (lost minus signs); its oblique
  rebound angle and its metal-bat speed do not follow from its data; its reaction times follow
  from its own speeds ({v("paper.t42.59")} and {v("paper.t38.57")} s) and inherit their errors;
  its v ~ F/M contradicts its own log spiral (section 5).
"""
