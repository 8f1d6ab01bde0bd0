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
from analytic.flight import time_to_travel

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

METAL_ES = (0.50, 0.55, 0.60)  # the aluminium bat's e: as wood's, and livelier
ROD_FRACTIONS = (0.5, 0.6, 0.7, 0.76, 0.8, 0.9)  # J_cm scanned, as fractions of a uniform rod's
COM_FRACTIONS = (0.55, 0.60, 0.65)  # the aluminium COM scanned, as fractions of its length
WOOD, ALUMINIUM = "R161 wood", "Easton aluminium"  # the bats' names in ``metal_table``
IN_M, OZ_KG = 0.0254, 0.028349523125
BBCOR_DROP_OZ = 3  # BBCOR bats: weight (oz) at least length (in) - 3 [ncaa]
BBCOR_LENGTHS_IN = (31, 32, 33, 34)  # the metal bats compared, each at drop -3


def uniform_rod_fraction(bat: Bat) -> float:
    """J_cm as a fraction of a uniform rod's M L^2 / 12."""
    return bat.inertia_cm_kgm2 / (bat.mass_kg * bat.length_m**2 / 12)


def aluminium_with(fraction: float) -> Bat:
    """The paper's aluminium bat with J_cm = ``fraction`` of a uniform rod's."""
    return replace(AL, inertia_cm_kgm2=fraction * AL.mass_kg * AL.length_m**2 / 12)


def time_to_pitcher_s(v1_mps: float) -> float:
    """The batted ball's time to a pitcher 16.5 m away, with drag (``flight.time_to_travel``, no
    spin: the least drag, so the shortest time)."""
    return time_to_travel(v1_mps, PITCHER_AFTER_FOLLOW_THROUGH_M).time_s


def metal_table(sc: Scenario, es: tuple[float, ...] = METAL_ES) -> pd.DataFrame:
    """Wood vs the paper's aluminium bat under each swing model: v1 at the best point (aluminium
    at several e) and the ball's time to a pitcher 16.5 m away, with drag."""
    rows = []
    for m in SwingModel:
        for label, bat in ((WOOD, R161), (ALUMINIUM, AL)):
            sw = carried_swing(bat, sc, m)
            row = {"swing model": m.value, "bat": label}
            for e in es if bat is AL else (E,):
                v1 = best_v1(bat, sc, sw, e)[1]
                row[f"v1, e={e:.2f} (m/s)"] = v1
                row[f"t to 16.5 m, e={e:.2f} (s)"] = time_to_pitcher_s(v1)
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
    d = [
        table_v1(t, m.value, ALUMINIUM, e) - table_v1(t, m.value, ALUMINIUM)
        for t in tables
        for m in SwingModel
    ]
    return min(d), max(d)


def aluminium_times(table: pd.DataFrame) -> int:
    """How many aluminium times to the pitcher a ``metal_table`` holds."""
    t = table[table.bat != WOOD]
    return int(t[[c for c in t.columns if c.startswith("t to")]].notna().sum().sum())


def metal_inertia_scan(sc: Scenario, fractions: tuple[float, ...] = ROD_FRACTIONS) -> pd.DataFrame:
    """The aluminium bat's sweet spot (swung as the measured n carries the swing over) and its v1
    gain over wood (e = 0.5) under each swing model as its unknown J_cm ranges over fractions of
    a uniform rod (the paper's 0.0205 kg m^2 is 50%, the R161 76%)."""
    wood_s, wood_v1 = best_v1(R161, sc)
    rows = []
    for f in fractions:
        bat = aluminium_with(f)
        s, _ = best_v1(bat, sc, carried_swing(bat, sc, SwingModel.MEASURED))
        rows.append(
            {
                "J_cm / uniform rod": f,
                "J_cm (kg m^2)": bat.inertia_cm_kgm2,
                "sweet spot (cm from end)": from_end_cm(bat, s),
                "wood's (cm from end)": from_end_cm(R161, wood_s),
                **{
                    f"gain over wood, {m.value} (m/s)": best_v1(bat, sc, carried_swing(bat, sc, m))[
                        1
                    ]
                    - wood_v1
                    for m in SwingModel
                },
            }
        )
    return pd.DataFrame(rows)


