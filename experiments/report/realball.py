"""A real baseball in each engine (realball_fits.csv): each engine's best ball model, how close
it comes to the declared ball (COR_LAW and its range) at the fitted and held-out speeds, the
sweet spot it gives the paper's swing, and the gradient fit beside the finite-difference one."""

from __future__ import annotations

import json

import pandas as pd

from analytic.ball import CONTACT_S, COR_LAW, SPEED_REF_MPS

from ..parts.realball_fit import METHODS
from .base import Results, bullets, label, lead, md_table, num


def section(res: Results) -> str:
    fits = res.csv("realball_fits.csv")
    fd = fits[fits.method == METHODS[0]]
    best = fd[fd.best.astype(bool)]
    table = pd.DataFrame(
        {
            "engine": [label(e) for e in best.engine],
            "model": best.model,
            "COR at 85 ft/s": [f"{c:.3f}" for c in best.cor_85fps],
            "in MLB's band": ["yes" if b else "no" for b in best.in_mlb_band],
            "speeds in range (held out)": [
                f"{r.speeds_in_range}/{r.speeds_checked} ({r.held_out_in_range}/{r.held_out})"
                for r in best.itertuples()
            ],
            "sweet spot (cm)": [f"{100 * s:.1f}" for s in best.sweet_spot_m],
            "fit cost": [num(c) for c in best.cost],
        }
    )
    others = fd[~fd.best.astype(bool)]
    facts = [
        f"{label(r.engine)}'s {r.model}: {r.speeds_in_range}/{r.speeds_checked} speeds in range, "
        f"COR {r.cor_85fps:.3f} at 85 ft/s, cost {num(r.cost)}"
        for r in others.itertuples()
    ]
    grad = fits[fits.method == METHODS[1]]
    gradient = [
        f"{label(r.engine)}'s own derivative fits its ball in {r.impacts} impacts against "
        f"{int(fd[(fd.engine == r.engine) & (fd.model == r.model)].impacts.iloc[0])} by finite "
        f"differences, its CORs within {num(r.cor_gap_bands)} half bands of theirs"
        for r in grad.itertuples()
    ]
    ball_m = float(best.sweet_spot_ball_m.iloc[0])  # (the same reference for every engine)
    head = lead(
        "`python -m experiments.realball` fits each ball model a record declares to the ball "
        f"fired at a rigid wall: COR_LAW's COR ({COR_LAW.cor(SPEED_REF_MPS):.3f} at 85 ft/s, "
        f"falling as v^-{COR_LAW.exponent:.3f}) at 10-60 m/s in units of COR_LAWS' half range, "
        f"and {1e3 * CONTACT_S:.1f} ms of contact at 40 m/s where the contact lasts. Each "
        "engine's lowest-cost model ([settings to copy](realball.md), "
        f"[chart](realball.png)); the realistic ball puts the sweet spot at {100 * ball_m:.1f} cm:",
        [],
    )
    return "\n\n".join(
        part
        for part in (
            head,
            md_table(table),
            lead(
                "The other models (a Hunt-Crossley e depends on d v alone and falls faster "
                "than COR_LAWS allows: no d keeps 5 of the 9 speeds in range, "
                "`tests/test_realball.py`):",
                facts,
            )
            if facts
            else "",
            bullets(gradient),
            _settings(best),
        )
        if part
    )


def _settings(best: pd.DataFrame) -> str:
    """The fitted knobs of the best models with a speed-dependent COR, as fitted."""
    soft = best[best.speed_dependent.astype(bool)]
    return lead(
        "The fitted knobs of the best models whose COR falls with speed:",
        [
            f"{label(r.engine)} ({r.model}): "
            + ", ".join(f"{k} {v:.3g}" for k, v in json.loads(r.knobs).items())
            for r in soft.itertuples()
        ],
    )
