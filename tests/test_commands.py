"""Every command, as a user types it: ``python -m experiments.<name>`` in a fresh interpreter,
at small size, exits 0 with no traceback; where a command takes a runner it runs with
``--workers 2``. The sweep's rows are the serial run's whatever runs them (two local processes,
a Dask LocalCluster, a Dask scheduler started as the README says), for every single-world
engine and for a batched one. The README's own command lines are in ``test_readme_commands``.
"""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import pandas as pd
import pytest

import adapters
from experiments import twins
from experiments.core import tables

from .conftest import COMMANDS, ROOT, cheapest, run_command, runs_in

SINGLE = cheapest(batched=False)
BATCHED = cheapest(batched=True)
SOFT = min(
    (n for n in adapters.available() if adapters.record(n).can.soft_contact is not None),
    key=lambda n: adapters.record(n).cost.step_cost_s,
)
TWIN = min(twins.twinned(adapters.available()), key=lambda n: adapters.record(n).cost.step_cost_s)
BASELINE_CSV = str(ROOT / "results" / "sweep_all_reference_r161_swing.csv")
WORKERS = ["--workers", "2"]

#: Each command at small size (its --out is added where it writes a run).
SMALL = {
    "sweep": ["--engine", SINGLE, "--points", "5", *WORKERS],
    "compare": [BASELINE_CSV, BASELINE_CSV],
    "pareto": ["--quick", "--engine", SINGLE, *WORKERS],
    "stability": ["--quick", "--engine", SINGLE, *WORKERS],
    "swing": ["--quick", "--engine", SINGLE, *WORKERS],
    "defaults": ["--phases", "2", "--engine", SINGLE, *WORKERS],
    "calibrate_soft": ["--quick", "--engine", SOFT, *WORKERS],
    "friction": ["--quick", "--engine", SINGLE, *WORKERS],
    "flex": ["--quick", "--engine", SINGLE],
    "bench_engines": [
        "--quick",
        "--engine",
        SINGLE,
        "--points",
        "5",
        "--batches",
        "1,10",
        "--batch-budget",
        "1",
    ],
    "bench_analytic": ["--points", "1000", "--repeats", "1"],
    "check_engine": ["--engine", SINGLE],
    "report": [],
    "twins": ["--points", "2", "--engine", TWIN, *WORKERS],
    "gradients": ["--quick", "--engine", SINGLE],
    "realball": ["--quick", "--engine", SINGLE],
    "gpu": [],
}
WRITES_NOTHING = {"compare", "check_engine"}


def test_every_command_is_covered():
    """Each module that runs as ``python -m`` is run here, by findings_run, by baselines, or
    (history, which installs engine releases) by tests/test_history.py."""
    assert set(COMMANDS) == set(SMALL) | {"findings", "baselines", "history"}


@pytest.mark.parametrize("command", sorted(SMALL))
def test_command_runs_at_small_size(command, tmp_path):
    out = [] if command in WRITES_NOTHING else ["--out", str(tmp_path)]
    res = run_command(["-m", f"experiments.{command}", *SMALL[command], *out])
    if out:  # one run directory, published whole
        (run,) = [tmp_path / name for name in runs_in(tmp_path)]
        assert any(run.iterdir()), res.stdout
        # whichever process ran the engine, its version is in the run's provenance
        for meta in run.glob("*.json"):
            versions = json.loads(meta.read_text()).get("provenance", {}).get("versions")
            if versions is not None and "--engine" in SMALL[command]:
                engine = SMALL[command][SMALL[command].index("--engine") + 1]
                assert adapters.record(engine).install.package in versions, (meta.name, versions)
    if command == "compare":
        assert "no change apart from timing" in res.stdout


@pytest.mark.xdist_group("findings")
def test_findings_runs_with_workers(findings_run):
    # conftest.findings_run: python -m experiments.findings --workers 2 ... exited 0
    assert (findings_run / "findings.md").stat().st_size > 0


