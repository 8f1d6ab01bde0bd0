"""Each engine out of the box: what it catches at its own step, and which default costs what."""

from __future__ import annotations

import math

import numpy as np
import pandas as pd

import adapters
from analytic import presets

from ..core.judge import Status
from .base import Results, dist, engines_text, label, lead, names, num, pct, span, step
from .data import need

REACH_M = presets.R161.radius_m + presets.BASEBALL.radius_m


def _record_default(engine: str, knob: str):
    try:
        return adapters.record(engine).engine_defaults.get(knob)
    except ValueError:
        return None


def out_of_the_box(res: Results) -> str:
    caught = res.csv("defaults_caught.csv")
    meta = res.json("defaults.json")
    (swing, default) = need(res, "swing", "default")
    pitch = swing.model.iloc[0]
    grid = np.asarray(meta["grid_s_m"])
    vc = pitch.v0_mps + pitch.u0_mps + pitch.omega0_radps * grid
    rigid = caught[caught.engine.isin(swing.rigid)]
    travel = (vc.min() * rigid.dt_s.min(), vc.max() * rigid.dt_s.max())
    steps = "; ".join(
        f"{step(dt)} in {engines_text(g.engine)}"
        for dt, g in rigid.sort_values("dt_s", ascending=False).groupby("dt_s", sort=False)
    )
    each = [
        _caught(g, pitch.omega0_radps)
        for _, g in rigid.assign(rel=np.sign(rigid.ok - rigid.theory_ok) + (rigid.ok == 0)).groupby(
            ["dt_s", "fraction_theory", "rel"], sort=False
        )
    ]
    facts = [
        f"their own time steps: {steps}",
        f"the ball moves {span(*travel)} m per step there",
        f"so only a contact first seen less than R = r_ball + r_bat = {dist(REACH_M, 3)} "
        "deep can be caught: a share R/(v_c dt) of contact instants",
        lead(
            f"caught over {meta['phases']} contact phases x {len(grid)} points of the "
            "paper's swing (`results/defaults_caught.csv`):",
            each,
        ),
    ]
    facts += [
        f"{label(r.engine)}'s compliant contact at {step(r.dt_s)} misses only "
        f"{pct(1 - r.fraction_ok)} (its contact lasts longer than a step), but is "
        f"{pct(r.max_rel_err_caught)} from rigid theory there (its law, judged no "
        "further: a step of most of a contact)"
        for r in caught[caught.engine.isin(swing.compliant)].itertuples()
    ]
    none = [e for e in default.rigid if default.counts(e).get(Status.OK, 0) == 0]
    if none:
        who = (
            "none catches any"
            if len(none) == len(default.rigid)
            else f"{engines_text(none)} catch none"
        )
        facts.append(
            f"with the contact mid-step, the default profiles' placement (`{default.stem}`): {who}"
        )
    return lead(
        "**Out of the box, they catch only the contacts that fall early in a step** "
        "(`python -m experiments.defaults`, `results/defaults_*.csv`):",
        facts,
    )


def _caught(g: pd.DataFrame, omega0: float) -> str:
    """Engines alike at one step: their share caught, against the bound's."""
    r = g.iloc[0]
    who = names(
        f"{label(x.engine)} {pct(x.fraction_ok, 3)}"
        + (
            f" (errors up to {pct(x.max_rel_err_caught)})"
            if x.ok and math.isfinite(x.max_rel_err_caught)
            else ""
        )
        for x in g.itertuples()
    )
    text = f"{who} ok at {step(r.dt_s)} (the bound allows {pct(r.fraction_theory, 3)}"
    if r.ok == r.theory_ok:
        return text + ": exactly the bound)"
    if r.ok == 0:
        return text + "; the default contact lets even those through)"
    if r.ok < r.theory_ok:
        return text + (
            f"; the bat also turns {num(omega0 * r.dt_s)} rad per step, which the "
            "bound, a translation, does not see)"
        )
    return text + "; above it: a contact made ahead of touching catches some more)"


