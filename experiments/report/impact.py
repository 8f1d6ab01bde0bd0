"""The swing into the impact (the hinged baseline) and the swing-speed models side by side."""

from __future__ import annotations

import math

import numpy as np
import pandas as pd

from analytic import presets
from analytic.dynamics import HingedSwing

from .base import Results, dist, engines_text, label, lead, names, num, secs, span, times
from .data import need

BAT = presets.R161  #: the baselines' bat


def into_impact(res: Results) -> str:
    hinged, swing = need(res, "hinged", "swing")
    m = hinged.model
    omega0, u0 = float(m.omega0_radps.iloc[0]), float(m.u0_mps.iloc[0])
    hands = BAT.com_from_knob_m - u0 / omega0
    drive = HingedSwing.for_omega(BAT, omega0, hands_from_knob_m=hands)
    paper = swing.model.iloc[0]
    pivot = BAT.com_from_knob_m - paper.u0_mps / paper.omega0_radps
    f64 = hinged.of_precision("float64")
    errs = [hinged.err(e) for e in f64]
    release = max(hinged.rows(e).release_angle_err_rad.abs().median() for e in f64)
    return lead(
        "**Swing into impact in one run** (`python -m experiments.sweep --swing`):",
        [
            f"the bat is swung from rest about the hands ({hands:.2g} m from the knob) by the "
            f"constant torque that reaches omega0 = {omega0:.0f} rad/s over "
            f"{math.degrees(drive.angle_rad):.0f} deg ({drive.torque_nm:.1f} N m, "
            f"{drive.duration_s(BAT):.3f} s), released, and hit",
            f"u0 = omega0 x {u0 / omega0:.2f} m = {u0:.2f} m/s comes from the same swing (the "
            f"paper's u0 = {paper.u0_mps:g} m/s with omega0 = {paper.omega0_radps:g} rad/s would "
            f"need the bat to turn about a point {dist(pivot)} from the knob)",
            f"{engines_text(f64)} reproduce theory to {span(min(errs), max(errs))} m/s at "
            f"dt = {secs(hinged.setting(f64[0], 'dt_s'))} (`{hinged.stem}.*`)",
            f"the error is the swing's first-order angle error ({num(release)} rad at release), "
            "which tilts the bat at contact" + _sign(hinged, f64),
            "`tests/test_dynamics.py::test_swing_into_impact` bounds it from the tilt, the foot's "
            "slide and the hinge's omega error",
            *_sides(hinged, f64, hands - BAT.com_from_knob_m),
        ],
    )


def _sign(sw, engines: list[str]) -> str:
    """Where v1 engine - v1 theory changes sign, if all the engines agree near the sweet spot."""
    spot = sw.meta["analytic"]["sweet_spot_m"]
    near = []
    for e in engines:
        r = sw.rows(e)
        d = (r.v1_engine_mps - r.v1_analytic_mps).to_numpy()
        s = r.s_m.to_numpy()
        flips = [(s[i] + s[i + 1]) / 2 for i in np.flatnonzero(np.sign(d[:-1]) != np.sign(d[1:]))]
        if not flips:
            return ""
        near.append(min(flips, key=lambda x: abs(x - spot)))
    step = float(np.diff(sw.model.s_m).max())
    if max(abs(x - spot) for x in near) > step:
        return ""
    return f"; it changes sign near the sweet spot, at {spot:.3f} m from the COM"


