"""The GPU's rows beside the CPU's, and the grid's jobs as one run.

A GPU machine is lent for minutes: its runs are committed (results/gpu_runs/) and gathered by
``python -m experiments.gpu`` on any machine; a CPU benchmark keeps their rows. No test here
needs a GPU. ``Jobs`` (a grid's jobs held as its cases) must fire exactly as the same jobs one
by one: same batch, same bits.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pandas as pd
import pytest

from analytic import presets
from experiments import bench_engines, gpu
from experiments.core import Job, firings, inputs, tables
from experiments.core.fire import Jobs, fire_jobs, runs
from experiments.parts import throughput

from .conftest import ROOT, cheapest

BATCHED = cheapest(batched=True)
COMMITTED = ROOT / "results" / "bench_batches.csv"
GPU_RUNS = ROOT / "results" / "gpu_runs"


def _kind(table: pd.DataFrame, kind: str) -> pd.DataFrame:
    return table[[throughput.kind(d) == kind for d in table.device]].reset_index(drop=True)


def test_kind_reads_each_device_name():
    # the names the adapters give: "cpu", JAX's "cpu: cpu", "gpu: <card>", Warp's "cuda:0: <card>"
    assert [
        throughput.kind(d) for d in ("cpu", "cpu: cpu", "gpu: NVIDIA H200", "cuda:0: NVIDIA H200")
    ] == ["CPU", "CPU", "GPU", "GPU"]


def test_merged_replaces_only_the_rows_measured_again():
    # engine a's CPU row at batch 1 measured again: it replaces that row alone; a's GPU row,
    # a's CPU row at batch 10 and engine b's CPU row are kept; the table's order is by engine,
    # batch, CPU before GPU
    measured = pd.DataFrame({"engine": ["a"], "device": ["cpu"], "batch": [1], "run": ["new"]})
    kept = pd.DataFrame(
        {
            "engine": ["a", "b", "a", "a"],
            "device": ["cpu", "cpu", "cuda:0: X", "cpu"],
            "batch": [1, 1, 1, 10],
            "run": ["old"] * 4,
        }
    )
    out = throughput.merged(measured, kept)
    assert out.to_dict("list") == {
        "engine": ["a", "a", "a", "b"],
        "device": ["cpu", "cuda:0: X", "cpu", "cpu"],
        "batch": [1, 1, 10, 1],
        "run": ["new", "old", "old", "old"],
    }


@pytest.mark.xdist_group(BATCHED)
def test_a_cpu_benchmark_keeps_the_committed_gpu_rows(tmp_path):
    """bench_engines --batches-only on this CPU: its rows, and the committed GPU rows as they
    were (no GPU needed to keep them); the table is one that --keep-rows accepts."""
    name = BATCHED
    assert (
        bench_engines.main(
            [
                "--quick",
                "--batches-only",
                "--engine",
                name,
                "--batches",
                "1",
                "--out",
                str(tmp_path),
            ]
        )
        == 0
    )
    written = next(tmp_path.rglob("bench_batches.csv"))
    table = inputs.table(written, inputs.THROUGHPUT)  # what --keep-rows and gpu accept
    committed = pd.read_csv(COMMITTED)
    mine = (table.engine == name) & (table.batch == 1)
    assert list(_kind(table[mine], "CPU").repeats) == [1]  # this run's (--quick), not committed
    pd.testing.assert_frame_equal(
        _kind(table, "GPU")[list(committed.columns)], _kind(committed, "GPU"), check_dtype=False
    )


@pytest.fixture(scope="module")
def gathered(tmp_path_factory):
    out = tmp_path_factory.mktemp("gpu")
    assert gpu.main(["--out", str(out), "--name", "g"]) == 0
    return out / "g"


def test_gathered_rows_are_the_runs_and_the_committed_cpu(gathered):
    table = pd.read_csv(gathered / "bench_batches.csv")
    committed = pd.read_csv(COMMITTED)
    pd.testing.assert_frame_equal(
        _kind(table, "CPU")[list(committed.columns)], _kind(committed, "CPU"), check_dtype=False
    )
    runs = [pd.read_csv(p) for p in GPU_RUNS.glob("*/bench_batches.csv")]
    expected = {(r.engine, r.batch) for t in runs for r in _kind(t, "GPU").itertuples()}
    assert {(r.engine, r.batch) for r in _kind(table, "GPU").itertuples()} == expected


def test_profile_and_bars_follow_the_rows(gathered):
    """At each engine's best GPU batch: harness share = harness us / wall us, the bare rate
    1e6 / bare us; each bar met exactly when its measurement passes it."""
    meta = json.loads((gathered / "gpu.json").read_text())
    table = _kind(pd.read_csv(gathered / "bench_batches.csv"), "GPU")
    for p in meta["profile"]:
        rows = table[table.engine == p["engine"]]
        best = rows.loc[rows.impacts_per_s.idxmax()]
        assert p["batch"] == best.batch
        assert math.isclose(p["harness_share"], best.harness_us_per_impact / best.us_per_impact)
        assert math.isclose(p["bare_impacts_per_s"], 1e6 / best.bare_us_per_impact)
    bars = meta["bars"]
    assert (
        bars["slowest_impacts_per_s"]["measured"]
        == table.groupby("engine").impacts_per_s.max().min()
    )
    assert bars["slowest_impacts_per_s"]["met"] == (
        bars["slowest_impacts_per_s"]["measured"] >= 1e5
    )
    assert bars["fastest_impacts_per_s"]["measured"] == table.impacts_per_s.max()
    assert bars["harness_share"]["met"] == (bars["harness_share"]["measured"] <= 0.25)


def test_twins_by_device(gathered):
    """Each GPU twin step beside the CPU's same step: ratio = GPU difference / CPU's."""
    pairs = pd.read_csv(gathered / "twins_gpu.csv")
    cpu = pd.read_csv(ROOT / "results" / "twins.csv").set_index(["engine", "step"])
    assert len(pairs) > 0
    for r in pairs.itertuples():
        assert r.max_abs_diff_mps_cpu == pytest.approx(
            cpu.loc[(r.engine, r.step)].max_abs_diff_mps, rel=1e-5
        )  # (csv's 6 digits)
        assert r.ratio == pytest.approx(r.max_abs_diff_mps_gpu / r.max_abs_diff_mps_cpu, rel=1e-5)


def test_gpu_refuses_a_folder_without_runs(tmp_path, capsys):
    with pytest.raises(SystemExit) as err:
        gpu.main(["--runs", str(tmp_path), "--out", str(tmp_path)])
    assert err.value.code == 2
    assert "--runs" in capsys.readouterr().err


def _firing() -> firings.Firing:
    return firings.Firing(
        bat=presets.R161,
        s_m=firings.grid(presets.R161, 5),
        v0_mps=40.0,
        u0_mps=0.0,
        omega0_radps=0.0,
        e=presets.E_WOOD,
    )


@pytest.mark.xdist_group(BATCHED)
def test_jobs_fire_as_the_same_jobs_one_by_one():
    """A grid tiled over 3x its points as ``Jobs``: one run, and every outcome the bits of the
    same jobs listed one by one (one batch either way)."""
    import adapters

    name = BATCHED
    settings = adapters.settings_for(name)
    cases = _firing().cases() * 3
    jobs = Jobs(engine=name, settings=settings, cases=cases)
    assert len(runs(jobs)) == 1 and len(runs(list(jobs))) == 1
    assert isinstance(jobs[1:3], Jobs) and jobs[4] == Job(
        engine=name, settings=settings, case=cases[4]
    )
    a = tables.table(fire_jobs(jobs), "x")
    b = tables.table(fire_jobs(list(jobs)), "x")
    cols = ["v1_engine_mps", "u1_engine_mps", "omega1_engine_radps", "status", "steps"]
    pd.testing.assert_frame_equal(a[cols], b[cols])
    assert np.isfinite(a.v1_engine_mps).all()
