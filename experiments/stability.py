"""Where methods fail: time step x closing speed (x soft-contact stiffness) -> outcome status.

    python -m experiments.stability [--quick]

A still R161 is hit at s = 0.1 m with e = 1 (so any spurious energy shows) by balls of 5 to
100 m/s, at every time step from 1e-6 to 1/60 s, each with the contact instant at K phases of a
step ((k + 1/2)/K). Theory: the contact is seen ``phase * v * dt`` deep; past R = r_ball + r_bat
the ball's centre is beyond the bat's axis, the normal flips and the ball is pushed through. So a
step catches every phase while v dt < R, and a fraction R/(v dt) of them above (THEORY_* below).
An engine whose contact converges to a Hunt-Crossley law gets a map of time step x
closing speed at e = 0.5 judged against that law, with the law's own limits drawn: the rebound
speed bound 1/d and the contact time. An engine with a soft contact (its record's
``soft_contact``) gets its own map: time step x stiffness w at 40 m/s, where an undamped
spring lets the ball sink v/w deep (through the bat when w < v/R) and Euler is unstable for
w dt > 2 (this map uses e = 0.5: at e = 1 every discretized spring gains a little energy).
Writes stability.csv, stability_cells.csv, stability.json, stability.png, stability_energy.png
and stability_<engine>_soft.png into the run directory.
"""

from __future__ import annotations

import argparse
import sys
import time
from dataclasses import replace

import numpy as np
import pandas as pd

import adapters
from analytic import ImpactCase, compliant, presets

from .core import cli, judge, runs, tables
from .core.cli import Command
from .core.fire import Job
from .core.io import figure_png, json_bytes, provenance
from .core.judge import Status
from .parts import throughput

BAT, BALL = presets.R161, presets.BASEBALL
REACH_M = BAT.radius_m + BALL.radius_m
S_M = 0.1
STEPS_S = tuple(np.geomspace(1e-6, 1 / 60, 13))
SPEEDS_MPS = (5.0, 10.0, 20.0, 40.0, 70.0, 100.0)
PHASES = 8
SOFT_OMEGAS = (100.0, 300.0, 1000.0, 3000.0, 10000.0, 30000.0, 100000.0)
SOFT_SPEED_MPS = 40.0
SOFT_E = 0.5  # at e = 1 a discretized spring gains ~w dt of energy on every contact
QUICK = dict(
    steps=tuple(np.geomspace(1e-5, 1 / 60, 5)),
    speeds=(10.0, 40.0, 100.0),
    phases=4,
    omegas=(300.0, 3000.0, 30000.0),
)
#: Each impact's budget (s): these impacts (e >= 0.5, v >= 10 m/s) end within a millisecond in
#: rigid theory, so 20 ms is 20x that; the harness default (0.1 s) is sized for e = 0 slides and
#: would make every held ball in the map 5x dearer.
BUDGET_S = 0.02
#: Sound impacts: ok, or unjudged (a soft contact, not judged against rigid theory)
SOUND = (Status.OK, Status.UNJUDGED)
LETTERS = {
    Status.TUNNELLED: "T",
    Status.NON_FINITE: "N",
    Status.ENERGY_GAINED: "E",
    Status.PENETRATION: "P",
    Status.INACCURATE: "I",
    Status.NO_SEPARATION: "S",
    Status.NO_CONTACT: "C",
    Status.UNSUPPORTED: "U",
    Status.ERROR: "X",
    Status.TIMEOUT: "L",
}


def theory_fraction_caught(
    v_mps: float, dt_s: float, k: int, overlap_m: float = 1e-9, speculative_m: float = 0.0
) -> float:
    """Fraction of the K phases a rigid contact is caught at (``judge.caught_in_theory``)."""
    return float(
        np.mean(
            judge.caught_in_theory(v_mps, dt_s, judge.phases(k), REACH_M, overlap_m, speculative_m)
        )
    )