def test_baselines_writes_results_and_the_readme_table(tmp_path):
    # In a copy of the project (baselines writes into its results/ and README): the report
    # part, which reads every committed result, writes the report the committed one is.
    copy = tmp_path / "project"
    for name in ("analytic", "adapters", "experiments", "results"):
        shutil.copytree(ROOT / name, copy / name, ignore=shutil.ignore_patterns("__pycache__"))
    shutil.copy(ROOT / "README.md", copy / "README.md")
    run_command(["-m", "experiments.baselines", "--only", "report"], cwd=copy)
    for name in ("results/report.md", "README.md"):
        assert (copy / name).read_text() == (ROOT / name).read_text(), name


def _sweep_rows(tmp_path: Path, name: str, engines: str, *runner: str) -> pd.DataFrame:
    run_command(
        [
            "-m",
            "experiments.sweep",
            "--engine",
            engines,
            "--points",
            "5",
            *runner,
            "--out",
            str(tmp_path),
            "--name",
            name,
        ]
    )
    return pd.read_csv(tmp_path / name / "sweep.csv").drop(columns=list(tables.TIMING_COLUMNS))


@pytest.mark.parametrize("kind", ["single-world", "batched"])
def test_sweep_rows_are_the_serial_ones_whatever_runs_them(kind, tmp_path):
    # Every single-world engine (the ones the runner spreads over workers), or the cheapest
    # batched one (whose jobs stay in the runner's process): the rows, bit for bit, and
    # `compare` says so.
    engines = ",".join(
        n
        for n in adapters.available()
        if (adapters.record(n).batched == (kind == "batched"))
        and (kind == "single-world" or n == BATCHED)
    )
    serial = _sweep_rows(tmp_path, "serial", engines)
    assert set(serial.engine) == set(engines.split(","))
    for name, runner in (("workers", WORKERS), ("local", [*WORKERS, "--scheduler", "local"])):
        pd.testing.assert_frame_equal(
            serial, _sweep_rows(tmp_path, name, engines, *runner), check_exact=True
        )
        res = run_command(
            [
                "-m",
                "experiments.compare",
                str(tmp_path / "serial" / "sweep.csv"),
                str(tmp_path / name / "sweep.csv"),
            ]
        )
        assert "no change apart from timing" in res.stdout


@pytest.mark.parametrize("command", sorted({*SMALL, "findings", "baselines"}))
def test_help_in_a_fresh_interpreter(command, tmp_path):
    # what a newcomer types first: the manual, exit 0, from anywhere (here a scratch directory)
    res = run_command(
        ["-m", f"experiments.{command}", "--help"], cwd=tmp_path, env={"PYTHONPATH": str(ROOT)}
    )
    assert res.stdout.startswith("usage: python -m experiments.") and not any(tmp_path.iterdir())


def test_benchmarking_one_engine_keeps_every_row_it_did_not_measure_again(tmp_path):
    # bench_engines --batches-only for one engine at two batch sizes, as a user runs it, keeping
    # the committed table's rows: its CPU rows at those sizes are this run's (--quick: one
    # repeat), and every other row (other engines', other devices', other sizes') is kept as
    # committed, byte for byte (the table is written at the precision it was read at)
    committed = ROOT / "results" / "bench_batches.csv"
    argv = ["--quick", "--batches-only", "--engine", SINGLE, "--batches", "1,10"]
    run_command(["-m", "experiments.bench_engines", *argv, "--out", str(tmp_path)])
    (run,) = [tmp_path / name for name in runs_in(tmp_path)]
    written = (run / "bench_batches.csv").read_text().splitlines()
    old = committed.read_text().splitlines()
    table = pd.read_csv(run / "bench_batches.csv")
    again = (table.engine == SINGLE) & table.batch.isin([1, 10]) & (table.device == "cpu")
    assert sorted(table[again].batch) == [1, 10] and set(table[again].repeats) == {1}
    head = old[0].split(",")
    measured = {
        line
        for line in old[1:]
        if (r := dict(zip(head, line.split(","))))["engine"] == SINGLE
        and r["batch"] in ("1", "10")
        and r["device"] == "cpu"
    }
    kept = [line for line in old[1:] if line not in measured]
    assert written[0] == old[0] and set(kept) <= set(written[1:])
    assert len(written) == len(old) - len(measured) + 2
