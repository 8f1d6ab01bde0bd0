"""Every command's error boundary: whatever goes wrong reaches the user as one line and an
exit code, and nothing half-made replaces what was there.

    @boundary.entry
    def main(argv=None) -> int: ...

- an expected failure (``UserError``, a full disk, a memory limit, a closed pipe) is one
  line on stderr and exit 1 (2 for a bad input, found before any work); a bug too, with its
  traceback only under ``--debug`` or BATSIM_DEBUG=1;
- Ctrl-C exits 130, SIGTERM 143 and SIGHUP 129 (``stopping``): the run's files are published as
  a whole or not at all (``runs.publish``), so every earlier file is left as it was;
- a closed stdout (``| head -1``) is handled as Python's documentation advises (the rest of the
  output goes to /dev/null), exit 141 as a shell says; a missing stdout or stderr (``2>&-``) is
  /dev/null, a stderr that cannot be written (``2>/dev/full``) is ignored, and
  text the terminal's encoding cannot show (a non-UTF-8 path, PYTHONIOENCODING=ascii) is
  shown escaped, never a failure;
- charts are drawn to files with matplotlib's Agg, whatever MPLBACKEND says (a name matplotlib
  does not know is refused first, as any bad setting is).
"""

from __future__ import annotations

import contextlib
import errno
import functools
import logging
import os
import re
import signal
import sys
import threading
import warnings
from collections.abc import Callable, Iterator

from ..errors import (
    DEBUG_VALUES,
    OutputLost,
    Terminated,
    UserError,
    debug_asked,
    report,
    report_stop,
)
from . import device_episode

#: What BATSIM_WARP_DEVICE may name (the engines on Warp read it): Warp's device names.
WARP_DEVICE = re.compile(r"^(cpu|cuda(:[0-9]+)?)$")
#: The signals that stop a run, each as its own exit code (128 + the signal's number): Ctrl-C,
#: a kill, a closed terminal, a CPU-time limit reached (``ulimit -t``).
STOPPING = (signal.SIGINT, signal.SIGTERM, signal.SIGHUP, signal.SIGXCPU)


class Stop:
    """The signal that stopped the run, if one did. Python code that an engine calls back
    (pymunk's velocity functions) swallows what the signal raises there, so the harness
    checks this once a batch is done (``check``)."""

    def __init__(self) -> None:
        self.signum: int | None = None
        #: whether a command's handlers are in place (``stopping``): a KeyboardInterrupt
        #: with no signal come is then an engine's own, not the user's
        self.active = False
        #: inside ``deferred``: a signal is kept (``held``), and raised when the section ends
        self.deferring = False
        self.held = False

    def clear(self) -> None:
        self.signum = None
        self.held = False

    @contextlib.contextmanager
    def deferred(self) -> Iterator[None]:
        """A section a signal must not cut in two (a worker pool half started, a job half
        queued, which no clean-up could then find): the signal raises as the section ends."""
        outer, self.deferring = self.deferring, True
        try:
            yield
        finally:
            self.deferring = outer
        if self.held and not outer:
            self.held = False
            self.check()

    def check(self) -> None:
        """Raise what the signal raises, if one came."""
        if self.signum is not None:
            raise _raised(self.signum)


STOP = Stop()


def _raised(signum: int) -> BaseException:
    return KeyboardInterrupt() if signum == signal.SIGINT else Terminated(signum)


def entry(
    main: Callable[[list[str] | None], int], prog: str | None = None
) -> Callable[[list[str] | None], int]:
    """A command's ``main(argv)`` behind the boundary (module docstring); ``prog`` names it in
    its messages (default: ``python -m`` and the module ``main`` is in)."""
    prog = prog or f"python -m {_module_name(main)}"

    @functools.wraps(main)
    def guarded(argv: list[str] | None = None) -> int:
        debug = debug_asked(argv)
        with _streams() as stdout, warnings.catch_warnings():
            warnings.simplefilter("ignore")  # a run keeps them (``cli.library_messages_kept``)
            try:
                return main(argv)
            except SystemExit:
                raise
            except KeyboardInterrupt:
                report_stop("interrupted", 130)
                return 130
            except Terminated as stop:
                report_stop(f"stopped by {signal.Signals(stop.signum).name}", 128 + stop.signum)
                return 128 + stop.signum
            except OutputLost as err:
                _drop_stdout(stdout)
                if err.errno == errno.EPIPE:  # a closed pipe (| head): the reader's choice,
                    return 128 + signal.SIGPIPE  # told as a shell tells it (not 1: a verdict)
                report(err, prog, debug)
                return 1
            except Exception as err:  # noqa: BLE001 - the boundary: any failure in one line
                report(err, prog, debug)
                return err.code if isinstance(err, UserError) else 1

    return guarded


