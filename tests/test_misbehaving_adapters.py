"""An adapter that breaks the interface fails its own rows, with a status that says what it did,
and never the run: one that raises, calls sys.exit, hangs (past its record's wall-clock limit:
``timeout``), says the bodies touch while its state has them apart (the passive check of its
contact flag), reads back the wrong shape, or holds another ball than the scene's. Beside it, in
the same run, another engine's rows are as they would be alone. The twins of the toy plug-in
(``tests/plugin/toy_engine.py``) are registered in this process, as an adapter under
development is."""

from __future__ import annotations

import sys
import time

import pandas as pd
import pytest

import adapters
from analytic import ImpactCase, presets
from experiments.core import Job, Physics, fire_jobs
from experiments.core.fire import TIMEOUTS_IN_A_ROW
from experiments.core.hosting import close_engines

from .conftest import PLUGIN, cheapest, plugin_site, run_command

sys.path.insert(0, str(PLUGIN.parent))
import toy_engine  # noqa: E402 - the plug-in's module, from its own folder

#: The engine fired after a twin, in the same firing: its rows must be as alone.
ENGINE = cheapest(batched=False)
#: twin -> (status, a word its rows' ``ended`` must hold)
EXPECTED = {
    "exits": (Physics.ERROR, "sys.exit(0)"),
    "hangs": (Physics.TIMEOUT, "timeout"),
    "stuckflag": (Physics.ERROR, "contact_flag"),
    "wrongshape": (Physics.ERROR, "shape"),
    "heavyball": (Physics.ERROR, "scene mismatch: toyengine_heavyball: ball_mass_kg"),
    "exitshard": (Physics.ERROR, "os._exit(3)"),
    "strings": (Physics.ERROR, "<U"),
    "integers": (Physics.ERROR, "int64"),
}
#: Twins whose failure only a command sees as theirs: a KeyboardInterrupt no Ctrl-C sent (a
#: library user's Ctrl-C stops the firing), a close that never returns (after the rows).
IN_A_COMMAND = {"interrupts": "error", "closehangs": "ok"}


@pytest.fixture(autouse=True)
def fresh_engines():
    """Each test meets its engines anew (a host keeps its timeouts in a row)."""
    close_engines()
    yield
    close_engines()


@pytest.fixture(scope="module")
def twins():
    for rec in toy_engine.MISBEHAVING.values():
        adapters.register(rec)
    yield {k: rec.name for k, rec in toy_engine.MISBEHAVING.items()}
    for rec in toy_engine.MISBEHAVING.values():
        adapters.unregister(rec.name)


def _jobs(name: str, es=(0.5,)) -> list[Job]:
    """Three impacts on the R161's barrel for each e (one batch per e: its scene)."""
    settings = adapters.settings_for(name)
    return [
        Job(
            engine=name,
            settings=settings,
            case=ImpactCase(
                bat=presets.R161,
                ball=presets.BASEBALL,
                s_m=s,
                v0_mps=40.0,
                u0_mps=10.0,
                omega0_radps=20.0,
                e=e,
            ),
        )
        for e in es
        for s in (0.05, 0.1, 0.15)
    ]


@pytest.mark.parametrize("twin", sorted(EXPECTED))
def test_a_misbehaving_adapter_fails_its_rows_not_the_run(twins, twin):
    physics, word = EXPECTED[twin]
    t0 = time.perf_counter()
    fired = fire_jobs(_jobs("toyengine_" + twin) + _jobs(ENGINE))
    elapsed = time.perf_counter() - t0
    theirs, ours = fired[:3], fired[3:]
    for f in theirs:
        assert f.outcome.physics is physics and word in f.outcome.ended, f.outcome.ended
    # the well-behaved engine after it, in the same firing: sound, as alone
    assert all(f.outcome.sound for f in ours), [f.outcome.ended for f in ours]
    # a hang costs its limit (1 s, the twin's record) and no more than a second over it
    assert elapsed < 30.0 if twin != "hangs" else 1.0 <= elapsed < 5.0, elapsed


def test_an_engine_that_times_out_twice_in_a_row_is_not_fired_again(twins):
    # Three scenes (e), so three batches: two wait out their limit, the third is not fired,
    # nor is a later firing in this process (a check after a check, a sweep's searches).
    t0 = time.perf_counter()
    fired = fire_jobs(_jobs(twins["hangs"], es=(0.3, 0.5, 0.7)))
    again = fire_jobs(_jobs(twins["hangs"]))
    assert time.perf_counter() - t0 < TIMEOUTS_IN_A_ROW * 1.0 + 5.0
    assert all(f.outcome.physics is Physics.TIMEOUT for f in [*fired, *again])
    assert [f.outcome.ended.startswith("not fired") for f in [*fired, *again]] == [False] * 6 + [
        True
    ] * 6


@pytest.fixture(scope="module")
def twins_site(tmp_path_factory):
    """The toy plug-in installed with its misbehaving twins as entry points."""
    return plugin_site(
        tmp_path_factory.mktemp("twins-site"),
        "batsim-toy-twins",
        {
            f"toyengine_{k}": f"toy_engine:MISBEHAVING_{k.upper()}"
            for k in [*EXPECTED, *IN_A_COMMAND]
        },
    )


def test_a_sweep_with_misbehaving_plugins_ends_with_their_rows(twins_site, tmp_path):
    # As a user runs it: the run ends (exit 0, in seconds: the close that hangs is left after
    # hosting.CLOSE_LIMIT_S) and its table holds every engine's rows, the twins' saying what
    # they did.
    twins = ["hangs", "exits", "exitshard", *IN_A_COMMAND]
    engines = ",".join([ENGINE, *(f"toyengine_{t}" for t in twins)])
    t0 = time.perf_counter()
    run_command(
        [
            "-m",
            "experiments.sweep",
            "--engine",
            engines,
            "--points",
            "3",
            "--no-locate",
            "--out",
            str(tmp_path),
            "--name",
            "r",
        ],
        env={"PYTHONPATH": str(twins_site)},
    )
    assert time.perf_counter() - t0 < 60.0
    table = pd.read_csv(tmp_path / "r" / "sweep.csv")
    by = table.groupby("engine").status.agg(set).to_dict()
    want = {
        f"toyengine_{t}": {str(EXPECTED[t][0]) if t in EXPECTED else IN_A_COMMAND[t]} for t in twins
    }
    assert by == {ENGINE: {"ok"}, **want}, by
    ended = table[table.engine == "toyengine_interrupts"].episode_end.iloc[0]
    assert "KeyboardInterrupt (no Ctrl-C was pressed)" in ended, ended


def test_check_engine_fails_a_hanging_adapter_in_seconds(twins_site):
    # Its first two batches wait out their limit (its record's 1 s); the checks after them
    # find it timed out twice in a row and fail at once, each saying so.
    t0 = time.perf_counter()
    res = run_command(
        ["-m", "experiments.check_engine", "--engine", "toyengine_hangs"],
        env={"PYTHONPATH": str(twins_site)},
        code=1,
    )
    assert time.perf_counter() - t0 < 60.0
    assert "FAILED" in res.stdout and "timeout" in res.stdout, res.stdout
