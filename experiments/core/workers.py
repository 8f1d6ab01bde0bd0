"""The runner's workers, and what happens when one is lost.

A local worker (``worker_start``) dies with the process that started it, however that one ends
(SIGTERM, SIGHUP, SIGKILL: Linux's parent-death signal), and leaves Ctrl-C to it. A worker
lost mid-run (killed, out of memory) or an item that never comes back (a hang inside compiled
code, past its limit) is not the end of the run:

- ``pool_results``: the items a broken pool still owed are sent once more to new workers; if
  it breaks again, they run one at a time, and the one whose worker dies then, or an item past
  its limit, is answered by ``lost(item, physics, why)`` (the impacts' rows) or, where the
  caller has no rows to give, a one-line ``UserError``;
- ``dask_results``: the same on a Dask cluster (which already retries a task whose worker
  died, ``distributed.scheduler.allowed-failures`` times, before it gives up on it).
"""

from __future__ import annotations

import contextlib
import ctypes
import os
import signal
import sys
import time
from collections.abc import Callable, Iterator
from concurrent.futures import Future
from concurrent.futures import TimeoutError as FutureTimeout
from concurrent.futures.process import BrokenProcessPool

import adapters

from ..errors import UserError
from .boundary import STOP
from .endings import Physics
from .hosting import forget_engines

#: Linux's prctl option that sends a signal to a process when its parent dies.
PR_SET_PDEATHSIG = 1
#: A pool that breaks has what it owed sent again, together, this many times; after that,
#: one at a time, so that the item that kills its worker is told from the others.
RETRIES = 1


def worker_start(parent_pid: int | None) -> None:
    """In a new local worker: drop the parent's engines (``forget_engines``), die with the
    parent (SIGTERM on its death, where Linux offers it; at once if ``parent_pid``, the process
    that forked it, died before this ran), and leave Ctrl-C and SIGHUP to the parent, which
    stops its workers itself. The engines' own threads: one (the workers fill the cores)."""
    forget_engines()
    adapters.set_engine_threads(1)
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    signal.signal(signal.SIGHUP, signal.SIG_IGN)
    signal.signal(signal.SIGTERM, signal.SIG_DFL)
    if sys.platform.startswith("linux"):
        with contextlib.suppress(OSError, AttributeError):
            ctypes.CDLL(None, use_errno=True).prctl(PR_SET_PDEATHSIG, int(signal.SIGTERM))
    if parent_pid is not None and os.getppid() != parent_pid:  # (died before it was asked)
        os._exit(128 + signal.SIGTERM)


def _give_up(item, physics: Physics, why: str):
    raise UserError(f"{why}; allowed: fewer --workers, or more memory")


def pool_results(
    runner, fn: Callable, items: list, lost: Callable | None, limit_s: Callable | None
) -> Iterator:
    """``fn`` over ``items`` on the runner's local workers, all sent now, their results in
    order as they come (module docstring). ``limit_s(item)``: how long one may take once
    waited for (None: no limit)."""
    with STOP.deferred():  # a stop mid-way would leave a worker the pool does not know
        futures: list[Future] = [runner.pool().submit(fn, item) for item in items]
    return _collected(runner, fn, items, futures, lost or _give_up, limit_s)