def map_jobs(
    engine: str,
    profile: str,
    steps,
    speeds,
    k: int,
    extra: dict | None = None,
    e: float = 1.0,
    label: str | None = None,
) -> tuple[list[Job], list[dict]]:
    """The jobs of one map (every step x phase x speed) and, for each, its coordinates."""
    jobs, meta = [], []
    base = adapters.settings_for(engine, profile, **(extra or {}))
    rec = adapters.record(engine)
    stiffness = (
        (extra or {}).get(rec.can.stiffness_setting, np.nan)
        if rec.can.stiffness_setting
        else np.nan
    )
    for dt in steps:
        for phase in judge.phases(k):
            settings = replace(
                base, dt_s=float(dt), contact_phase=float(phase), max_contact_s=BUDGET_S
            )
            for v in speeds:
                jobs.append(
                    Job(
                        engine=engine,
                        settings=settings,
                        case=ImpactCase(bat=BAT, ball=BALL, s_m=S_M, v0_mps=v, e=e),
                    )
                )
                meta.append(
                    {
                        "map": label or f"{engine} {profile}",
                        "engine": engine,
                        "profile": profile,
                        "dt_s": float(dt),
                        "v0_mps": v,
                        "phase": float(phase),
                        "soft_omega_radps": stiffness,
                    }
                )
    return jobs, meta


#: Hunt-Crossley contacts get a map over time step x closing speed at this e (mapped at the
#: engine's stated speed), judged against their own law.
HC_E = 0.5


def hunt_crossley_law(engine: str):
    """The Hunt-Crossley law an engine's reference contact converges to at HC_E, or None."""
    law = adapters.record(engine).errors.contact_law(adapters.settings_for(engine), HC_E)
    return law if isinstance(law, compliant.HuntCrossley) else None


def hc_label(engine: str) -> str:
    d = hunt_crossley_law(engine).dissipation_spm
    return f"{engine} Hunt-Crossley (e = {HC_E:g} mapped, d = {d:.3f} s/m)"


def soft_label(engine: str) -> str:
    return f"{engine} soft"


def summarize(rows: pd.DataFrame, x: str, y: str) -> pd.DataFrame:
    """Per cell: fraction sound (SOUND) and the most common failure."""

    def dominant(s: pd.Series) -> str:
        bad = s[~s.isin(SOUND)]
        return "" if bad.empty else LETTERS[bad.value_counts().index[0]]

    g = rows.groupby(["map", x, y], sort=False)
    return g.agg(
        fraction_ok=("status", lambda s: float(s.isin(SOUND).mean())),
        fraction_caught=("status", lambda s: float(s.isin(judge.MEASURED).mean())),
        failure=("status", dominant),
    ).reset_index()


def _edges(values) -> np.ndarray:
    """Cell edges on a log axis: geometric midpoints, the ends half a step out."""
    v = np.log10(np.asarray(values, dtype=float))
    step = np.diff(v).mean() if len(v) > 1 else 1.0
    mids = (v[:-1] + v[1:]) / 2
    return 10 ** np.concatenate([[v[0] - step / 2], mids, [v[-1] + step / 2]])


def heatmap(ax, cells: pd.DataFrame, x: str, y: str, title: str):
    """Fraction ok per cell on log-log axes, the most common failure lettered in each cell in
    black or white, whichever reads on the cell's colour."""
    import matplotlib

    cmap = matplotlib.colormaps["RdYlGn"]
    xs, ys = sorted(cells[x].unique()), sorted(cells[y].unique())
    grid = np.full((len(ys), len(xs)), np.nan)
    for _, c in cells.iterrows():
        grid[ys.index(c[y]), xs.index(c[x])] = c.fraction_ok
    im = ax.pcolormesh(_edges(xs), _edges(ys), grid, cmap=cmap, vmin=0, vmax=1)
    for _, c in cells.iterrows():
        if c.failure:
            r, g, b, _ = cmap(c.fraction_ok)
            dark = 0.299 * r + 0.587 * g + 0.114 * b < 0.5
            ax.text(
                c[x],
                c[y],
                c.failure,
                ha="center",
                va="center",
                fontsize=9,
                fontweight="bold",
                color="white" if dark else "black",
            )
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_title(title, fontsize=9)
    return im


