"""The baseline sweeps: the committed summary, the charts, and what they show."""

from __future__ import annotations

import numpy as np
import pandas as pd

from ..core.judge import Status
from .base import (
    Results,
    bullets,
    count,
    dist,
    engines_text,
    label,
    names,
    num,
    orders,
    secs,
    span,
    step,
)
from .data import ROLES, baselines, need
from .defaults import out_of_the_box, small_step


def section(res: Results) -> str:
    charts = [res.chart(f"{sw.stem}.png", f"v1 along the R161: {ROLES[role][1]}") + "\n\n"
              f"*{ROLES[role][1].capitalize()}* (`{sw.stem}.*`)."
              for role, sw in baselines(res).items()]
    points = [agreement(res), plastic(res), tuned(res), out_of_the_box(res), small_step(res)]
    return "\n\n".join([
        "Everything in `results/` is written by `python -m experiments.baselines`, which runs "
        "the baseline sweeps and every study below into it. The baseline sweeps' statuses, "
        "errors and costs, one row per baseline and engine, are in [summary.md](summary.md); "
        "each engine's own numbers on its [page](engines.md). What they show:", bullets(points),
        *charts])


def agreement(res: Results) -> str:
    swing, still, hinged = need(res, "swing", "still", "hinged")
    f64, f32 = swing.of_precision("float64"), swing.of_precision("float32")
    kinds = sum(bool(g) for g in (f64, f32, swing.compliant))
    common_dt = pd.Series([swing.setting(e, "dt_s") for e in swing.engines]).mode()[0]
    text = f"**{count(len(swing.engines), True)} engines, {count(kinds)} kinds of agreement.** "
    if f64:
        each = [f"{label(e)} {num(swing.err(e))} m/s" for e in sorted(f64, key=swing.err)]
        text += (f"The float64 impulse engines reproduce rigid-body theory on the swing: "
                 f"{names(each)} (on a still bat to "
                 f"{num(max(still.err(e) for e in f64))} m/s at most). ")
    if f32 and f64:
        best = min(swing.err(e) for e in f64)
        each = [f"{label(e)} {num(swing.err(e))} m/s"
                + ("" if swing.setting(e, "dt_s") == common_dt
                   else f" (at a {step(swing.setting(e, 'dt_s'))} step)")
                for e in sorted(f32, key=swing.err)]
        lo, hi = (orders(min(swing.err(e) for e in f32), best),
                  orders(max(swing.err(e) for e in f32), best))
        text += (f"The float32 engines land within their tolerance, {span(lo, hi, str)} orders "
                 f"of magnitude behind the best float64 one: {names(each)} on the swing (the "
                 "section on engines gives each one's cause: a speculative contact solved from "
                 "the geometry at the start of the step that closes it, or a stiff solve). ")
    for e in swing.compliant:
        text += (f"{label(e)} is a different model: its Hunt-Crossley contact's e falls with "
                 f"speed, {num(swing.err(e))} m/s from rigid theory on the swing by design, and "
                 f"within {num(swing.law_err(e))} m/s of its own law (the summary's law "
                 "column). ")
    errs = {e: hinged.err(e) for e in hinged.rigid}
    top = sorted(errs, key=errs.get, reverse=True)[:len(f32)]
    where = ("the float32 engines at the top" if f32 and set(top) == set(f32)
             else f"largest: {engines_text(top[:1])}")
    text += (f"With a swing in the engine first, the {count(len(errs))} rigid-contact engines "
             f"reproduce theory to {span(min(errs.values()), max(errs.values()))} m/s "
             f"({where}: see Swing dynamics)")
    laws = [f"{label(e)} its law to {num(hinged.law_err(e))} m/s" for e in hinged.compliant]
    return text + (", " + names(laws) if laws else "") + "."


