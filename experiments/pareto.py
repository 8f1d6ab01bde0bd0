"""Speed against accuracy: every engine over its cost knobs, Pareto fronts, convergence orders.

    python -m experiments.pareto [--quick] [--repeats K]

Each setting fires the paper's swing (R161, v0 = 46.9 m/s, u0 = 17.87 m/s, omega0 = 32 rad/s,
e = 0.5) at points spread over s in [-0.2, 0.25] m. Unlike the reference profile, the contact
instant falls mid-step (contact_phase = 0.5) as in a simulation that does not align it, so the
time step's real cost shows; the aligned reference profile is drawn apart for comparison.
Cost per collision is the wall time to simulate the collision window: WINDOW_S of approach
(``approach_steps`` = WINDOW_S/dt) and the contact until separation, as a simulation must step
through it; with a fixed number of steps an impulse engine would cost the same at every dt.
Writes pareto.csv, pareto.png, pareto.json, convergence.csv and pareto_cheapest.csv (the
cheapest sound setting per engine for max relative errors of 1e-2, 1e-3 and 1e-4) into the run
directory.
"""

from __future__ import annotations

import argparse
import math
import statistics
import sys
import time
from dataclasses import dataclass, replace

import numpy as np
import pandas as pd

import adapters
from analytic import presets

from .core import cli, firings, judge, runs, tables
from .core.cli import Command
from .core.io import figure_png, json_bytes, provenance
from .core.judge import Status
from .core.runner import Runner

STEPS_S = (1e-6, 3e-6, 1e-5, 3e-5, 1e-4, 3e-4, 1e-3, 2e-3, 1 / 240, 1 / 60)
QUICK_STEPS_S = (1e-5, 1e-4, 2e-3, 1 / 240, 1 / 60)
SOFT_OMEGAS = (1000.0, 3000.0, 10000.0)
PHASE = 0.5
WINDOW_S = 1e-3  # simulated approach before contact: 47 mm of ball travel at 46.9 m/s
FLOOR = 1e-16  # errors are drawn no lower than this (float64 rounding of v1 ~ 40 m/s is ~1e-14)


DEFAULT_FAMILY = "default profile"


@dataclass(frozen=True, kw_only=True)
class Config:
    """One point of an engine's knob space: a knob family at one time step."""

    engine: str
    family: str
    overrides: tuple[tuple[str, object], ...]
    profile: str = "reference"

    @property
    def label(self) -> str:
        return ", ".join(
            f"{k}={v:g}" if isinstance(v, float) else f"{k}={v}" for k, v in self.overrides
        )

    def settings(self) -> adapters.Settings:
        return _windowed(adapters.settings_for(self.engine, self.profile, **dict(self.overrides)))


def configs(quick: bool, engines: tuple[str, ...]) -> list[Config]:
    """The knob grid: each engine's knob families (from its record) and its default profile,
    crossed with the time steps; the default profile also at its own (out-of-the-box) step."""
    steps = QUICK_STEPS_S if quick else STEPS_S
    out = []
    for engine in engines:
        rec = adapters.record(engine)
        families = [f for f in rec.studies.speed_accuracy if f.quick or not quick]
        families.append(adapters.KnobFamily(label=DEFAULT_FAMILY, profile="default"))
        for fam in families:
            dts = steps
            if fam.profile == "default":
                dts = sorted({*steps, rec.profiles["default"].dt_s})
            out += [
                Config(
                    engine=engine,
                    family=fam.label,
                    profile=fam.profile,
                    overrides=(("dt_s", dt), ("contact_phase", PHASE), *fam.overrides),
                )
                for dt in dts
            ]
    return out


def _windowed(settings: adapters.Settings) -> adapters.Settings:
    return replace(settings, approach_steps=max(2, round(WINDOW_S / settings.dt_s)))


