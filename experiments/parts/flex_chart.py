"""Charts of ``experiments.flex``: the flexible bat's exit speed and vibration along the
barrel, and each engine's segmented bat (accuracy at N = 8, stability over N x dt)."""

from __future__ import annotations

import numpy as np
import pandas as pd

import adapters
from analytic import presets

from ..core.io import figure_png
from ..core.judge import Status

#: Status colours of the stability map (the order is the legend's).
STATUS_COLORS = {
    Status.OK.value: "#2ca02c",
    Status.INACCURATE.value: "#ff7f0e",
    Status.UNJUDGED.value: "#bcbd22",
    Status.ENERGY_GAINED.value: "#d62728",
    Status.NON_FINITE.value: "#7f0000",
    Status.NO_SEPARATION.value: "#9467bd",
    Status.NO_CONTACT.value: "#8c564b",
    Status.ERROR.value: "#000000",
    Status.UNSUPPORTED.value: "#cccccc",
}


#: The accuracy chart's floor: below every float64 engine's rounding, so no marks stack on it.
FLOOR = 1e-15


def _pyplot():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def barrel(rows: pd.DataFrame, spots: pd.DataFrame, zones: dict) -> bytes:
    """Per swing: v1 of the rigid bat and of the beam, and the energy left in bending, against
    the impact point's distance from the barrel end; both sweet spots marked."""
    plt = _pyplot()
    swings = list(dict.fromkeys(rows.swing))
    fig, axes = plt.subplots(
        2, len(swings), figsize=(4.6 * len(swings), 7.0), sharex=True, squeeze=False
    )
    length = presets.R161.length_m
    for col, key in enumerate(swings):
        t = rows[(rows.swing == key) & (rows.modulus_scale == 1.0)].sort_values("x_m")
        d_cm = 100 * (length - t.x_m)
        top, bottom = axes[0][col], axes[1][col]
        top.plot(d_cm, t.v1_rigid_mps, "k--", label="rigid bat, realistic ball")
        top.plot(d_cm, t.v1_beam_mps, "o-", color="#1f77b4", label="beam, realistic ball")
        bottom.plot(d_cm, t.vibration_j, "o-", color="#1f77b4", label="all modes")
        bottom.plot(d_cm, t.mode1_j, "s-", color="#d62728", label="first mode")
        spot = spots[(spots.swing == key) & (spots.modulus_scale == 1.0)].iloc[0]
        for ax in (top, bottom):
            ax.axvline(
                100 * spot.speed_peak_from_tip_m, color="#1f77b4", ls=":", label="exit-speed peak"
            )
            ax.axvline(
                100 * spot.node1_from_tip_m, color="#d62728", ls=":", label="first-mode node"
            )
            if zones.get(key):
                ax.axvspan(
                    100 * zones[key][0],
                    100 * zones[key][1],
                    color="#2ca02c",
                    alpha=0.15,
                    label="sweet zone",
                )
            ax.grid(alpha=0.3)
        top.set_title(f"{key} swing" if key != "still" else "bat at rest, 40 m/s pitch")
        top.set_ylabel("batted-ball speed v1 (m/s)")
        bottom.set_ylabel("energy left in bending (J)")
        bottom.set_xlabel("impact point from the barrel end (cm)")
    axes[0][0].legend(fontsize=8)
    axes[1][0].legend(fontsize=8)
    fig.suptitle(
        "R161 as a Timoshenko beam, hit by the realistic ball (Hunt-Crossley loss, COR falling "
        "with speed: analytic.ball.REALISTIC_BALL) on the beam and the rigid bat alike;\n"
        "under a rate-independent (hysteretic) ball the exit-speed peak lies nearer the end "
        "and the beam returns the ball slower (results/findings.md, section 3c)",
        fontsize=9,
    )
    fig.tight_layout()
    return figure_png(fig)


def engines(accuracy: pd.DataFrame, stability: pd.DataFrame) -> bytes:
    """Left: each engine's exit speed off the chain at N = 8 over the barrel, in units of its
    tolerance. Right: the stability map, status per N and dt, one row of cells per engine."""
    plt = _pyplot()
    names = list(dict.fromkeys(stability.engine)) or list(dict.fromkeys(accuracy.engine))
    fig, (ax, mp) = plt.subplots(
        1, 2, figsize=(14, 0.5 * len(names) + 4.5), gridspec_kw={"width_ratios": [1, 1.3]}
    )
    for name in dict.fromkeys(accuracy.engine):
        t = accuracy[accuracy.engine == name]
        rec = adapters.record(name)
        ratio = np.where(
            t.status.isin([Status.OK.value, Status.INACCURATE.value]), t.err_mps / t.tol_mps, np.nan
        )
        ax.semilogy(
            100 * (presets.R161.length_m - t.x_m),
            np.maximum(ratio, FLOOR),
            marker=rec.look.marker,
            color=rec.look.color,
            label=name,
        )
    ax.axhline(1.0, color="k", lw=1)
    ax.set_xlabel("impact point from the barrel end (cm)")
    ax.set_ylabel(f"|v1 engine - v1 chain| / tolerance (1: the limit; floor {FLOOR:g})")
    ax.set_title("segmented bat, N = 8, reference profiles")
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=8)
    _status_map(mp, stability, names)
    fig.tight_layout()
    return figure_png(fig)


def _status_map(ax, t: pd.DataFrame, names: list[str]) -> None:
    """One row per engine, columns N x dt, coloured by status."""
    cols = [(n, dt) for n in sorted(set(t.segments)) for dt in sorted(set(t.dt_s), reverse=True)]
    for i, name in enumerate(names):
        mine = t[t.engine == name]
        for j, (n, dt) in enumerate(cols):
            hit = mine[(mine.segments == n) & (mine.dt_s == dt)]
            status = hit.status.iloc[0] if len(hit) else Status.UNSUPPORTED.value
            ax.add_patch(_patch(j, i, STATUS_COLORS.get(status, "#ffffff")))
    ax.set_xlim(0, len(cols))
    ax.set_ylim(len(names), 0)
    ax.set_yticks(np.arange(len(names)) + 0.5, names)
    ax.set_xticks(np.arange(len(cols)) + 0.5, [f"N={n}\n{dt:.0e}" for n, dt in cols], fontsize=7)
    ax.set_xlabel("segments N and time step dt (s)")
    ax.set_title(f"stability map at {100 * (presets.R161.length_m - 0.66):.0f} cm from the end")
    from matplotlib.patches import Patch

    ax.legend(
        handles=[Patch(color=c, label=s) for s, c in STATUS_COLORS.items() if s in set(t.status)],
        fontsize=8,
        loc="upper left",
        bbox_to_anchor=(1.0, 1.0),
    )


def _patch(x, y, color):
    from matplotlib.patches import Rectangle

    return Rectangle((x + 0.05, y + 0.05), 0.9, 0.9, color=color)
