"""Where methods fail: the stability maps (time step x closing speed -> status)."""

from __future__ import annotations

import re

import numpy as np
import pandas as pd

from .. import stability as study
from ..core.judge import Status
from .base import (
    Results,
    alike,
    bullets,
    count,
    dist,
    engines_text,
    label,
    lead,
    num,
    pct,
    secs,
    span,
    step,
)
from .data import need


def section(res: Results) -> str:
    cells = res.csv("stability_cells.csv")
    table = res.csv("stability.csv")
    dts = sorted(table.dt_s.unique())
    speeds = sorted(table.v0_mps.unique())
    soft_maps = res.glob("stability_*_soft.png")
    head = (
        f"{res.chart('stability.png', 'status over time step and closing speed')}\n\n"
        f"A still R161 hit at s = {study.S_M:g} m with e = 1 by balls of "
        f"{span(speeds[0], speeds[-1], lambda v: f'{v:g}')} m/s, at {len(dts)} time steps "
        f"from {step(dts[0])} to {step(dts[-1])} and {table.phase.nunique()} contact phases "
        "per step (`results/stability.csv`, per-cell summary in "
        "`results/stability_cells.csv`). Letters mark the most common failure."
    )
    points = [
        bound(res, cells),
        *inaccurate(table),
        *compliant(res, table, cells),
        *defaults(table, cells),
        *soft(table),
    ]
    charts = [res.chart(n, "soft contact stability") for n in soft_maps]
    charts.append(res.chart("stability_energy.png", "penetration and energy change"))
    return "\n\n".join([head, bullets(points), *charts])


def bound(res: Results, cells: pd.DataFrame) -> str:
    (swing,) = need(res, "swing")
    r = study.REACH_M
    pitch = swing.model.iloc[0]
    v_rel = pitch.v0_mps + pitch.u0_mps
    top = cells.v0_mps.max()
    ref = cells[cells["map"].isin([f"{e} reference" for e in swing.rigid])]
    same = np.isclose(ref.fraction_caught, ref.theory_fraction_caught)
    return lead(
        f"**Tunnelling bound: every contact is caught while v_rel dt < {dist(r, 3)}**, "
        "R = r_ball + r_bat:",
        [
            "a contact first seen phase x v x dt deep is resolved iff that is below R; "
            "beyond, the ball's centre has crossed the bat's axis and the ball is pushed "
            "through",
            f"so dt <= {secs(r / pitch.v0_mps)} at {pitch.v0_mps:g} m/s, {secs(r / top)} "
            f"at {top:g} m/s; for the paper's swing (v_rel = {v_rel:.1f} m/s at the COM) "
            f"dt <= {secs(r / v_rel)}",
            "above it, a fraction R/(v_rel dt) of them",
            "an engine with a speculative contact (a contact offset, prediction distance "
            "or margin) also solves a contact whose gap at the step's start is within its "
            "margin: it catches every phase while v_rel dt < R + margin (the blue "
            "dash-dot line)",
            "with the reference solvers the fraction of contacts caught equals this count "
            f"in {pct(same.mean(), 3)} of the {len(ref)} cells of the "
            f"{count(len(swing.rigid))} rigid-contact engines (a test checks it: "
            "`tests/test_pareto_stability.py`)",
        ],
    )


def inaccurate(table: pd.DataFrame) -> list[str]:
    out = []
    ref = table[table.profile == "reference"]
    for m, g in ref.groupby("map", sort=False):
        bad = g[g.status == Status.INACCURATE]
        if bad.empty or not m.endswith(" reference"):
            continue
        e = g.engine.iloc[0]
        out.append(
            f"**{label(e)} catches them but not always accurately**: {len(bad)} of its {len(g)} "
            "reference impacts are `inaccurate`, where the contact is first seen already "
            f"overlapping at coarse steps ({span(bad.dt_s.min(), bad.dt_s.max(), step)} at "
            f"{span(bad.v0_mps.min(), bad.v0_mps.max(), lambda v: f'{v:g}')} m/s, phases "
            f"{span(bad.phase.min(), bad.phase.max(), lambda v: f'{v:g}')} of a step): the "
            "solver then bounces the ball short."
        )
    return out


