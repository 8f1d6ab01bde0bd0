"""A wall-clock limit on an engine's work: an adapter that hangs becomes a ``timeout``, not a
run that never ends.

    with limited(limit_s(record, settings, worlds=n)):
        ...                       # TimedOut is raised here once limit_s has passed

The limit is raised where the clock runs out: in the main thread by SIGALRM (which also wakes
a ``time.sleep``), in another thread (a Dask worker's) by an asynchronous exception; both land
when Python code next runs, so a hang inside compiled code that never returns is caught by the
process that waits for it (``runner``: a worker is stopped). It is raised again every
``REPEAT_S`` until the block ends, since an engine's callback may swallow the first.
"""

from __future__ import annotations

import contextlib
import ctypes
import math
import signal
import threading
import time
from collections.abc import Iterator

import adapters

#: A batch of impacts may take this many times its worst-case cost (every episode stepped to
#: ``max_contact_s``, at the record's step cost) before it is a timeout: the record's costs are
#: measured on one 2-core host and a loaded one may be ten times slower; a hang is not slow.
SLACK = 50.0
#: No batch is a timeout before this (s): starting an engine (a JAX compile, a Warp module's
#: load) is part of its first batch, whatever its record says.
FLOOR_S = 60.0
#: How often the limit is raised again once it has passed (s).
REPEAT_S = 1.0


class TimedOut(BaseException):
    """The engine's work ran past its limit. A BaseException, as KeyboardInterrupt is: no
    engine's ``except Exception`` may swallow it."""


def limit_s(record: adapters.EngineRecord, settings: adapters.Settings, worlds: int,
            swing_steps: int = 0, floor_s: float = FLOOR_S) -> float:
    """How long a batch of ``worlds`` impacts on this engine may take (s): the record's own
    ``Cost.impact_limit_s`` per impact where it sets one, else SLACK times the worst case (at
    least ``floor_s``), plus the engine's start-up."""
    cost = record.cost
    per_world = worlds if cost.world_step_cost_s is None else 1
    if cost.impact_limit_s is not None:
        return cost.start_s + cost.impact_limit_s * per_world
    steps = (settings.approach_steps + math.ceil(settings.max_contact_s / settings.dt_s) + 2
             + swing_steps)
    step = cost.step_cost_s * per_world + (cost.world_step_cost_s or 0.0) * worlds
    return cost.start_s + max(floor_s, SLACK * steps * step)


@contextlib.contextmanager
def limited(seconds: float) -> Iterator[None]:
    """Raise ``TimedOut`` in this thread once ``seconds`` have passed, and every REPEAT_S after,
    until the block ends (module docstring)."""
    if threading.current_thread() is threading.main_thread():
        with _alarm(seconds):
            yield
    else:
        with _async(seconds):
            yield


@contextlib.contextmanager
def _alarm(seconds: float) -> Iterator[None]:
    """SIGALRM after ``seconds``; an outer alarm already set (pytest-timeout's) keeps its time
    and its handler."""
    t0 = time.monotonic()
    outer = signal.getsignal(signal.SIGALRM)
    outer_delay, outer_every = signal.setitimer(signal.ITIMER_REAL, 0)

    def ring(signum, frame) -> None:
        if outer_delay and time.monotonic() - t0 >= outer_delay and callable(outer):
            outer(signum, frame)
        if time.monotonic() - t0 >= seconds:
            raise TimedOut

    signal.signal(signal.SIGALRM, ring)
    first = min(seconds, outer_delay) if outer_delay else seconds
    signal.setitimer(signal.ITIMER_REAL, max(first, 1e-3), REPEAT_S)
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, outer)
        if outer_delay:
            left = outer_delay - (time.monotonic() - t0)
            signal.setitimer(signal.ITIMER_REAL, max(left, 1e-3), outer_every)


@contextlib.contextmanager
def _async(seconds: float) -> Iterator[None]:
    """``TimedOut`` sent to this thread by a timer thread after ``seconds``, then every
    REPEAT_S, until the block ends."""
    target, done = threading.get_ident(), threading.Event()

    def watch() -> None:
        if done.wait(seconds):
            return
        while not done.is_set():
            ctypes.pythonapi.PyThreadState_SetAsyncExc(ctypes.c_ulong(target),
                                                       ctypes.py_object(TimedOut))
            done.wait(REPEAT_S)

    watcher = threading.Thread(target=watch, daemon=True, name="batsim-watchdog")
    watcher.start()
    try:
        yield
    finally:
        done.set()
        watcher.join()
        ctypes.pythonapi.PyThreadState_SetAsyncExc(ctypes.c_ulong(target), None)
