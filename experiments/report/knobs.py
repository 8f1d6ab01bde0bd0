"""Speed against accuracy, knob by knob: iterations, soft contacts, integrators, defaults."""

from __future__ import annotations

import re

import numpy as np
import pandas as pd

from .base import (
    Results,
    alike,
    engines_text,
    label,
    lead,
    names,
    pct,
    sci,
    span,
    step,
    times,
)
from .data import need

ALIGNED = "reference profile (aligned)"
DEFAULT = "default profile"


def knob_points(res: Results) -> list[str]:
    table = res.csv("pareto.csv")
    conv = res.csv("convergence.csv")
    return [
        *iterations(table, conv, res.csv("defaults_knobs.csv")),
        *soft(res, table, conv),
        integrator_fails(table),
        out_of_the_box(res, table),
    ]


def _errs(table: pd.DataFrame, engine: str, family: str) -> pd.Series:
    d = table[(table.engine == engine) & (table.family == family)]
    return d.set_index("dt_s").max_rel_err


def iterations(table: pd.DataFrame, conv: pd.DataFrame, knobs: pd.DataFrame) -> list[str]:
    """Iteration counts that change nothing; default solver values that cost at every step."""
    same = []
    for e, g in table[table.family.str.contains("iteration")].groupby("engine", sort=False):
        fams = list(g.family.unique())
        errs = [_errs(table, e, f) for f in fams]
        if len(fams) > 1 and all(np.allclose(x, errs[0], equal_nan=True) for x in errs):
            counts = [m.group(0) for f in fams if (m := re.search(r"\d+", f))]
            same.append(f"{label(e)} {' = '.join(counts)}")
    out = (
        [
            lead(
                "**Solver iterations do nothing** for one frictionless contact (identical "
                "errors at every step):",
                same,
            )
        ]
        if same
        else []
    )
    for r in conv[conv.family == DEFAULT].itertuples():
        base = conv[(conv.engine == r.engine) & (conv.family != DEFAULT)]
        if len(base) and r.err_at_dt_min > 100 * base.err_at_dt_min.min():
            lo, hi = sorted((r.err_at_dt_min, r.err_at_dt_max))
            out.append(
                lead(
                    f"**{label(r.engine)}'s default solver values** cost "
                    f"{span(100 * lo, 100 * hi)}% "
                    "at every step:",
                    [
                        f"{pct(r.err_at_dt_max)} at {step(r.dt_max_s)}, {pct(r.err_at_dt_min)} at "
                        f"{step(r.dt_min_s)} (p = {r.p:.2f})",
                        _culprit(knobs, r.engine),
                    ],
                )
            )
    return out


def _culprit(knobs: pd.DataFrame, engine: str) -> str:
    """'all of it from K' where the default with K alone put back errs like the reference."""
    k = knobs[knobs.engine == engine]
    ref = k[k.change == "reference profile"].max_rel_err
    if ref.empty:
        return ""
    back = [
        c.split(", ", 1)[1].split(" = ")[0]
        for c, err in zip(k.change, k.max_rel_err)
        if c.startswith("default, ") and err <= 1.1 * ref.iloc[0]
    ]
    if not back:
        return ""
    return (
        f"all of it from its {names((f'`{b}`' for b in back), 'or')}: put back alone, "
        f"{'it gives' if len(back) == 1 else 'each gives'} the reference profile's error "
        "(`defaults_knobs.csv`)"
    )


def _soft(conv: pd.DataFrame, engine: str) -> pd.DataFrame:
    c = conv[(conv.engine == engine) & conv.family.str.match(r"soft w=\d+")].copy()
    c["w"] = c.family.str.extract(r"w=(\d+)")[0].astype(float)
    c["integrator"] = c.family.str.split(", ").str[-1]
    return c


def soft(res: Results, table: pd.DataFrame, conv: pd.DataFrame) -> list[str]:
    """What every soft contact does (said once, ``SOFT_LEAD``), then each engine's numbers
    (engines with the same numbers together)."""
    (swing,) = need(res, "swing")
    said = []
    for e in swing.rigid:
        c = _soft(conv, e)
        if c.empty:
            continue
        fit = c[c.r2 >= 0.95]
        wall = table[(table.engine == e) & table.family.str.match(r"soft w=\d+")].copy()
        wall["integrator"] = wall.family.str.split(", ").str[-1]
        wall["w"] = wall.family.str.extract(r"w=(\d+)")[0]
        piv = wall.pivot_table(
            index=["dt_s", "w"],
            columns="integrator",
            dropna=False,
            values=["wall_per_collision_s", "max_rel_err"],
        )
        facts = [
            f"against rigid theory it leaves "
            f"{span(c.err_at_dt_min.min(), c.err_at_dt_min.max())} at the smallest step "
            f"(fitted p {span(c.p.min(), c.p.max(), lambda v: f'{v:.2f}', ' to ')}; "
            + (
                names(
                    f"{r.family} fits a power law well, r^2 = {r.r2:.2f}, and it too "
                    f"levels off near {sci(r.err_at_dt_min, 1)}"
                    for r in fit.itertuples()
                )
                if len(fit)
                else "none fits a power law well"
            )
            + ")",
            *_integrators(piv["wall_per_collision_s"], piv["max_rel_err"]),
            *own_law(c),
        ]
        said.append((e, "\n".join(facts)))
    out = [
        lead(
            f"**{names(f'{label(e)}' for e in who)}: soft contact"
            + ("s**:" if len(who) > 1 else "**:"),
            text.split("\n"),
        )
        for who, text in alike(said)
    ]
    return [SOFT_LEAD, *out] if out else out


