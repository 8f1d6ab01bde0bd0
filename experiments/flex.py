"""The flexible bat: the sweet spot by exit speed and by the first mode's node, from a beam
reference, and every engine's segmented bat against the same chain solved exactly.

    python -m experiments.flex [--engine ...] [--quick]

Beam (``analytic.beam``, ``analytic.flexible``): the R161 as a free-free Timoshenko beam
(its profile fitted to its mass, balance and J_cm; white ash), hit by the realistic ball
(``analytic.ball.REALISTIC_BALL``: Hertz, its COR the assumed law's) along the barrel, for the
paper's swing, a major-league swing and a bat at rest: exit speed, energy left in bending (each
mode), contact time, beside the rigid bat under the same law; the two sweet spots and the sweet zone
(``flex_beam``), with the wood's modulus at 80, 100 and 120%. Chain (``analytic.chain``):
N segments against the Euler-Bernoulli beam as N grows. Engines (``flex_engines``): each
engine's chain at N = 8 on 11 impact points, and a stability map over N x dt.
Writes flex_modes.csv, flex.csv (impacts on the beam), flex_sweet.csv, flex_chain.csv,
flex_engines.csv (the engines' rows, column ``study``: accuracy or stability), flex.json (the
summary) and flex.png, flex_engines.png.
"""

from __future__ import annotations

import argparse
import sys

import pandas as pd

from .core import runs
from .core.cli import Command
from .core.io import json_bytes, provenance
from .core.judge import Status
from .parts import flex_beam as B
from .parts import flex_chart
from .parts import flex_engines as E


def _csv(rows) -> bytes:
    return pd.DataFrame(rows).to_csv(index=False, float_format="%.9g", lineterminator="\n").encode()


def beam_part(quick: bool) -> tuple[list, list, dict]:
    """Impacts along the barrel, the sweet spots and the zones."""
    swings = B.SWINGS[:1] if quick else B.SWINGS
    points = B.POINTS_M[::3] if quick else sorted(set(B.POINTS_M) | set(B.ZONE_POINTS_M))
    scales = (1.0,) if quick else B.MODULUS_SCALES
    with runs.Progress(len(swings) * len(points), "beam impacts") as bar:
        rows = []
        for sw in swings:
            for x in points:
                rows.append(B.impact_row(sw, x))
                bar(1)
    spots = [B.sweet_spots(sw, k) for sw in swings for k in scales]
    zones = {sw.key: B.sweet_zone(rows, sw.key) for sw in swings}
    return rows, spots, zones


def engine_part(names, quick: bool) -> tuple[list, list]:
    """The accuracy rows and the stability map."""
    names = E.chain_engines(names)
    steps = E.MAP_STEPS_S[1:2] if quick else E.MAP_STEPS_S
    segments = E.MAP_SEGMENTS[:2] if quick else E.MAP_SEGMENTS
    each = len(E.POINTS_M) + len(steps) * len(segments)
    with runs.Progress(len(names) * each, "chain impacts") as bar:
        accuracy, stability = [], []
        for n in names:
            mine = [r | {"study": "accuracy"} for r in E.accuracy_rows([n], bar)]
            cost = {n: E.step_body_cost_s(mine)}
            accuracy += mine
            stability += [
                r | {"study": "stability"}
                for r in E.stability_rows([n], cost, steps, segments, bar)
            ]
    return accuracy, stability


def summary(spots, zones, accuracy) -> dict:
    """What the findings quote: the sweet spots per swing and modulus, the zones, and per
    engine the statuses and the worst error at N = 8 against its tolerance."""
    t = pd.DataFrame(accuracy)
    per_engine = {}
    for name, df in t.groupby("engine", sort=False) if len(t) else ():
        judged = df[df.status.isin([Status.OK, Status.INACCURATE])]
        per_engine[name] = {
            "statuses": {k: int(v) for k, v in df.status.value_counts().sort_index().items()},
            "max_err_mps": float(judged.err_mps.max()) if len(judged) else None,
            "max_err_over_tol": float((judged.err_mps / judged.tol_mps).max())
            if len(judged)
            else None,
        }
    return {
        "sweet_spots": spots,
        "sweet_zones_from_tip_m": zones,
        "engines": per_engine,
        "speed_share": B.SPEED_SHARE,
        "sting_share": B.STING_SHARE,
        "provenance": provenance(),
    }


def _options(p: argparse.ArgumentParser) -> None:
    p.add_argument(
        "--quick",
        action="store_true",
        help="the paper's swing at 5 points, the modulus as given, a 2 x 1 map",
    )


def produce(args: argparse.Namespace) -> tuple[dict[str, bytes], str]:
    modes = B.modes_rows()
    rows, spots, zones = beam_part(args.quick)
    chain = B.chain_rows((0.66,) if args.quick else (0.50, 0.66, 0.75))
    accuracy, stability = engine_part(tuple(args.engine), args.quick)
    engines = pd.DataFrame(accuracy + stability)
    files = {
        "flex_modes.csv": _csv(modes),
        "flex.csv": _csv(rows),
        "flex_sweet.csv": _csv(spots),
        "flex_chain.csv": _csv(chain),
        "flex_engines.csv": _csv(accuracy + stability),
        "flex.json": json_bytes(summary(spots, zones, accuracy)),
        "flex.png": flex_chart.barrel(pd.DataFrame(rows), pd.DataFrame(spots), zones),
    }
    if len(engines):
        files["flex_engines.png"] = flex_chart.engines(
            pd.DataFrame(accuracy), pd.DataFrame(stability)
        )
    text = pd.DataFrame(spots).to_string(index=False, float_format=lambda v: f"{v:.4g}")
    return files, text


COMMAND = Command(name="flex", doc=__doc__, produce=produce, options=_options, runner=False)
main = COMMAND.main


if __name__ == "__main__":
    sys.exit(main())
