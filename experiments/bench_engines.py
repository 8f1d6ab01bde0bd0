"""Benchmark: what a collision costs in each engine, against the bare engine, and the runners.

    python -m experiments.bench_engines [--engine ...] [--repeats K] [--points N] [--quick]

For each engine (reference profile, R161, the paper's swing, N impact points):
- the harness's cost per collision: firing the grid through the runner and tabulating it
  (median over repeats of the whole grid's time per impact), and simulate()'s own wall;
- the bare engine's cost for the same steps: the same start state stepped the same number of
  times with nothing else done (median; a batched engine's grid as the one batch the harness
  fired, its slowest world's steps); overhead = harness - bare, and their ratio; and one
  world's bare step (``one_world_step_us``, what a record's ``step_cost_s`` states);
- one sweep's wall time serially, with 2 local processes and on a 2-worker Dask LocalCluster, on
  the cheap sweep of every single-world engine (a batched engine's jobs stay in the runner's
  process) and on an expensive hinged-swing sweep of 96 points;
- the wall time of the sweep command on 41 points, start-up included;
- throughput against batch size (``experiments.parts.throughput``): impacts per second at each
  --batches size, with the largest error against theory and the harness's own share, on the
  device each engine computes on. --batches-only measures this part alone (a batched engine
  on a GPU machine: BATSIM_WARP_DEVICE=cuda:0 for the engines on Warp, JAX's default device
  for those on JAX). Every row this run did not measure again (another engine's, one on the
  other kind of device, CPU or GPU, or at a batch size not asked for) is kept from --keep-rows
  (default: the committed results/bench_batches.csv), so that one table holds them all and a
  run of one engine replaces only its own rows (``throughput.merged``).
Writes bench_engines.csv, .json and .png (not with --batches-only), and bench_batches.csv and
.png into the run directory.
"""

from __future__ import annotations

import argparse
import contextlib
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import pandas as pd

import adapters
from adapters import Scene
from analytic import presets

from . import sweep as sweep_cmd
from .core import cli, firings, inputs, runs, tables
from .core.cli import Command
from .core.hosting import hosted
from .core.io import ROOT, figure_png, json_bytes, provenance
from .core.placement import start_state
from .core.runner import MIN_PARALLEL_S, Runner
from .errors import BadInput
from .parts import throughput

#: The table whose rows a run does not measure again are kept by default (committed).
KEEP_ROWS = ROOT / "results" / "bench_batches.csv"


def per_collision(name: str, firing: firings.Firing, repeats: int) -> dict:
    """Median cost per collision, through the harness and for the bare engine, same steps."""
    settings = adapters.settings_for(name)
    jobs = firing.jobs(name, settings)
    runner = Runner()
    # build the scene (a batched engine: the grid's batch) outside the timing
    tables.table(runner.fire(jobs if adapters.record(name).batched else jobs[:1]), "bench")
    harness, walls, bares, steps, grid = [], [], [], [], []
    host = hosted(name, settings)
    for _ in range(repeats):
        t0 = time.perf_counter()
        fired = runner.fire(jobs)
        tables.table(fired, "bench")
        harness.append((time.perf_counter() - t0) / len(jobs))
        walls += [f.outcome.wall_s for f in fired]
        steps += [f.outcome.steps for f in fired]
        if host.batched:  # the harness fired the grid as one batch: its bare is that batch's
            grid.append(
                throughput.bare_s(
                    name, settings, [f.case for f in fired], max(f.outcome.steps for f in fired)
                )
                / len(fired)
            )
    for _ in range(repeats):  # one world at a time (a batched engine: rebuilt for one world)
        for f in fired:
            batch = host.batch(Scene(bat=f.case.bat, ball=f.case.ball, e=f.case.e), 1)
            batch.set_state(batch.xp.stack([start_state(f.case, settings)[0]]))
            t0 = time.perf_counter()
            for _ in range(f.outcome.steps):
                batch.step()
            bares.append(time.perf_counter() - t0)
    runner.close()
    one = statistics.median(bares)
    per, bare = statistics.median(harness), statistics.median(grid) if grid else one
    sim = statistics.median(walls)
    return {
        "engine": name,
        "impacts": len(walls),
        "steps_median": statistics.median(steps),
        "harness_per_collision_us": per * 1e6,
        "simulate_per_collision_us": sim * 1e6,
        "bare_steps_us": bare * 1e6,
        "bare_per_step_us": bare * 1e6 / statistics.median(steps),
        "one_world_step_us": one * 1e6 / statistics.median(steps),
        "simulate_overhead_us": (sim - bare) * 1e6,
        "harness_overhead_us": (per - bare) * 1e6,
        "ratio": per / bare,
    }


