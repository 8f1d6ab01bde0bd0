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

ALIGNED = "reference profile (aligned)"
DEFAULT = study.DEFAULT_FAMILY
#: Two families are on one line where their errors agree within this factor.
SAME_LINE = 1.5


def section(res: Results) -> str:
    meta = res.json("pareto.json")
    table = res.csv("pareto.csv")
    head = (f"{res.chart('pareto.png', 'error against cost per collision')}\n\n"
            f"(`python -m experiments.pareto`: {meta['elapsed_s']:.0f} s in its last run, "
            f"`{meta['provenance']['command']}`.)")
    named = set(res.csv("pareto_cheapest.csv").setting.dropna())
    return "\n\n".join([head, cheapest(res), ties(table, named), drake(res, table),
                        grid(table, meta),
                        bullets([line(res, table), aligned(res, table), *knob_points(res)])])


def _setting(text: str) -> str:
    """'iterations 1, dt = 1e-05 s' -> 'iterations 1, dt = 10 us'."""
    m = re.search(r"dt = ([0-9.e+-]+) s", text)
    return text if not m else text.replace(m.group(0), f"dt = {step(float(m.group(1)))}")


def cheapest(res: Results) -> str:
    best = res.csv("pareto_cheapest.csv")
    rows = []
    for target, g in best.groupby("target", sort=False):
        top = g[g.engine == "any"].iloc[0]
        each = g[(g.engine != "any") & (g.engine != top.winner)]
        reach = [f"{label(r.engine)} {_setting(r.setting)} ({secs(r.wall_per_collision_s)})"
                 for r in each.itertuples() if isinstance(r.winner, str)]
        none = [label(r.engine) for r in each.itertuples() if not isinstance(r.winner, str)]
        rows.append({
            "max relative error": sci(target, 1),
            "cheapest of all": f"{label(top.winner)}, {_setting(top.setting)}",
            "its error, cost per collision": f"{sci(top.max_rel_err)}, "
                                             f"{secs(top.wall_per_collision_s)}",
            "each engine's cheapest (cost)": "; ".join(reach)
            + (f"; {names(none)}: none" if none else "")})
    return ("**The cheapest engine and setting for an accuracy** (max relative error of v1 "
            "against rigid theory over the mid-step grid, every impact sound; "
            "`results/pareto_cheapest.csv`, cost per collision = "
            f"{secs(study.WINDOW_S)} of approach plus the contact, medians of one run):\n\n"
            + md_table(pd.DataFrame(rows)))


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
        found += [f"{label(e)}'s {' = '.join(fams)}" for fams in groups.values()
                  if len(fams) > 1 and any(n.startswith(f"{f}, dt") for f in fams for n in named)]
    if not found:
        return ""
    return (f"Solver knobs that do nothing here make ties ({'; '.join(found)} give the same "
            "errors at every step): the table names whichever was cheapest in this run.")


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
            f"{label(e)} reaches {'none of them' if reached.empty else 'some of them'} by "
            "design: its Hunt-Crossley contact is a different model (e falls with speed), at "
            f"least {pct_of(d.max_rel_err.min())} from rigid theory on this grid at any step. "
            "Against its own law it converges: "
            + (f"its continuous mode at accuracy {gnum(swing.setting(e, 'accuracy'))} is "
               f"within {sci(cont.law_err_at_dt_min.iloc[0])} relative (set by the grid's "
               "barrel-end point, where the ball slides onto the cap during the contact and the "
               "law's infinite cylinder does not follow it), " if len(cont) else "")
            + "its discrete approximations are first order (`p_law` "
            + names(f"{p} {names(f)}" for p, f in laws.items()) + ", `convergence.csv`).")
    return " ".join(out)


def _acc(x) -> str:
    return f"{x:g}"  # as the family's name spells it


def pct_of(x: float) -> str:
    return f"{num(100 * x)}%"


def grid(table: pd.DataFrame, meta: dict) -> str:
    dts = sorted(table[~table.family.isin([DEFAULT, ALIGNED])].dt_s.unique())
    fams = [f"{label(e)}: {' / '.join(f for f in g.family.unique() if f not in (DEFAULT, ALIGNED))}"
            for e, g in table.groupby("engine", sort=False)]
    s = meta["grid_s_m"]
    return (f"Every engine over the knob families its record declares, each at {len(dts)} time "
            f"steps from {step(dts[0])} to {step(dts[-1])}, plus its default profile (also at "
            f"its own step): {'; '.join(fams)}. The paper's swing is fired at {len(s)} points "
            f"over s in [{s[0]:g}, {s[-1]:g}] m with the contact instant at "
            f"{meta['contact_phase']:g} of a step (what a simulation that does not align "
            "contacts meets on average), and the cost is the wall time to simulate "
            f"{secs(study.WINDOW_S)} of approach plus the contact (`results/pareto.csv`: median "
            f"and max relative error of v1, median wall per collision over {meta['repeats']} "
            "repeats, counts of every status).")