def fraction_matching_wood_sweet_spot(
    sc: Scenario, model: SwingModel = SwingModel.MEASURED
) -> float:
    """The aluminium J_cm fraction at which its sweet spot lies as far from its end as the
    R161's does from its own (what Crisco et al. measured on real wood and metal bats), each
    bat swung as ``model`` carries the scenario's swing over (so the aluminium bat's speed
    follows its own balance point and inertia); nan if no fraction in 0.2-2 does."""
    target = from_end_cm(R161, best_v1(R161, sc)[0])

    def gap(f: float) -> float:
        bat = aluminium_with(f)
        return from_end_cm(bat, best_v1(bat, sc, carried_swing(bat, sc, model))[0]) - target

    if gap(0.2) * gap(2.0) > 0:
        return float("nan")
    return float(optimize.brentq(gap, 0.2, 2.0))


def bbcor_bat(
    length_in: float,
    drop_oz: float = BBCOR_DROP_OZ,
    *,
    com_fraction: float | None = None,
    rod_fraction: float | None = None,
) -> Bat:
    """A metal bat ``length_in`` long weighing length - drop oz, its COM at ``com_fraction`` of
    its length and J_cm ``rod_fraction`` of a uniform rod's; by default the paper's aluminium
    bat's proportions (60% and 50%: both unsourced, ``inputs.INPUTS`` gives their ranges)."""
    length, mass = length_in * IN_M, (length_in - drop_oz) * OZ_KG
    com = AL.com_from_knob_m / AL.length_m if com_fraction is None else com_fraction
    rod = uniform_rod_fraction(AL) if rod_fraction is None else rod_fraction
    return replace(
        AL,
        name=f"metal{length_in:g}",
        length_m=length,
        mass_kg=mass,
        com_from_knob_m=com * length,
        inertia_cm_kgm2=rod * mass * length**2 / 12,
    )


EQUAL_BAT = bbcor_bat(33)  # the metal bat of the R161's length (33 in, 30 oz)
EQUAL_LENGTH = "metal 33 in, 30 oz"  # its name in the tables


def bbcor_table(sc: Scenario, lengths_in: tuple[int, ...] = BBCOR_LENGTHS_IN) -> pd.DataFrame:
    """Metal bats at BBCOR's drop -3 against the 33 in R161, at e = 0.5 (the BBCOR cap, about
    wood's): v1 at each bat's best point minus the R161's, per swing model (m/s)."""
    wood = best_v1(R161, sc)[1]
    rows = []
    for length in lengths_in:
        bat = bbcor_bat(length)
        rows.append(
            {
                "metal bat": f"{length} in, {length - BBCOR_DROP_OZ} oz",
                "mass (kg)": bat.mass_kg,
                **{
                    f"gain over wood, {m.value} (m/s)": best_v1(bat, sc, carried_swing(bat, sc, m))[
                        1
                    ]
                    - wood
                    for m in SwingModel
                },
            }
        )
    return pd.DataFrame(rows)


def al_com_sensitivity(
    sc: Scenario, fractions: tuple[float, ...] = COM_FRACTIONS
) -> dict[float, float]:
    """The measured-model v1 gain of aluminium over wood with its assumed COM moved."""
    wood = best_v1(R161, sc, carried_swing(R161, sc, SwingModel.MEASURED))[1]
    out = {}
    for f in fractions:
        bat = replace(AL, com_from_knob_m=f * AL.length_m)
        out[f] = best_v1(bat, sc, carried_swing(bat, sc, SwingModel.MEASURED))[1] - wood
    return out


def time_below(v1_mps: float) -> bool:
    """True if a ball at v1 reaches the pitcher in less than REACTION_S, with drag."""
    return time_to_pitcher_s(v1_mps) < REACTION_S
