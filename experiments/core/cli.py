"""The command-line convention every experiment follows, and where its files go.

Options spelled the same everywhere:
    --engine NAME[,NAME...]|all   engines from the registry (built-ins and plug-ins)
    --workers N / --scheduler     how the impacts run (experiments.core.runner)
    --out DIR  --name STEM  --force
                                  a run's files go to DIR/STEM (default runs/<experiment>-<the
                                  options that differ from the defaults>); an existing run is
                                  never overwritten (a default name gets a .2, .3 ... suffix;
                                  --force replaces). results/ is written only by
                                  python -m experiments.baselines.
Every option is checked before any simulation runs or any file is touched: a bad one exits 2
with one line naming the option, the value and what is allowed. --help only prints. Progress
goes to stderr (a bar on a terminal, a line every few seconds otherwise; none with
BATSIM_QUIET=1). Ctrl-C stops a run with exit 130 and leaves every earlier file as it was.
"""

from __future__ import annotations

import argparse
import hashlib
import json
import math
import os
import re
import shutil
import signal
import sys
import tempfile
import threading
import time
from pathlib import Path
from typing import Callable

import adapters

from . import fire, runner as _runner
from .io import ROOT, make_public

RUNS = ROOT / "runs"
RESULTS = ROOT / "results"
MAX_WORKERS = 64
#: Options that say how or where a run goes, not what it computes: left out of run names.
NOT_IN_NAME = frozenset({"help", "out", "name", "force", "workers", "scheduler", "compare"})
STEM = re.compile(r"^[A-Za-z0-9][A-Za-z0-9._=+,-]{0,99}$")
PROGRESS_EVERY_S = 5.0


class Parser(argparse.ArgumentParser):
    """argparse with one-line errors (exit 2) and negative numbers accepted as values."""

    def error(self, message: str):  # noqa: D102 - argparse's hook
        self.exit(2, f"{self.prog}: error: {message} (see --help)\n")

    def parse_args(self, args=None, namespace=None):  # noqa: D102
        return super().parse_args(_join_negative_values(self, args), namespace)


def _join_negative_values(parser: argparse.ArgumentParser, argv):
    """['--dt', '-1e-5'] -> ['--dt=-1e-5'] for options taking one value: argparse would take
    '-1e-5' for an option (it only recognizes plain negative numbers like -1 or -0.5)."""
    argv = list(sys.argv[1:] if argv is None else argv)
    single = {s for a in parser._actions if a.nargs is None and a.option_strings
              for s in a.option_strings}
    out, i = [], 0
    while i < len(argv):
        tok = argv[i]
        if tok in single and i + 1 < len(argv) and argv[i + 1].startswith("-") \
                and _is_number(argv[i + 1]):
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

def number(lo: float = -math.inf, hi: float = math.inf, *, lo_open: bool = False,
           unit: str = "") -> Callable[[str], float]:
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
            raise argparse.ArgumentTypeError(f"{text!r} is not allowed; allowed: a number "
                                             f"{span}{' ' + unit if unit else ''}")
        return x
    return parse


def integer(lo: int, hi: int) -> Callable[[str], int]:
    """An integer in [lo, hi]."""
    def parse(text: str) -> int:
        try:
            n = int(text)
        except ValueError:
            n = None
        if n is None or not lo <= n <= hi:
            raise argparse.ArgumentTypeError(f"{text!r} is not allowed; allowed: an integer "
                                             f"{lo}..{hi}")
        return n
    return parse


def engines_arg(value: str) -> tuple[str, ...]:
    """``all`` (every installed engine; each missing one named on stderr with its install hint)
    or a comma-separated list of registered engine names, as a tuple."""
    known = adapters.names()
    if value == "all":
        for hint in adapters.missing().values():
            print(f"skipped: {hint}", file=sys.stderr)
        return adapters.available()
    picked = tuple(dict.fromkeys(v.strip() for v in value.split(",") if v.strip()))
    bad = [v for v in picked if v not in known]
    if bad or not picked:
        raise argparse.ArgumentTypeError(
            f"{value!r}: {bad[0] if bad else 'no engine'} is not an engine; allowed: all, or a "
            f"comma-separated list of {', '.join(known)}")
    for name in picked:
        try:
            adapters.engine_class(name)
        except adapters.EngineNotInstalled as err:
            raise argparse.ArgumentTypeError(str(err)) from None
    return picked


