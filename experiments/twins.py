"""Twins: an engine that implements another's model (MJX and MuJoCo Warp of MuJoCo C), row by
row against it on the same MJCF, cause by cause.

    python -m experiments.twins [--engine ...] [--points N]

For every engine whose record names a twin (``twin_of``) and each of its ``twin_steps``: the
paper's swing (R161, v0 46.9 m/s, u0 17.87 m/s, omega0 32 rad/s, e = 0.5) over N points of the
barrel in both engines, the engine with the step's overrides, the twin with the settings the
two share copied from it (the same model, as far as the twin can express it). Reported: the
largest |v1 difference| over the grid and where, the median, and each engine's largest error
against its own reference answer. Steps go from each engine at its own reference profile to
every known cause removed; a difference that stays is a cause not yet found.
Writes twins.csv and twins.json into the run directory.
"""

from __future__ import annotations

import argparse
import dataclasses
import sys
import time

import numpy as np
import pandas as pd

import adapters
from analytic import presets

from .core import cli, estimate, firings, runs, tables
from .core.cli import Command
from .core.io import json_bytes, provenance
from .parts import throughput


def firing(points: int) -> firings.Firing:
    """The paper's swing over ``points`` points of the barrel (s from -0.2 to 0.25 m)."""
    return firings.Firing(
        bat=presets.R161,
        s_m=tuple(np.linspace(-0.2, 0.25, points)),
        v0_mps=presets.PAPER_PITCH_MPS,
        u0_mps=presets.PAPER_SWING.u0_mps,
        omega0_radps=presets.PAPER_SWING.omega0_radps,
        e=presets.E_WOOD,
    )


def twinned(names: tuple[str, ...]) -> list[str]:
    """The engines among ``names`` whose record names a twin."""
    return [n for n in names if adapters.record(n).can.twin_of]


def pair(name: str, step: adapters.TwinStep) -> tuple[adapters.Settings, adapters.Settings]:
    """The engine's settings and its twin's for one step (module docstring)."""
    rec = adapters.record(name)
    mine = adapters.settings_for(name, "reference", **dict(step.overrides))
    twin_ref = adapters.record(rec.can.twin_of).profiles["reference"]
    shared = {}
    if step.shared:
        theirs = {f.name for f in dataclasses.fields(twin_ref)}
        shared = {
            f.name: getattr(mine, f.name) for f in dataclasses.fields(mine) if f.name in theirs
        }
    twin = adapters.settings_for(
        rec.can.twin_of, "reference", **{**shared, **dict(step.twin_overrides)}
    )
    return mine, twin


def _options(p: argparse.ArgumentParser) -> None:
    p.add_argument(
        "--points",
        type=cli.integer(2, 10_000),
        default=41,
        help="impact points over the barrel (default 41)",
    )


def _check(p: argparse.ArgumentParser, args: argparse.Namespace) -> None:
    if not twinned(args.engine):
        p.error(
            f"--engine {','.join(args.engine)}: none implements another engine's model; "
            f"allowed: {', '.join(twinned(adapters.names())) or 'none registered'}"
        )


def _work(args: argparse.Namespace) -> tuple[firings.Firing, list, list]:
    """The firing, each (engine, step, its settings, its twin's), and the jobs: per pair, the
    engine's impacts then its twin's."""
    f = firing(args.points)
    todo = [
        (name, step, *pair(name, step))
        for name in twinned(args.engine)
        for step in adapters.record(name).studies.twin_steps
    ]
    jobs = [
        j
        for name, _, mine, twin in todo
        for j in f.jobs(name, mine) + f.jobs(adapters.record(name).can.twin_of, twin)
    ]
    return f, todo, jobs


def _estimate(args: argparse.Namespace) -> float:
    return sum(estimate.run_s(_work(args)[2]).values())


def produce(args: argparse.Namespace) -> tuple[dict[str, bytes], str]:
    t0 = time.perf_counter()
    f, todo, jobs = _work(args)
    with runs.Progress(len(jobs), "impacts") as bar, cli.runner(args, bar) as runner:
        table = tables.table(runner.fire(jobs), "twins")
    n, rows = len(f.s_m), []
    for i, (name, step, mine, _) in enumerate(todo):
        a = table.iloc[2 * i * n : (2 * i + 1) * n].reset_index(drop=True)
        b = table.iloc[(2 * i + 1) * n : (2 * i + 2) * n].reset_index(drop=True)
        diff = (a.v1_engine_mps - b.v1_engine_mps).abs()
        worst = int(diff.idxmax()) if diff.notna().any() else 0
        rows.append(
            {
                "engine": name,
                "device": throughput.device(name, mine),
                "twin": adapters.record(name).can.twin_of,
                "step": step.label,
                "points": n,
                "max_abs_diff_mps": float(diff.max()),
                "at_s_m": float(a.s_m[worst]),
                "median_abs_diff_mps": float(diff.median()),
                "engine_err_mps": float(a.v1_abs_err_mps.max()),
                "twin_err_mps": float(b.v1_abs_err_mps.max()),
                "statuses": _statuses(a, b),
            }
        )
    out = pd.DataFrame(rows)
    files = {
        "twins.csv": out.to_csv(index=False, float_format="%.6g", lineterminator="\n").encode(),
        "twins.json": json_bytes(
            {
                "points": n,
                "elapsed_s": time.perf_counter() - t0,
                "settings": {
                    f"{name}: {step.label}": {"engine": mine.as_dict(), "twin": twin.as_dict()}
                    for name, step, mine, twin in todo
                },
                "provenance": provenance(),
            }
        ),
    }
    text = out.drop(columns=["twin", "points", "device"]).to_string(
        index=False, float_format=lambda v: f"{v:.3g}"
    )
    return files, text


def _statuses(a: pd.DataFrame, b: pd.DataFrame) -> str:
    """Both engines' statuses, counted ('ok 41 / ok 41')."""

    def count(df: pd.DataFrame) -> str:
        return ", ".join(f"{k} {v}" for k, v in df.status.value_counts().items())

    return f"{count(a)} / {count(b)}"


COMMAND = Command(
    name="twins", doc=__doc__, produce=produce, options=_options, check=_check, estimate=_estimate
)
main = COMMAND.main


if __name__ == "__main__":
    sys.exit(main())
