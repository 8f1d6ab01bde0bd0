"""Speed against accuracy: the cheapest setting per accuracy, the fronts, convergence orders."""

from __future__ import annotations

import math
import re

import numpy as np
import pandas as pd

from .. import pareto as study
from .base import (
    Results,
    bullets,
    count,
    engines_text,
    gnum,
    label,
    lead,
    md_table,
    names,
    num,
    orders,
    sci,
    secs,
    span,
    step,
)
from .data import need
from .knobs import knob_points
from .pages import PAGE_TARGET

ALIGNED = "reference profile (aligned)"
DEFAULT = study.DEFAULT_FAMILY
#: Two families are on one line where their errors agree within this factor.
SAME_LINE = 1.5


def section(res: Results) -> str:
    meta = res.json("pareto.json")
    table = res.csv("pareto.csv")
    head = (
        f"{res.chart('pareto.png', 'error against cost per collision')}\n\n"
        f"(`python -m experiments.pareto`: {meta['elapsed_s']:.0f} s in its last run, "
        f"`{meta['provenance']['command']}`.)"
    )
    named = set(res.csv("pareto_cheapest.csv").setting.dropna())
    (swing,) = need(res, "swing")
    return "\n\n".join(
        [
            head,
            *cheapest(res),
            ties(table, named),
            drake(res, table),
            *grid(table, meta),
            bullets(
                [line(res, table), knees(table, swing), aligned(res, table), *knob_points(res)]
            ),
        ]
    )


def _setting(text: str) -> str:
    """'iterations 1, dt = 1e-05 s' -> 'iterations 1, dt = 10 us'."""
    m = re.search(r"dt = ([0-9.e+-]+) s", text)
    return text if not m else text.replace(m.group(0), f"dt = {step(float(m.group(1)))}")


def cheapest(res: Results) -> list[str]:
    """The cheapest setting of all per accuracy, then each engine's at the accuracies its page
    does not give (``pages.PAGE_TARGET`` is there)."""
    best = res.csv("pareto_cheapest.csv")
    top = best[best.engine == "any"]
    overall = pd.DataFrame(
        {
            "max relative error": top.target.map(lambda t: sci(t, 1)),
            "cheapest of all": [
                f"{label(r.winner)}, {_setting(r.setting)}" for r in top.itertuples()
            ],
            "its error": top.max_rel_err.map(sci),
            "cost per collision": top.wall_per_collision_s.map(secs),
        }
    )
    each = best[(best.engine != "any") & ~np.isclose(best.target, PAGE_TARGET)]
    table = each.pivot(index="engine", columns="target", values="setting")
    cost = each.pivot(index="engine", columns="target", values="wall_per_collision_s")
    rows = pd.DataFrame(
        {"engine": [label(e) for e in table.index]}
        | {
            f"within {sci(t, 1)}": [
                f"{_setting(s)} ({secs(c)})" if isinstance(s, str) and pd.notna(c) else "none"
                for s, c in zip(table[t], cost[t])
            ]
            for t in sorted(table.columns, reverse=True)
        }
    )
    return [
        "**The cheapest engine and setting for an accuracy** (max relative error of v1 "
        "against rigid theory over the mid-step grid, every impact sound; "
        "`results/pareto_cheapest.csv`, cost per collision = "
        f"{secs(study.WINDOW_S)} of approach plus the contact, medians of one run):",
        md_table(overall),
        "Each engine's cheapest setting (cost per collision); within "
        f"{sci(PAGE_TARGET, 1)}: its [page](engines.md).",
        md_table(rows),
    ]


def _errors(table: pd.DataFrame, engine: str, family: str) -> pd.Series:
    d = table[(table.engine == engine) & (table.family == family) & table.all_ok]
    return d.set_index("dt_s").max_rel_err


def ties(table: pd.DataFrame, named: set[str]) -> str:
    """Families of one engine whose errors agree at every step (knobs that do nothing), where
    the cheapest-setting table names one of them."""
    found = []
    for e, g in table[~table.family.isin([DEFAULT, ALIGNED])].groupby("engine", sort=False):
        groups: dict[tuple, list[str]] = {}
        for fam, d in g.groupby("family", sort=False):
            key = tuple(f"{v:.4g}" for v in d.sort_values("dt_s").max_rel_err)
            groups.setdefault(key, []).append(fam)
        found += [
            f"{label(e)}'s {' = '.join(fams)}"
            for fams in groups.values()
            if len(fams) > 1 and any(n.startswith(f"{f}, dt") for f in fams for n in named)
        ]
    if not found:
        return ""
    return lead(
        "Solver knobs that do nothing here make ties, the same errors at every step "
        "(the tables name whichever was cheapest in this run):",
        found,
    )