def stem_arg(value: str) -> str:
    """A plain file stem: letters, digits and ._=+,- only, no path."""
    if not STEM.match(value) or value in (".", ".."):
        raise argparse.ArgumentTypeError(
            f"{value!r} is not a plain name; allowed: letters, digits and . _ = + , - (no "
            "slashes, at most 100 characters, not starting with a dot)")
    return value


def directory_arg(value: str) -> Path:
    """A directory that exists or can be made, writable, outside results/."""
    path = Path(value).expanduser().resolve()
    if path == RESULTS or RESULTS in path.parents:
        raise argparse.ArgumentTypeError(
            f"{value!r} is inside results/, which only `python -m experiments.baselines` "
            "writes; allowed: any other directory (default runs/)")
    probe = path
    while not probe.exists():
        probe = probe.parent
    if not probe.is_dir():
        raise argparse.ArgumentTypeError(f"{value!r}: {probe} is a file; allowed: a directory")
    if not os.access(probe, os.W_OK | os.X_OK):
        raise argparse.ArgumentTypeError(f"{value!r}: {probe} is not writable; allowed: a "
                                         "directory you can write to")
    return path


# -- the shared options ---------------------------------------------------------------------

def add_engine(p: argparse.ArgumentParser, default: str = "all") -> None:
    # a str default is converted by engines_arg only when --engine is not given
    p.add_argument("--engine", type=engines_arg, default=default,
                   metavar="NAME[,NAME...]|all",
                   help=f"engines to run (default {default}); registered: "
                        f"{', '.join(adapters.names())}")


def add_runner(p: argparse.ArgumentParser) -> None:
    p.add_argument("--workers", type=integer(1, MAX_WORKERS), default=1, metavar="N",
                   help="local processes to spread impacts over (used when the work pays for "
                        "them)")
    p.add_argument("--scheduler", default=None, metavar="ADDRESS",
                   help="run impacts on a Dask cluster: its scheduler address (tcp://host:8786) "
                        "or 'local' for a LocalCluster of --workers processes")


def add_output(p: argparse.ArgumentParser) -> None:
    p.add_argument("--out", type=directory_arg, default=RUNS, metavar="DIR",
                   help="where runs go (default runs/, which git ignores)")
    p.add_argument("--name", type=stem_arg, default=None, metavar="STEM",
                   help="the run's directory name (default: the experiment and every option "
                        "that differs from its default, or a short hash of them)")
    p.add_argument("--force", action="store_true", help="replace an existing run of that name")


def engine_label(engines: tuple[str, ...]) -> str:
    """'all' for every installed engine, else the names joined by '+' (for file names)."""
    return "all" if engines == adapters.available() else "+".join(engines)


def configuration(p: argparse.ArgumentParser, args: argparse.Namespace) -> dict:
    """Every option that decides what a run computes, with its value (for names and JSON)."""
    return {a.dest: _plain(getattr(args, a.dest)) for a in p._actions
            if a.dest not in NOT_IN_NAME and a.dest != argparse.SUPPRESS}


def _plain(v):
    if isinstance(v, tuple) and v == adapters.available():
        return "all"
    if isinstance(v, (tuple, list)):
        return ",".join(map(str, v))
    return v.as_posix() if isinstance(v, Path) else v


def run_name(p: argparse.ArgumentParser, args: argparse.Namespace, experiment: str) -> str:
    """<experiment>-<option=value...> for the options that differ from their defaults, or
    <experiment>-<8-hex hash of the whole configuration> when that is too long."""
    conf = configuration(p, args)
    defaults = {a.dest: _plain(a.default) for a in p._actions if a.dest in conf}
    parts = []
    for key, value in conf.items():
        if value == defaults[key]:
            continue
        parts.append(key if value is True else f"{key}={value:g}" if isinstance(value, float)
                     else f"{key}={value}")
    label = re.sub(r"[^A-Za-z0-9._=+,-]", "", "_".join(parts)) or "defaults"
    if len(label) > 60:
        label = hashlib.sha1(json.dumps(conf, sort_keys=True, default=str).encode()).hexdigest()[:8]
    return f"{experiment}-{label}"


def run_dir(p: argparse.ArgumentParser, args: argparse.Namespace, experiment: str) -> Path:
    """Where this run's files go (not created yet). An explicit --name that exists is an error
    without --force; a default name that exists gets the first free .2, .3 ... suffix."""
    if args.name is not None:
        target = args.out / args.name
        if target.exists() and not args.force:
            p.error(f"--name {args.name!r}: {target} exists; allowed: --force to replace it, or "
                    "another --name")
        return target
    base = args.out / run_name(p, args, experiment)
    if args.force or not base.exists():
        return base
    n = 2
    while (args.out / f"{base.name}.{n}").exists():
        n += 1
    return args.out / f"{base.name}.{n}"