def _sides(sw, engines: list[str], s_hands: float) -> list[str]:
    knob_deep, barrel_deep = [], []
    for e in engines:
        r = sw.rows(e)
        knob, rest = r[r.s_m < s_hands], r[r.s_m >= s_hands]
        if knob.empty or rest.empty:
            continue
        if knob.peak_penetration_m.median() > 5 * rest.peak_penetration_m.median():
            knob_deep.append((e, knob, rest))
        elif rest.peak_penetration_m.median() > 5 * knob.peak_penetration_m.median():
            barrel_deep.append((e, rest))
    out = []
    if knob_deep:
        knob = pd.concat([k for _, k, _ in knob_deep])
        rest = pd.concat([r for _, _, r in knob_deep])
        beside = pd.concat([r.iloc[:1] for _, _, r in knob_deep])
        more = knob.steps.median() - rest.steps.median()
        out.append(
            lead(
                f"between the knob and the hands (s < {s_hands:.2f} m) "
                f"{engines_text(e for e, _, _ in knob_deep)} are "
                f"{times(knob.v1_abs_err_mps.max() / beside.v1_abs_err_mps.max(), 1)} worse:",
                [
                    f"{span(knob.v1_abs_err_mps.min(), knob.v1_abs_err_mps.max())} against "
                    f"{num(beside.v1_abs_err_mps.max())} m/s beside them",
                    "the turned bat is displaced the other way on that side of the pivot: the "
                    "contact arrives a step late",
                    f"it is first seen {_depths(knob)} deep instead of {_depths(rest)} "
                    f"(`peak_penetration_m`, and {more:g} more `steps`)",
                    "the deeper contact slides the foot farther",
                ],
            )
        )
    out += [
        f"{label(e)}'s angle error has the opposite sign (it moves positions before "
        f"velocities): its deep contacts ({_depths(rest)}) are on the barrel side"
        for e, rest in barrel_deep
    ]
    return out


def _depths(rows: pd.DataFrame) -> str:
    return span(rows.peak_penetration_m.min(), rows.peak_penetration_m.max(), dist)


def models(res: Results) -> list[str]:
    t = res.csv("swing_models.csv")
    bats = list(dict.fromkeys(t.bat))
    ref = t[t.bat == bats[0]].set_index("model")
    meas = t[(t.model == "measured") & (t.bat != bats[0])].iloc[0]
    n = -math.log(meas.omega0_radps / ref.loc["measured"].omega0_radps) / math.log(
        meas.inertia_knob_kgm2 / ref.loc["measured"].inertia_knob_kgm2
    )
    heads = {
        "constant_force": "paper: u0 ~ 1/M",
        "constant_torque": "constant torque: omega ~ I_knob^-1/2",
        "measured": f"measured: ~ I^-{n:.2f}",
    }
    piv = t.pivot(index="bat", columns="model", values="v1_max_mps").reindex(bats)
    base = piv.iloc[0]
    corked = [b for b in bats if "corked" in b and "cork" in b.split(",")[-1]]
    pays = [c for c in piv.columns if all(piv.loc[b, c] > base[c] for b in corked)]
    loses = [c for c in piv.columns if all(piv.loc[b, c] < base[c] for b in corked)]
    others = set(piv.columns) - {"constant_force"}
    if pays == ["constant_force"] and set(loses) == others:
        verdict = lead(
            "For this swing only the paper's model makes corking pay (every "
            "cork-filled bat of `swing_models.csv`):",
            [
                "it speeds up the COM of a lighter bat but keeps its spin",
                "the models that tie swing speed to the swing weight cost ball speed here",
                "that depends on the swing: for an MLB-like swing about the knob "
                "constant torque gains (findings, section 2)",
            ],
        )
    else:
        verdict = (
            f"Corking (every cork-filled bat of `swing_models.csv`) pays under "
            f"{names(heads[c] for c in pays) or 'no model'} and costs ball speed under "
            f"{names(heads[c] for c in loses) or 'no model'}."
        )
    r0 = ref.iloc[0]
    return [
        lead(
            "Swing-speed models side by side (`results/swing_models.csv`, `.png`), from "
            f"the paper's {bats[0]} swing (u0 = {r0.u0_mps:g} m/s, omega0 = "
            f"{r0.omega0_radps:g} rad/s):",
            [heads[c] for c in heads if c in piv],
        ),
        "The v1 of each bat under each model is in findings.md: [corked "
        "bats](findings.md#2-does-corking-help), [metal "
        "bats](findings.md#3-why-are-metal-bats-restricted).",
        verdict,
        res.chart("swing_models.png", "swing-speed models"),
    ]