def chart_maps(
    cells: pd.DataFrame,
    steps,
    speeds,
    margins: dict[str, float] | None = None,
    laws: dict | None = None,
):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    maps = list(cells["map"].unique())
    ncol = 3
    nrow = int(np.ceil(len(maps) / ncol))
    fig, axes = plt.subplots(
        nrow,
        ncol,
        figsize=(14, 4.6 * nrow),
        squeeze=False,
        sharex=True,
        sharey=True,
        layout="constrained",
    )
    dts = np.geomspace(min(steps) / 3, max(steps) * 3, 100)
    for ax, name in zip(axes.flat, maps):
        im = heatmap(ax, cells[cells["map"] == name], "dt_s", "v0_mps", name)
        if name in (laws or {}):
            _draw_hunt_crossley(ax, laws[name], sorted(cells.v0_mps.unique()))
        else:
            ax.plot(dts, REACH_M / dts, "k--", lw=1.2, label="v dt = r_ball + r_bat")
            ax.plot(
                dts,
                2 * REACH_M / dts,
                "k:",
                lw=1,
                label="v dt = 2 (r_ball + r_bat): half the phases",
            )
        margin = (margins or {}).get(name, 0.0)
        if margin > 0.0:
            ax.plot(
                dts,
                (REACH_M + margin) / dts,
                color="tab:blue",
                ls="-.",
                lw=1.2,
                label="v dt = r_ball + r_bat + speculative margin: every phase caught",
            )
        e_x, e_y = _edges(sorted(cells.dt_s.unique())), _edges(sorted(cells.v0_mps.unique()))
        ax.set_xlim(e_x[0], e_x[-1])
        ax.set_ylim(e_y[0], e_y[-1])
    for ax in axes[-1]:
        ax.set_xlabel("time step (s)")
    for ax in axes[:, 0]:
        ax.set_ylabel("closing speed (m/s)")
    for ax in list(axes.flat)[len(maps) :]:
        ax.axis("off")
    legend = {}
    for ax in axes.flat:
        for h, lab in zip(*ax.get_legend_handles_labels()):
            legend.setdefault(lab, h)
    fig.legend(legend.values(), legend.keys(), loc="outside lower center", ncol=2, fontsize=8)
    fig.colorbar(im, ax=axes, shrink=0.8, label="fraction of contact phases ok")
    letters = ", ".join(f"{v} {k.replace('_', ' ')}" for k, v in LETTERS.items())
    fig.suptitle(
        "Outcome over time step x closing speed (still R161, s = 0.1 m, e = 1)\n"
        f"letters: most common failure ({letters})",
        fontsize=9,
    )
    return fig


def _draw_hunt_crossley(ax, law, speeds) -> None:
    """Where a Hunt-Crossley contact's own law stops answering the question: its rebound cannot
    exceed 1/d (e < 1/(d v)), and a step longer than the contact can pass over
    it between two readings (the contact time t_c(v) from ``analytic.compliant``)."""
    ax.axhline(
        1.0 / law.dissipation_spm,
        color="tab:purple",
        ls="-.",
        lw=1.4,
        label="Hunt-Crossley: v = 1/d, above it the rebound stays below 1/d",
    )
    t_c = [
        compliant.predict(
            ImpactCase(bat=BAT, ball=BALL, s_m=S_M, v0_mps=v, e=HC_E), law
        ).contact_duration_s
        for v in speeds
    ]
    ax.plot(
        t_c,
        speeds,
        color="k",
        ls="--",
        lw=1.2,
        label="dt = contact time t_c(v) (compliant contact)",
    )