def publish(target: Path, files: dict[str, bytes]) -> Path:
    """Write a run's files into ``target`` as a whole: all of them into a new directory beside
    it, then renamed into place (an existing run there is replaced only after that)."""
    target.parent.mkdir(parents=True, exist_ok=True)
    tmp = Path(tempfile.mkdtemp(dir=target.parent, prefix=f".{target.name}.", suffix=".tmp"))
    old = None
    try:
        for name, data in files.items():
            (tmp / name).write_bytes(data)
        make_public(tmp, directory=True)
        if target.exists():
            old = target.with_name(f".{target.name}.old-{os.getpid()}")
            os.replace(target, old)
        os.replace(tmp, target)
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        if old is not None and not target.exists():
            os.replace(old, target)
        raise
    if old is not None:
        shutil.rmtree(old, ignore_errors=True)
    return target


def shown(path: Path) -> str:
    """A path as the user would type it from the project root."""
    return str(path.relative_to(ROOT)) if path.is_relative_to(ROOT) else str(path)


def main_guard(run: Callable[[], int]) -> int:
    """Run a command's body; Ctrl-C (anywhere, engine callbacks included) exits 130 and leaves
    every earlier file as it was, since nothing is renamed into place before the end."""
    fire.INTERRUPTED.clear()
    previous = signal.getsignal(signal.SIGINT)
    in_main = threading.current_thread() is threading.main_thread()
    if in_main:
        signal.signal(signal.SIGINT, _on_sigint)
    try:
        return run()
    except KeyboardInterrupt:
        print("interrupted: nothing written, earlier results left as they were", file=sys.stderr)
        return 130
    finally:
        if in_main:
            signal.signal(signal.SIGINT, previous)


def _on_sigint(signum, frame) -> None:
    # Raised where the signal lands; if that is inside an engine's callback, which swallows it,
    # the flag stops the run when the impact is done.
    fire.INTERRUPTED.set()
    raise KeyboardInterrupt


def run_command(p: argparse.ArgumentParser, argv: list[str] | None, experiment: str,
                produce: Callable[[argparse.Namespace], tuple[dict[str, bytes], str]]) -> int:
    """The main of a study: parse and check every option, pick the run directory, then
    produce the files (and the text to print) and publish them as a whole."""
    args = p.parse_args(argv)
    target = run_dir(p, args, experiment)

    def body() -> int:
        t0 = time.perf_counter()
        files, text = produce(args)
        publish(target, files)
        if text:
            print(text)
        print(f"{experiment}: {time.perf_counter() - t0:.1f} s -> {shown(target)}/")
        return 0

    return main_guard(body)


# -- progress -------------------------------------------------------------------------------

def quiet() -> bool:
    """No progress output (BATSIM_QUIET=1, as the tests set)."""
    return os.environ.get("BATSIM_QUIET", "") not in ("", "0")


class Progress:
    """Progress of a count on stderr: a bar on a terminal, else a line every few seconds, to
    pass to a Runner as ``progress``."""

    def __init__(self, total: int, desc: str, unit: str = "impacts") -> None:
        self.total, self.desc, self.unit = total, desc, unit
        self.done = 0
        self.t0 = self.last = time.perf_counter()
        self.bar = None
        if not quiet() and sys.stderr.isatty():
            from tqdm import tqdm

            self.bar = tqdm(total=total, desc=desc, unit=unit.rstrip("s"), leave=False)

    def __call__(self, n: int) -> None:
        self.done += n
        if self.bar is not None:
            self.bar.update(n)
            return
        now = time.perf_counter()
        if quiet() or now - self.last < PROGRESS_EVERY_S:
            return
        self.last = now
        frac = self.done / self.total if self.total else 1.0
        left = (now - self.t0) * (1 - frac) / frac if frac > 0 else math.nan
        print(f"{self.desc}: {self.done}/{self.total} {self.unit} ({frac:.0%}), "
              f"{now - self.t0:.0f} s, about {left:.0f} s left", file=sys.stderr, flush=True)

    def __enter__(self) -> Progress:
        return self

    def __exit__(self, *exc) -> None:
        if self.bar is not None:
            self.bar.close()


def runner(args: argparse.Namespace, progress: Progress | None = None) -> _runner.Runner:
    """The runner the options ask for."""
    return _runner.Runner(workers=args.workers, scheduler=args.scheduler, progress=progress)
