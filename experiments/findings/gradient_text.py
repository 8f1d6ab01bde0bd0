"""Section 6b: can a differentiable engine measure a bat? The R161's J recovered from 20 noisy
exit speeds by gradient descent through each differentiable engine's own derivative, against
the closed-form least-squares fit (``experiments.parts.gradient_studies``)."""

from __future__ import annotations

import pandas as pd

import adapters

from .. import gradients
from ..parts import gradient_studies as studies
from .report import md_table

#: Steps each impact is followed through (the reference profiles' episodes take 3-8).
STEPS = 16


def fit_section(engines: tuple[str, ...]) -> str:
    """The worked answer as markdown."""
    base = gradients.base_case()
    s, v1 = studies.fit_data(base)
    ls = studies.least_squares_j(base, s, v1)
    rows = [
        {
            "method": "closed form, least squares (scipy)",
            "J (kg m^2)": ls["j_kgm2"],
            "minus true J (kg m^2)": ls["j_kgm2"] - base.bat.inertia_cm_kgm2,
            "iterations": ls["evaluations"],
            "wall (s)": ls["cost_s"],
        }
    ]
    lame = []
    for name in (n for n in engines if adapters.record(n).can.autodiff):
        d = studies.descend_j(
            name, adapters.settings_for(name), base, s, v1, ls["sigma_kgm2"], STEPS
        )
        if d["why"]:
            lame.append(f"{name}: {d['why']}")
            continue
        rows.append(
            {
                "method": f"descent through {name}",
                "J (kg m^2)": d["j_kgm2"],
                "minus true J (kg m^2)": d["j_kgm2"] - base.bat.inertia_cm_kgm2,
                "iterations": d["iterations"],
                "wall (s)": d["cost_s"],
            }
        )
    table = pd.DataFrame(rows)
    ran = "" if len(rows) > 1 else "\nNo engine with its own derivative was run.\n"
    lame_text = "".join(f"{x}\n" for x in lame)
    return f"""## 6b. Can a differentiable engine measure a bat?

The R161's moment of inertia about its COM (true J = {base.bat.inertia_cm_kgm2:.4f} kg m^2
[cross2009]) from {len(s)} exit speeds on the paper's swing, s = {s[0]:.2f} to {s[-1]:.2f} m
from the COM, each the closed form's v1 plus Gaussian noise of {studies.FIT_NOISE_MPS} m/s (an
assumption, seeded: no measured set of this kind is at hand). The closed-form least-squares fit
has a standard error of {ls["sigma_kgm2"]:.2e} kg m^2. Each differentiable engine starts at
{studies.FIT_START:g} J and steps by -sum(r dv1/dJ) / sum((dv1/dJ)^2), its own dv1/dJ through the
impact, until the step is below {studies.FIT_STOP:g} of that error or the loss stops falling
(wall time with the first call's compile; `python -m experiments.gradients` judges the
derivatives themselves):

{md_table(table, "{:.6g}")}
{ran}{lame_text}
An engine whose dv1/dJ is right lands on the least-squares J: the fit's error is the
measurements', not the method's. One whose derivative misses (its record's `gradient_defect`)
steps by the wrong length and stops where its loss stops falling.
"""
