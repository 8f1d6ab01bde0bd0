"""The friction study's chart: the ball's spin and tangential speed errors against mu, in the
swing plane and with an undercut, per engine and friction family."""

from __future__ import annotations

import numpy as np
import pandas as pd

import adapters

from ..core.io import figure_png

#: Errors below this are drawn on it (log axes; rounding is 1e-16 to 1e-7 relative).
FLOOR = 1e-9
PANELS = (("spin", "spin"), ("tangential", "tangential velocity"))
UNITS = {"spin": "(rad/s) / (rad/s)", "tangential": "(m/s) / (m/s)"}
CASES = (
    ("in the swing plane (theta 0-0.4 rad)", lambda df: df.undercut_m == 0.0),
    ("undercut 1-3 cm (theta 0-0.4 rad)", lambda df: df.undercut_m != 0.0),
)


def render(table: pd.DataFrame) -> bytes:
    """The chart as PNG bytes."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(2, 2, figsize=(12, 11), sharex=True)
    for row, (what, label) in enumerate(PANELS):
        for col, (title, pick) in enumerate(CASES):
            _panel(axes[row, col], table[pick(table)], what, label, title)
    handles, labels = axes[0, 0].get_legend_handles_labels()
    more = axes[0, 1].get_legend_handles_labels()
    for h, lab in zip(*more):
        if lab not in labels:
            handles.append(h)
            labels.append(lab)
    fig.legend(handles, labels, loc="lower center", ncol=3, fontsize=8, frameon=False)
    fig.suptitle(
        "Friction at impact: the ball's spin and tangential speed against Routh's "
        "impulse (paper's swing, e = 0.5; largest over 3 impact points and the angles)",
        fontsize=10,
    )
    fig.tight_layout(rect=(0, 0.2, 1, 0.96))
    png = figure_png(fig)
    plt.close(fig)
    return png


def _panel(ax, df: pd.DataFrame, what: str, label: str, title: str) -> None:
    """Per engine and family, the largest relative error against mu; the one-step law's own
    gap from Routh's impulse in black."""
    ax.set_title(title, fontsize=9)
    ax.set_yscale("log")
    ax.set_ylabel(f"relative {label} error {UNITS[what]}", fontsize=9)
    ax.set_xlabel("coefficient of friction mu")
    ax.axhline(0.01, color="tab:gray", lw=0.8, ls=":")
    if df.empty:
        ax.text(0.5, 0.5, "no 3-D engine", transform=ax.transAxes, ha="center")
        return
    gap = df.groupby("mu")[f"law_{what}_rel_gap"].max()
    ax.plot(
        gap.index,
        np.maximum(gap.values, FLOOR),
        "k--",
        lw=2,
        zorder=5,
        label="the engines' one-step law vs Routh (the law's own gap)",
    )
    for (name, family), part in df.groupby(["engine", "family"], sort=False):
        rec = adapters.record(name)
        err = part.groupby("mu")[f"{what}_rel_err"].max()
        ax.plot(
            err.index,
            np.maximum(err.values, FLOOR),
            rec.look.marker,
            ls="-" if family == "reference" else ":",
            color=rec.look.color,
            mfc="none",
            label=name if family == "reference" else f"{name}, {family}",
        )
