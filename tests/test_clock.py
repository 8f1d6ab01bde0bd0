"""``adapters.clock``: a limit on code that may never return, raised where it runs (SIGALRM in
the main thread, which wakes a sleep; an asynchronous exception in another thread), and again
if swallowed; an outer alarm (pytest-timeout's) keeps its time; ``os._exit`` raises instead of
ending the process, but a child forked meanwhile still ends with it."""

from __future__ import annotations

import os
import signal
import threading
import time

import pytest

from adapters import clock

#: A limit short against the test, long against the timer's granularity (s).
LIMIT_S = 0.2


def test_a_sleep_past_the_limit_is_woken_in_the_main_thread():
    t0 = time.monotonic()
    with pytest.raises(clock.TimedOut), clock.limited(LIMIT_S):
        time.sleep(30)
    assert LIMIT_S <= time.monotonic() - t0 < LIMIT_S + 1.0


def test_a_busy_loop_past_the_limit_is_stopped_in_another_thread():
    caught = []

    def spin() -> None:
        try:
            with clock.limited(LIMIT_S):
                while True:
                    pass
        except clock.TimedOut:
            caught.append(True)

    worker = threading.Thread(target=spin)
    worker.start()
    worker.join(timeout=10)
    assert caught == [True] and not worker.is_alive()


def test_a_swallowed_limit_is_raised_again():
    swallowed = 0
    with pytest.raises(clock.TimedOut), clock.limited(LIMIT_S):
        while True:
            try:
                time.sleep(30)
            except clock.TimedOut:  # an engine's callback that swallows what lands in it
                swallowed += 1
                if swallowed > 1:
                    raise
    assert swallowed == 2


def test_an_outer_alarm_keeps_its_time_and_handler():
    rang = []
    previous = signal.signal(signal.SIGALRM, lambda *a: rang.append(time.monotonic()))
    try:
        t0 = time.monotonic()
        signal.setitimer(signal.ITIMER_REAL, 0.5)
        with clock.limited(10.0):
            time.sleep(0.1)
        time.sleep(1.0)  # the outer alarm rings at 0.5 s, as set before the block
        assert len(rang) == 1 and 0.45 <= rang[0] - t0 < 0.7, rang
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, previous)


def test_os_exit_raises_but_a_forked_child_exits():
    with pytest.raises(clock.ProcessExit) as stop, clock.exits_raise():
        os._exit(3)
    assert stop.value.code == 3
    with clock.exits_raise():
        pid = os.fork()
        if pid == 0:
            os._exit(7)
        _, status = os.waitpid(pid, 0)
    assert os.waitstatus_to_exitcode(status) == 7
