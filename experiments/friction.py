"""Friction study: per engine, the error in the ball's spin and tangential speed over mu x
obliquity x undercut, and where each engine's approximation of Coulomb's cone shows.

    python -m experiments.friction [--engine ...] [--quick]

The paper's swing (R161, v0 46.9 m/s, u0 17.87 m/s, omega0 32 rad/s, e = 0.5) at POINTS_M, for
every engine with friction at its reference profile and each of its record's
``friction_families`` (another cone, friction solved otherwise): mu in MUS with the ball
oblique in the swing plane (THETAS_RAD, undercut 0) and, in the 3-D engines, undercut
(UNDERCUTS_M, theta 0) and both at once (DIAGONAL). Each impact is compared, as a sweep
compares it
(``experiments.core.friction_judge``), with Routh's impulse (theory, ``analytic.friction``)
and with the law an impulse engine solves in one step (Newton's restitution and Coulomb's cone
on the total impulse, ``one_step_impulse``, or its relaxation a convex solver converges to:
``ErrorModel.friction_law``), which its status judges: the engine's error splits
into the law's own gap from Routh's (``law_*``) and the engine's from its law (``*_law``),
where a pyramid, a relaxed cone or friction solved apart from the normal show.
Writes friction.csv (one row per impact), friction.json (per engine and family: the largest
relative errors, and the cells where the spin misses its law by more than SPIN_COST_REL) and
friction.png.
"""

from __future__ import annotations

import argparse
import math
import sys
from dataclasses import replace

import numpy as np
import pandas as pd

import adapters
from analytic import presets

from .core import cli, firings, runs, tables
from .core.cli import Command
from .core.fire import Job
from .core.io import json_bytes, provenance
from .core.judge import Status
from .parts import friction_chart

MUS = (0.1, 0.25, 0.5, 1.0)
THETAS_RAD = (0.0, 0.2, 0.4)
UNDERCUTS_M = (0.01, 0.02, 0.03)
#: Oblique and undercut at once: the slip turns across both tangents, where a pyramid or a
#: box of two friction rows departs from Coulomb's cone.
DIAGONAL = ((0.4, 0.02), (0.2, 0.03))
POINTS_M = (-0.05, 0.1, 0.2)
#: A spin error beyond this fraction of the spin is where an engine's cone costs (the cells
#: the summary lists).
SPIN_COST_REL = 0.01


def friction_engines(names: tuple[str, ...]) -> list[str]:
    """The engines among ``names`` whose adapter sets friction."""
    return [n for n in names if adapters.record(n).can.friction_rule is not None]


def families(name: str) -> list[tuple[str, adapters.Settings]]:
    """(label, settings): the reference profile, then each friction family."""
    rec = adapters.record(name)
    return [
        ("reference", adapters.settings_for(name)),
        *(
            (f.label, adapters.settings_for(name, f.profile, **dict(f.overrides)))
            for f in rec.studies.friction_families
        ),
    ]


def cells(planar: bool, quick: bool) -> list[dict]:
    """The (mu, theta, undercut) cells an engine is fired over."""
    mus = MUS[1::2] if quick else MUS
    out = [dict(mu=mu, theta_rad=t, undercut_m=0.0) for mu in mus for t in THETAS_RAD]
    if not planar:
        out += [dict(mu=mu, theta_rad=0.0, undercut_m=u) for mu in mus for u in UNDERCUTS_M]
        out += [dict(mu=mu, theta_rad=t, undercut_m=u) for mu in mus for t, u in DIAGONAL]
    return out


def jobs(name: str, quick: bool) -> list[tuple[str, Job]]:
    """(family, job) for every family, cell and impact point of one engine."""
    base = firings.Firing(
        bat=presets.R161,
        s_m=POINTS_M,
        v0_mps=presets.PAPER_PITCH_MPS,
        u0_mps=presets.PAPER_SWING.u0_mps,
        omega0_radps=presets.PAPER_SWING.omega0_radps,
        e=presets.E_WOOD,
    )
    return [
        (label, job)
        for label, st in families(name)
        for cell in cells(adapters.record(name).can.planar, quick)
        for job in replace(base, **cell).jobs(name, st)
    ]


