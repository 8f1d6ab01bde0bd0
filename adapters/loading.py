"""Loading an engine when an impact is fired: its modules imported (``import_engine``, with
the install hint where one is missing and whatever it prints while loading dropped), and an
older release's missing attribute told apart from a bug (``feature``)."""

from __future__ import annotations

import contextlib
import importlib
import os
import sys
from collections.abc import Iterator
from types import ModuleType
from typing import Any

from .records import EngineNotInstalled, EngineRecord, MissingFeature


def feature(owner: object, attribute: str, setting: str) -> Any:
    """``owner.attribute`` of the engine's module, or MissingFeature naming the setting that
    needs it: adapters span releases by what a release has, not by its version string."""
    try:
        return getattr(owner, attribute)
    except AttributeError:
        raise MissingFeature(
            f"{getattr(owner, '__name__', owner)} has no {attribute} in this "
            f"release ({setting} needs it)"
        ) from None


def import_engine(record: EngineRecord) -> ModuleType:
    """Import the engine's module, or raise EngineNotInstalled with the install hint. Whatever
    the engine prints to the process's stdout while it loads (PyBullet's build-time banner) is
    dropped, so that it never mixes with a command's own output."""
    try:
        with stdout_silenced():
            for name in record.install.requires:
                importlib.import_module(name)
            return importlib.import_module(record.install.import_name)
    except ModuleNotFoundError as err:
        tops = {m.split(".")[0] for m in (record.install.import_name, *record.install.requires)}
        if err.name is None or err.name.split(".")[0] not in tops:
            raise
        raise EngineNotInstalled(record.install_hint) from err


@contextlib.contextmanager
def stdout_silenced() -> Iterator[None]:
    """Point file descriptors 1 and 2 at /dev/null for the block (C libraries print there
    directly); an import error still arrives as a Python exception."""
    streams = []
    for stream in (sys.stdout, sys.stderr):
        try:
            streams.append(stream.fileno())
            stream.flush()
        except (AttributeError, OSError, ValueError):  # no real stream (captured by pytest)
            continue
    saved = [os.dup(fd) for fd in streams]
    try:
        with open(os.devnull, "wb") as null:
            for fd in streams:
                os.dup2(null.fileno(), fd)
        yield
    finally:
        _flush_c_stdio()  # C's buffered output would otherwise reach the real streams later
        for fd, copy in zip(streams, saved):
            os.dup2(copy, fd)
            os.close(copy)


def _flush_c_stdio() -> None:
    import ctypes

    try:
        ctypes.CDLL(None).fflush(None)
    except (OSError, AttributeError):
        pass


#: Threads an engine's own batched step may use in this process (``engine_threads``); None: one
#: per core this process may run on.
_THREADS: list[int | None] = [None]


def engine_threads() -> int:
    """How many threads an engine library's batched or threaded step may use here: one per
    core this process may run on, unless the runner spreads the work over processes
    (``set_engine_threads``: one each, so that the workers do not fight for the cores)."""
    if _THREADS[0] is not None:
        return _THREADS[0]
    return len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count() or 1


def set_engine_threads(threads: int | None) -> None:
    """Set ``engine_threads`` for this process (None: one per core again); adapters made
    afterwards take it."""
    if threads is not None and threads < 1:
        raise ValueError(f"threads={threads!r}; allowed: None or an integer >= 1")
    _THREADS[0] = threads
