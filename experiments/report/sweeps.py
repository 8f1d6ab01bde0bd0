"""The baseline sweeps: the committed summary, the charts, and what they show."""

from __future__ import annotations

import numpy as np

from ..core.judge import Status
from .base import (
    Results,
    bullets,
    count,
    dist,
    engines_text,
    label,
    lead,
    names,
    num,
    orders,
    secs,
    span,
)
from .data import ROLES, baselines, need
from .defaults import out_of_the_box, small_step


def section(res: Results) -> str:
    charts = [
        res.chart(f"{sw.stem}.png", f"v1 along the R161: {ROLES[role][1]}") + "\n\n"
        f"*{ROLES[role][1].capitalize()}* (`{sw.stem}.*`)."
        for role, sw in baselines(res).items()
    ]
    points = [agreement(res), plastic(res), tuned(res), out_of_the_box(res), small_step(res)]
    return "\n\n".join(
        [
            "Everything in `results/` is written by `python -m experiments.baselines`. The "
            "baseline "
            "sweeps' statuses, errors and costs, per baseline and engine: "
            "[summary.md](summary.md); "
            "each engine's own numbers: its [page](engines.md). What they show:",
            bullets(points),
            *charts,
        ]
    )


def agreement(res: Results) -> str:
    swing, hinged = need(res, "swing", "hinged")
    f64, f32 = swing.of_precision("float64"), swing.of_precision("float32")
    kinds = sum(bool(g) for g in (f64, f32, swing.compliant))
    facts = []
    if f64:
        errs = [swing.err(e) for e in f64]
        facts.append(
            f"float64 impulse engines ({engines_text(sorted(f64, key=swing.err))}): "
            f"rigid-body theory to {span(min(errs), max(errs))} m/s on the swing"
        )
    if f32 and f64:
        best = min(swing.err(e) for e in f64)
        errs = [swing.err(e) for e in f32]
        facts += [
            f"float32 engines ({engines_text(sorted(f32, key=swing.err))}): "
            f"{span(min(errs), max(errs))} m/s on the swing, within their tolerance, "
            f"{span(orders(min(errs), best), orders(max(errs), best), str)} orders of "
            "magnitude behind the best float64 one",
            "their cause (the section on engines gives each one's): a speculative "
            "contact solved from the geometry at the start of the step that closes it, or "
            "a stiff solve",
        ]
    facts += [
        f"{label(e)} is a different model: its Hunt-Crossley contact's e falls with "
        f"speed: {num(swing.err(e))} m/s from rigid theory on the swing by design, within "
        f"{num(swing.law_err(e))} m/s of its own law"
        for e in swing.compliant
    ]
    errs = {e: hinged.err(e) for e in hinged.rigid}
    top = sorted(errs, key=errs.get, reverse=True)[: len(f32)]
    where = (
        "the float32 engines at the top"
        if f32 and set(top) == set(f32)
        else f"largest: {engines_text(top[:1])}"
    )
    laws = [f"{label(e)} its law to {num(hinged.law_err(e))} m/s" for e in hinged.compliant]
    facts.append(
        f"with a swing in the engine first: the {count(len(errs))} rigid-contact "
        f"engines reproduce theory to {span(min(errs.values()), max(errs.values()))} "
        f"m/s ({where}: see Swing dynamics)" + ("; " + names(laws) if laws else "")
    )
    return lead(
        f"**{count(len(swing.engines), True)} engines, {count(kinds)} kinds of agreement**:", facts
    )


def plastic(res: Results) -> str:
    (sw,) = need(res, "plastic")
    m = sw.model
    n = len(m)
    held = m[m.rigid_sustained_s > 0]
    ends = held[held.rigid_end != "time_limit"]
    first, longest = ends.loc[ends.s_m.idxmin()], ends.loc[ends.rigid_sustained_s.idxmax()]
    again = m[m.rigid_impacts > 1].s_m.tolist()
    jump = (m.v1_analytic_mps - m.v1_impulse_mps).abs().max()
    facts = [
        f"on the paper's swing {'every one' if len(held) == n else len(held)} of the {n} "
        "points has sustained contact after the plastic impulse",
        f"the ball rides the turning bat for {secs(first.rigid_sustained_s)} at the knob "
        f"end (s = {first.s_m:g} m), up to {secs(longest.rigid_sustained_s)} at "
        f"s = {longest.s_m:g} m",
        f"at s = {names(f'{s:g}' for s in again)} m the bat catches it a second time"
        if again
        else "",
        f"the rigid episode's v1 differs from the single impulse by up to {num(jump)} m/s",
    ]
    return lead(
        "**A plastic impact (e = 0) is not one impulse, and the engines know it.**",
        facts + _plastic_engines(sw),
    )


