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
from experiments import compare, sweep
from experiments.core import Runner, runs, tables
from experiments.core.io import ROOT
from experiments.parts import sweep_chart

from .conftest import cheapest


def _run(*args: str, cwd: Path = ROOT) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "experiments.sweep", *args], cwd=cwd,
                          capture_output=True, text=True, timeout=300, check=False)


def test_help_lists_engines_and_bats():
    res = _run("--help")
    assert res.returncode == 0
    for name in (*adapters.names(), *presets.BATS):
        assert name in res.stdout


@pytest.mark.full
def test_outputs_are_written_and_reproducible(tmp_path):
    args = ["--engine", "all", "--points", "5", "--out", str(tmp_path)]
    assert sweep.main([*args, "--name", "a"]) == 0
    assert sweep.main([*args, "--name", "b"]) == 0
    a = pd.read_csv(tmp_path / "a" / "sweep.csv").drop(columns=list(tables.TIMING_COLUMNS))
    b = pd.read_csv(tmp_path / "b" / "sweep.csv").drop(columns=list(tables.TIMING_COLUMNS))
    pd.testing.assert_frame_equal(a, b, check_exact=True)
    assert list(a.columns) == [c for c in tables.COLUMNS if c not in tables.TIMING_COLUMNS]
    assert {p.name for p in (tmp_path / "a").iterdir()} == {"sweep.csv", "sweep.json",
                                                             "sweep.png", runs.MANIFEST}
    assert compare.compare_tables(tmp_path / "a" / "sweep.csv", tmp_path / "b" / "sweep.csv") == 0


def test_interrupted_run_leaves_previous_results(tmp_path, monkeypatch):
    args = ["--engine", cheapest(batched=False), "--points", "3", "--out", str(tmp_path),
            "--name", "t"]
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
    # Every single-world engine (the ones the runner spreads over workers) and the cheapest
    # batched one (whose jobs stay in the runner's process, beside the others') over the
    # paper's swing, a still bat and a hinged swing at a coarse step (so the swing is cheap):
    # rows from every path through the runner.
    engines = ",".join(n for n in adapters.names() if not adapters.record(n).batched
                       or n == cheapest(batched=True))
    plans = [sweep.sweep_from_args(sweep.build_parser().parse_args(
        ["--engine", engines, "--points", "6", *extra]))
        for extra in ([], ["--u0", "0", "--omega0", "0"], ["--swing", "--dt", "1e-4"])]
    return plans


def _rows(plans, **runner_kw) -> pd.DataFrame:
    # min_parallel_s = 0: every chunk goes to the workers, however cheap
    with Runner(min_parallel_s=0.0, **runner_kw) as runner:
        runs = [sweep.run(plan, runner, locate=False)[0] for plan in plans]
    cols = [c for c in runs[0].columns if c not in tables.TIMING_COLUMNS]
    return pd.concat([t[[c for c in t.columns if c in cols or c.startswith("release")]]
                      for t in runs], ignore_index=True)


@pytest.mark.full
def test_runners_give_identical_rows(sweep_plan):
    # Serial, two local processes and a Dask LocalCluster of two: the same rows, bit for bit,
    # in the same order (adapters hold no state between impacts).
    serial = _rows(sweep_plan)
    assert set(serial.engine) == set(sweep_plan[0].engines)
    for kw in ({"workers": 2}, {"workers": 2, "scheduler": "local"}):
        pd.testing.assert_frame_equal(serial, _rows(sweep_plan, **kw), check_exact=True)


@pytest.mark.full
def test_compliant_reference_beside_the_rigid_one(tmp_path):
    # --reference compliant adds the law's prediction per row; the default law is the realistic
    # ball. Checked here: the law's e at each closing speed v_c = v0 + u0 + omega0 s is the
    # assumed power law e = cor_ref (v_c / v_ref)^-exponent; the difference column is rigid
    # minus compliant; and the contact lasts what a Hertz contact of this baseball does.
    from analytic import ImpactCase, compliant, presets
    from analytic.ball import REALISTIC_BALL, WALL

    assert sweep.main(["--engine", "all", "--points", "3", "--reference", "compliant",
                       "--no-locate", "--out", str(tmp_path), "--name", "c"]) == 0
    t = pd.read_csv(tmp_path / "c" / "sweep.csv")
    law = REALISTIC_BALL.cor_law
    v_c = t.v0_mps + t.u0_mps + t.omega0_radps * t.s_m
    # the CSV keeps 12 significant digits of each column
    assert list(t.compliant_e) == pytest.approx(
        list(law.cor_ref * (v_c / law.speed_ref_mps) ** -law.exponent), rel=1e-10)
    assert list(t.v1_rigid_minus_compliant_mps) == pytest.approx(
        list(t.v1_analytic_mps - t.v1_compliant_mps), abs=1e-10)
    # Hertz: x'' = -(k/m_eff) x^1.5 (1 + d x') lasts t = (m_eff^2 / (k^2 v_c))^(1/5) tau(d v_c),
    # so at one v_c (one e, one d v_c) t scales as m_eff^(2/5) from the ball on a wall
    # (m_eff = m); m_eff = 1/(1/m + 1/M + s^2/J). Within 1%: the bat turns up to 37 mrad
    # meanwhile, which moves the arm s (measured 0.14%). So the contact lasts 0.55-0.6 ms on
    # the bat's middle and barrel (0.7 ms on a wall at 40 m/s, 0.6-1 ms measured
    # [nathan2000]), and a little under 0.5 ms near the knob, where m_eff = 0.066 kg is under
    # half the ball's mass.
    bat, ball = presets.R161, presets.BASEBALL
    for _, row in t.drop_duplicates("s_m").iterrows():
        v = row.v0_mps + row.u0_mps + row.omega0_radps * row.s_m
        m_eff = 1 / (1 / ball.mass_kg + 1 / bat.mass_kg + row.s_m**2 / bat.inertia_cm_kgm2)
        wall = ImpactCase(bat=WALL, ball=ball, s_m=0.0, v0_mps=v, e=0.5)
        t_wall = compliant.predict(wall, REALISTIC_BALL).contact_duration_s
        assert row.compliant_contact_s == pytest.approx(
            t_wall * (m_eff / ball.mass_kg) ** 0.4, rel=0.01)
    assert t.compliant_contact_s.between(0.45e-3, 1e-3).all()
    assert _run("--law", "hertz").returncode == 2  # a law without the compliant reference
    # the realistic ball is the default; the older Hertz law stays selectable by name
    def law_of(*extra):
        args = sweep.build_parser().parse_args(["--points", "3", "--reference", "compliant",
                                                *extra])
        return sweep.sweep_from_args(args).law

    assert (law_of(), law_of("--law", "hertz")) == ("ball", "hertz")