@contextlib.contextmanager
def _streams() -> Iterator:
    """stdout and stderr for a command (``prepare_streams``): stdout's failures to write are
    ``OutputLost``, told apart from a file's; stderr's are dropped (progress and messages
    that cannot be shown must not stop a run). Yields the stdout it wrapped."""
    prepare_streams()
    stdout, stderr = sys.stdout, sys.stderr
    sys.stdout, sys.stderr = _Stream(stdout, OutputLost), _Stream(stderr, None)
    try:
        yield stdout
    finally:
        sys.stdout, sys.stderr = stdout, stderr


class _Stream:
    """A text stream whose OSErrors become ``failure(err)`` (None: the text is dropped)."""

    def __init__(self, stream, failure) -> None:
        self._stream, self._failure = stream, failure

    def write(self, text: str) -> int:
        try:
            return self._stream.write(text)
        except (OSError, ValueError) as err:  # (ValueError: closed, by an engine, say)
            if self._failure is None:
                return len(text)
            raise self._failure(err) from None

    def flush(self) -> None:
        try:
            self._stream.flush()
        except (OSError, ValueError) as err:
            if self._failure is not None:
                raise self._failure(err) from None

    def __getattr__(self, name: str):
        return getattr(self._stream, name)


def _module_name(fn: Callable) -> str:
    """The module ``fn`` is in, as ``python -m`` names it (its spec's name when run so)."""
    if fn.__module__ != "__main__":
        return fn.__module__
    spec = getattr(sys.modules["__main__"], "__spec__", None)
    return spec.name if spec is not None else "__main__"


def prepare_streams() -> None:
    """A missing stdout or stderr becomes /dev/null; both show what their encoding cannot
    encode as escapes (``backslashreplace``) instead of failing."""
    for name in ("stdout", "stderr"):
        stream = getattr(sys, name)
        if stream is None:
            setattr(sys, name, open(os.devnull, "w"))  # noqa: SIM115 - for the process's life
            continue
        with contextlib.suppress(AttributeError, ValueError, OSError):
            stream.reconfigure(errors="backslashreplace")


def _drop_stdout(stream) -> None:
    """stdout cannot take more (a closed pipe, a full device): point it at /dev/null, as
    Python's documentation advises for SIGPIPE, so that the interpreter's flush at exit fails
    no more."""
    with contextlib.suppress(OSError, ValueError, AttributeError):
        os.dup2(os.open(os.devnull, os.O_WRONLY), stream.fileno())


def environment_error() -> str | None:
    """The one-line complaint about the environment's settings, or None: BATSIM_DEBUG's value,
    BATSIM_WARP_DEVICE's and BATSIM_DEVICE_EPISODE's (``device_episode``), and MPLBACKEND's (a
    name matplotlib does not know; any known one is replaced by Agg, since every chart goes to a
    file)."""
    raw = os.environ.get("BATSIM_DEBUG", "")
    if raw.strip().lower() not in DEBUG_VALUES:
        return (
            f"BATSIM_DEBUG={raw!r} is not allowed; allowed: 1, true or yes (tracebacks), "
            "0, false, no or empty"
        )
    device = os.environ.get("BATSIM_WARP_DEVICE", "")
    if device and not WARP_DEVICE.match(device):
        return (
            f"BATSIM_WARP_DEVICE={device!r} is not a Warp device; allowed: cpu, cuda or "
            "cuda:N (N a GPU's number), or unset (the CPU)"
        )
    episode = os.environ.get(device_episode.ENV, "")
    if episode and episode not in device_episode.CHOICES:
        return (
            f"{device_episode.ENV}={episode!r} is not allowed; allowed: "
            f"{', '.join(device_episode.CHOICES)}, or unset (auto)"
        )
    backend = os.environ.pop("MPLBACKEND", None)
    # what matplotlib says of its own cache (unwritable: it makes a temporary one) is not the
    # run's business: its errors only
    logging.getLogger("matplotlib").setLevel(logging.ERROR)
    import matplotlib

    matplotlib.use("Agg")
    if backend is None:
        return None
    from matplotlib import rcsetup

    try:
        rcsetup.validate_backend(backend)
    except ValueError:
        return (
            f"MPLBACKEND={backend!r} is not a matplotlib backend; allowed: unset it, or a "
            "backend's name such as agg (the charts are drawn to files with Agg)"
        )
    return None


@contextlib.contextmanager
def stopping() -> Iterator[None]:
    """Ctrl-C raises KeyboardInterrupt and SIGTERM or SIGHUP ``Terminated`` where they
    land (in the main thread), and ``STOP`` keeps which came: the run stops, its workers with
    it (``runner``), and nothing is published."""
    STOP.clear()
    if threading.current_thread() is not threading.main_thread():
        yield
        return

    owner = os.getpid()

    def stop(signum, frame) -> None:
        if os.getpid() != owner:  # a worker forked here, stopped before it set its own
            signal.signal(signum, signal.SIG_DFL)
            os.kill(os.getpid(), signum)
            return
        STOP.signum = signum
        STOP.held = STOP.deferring
        if not STOP.deferring:
            raise _raised(signum)

    previous = {s: signal.signal(s, stop) for s in STOPPING}
    STOP.active = True
    try:
        yield
    finally:
        STOP.active = False
        for s, handler in previous.items():
            signal.signal(s, handler)