def _collected(
    runner,
    fn: Callable,
    items: list,
    futures: list[Future | None],
    lost: Callable,
    limit_s: Callable | None,
) -> Iterator:
    """The results in order. A pool that breaks has what it owed sent again to new workers,
    together, RETRIES times; after that, one at a time (``alone``): an item whose worker dies
    while it runs alone is the one that kills them, and it alone is lost, once it has done so
    RETRIES + 1 times (an out-of-memory kill may not come again)."""
    breaks, alone, tries = 0, False, 0
    i = 0
    while i < len(items):
        if futures[i] is None:  # one at a time, from here on
            with STOP.deferred():
                futures[i] = runner.pool().submit(fn, items[i])
        limit = limit_s(items[i]) if limit_s else None
        try:
            result = futures[i].result(timeout=limit)
        except BrokenProcessPool:
            cause = death(runner.pool())
            tries += alone
            if tries <= RETRIES:
                breaks += 1
                alone = breaks > RETRIES
                _send_again(runner, fn, items, futures, i, alone)
                continue
            result = lost(
                items[i],
                Physics.ERROR,
                f"error: its worker process died ({cause}), {tries} times while it ran alone",
            )
            _send_again(runner, fn, items, futures, i + 1, alone)
        except FutureTimeout:
            result = lost(
                items[i],
                Physics.TIMEOUT,
                f"timeout: its worker gave no result within {limit:.3g} s and was stopped",
            )
            _send_again(runner, fn, items, futures, i + 1, alone)
        yield result
        i, tries = i + 1, 0


def _send_again(
    runner, fn: Callable, items: list, futures: list[Future | None], start: int, alone: bool
) -> None:
    """New workers in place of the pool's, and the items from ``start`` on that it still
    owed sent to them (``alone``: each when its turn comes)."""
    with STOP.deferred():
        pool = runner.renew_pool()
        for k in range(start, len(items)):
            f = futures[k]
            if (
                f is None
                or not f.done()
                or f.cancelled()
                or isinstance(f.exception(), BrokenProcessPool)
            ):
                futures[k] = None if alone else pool.submit(fn, items[k])


def death(pool) -> str:
    """How a broken pool's workers died: the signal or exit code of each that ended on its
    own (the pool stops the others with SIGTERM)."""
    said = []
    for process in list((getattr(pool, "_processes", None) or {}).values()):
        code = _exit_code(process)
        if code is None or code == -signal.SIGTERM:
            continue
        said.append(
            f"killed by {signal.Signals(-code).name}" if code < 0 else f"exited with code {code}"
        )
    return ", ".join(dict.fromkeys(said)) or "it ended"


def _exit_code(process, wait_s: float = 2.0) -> int | None:
    """The process's exit code, once it has one (None past ``wait_s``). The pool's own thread
    reaps its workers too: a join that loses that race reads no code although the process is
    gone, so the code is read again until the winner has set it."""
    deadline = time.monotonic() + wait_s
    while True:
        process.join(timeout=0.05)  # (the pool stops the others meanwhile, in its own thread)
        if process.exitcode is not None or time.monotonic() > deadline:
            return process.exitcode


def _dask_losses() -> tuple[type[BaseException], ...]:
    """What a Dask future raises when its worker, not its task, failed."""
    from distributed import KilledWorker
    from distributed.comm.core import CommClosedError

    return (KilledWorker, CommClosedError)


def dask_results(
    client, fn: Callable, items: list, lost: Callable | None, limit_s: Callable | None
) -> Iterator:
    """``fn`` over ``items`` on a Dask cluster, all sent now, their results in order as they
    come (module docstring)."""
    futures = client.map(fn, items, pure=False)
    return _dask_collected(client, fn, items, futures, lost or _give_up, limit_s)


def _dask_collected(
    client, fn: Callable, items: list, futures: list, lost: Callable, limit_s: Callable | None
) -> Iterator:
    losses = _dask_losses()
    for item, future in zip(items, futures):
        limit = limit_s(item) if limit_s else None
        for attempt in range(RETRIES + 1):
            try:
                yield future.result(timeout=limit)
                break
            except losses as err:
                if attempt < RETRIES:
                    future = client.submit(fn, item, pure=False)
                    continue
                yield lost(
                    item,
                    Physics.ERROR,
                    f"error: its Dask worker was lost ({type(err).__name__}: {err})"[:200],
                )
            except TimeoutError:
                future.cancel()
                yield lost(
                    item,
                    Physics.TIMEOUT,
                    f"timeout: its Dask worker gave no result within {limit:.3g} s",
                )
                break
