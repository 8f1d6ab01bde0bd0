"""A wall-clock limit on code that may never return, and an exit that may not end the process:
what the registry puts around a plug-in's import and the harness around an engine's work.

    with limited(60.0), exits_raise():
        ...          # TimedOut is raised here once 60 s have passed; os._exit raises ProcessExit

The limit is raised where the clock runs out: in the main thread by SIGALRM (which also wakes
a ``time.sleep``), in another thread (a Dask worker's) by an asynchronous exception; both land
when Python code next runs, so a hang inside compiled code that never returns is for the
process that waits for it to stop. It is raised again every ``REPEAT_S`` until the block ends,
since an engine's callback may swallow the first.
"""

from __future__ import annotations

import contextlib
import ctypes
import os
import signal
import threading
import time
from collections.abc import Iterator

#: How often the limit is raised again once it has passed (s).
REPEAT_S = 1.0


class TimedOut(BaseException):
    """The code ran past its limit. A BaseException, as KeyboardInterrupt is: no engine's
    ``except Exception`` may swallow it."""


class ProcessExit(BaseException):
    """The code called ``os._exit`` (``exits_raise``): ``code`` is what it asked for."""

    def __init__(self, code: int) -> None:
        super().__init__(code)
        self.code = code


@contextlib.contextmanager
def exits_raise() -> Iterator[None]:
    """``os._exit`` raises ``ProcessExit`` meanwhile, instead of ending the process with no
    word and no file written: a plug-in's own exit is its failure, not the run's end. (A
    process forked meanwhile exits as it asks: its ``os._exit`` is how a child ends.)"""
    real, pid = os._exit, os.getpid()

    def refuse(code: int) -> None:
        if os.getpid() != pid:
            real(code)
        raise ProcessExit(code)

    os._exit = refuse
    try:
        yield
    finally:
        os._exit = real


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
            ctypes.pythonapi.PyThreadState_SetAsyncExc(
                ctypes.c_ulong(target), ctypes.py_object(TimedOut)
            )
            done.wait(REPEAT_S)

    watcher = threading.Thread(target=watch, daemon=True, name="batsim-watchdog")
    watcher.start()
    try:
        yield
    finally:
        done.set()
        watcher.join()
        ctypes.pythonapi.PyThreadState_SetAsyncExc(ctypes.c_ulong(target), None)
