"""Benchmark: the vectorized batted-ball speed over 10^6 impact points.

    python -m experiments.bench_analytic [--points N] [--repeats K]

Prints the median time and impacts per second and writes results/bench_analytic.json.
"""

from __future__ import annotations

import argparse
import statistics
import time

import numpy as np

from analytic import batted_ball_speed, presets

from ._io import ROOT, provenance, write_json


def main(argv: list[str] | None = None) -> dict:
    parser = argparse.ArgumentParser(prog="python -m experiments.bench_analytic",
                                     description=__doc__.splitlines()[0])
    parser.add_argument("--points", type=int, default=1_000_000)
    parser.add_argument("--repeats", type=int, default=15)
    args = parser.parse_args(argv)
    bat, ball = presets.R161, presets.BASEBALL
    s = np.linspace(bat.s_min_m, bat.s_max_m, args.points)
    times = []
    for _ in range(args.repeats):
        t0 = time.perf_counter()
        batted_ball_speed(bat, ball, s, v0_mps=46.9, u0_mps=17.87, omega0_radps=32.0, e=0.5)
        times.append(time.perf_counter() - t0)
    med = statistics.median(times)
    result = {"points": args.points, "repeats": args.repeats, "median_s": med,
              "min_s": min(times), "impacts_per_s": args.points / med}
    print(f"{args.points} impacts: median {med * 1e3:.2f} ms over {args.repeats} runs, "
          f"{args.points / med:.3g} impacts/s")
    write_json(ROOT / "results" / "bench_analytic.json", {**result, "provenance": provenance()})
    return result


if __name__ == "__main__":
    main()