def evaluate(
    runner: Runner, settings: list[tuple[str, adapters.Settings]], firing, repeats: int
) -> list[dict]:
    """Errors and statuses of each (engine, settings) over the grid; median wall per collision
    over ``repeats`` firings of the grid (all settings go to the runner at once)."""
    jobs = [j for _ in range(repeats) for name, st in settings for j in firing.jobs(name, st)]
    table = tables.table(runner.fire(jobs), "pareto")
    n = len(firing.s_m)
    per_setting = len(settings) * n
    out = []
    for k in range(len(settings)):
        repeated = [
            table.iloc[r * per_setting + k * n : r * per_setting + (k + 1) * n]
            for r in range(repeats)
        ]
        df = repeated[-1]
        ok = df[df.status.isin(judge.MEASURED)]
        counts = df.status.value_counts()
        out.append(
            {
                "median_rel_err": float(ok.v1_rel_err.median()) if len(ok) else math.nan,
                "max_rel_err": float(ok.v1_rel_err.max()) if len(ok) else math.nan,
                # soft contacts: the same against the engine's own law (its discretization alone)
                "max_law_rel_err": float((ok.v1_law_err_mps / ok.v1_law_mps.abs()).max())
                if len(ok) and ok.v1_law_mps.notna().all()
                else math.nan,
                "wall_per_collision_s": statistics.median(w for r in repeated for w in r.wall_s),
                "steps_median": float(df.steps.median()),
                "impacts": len(df),
                **{f"n_{s.value}": int(counts.get(s.value, 0)) for s in Status},
                "all_ok": bool(len(ok) == len(df)),
            }
        )
    return out


def pareto_front(times: np.ndarray, errors: np.ndarray) -> np.ndarray:
    """Indices of non-dominated points (no other is both faster and more accurate), by time."""
    order = np.argsort(times, kind="stable")
    front, best = [], math.inf
    for i in order:
        if errors[i] < best:
            front.append(i)
            best = errors[i]
    return np.array(front, dtype=int)


def knee(times: np.ndarray, errors: np.ndarray) -> int:
    """Index of the front point farthest from the chord joining its ends in log-log space."""
    x, y = np.log10(times), np.log10(np.maximum(errors, FLOOR))
    if len(x) < 3:
        return int(np.argmin(y))
    (x0, y0), (x1, y1) = (x[0], y[0]), (x[-1], y[-1])
    dist = np.abs((y1 - y0) * x - (x1 - x0) * y + x1 * y0 - y1 * x0)
    return int(np.argmax(dist))


def convergence(table: pd.DataFrame) -> pd.DataFrame:
    """Fit max_rel_err ~ C dt^p per engine and family over all-ok settings above the noise."""
    rows = []
    for (engine, family), df in table.groupby(["engine", "family"], sort=False):
        d = df[df.all_ok & (df.max_rel_err > 1e3 * FLOOR)]
        if len(d) < 3:
            rows.append({"engine": engine, "family": family, "p": math.nan, "points": len(d)})
            continue
        x, y = np.log10(d.dt_s.to_numpy()), np.log10(d.max_rel_err.to_numpy())
        p, c = np.polyfit(x, y, 1)
        resid = y - (p * x + c)
        r2 = 1 - resid.var() / y.var() if y.var() > 0 else 1.0
        law = d[d.max_law_rel_err > 1e3 * FLOOR]
        p_law = (
            np.polyfit(np.log10(law.dt_s.to_numpy()), np.log10(law.max_law_rel_err.to_numpy()), 1)[
                0
            ]
            if len(law) >= 3
            else math.nan
        )
        rows.append(
            {
                "engine": engine,
                "family": family,
                "p": p,
                "r2": r2,
                "points": len(d),
                "dt_min_s": d.dt_s.min(),
                "dt_max_s": d.dt_s.max(),
                "err_at_dt_min": float(d.sort_values("dt_s").max_rel_err.iloc[0]),
                "err_at_dt_max": float(d.sort_values("dt_s").max_rel_err.iloc[-1]),
                "p_law": p_law,
                "law_err_at_dt_min": float(d.sort_values("dt_s").max_law_rel_err.iloc[0]),
            }
        )
    return pd.DataFrame(rows)


#: Accuracy targets (max relative error of v1 over the mid-step grid) the study answers for.
TARGETS = (1e-2, 1e-3, 1e-4)


def cheapest(table: pd.DataFrame, targets=TARGETS) -> pd.DataFrame:
    """Per target and engine: the cheapest setting whose every impact is sound and whose max
    relative error against rigid theory is within the target (the row ``engine = "any"`` is the
    cheapest of all); none where no setting reaches it."""
    rows = []
    sound = table[table.all_ok]
    for target in targets:
        hit = sound[sound.max_rel_err <= target]
        for engine in ["any", *table.engine.unique()]:
            d = hit if engine == "any" else hit[hit.engine == engine]
            if d.empty:
                rows.append({"target": target, "engine": engine, "setting": "none reaches it"})
                continue
            best = d.loc[d.wall_per_collision_s.idxmin()]
            rows.append(
                {
                    "target": target,
                    "engine": engine,
                    "winner": best.engine,
                    "setting": f"{best.family}, dt = {best.dt_s:.3g} s",
                    "max_rel_err": best.max_rel_err,
                    "wall_per_collision_s": best.wall_per_collision_s,
                }
            )
    return pd.DataFrame(rows)


