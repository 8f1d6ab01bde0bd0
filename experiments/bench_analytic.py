"""Benchmark: the vectorized batted-ball speed over 10^6 impact points, and the judge of one
impact (``verdicts.judge``) against it.

    python -m experiments.bench_analytic [--points N] [--repeats K]

Prints the median time and impacts per second and writes bench_analytic.json into the run
directory. The judge is timed on an outcome that is the theory's own answer (no engine: its
time is the judge's alone), the paper's swing at s = 0.1 m with a float64 rigid-contact error
model, the median of JUDGE_CALLS calls after one that fills the caches a run fills once.
"""

from __future__ import annotations

import argparse
import dataclasses
import statistics
import sys
import time

import numpy as np

import adapters
from analytic import ImpactCase, batted_ball_speed, predict, presets

from .core import Physics, Status, cli
from .core.cli import Command
from .core.episode import SimOutcome
from .core.io import json_bytes, provenance
from .core.verdicts import judge

#: One impact judged this many times, the median taken.
JUDGE_CALLS = 100


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
    judge_s = judge_one_impact_s()
    result = {
        "points": args.points,
        "repeats": args.repeats,
        "median_s": med,
        "min_s": min(times),
        "impacts_per_s": args.points / med,
        "judge_calls": JUDGE_CALLS,
        "judge_one_impact_us": judge_s * 1e6,
    }
    return {"bench_analytic.json": json_bytes({**result, "provenance": provenance()})}, (
        f"{args.points} impacts: median {med * 1e3:.2f} ms over {args.repeats} runs, "
        f"{args.points / med:.3g} impacts/s; one impact judged in {judge_s * 1e6:.0f} us"
    )


def judge_one_impact_s() -> float:
    """Median seconds of ``verdicts.judge`` on one impact whose outcome is the theory's answer
    (module docstring): the verdict must be ok, with v1 off by rounding at most."""
    case = ImpactCase(
        bat=presets.R161,
        ball=presets.BASEBALL,
        s_m=0.1,
        v0_mps=presets.PAPER_PITCH_MPS,
        u0_mps=presets.PAPER_SWING.u0_mps,
        omega0_radps=presets.PAPER_SWING.omega0_radps,
        e=presets.E_WOOD,
    )
    theory = dataclasses.asdict(predict(case))
    outcome = SimOutcome(
        **theory,
        engine="theory",
        physics=Physics.SOUND,
        contact_duration_s=0.0,
        peak_penetration_m=0.0,
        steps=1,
        wall_s=0.0,
        settings=adapters.Settings(dt_s=1e-5),
        ended="separated",
        ball_side_m=case.ball.radius_m,
    )
    model = adapters.ErrorModel()
    first = judge(case, outcome, model)
    if first.status is not Status.OK:  # (a judge that refuses theory times nothing sound)
        raise RuntimeError(f"the theory's own answer judged {first.status}")
    times = []
    for _ in range(JUDGE_CALLS):
        t0 = time.perf_counter()
        judge(case, outcome, model)
        times.append(time.perf_counter() - t0)
    return statistics.median(times)


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