def chart_soft(cells: pd.DataFrame, steps, omegas, name: str):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(7.5, 5.8), layout="constrained")
    im = heatmap(
        ax,
        cells,
        "dt_s",
        "soft_omega_radps",
        f"{name} contact at {SOFT_SPEED_MPS:g} m/s (e = {SOFT_E:g}): "
        "fraction of phases ok\n"
        "(judged against its own contact law, not rigid theory)",
    )
    dts = np.geomspace(min(steps) / 3, max(steps) * 3, 100)
    ax.plot(dts, 2 / dts, "k--", label="w dt = 2 (Euler stability)")
    ax.axhline(
        SOFT_SPEED_MPS / REACH_M, color="k", ls=":", label="w = v/(r_ball + r_bat): sinks through"
    )
    e_x, e_y = _edges(sorted(cells.dt_s.unique())), _edges(sorted(cells.soft_omega_radps.unique()))
    ax.set_xlim(e_x[0], e_x[-1])
    ax.set_ylim(e_y[0], e_y[-1])
    ax.set_xlabel("time step (s)")
    ax.set_ylabel("contact stiffness w (rad/s)")
    fig.legend(loc="outside lower center", ncol=2, fontsize=8)
    fig.colorbar(im, ax=ax, label="fraction of contact phases ok")
    return fig


def chart_energy(rows: pd.DataFrame):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (top, bottom) = plt.subplots(2, 1, figsize=(10, 7.5), sharex=True)
    colors = {n: adapters.record(n).look.color for n in rows.engine.unique()}
    maps = rows[rows.soft_omega_radps.isna()]
    for (engine, profile), df in maps.groupby(["engine", "profile"], sort=False):
        x = df.v0_mps * df.dt_s * df.phase / REACH_M
        filled = profile == "reference"
        face = colors[engine] if filled else "none"
        top.scatter(
            x,
            np.maximum(df.peak_penetration_m / REACH_M, 1e-12),
            s=10,
            alpha=0.6,
            color=colors[engine],
            facecolor=face,
            label=f"{engine} {profile}",
        )
        change = (df.ke_ratio - 1.0).to_numpy()
        for mask, marker in ((change > 0, "^"), (change <= 0, "v")):
            bottom.scatter(
                x[mask],
                np.maximum(np.abs(change[mask]), 1e-16),
                s=12,
                alpha=0.6,
                marker=marker,
                color=colors[engine],
                facecolor=face,
            )
    for ax in (top, bottom):
        ax.axvline(1.0, color="k", ls="--", lw=1)
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.grid(alpha=0.3, which="both")
    top.set_ylabel("peak penetration / (r_ball + r_bat)\n(gaps drawn at 1e-12)")
    # beside the panels, never over the points
    top.legend(
        fontsize=7,
        ncol=1,
        title="filled: reference solver,\nhollow: default",
        title_fontsize=7,
        loc="upper left",
        bbox_to_anchor=(1.01, 1.0),
    )
    bottom.set_ylabel("|KE after / KE before - 1| at e = 1\n(^ gained, v lost; 0 at 1e-16)")
    bottom.set_xlabel(
        "first-seen overlap phase * v * dt / (r_ball + r_bat); dashed: the ball's "
        "centre reaches the bat's axis"
    )
    top.set_title("Penetration and energy change against the overlap at first contact", fontsize=10)
    fig.tight_layout()
    return fig


def charts(
    table: pd.DataFrame, cells: pd.DataFrame, soft: pd.DataFrame, axes, map_margin: dict, laws: dict
) -> dict[str, bytes]:
    """The maps, the energy chart and each soft contact's map, as PNG bytes by file name;
    ``axes``: (steps, speeds, omegas)."""
    import matplotlib.pyplot as plt

    steps, speeds, omegas = axes
    figs = {
        "stability.png": chart_maps(cells, steps, speeds, map_margin, laws),
        "stability_energy.png": chart_energy(table),
    }
    for name, cells_soft in soft.groupby("map", sort=False):
        figs[f"stability_{name.replace(' ', '_')}.png"] = chart_soft(
            cells_soft, steps, omegas, name
        )
    files = {name: figure_png(fig) for name, fig in figs.items()}
    for fig in figs.values():
        plt.close(fig)
    return files


