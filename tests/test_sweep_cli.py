"""The sweep command: bad input exits 2 and leaves results untouched; output is atomic and
reproducible."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pandas as pd
import pytest

from analytic import presets
from experiments import _grid, _runner, compare, sweep
from experiments._io import ROOT


def _run(*args: str, cwd: Path = ROOT) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "experiments.sweep", *args], cwd=cwd,
                          capture_output=True, text=True, timeout=300, check=False)


def test_help_lists_engines_and_bats():
    res = _run("--help")
    assert res.returncode == 0
    for name in (*_grid.adapters.names(), *presets.BATS):
        assert name in res.stdout


def test_outputs_are_written_and_reproducible(tmp_path):
    args = ["--engine", "all", "--points", "5", "--out", str(tmp_path)]
    assert sweep.main([*args, "--name", "a"]) == 0
    assert sweep.main([*args, "--name", "b"]) == 0
    a = pd.read_csv(tmp_path / "a" / "sweep.csv").drop(columns=list(_grid.TIMING_COLUMNS))
    b = pd.read_csv(tmp_path / "b" / "sweep.csv").drop(columns=list(_grid.TIMING_COLUMNS))
    pd.testing.assert_frame_equal(a, b, check_exact=True)
    assert list(a.columns) == [c for c in _grid.COLUMNS if c not in _grid.TIMING_COLUMNS]
    assert {p.name for p in (tmp_path / "a").iterdir()} == {"sweep.csv", "sweep.json",
                                                             "sweep.png"}
    assert compare.compare_tables(tmp_path / "a" / "sweep.csv", tmp_path / "b" / "sweep.csv") == 0


def test_interrupted_run_leaves_previous_results(tmp_path, monkeypatch):
    args = ["--points", "3", "--out", str(tmp_path), "--name", "t"]
    assert sweep.main(args) == 0
    before = {p.name: p.read_bytes() for p in (tmp_path / "t").iterdir()}

    def interrupted(*a, **k):
        raise KeyboardInterrupt

    monkeypatch.setattr(sweep, "plot", interrupted)  # dies after the CSV was prepared
    assert sweep.main([*args, "--force"]) == 130
    assert {p.name: p.read_bytes() for p in (tmp_path / "t").iterdir()} == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["t"]  # no temporary left behind


@pytest.fixture(scope="module")
def sweep_plan():
    # Every engine over the paper's swing, a still bat and a hinged swing at a coarse step (so
    # the swing is cheap): rows from every path through the engines.
    plans = [sweep.sweep_from_args(sweep.build_parser().parse_args(["--points", "6", *extra]))
             for extra in ([], ["--u0", "0", "--omega0", "0"], ["--swing", "--dt", "1e-4"])]
    return plans


def _rows(plans, **runner_kw) -> pd.DataFrame:
    # min_parallel_s = 0: every chunk goes to the workers, however cheap
    with _runner.Runner(min_parallel_s=0.0, **runner_kw) as runner:
        tables = [sweep.run(plan, runner, locate=False)[0] for plan in plans]
    cols = [c for c in tables[0].columns if c not in _grid.TIMING_COLUMNS]
    return pd.concat([t[[c for c in t.columns if c in cols or c.startswith("release")]]
                      for t in tables], ignore_index=True)


def test_runners_give_identical_rows(sweep_plan):
    # Serial, two local processes and a Dask LocalCluster of two: the same rows, bit for bit,
    # in the same order, for every engine (adapters hold no state between impacts).
    serial = _rows(sweep_plan)
    assert set(serial.engine) == set(_grid.adapters.names())
    for kw in ({"workers": 2}, {"workers": 2, "scheduler": "local"}):
        pd.testing.assert_frame_equal(serial, _rows(sweep_plan, **kw), check_exact=True)