def plastic(res: Results) -> str:
    (sw,) = need(res, "plastic")
    m = sw.model
    n = len(m)
    held = m[m.rigid_sustained_s > 0]
    ends = held[held.rigid_end != "time_limit"]
    first, longest = ends.loc[ends.s_m.idxmin()], ends.loc[ends.rigid_sustained_s.idxmax()]
    again = m[m.rigid_impacts > 1].s_m.tolist()
    jump = (m.v1_analytic_mps - m.v1_impulse_mps).abs().max()
    text = (f"**A plastic impact (e = 0) is not one impulse, and the engines know it.** On the "
            f"paper's swing {'every one' if len(held) == n else len(held)} of the {n} points "
            "has sustained contact after the plastic impulse (the ball rides the turning bat "
            f"for {secs(first.rigid_sustained_s)} "
            f"at the knob end, s = {first.s_m:g} m, up to {secs(longest.rigid_sustained_s)} at "
            f"s = {longest.s_m:g} m")
    if again:
        text += f"; at s = {names(f'{s:g}' for s in again)} m the bat catches it a second time"
    text += (f"), and the rigid episode's v1 differs from the single impulse by up to "
             f"{num(jump)} m/s. ")
    ok = {e: sw.counts(e).get(Status.OK, 0) for e in sw.rigid}
    ratio = {e: float((r.v1_abs_err_mps / r.v1_tol_mps)[r.status == Status.OK].max())
             for e in sw.rigid for r in [sw.rows(e)]}
    by_err: dict[str, list[str]] = {}
    for e in sorted(sw.rigid, key=sw.err):
        by_err.setdefault(num(sw.err(e)), []).append(label(e))
    worst = [f"{err} m/s in {names(group)}" for err, group in by_err.items()]
    best_ratio = ratio[min(sw.rigid, key=sw.err)]
    okays = (f"{next(iter(ok.values()))} of {n} points `ok`" if len(set(ok.values())) == 1
             else names(f"{label(e)} {k} of {n} `ok`" for e, k in ok.items()))
    text += (f"All {count(len(sw.rigid))} rigid-contact engines follow the episode: {okays} (worst "
             f"{worst[0]}, {num(best_ratio)} of its tolerance; {'; '.join(worst[1:])}; "
             f"each within its own, at most {num(max(ratio.values()))} of it)")
    stuck = sw.table[(sw.table.engine.isin(sw.rigid)) & (sw.table.status == Status.NO_SEPARATION)]
    if len(stuck):
        s = np.unique(stuck.s_m)
        also = (stuck.rigid_end == "time_limit").all()
        text += (f"; the other {len(s)} (s = {span(s.min(), s.max(), lambda v: f'{v:g}')} m) are "
                 f"still in contact after the {secs(sw.setting(sw.rigid[0], 'max_contact_s'))} "
                 "budget" + (", as the rigid bodies are (`rigid_end = time_limit`)" if also
                             else ""))
    text += ". "
    for e in sw.compliant:
        rows = sw.rows(e)
        unjudged = rows[rows.status == Status.UNJUDGED].s_m
        at_ends = set(unjudged) <= {m.s_m.min(), m.s_m.max()}
        text += (f"{label(e)} floors e (a Hunt-Crossley contact cannot be plastic: `E_FLOOR` in "
                 f"`adapters/{e}`) and is judged against its law where one contact is the whole "
                 f"episode ({sw.counts(e).get(Status.OK, 0)} of {n}, within "
                 f"{num(sw.law_err(e))} m/s; the {len(unjudged)} "
                 + ("at the cylinder's ends, where the ball slides onto a cap during the "
                    "contact, " if at_ends and len(unjudged) else "others ")
                 + "`unjudged`).")
    return text


def tuned(res: Results) -> str:
    swing, still = need(res, "swing", "still")
    f64 = swing.of_precision("float64")
    if not f64:
        return ""
    rest = max(still.err(e) for e in f64)
    rounding = "to rounding " if rest < 1e-12 else ""
    same = len({f"{swing.err(e):.3g}" for e in f64}) == 1
    m = swing.model
    marks = swing.meta["analytic"]
    near = m.loc[(m.s_m - marks["sweet_spot_m"]).abs().idxmin()].s_m
    rows = swing.rows(f64[0])
    inner = rows.iloc[:-1]  # the cylinder's end is a case of its own (see Swing dynamics)
    low = inner.loc[inner.v1_abs_err_mps.idxmin()].s_m
    where = (f"it is smallest at s = {low:g} m, the grid point nearest the sweet spot "
             f"at {marks['sweet_spot_m']:.3f} m" if low == near
             else f"it is smallest at s = {low:g} m")
    where += (f", and {num(rows.v1_abs_err_mps.iloc[-1])} m/s at the cylinder's end, where "
              "the contact point cannot slide")
    ss = max(abs(swing.summary(e)["sweet_spot_engine_m"] - marks["sweet_spot_m"]) for e in f64)
    cop = max(abs(swing.summary(e)["cop_engine_m"] - marks["cop_m"]) for e in f64)
    overlap = swing.setting(f64[0], "overlap_m")
    return (f"**Tuned, the {count(len(f64))} float64 impulse engines reproduce rigid-body impact "
            f"theory**: {rounding}({num(rest)} m/s) for a bat at rest, to "
            f"{num(max(swing.err(e) for e in f64))} m/s for the swinging bat. The swinging error "
            f"is the harness's own: the contact is first seen {dist(overlap)} deep (`overlap_m`), "
            "by which time the turning bat has slid the contact foot along its axis by "
            "(r_bat + r_ball) omega0 delta / v_c; the error follows |dv1/ds| "
            f"({where}), is {'the same in all of them' if same else 'alike in all of them'} "
            f"and scales with `overlap_m`. Each engine locates the sweet spot within {dist(ss)} "
            f"and the COP within {dist(cop)} of theory.")
