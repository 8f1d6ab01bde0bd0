"""Swing dynamics in the engines against closed form, and the swing-speed models side by side.

    python -m experiments.swing [--quick]

1. Scenes (analytic.dynamics), each run for T_END in every engine and integrator over a range of
   time steps: (a) a force through the COM, (b) a pure torque, (c) a force at the knob at
   q = 0, 45, 90 deg to the axis, held in the bat's frame (the seed lecture's example), (d) a
   torque on the bat hinged at the hands. Errors of angle and angular velocity at T_END against
   closed form (or solve_ivp at rtol 1e-12), and the fitted order p of error ~ dt^p.
   -> swing.csv, swing_orders.csv, swing.png (in the run directory)
2. Swing-speed models: the swing each model predicts for the R161, its corked variants and the
   aluminium bat, given the paper's swing of the R161, and what it does to v1 at the sweet spot.
   -> swing_models.csv, swing_models.png
"""

from __future__ import annotations

import argparse
import itertools
import math
import sys
import time

import numpy as np
import pandas as pd

import adapters
from analytic import (
    SwingModel,
    batted_ball_speed,
    hittable_sweet_spot,
    presets,
    sweet_spot,
    swing_for,
)
from analytic.cork import corked_bat
from analytic.dynamics import Drive, motion, state_array

from .core import cli
from .core.cli import Command
from .core.drive import run_motion
from .core.io import figure_png, json_bytes, provenance
from .core.runner import Runner

T_END_S = 0.1
STEPS_S = (1e-3, 3e-4, 1e-4, 3e-5, 1e-5, 3e-6)
QUICK_STEPS_S = (1e-3, 1e-4)
SCENES = {
    "a: force through COM": Drive(force_n=100.0, force_angle_rad=math.pi / 2),
    "b: pure torque": Drive(torque_nm=50.0),
    "c: knob force, q = 0": Drive(force_n=100.0, force_at_from_knob_m=0.0),
    "c: knob force, q = 45 deg": Drive(
        force_n=100.0, force_at_from_knob_m=0.0, force_angle_rad=math.pi / 4
    ),
    "c: knob force, q = 90 deg": Drive(
        force_n=100.0, force_at_from_knob_m=0.0, force_angle_rad=math.pi / 2
    ),
    "d: torque, hinged at the hands": Drive(torque_nm=72.8, pivot_from_knob_m=0.1),
}
#: The most one engine x integrator x time step may cost, priced at the record's step cost (s,
#: on the records' 2-core host): Drake's and the batched engines' finest steps cost more.
BUDGET_S = 80.0
FLOOR = 1e-13  # drawing floor for errors that are zero or float noise
EPS = float(np.finfo(float).eps)


def noise_floor(df: pd.DataFrame, quantity: str) -> pd.Series:
    """Rounding can grow by ~EPS |value| a step: 8 EPS n max(|value|, 1) bounds it. Errors
    below it are not integration error and stay out of the fits."""
    ref = (
        {
            "angle_err_rad": df.angle_ref_rad,
            "omega_err_radps": df.omega_ref_radps,
            "com_speed_err_mps": df.com_speed_ref_mps,
        }[quantity]
        .abs()
        .clip(lower=1.0)
    )
    return 8 * EPS * df.steps * ref


def wrap(a: float) -> float:
    """An angle difference in (-pi, pi]."""
    return (a + math.pi) % (2 * math.pi) - math.pi


def method_rows(engine: str, integrator: adapters.Integrator, dt: float) -> list[dict]:
    """Every scene in one engine with one integrator and time step, against closed form."""
    bat = presets.R161
    settings = adapters.settings_for(engine, dt_s=dt, **dict(integrator.overrides))
    label = (
        engine
        if len(adapters.record(engine).can.integrators) == 1
        else f"{engine} {integrator.label}"
    )
    rows = []
    for name, drive in SCENES.items():
        t0 = time.perf_counter()
        got = run_motion(engine, settings, bat, drive, T_END_S)
        wall = time.perf_counter() - t0
        ref = motion(bat, drive, got.t_s)  # round(T/dt) steps: compare at n dt
        err = state_array(got) - state_array(ref)
        rows.append(
            {
                "scene": name,
                "engine": engine,
                "method": label,
                "dt_s": dt,
                "angle_err_rad": abs(wrap(err[2])),
                "omega_err_radps": abs(err[5]),
                "com_speed_err_mps": float(np.hypot(err[3], err[4])),
                "angle_ref_rad": ref.angle_rad,
                "omega_ref_radps": ref.omega_radps,
                "com_speed_ref_mps": math.hypot(ref.vx_mps, ref.vy_mps),
                "steps": round(T_END_S / dt),
                "wall_s": wall,
            }
        )
    return rows


def affordable(engine: str, dt: float) -> bool:
    """Whether the scenes at step dt fit BUDGET_S at the record's measured step cost (a batched
    engine steps one world at milliseconds a step on a CPU: its finest steps are left out)."""
    return adapters.record(engine).cost.step_cost_s * round(T_END_S / dt) * len(SCENES) <= BUDGET_S


