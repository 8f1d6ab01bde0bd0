"""Benchmark: the vectorized batted-ball speed over 10^6 impact points.

    python -m experiments.bench_analytic [--points N] [--repeats K]

Prints the median time and impacts per second and writes bench_analytic.json into the run
directory.
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time

import numpy as np

from analytic import batted_ball_speed, presets

from .core import cli
from .core.cli import Command
from .core.io import json_bytes, provenance


def _options(p: argparse.ArgumentParser) -> None:
    p.add_argument(
        "--points",
        type=cli.integer(1, 10**8),
        default=1_000_000,
        help="impacts per timed call (1..1e8, default 1e6)",
    )
    p.add_argument(
        "--repeats",
        type=cli.integer(1, 1000),
        default=15,
        help="timed repeats, the median reported (1..1000, default 15)",
    )


def produce(args: argparse.Namespace) -> tuple[dict[str, bytes], str]:
    """Time the vectorized v1 over the grid; the JSON and a one-line summary."""
    bat, ball = presets.R161, presets.BASEBALL
    s = np.linspace(bat.s_min_m, bat.s_max_m, args.points)
    times = []
    for _ in range(args.repeats):
        t0 = time.perf_counter()
        batted_ball_speed(bat, ball, s, v0_mps=46.9, u0_mps=17.87, omega0_radps=32.0, e=0.5)
        times.append(time.perf_counter() - t0)
    med = statistics.median(times)
    result = {
        "points": args.points,
        "repeats": args.repeats,
        "median_s": med,
        "min_s": min(times),
        "impacts_per_s": args.points / med,
    }
    return {"bench_analytic.json": json_bytes({**result, "provenance": provenance()})}, (
        f"{args.points} impacts: median {med * 1e3:.2f} ms over {args.repeats} runs, "
        f"{args.points / med:.3g} impacts/s"
    )


COMMAND = Command(
    name="bench_analytic",
    doc=__doc__,
    produce=produce,
    options=_options,
    engines=False,
    runner=False,
)
main = COMMAND.main


if __name__ == "__main__":
    sys.exit(main())