def drake(res: Results, table: pd.DataFrame) -> str:
    (swing,) = need(res, "swing")
    conv = res.csv("convergence.csv")
    best = res.csv("pareto_cheapest.csv")
    out = []
    for e in swing.compliant:
        d = table[(table.engine == e) & table.all_ok & (table.family != ALIGNED)]
        c = conv[conv.engine == e]
        cont = c[c.family.str.contains(f"accuracy {_acc(swing.setting(e, 'accuracy'))},")]
        laws: dict[str, list[str]] = {}
        for r in c[c.family.str.startswith("discrete") & c.p_law.notna()].itertuples():
            laws.setdefault(f"{r.p_law:.2f}", []).append(r.family.split(",")[0][9:])
        reached = best[(best.engine == e) & best.winner.notna()]
        out.append(
            lead(
                f"**{label(e)} reaches {'none of them' if reached.empty else 'some of them'}** by "
                "design, but converges to its own law:",
                [
                    "its Hunt-Crossley contact is a different model (e falls with speed)",
                    f"at least {pct_of(d.max_rel_err.min())} from rigid theory on this grid at any "
                    "step",
                    f"its continuous mode at accuracy {gnum(swing.setting(e, 'accuracy'))}: within "
                    f"{sci(cont.law_err_at_dt_min.iloc[0])} of its law (relative), set by the "
                    "grid's barrel-end point, where the ball slides onto the cap during the "
                    "contact "
                    "and the law's infinite cylinder does not follow it"
                    if len(cont)
                    else "",
                    "its discrete approximations: first order (`p_law` "
                    + names(f"{p} {names(f)}" for p, f in laws.items())
                    + ", `convergence.csv`)",
                ],
            )
        )
    return "\n\n".join(out)


def _acc(x) -> str:
    return f"{x:g}"  # as the family's name spells it


def pct_of(x: float) -> str:
    return f"{num(100 * x)}%"


def grid(table: pd.DataFrame, meta: dict) -> list[str]:
    dts = sorted(table[~table.family.isin([DEFAULT, ALIGNED])].dt_s.unique())
    fams = [
        f"{label(e)}: {' / '.join(f for f in g.family.unique() if f not in (DEFAULT, ALIGNED))}"
        for e, g in table.groupby("engine", sort=False)
    ]
    s = meta["grid_s_m"]
    return [
        lead(
            f"Every engine over the knob families its record declares, each at {len(dts)} "
            f"time steps from {step(dts[0])} to {step(dts[-1])}, plus its default profile "
            "(also at its own step):",
            fams,
        ),
        lead(
            "The grid (`results/pareto.csv`):",
            [
                f"the paper's swing at {len(s)} points over s in [{s[0]:g}, {s[-1]:g}] m",
                f"the contact instant at {meta['contact_phase']:g} of a step, what a simulation "
                "that does not align contacts meets on average",
                f"the cost: the wall time to simulate {secs(study.WINDOW_S)} of approach plus "
                "the contact",
                "recorded: median and max relative error of v1, median wall per collision over "
                f"{meta['repeats']} repeats, counts of every status",
            ],
        ),
    ]


def _reference_family(table: pd.DataFrame, engine: str) -> str:
    """An engine's first knob family: its reference solver."""
    fams = [f for f in table[table.engine == engine].family.unique() if f not in (DEFAULT, ALIGNED)]
    return fams[0]


def _joins(table: pd.DataFrame, engine: str, ref: pd.Series) -> tuple[str, float]:
    """The engine's family closest to the reference line, and the smallest step down to which
    it stays on it (within SAME_LINE at every sound step from there up)."""
    best = ("", math.inf)
    for fam in table[table.engine == engine].family.unique():
        if fam in (DEFAULT, ALIGNED):
            continue
        ratio = (_errors(table, engine, fam) / ref).dropna().sort_index(ascending=False)
        off = np.abs(np.log(ratio.to_numpy())) > math.log(SAME_LINE)
        n = int(np.argmax(off)) if off.any() else len(ratio)
        if n and ratio.index[n - 1] < best[1]:
            best = (fam, float(ratio.index[n - 1]))
    return best