def scene_errors(runner: Runner, engines: tuple[str, ...], steps) -> pd.DataFrame:
    """Every engine x integrator (from its record) x affordable time step, side by side."""
    calls = [
        (method_rows, (engine, integrator, dt))
        for engine in engines
        for integrator in adapters.record(engine).can.integrators
        for dt in steps
        if affordable(engine, dt)
    ]
    engines_of_calls = [args[0] for _, args in calls]
    return pd.DataFrame([r for rows in runner.call_all(calls, engines_of_calls) for r in rows])


def orders(table: pd.DataFrame) -> pd.DataFrame:
    """Fit err ~ C dt^p per method, scene and quantity, over errors above the rounding floor.
    p is NaN where fewer than 3 steps leave an error above it: exact to rounding."""
    rows = []
    for (scene, method), df in table.groupby(["scene", "method"], sort=False):
        for q in ("angle_err_rad", "omega_err_radps", "com_speed_err_mps"):
            d = df[df[q] > noise_floor(df, q)]
            p = np.polyfit(np.log10(d.dt_s), np.log10(d[q]), 1)[0] if len(d) >= 3 else math.nan
            rows.append(
                {
                    "scene": scene,
                    "method": method,
                    "quantity": q,
                    "p": p,
                    "points": len(d),
                    "err_at_smallest_dt": float(df.sort_values("dt_s")[q].iloc[0]),
                }
            )
    return pd.DataFrame(rows)


QUANTITIES = (
    ("angle_err_rad", "angle error (rad)"),
    ("omega_err_radps", "angular velocity error (rad/s)"),
    ("com_speed_err_mps", "COM velocity error (m/s)"),
)


def chart_scenes(table: pd.DataFrame):
    """Error against time step, one column per scene and one row per quantity; every method
    drawn, each a little smaller than the one before (equal curves stack visibly, one legend
    below), and a panel whose errors are all rounding says so."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    scenes = list(dict.fromkeys(table.scene))
    methods = list(dict.fromkeys(table.method))
    colors = dict(zip(methods, itertools.cycle(plt.cm.tab20.colors)))
    markers = dict(zip(methods, itertools.cycle("osv^Dpx*<>hP")))
    fig, axes = plt.subplots(
        len(QUANTITIES),
        len(scenes),
        figsize=(3.3 * len(scenes), 11),
        sharex=True,
        layout="constrained",
    )
    for col, scene in enumerate(scenes):
        df = table[table.scene == scene]
        for row, (q, label) in enumerate(QUANTITIES):
            ax = axes[row, col]
            above = df[df[q] > noise_floor(df, q)]
            if above.empty:
                ax.text(
                    0.5,
                    0.5,
                    f"every method exact\nto rounding\n(max {df[q].max():.0e})",
                    transform=ax.transAxes,
                    ha="center",
                    va="center",
                    fontsize=8,
                )
                ax.set_xscale("log")
                ax.set_yticks([])
            # every method drawn, each smaller than the one before: equal curves stack visibly
            for method, d in df.groupby("method", sort=False) if not above.empty else []:
                k = methods.index(method) / max(len(methods) - 1, 1)
                ax.loglog(
                    d.dt_s,
                    np.maximum(d[q], FLOOR),
                    "-",
                    marker=markers[method],
                    ms=9 - 6 * k,
                    mfc="none",
                    lw=2.6 - 2.0 * k,
                    alpha=0.85,
                    color=colors[method],
                    label=method,
                )
            ax.grid(alpha=0.3, which="both")
            if row == 0:
                ax.set_title(scene, fontsize=9)
            if col == 0:
                ax.set_ylabel(label)
            if row == len(QUANTITIES) - 1:
                ax.set_xlabel("time step (s)")
    handles = [
        plt.Line2D([], [], color=colors[m], marker=markers[m], mfc="none", label=m) for m in methods
    ]
    fig.legend(handles=handles, loc="outside lower center", ncol=7, fontsize=7)
    fig.suptitle(
        f"Forces and torques on the R161 in each engine and integrator vs closed form "
        f"/ solve_ivp: |error| at t = {T_END_S:g} s (errors below the rounding floor "
        f"drawn at {FLOOR:g})",
        fontsize=10,
    )
    return fig


def swing_models() -> pd.DataFrame:
    """Each bat under each swing model, from the paper's R161 swing."""
    ref, pitch = presets.R161, presets.PAPER_PITCH_MPS
    bats = {"R161 (wood)": ref}
    for depth_in in (6, 8, 10):
        bats[f"R161 corked 1x{depth_in} in, cork"] = corked_bat(ref, hole_depth_m=depth_in * 0.0254)
    bats["R161 corked 1x10 in, rubber"] = corked_bat(ref, fill_density_kgm3=1100.0)
    bats["R161 hollowed 1x10 in"] = corked_bat(ref, fill_density_kgm3=0.0)
    bats["Easton 31 in (aluminium)"] = presets.EASTON31
    rows = []
    for label, bat in bats.items():
        for model in SwingModel:
            sw = swing_for(bat, model=model, reference_bat=ref, reference=presets.PAPER_SWING)
            s_star = sweet_spot(bat, presets.BASEBALL, pitch, sw.u0_mps, sw.omega0_radps)
            s_hit = hittable_sweet_spot(bat, presets.BASEBALL, pitch, sw.u0_mps, sw.omega0_radps)
            v1 = float(
                batted_ball_speed(
                    bat,
                    presets.BASEBALL,
                    s_hit,
                    v0_mps=pitch,
                    u0_mps=sw.u0_mps,
                    omega0_radps=sw.omega0_radps,
                    e=presets.E_WOOD,
                )
            )
            rows.append(
                {
                    "bat": label,
                    "model": model.value,
                    "mass_kg": bat.mass_kg,
                    "inertia_knob_kgm2": bat.inertia_knob_kgm2,
                    "u0_mps": sw.u0_mps,
                    "omega0_radps": sw.omega0_radps,
                    "sweet_spot_m": s_star,
                    "bat_speed_at_sweet_spot_mps": sw.speed_at(s_hit),
                    "v1_max_mps": v1,
                }
            )
    return pd.DataFrame(rows)