def timed_command(args: list[str], repeats: int) -> float:
    """Median wall time of a sweep command, start-up included (s)."""
    times = []
    for _ in range(repeats):
        with tempfile.TemporaryDirectory() as tmp:
            t0 = time.perf_counter()
            subprocess.run(
                [sys.executable, "-m", "experiments.sweep", *args, "--out", tmp],
                cwd=ROOT,
                check=True,
                capture_output=True,
                env={**os.environ, "BATSIM_QUIET": "1"},
            )
            times.append(time.perf_counter() - t0)
    return statistics.median(times)


def _burn(n: int) -> float:
    x = 0
    for i in range(n):
        x += i * i
    return float(x)


def machine_ceiling(repeats: int = 3, n: int = 5_000_000) -> float:
    """What two processes gain over one on this machine for pure CPU work: the same Python loop
    twice in this process, then once in each of two processes started together; the median
    ratio of the two wall times. No runner can beat it."""
    import multiprocessing

    fork = multiprocessing.get_context("fork")
    ratios = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        _burn(n), _burn(n)
        serial = time.perf_counter() - t0
        procs = [fork.Process(target=_burn, args=(n,)) for _ in range(2)]
        t0 = time.perf_counter()
        for proc in procs:
            proc.start()
        for proc in procs:
            proc.join()
        ratios.append(serial / (time.perf_counter() - t0))
    return statistics.median(ratios)


def runner_speedups(label: str, args: list[str], repeats: int) -> dict:
    """Wall time of one sweep (firing, locating, charting, writing) serially, with 2 local
    processes and on a 2-worker Dask LocalCluster, each started and warmed before the timing
    (workers that have imported the engines, as in a long-lived pool or cluster). The three
    take turns, repeat after repeat, so that a drift of the machine's speed hits all alike."""
    plan = sweep_cmd.sweep_from_args(sweep_cmd.build_parser().parse_args(args))
    kinds = {
        "serial": {},
        "workers2": {"workers": 2},
        "dask_local2": {"workers": 2, "scheduler": "local"},
    }
    times: dict[str, list[float]] = {k: [] for k in kinds}
    warm = [j for n in plan.engines for j in plan.firing.jobs(n, adapters.settings_for(n))[:3]]
    with tempfile.TemporaryDirectory() as tmp, contextlib.ExitStack() as stack:
        runners = {
            k: stack.enter_context(Runner(min_parallel_s=0.0, **kw)) for k, kw in kinds.items()
        }
        for runner in runners.values():
            runner.fire(warm)  # start the workers, import the engines
            runner.min_parallel_s = MIN_PARALLEL_S
        for _ in range(repeats):
            for key, runner in runners.items():
                t0 = time.perf_counter()
                table, meta = sweep_cmd.run(plan, runner, chart=True)
                runs.publish(Path(tmp) / key, sweep_cmd.files(table, meta, plan))
                times[key].append(time.perf_counter() - t0)
    out = {
        "label": label,
        "args": " ".join(args),
        "repeats": repeats,
        **{f"{k}_s": statistics.median(v) for k, v in times.items()},
        **{f"{k}_range_s": [min(v), max(v)] for k, v in times.items()},
    }
    out["speedup_workers2"] = out["serial_s"] / out["workers2_s"]
    out["dask_over_processes"] = out["dask_local2_s"] / out["workers2_s"]
    return out


