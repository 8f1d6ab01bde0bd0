"""Friction at impact (friction.json and .csv): per engine and friction family, how it combines
friction, the law its contact follows, its statuses and its errors against that law and
against Routh's impulse; and the defects an engine's record declares."""

from __future__ import annotations

import math

import pandas as pd

import adapters

from .base import Results, bullets, claim, label, lead, md_table, pct, sci

#: The study's summary keys, as the table shows them.
COLUMNS = {
    "family": "family",
    "friction_cone": "cone",
    "friction_law": "law",
    "statuses": "statuses",
    "max_spin_rel_err_law": "spin vs its law",
    "max_spin_rel_err": "spin vs Routh",
    "max_v1_law_err_mps": "v1 vs its law (m/s)",
}


def section(res: Results) -> str:
    data = res.json("friction.json")
    rows = []
    for row in data["summary"]:
        rec = adapters.record(row["engine"])
        rows.append(
            {
                "engine": label(row["engine"]),
                "rule": rec.can.friction_rule.value if rec.can.friction_rule else "none",
                **{v: _cell(k, row[k]) for k, v in COLUMNS.items()},
            }
        )
    df = res.csv("friction.csv")
    gap = df.law_spin_rel_gap.max()
    v1_gap = df.law_v1_gap_mps.max()
    defects = [
        _defect(n)
        for n in dict.fromkeys(r["engine"] for r in data["summary"])
        if adapters.record(n).errors.friction_defect
    ]
    costly = [
        f"{label(r['engine'])} ({r['family']}): {len(r['spin_cost_cells'])} of "
        f"{sum(r['statuses'].values()) // len(data['points_m'])} cells"
        for r in data["summary"]
        if r["spin_cost_cells"]
    ]
    compliant = [
        f"{label(r['engine'])} ({r['family']})"
        for r in data["summary"]
        if math.isnan(r["max_spin_rel_err_law"])
    ]
    intro = lead(
        f"`python -m experiments.friction` fires the paper's swing at {len(data['points_m'])} "
        "impact points:",
        [
            f"mu in {', '.join(f'{m:g}' for m in data['mus'])}",
            f"the ball oblique in the swing plane (theta up to {max(data['thetas_rad']):g} rad)",
            f"in the 3-D engines, undercut up to {100 * max(data['undercuts_m']):g} cm",
        ],
    )
    judged = lead(
        "Each row is judged against the law its contact follows as the step shrinks (Newton's "
        "restitution and Coulomb's cone on the total impulse in one step; a convex solver's "
        "relaxation of it), with Routh's impulse (theory) beside it:",
        [
            f"the laws' own gap from Routh's: up to {pct(gap)} of the spin and {sci(v1_gap)} m/s "
            "of v1 on this grid",
            "no engine setting removes it",
        ],
    )
    parts = [
        intro,
        judged,
        md_table(pd.DataFrame(rows)),
        lead(
            "Where an engine's spin misses its own law by more than "
            f"{pct(data['spin_cost_rel'])} (the cost of its cone or solver):",
            costly or ["nowhere"],
        ),
        res.chart("friction.png", "friction errors against mu"),
    ]
    if compliant:
        parts.insert(
            3,
            "Unjudged, a compliant contact with friction (no frictional contact "
            "law here to judge it against; its errors against Routh's impulse "
            "stand): " + ", ".join(compliant) + ".",
        )
    if defects:
        parts.insert(
            3,
            "Declared friction defects (records' `friction_defect`, pinned by "
            "tests):\n\n" + bullets(defects),
        )
    return "\n\n".join(parts)


def _defect(engine: str) -> str:
    """The engine's declared friction defect: its claim, then its reasons a line each."""
    head, *facts = claim(adapters.record(engine).errors.friction_defect)
    return lead(f"**{label(engine)}**: {head}", facts)


def _cell(key: str, value) -> str:
    if key == "statuses":
        return ", ".join(f"{k} {v}" for k, v in value.items())
    if isinstance(value, float):
        if math.isnan(value):
            return "-"
        return pct(value) if key.startswith("max_spin") else sci(value)
    return str(value)
