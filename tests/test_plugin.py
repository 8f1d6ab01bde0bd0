"""A plug-in engine from outside the repository, written from ``adapters.interface`` alone
(``tests/plugin/toy_engine.py``: planar impulses in numpy, the batched form), installed as a
distribution with an entry point: every experiment runs it with no edit to the harness,
``check_engine`` passes it, and fails its twin whose batted ball is 1% too fast."""

from __future__ import annotations

import json
import shutil
import sys
from pathlib import Path

import pandas as pd
import pytest

import adapters
from experiments import bench_engines, defaults, findings, pareto, stability, sweep, swing
from experiments import check_engine as check_engine_cmd
from experiments.core import check, check_engine

PLUGIN = Path(__file__).parent / "plugin" / "toy_engine.py"


@pytest.fixture(scope="module")
def toyengine(tmp_path_factory):
    """The plug-in installed in a fresh site directory (a dist-info with the entry point) for
    this module's tests; subprocesses find it through PYTHONPATH."""
    site = tmp_path_factory.mktemp("site")
    shutil.copy(PLUGIN, site / "toy_engine.py")
    info = site / "batsim_toy_engine-0.1.dist-info"
    info.mkdir()
    (info / "METADATA").write_text("Metadata-Version: 2.1\nName: batsim-toy-engine\n"
                                   "Version: 0.1\n")
    (info / "entry_points.txt").write_text(
        f"[{adapters.ENTRY_POINT_GROUP}]\ntoyengine = toy_engine:RECORD\n")
    mp = pytest.MonkeyPatch()
    mp.syspath_prepend(str(site))
    mp.setenv("PYTHONPATH", str(site))
    adapters.reload_plugins()
    yield "toyengine"
    mp.undo()
    sys.modules.pop("toy_engine", None)
    adapters.reload_plugins()


def test_the_entry_point_registers_it_under_its_name(toyengine):
    assert toyengine in adapters.names() and toyengine in adapters.available()
    rec = adapters.record(toyengine)
    assert rec.name == toyengine and rec.color not in {adapters.record(n).color
                                                       for n in adapters.names()
                                                       if n != toyengine}
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
        code = check_engine_cmd.main(["--engine", toy_engine.FAULTY.name, "--check",
                                      "restitution"])
    finally:
        adapters.unregister(toy_engine.FAULTY.name)
    assert code == 1 and "FAILED restitution" in capsys.readouterr().out


def test_an_engine_that_raises_gives_error_rows_not_a_crash(toyengine, tmp_path):
    """An exception inside the engine's step ends that impact as ``error`` naming it; the
    sweep writes its table."""
    import toy_engine

    adapters.register(toy_engine.BROKEN)
    try:
        assert sweep.main(["--engine", toy_engine.BROKEN.name, "--points", "3", "--no-locate",
                           "--out", str(tmp_path)]) == 0
    finally:
        adapters.unregister(toy_engine.BROKEN.name)
    rows = pd.read_csv(next(tmp_path.rglob("sweep.csv")))
    assert set(rows.status) == {"error"}
    assert rows.episode_end.str.contains("solver diverged").all()


def test_every_experiment_runs_it(toyengine, tmp_path):
    out = ["--out", str(tmp_path)]
    assert sweep.main(["--engine", toyengine, "--points", "5", *out, "--name", "s"]) == 0
    rows = pd.read_csv(tmp_path / "s" / "sweep.csv")
    assert (rows.engine == toyengine).all() and (rows.status == "ok").all()
    meta = json.loads((tmp_path / "s" / "sweep.json").read_text())
    assert set(meta["engines"]) == {toyengine}
    assert sweep.main(["--engine", toyengine, "--points", "3", "--swing", "--dt", "1e-4",
                       "--no-locate", *out, "--name", "h"]) == 0
    assert (pd.read_csv(tmp_path / "h" / "sweep.csv").status == "ok").all()
    for study in (pareto, stability, swing, bench_engines):
        assert study.main(["--quick", "--engine", toyengine, *out]) == 0, study.__name__
    assert defaults.main(["--phases", "2", "--engine", toyengine, *out]) == 0
    assert findings.main(["--engine", toyengine, *out, "--name", "f"]) == 0
    assert f"| {toyengine} |" in (tmp_path / "f" / "findings.md").read_text()