def chart_models(table: pd.DataFrame):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    bats = list(dict.fromkeys(table.bat))
    models = list(dict.fromkeys(table.model))
    fig, (left, right) = plt.subplots(1, 2, figsize=(13, 5), layout="constrained")
    width = 0.8 / len(models)
    for i, model in enumerate(models):
        d = table[table.model == model].set_index("bat").loc[bats]
        x = np.arange(len(bats)) + (i - (len(models) - 1) / 2) * width
        left.bar(x, d.bat_speed_at_sweet_spot_mps, width, label=model)
        right.bar(x, d.v1_max_mps, width, label=model)
    for ax, label in (
        (left, "bat speed at the sweet spot (m/s)"),
        (right, "batted-ball speed at the sweet spot (m/s)"),
    ):
        ax.set_xticks(np.arange(len(bats)), bats, rotation=30, ha="right", fontsize=8)
        ax.set_ylabel(label)
        ax.grid(axis="y", alpha=0.3)
        ref = table[(table.bat == bats[0])].iloc[0]
        ax.axhline(
            ref.bat_speed_at_sweet_spot_mps if ax is left else ref.v1_max_mps,
            color="k",
            lw=0.8,
            ls=":",
        )
        lo = table.bat_speed_at_sweet_spot_mps if ax is left else table.v1_max_mps
        ax.set_ylim(lo.min() * 0.95, lo.max() * 1.02)
    left.legend(title="swing model", fontsize=8)
    fig.suptitle(
        "Swing-speed models: the paper's R161 swing (u0 17.87 m/s, omega0 32 rad/s) "
        "carried to other bats; pitch 46.9 m/s, e = 0.5",
        fontsize=10,
    )
    return fig


def produce(args: argparse.Namespace) -> tuple[dict[str, bytes], str]:
    """The scenes in every chosen engine and integrator, and the swing-model table."""
    t0 = time.perf_counter()
    with cli.runner(args) as runner:
        steps = QUICK_STEPS_S if args.quick else STEPS_S
        table = scene_errors(runner, args.engine, steps)
    fits = orders(table)
    models = swing_models()
    import matplotlib.pyplot as plt

    figs = {"swing.png": chart_scenes(table), "swing_models.png": chart_models(models)}
    files = {n: figure_png(f) for n, f in figs.items()}
    for f in figs.values():
        plt.close(f)
    for name, df, fmt in (
        ("swing.csv", table, "%.6g"),
        ("swing_orders.csv", fits, "%.4g"),
        ("swing_models.csv", models, "%.6g"),
    ):
        files[name] = df.to_csv(index=False, float_format=fmt, lineterminator="\n").encode()
    left_out = {e: [dt for dt in steps if not affordable(e, dt)] for e in args.engine}
    files["swing.json"] = json_bytes(
        {
            "t_end_s": T_END_S,
            "quick": args.quick,
            "budget_s": BUDGET_S,
            "steps_left_out_s": {e: v for e, v in left_out.items() if v},
            "elapsed_s": time.perf_counter() - t0,
            "provenance": provenance(),
        }
    )
    pivot = fits.pivot_table(
        index=["scene", "method"], columns="quantity", values="p", dropna=False, sort=False
    )
    why = f"--quick fires {len(steps)} time steps, too few to fit an order: " if args.quick else ""
    head = (
        f"order p of error ~ dt^p ({why}NaN where fewer than 3 steps leave an error above "
        "rounding)\n"
    )
    text = (
        head
        + pivot.to_string(float_format=lambda v: f"{v:.2f}")
        + "\n"
        + models.pivot_table(
            index="bat", columns="model", values="v1_max_mps", sort=False
        ).to_string(float_format=lambda v: f"{v:.2f}")
    )
    return files, text


COMMAND = Command(
    name="swing", doc=__doc__, produce=produce, quick="two time steps only (smoke test)"
)
main = COMMAND.main


if __name__ == "__main__":
    sys.exit(main())