def relative_errors(table: pd.DataFrame) -> pd.DataFrame:
    """The table with relative errors of the ball's tangential velocity (vt1, vz1) and spin
    (backspin1, spin1) as vectors: the engine's against Routh's impulse (``*_rel_err``) and
    against the one-step law (``*_rel_err_law``), and the law's own gap from Routh's
    (``law_*_rel_gap``), each over the size of Routh's vector, or where that is smaller, what
    the contact's slip before the impact makes of it (a ball leaving rolling on it: slip0 for
    the velocity, slip0 / r for the spin; a near-square hit leaves with almost no spin, and
    its relative error would say nothing); and the law's v1 gap (m/s)."""
    t = table.copy()
    pairs = {"tangential": ("vt1", "vz1", "mps"), "spin": ("backspin1", "spin1", "radps")}
    r = presets.BASEBALL.radius_m
    for what, (a, b, unit) in pairs.items():
        routh, engine, law = (
            t[[f"{a}_{k}_{unit}", f"{b}_{k}_{unit}"]].to_numpy()
            for k in ("analytic", "engine", "law")
        )
        floor = t.slip0_mps.to_numpy() / (r if what == "spin" else 1.0)
        scale = np.maximum(np.linalg.norm(routh, axis=1), floor)
        with np.errstate(divide="ignore", invalid="ignore"):
            t[f"{what}_rel_err"] = np.linalg.norm(engine - routh, axis=1) / scale
            t[f"{what}_rel_err_law"] = np.linalg.norm(engine - law, axis=1) / scale
            t[f"law_{what}_rel_gap"] = np.linalg.norm(law - routh, axis=1) / scale
    t["law_v1_gap_mps"] = (t.v1_law_mps - t.v1_analytic_mps).abs()
    return t


def summary(t: pd.DataFrame) -> list[dict]:
    """Per engine and family: statuses, the largest errors (against its law over the rows
    judged against it: NaN for a compliant contact, which follows no one-step law), and the
    cells where the spin misses its law by more than SPIN_COST_REL (the cone's cost)."""
    out = []
    for (name, family), df in t.groupby(["engine", "family"], sort=False):
        judged = df[df.status != Status.UNJUDGED.value]
        costly = judged[judged.spin_rel_err_law > SPIN_COST_REL]
        out.append(
            {
                "engine": name,
                "family": family,
                "friction_cone": df.friction_cone.iloc[0],
                "friction_law": df.friction_law.iloc[0] if len(judged) else "none (compliant)",
                "statuses": {k: int(v) for k, v in df.status.value_counts().sort_index().items()},
                **{
                    f"max_{c}": float(df[c].max())
                    for c in ("spin_rel_err", "tangential_rel_err", "v1_abs_err_mps")
                },
                **{
                    f"max_{c}": float(judged[c].max()) if len(judged) else math.nan
                    for c in ("spin_rel_err_law", "tangential_rel_err_law", "v1_law_err_mps")
                },
                "spin_cost_cells": sorted(
                    {
                        f"mu={r.mu:g} theta={r.theta_rad:g} undercut={r.undercut_m:g}"
                        for r in costly.itertuples()
                    }
                ),
            }
        )
    return out


def _options(p: argparse.ArgumentParser) -> None:
    p.add_argument("--quick", action="store_true", help="two friction coefficients, not four")


def _check(p: argparse.ArgumentParser, args: argparse.Namespace) -> None:
    if not friction_engines(args.engine):
        p.error(
            f"--engine {','.join(args.engine)}: none sets friction; allowed: "
            + ", ".join(friction_engines(adapters.names()))
        )


def produce(args: argparse.Namespace) -> tuple[dict[str, bytes], str]:
    todo = [fj for name in friction_engines(args.engine) for fj in jobs(name, args.quick)]
    with runs.Progress(len(todo), "impacts") as bar, cli.runner(args, bar) as runner:
        fired = runner.fire([j for _, j in todo])
    t = tables.table(fired, "reference", spin_columns=True)
    t.insert(1, "family", [label for label, _ in todo])
    t = relative_errors(t)
    rows = summary(t)
    files = {
        "friction.csv": t.to_csv(index=False, float_format="%.9g", lineterminator="\n").encode(),
        "friction.json": json_bytes(
            {
                "summary": rows,
                "mus": MUS,
                "thetas_rad": THETAS_RAD,
                "undercuts_m": UNDERCUTS_M,
                "points_m": POINTS_M,
                "spin_cost_rel": SPIN_COST_REL,
                "provenance": provenance(),
            }
        ),
        "friction.png": friction_chart.render(t),
    }
    text = (
        pd.DataFrame(rows)
        .drop(columns=["spin_cost_cells", "statuses"])
        .to_string(index=False, float_format=lambda v: f"{v:.3g}")
    )
    return files, text


COMMAND = Command(name="friction", doc=__doc__, produce=produce, options=_options, check=_check)
main = COMMAND.main


if __name__ == "__main__":
    sys.exit(main())
