"""The metal-bat answers behind ``results/findings.md``: the paper's aluminium bat against wood.

Numbers and tables only (no prose, no plotting), like ``experiments.findings.answers``, whose
scenarios, swings and constants they use. The aluminium bat's J_cm and COM have no source, so
the functions here also scan them. Units: m, m/s, kg, kg m^2, s, unless a column name says
otherwise.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import replace

import pandas as pd
from scipy import optimize

from analytic import Bat, SwingModel

from .answers import (
    AL,
    PITCHER_AFTER_FOLLOW_THROUGH_M,
    R161,
    REACTION_S,
    E,
    Scenario,
    best_v1,
    carried_swing,
    from_end_cm,
)

METAL_ES = (0.50, 0.55, 0.60)   # the aluminium bat's e: as wood's, and livelier
ROD_FRACTIONS = (0.5, 0.6, 0.7, 0.76, 0.8, 0.9)  # J_cm scanned, as fractions of a uniform rod's
COM_FRACTIONS = (0.55, 0.60, 0.65)  # the aluminium COM scanned, as fractions of its length
WOOD, ALUMINIUM = "R161 wood", "Easton aluminium"  # the bats' names in ``metal_table``


def uniform_rod_fraction(bat: Bat) -> float:
    """J_cm as a fraction of a uniform rod's M L^2 / 12."""
    return bat.inertia_cm_kgm2 / (bat.mass_kg * bat.length_m**2 / 12)


def aluminium_with(fraction: float) -> Bat:
    """The paper's aluminium bat with J_cm = ``fraction`` of a uniform rod's."""
    return replace(AL, inertia_cm_kgm2=fraction * AL.mass_kg * AL.length_m**2 / 12)


def metal_table(sc: Scenario, es: tuple[float, ...] = METAL_ES) -> pd.DataFrame:
    """Wood vs the paper's aluminium bat under each swing model: v1 at the best point (aluminium
    at several e) and the ball's time to a pitcher 16.5 m away."""
    rows = []
    for m in SwingModel:
        for label, bat in ((WOOD, R161), (ALUMINIUM, AL)):
            sw = carried_swing(bat, sc, m)
            row = {"swing model": m.value, "bat": label}
            for e in (es if bat is AL else (E,)):
                v1 = best_v1(bat, sc, sw, e)[1]
                row[f"v1, e={e:.2f} (m/s)"] = v1
                row[f"t to 16.5 m, e={e:.2f} (s)"] = PITCHER_AFTER_FOLLOW_THROUGH_M / v1
            rows.append(row)
    return pd.DataFrame(rows)


def table_v1(table: pd.DataFrame, model: str, bat: str, e: float = E) -> float:
    """v1 (m/s) of one bat under one swing model at e, read from a ``metal_table``."""
    row = table[(table["swing model"] == model) & (table.bat == bat)]
    return float(row[f"v1, e={e:.2f} (m/s)"].iloc[0])


def gain_over_wood(table: pd.DataFrame, model: str) -> float:
    """Aluminium minus wood v1 (m/s) at e = 0.5 under one swing model, from a ``metal_table``."""
    return table_v1(table, model, ALUMINIUM) - table_v1(table, model, WOOD)


def lively_gain(tables: Iterable[pd.DataFrame], e: float) -> tuple[float, float]:
    """The least and the most (m/s), over the tables' swings and every swing model, that the
    aluminium bat gains at e over itself at e = 0.5."""
    d = [table_v1(t, m.value, ALUMINIUM, e) - table_v1(t, m.value, ALUMINIUM)
         for t in tables for m in SwingModel]
    return min(d), max(d)


def aluminium_times(table: pd.DataFrame) -> int:
    """How many aluminium times to the pitcher a ``metal_table`` holds."""
    t = table[table.bat != WOOD]
    return int(t[[c for c in t.columns if c.startswith("t to")]].notna().sum().sum())


def metal_inertia_scan(sc: Scenario,
                       fractions: tuple[float, ...] = ROD_FRACTIONS) -> pd.DataFrame:
    """The aluminium bat's sweet spot and its v1 gain over wood (e = 0.5) as its unknown J_cm
    ranges over fractions of a uniform rod (the paper's 0.0205 kg m^2 is 50%, the R161 76%)."""
    wood_s, wood_v1 = best_v1(R161, sc)
    rows = []
    for f in fractions:
        bat = aluminium_with(f)
        s, _ = best_v1(bat, sc)
        rows.append({"J_cm / uniform rod": f, "J_cm (kg m^2)": bat.inertia_cm_kgm2,
                     "sweet spot (cm from end)": from_end_cm(bat, s),
                     "wood's (cm from end)": from_end_cm(R161, wood_s),
                     **{f"gain over wood, {m.value} (m/s)":
                        best_v1(bat, sc, carried_swing(bat, sc, m))[1] - wood_v1
                        for m in SwingModel}})
    return pd.DataFrame(rows)


def fraction_matching_wood_sweet_spot(sc: Scenario) -> float:
    """The aluminium J_cm fraction at which its sweet spot lies as far from its end as the
    R161's does from its own (what Crisco et al. measured on real wood and metal bats)."""
    target = from_end_cm(R161, best_v1(R161, sc)[0])
    return float(optimize.brentq(
        lambda f: from_end_cm(aluminium_with(f), best_v1(aluminium_with(f), sc)[0]) - target,
        0.2, 1.5))


def al_com_sensitivity(sc: Scenario,
                       fractions: tuple[float, ...] = COM_FRACTIONS) -> dict[float, float]:
    """The measured-model v1 gain of aluminium over wood with its assumed COM moved."""
    wood = best_v1(R161, sc, carried_swing(R161, sc, SwingModel.MEASURED))[1]
    out = {}
    for f in fractions:
        bat = replace(AL, com_from_knob_m=f * AL.length_m)
        out[f] = best_v1(bat, sc, carried_swing(bat, sc, SwingModel.MEASURED))[1] - wood
    return out



def time_below(v1_mps: float, distance_m: float = PITCHER_AFTER_FOLLOW_THROUGH_M) -> bool:
    """True if a ball at v1 reaches a pitcher ``distance_m`` away in less than REACTION_S."""
    return distance_m / v1_mps < REACTION_S
