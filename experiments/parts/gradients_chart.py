"""The gradient study's charts and its worked answer's text (a part of
``experiments.gradients``): dv1/ds along the bat over the closed form with each engine's error
beside its tolerance, and the soft contact's bias against stiffness and omega dt."""

from __future__ import annotations

import numpy as np
import pandas as pd

import adapters
from analytic.gradients import derivatives

from ..core.gradients import GradStatus
from ..core.io import md_table

#: Errors below this are drawn on it (log axes: float64 finite differences reach 1e-9).
FLOOR = 1e-10
METHODS = {"finite_difference": ("-", "finite differences"), "autodiff": ("--", "autodiff")}


def _plt():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def along_the_bat(table: pd.DataFrame, cases) -> object:
    """Left: the closed form's dv1/ds along the bat and each engine's, by finite differences
    (filled) and autodiff (hollow). Right: |engine - the answer that applies| against s."""
    plt = _plt()
    fig, (a, b) = plt.subplots(1, 2, figsize=(13, 7.5))
    c0 = cases[0]
    s = np.linspace(min(c.s_m for c in cases), max(c.s_m for c in cases), 200)
    exact = derivatives(
        c0.bat,
        c0.ball,
        s_m=s,
        v0_mps=c0.v0_mps,
        u0_mps=c0.u0_mps,
        omega0_radps=c0.omega0_radps,
        e=c0.e,
    )["v1_mps"]["s_m"]
    a.plot(s, exact, "k-", lw=2.5, label="closed form", zorder=1)
    rows = table[(table.input == "s_m") & (table.status != GradStatus.UNSUPPORTED)]
    groups = list(rows.groupby(["engine", "method"], sort=False))
    for k, ((name, method), df) in enumerate(groups):
        look = adapters.record(name).look
        ls, label = METHODS[method]
        filled = method == "finite_difference"
        size = 4 + 8 * (1 - k / len(groups))  # nested: marks that coincide all show
        kw = dict(color=look.color, mfc=look.color if filled else "none", ms=size)
        ref = df.reference.iloc[0]
        label = f"{name}, {label}" + ("" if ref == "rigid impulse" else f" (its {ref} law)")
        a.plot(df.s_m, df.value, look.marker, ls="none", **kw, label=label)
        b.plot(df.s_m, np.maximum(df.abs_err, FLOOR), look.marker, ls=ls, **kw, label=label)
    a.axhline(0.0, color="tab:gray", lw=0.8)
    a.set_xlabel("impact point s from the COM (m)")
    a.set_ylabel("dv1/ds ((m/s)/m)")
    a.set_title("dv1/ds along the bat (line: rigid theory; zero: the sweet spot)", fontsize=10)
    b.set_yscale("log")
    b.set_xlabel("impact point s from the COM (m)")
    b.set_ylabel("|dv1/ds - the answer that applies| ((m/s)/m)")
    b.set_title(f"error (drawn at {FLOOR:g} where below)", fontsize=10)
    handles, labels = b.get_legend_handles_labels()
    fig.legend(handles, labels, loc="lower center", ncol=3, fontsize=8, frameon=False)
    fig.suptitle(
        "Gradients through the impact, each engine at its reference profile (R161, "
        "paper's swing, e = 0.5)",
        fontsize=11,
    )
    fig.tight_layout(rect=(0, 0.17, 1, 1))
    return fig


def bias(table: pd.DataFrame) -> object:
    """The autodiff dv1/ds's bias through each soft contact against its stiffness, one line per
    resolution omega dt; the rigid closed form is 0."""
    plt = _plt()
    fig, ax = plt.subplots(figsize=(8, 5.5))
    styles = ("-", "--", ":")
    for name, df in table.groupby("engine", sort=False):
        look = adapters.record(name).look
        for k, (res, d) in enumerate(df.groupby("omega_dt")):
            ax.plot(
                d.stiffness_radps,
                np.maximum(d.bias.abs(), FLOOR),
                look.marker,
                ls=styles[k % 3],
                color=look.color,
                mfc="none" if k else look.color,
                label=f"{name}, omega dt = {res:g}",
            )
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("soft contact's stiffness: natural frequency omega (rad/s)")
    ax.set_ylabel("|autodiff dv1/ds - rigid closed form| ((m/s)/m)")
    point = table.analytic.iloc[0]
    ax.set_title(
        f"A soft contact's gradient is a smoothed impact's (closed form {point:.2f} (m/s)/m)",
        fontsize=10,
    )
    ax.legend(fontsize=8)
    fig.tight_layout()
    return fig


def fit_text(fit: dict) -> str:
    """The J fit in a few lines."""
    ls, true = fit["least_squares"], fit["true_j_kgm2"]
    lines = [
        f"J of the R161 from {len(fit['points_m'])} exit speeds with "
        f"{fit['noise_mps']:g} m/s noise: true {true:.6f} kg m^2; closed-form least "
        f"squares {ls['j_kgm2']:.6f} +- {ls['sigma_kgm2']:.6f} ({ls['cost_s']:.3f} s)"
    ]
    for d in fit["descent"]:
        if d["why"]:
            lines.append(f"  {d['engine']}: {d['why']}")
            continue
        lines.append(
            f"  descent through {d['engine']}: {d['j_kgm2']:.6f} kg m^2 in "
            f"{d['iterations']} iterations ({d['cost_s']:.2f} s), "
            f"{d['j_kgm2'] - ls['j_kgm2']:+.2e} from the least-squares fit"
        )
    return "\n".join(lines)


def page(
    summary: pd.DataFrame, sweet: pd.DataFrame, bias_rows: pd.DataFrame, fit: dict, points: int
) -> str:
    """gradients.md: the statuses, the sweet spots, the soft contact's bias and the J fit."""
    sweet = sweet.assign(
        off_mm=1e3 * (sweet.found_m - sweet.reference_m), tolerance_mm=1e3 * sweet.tolerance_m
    )
    cols = [
        "engine",
        "method",
        "reference",
        "reference_m",
        "found_m",
        "off_mm",
        "tolerance_mm",
        "status",
    ]
    parts = [
        "# Gradients through the impact\n",
        "Written by `python -m experiments.gradients` (the command's docstring says how each "
        f"gradient is taken and judged): the paper's swing on the R161, {points} impact points, "
        "each engine at its reference profile. Statuses per engine, method and input, and the "
        "largest error beside the largest tolerance ((m/s) per unit of the input):\n",
        md_table(summary, lambda v: f"{v:.3g}"),
        "\n## The sweet spot as the root of each engine's dv1/ds\n",
        md_table(sweet[cols], lambda v: f"{v:.6g}"),
        "\n## The J fit\n",
        "```\n" + fit_text(fit) + "\n```",
    ]
    if len(bias_rows):
        cols = ["engine", "stiffness_radps", "omega_dt", "value", "analytic", "bias"]
        parts += [
            "\n## A soft contact's gradient ([chart](gradients_bias.png))\n",
            md_table(bias_rows[cols], lambda v: f"{v:.4g}"),
        ]
    return "\n".join(parts) + "\n"
