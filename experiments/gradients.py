"""Gradients through the impact: each engine's dv1/dx by finite differences through the
harness and by its own automatic differentiation, judged against the closed form.

    python -m experiments.gradients [--engine ...] [--points N] [--quick]

The paper's swing on the R161 (v0 46.9 m/s, u0 17.87 m/s, omega0 32 rad/s, e = 0.5, no
friction), every engine at its reference profile, at N impact points where the rigid answer is
one impulse (``analytic.collide``: the closed-form derivatives hold there). For x in s, v0, e
and J: dv1/dx by central differences through the harness (every engine; the step chosen from
the engine's error model) and by the engine's own ``derivative`` where its adapter has one,
each judged against ``analytic.gradients`` (``experiments.core.gradients``: statuses and
tolerances). Then, per engine and method, the sweet spot as the root of the engine's dv1/ds
against ``analytic.impact.sweet_spot``; for engines with their own derivative and a soft
contact, dv1/ds's bias against stiffness and omega dt; and the R161's J recovered from 20
noisy exit speeds by gradient descent through each differentiable engine, against the
closed-form least-squares fit (``experiments.parts.gradient_studies``). Writes gradients.csv,
gradients_sweet.csv, gradients_bias.csv, gradients.json, gradients.md, gradients.png and
gradients_bias.png.
"""

from __future__ import annotations

import argparse
import sys
import time

import pandas as pd

import adapters
from analytic import presets
from analytic.collide import collide

from .core import cli, firings
from .core.cli import Command
from .core.gradients import INPUTS, finite_differences, gradient_rows, moved
from .core.io import figure_png, json_bytes, provenance
from .parts import gradient_studies as studies
from .parts import gradients_chart

#: The point whose dv1/ds the soft-contact bias is measured at (m from the COM): a steep one.
BIAS_POINT_M = 0.2
#: The grid keeps this far inside the hittable range: a central difference needs room (m).
EDGE_M = 0.01


def base_case():
    """The paper's swing on the R161, frictionless, at the sweet spot's neighbourhood."""
    f = firings.Firing(
        bat=presets.R161,
        s_m=(0.0,),
        v0_mps=presets.PAPER_PITCH_MPS,
        u0_mps=presets.PAPER_SWING.u0_mps,
        omega0_radps=presets.PAPER_SWING.omega0_radps,
        e=presets.E_WOOD,
    )
    return f.cases()[0]


def points(n: int) -> list:
    """The cases at ``n`` points over the hittable range where the rigid answer is one
    impulse."""
    base = base_case()
    bat = base.bat
    grid = firings.grid(bat, n, bat.s_min_m + EDGE_M, bat.s_max_m - EDGE_M)
    cases = [moved(base, "s_m", s) for s in grid]
    return [c for c in cases if collide(c).impacts == 1 and collide(c).sustained_contact_s == 0.0]


def differentiable(names) -> list[str]:
    return [n for n in names if adapters.record(n).can.autodiff]


def _table(names, cases) -> pd.DataFrame:
    rows = [
        r
        for name in names
        for wrt in INPUTS
        for r in gradient_rows(name, adapters.settings_for(name), cases, wrt)
    ]
    return pd.DataFrame(rows)


def _steps(name: str):
    """The episode's steps at given settings (the middle impact's, at BIAS_POINT_M)."""

    def steps(settings) -> int:
        return finite_differences(name, settings, [moved(base_case(), "s_m", BIAS_POINT_M)], "s_m")[
            0
        ]["steps"]

    return steps


def _studies(names, table: pd.DataFrame, quick: bool) -> tuple[list, list, dict]:
    base = base_case()
    steps = {n: int(table[table.engine == n].steps.max()) for n in names}
    sweet = [
        studies.sweet_spot(n, adapters.settings_for(n), base, method, steps[n])
        for n in names
        for method in ("finite_difference", "autodiff")
        if method == "finite_difference" or adapters.record(n).can.autodiff
    ]
    soft = [n for n in differentiable(names) if adapters.record(n).can.soft_contact]
    bias = [
        r
        for n in soft
        for r in studies.soft_bias(n, moved(base, "s_m", BIAS_POINT_M), _steps(n), quick)
    ]
    s, v1 = studies.fit_data(base)
    ls = studies.least_squares_j(base, s, v1)
    fits = [
        studies.descend_j(n, adapters.settings_for(n), base, s, v1, ls["sigma_kgm2"], steps[n])
        for n in differentiable(names)
    ]
    fit = {
        "true_j_kgm2": base.bat.inertia_cm_kgm2,
        "noise_mps": studies.FIT_NOISE_MPS,
        "points_m": list(s),
        "measured_mps": list(v1),
        "least_squares": ls,
        "descent": fits,
    }
    return sweet, bias, fit


def summary(table: pd.DataFrame) -> pd.DataFrame:
    """Per engine, method and input: the statuses and the largest error against its
    tolerance."""
    g = table.groupby(["engine", "method", "input"], sort=False)
    return g.agg(
        points=("status", "size"),
        statuses=("status", lambda s: ", ".join(f"{k} {v}" for k, v in s.value_counts().items())),
        max_abs_err=("abs_err", "max"),
        max_tolerance=("tolerance", "max"),
    ).reset_index()


def _options(p: argparse.ArgumentParser) -> None:
    p.add_argument(
        "--points",
        type=cli.integer(3, 201),
        default=21,
        help="impact points over the hittable range (default 21)",
    )


def produce(args: argparse.Namespace) -> tuple[dict[str, bytes], str]:
    t0 = time.perf_counter()
    cases = points(5 if args.quick else args.points)
    names = list(args.engine)
    table = _table(names, cases)
    sweet, bias, fit = _studies(names, table, args.quick)
    sweet_t, bias_t = pd.DataFrame(sweet), pd.DataFrame(bias)
    sums = summary(table)

    def csv(df: pd.DataFrame) -> bytes:
        return df.to_csv(index=False, float_format="%.9g", lineterminator="\n").encode()

    files = {
        "gradients.csv": csv(table),
        "gradients_sweet.csv": csv(sweet_t),
        "gradients_bias.csv": csv(bias_t),
        "gradients.png": figure_png(gradients_chart.along_the_bat(table, cases)),
        "gradients.json": json_bytes(
            {
                "points": len(cases),
                "summary": sums.to_dict("records"),
                "sweet_spot": sweet,
                "j_fit": fit,
                "elapsed_s": time.perf_counter() - t0,
                "provenance": provenance(),
            }
        ),
    }
    if len(bias_t):
        files["gradients_bias.png"] = figure_png(gradients_chart.bias(bias_t))
    files["gradients.md"] = gradients_chart.page(sums, sweet_t, bias_t, fit, len(cases)).encode()
    text = "\n\n".join(
        [
            sums.to_string(index=False, float_format=lambda v: f"{v:.3g}"),
            sweet_t.drop(columns=["why"]).to_string(index=False, float_format=lambda v: f"{v:.6g}"),
            gradients_chart.fit_text(fit),
        ]
    )
    return files, text


COMMAND = Command(
    name="gradients",
    doc=__doc__,
    produce=produce,
    options=_options,
    quick="5 impact points, one soft stiffness at one resolution",
    runner=False,
)
main = COMMAND.main


if __name__ == "__main__":
    sys.exit(main())
