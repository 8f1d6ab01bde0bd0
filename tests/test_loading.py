"""``adapters.set_engine_threads`` does what it says, read back through ``engine_threads``
(what an engine library's batched or threaded step is given): the count set, one per core this
process may run on again with None, no count below one; and the runner's workers run their
engines on one thread each, so that they do not fight for the cores."""

from __future__ import annotations

import os
import subprocess
import sys

import pytest

import adapters
from experiments.core.runner import Runner
from experiments.core.workers import pool_results

from .conftest import ROOT


def _cores() -> int:
    """The cores this process may run on, as the operating system says."""
    return len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count()


def test_set_engine_threads_is_read_back_and_undone():
    try:
        for threads in (1, 3, 1000):
            adapters.set_engine_threads(threads)
            assert adapters.engine_threads() == threads
        adapters.set_engine_threads(None)
        assert adapters.engine_threads() == _cores()
        for bad in (0, -2):
            with pytest.raises(ValueError, match="allowed: None or an integer >= 1"):
                adapters.set_engine_threads(bad)
            assert adapters.engine_threads() == _cores()  # a refused count changes nothing
    finally:
        adapters.set_engine_threads(None)


def test_by_default_one_thread_per_core_the_process_may_run_on():
    # a fresh interpreter held to one core (its affinity, as taskset sets it) gives its engines
    # one thread, though the machine has more
    code = (
        "import os, adapters\n"
        "if hasattr(os, 'sched_setaffinity'):\n"
        "    os.sched_setaffinity(0, {min(os.sched_getaffinity(0))})\n"
        "    print(adapters.engine_threads())\n"
        "else:\n"
        "    print(1)\n"
    )
    res = subprocess.run(
        [sys.executable, "-c", code], cwd=ROOT, capture_output=True, text=True, check=True
    )
    assert res.stdout.strip() == "1", res.stderr


def _threads(_: str) -> int:
    return adapters.engine_threads()


def _lost(item, status, why):
    return (item, status, why)


def test_the_runners_workers_give_their_engines_one_thread_each():
    with Runner(workers=2) as runner:
        got = list(pool_results(runner, _threads, ["a", "b", "c", "d"], _lost, None))
    assert got == [1, 1, 1, 1]
