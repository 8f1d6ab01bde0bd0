"""The command-line convention every experiment follows.

Options spelled the same everywhere:
    --engine NAME[,NAME...]|all   engines from the registry (built-ins and plug-ins)
    --workers N / --scheduler     how the impacts run (experiments.core.runner)
    --out DIR  --name STEM  --force
                                  where a run's files go (experiments.core.runs)
Every option is checked before any simulation runs or any file is touched: a bad one exits 2
with one line naming the option, the value and what is allowed (an unwritable --out and a
--scheduler that does not answer within seconds included). --help only prints. Progress goes
to stderr (a bar on a terminal, a line every few seconds otherwise; none with BATSIM_QUIET=1).
Ctrl-C stops a run with exit 130 and leaves every earlier file as it was.

A study is a ``Command``: its name, the options it adds, and ``produce(args) -> (files, text)``.
"""

from __future__ import annotations

import argparse
import contextlib
import math
import os
import re
import shutil
import sys
import tempfile
import time
import warnings
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import adapters

from . import boundary, runs
from . import runner as _runner
from .estimate import duration
from .runs import RESULTS, RUNS, Progress, publish, quiet_error, run_dir, shown

MAX_WORKERS = 64
#: The longest file name most file systems take (bytes).
NAME_MAX = 255
#: A command expected to run at least this long (s) says so before it starts.
SAY_ESTIMATE_S = 10.0
STEM = re.compile(r"^[A-Za-z0-9][A-Za-z0-9._=+,-]{0,99}$")


class Parser(argparse.ArgumentParser):
    """argparse with one-line errors (exit 2), negative numbers accepted as values, each option
    spelled out (no abbreviations) and given at most once, and BATSIM_QUIET checked."""

    def __init__(self, *args, **kwargs) -> None:
        super().__init__(*args, allow_abbrev=False, **kwargs)
        self.add_argument(
            "--debug",
            action="store_true",
            help="show the traceback of a failure (also BATSIM_DEBUG=1)",
        )

    def error(self, message: str):  # noqa: D102 - argparse's hook
        self.exit(2, f"{self.prog}: error: {message} (see --help)\n")

    def parse_args(self, args=None, namespace=None):  # noqa: D102
        argv = _join_negative_values(self, args)
        for action in self._actions:
            given = [t for t in argv if t.split("=", 1)[0] in action.option_strings]
            if len(given) > 1 and action.dest != "help":
                self.error(
                    f"{action.option_strings[-1]} given {len(given)} times "
                    f"({', '.join(given)}); allowed: once (several engines or checks: "
                    "one comma-separated list)"
                )
        parsed = super().parse_args(argv, namespace)
        if (complaint := quiet_error() or boundary.environment_error()) is not None:
            self.error(complaint)
        return parsed


#: What every command's exit code means (its --help ends with it).
EXIT_CODES = (
    "exit codes: 0 done; 1 a failure, told in one line (--debug: its traceback); 2 a "
    "bad option or input file, refused before any work; 130 interrupted (Ctrl-C), "
    "143, 129 or 152 stopped (SIGTERM, SIGHUP, SIGXCPU): earlier files left as they "
    "were; 141 its output pipe closed"
)


def summary(doc: str | None) -> str:
    """A docstring's first paragraph, in one line (a command's --help description); '' where
    Python dropped its docstrings (PYTHONOPTIMIZE=2)."""
    return " ".join((doc or "").strip().split("\n\n")[0].split())


def _join_negative_values(parser: argparse.ArgumentParser, argv):
    """['--dt', '-1e-5'] -> ['--dt=-1e-5'] for options taking one value: argparse would take
    '-1e-5' for an option (it only recognizes plain negative numbers like -1 or -0.5)."""
    argv = list(sys.argv[1:] if argv is None else argv)
    single = {
        s for a in parser._actions if a.nargs is None and a.option_strings for s in a.option_strings
    }
    out, i = [], 0
    while i < len(argv):
        tok = argv[i]
        if (
            tok in single
            and i + 1 < len(argv)
            and argv[i + 1].startswith("-")
            and _is_number(argv[i + 1])
        ):
            out.append(f"{tok}={argv[i + 1]}")
            i += 2
            continue
        out.append(tok)
        i += 1
    return out