def line(res: Results, table: pd.DataFrame) -> str:
    (swing,) = need(res, "swing")
    conv = res.csv("convergence.csv")
    t = table.assign(per_step_us=table.wall_per_collision_s / table.steps_median * 1e6)
    f64 = [
        (e, _reference_family(t, e)) for e in swing.of_precision("float64") if e in set(t.engine)
    ]  # those the pareto study ran
    errs = [_errors(t, e, f) for e, f in f64]
    ref = errs[0]
    same = all(np.allclose(x.reindex(ref.index), ref, rtol=1e-3) for x in errs)
    at = [d for d in (1e-3, 1e-4, 1e-5, 1e-6) if d in ref.index]
    c = conv[(conv.engine == f64[0][0]) & (conv.family == f64[0][1])].iloc[0]
    cost = {
        e: t[(t.engine == e) & (t.family == f) & (t.dt_s <= 1e-5)].per_step_us.median()
        for e, f in f64
    }
    order = sorted(cost, key=cost.get)
    facts = [
        names(f"{label(e)} ({f})" for e, f in f64)
        + f": {'the same' if same else 'about the same'} error at the same step",
        "max relative error " + names(f"{sci(ref[d])} at {step(d)}" for d in at),
        f"first order in dt (fitted p = {c.p:.2f}, r^2 = {c.r2:.2f}, "
        "`results/convergence.csv`): the contact is seen half a step late while the bat "
        "turns",
        f"cost per step: {label(order[0])} is cheapest, then {names(label(e) for e in order[1:])}",
    ]
    f32 = [e for e in swing.of_precision("float32") if e in set(t.engine)]
    joined = [(e, *_joins(t, e, ref)) for e in f32]
    facts.append(
        lead(
            f"joining the same line (within a factor {SAME_LINE:g}): they too see the "
            "contact from a step's geometry",
            [f"{label(e)} ({f}, down to {step(d)})" for e, f, d in joined if f],
        )
    )
    level = []
    for e in f32:
        c = conv[(conv.engine == e) & (conv.family == _reference_family(t, e))]
        if len(c) and c.err_at_dt_min.iloc[0] > 10 * ref.get(c.dt_min_s.iloc[0], math.inf):
            level.append(f"{label(e)}'s at {sci(c.err_at_dt_min.iloc[0])}")
    if level:
        facts.append(
            f"reference solvers that level off (a contact made a step early): {names(level)}"
        )
    small = t[(t.dt_s == t.dt_s.min()) & t.all_ok & t.engine.isin(swing.rigid)]
    low = small.loc[small.per_step_us.idxmin()]
    facts.append(
        f"the cheapest step of all: {label(low.engine)}'s ({low.family}, "
        f"{num(low.per_step_us)} us at {step(low.dt_s)})"
    )
    return lead(f"**The {count(len(f64))} float64 impulse-type solvers sit on one line**:", facts)


def knees(t: pd.DataFrame, swing) -> str:
    each = []
    for e in [e for e in swing.rigid if e in set(t.engine)]:  # those the pareto study ran
        good = t[(t.engine == e) & t.all_ok & (t.family != ALIGNED)]
        times, errs = good.wall_per_collision_s.to_numpy(), good.max_rel_err.to_numpy()
        front = study.pareto_front(times, errs)
        k = front[study.knee(times[front], errs[front])]
        r = good.iloc[k]
        each.append(
            f"{label(e)} {r.family}, dt = {step(r.dt_s)} ({sci(r.max_rel_err)} in "
            f"{secs(r.wall_per_collision_s)})"
        )
    return lead(
        "**Knees of the fronts** (farthest from the chord in log-log, circled on the "
        "chart; the knee moves between neighbouring steps from run to run, as the "
        "timings do):",
        each,
    )


def aligned(res: Results, table: pd.DataFrame) -> str:
    (swing,) = need(res, "swing")
    f64 = swing.of_precision("float64")
    al = table[(table.family == ALIGNED) & table.engine.isin(f64)]
    gains = []
    for r in al.itertuples():
        mid = _errors(table, r.engine, _reference_family(table, r.engine)).get(r.dt_s)
        if mid is not None:
            gains.append((orders(mid, r.max_rel_err), r.max_rel_err, r.dt_s))
    if not gains:
        return ""
    low = min(g[0] for g in gains)
    return (
        f"**Aligning the contact with a step** (the reference profile's placement, stars) "
        f"buys {span(low, max(g[0] for g in gains), str)} orders of magnitude at the same "
        f"cost in {engines_text(f64)}: {sci(max(g[1] for g in gains))} at dt = "
        f"{step(gains[0][2])}."
    )