def _plastic_engines(sw) -> list[str]:
    """How the engines follow the plastic episode: ok counts, errors against tolerance."""
    n = len(sw.model)
    ok = [sw.counts(e).get(Status.OK, 0) for e in sw.rigid]
    ratio = {
        e: float((r.v1_abs_err_mps / r.v1_tol_mps)[r.status == Status.OK].max())
        for e in sw.rigid
        for r in [sw.rows(e)]
    }
    low, high = min(sw.rigid, key=sw.err), max(sw.rigid, key=sw.err)
    tied = [e for e in sw.rigid if num(sw.err(e)) == num(sw.err(low))]
    facts = [
        f"all {count(len(sw.rigid))} rigid-contact engines follow the episode: "
        f"{span(min(ok), max(ok), str)} of {n} `ok` each",
        f"their worst errors: {num(sw.err(low))} m/s ({engines_text(tied)}, "
        f"{num(ratio[low])} of its tolerance) to {num(sw.err(high))} m/s "
        f"({label(high)}); each at most {num(max(ratio.values()))} of its tolerance",
    ]
    stuck = sw.table[(sw.table.engine.isin(sw.rigid)) & (sw.table.status == Status.NO_SEPARATION)]
    if len(stuck):
        s = np.unique(stuck.s_m)
        also = (stuck.rigid_end == "time_limit").all()
        facts.append(
            f"the other {len(s)} (s = {span(s.min(), s.max(), lambda v: f'{v:g}')} m) "
            f"are still in contact after the "
            f"{secs(sw.setting(sw.rigid[0], 'max_contact_s'))} budget"
            + (", as the rigid bodies are (`rigid_end = time_limit`)" if also else "")
        )
    for e in sw.compliant:
        rows = sw.rows(e)
        unjudged = rows[rows.status == Status.UNJUDGED].s_m
        at_ends = set(unjudged) <= {sw.model.s_m.min(), sw.model.s_m.max()}
        facts += [
            f"{label(e)} floors e (a Hunt-Crossley contact cannot be plastic: `E_FLOOR` in "
            f"`adapters/{e}`)",
            f"{label(e)} is judged against its law where one contact is the whole "
            f"episode: {sw.counts(e).get(Status.OK, 0)} of {n}, within "
            f"{num(sw.law_err(e))} m/s",
            f"its {len(unjudged)} "
            + (
                "at the cylinder's ends (the ball slides onto a cap during the contact)"
                if at_ends and len(unjudged)
                else "others"
            )
            + ": `unjudged`",
        ]
    return facts


def tuned(res: Results) -> str:
    swing, still = need(res, "swing", "still")
    f64 = swing.of_precision("float64")
    if not f64:
        return ""
    rest = max(still.err(e) for e in f64)
    same = len({f"{swing.err(e):.3g}" for e in f64}) == 1
    m = swing.model
    marks = swing.meta["analytic"]
    near = m.loc[(m.s_m - marks["sweet_spot_m"]).abs().idxmin()].s_m
    rows = swing.rows(f64[0])
    inner = rows.iloc[:-1]  # the cylinder's end is a case of its own (see Swing dynamics)
    low = inner.loc[inner.v1_abs_err_mps.idxmin()].s_m
    where = f"smallest at s = {low:g} m" + (
        f", the grid point nearest the sweet spot at {marks['sweet_spot_m']:.3f} m"
        if low == near
        else ""
    )
    ss = max(abs(swing.summary(e)["sweet_spot_engine_m"] - marks["sweet_spot_m"]) for e in f64)
    cop = max(abs(swing.summary(e)["cop_engine_m"] - marks["cop_m"]) for e in f64)
    overlap = swing.setting(f64[0], "overlap_m")
    return lead(
        f"**Tuned, the {count(len(f64))} float64 impulse engines reproduce rigid-body impact "
        "theory**:",
        [
            f"a bat at rest: {'to rounding, ' if rest < 1e-12 else ''}{num(rest)} m/s at most",
            f"the swinging bat: {num(max(swing.err(e) for e in f64))} m/s, the harness's own "
            f"error, {'the same in all of them' if same else 'alike in all of them'}",
            f"its cause: the contact is first seen {dist(overlap)} deep (`overlap_m`), by which "
            "time the turning bat has slid the contact foot along its axis by "
            "(r_bat + r_ball) omega0 delta / v_c; it scales with `overlap_m`",
            f"it follows |dv1/ds|: {where}",
            f"at the cylinder's end, where the contact point cannot slide: "
            f"{num(rows.v1_abs_err_mps.iloc[-1])} m/s",
            f"each engine locates the sweet spot within {dist(ss)} and the COP within "
            f"{dist(cop)} of theory",
        ],
    )
