"""Workers die with their parent and a lost worker is not the end of a run: a ``--workers 2``
sweep stopped by SIGTERM or SIGHUP exits 143 or 129 with no process left behind (none
re-parented, none holding its output pipe open); a worker killed mid-run has its impacts sent
again once to a new worker, and lost twice they are rows that say so; a worker that never
answers (a hang in compiled code, which its own limit cannot reach) is stopped at the chunk's
limit, its impacts ``timeout`` rows."""

from __future__ import annotations

import contextlib
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import psutil
import pytest

import adapters
from analytic import presets
from experiments.core import Physics, fire_jobs, firings, hosting
from experiments.core.boundary import STOP, stopping
from experiments.core.runner import Runner
from experiments.core.workers import pool_results

from .conftest import ROOT, cheapest

ENGINE = cheapest(batched=False)
#: Single-world engines whose pool steps through their library's own threaded call (records
#: only: collecting the tests imports no engine).
THREADED = [
    n
    for n in adapters.names()
    if not adapters.record(n).batched
    and adapters.record(n).can.pool_adapter is not None
    and (said := adapters.record(n).batching) is not None
    and said.used
]


def _die_once(marker: str) -> str:
    """Kill this worker the first time (SIGKILL, as the kernel's OOM killer does)."""
    if not Path(marker).exists():
        Path(marker).write_text("died")
        os.kill(os.getpid(), signal.SIGKILL)
    return "done"


def _die(_: str) -> str:
    os.kill(os.getpid(), signal.SIGKILL)
    return "never"


def _die_at_x(item: str) -> str:
    """'x' kills its worker every time; the others once each."""
    return _die(item) if item == "x" else _die_once(item)


def _hang(_: str) -> str:
    time.sleep(3600)  # no watchdog around it here: as a hang in compiled code looks
    return "never"


def _lost(item, status, why):
    return (item, status, why)


def test_killed_workers_are_replaced_and_their_items_sent_again(tmp_path):
    # each item kills its worker once: the pool breaks as often as there are items, and every
    # item still comes back (sent again together, then one at a time)
    items = [str(tmp_path / k) for k in "abcde"]
    with Runner(workers=2) as runner:
        got = list(pool_results(runner, _die_once, items, _lost, None))
    assert got == ["done"] * 5


def test_the_item_that_kills_its_worker_is_its_only_row_lost(tmp_path):
    items = [str(tmp_path / "a"), "x", str(tmp_path / "b")]
    with Runner(workers=2) as runner:
        got = list(pool_results(runner, _die_at_x, items, _lost, None))
    assert got[0] == got[2] == "done", got
    item, physics, why = got[1]
    assert item == "x" and physics is Physics.ERROR and "killed by SIGKILL" in why, why


def test_a_worker_that_never_answers_is_stopped_at_its_limit():
    t0 = time.perf_counter()
    with Runner(workers=2) as runner:
        ((item, physics, why),) = list(pool_results(runner, _hang, ["x"], _lost, lambda i: 1.0))
    assert physics is Physics.TIMEOUT and "within 1 s" in why, why
    assert time.perf_counter() - t0 < 20.0


def test_a_worker_stopped_before_it_starts_dies_of_the_signal():
    # forked inside a section that holds signals back (the pool starting its workers), before
    # its own handlers are set: the parent's handler, inherited, must not swallow a SIGTERM
    # (the pool's clean-up would then wait for it forever)
    # (signalled once the child is past fork's own fix-up, which drops a signal that comes
    # before it: the pool's clean-up kills what terminate does not stop)
    with stopping(), STOP.deferred():
        ready, told = os.pipe()
        pid = os.fork()
        if pid == 0:
            try:
                os.write(told, b"1")
                time.sleep(30.0)
            finally:
                os._exit(0)
        os.read(ready, 1)
        os.kill(pid, signal.SIGTERM)
        _, status = os.waitpid(pid, 0)
        os.close(ready), os.close(told)
    assert os.WIFSIGNALED(status) and os.WTERMSIG(status) == signal.SIGTERM, status


def _ended(proc: subprocess.Popen, workers: list, timeout_s: float) -> tuple[str, str]:
    """The run's output once its pipes close; if they do not, a failure naming who holds
    them, with where each such process stands (faulthandler's dump on SIGABRT)."""
    try:
        return proc.communicate(timeout=timeout_s)
    except subprocess.TimeoutExpired:
        holders = [proc] if proc.poll() is None else []
        holders += [w for w in workers if w.is_running() and w.status() != psutil.STATUS_ZOMBIE]
        for p in holders:
            p.send_signal(signal.SIGABRT)
        time.sleep(2.0)
        for w in workers:
            with contextlib.suppress(psutil.Error):
                w.kill()
        out, err = proc.communicate(timeout=30)
        pytest.fail(
            f"not ended within {timeout_s:g} s; still running: "
            f"{[(p.pid, 'parent' if p is proc else 'worker') for p in holders]}\n{err}"
        )


@pytest.mark.parametrize("sig,code", [(signal.SIGTERM, 143), (signal.SIGHUP, 129)])
def test_a_stopped_sweep_leaves_no_worker_behind(sig, code, tmp_path):
    # 600 swings: many seconds on two workers, stopped once its workers are up
    proc = subprocess.Popen(
        [
            sys.executable,
            "-m",
            "experiments.sweep",
            "--engine",
            ENGINE,
            "--points",
            "600",
            "--swing",
            "--no-locate",
            "--workers",
            "2",
            "--budget-h",
            "100",
            "--out",
            str(tmp_path),
            "--name",
            "r",
        ],
        cwd=ROOT,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        env={**os.environ, "BATSIM_QUIET": "1", "PYTHONFAULTHANDLER": "1"},
    )
    parent = psutil.Process(proc.pid)
    deadline = time.monotonic() + 60.0
    while len(parent.children()) < 2 and time.monotonic() < deadline:
        time.sleep(0.2)
    workers = parent.children(recursive=True)
    assert len(workers) >= 2, "the workers never started"
    proc.send_signal(sig)
    out, err = _ended(proc, workers, timeout_s=60.0)  # the pipes close: no worker holds them
    assert proc.returncode == code, err
    assert err.count("\n") == 1 and "nothing written" in err, err
    gone, alive = psutil.wait_procs(workers, timeout=10)
    assert not alive, [p.pid for p in alive]
    assert not (tmp_path / "r").exists()


def _answer(_: str) -> str:
    return "done"


@pytest.mark.parametrize("name", THREADED)
def test_workers_forked_from_a_process_holding_a_threaded_pool_answer(name):
    # A pool's library threads stay in the parent when a worker is forked: the worker drops its
    # copies of the parent's engines without freeing that pool (freeing it joins threads the
    # child does not have: the workers hung, or died of SIGSEGV, and their items were lost).
    settings = adapters.settings_for(name)
    grid = firings.Firing(
        bat=presets.R161,
        s_m=firings.grid(presets.R161, 41),
        v0_mps=presets.PAPER_PITCH_MPS,
        u0_mps=presets.PAPER_SWING.u0_mps,
        omega0_radps=presets.PAPER_SWING.omega0_radps,
        e=presets.E_WOOD,
    )
    try:
        fire_jobs(grid.jobs(name, settings))  # (41 impacts: on the pool, its threads alive here)
        assert hosting.hosted(name, settings).held() > 1
        with Runner(workers=2) as runner:
            got = list(pool_results(runner, _answer, ["a", "b", "c"], _lost, lambda _: 60.0))
        assert got == ["done"] * 3
    finally:
        hosting.close_engines()