def _engine_marks(ax, df: pd.DataFrame, aligned: pd.DataFrame, name: str, color) -> list:
    """One engine's points, Pareto front and knee, soft-law and reference marks on ``ax``;
    the notes it adds under the axes, as (color, text)."""
    notes = []
    colors = {name: color}
    good = df[df.all_ok]
    bad = df[~df.all_ok]
    ax.scatter(
        good.wall_per_collision_s * 1e6,
        np.maximum(good.max_rel_err, FLOOR),
        s=14,
        color=colors[name],
        alpha=0.45,
        label=f"{name}: every impact sound",
    )
    ax.scatter(
        bad.wall_per_collision_s * 1e6,
        _failed_y(bad.max_rel_err),
        s=18,
        color=colors[name],
        marker="x",
        alpha=0.6,
        label=f"{name}: some impacts failed (all failed: drawn at {FAILED_Y:g})",
    )
    if len(good):
        t, e = good.wall_per_collision_s.to_numpy(), good.max_rel_err.to_numpy()
        front = pareto_front(t, e)
        ax.step(
            t[front] * 1e6,
            np.maximum(e[front], FLOOR),
            where="post",
            color=colors[name],
            lw=1.8,
        )
        k = front[knee(t[front], e[front])]
        row = good.iloc[k]
        ax.scatter(
            [t[k] * 1e6],
            [max(e[k], FLOOR)],
            s=160,
            facecolor="none",
            edgecolor=colors[name],
            lw=2,
            zorder=6,
        )
        notes.append(
            (
                colors[name],
                f"{name} knee (circled): {row.family}, dt = "
                f"{row.dt_s:.0e} s: {e[k]:.1e} in {t[k] * 1e6:.0f} us",
            )
        )
    law = good[good.max_law_rel_err.notna()]
    if len(law):
        ax.scatter(
            law.wall_per_collision_s * 1e6,
            np.maximum(law.max_law_rel_err, FLOOR),
            s=22,
            marker="D",
            facecolor="none",
            edgecolor=colors[name],
            lw=0.9,
            label=f"{name}: soft, against its own law",
        )
    ref = aligned[aligned.engine == name]
    ax.scatter(
        ref.wall_per_collision_s * 1e6,
        np.maximum(ref.max_rel_err, FLOOR),
        s=120,
        marker="*",
        color=colors[name],
        edgecolor="black",
        zorder=5,
        label=f"{name}: reference profile (aligned contact)",
    )
    dt = adapters.record(name).profiles["default"].dt_s
    for _, d in df[(df.family == DEFAULT_FAMILY) & np.isclose(df.dt_s, dt)].iterrows():
        verdict = (
            f"max error {d.max_rel_err:.1e}"
            if d.all_ok
            else ", ".join(f"{s.value} {d[f'n_{s.value}']}" for s in Status if d[f"n_{s.value}"])
        )
        notes.append((colors[name], f"{name} out of the box (dt = {dt:.3g} s): {verdict}"))
    return notes


def chart(table: pd.DataFrame, aligned: pd.DataFrame):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(13, 9.5), layout="constrained")
    notes = []
    colors = {n: adapters.record(n).look.color for n in table.engine.unique()}
    for name in table.engine.unique():
        notes += _engine_marks(ax, table[table.engine == name], aligned, name, colors[name])
    # the notes under the axes, the legend to the right: nothing over the data
    bottom = 0.02 + 0.0145 * len(notes)
    for i, (color, text) in enumerate(notes):
        fig.text(0.03, bottom - 0.0145 * (i + 1), text, fontsize=7.5, color=color)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel(_x_label(table))
    ax.set_ylabel("max relative error of v1 over the grid")
    ax.set_title(
        "Speed vs accuracy, R161 swing (v0 46.9, u0 17.87 m/s, omega0 32 rad/s), "
        "contact mid-step; lines: Pareto fronts",
        fontsize=9,
    )
    ax.grid(alpha=0.3, which="both")
    ax.set_ylim(top=10)
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0), ncol=1)
    fig.set_layout_engine("constrained", rect=(0, bottom + 0.01, 1, 0.99 - bottom))
    return fig


