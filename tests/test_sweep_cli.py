"""The sweep command: bad input exits 2 and leaves results untouched; output is atomic and
reproducible."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pandas as pd
import pytest

import adapters
from analytic import presets
from experiments import compare, sweep, sweep_chart
from experiments.core import Runner, tables
from experiments.core.io import ROOT


def _run(*args: str, cwd: Path = ROOT) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "experiments.sweep", *args], cwd=cwd,
                          capture_output=True, text=True, timeout=300, check=False)


def test_help_lists_engines_and_bats():
    res = _run("--help")
    assert res.returncode == 0
    for name in (*adapters.names(), *presets.BATS):
        assert name in res.stdout


def test_outputs_are_written_and_reproducible(tmp_path):
    args = ["--engine", "all", "--points", "5", "--out", str(tmp_path)]
    assert sweep.main([*args, "--name", "a"]) == 0
    assert sweep.main([*args, "--name", "b"]) == 0
    a = pd.read_csv(tmp_path / "a" / "sweep.csv").drop(columns=list(tables.TIMING_COLUMNS))
    b = pd.read_csv(tmp_path / "b" / "sweep.csv").drop(columns=list(tables.TIMING_COLUMNS))
    pd.testing.assert_frame_equal(a, b, check_exact=True)
    assert list(a.columns) == [c for c in tables.COLUMNS if c not in tables.TIMING_COLUMNS]
    assert {p.name for p in (tmp_path / "a").iterdir()} == {"sweep.csv", "sweep.json",
                                                             "sweep.png"}
    assert compare.compare_tables(tmp_path / "a" / "sweep.csv", tmp_path / "b" / "sweep.csv") == 0


def test_interrupted_run_leaves_previous_results(tmp_path, monkeypatch):
    args = ["--points", "3", "--out", str(tmp_path), "--name", "t"]
    assert sweep.main(args) == 0
    before = {p.name: p.read_bytes() for p in (tmp_path / "t").iterdir()}

    def interrupted(*a, **k):
        raise KeyboardInterrupt

    monkeypatch.setattr(sweep_chart, "plot", interrupted)  # dies after the CSV was prepared
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
    with Runner(min_parallel_s=0.0, **runner_kw) as runner:
        runs = [sweep.run(plan, runner, locate=False)[0] for plan in plans]
    cols = [c for c in runs[0].columns if c not in tables.TIMING_COLUMNS]
    return pd.concat([t[[c for c in t.columns if c in cols or c.startswith("release")]]
                      for t in runs], ignore_index=True)


def test_runners_give_identical_rows(sweep_plan):
    # Serial, two local processes and a Dask LocalCluster of two: the same rows, bit for bit,
    # in the same order, for every engine (adapters hold no state between impacts).
    serial = _rows(sweep_plan)
    assert set(serial.engine) == set(adapters.names())
    for kw in ({"workers": 2}, {"workers": 2, "scheduler": "local"}):
        pd.testing.assert_frame_equal(serial, _rows(sweep_plan, **kw), check_exact=True)


def test_compliant_reference_beside_the_rigid_one(tmp_path):
    # --reference compliant adds the law's prediction per row. Checked here: the law's e at each
    # closing speed solves Hunt-Crossley's a - ln(1 + a) = -e a - ln(1 - e a), a = d v_c; the
    # difference column is rigid minus compliant; and the contact lasts what a Hertz contact of
    # this baseball does, 0.5-1 ms (it was calibrated to 0.7 ms at 40 m/s on a wall).
    import math

    from analytic.compliant import LAWS

    assert sweep.main(["--engine", "all", "--points", "3", "--reference", "compliant",
                       "--no-locate", "--out", str(tmp_path), "--name", "c"]) == 0
    t = pd.read_csv(tmp_path / "c" / "sweep.csv")
    d = LAWS["hertz"].dissipation_spm
    for _, row in t.iterrows():
        v_c = row.v0_mps + row.u0_mps + row.omega0_radps * row.s_m
        a, e = d * v_c, row.compliant_e
        assert a - math.log1p(a) == pytest.approx(-e * a - math.log1p(-e * a), rel=1e-9)
    # the CSV keeps 12 significant digits of each column
    assert list(t.v1_rigid_minus_compliant_mps) == pytest.approx(
        list(t.v1_analytic_mps - t.v1_compliant_mps), abs=1e-10)
    assert t.compliant_contact_s.between(0.5e-3, 1e-3).all()
    assert _run("--law", "hertz").returncode == 2  # a law without the compliant reference
