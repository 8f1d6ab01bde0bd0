"""The baseline sweeps the other sections read: found by role, with their summaries."""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import pandas as pd

from .base import Missing, Results, precision

#: The baselines of ``experiments.baselines`` by role, as the file stems the sweep gives them.
ROLES = {
    "swing": ("sweep_*_reference_r161_swing", "the paper's swing, reference profiles"),
    "still": ("sweep_*_reference_r161_still", "a still bat"),
    "hinged": ("sweep_*_reference_r161_hinged", "swung about the hands in the engine, then hit"),
    "plastic": ("sweep_*_reference_r161_swing_e0", "a plastic ball (e = 0) on the paper's swing"),
    "default": ("sweep_*_default_r161_swing", "each engine out of the box, contact mid-step"),
    "default_dt": (
        "sweep_*_default-dt*_r161_swing",
        "default solver values at a small step, contact mid-step",
    ),
}


@dataclass
class Sweep:
    """One baseline sweep: its table (sweep CSV) and its summary (sweep JSON)."""

    stem: str
    table: pd.DataFrame
    meta: dict

    @property
    def engines(self) -> list[str]:
        return list(self.meta["engines"])

    def summary(self, engine: str) -> dict:
        return self.meta["engines"][engine]

    def rows(self, engine: str) -> pd.DataFrame:
        return self.table[self.table.engine == engine].sort_values("s_m")

    def err(self, engine: str) -> float:
        """Largest |v1 engine - v1 rigid| over the measured impacts (m/s)."""
        return float(self.summary(engine)["v1_abs_err_max_mps"])

    def law_err(self, engine: str) -> float:
        """Largest |v1 engine - v1 of its own contact law| over the impacts it judges."""
        rows = self.rows(engine)
        judged = rows[rows.v1_law_tol_mps.notna()]
        return float(judged.v1_law_err_mps.max()) if len(judged) else float("nan")

    def setting(self, engine: str, name: str):
        return self.summary(engine)["settings"].get(name)

    @cached_property
    def compliant(self) -> list[str]:
        """Engines judged against their own contact law (a compliant contact)."""
        return [e for e in self.engines if self.rows(e).v1_law_mps.notna().any()]

    @cached_property
    def rigid(self) -> list[str]:
        return [e for e in self.engines if e not in self.compliant]

    def of_precision(self, bits: str) -> list[str]:
        return [e for e in self.rigid if precision(e) == bits]

    @property
    def model(self) -> pd.DataFrame:
        """The model's columns, one row per impact point (the same for every engine)."""
        return self.rows(self.engines[0])

    def counts(self, engine: str) -> dict[str, int]:
        return self.summary(engine)["status_counts"]


def baselines(res: Results) -> dict[str, Sweep]:
    """Every baseline role found in the results (the newest file where a role has several)."""

    def find() -> dict[str, Sweep]:
        found = {}
        for role, (pattern, _) in ROLES.items():
            stems = [n.removesuffix(".json") for n in res.glob(pattern + ".json")]
            if stems:
                stem = max(stems, key=lambda s: res.json(f"{s}.json")["provenance"]["date_utc"])
                found[role] = Sweep(stem, res.csv(f"{stem}.csv"), res.json(f"{stem}.json"))
        return found

    return res.memo("baselines", find)


def need(res: Results, *roles: str) -> list[Sweep]:
    got = baselines(res)
    for role in roles:
        if role not in got:
            raise Missing(ROLES[role][0] + ".csv/.json")
    return [got[r] for r in roles]