def chart(table: pd.DataFrame):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(8, 4.8), layout="constrained")
    x = range(len(table))
    ax.bar(
        [i - 0.27 for i in x],
        table.harness_per_collision_us,
        0.27,
        label="harness: fire through the runner and tabulate, per impact",
    )
    ax.bar(list(x), table.simulate_per_collision_us, 0.27, label="simulate() alone")
    ax.bar([i + 0.27 for i in x], table.bare_steps_us, 0.27, label="bare engine, the same steps")
    for i, r in table.iterrows():
        ax.annotate(
            f"{r.simulate_overhead_us:+.0f} us",
            (i, r.simulate_per_collision_us),
            ha="center",
            va="bottom",
            fontsize=8,
        )
    ax.set_xticks(list(x), table.engine)
    ax.set_ylabel("median time per collision (us, log scale)")
    ax.set_yscale("log")  # the engines span four orders of magnitude
    ax.set_ylim(top=8 * table.harness_per_collision_us.max())  # room for the labels
    ax.set_title(
        "Cost of one collision, each engine's reference profile, R161, paper's swing;\n"
        "label: simulate() minus the bare steps",
        fontsize=10,
    )
    fig.legend(loc="outside lower center", fontsize=8, ncol=3)
    ax.grid(axis="y", alpha=0.3, which="both")
    return fig


def _sizes(text: str) -> tuple[int, ...]:
    parse = cli.integer(1, 1_000_000)
    return tuple(parse(part) for part in text.split(","))


def _options(p: argparse.ArgumentParser) -> None:
    p.add_argument(
        "--repeats",
        type=cli.integer(1, 100),
        default=5,
        help="timed repeats per engine, the median reported (1..100, default 5)",
    )
    p.add_argument(
        "--points",
        type=cli.integer(2, 10_000),
        default=41,
        help="impact points per timed sweep (2..10000, default 41)",
    )
    p.add_argument(
        "--batches",
        type=_sizes,
        default=throughput.SIZES,
        metavar="N[,N...]",
        help="batch sizes of the throughput part (default 1,10,...,100000)",
    )
    p.add_argument(
        "--batch-budget",
        type=cli.number(0.0, lo_open=True),
        default=30.0,
        metavar="S",
        help="grow the batch while a firing would last at most this (s)",
    )
    p.add_argument(
        "--batches-only",
        action="store_true",
        help="only the throughput part (e.g. the batched engines on a GPU)",
    )
    p.add_argument(
        "--keep-rows",
        type=Path,
        default=None,
        metavar="CSV",
        help="throughput rows this run does not measure again (another engine's, another "
        "kind of device's, another batch size's) are kept from this table (default: the "
        "committed one, results/bench_batches.csv)",
    )


def _check(p: argparse.ArgumentParser, args: argparse.Namespace) -> None:
    """--keep-rows must be a throughput table, read before any work. Not named, it is the
    committed table, which a checkout holds: if that was deleted, no rows are kept, and
    stderr says so."""
    if args.keep_rows is None:
        if not KEEP_ROWS.exists():
            print(
                f"bench_engines: {KEEP_ROWS.relative_to(ROOT)} is absent: no rows of other "
                "engines, devices or batch sizes are kept",
                file=sys.stderr,
            )
            return
        args.keep_rows = KEEP_ROWS
    try:
        inputs.table(args.keep_rows, inputs.THROUGHPUT)
    except BadInput as err:
        p.error(f"--keep-rows: {err}")