def _is_number(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True


# -- option types: each raises ArgumentTypeError naming the value and what is allowed --------


def number(
    lo: float = -math.inf, hi: float = math.inf, *, lo_open: bool = False, unit: str = ""
) -> Callable[[str], float]:
    """A finite float in [lo, hi] (lo excluded with lo_open)."""

    def parse(text: str) -> float:
        try:
            x = float(text)
        except ValueError:
            x = math.nan
        ok = math.isfinite(x) and (x > lo if lo_open else x >= lo) and x <= hi
        if not ok:
            low = f"> {lo:g}" if lo_open else f">= {lo:g}"
            span = low if hi == math.inf else f"{low} and <= {hi:g}"
            span = "" if (lo, hi) == (-math.inf, math.inf) else span
            raise argparse.ArgumentTypeError(
                f"{text!r} is not allowed; allowed: a finite "
                f"number {span}{' ' + unit if unit else ''}".replace("  ", " ").rstrip()
            )
        return x

    return parse


def integer(lo: int, hi: int) -> Callable[[str], int]:
    """An integer in [lo, hi], written as one (42) or as a whole number in a float's way (1e3,
    as the help writes large ranges)."""

    def parse(text: str) -> int:
        try:
            n = int(text)
        except ValueError:
            try:
                x = float(text)
            except ValueError:
                x = math.nan
            n = int(x) if math.isfinite(x) and x.is_integer() else None
        if n is None or not lo <= n <= hi:
            raise argparse.ArgumentTypeError(
                f"{text!r} is not allowed; allowed: an integer {lo}..{hi}"
            )
        return n

    return parse


def engines_arg(value: str) -> tuple[str, ...]:
    """``all`` (every installed engine; each missing one named on stderr with its install hint)
    or a comma-separated list of registered engine names, as a tuple."""
    known = adapters.names()
    if value == "all":
        for hint in adapters.missing().values():
            print(f"skipped: {hint}", file=sys.stderr)
        for name, why in adapters.broken().items():
            print(f"skipped: broken plug-in {name!r}: {why}", file=sys.stderr)
        return adapters.available()
    picked = tuple(dict.fromkeys(v.strip() for v in value.split(",") if v.strip()))
    for name in picked:
        if name in adapters.broken() and name not in known:
            raise argparse.ArgumentTypeError(
                f"{name!r} is a broken plug-in: {adapters.broken()[name]}"
            )
    bad = [v for v in picked if v not in known]
    if bad or not picked:
        raise argparse.ArgumentTypeError(
            f"{value!r}: {bad[0] if bad else 'no engine'} is not an engine; allowed: all, or a "
            f"comma-separated list of {', '.join(known)}"
        )
    for name in picked:  # found or not, without importing it
        if name in adapters.missing():
            raise argparse.ArgumentTypeError(adapters.missing()[name])
    return picked


def stem_arg(value: str) -> str:
    """A plain file stem: letters, digits and ._=+,- only, no path."""
    if not STEM.match(value) or value in (".", ".."):
        raise argparse.ArgumentTypeError(
            f"{value!r} is not a plain name; allowed: ASCII letters, digits and . _ = + , - (no "
            "slashes, at most 100 characters, not starting with a dot)"
        )
    return value


def resolved_path(value: str) -> Path:
    """``value`` as an absolute path, or an ArgumentTypeError naming it: empty, unresolvable
    (~nosuchuser, a loop of links) or with a name longer than the filesystem allows."""
    if not value.strip():
        raise argparse.ArgumentTypeError(
            f"{value!r} is not a directory; allowed: a directory's path"
        )
    try:
        path = Path(value).expanduser().resolve()
    except (RuntimeError, OSError) as err:  # ~nosuchuser, a loop of links
        raise argparse.ArgumentTypeError(
            f"{value!r} cannot be resolved ({err}); allowed: a directory's path"
        ) from None
    long = [part for part in path.parts if len(os.fsencode(part)) > NAME_MAX]
    if long:
        raise argparse.ArgumentTypeError(
            f"{value!r}: a name of {len(os.fsencode(long[0]))} bytes; "
            f"allowed: names of at most {NAME_MAX} bytes"
        )
    return path


def directory_arg(value: str) -> Path:
    """A directory that exists or can be made, writable (tried, not assumed: a root user's
    os.access says yes to /proc), outside results/."""
    path = resolved_path(value)
    if path == RESULTS or RESULTS in path.parents:
        raise argparse.ArgumentTypeError(
            f"{value!r} is inside results/, which only `python -m experiments.baselines` "
            "writes; allowed: any other directory (default runs/)"
        )
    probe = path
    while not probe.exists():
        probe = probe.parent
    if not probe.is_dir():
        raise argparse.ArgumentTypeError(f"{value!r}: {probe} is a file; allowed: a directory")
    try:
        shutil.rmtree(tempfile.mkdtemp(dir=probe, prefix=".batsim-probe-"))
    except OSError as err:
        raise argparse.ArgumentTypeError(
            f"{value!r}: cannot create files in {probe} ({err.strerror or type(err).__name__})"
            "; allowed: a directory you can write to"
        ) from None
    return path


def scheduler_arg(value: str) -> str:
    """'local', or the address of a Dask scheduler that answers now (within
    ``runner.CONNECT_TIMEOUT_S``): refused at once otherwise, whatever the job's size."""
    if value == "local":
        return value
    try:
        _runner.connect(value).close()
    except (OSError, ValueError, TypeError) as err:
        raise argparse.ArgumentTypeError(
            f"{value!r}: {err}; allowed: 'local', or the address "
            "of a running scheduler (tcp://host:8786)"
        ) from None
    return value


# -- the shared options ---------------------------------------------------------------------


def add_engine(p: argparse.ArgumentParser, default: str = "all") -> None:
    # a str default is converted by engines_arg only when --engine is not given
    broken = "".join(
        f"; broken plug-in {n!r} left out ({why})" for n, why in adapters.broken().items()
    )
    p.add_argument(
        "--engine",
        type=engines_arg,
        default=default,
        metavar="NAME[,NAME...]|all",
        help=f"engines to run (default {default}); registered: "
        f"{', '.join(adapters.names())}{broken.replace('%', '%%')}",
    )


def add_runner(p: argparse.ArgumentParser) -> None:
    p.add_argument(
        "--workers",
        type=integer(1, MAX_WORKERS),
        default=1,
        metavar="N",
        help="local processes to spread impacts over (used when the work pays for them)",
    )
    p.add_argument(
        "--scheduler",
        type=scheduler_arg,
        default=None,
        metavar="ADDRESS",
        help="run impacts on a Dask cluster: its scheduler address (tcp://host:8786) "
        "or 'local' for a LocalCluster of --workers processes",
    )


def add_output(p: argparse.ArgumentParser) -> None:
    p.add_argument(
        "--out",
        type=directory_arg,
        default=RUNS,
        metavar="DIR",
        help="where runs go (default runs/, which git ignores)",
    )
    p.add_argument(
        "--name",
        type=stem_arg,
        default=None,
        metavar="STEM",
        help="the run's directory name (default: the experiment and every option "
        "that differs from its default, or a short hash of them)",
    )
    p.add_argument("--force", action="store_true", help="replace an existing run of that name")


def main_guard(run: Callable[[], int]) -> int:
    """Run a command's body: Ctrl-C (anywhere, engine callbacks included), SIGTERM or SIGHUP
    stops it (``boundary.stopping``; the command's ``boundary.entry`` says so and exits 130,
    143 or 129), and every earlier file is left as it was, since nothing is renamed into place
    before the end; what libraries say goes to the run's manifest."""
    with boundary.stopping(), library_messages_kept():
        return run()


@contextlib.contextmanager
def library_messages_kept():
    """Libraries' warnings and the errors raised inside engine callbacks (which Python would
    print as "Exception ignored ...", a Ctrl-C's included) go to the run's manifest
    (``runs.library_messages``), not to the user's terminal."""
    hook = sys.unraisablehook

    def keep(unraisable) -> None:
        if not isinstance(unraisable.exc_value, KeyboardInterrupt):  # the flag stops the run
            runs.UNRAISABLE.append(
                f"{type(unraisable.exc_value).__name__} in "
                f"{unraisable.object!r}: {unraisable.exc_value}"
            )

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("default")  # each warning once per place: a hot loop adds none
        runs.UNRAISABLE.clear()
        runs.WARNINGS = caught
        sys.unraisablehook = keep
        try:
            yield
        finally:
            sys.unraisablehook = hook
            runs.WARNINGS = []


@dataclass(frozen=True, kw_only=True)
class Command:
    """A study run from the command line: ``python -m experiments.<name>``.

    ``produce(args)`` returns the run's files (name -> bytes) and the text to print, and may
    add the exit code (a verdict: 1 when a check the command makes failed; the files are kept);
    ``options(parser)`` adds the study's own options; ``check(parser, args)`` refuses option
    combinations before any work (``parser.error``); ``estimate(args)``, the run's expected
    wall time (s), is said before the work when it is long. The shared options come with
    ``engines``, ``runner`` and ``output``; ``quick`` is the help of a --quick flag, if the study
    has one.
    """

    name: str
    doc: str | None
    produce: Callable[[argparse.Namespace], tuple]
    options: Callable[[argparse.ArgumentParser], None] | None = None
    check: Callable[[argparse.ArgumentParser, argparse.Namespace], None] | None = None
    estimate: Callable[[argparse.Namespace], float] | None = None
    quick: str | None = None
    engines: bool = True
    runner: bool = True
    output: bool = True

    def parser(self) -> Parser:
        """The command's parser: its own options, then the shared ones."""
        p = Parser(
            prog=f"python -m experiments.{self.name}",
            description=summary(self.doc),
            epilog=EXIT_CODES,
        )
        if self.quick:
            p.add_argument("--quick", action="store_true", help=self.quick)
        if self.options:
            self.options(p)
        if self.engines:
            add_engine(p)
        if self.runner:
            add_runner(p)
        if self.output:
            add_output(p)
        return p

    def main(self, argv: list[str] | None = None) -> int:
        """Parse and check every option, pick the run directory, then produce the files (and
        the text to print) and publish them as a whole; behind the error boundary
        (``boundary.entry``)."""
        return boundary.entry(self._main, f"python -m experiments.{self.name}")(argv)

    def _main(self, argv: list[str] | None) -> int:
        p = self.parser()
        args = p.parse_args(argv)
        if self.check:
            self.check(p, args)
        target = run_dir(p, args, self.name)
        expected_s = self.estimate(args) if self.estimate else 0.0
        if expected_s >= SAY_ESTIMATE_S and not runs.quiet():
            print(f"{self.name}: estimated about {duration(expected_s)}", file=sys.stderr)

        def body() -> int:
            t0 = time.perf_counter()
            files, text, *code = self.produce(args)  # a verdict's exit code may follow
            publish(target, files)
            if text:
                print(text)
            print(f"{self.name}: {time.perf_counter() - t0:.1f} s -> {shown(target)}/")
            return code[0] if code else 0

        return main_guard(body)


def runner(args: argparse.Namespace, progress: Progress | None = None) -> _runner.Runner:
    """The runner the options ask for."""
    return _runner.Runner(workers=args.workers, scheduler=args.scheduler, progress=progress)