def compliant(res: Results, table: pd.DataFrame, cells: pd.DataFrame) -> list[str]:
    (swing,) = need(res, "swing")
    out = []
    for e in swing.compliant:
        contact = swing.rows(e).contact_duration_s.median()
        facts = [
            f"its contact lasts about {secs(contact)} on the paper's swing and is missed "
            "when a reading interval is longer than that (its reference mode is "
            "continuous; dt only spaces the readings)"
        ]
        for m, g in cells[cells["map"].str.startswith(f"{e} Hunt-Crossley")].groupby("map"):
            d = re.search(r"d = ([0-9.]+) s/m", m)
            full = g.groupby("dt_s").fraction_ok.min()
            clean = full[full == 1].index
            last = max((dt for dt in clean if (full[full.index <= dt] == 1).all()), default=None)
            facts.append(
                lead(
                    f"its Hunt-Crossley map ({m.split('(', 1)[-1].rstrip(')')}; judged against the "
                    "law) draws the law's own limits:",
                    [
                        f"the rebound speed cannot exceed 1/d = {1 / float(d.group(1)):.0f} m/s "
                        "however fast the ball comes in (e < 1/(d v), drake#19320)"
                        if d
                        else "",
                        "a step longer than the contact time t_c(v) misses the contact",
                        f"every phase is ok up to dt = {step(last)}" if last else "",
                        "rows with fewer than ten steps per contact are `unjudged`",
                    ],
                )
            )
        out.append(
            lead(
                f"**{label(e)}** (a compliant contact, judged against its own law) has "
                "no tunnelling bound of this kind:",
                facts,
            )
        )
    return out


def defaults(table: pd.DataFrame, cells: pd.DataFrame) -> list[str]:
    out, through = [], []
    for m, g in table[table.profile == "default"].groupby("map", sort=False):
        e, n = g.engine.iloc[0], len(g)
        counts = g.status.value_counts()
        gained = g[g.status == Status.ENERGY_GAINED]
        if len(gained) > n / 10:
            letters = cells[cells["map"] == m].failure
            rise = gained.ke_ratio - 1
            out.append(
                lead(
                    f"**{label(e)}'s default solver gains energy at e = 1** in {len(gained)} of "
                    "its "
                    f"{n} impacts:",
                    [
                        f"the most common failure in {int((letters == 'E').sum())} of its "
                        f"{len(letters)} cells",
                        f"energy gained: {pct(rise.min())} to {pct(rise.max())}, median "
                        f"{pct(rise.median())}",
                        "its contact error reduction turns the overlap at first contact into "
                        "velocity",
                    ],
                )
            )
        elif counts.get(Status.OK, 0) == 0:
            through.append(
                (
                    e,
                    f"{counts.get(Status.TUNNELLED, 0)} of {n} impacts tunnelled\n"
                    f"{counts.get(Status.NO_SEPARATION, 0)} held past "
                    f"{secs(study.BUDGET_S)} (reported `no_separation`)",
                )
            )
    for who, text in alike(through):
        out.append(
            lead(
                "**The default contact lets the ball through at every step and speed** "
                f"in {engines_text(who)}" + (", each" if len(who) > 1 else "") + ":",
                text.split("\n"),
            )
        )
    return out


def soft(table: pd.DataFrame) -> list[str]:
    said = []
    for _, g in table[table["map"].str.endswith(" soft")].groupby("map", sort=False):
        ok = g[g.status == Status.OK]
        wdt = ok.soft_omega_radps * ok.dt_s
        sink = study.SOFT_SPEED_MPS / study.REACH_M
        inside = bool((ok.soft_omega_radps > sink).all() and (wdt < 2).all())
        said.append(
            (
                g.engine.iloc[0],
                "\n".join(
                    [
                        f"the ball sinks through when w < v/R = {sink:.0f} rad/s (the spring's "
                        "depth v/w "
                        "exceeds R)",
                        "Euler is unstable when w dt > 2 (energy gain, then pass-through)",
                        f"every `ok` impact lies between these lines: w from "
                        f"{num(ok.soft_omega_radps.min())} rad/s, w dt up to {num(wdt.max())}"
                        if inside and len(ok)
                        else f"{len(ok)} impacts are `ok`",
                    ]
                ),
            )
        )
    return [
        lead(
            f"**{engines_text(who)}: soft contact{'s' if len(who) > 1 else ''}** "
            f"(e = {study.SOFT_E:g}, {study.SOFT_SPEED_MPS:g} m/s):",
            text.split("\n"),
        )
        for who, text in alike(said)
    ]
