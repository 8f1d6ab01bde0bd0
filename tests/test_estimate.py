"""A run's cost, said before it starts (``experiments.core.estimate``), is honest: each engine
record's ``step_cost_s`` is the bare step ``experiments.bench_engines`` measured (committed
in results/bench_engines.csv), and the estimate of every committed baseline sweep is within
the factor of a few the module promises of the wall time the sweep measured."""

from __future__ import annotations

import pandas as pd
import pytest

import adapters
from experiments import baselines
from experiments import sweep as sweep_cmd
from experiments.core import estimate
from experiments.core.io import ROOT

BENCH = pd.read_csv(ROOT / "results" / "bench_engines.csv").set_index("engine")
#: Records round the measured step to one significant figure: at most 1.5x off, 2x allowed.
STEP_COST_FACTOR = 2.0
#: The estimate's promise ("good to a factor of a few"), checked where the sweep took long
#: enough (MIN_MEASURED_S) for per-impact fixed costs not to dominate.
ESTIMATE_FACTOR = 8.0
MIN_MEASURED_S = 0.5


@pytest.mark.parametrize("name", sorted(set(BENCH.index) & set(adapters.names())))
def test_each_records_step_cost_is_the_benchmarked_one(name):
    measured_s = BENCH.loc[name, "one_world_step_us"] * 1e-6
    ratio = adapters.record(name).step_cost_s / measured_s
    assert 1 / STEP_COST_FACTOR <= ratio <= STEP_COST_FACTOR, (name, ratio)


@pytest.mark.parametrize("label", list(baselines.BASELINES))
def test_the_estimate_of_each_baseline_is_within_a_few_times_its_wall_time(label):
    args = sweep_cmd.build_parser().parse_args(["--engine", "all", *baselines.BASELINES[label]])
    sweep = sweep_cmd.sweep_from_args(args)
    table = pd.read_csv(ROOT / "results" / f"{sweep.name}.csv")
    jobs = [j for name in sweep.engines for j in sweep.firing.jobs(name, sweep.settings[name])]
    estimated = estimate.run_s(jobs)
    checked = 0
    for name, rows in table.groupby("engine"):
        # A batched engine's wall time in a sweep is mostly its compile (JAX: seconds per
        # batch size) and its batching, which steps cannot price: held to nothing here
        # (reported in the README as not yet validated).
        if adapters.record(name).batched:
            continue
        measured = rows.wall_s.sum()
        if measured >= MIN_MEASURED_S:
            ratio = estimated[name] / measured
            assert 1 / ESTIMATE_FACTOR <= ratio <= ESTIMATE_FACTOR, (name, ratio)
            checked += 1
    single = table[[not adapters.record(n).batched for n in table.engine]]
    assert checked or single.wall_s.groupby(single.engine).sum().max() < MIN_MEASURED_S


def test_the_benchmark_runs_a_single_world_engine(tmp_path):
    """The benchmark that measures ``step_cost_s`` steps single-world engines too (the plug-in
    test runs it on a batched one)."""
    from experiments import bench_engines

    name = next(n for n in adapters.names() if not adapters.is_batched(n))
    assert bench_engines.main(["--quick", "--engine", name, "--points", "5", "--batches",
                               "1,10", "--batch-budget", "1", "--out", str(tmp_path)]) == 0
    table = pd.read_csv(next(tmp_path.rglob("bench_engines.csv"))).set_index("engine")
    assert table.loc[name, "bare_per_step_us"] > 0.0