def all_jobs(engines: tuple[str, ...], steps, speeds, k: int, omegas):
    """Every map's impacts: each engine's two profiles, its Hunt-Crossley law map and its
    soft-contact map where it has them; with the rows' metadata and the laws by map."""
    jobs, meta, laws = [], [], {}

    def add(j, m) -> None:
        jobs.extend(j)
        meta.extend(m)

    for profile in adapters.PROFILES:
        for engine in engines:
            add(*map_jobs(engine, profile, steps, speeds, k))
    for engine in engines:
        law = hunt_crossley_law(engine)
        if law is not None:
            add(*map_jobs(engine, "reference", steps, speeds, k, e=HC_E, label=hc_label(engine)))
            laws[hc_label(engine)] = law
    for engine in engines:
        rec = adapters.record(engine)
        for w in omegas if rec.can.soft_contact is not None else ():
            add(
                *map_jobs(
                    engine,
                    "reference",
                    steps,
                    (SOFT_SPEED_MPS,),
                    k,
                    {**rec.can.soft_contact, rec.can.stiffness_setting: w},
                    e=SOFT_E,
                    label=soft_label(engine),
                )
            )
    return jobs, meta, laws


def produce(args: argparse.Namespace) -> tuple[dict[str, bytes], str]:
    """Every map for the chosen engines: the files and a summary."""
    steps = QUICK["steps"] if args.quick else STEPS_S
    speeds = QUICK["speeds"] if args.quick else SPEEDS_MPS
    k = QUICK["phases"] if args.quick else PHASES
    omegas = QUICK["omegas"] if args.quick else SOFT_OMEGAS
    t0 = time.perf_counter()
    jobs, meta, laws = all_jobs(args.engine, steps, speeds, k, omegas)
    with runs.Progress(len(jobs), "impacts") as bar, cli.runner(args, bar) as runner:
        fired = tables.table(runner.fire(jobs), "")
    table = pd.DataFrame(meta)
    table["status"] = fired.status.to_numpy()
    table["peak_penetration_m"] = fired.peak_penetration_m.to_numpy()
    table["ke_ratio"] = (fired.ke_after_j / fired.ke_before_j).to_numpy()
    table["v1_rel_err"] = fired.v1_rel_err.to_numpy()
    margins = [adapters.record(j.engine).errors.speculative_margin_m(j.settings) for j in jobs]
    table["theory_fraction_caught"] = [
        theory_fraction_caught(v, dt, k, speculative_m=m)
        for v, dt, m in zip(table.v0_mps, table.dt_s, margins)
    ]
    is_soft = table.soft_omega_radps.notna()
    cells = summarize(table[~is_soft], "dt_s", "v0_mps")
    theory = table.groupby(["map", "dt_s", "v0_mps"], sort=False).theory_fraction_caught.first()
    cells["theory_fraction_caught"] = [
        theory[(m, d, v)] for m, d, v in zip(cells["map"], cells.dt_s, cells.v0_mps)
    ]
    soft = summarize(table[is_soft], "dt_s", "soft_omega_radps")
    elapsed = time.perf_counter() - t0
    files = charts(
        table, cells, soft, (steps, speeds, omegas), dict(zip(table["map"], margins)), laws
    )
    files["stability.csv"] = table.to_csv(
        index=False, float_format="%.6g", lineterminator="\n"
    ).encode()
    files["stability_cells.csv"] = (
        pd.concat([cells, soft])
        .to_csv(index=False, float_format="%.6g", lineterminator="\n")
        .encode()
    )
    files["stability.json"] = json_bytes(
        {
            "quick": args.quick,
            "phases": k,
            "elapsed_s": elapsed,
            "provenance": provenance(),
            "devices": {n: throughput.device(n, adapters.settings_for(n)) for n in args.engine},
        }
    )
    rigid = [
        f"{n} reference"
        for n in args.engine
        if adapters.contact_reference(n) is adapters.ContactReference.RIGID_IMPULSE
    ]
    ref = cells[cells["map"].isin(rigid)]
    match = (ref.fraction_caught == ref.theory_fraction_caught).mean()
    return files, (
        f"rigid reference maps: the fraction of contacts caught equals theory in "
        f"{match:.1%} of cells\n{len(table)} impacts in {elapsed:.1f} s"
    )


COMMAND = Command(name="stability", doc=__doc__, produce=produce, quick="a small grid (smoke test)")
main = COMMAND.main


if __name__ == "__main__":
    sys.exit(main())
