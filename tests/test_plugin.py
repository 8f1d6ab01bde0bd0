"""A plug-in engine from outside the repository, written from ``adapters.interface`` alone
(``tests/plugin/toy_engine.py``: planar impulses in numpy, the batched form), installed as a
distribution with an entry point: every experiment runs it with no edit to the harness,
``check_engine`` passes it, and fails its twin whose batted ball is 1% too fast."""

from __future__ import annotations

import json
import sys

import pandas as pd
import pytest

import adapters
from experiments import bench_engines, defaults, pareto, stability, sweep, swing
from experiments import check_engine as check_engine_cmd
from experiments.core import Status, check, check_engine


@pytest.fixture(scope="module")
def toyengine(toy_site):
    """The plug-in installed (``toy_site``, on sys.path and PYTHONPATH) for this module's
    tests; subprocesses find it through PYTHONPATH."""
    mp = pytest.MonkeyPatch()
    mp.syspath_prepend(str(toy_site))
    mp.setenv("PYTHONPATH", str(toy_site))
    adapters.reload_plugins()
    yield "toyengine"
    mp.undo()
    sys.modules.pop("toy_engine", None)
    adapters.reload_plugins()


def test_the_entry_point_registers_it_under_its_name(toyengine):
    assert toyengine in adapters.names() and toyengine in adapters.available()
    rec = adapters.record(toyengine)
    assert rec.name == toyengine and rec.look.color not in {
        adapters.record(n).look.color for n in adapters.names() if n != toyengine
    }
    assert adapters.is_batched(toyengine)


def test_check_engine_passes_it_and_fails_its_one_percent_twin(toyengine):
    report = check_engine(toyengine)
    assert report.passed, str(report)
    assert {r.name for r in report.results} == set(check.applicable(toyengine))
    import toy_engine

    adapters.register(toy_engine.FAULTY)
    try:
        faulty = check_engine(toy_engine.FAULTY.name)
    finally:
        adapters.unregister(toy_engine.FAULTY.name)
    # v1 1% off is 0.4 m/s at 40 m/s: every check that measures v1 sees it
    failed = {r.name for r in faulty.failures}
    assert {"restitution", "still_bat", "swinging_bat", "oblique"} <= failed, str(faulty)
    assert "FAILED" in str(faulty)


def test_the_check_engine_command_exits_0_for_it(toyengine, capsys):
    """What a plug-in author runs: one line per check, exit 0 when all pass, 1 when one fails."""
    assert check_engine_cmd.main(["--engine", toyengine, "--check", "restitution"]) == 0
    assert "ok     restitution" in capsys.readouterr().out
    import toy_engine

    adapters.register(toy_engine.FAULTY)
    try:
        code = check_engine_cmd.main(["--engine", toy_engine.FAULTY.name, "--check", "restitution"])
    finally:
        adapters.unregister(toy_engine.FAULTY.name)
    assert code == 1 and "FAILED restitution" in capsys.readouterr().out


def test_an_engine_that_raises_gives_error_rows_not_a_crash(toyengine, tmp_path):
    """An exception inside the engine's step ends that impact as ``error`` naming it; the
    sweep writes its table."""
    import toy_engine

    adapters.register(toy_engine.BROKEN)
    try:
        assert (
            sweep.main(
                [
                    "--engine",
                    toy_engine.BROKEN.name,
                    "--points",
                    "3",
                    "--no-locate",
                    "--out",
                    str(tmp_path),
                ]
            )
            == 0
        )
    finally:
        adapters.unregister(toy_engine.BROKEN.name)
    rows = pd.read_csv(next(tmp_path.rglob("sweep.csv")))
    assert set(rows.status) == {Status.ERROR}
    assert rows.episode_end.str.contains("solver diverged").all()


@pytest.mark.xdist_group("findings")
def test_every_experiment_runs_it(toyengine, tmp_path, findings_run):
    out = ["--out", str(tmp_path)]
    assert sweep.main(["--engine", toyengine, "--points", "5", *out, "--name", "s"]) == 0
    rows = pd.read_csv(tmp_path / "s" / "sweep.csv")
    assert (rows.engine == toyengine).all() and (rows.status == Status.OK).all()
    meta = json.loads((tmp_path / "s" / "sweep.json").read_text())
    assert set(meta["engines"]) == {toyengine}
    assert (
        sweep.main(
            [
                "--engine",
                toyengine,
                "--points",
                "3",
                "--swing",
                "--dt",
                "1e-4",
                "--no-locate",
                *out,
                "--name",
                "h",
            ]
        )
        == 0
    )
    assert (pd.read_csv(tmp_path / "h" / "sweep.csv").status == Status.OK).all()
    for study in (pareto, stability, swing, bench_engines):
        assert study.main(["--quick", "--engine", toyengine, *out]) == 0, study.__name__
    assert defaults.main(["--phases", "2", "--engine", toyengine, *out]) == 0
    # the findings (run once per test run, conftest.findings_run) judge it beside a built-in
    assert f"| {toyengine} |" in (findings_run / "findings.md").read_text()
