"""The failures a command expects, and how the user is told: one line, an exit code.

``UserError`` is a failure the user can act on (a file that is not what it must be, a broken
environment): the command's error boundary (``boundary.entry``) prints its message as one line
and exits with its code. ``BadInput`` is one found before any work (exit 2, as a bad option
is). Everything else that escapes a command (a full disk, a memory limit, a bug) is told in one
line by ``describe``, with the traceback only under ``--debug`` or ``BATSIM_DEBUG=1``.

This module imports nothing of the harness: ``experiments/__init__.py`` installs ``excepthook``
before a command's first import, so even a failure to import (a library that cannot map its
code under ``ulimit -v``) reads as one line.
"""

from __future__ import annotations

import errno
import os
import sys
import traceback

#: BATSIM_DEBUG's values (any case, spaces around ignored): whether a failure shows its traceback.
DEBUG_VALUES = {
    "1": True,
    "true": True,
    "yes": True,
    "0": False,
    "false": False,
    "no": False,
    "": False,
}


class UserError(Exception):
    """An expected failure: ``str(err)`` is the one line the user reads (what failed, what to
    do), ``code`` the exit code (1: the work failed)."""

    code = 1


class BadInput(UserError):
    """A file or setting handed to a command is not what it must be, found before any work."""

    code = 2


class OutputLost(UserError):
    """stdout could not take what the command printed (a full device, a closed pipe): the
    run's files are whole, what was left to print is lost."""

    def __init__(self, err: OSError | ValueError) -> None:
        why = getattr(err, "strerror", None) or err
        super().__init__(
            f"stdout could not be written ({why}); what was left to print is "
            "lost, the run's files are whole"
        )
        self.errno = getattr(err, "errno", None)


class Terminated(BaseException):
    """The process was asked to stop (SIGTERM, SIGHUP): raised where the signal lands, like
    KeyboardInterrupt, so that no engine's ``except Exception`` swallows it."""

    def __init__(self, signum: int) -> None:
        super().__init__(signum)
        self.signum = signum


def debug_asked(argv: list[str] | None = None) -> bool:
    """Whether the user asked for tracebacks: ``--debug`` on the command line or BATSIM_DEBUG."""
    args = sys.argv[1:] if argv is None else argv
    raw = os.environ.get("BATSIM_DEBUG", "").strip().lower()
    return "--debug" in args or DEBUG_VALUES.get(raw, False)


#: What to do about an operating system's refusal, by errno.
_ADVICE = {
    errno.ENOSPC: "free some space, or choose another --out",
    errno.EDQUOT: "free some space (a disk quota is reached), or choose another --out",
    errno.EFBIG: "the file size limit (ulimit -f) is below the run's files: raise it",
    errno.EROFS: "the file system is read-only: choose another --out",
    errno.EACCES: "choose a place you can write to (--out), or change its permissions",
    errno.EPERM: "choose a place you can write to (--out), or change its permissions",
    errno.ENOMEM: "the memory limit (ulimit -v) or the machine's memory is too small: raise "
    "it, or run fewer impacts or --workers",
    errno.EMFILE: "too many open files (ulimit -n): raise the limit, or run fewer --workers",
    errno.EIO: "an input/output error: check the disk",
}


def describe(err: BaseException) -> str:
    """One line saying what failed and what to do, for any exception a command lets escape."""
    if isinstance(err, UserError):
        return str(err)
    if isinstance(err, MemoryError):
        return (
            "out of memory (the memory limit, ulimit -v, or the machine's): run fewer "
            "impacts or --workers, or raise the limit"
        )
    if isinstance(err, ImportError) and "failed to map segment" in str(err):
        return (
            f"a library could not be loaded: {_line(err)}; the memory limit (ulimit -v) "
            "is too small: raise it"
        )
    if isinstance(err, ImportError):
        return (
            f"a library could not be imported: {_line(err)}; reinstall the project's "
            "environment (make test builds it)"
        )
    if isinstance(err, OSError):
        what = f"{err.strerror or type(err).__name__}"
        where = f": {err.filename}" if err.filename is not None else ""
        advice = _ADVICE.get(err.errno, "check the file and the disk")
        return f"{what}{where}; {advice}"
    return (
        f"internal error: {type(err).__name__}: {_line(err)} (rerun with --debug or "
        "BATSIM_DEBUG=1 for the traceback, and report it)"
    )


def _line(err: BaseException) -> str:
    return " ".join(str(err).split())[:300]


def report(err: BaseException, prog: str, debug: bool) -> None:
    """Tell the user of ``err`` on stderr: one line, or the traceback under ``debug``."""
    try:
        if debug:
            traceback.print_exception(err, file=sys.stderr)
        print(f"{prog}: error: {describe(err)}", file=sys.stderr, flush=True)
    except (OSError, ValueError):  # stderr itself is closed or full: nothing left to tell
        pass


def excepthook(kind, value, tb) -> None:
    """``sys.excepthook`` of a command: what escapes it (an import included) in one line."""
    if issubclass(kind, KeyboardInterrupt):
        report_stop("interrupted", 130)
        return
    spec = getattr(sys.modules.get("__main__"), "__spec__", None)
    report(
        value.with_traceback(tb), f"python -m {spec.name if spec else 'experiments'}", debug_asked()
    )


def report_stop(why: str, code: int) -> None:
    """A run stopped from outside (Ctrl-C, a signal): say so in one line."""
    try:
        print(
            f"{why}: nothing written, earlier results left as they were",
            file=sys.stderr,
            flush=True,
        )
    except (OSError, ValueError):
        pass
