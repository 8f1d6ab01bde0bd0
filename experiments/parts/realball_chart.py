"""The chart of ``experiments.realball``: each engine's fitted ball models' COR against impact
speed over the declared ball's range (COR_LAWS), its central law (COR_LAW) and MLB's
specification; an engine's best model drawn solid, its others dotted and named."""

from __future__ import annotations

import numpy as np
import pandas as pd

import adapters
from analytic.ball import COR_DATA, COR_LAW, cor_range

from ..core.io import figure_png


def _pyplot():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def render(rows: pd.DataFrame) -> bytes:
    """COR (1) against speed (m/s): the band shaded, the law as a line, MLB's point with its
    error bar, each engine's and model's measured CORs (filled: fitted speeds, open: held out)
    joined by a line (solid: the engine's best model; dotted: another; the model named where
    an engine has several)."""
    plt = _pyplot()
    fig, ax = plt.subplots(figsize=(8.0, 5.2))
    v = np.linspace(8.0, 62.0, 200)
    lo, hi = np.array([cor_range(x) for x in v]).T
    ax.fill_between(v, lo, hi, color="0.88", label="COR_LAWS' range (MLB band x v^-0..0.25)")
    ax.plot(v, [COR_LAW.cor(x) for x in v], "k--", lw=1.2, label="COR_LAW (central)")
    mlb = next(p for p in COR_DATA if p.source == "mlbcor")
    ax.errorbar(
        [mlb.speed_mps], [mlb.cor], yerr=[mlb.half_width], fmt="ks", capsize=4, zorder=5,
        label="MLB specification at 85 ft/s",
    )  # fmt: skip
    several = rows.groupby("engine").model.nunique() > 1
    for (name, model), t in rows.groupby(["engine", "model"], sort=False):
        look = adapters.record(name).look
        t = t.sort_values("speed_mps")
        best = bool(t.best.iloc[0])
        label = f"{name}: {model}{' (best)' if best else ''}" if several[name] else name
        line = "-" if best else ":"
        ax.plot(t.speed_mps, t.cor_engine, line, color=look.color, lw=1.0, alpha=0.8)
        for role, face in (("fit", look.color), ("held_out", "none")):
            s = t[t.role == role]
            ax.plot(
                s.speed_mps, s.cor_engine, look.marker, color=look.color, mfc=face,
                alpha=1.0 if best else 0.6,
                label=label if role == "fit" else None,
            )  # fmt: skip
    ax.set_xlabel("impact speed on a rigid wall (m/s)")
    ax.set_ylabel("COR (v1 - u1)/v0 (1)")
    ax.set_ylim(0.2, 0.9)
    ax.set_title(
        "A baseball in each engine: fitted COR against speed (open: held out; dotted: not "
        "the engine's best model)",
        fontsize=10,
    )
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7, ncol=2, loc="upper right")
    fig.tight_layout()
    png = figure_png(fig)
    plt.close(fig)
    return png
