"""Benchmark: what a collision costs in each engine, against the bare engine, and sweep speed.

    python -m experiments.bench_engines [--repeats K] [--points N]

For each engine (reference profile, R161, the paper's swing, N impact points):
- per-collision wall time of ``simulate`` (median over impacts and repeats);
- the bare engine's cost for the same steps: the same start state stepped the same number of
  times with nothing else done (median), and the ratio of the two;
- the wall time of ``python -m experiments.sweep --engine all`` on 41 points, start-up included;
- the speed-up of --workers 2 over 1, on a cheap sweep and on an expensive one.
Writes results/bench_engines.csv, .json and .png.
"""

from __future__ import annotations

import argparse
import statistics
import subprocess
import sys
import tempfile
import time

import pandas as pd

import adapters
from adapters.base import start_reading

from . import _grid, sweep
from ._io import ROOT, atomic_write_many, figure_png, json_bytes, provenance


def per_collision(name: str, cases, repeats: int) -> dict:
    engine = adapters.load(name)
    engine.simulate(cases[0])  # build once, outside the timing
    walls, bares, steps = [], [], []
    for _ in range(repeats):
        for case in cases:
            out = engine.simulate(case)
            walls.append(out.wall_s)
            steps.append(out.steps)
            engine._configure(case)
            engine._set_state(start_reading(case, engine.settings)[0])
            t0 = time.perf_counter()
            for _ in range(out.steps):
                engine._step()
            bares.append(time.perf_counter() - t0)
    engine.close()
    wall, bare = statistics.median(walls), statistics.median(bares)
    return {"engine": name, "impacts": len(walls), "steps_median": statistics.median(steps),
            "wall_per_collision_us": wall * 1e6, "bare_steps_us": bare * 1e6,
            "bare_per_step_us": bare * 1e6 / statistics.median(steps), "ratio": wall / bare}


def timed_command(args: list[str], repeats: int) -> float:
    times = []
    for _ in range(repeats):
        with tempfile.TemporaryDirectory() as tmp:
            t0 = time.perf_counter()
            subprocess.run([sys.executable, "-m", "experiments.sweep", *args, "--out", tmp],
                           cwd=ROOT, check=True, capture_output=True)
            times.append(time.perf_counter() - t0)
    return statistics.median(times)


def parallel_speedup(label: str, engines: dict[str, adapters.Settings], points: int,
                     repeats: int) -> dict:
    """Median wall time of firing ``points`` impacts per engine with 1 and 2 worker processes."""
    plan = sweep.sweep_from_args(sweep.build_parser().parse_args(["--points", str(points)]))
    cases = plan.firing.cases()
    out = {"label": label, "points": points, "engines": list(engines)}
    for workers in (1, 2):
        times = []
        for _ in range(repeats):
            t0 = time.perf_counter()
            for name, settings in engines.items():
                _grid.fire(name, settings, "custom", cases, workers=workers)
            times.append(time.perf_counter() - t0)
        out[f"wall_workers{workers}_s"] = statistics.median(times)
    out["speedup"] = out["wall_workers1_s"] / out["wall_workers2_s"]
    return out


def chart(table: pd.DataFrame):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(7, 4))
    x = range(len(table))
    ax.bar([i - 0.2 for i in x], table.wall_per_collision_us, 0.4, label="harness: simulate()")
    ax.bar([i + 0.2 for i in x], table.bare_steps_us, 0.4, label="bare engine, same steps")
    for i, r in table.iterrows():
        ax.annotate(f"{r.ratio:.1f}x", (i - 0.2, r.wall_per_collision_us), ha="center",
                    va="bottom", fontsize=9)
    ax.set_xticks(list(x), table.engine)
    ax.set_ylabel("median time per collision (us)")
    ax.set_title("Cost of one collision, reference profile (dt = 10 us), R161, paper's swing",
                 fontsize=10)
    ax.legend()
    ax.grid(axis="y", alpha=0.3)
    fig.tight_layout()
    return fig


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(prog="python -m experiments.bench_engines",
                                description=__doc__.splitlines()[0])
    p.add_argument("--repeats", type=int, default=5)
    p.add_argument("--points", type=int, default=41)
    args = p.parse_args(argv)
    plan = sweep.sweep_from_args(sweep.build_parser().parse_args(["--points", str(args.points)]))
    table = pd.DataFrame([per_collision(n, plan.firing.cases(), args.repeats)
                          for n in adapters.names()])
    print(table.to_string(index=False, float_format=lambda v: f"{v:.2f}"))
    sweep_s = timed_command(["--engine", "all", "--points", "41"], 3)
    print(f"sweep --engine all, 41 points, start-up included: median {sweep_s:.2f} s")
    par = [
        parallel_speedup("reference, 3 engines", {n: adapters.settings_for(n)
                                                  for n in adapters.names()}, 401, 3),
        parallel_speedup("mujoco soft contact, w = 3000 rad/s, dt = 1e-6 s",
                         {"mujoco": adapters.settings_for("mujoco", contact_model="soft",
                                                          dt_s=1e-6)}, 101, 1),
    ]
    for r in par:
        print(f"{r['label']}, {r['points']} points: 1 worker {r['wall_workers1_s']:.2f} s, "
              f"2 workers {r['wall_workers2_s']:.2f} s, speed-up {r['speedup']:.2f}x")
    import matplotlib.pyplot as plt

    fig = chart(table)
    atomic_write_many({
        ROOT / "results" / "bench_engines.csv":
            table.to_csv(index=False, float_format="%.4g", lineterminator="\n").encode(),
        ROOT / "results" / "bench_engines.json": json_bytes({
            "per_collision": table.to_dict(orient="records"), "sweep_all_41_s": sweep_s,
            "parallel": par, "provenance": provenance()}),
        ROOT / "results" / "bench_engines.png": figure_png(fig),
    })
    plt.close(fig)
    return 0


if __name__ == "__main__":
    sys.exit(main())