def _x_label(table: pd.DataFrame) -> str:
    batched = [n for n in table.engine.unique() if adapters.record(n).batched]
    return (
        f"median wall time per collision (us; a batched engine's "
        f"({', '.join(batched) or 'none'}): its grid of {int(table.impacts.max())} worlds "
        "in one batch, per world)"
    )


FAILED_Y = 3.0
GRID_POINTS = 10  # impact points per setting (4 with --quick)


def _failed_y(errors: pd.Series) -> np.ndarray:
    """Where a setting is drawn: its max error, or FAILED_Y if no impact came back ok."""
    e = errors.to_numpy(dtype=float)
    return np.where(np.isfinite(e), np.maximum(e, FLOOR), FAILED_Y)


def _options(p: argparse.ArgumentParser) -> None:
    p.add_argument(
        "--repeats",
        type=cli.integer(1, 100),
        default=None,
        help="timing repeats per setting (default 3, 1 with --quick)",
    )


def produce(args: argparse.Namespace) -> tuple[dict[str, bytes], str]:
    """Every setting of every chosen engine over the grid: the files and a summary."""
    repeats = args.repeats or (1 if args.quick else 3)
    s = np.linspace(-0.2, 0.25, 4 if args.quick else GRID_POINTS)
    firing = firings.Firing(
        bat=presets.R161,
        s_m=tuple(s),
        v0_mps=presets.PAPER_PITCH_MPS,
        u0_mps=presets.PAPER_SWING.u0_mps,
        omega0_radps=presets.PAPER_SWING.omega0_radps,
        e=presets.E_WOOD,
    )
    t0 = time.perf_counter()
    todo = configs(args.quick, args.engine)
    aligned_settings = [(n, _windowed(adapters.settings_for(n))) for n in args.engine]
    settings = [(c.engine, c.settings()) for c in todo] + aligned_settings
    total = repeats * len(settings) * len(s)
    with runs.Progress(total, "impacts") as bar, cli.runner(args, bar) as runner:
        results = evaluate(runner, settings, firing, repeats)
    table = pd.DataFrame(
        [
            {
                "engine": c.engine,
                "family": c.family,
                "profile": c.profile,
                "label": c.label,
                "dt_s": st.dt_s,
                **r,
            }
            for c, (_, st), r in zip(todo, settings, results)
        ]
    )
    aligned = pd.DataFrame(
        [
            {"engine": n, "profile": "reference", "label": "reference profile", **r}
            for (n, _), r in zip(aligned_settings, results[len(todo) :])
        ]
    )
    conv = convergence(table)
    best = cheapest(table)
    elapsed = time.perf_counter() - t0
    import matplotlib.pyplot as plt

    fig = chart(table, aligned)
    both = pd.concat(
        [
            table,
            aligned.assign(
                family="reference profile (aligned)", dt_s=[st.dt_s for _, st in aligned_settings]
            ),
        ],
        ignore_index=True,
    )
    files = {
        "pareto.csv": both.to_csv(index=False, float_format="%.6g", lineterminator="\n").encode(),
        "pareto.png": figure_png(fig),
        "convergence.csv": conv.to_csv(
            index=False, float_format="%.4g", lineterminator="\n"
        ).encode(),
        "pareto_cheapest.csv": best.to_csv(
            index=False, float_format="%.4g", lineterminator="\n"
        ).encode(),
        "pareto.json": json_bytes(
            {
                "quick": args.quick,
                "repeats": repeats,
                "grid_s_m": list(s),
                "contact_phase": PHASE,
                "elapsed_s": elapsed,
                "provenance": provenance(),
            }
        ),
    }
    plt.close(fig)
    return files, (
        conv.to_string(index=False, float_format=lambda v: f"{v:.3g}")
        + "\n\n"
        + best.to_string(index=False, float_format=lambda v: f"{v:.3g}")
        + f"\n{len(table)} settings in {elapsed:.1f} s"
    )


COMMAND = Command(
    name="pareto", doc=__doc__, produce=produce, options=_options, quick="a small grid (smoke test)"
)
main = COMMAND.main


if __name__ == "__main__":
    sys.exit(main())