def batches_files(args: argparse.Namespace) -> tuple[dict[str, bytes], list[str]]:
    """The throughput part: bench_batches.csv and .png (with the rows kept from --keep-rows)
    and its summary lines."""
    import matplotlib.pyplot as plt

    repeats = 1 if args.quick else 3
    measured = pd.DataFrame(
        [
            row
            for n in args.engine
            for row in throughput.measure(n, args.batches, args.batch_budget, repeats)
        ]
    )
    kept = pd.read_csv(args.keep_rows) if args.keep_rows else None  # checked by _check
    batches = throughput.merged(measured, kept)
    fig = throughput.chart(batches)
    files = {
        "bench_batches.csv": batches.to_csv(
            index=False, float_format="%.4g", lineterminator="\n"
        ).encode(),
        "bench_batches.png": figure_png(fig),
    }
    plt.close(fig)
    return files, [
        throughput.summary(measured).to_string(index=False, float_format=lambda v: f"{v:.3g}")
    ]


def produce(args: argparse.Namespace) -> tuple[dict[str, bytes], str]:
    """Every measurement: the files and what to print."""
    if args.batches_only:
        files, lines = batches_files(args)
        return files, "\n".join(lines)
    repeats = 1 if args.quick else args.repeats
    firing = firings.Firing(
        bat=presets.R161,
        s_m=firings.grid(presets.R161, args.points),
        v0_mps=presets.PAPER_PITCH_MPS,
        u0_mps=presets.PAPER_SWING.u0_mps,
        omega0_radps=presets.PAPER_SWING.omega0_radps,
        e=presets.E_WOOD,
    )
    table = pd.DataFrame([per_collision(n, firing, repeats) for n in args.engine])
    lines = [table.to_string(index=False, float_format=lambda v: f"{v:.2f}")]
    engines = ",".join(args.engine)
    par, ceiling = [], None
    # a batched engine's jobs stay in the runner's own process: the runners compare the others
    single = ",".join(n for n in args.engine if not adapters.record(n).batched)
    if not args.quick and single:
        ceiling = machine_ceiling()
        lines.append(f"this machine: 2 processes run pure CPU work {ceiling:.2f}x as fast as 1")
        par = [
            runner_speedups(f"{single}, 41 points, reference", ["--engine", single], 21),
            runner_speedups(
                "first engine, hinged swing, 96 points",
                ["--engine", single.split(",")[0], "--swing", "--points", "96"],
                3,
            ),
        ]
        lines += [
            f"{r['label']}: serial {r['serial_s']:.2f} s, 2 processes "
            f"{r['workers2_s']:.2f} s ({r['speedup_workers2']:.2f}x), Dask LocalCluster "
            f"of 2 {r['dask_local2_s']:.2f} s ({r['dask_over_processes']:.2f} x processes)"
            for r in par
        ]
    sweep_s = timed_command(["--engine", engines, "--points", "41"], 1 if args.quick else 3)
    lines.append(f"sweep --engine {engines}, 41 points, start-up included: median {sweep_s:.2f} s")
    files, more = batches_files(args)
    lines += more
    import matplotlib.pyplot as plt

    fig = chart(table)
    files |= {
        "bench_engines.csv": table.to_csv(
            index=False, float_format="%.4g", lineterminator="\n"
        ).encode(),
        "bench_engines.json": json_bytes(
            {
                "per_collision": table.to_dict(orient="records"),
                "sweep_41_s": sweep_s,
                "runners": par,
                "two_process_ceiling": ceiling,
                "repeats": repeats,
                "provenance": provenance(),
            }
        ),
        "bench_engines.png": figure_png(fig),
    }
    plt.close(fig)
    return files, "\n".join(lines)


COMMAND = Command(
    name="bench_engines",
    doc=__doc__,
    produce=produce,
    options=_options,
    check=_check,
    quick="one repeat, no runner comparison",
    runner=False,
)
main = COMMAND.main


if __name__ == "__main__":
    sys.exit(main())