def _reference_family(table: pd.DataFrame, engine: str) -> str:
    """An engine's first knob family: its reference solver."""
    fams = [f for f in table[table.engine == engine].family.unique() if f not in (DEFAULT,
                                                                                  ALIGNED)]
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
    f64 = [(e, _reference_family(t, e)) for e in swing.of_precision("float64")
           if e in set(t.engine)]  # those the pareto study ran
    errs = [_errors(t, e, f) for e, f in f64]
    ref = errs[0]
    same = all(np.allclose(x.reindex(ref.index), ref, rtol=1e-3) for x in errs)
    at = [d for d in (1e-3, 1e-4, 1e-5, 1e-6) if d in ref.index]
    c = conv[(conv.engine == f64[0][0]) & (conv.family == f64[0][1])].iloc[0]
    cost = {e: t[(t.engine == e) & (t.family == f) & (t.dt_s <= 1e-5)].per_step_us.median()
            for e, f in f64}
    order = sorted(cost, key=cost.get)
    text = (f"**The {count(len(f64))} float64 impulse-type solvers sit on one line**: "
            + names(f"{label(e)} ({f})" for e, f in f64)
            + f" give {'the same' if same else 'about the same'} error at the same step (max "
            f"relative error {names(f'{sci(ref[d])} at {step(d)}' for d in at)}), first order "
            f"in dt (fitted p = {c.p:.2f}, r^2 = {c.r2:.2f}, `results/convergence.csv`): the "
            "contact is seen half a step late while the bat turns. They differ in cost per "
            f"step: {label(order[0])} is cheapest, then {names(label(e) for e in order[1:])}.")
    f32 = [e for e in swing.of_precision("float32") if e in set(t.engine)]
    joined = [(e, *_joins(t, e, ref)) for e in f32]
    joined = [(e, f, d) for e, f, d in joined if f]
    if joined:
        text += (" " + names(f"{label(e)} ({f}, down to {step(d)})" for e, f, d in joined)
                 + " join the same line (within a factor "
                 f"{SAME_LINE:g}): they too see the contact from a step's geometry.")
    for e in f32:
        c = conv[(conv.engine == e) & (conv.family == _reference_family(t, e))]
        if len(c) and c.err_at_dt_min.iloc[0] > 10 * ref.get(c.dt_min_s.iloc[0], math.inf):
            text += (f" {label(e)}'s reference solver levels off at "
                     f"{sci(c.err_at_dt_min.iloc[0])} (a contact made a step early).")
    small = t[(t.dt_s == t.dt_s.min()) & t.all_ok & t.engine.isin(swing.rigid)]
    low = small.loc[small.per_step_us.idxmin()]
    text += (f" The cheapest step of all is {label(low.engine)}'s ({low.family}, "
             f"{num(low.per_step_us)} us at {step(low.dt_s)}).")
    return text + " " + knees(t, swing)


def knees(t: pd.DataFrame, swing) -> str:
    each = []
    for e in [e for e in swing.rigid if e in set(t.engine)]:  # those the pareto study ran
        good = t[(t.engine == e) & t.all_ok & (t.family != ALIGNED)]
        times, errs = good.wall_per_collision_s.to_numpy(), good.max_rel_err.to_numpy()
        front = study.pareto_front(times, errs)
        k = front[study.knee(times[front], errs[front])]
        r = good.iloc[k]
        each.append(f"{label(e)} {r.family}, dt = {step(r.dt_s)} ({sci(r.max_rel_err)} in "
                    f"{secs(r.wall_per_collision_s)})")
    return ("Knees of the fronts (farthest from the chord in log-log, circled on the chart): "
            + "; ".join(each) + "; the knee moves between neighbouring steps from run to run, "
            "as the timings do.")


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
    return (f"**Aligning the contact with a step** (the reference profile's placement, stars) "
            f"buys {span(low, max(g[0] for g in gains), str)} orders of magnitude at the same "
            f"cost in {engines_text(f64)}: {sci(max(g[1] for g in gains))} at dt = "
            f"{step(gains[0][2])}.")
