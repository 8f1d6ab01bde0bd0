"""Friction at impact (friction.json and .csv): per engine and friction family, how it combines
friction, the law its contact follows, its statuses and its errors against that law and
against Routh's impulse; and the defects an engine's record declares."""

from __future__ import annotations

import math

import pandas as pd

import adapters

from .base import Results, label, md_table, pct, sci

#: The study's summary keys, as the table shows them.
COLUMNS = {"family": "family", "friction_cone": "cone", "friction_law": "law",
           "statuses": "statuses", "max_spin_rel_err_law": "spin vs its law",
           "max_spin_rel_err": "spin vs Routh", "max_v1_law_err_mps": "v1 vs its law (m/s)"}


def section(res: Results) -> str:
    data = res.json("friction.json")
    rows = []
    for row in data["summary"]:
        rec = adapters.record(row["engine"])
        rows.append({"engine": label(row["engine"]),
                     "rule": rec.can.friction_rule.value if rec.can.friction_rule else "none",
                     **{v: _cell(k, row[k]) for k, v in COLUMNS.items()}})
    df = res.csv("friction.csv")
    gap = df.law_spin_rel_gap.max()
    v1_gap = df.law_v1_gap_mps.max()
    defects = [f"**{label(n)}**: {adapters.record(n).errors.friction_defect}."
               for n in dict.fromkeys(r["engine"] for r in data["summary"])
               if adapters.record(n).errors.friction_defect]
    costly = [f"{label(r['engine'])} ({r['family']}): {len(r['spin_cost_cells'])} of "
              f"{sum(r['statuses'].values()) // len(data['points_m'])} cells"
              for r in data["summary"] if r["spin_cost_cells"]]
    compliant = [f"{label(r['engine'])} ({r['family']})" for r in data["summary"]
                 if math.isnan(r["max_spin_rel_err_law"])]
    intro = (
        f"`python -m experiments.friction` fires the paper's swing at "
        f"{len(data['points_m'])} impact points with mu in "
        f"{', '.join(f'{m:g}' for m in data['mus'])}, the ball oblique in the swing plane "
        f"(theta up to {max(data['thetas_rad']):g} rad) and, in the 3-D engines, undercut "
        f"up to {100 * max(data['undercuts_m']):g} cm. Each row is judged against the law its "
        "contact follows as the step shrinks (Newton's restitution and Coulomb's cone on the "
        "total impulse in one step; a convex solver's relaxation of it), with Routh's impulse "
        f"(theory) beside it: the laws' own gap from Routh's is up to {pct(gap)} of the spin "
        f"and {sci(v1_gap)} m/s of v1 on this grid, which no engine setting removes.")
    parts = [intro, md_table(pd.DataFrame(rows)),
             "Where an engine's spin misses its own law by more than "
             f"{pct(data['spin_cost_rel'])} (the cost of its cone or solver): "
             + ("; ".join(costly) if costly else "nowhere") + ".",
             res.chart("friction.png", "friction errors against mu")]
    if compliant:
        parts.insert(2, "Unjudged, a compliant contact with friction (no frictional contact "
                        "law here to judge it against; its errors against Routh's impulse "
                        "stand): " + ", ".join(compliant) + ".")
    if defects:
        parts.insert(2, "Declared friction defects (records' `friction_defect`, pinned by "
                        "tests):\n\n" + "\n".join(f"- {d}" for d in defects))
    return "\n\n".join(parts)


def _cell(key: str, value) -> str:
    if key == "statuses":
        return ", ".join(f"{k} {v}" for k, v in value.items())
    if isinstance(value, float):
        if math.isnan(value):
            return "-"
        return pct(value) if key.startswith("max_spin") else sci(value)
    return str(value)