#: What every soft contact of the MuJoCo family does, said once before each engine's numbers.
SOFT_LEAD = lead(
    "**A soft contact does not converge to the impulse model, but to its own law**:",
    [
        "a spring-damper in contact space, m_eff (w^2 x + 2 zeta w x') with m_eff at the "
        "current contact point (`ErrorModel.contact_law`, "
        "`analytic.compliant.ContactSpaceSpringDamper`)",
        "its finite contact time while the bat turns is a model error no step removes",
        "its v1 approaches its law at about first order (a test checks the order for every "
        "soft contact an engine declares: "
        "`tests/test_adapters_semantics.py::test_soft_contact_converges_to_its_own_law`)",
        "the chart draws each soft setting twice: a dot against rigid theory, a hollow diamond "
        "against its own law (`max_law_rel_err` in `results/pareto.csv`; fitted orders `p_law` "
        "in `results/convergence.csv`)",
    ],
)


def _integrators(t: pd.DataFrame, err: pd.DataFrame) -> list[str]:
    """RK4's and implicitfast's cost and error beside Euler's, where the engine ran them."""
    if not {"RK4", "Euler", "implicitfast"} <= set(t.columns):
        return []
    cost = (t["RK4"] / t["Euler"]).median()
    worse = int((err["RK4"] > err["Euler"]).sum())
    both = int(err[["RK4", "Euler"]].notna().all(axis=1).sum())
    same = np.allclose(err["implicitfast"], err["Euler"], equal_nan=True)
    implicit = (t["implicitfast"] / t["Euler"]).median()
    return [
        f"RK4 costs {times(cost, 1)} Euler and its max error is the larger at {worse} of "
        f"{both} settings",
        f"implicitfast gives {'Euler' if same else 'about Euler'}'s numbers at "
        f"{times(implicit, 1)} its cost",
    ]


def own_law(c: pd.DataFrame) -> list[str]:
    """The fitted orders against its own law (``p_law``): at the middle stiffness, then the
    others."""
    mid = c[c.w == c.w.median()]
    rest = c[c.w != c.w.median()]
    at = names(f"{r.p_law:.2f} for {r.integrator}" for r in mid.itertuples())
    return [
        f"against its own law: order {at} at w = {mid.w.iloc[0]:g} rad/s",
        f"orders {span(rest.p_law.min(), rest.p_law.max(), lambda v: f'{v:.2f}')} at w = "
        f"{names(f'{w:g}' for w in sorted(rest.w.unique()))} rad/s, where the grid's "
        "deepest contacts approach the sinking limit w = v/R or the step w dt = 0.1"
        if len(rest)
        else "",
    ]


def integrator_fails(table: pd.DataFrame) -> str:
    out = []
    for (e, fam), g in table[~table.family.isin([DEFAULT, ALIGNED])].groupby(
        ["engine", "family"], sort=False
    ):
        if not g.all_ok.any() and g.n_ok.sum() == 0:
            counts = {
                c[2:]: int(g[c].sum()) for c in g.columns if c.startswith("n_") and g[c].sum()
            }
            why = (
                "; an impulse mapping assumes one explicit step"
                if "impulse" in fam and "RK4" in fam
                else ""
            )
            out.append(
                f"{label(e)}'s {fam}: " + ", ".join(f"{k} {v}" for k, v in counts.items()) + why
            )
    return lead("**Some settings fail at every step**:", out) if out else ""


def out_of_the_box(res: Results, table: pd.DataFrame) -> str:
    (swing,) = need(res, "swing")
    caught = res.csv("defaults_caught.csv")
    own = []
    for e, g in table[table.family == DEFAULT].groupby("engine", sort=False):
        dt = caught[caught.engine == e].dt_s
        if len(dt):
            row = g.loc[(g.dt_s - float(dt.iloc[0])).abs().idxmin()]
            own.append(row)
    own = pd.DataFrame(own)
    rigid = own[own.engine.isin(swing.rigid)]
    lost = rigid[rigid.n_ok == 0]
    steps = names(step(d) for d in sorted(set(own.dt_s)))
    every = "every" if len(lost) == len(rigid) else "nearly every"
    facts = [
        f"{engines_text(lost.engine)} catch none",
        "with random contact instants: see [the baseline "
        "sweeps](#baseline-sweeps-and-what-they-show)",
    ]
    for r in own[own.engine.isin(swing.compliant)].itertuples():
        missed = r.n_tunnelled + r.n_non_finite
        facts.append(
            f"{label(r.engine)}'s {step(r.dt_s)} default misses "
            f"{'nothing' if missed == 0 else f'{missed} of {r.impacts}'} but is "
            f"{pct(r.max_rel_err)} from rigid theory and too coarse for its own law "
            "(fewer than ten steps per contact: `unjudged`)"
        )
    return lead(
        f"**Out of the box** ({steps}), with the contact mid-step, {every} "
        "rigid-contact engine fails:",
        facts,
    )