def _knobs(res: Results, engine: str) -> dict[str, list]:
    """The engine's knobs by what each does alone at the reference step, contact mid-step."""
    k = res.csv("defaults_knobs.csv")
    k = k[k.engine == engine]
    out = {
        "restores": [],
        "catches": [],
        "breaks": [],
        "base": k[k.change == "default profile"],
        "ref": k[k.change == "reference profile"],
    }
    for r in k.itertuples():
        knob = r.change.split(", ", 1)[-1].split(" = ")[0]
        if r.change.startswith("default, "):
            if r.within_tolerance == r.impacts:
                out["restores"].append((knob, r))
            elif r.ok == r.impacts and out["base"].ok.iloc[0] < r.impacts:
                out["catches"].append((knob, r))
        elif r.change.startswith("reference, ") and r.within_tolerance < r.impacts:
            out["breaks"].append((knob, r))
    return out


def small_step(res: Results) -> str:
    (sw,) = need(res, "default_dt")
    dt = sw.setting(sw.rigid[0], "dt_s")
    conv = res.csv("convergence.csv")
    pareto = res.csv("pareto.csv")
    good = [e for e in sw.rigid if sw.counts(e).get(Status.OK, 0) == len(sw.model)]
    errs = [sw.err(e) for e in good]
    facts = [
        f"the largest errors on the swing: {span(min(errs), max(errs))} m/s in "
        f"{engines_text(sorted(good, key=sw.err))}, every impact `ok`"
        if good
        else "",
        "the mid-step contact is seen late, tilted by the bat's turn",
    ]
    for e in sw.rigid:
        knobs = _knobs(res, e)
        if (
            knobs["base"].empty
            or knobs["base"].within_tolerance.iloc[0] == knobs["base"].impacts.iloc[0]
        ):
            continue
        facts.append(_failing_default(e, sw, knobs, conv, pareto))
    return lead(
        f"**With a small step but default solver values** (dt = {step(dt)}, contact "
        f"mid-step: `{sw.stem}`):",
        facts,
    )


def _failing_default(e: str, sw, knobs: dict, conv: pd.DataFrame, pareto: pd.DataFrame) -> str:
    base, ref = knobs["base"].iloc[0], knobs["ref"].iloc[0]
    rows = sw.rows(e)
    if sw.counts(e).get(Status.INACCURATE, 0) == len(rows):
        rel = (rows.v1_engine_mps - rows.v1_analytic_mps) / rows.v1_analytic_mps.abs()
        way = "high" if (rel > 0).all() else "off"
        head = (
            f"**{label(e)}**'s v1 is {pct(rel.abs().median())} too {way} there (median over "
            f"the points)"
        )
    else:
        counts = sw.counts(e)
        head = (
            f"**{label(e)}** lets {counts.get(Status.TUNNELLED, 0)} of {len(rows)} through "
            f"there ({', '.join(f'{k} {v}' for k, v in counts.items())})"
        )
    facts = []
    fix = [k for k, _ in knobs["restores"]]
    brk = [k for k, _ in knobs["breaks"]]
    if fix and set(fix) == set(brk):
        value = _record_default(e, fix[0])
        facts.append(
            f"its `{fix[0]}` alone does it (every other default alone changes "
            f"nothing at {step(base.dt_s)}): put back, max relative error "
            f"{num(knobs['restores'][0][1].max_rel_err)}, the reference profile's "
            f"{num(ref.max_rel_err)} (`defaults_knobs.csv`)"
        )
        if value is not None:
            facts.append(
                f"the engine does not report it: {fix[0]} = {value:g} set explicitly "
                "reproduces its default solver bit for bit (a value measured, not the "
                "one often quoted; `tests/test_engine_defaults.py` pins it)"
            )
    elif knobs["catches"]:
        knob, r = knobs["catches"][0]
        facts.append(
            f"at {step(r.dt_s)}, its reference `{knob}` alone catches every impact, "
            f"with errors up to {pct(r.max_rel_err)} (`defaults_knobs.csv`)"
        )
    fam = conv[(conv.engine == e) & (conv.family == "default profile")]
    if len(fam) and math.isfinite(fam.p.iloc[0]):
        facts.append("smaller steps help little: see [Speed vs accuracy](#speed-vs-accuracy)")
    dp = pareto[(pareto.engine == e) & (pareto.family == "default profile")]
    if len(dp) and (dp.n_ok == 0).all():
        facts.append(
            f"not one impact `ok` at any step from {step(dp.dt_s.min())} to {step(dp.dt_s.max())}"
        )
    return lead(head, facts)
