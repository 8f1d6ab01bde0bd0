"""Command-line options every experiment spells the same way, and progress on stderr.

    --engine NAME[,NAME...]|all   engines from the registry (built-ins and plug-ins)
    --out DIR                     where the files go
    --workers N / --scheduler     how the impacts run (experiments._runner)
"""

from __future__ import annotations

import argparse
from pathlib import Path

from tqdm import tqdm

import adapters

from . import _runner

MAX_WORKERS = 64


def engines_arg(value: str) -> tuple[str, ...]:
    """``all`` or a comma-separated list of registered engine names, as a tuple."""
    known = adapters.names()
    if value == "all":
        return known
    picked = tuple(dict.fromkeys(v.strip() for v in value.split(",") if v.strip()))
    bad = [v for v in picked if v not in known]
    if bad or not picked:
        raise argparse.ArgumentTypeError(
            f"--engine {value!r}: {bad[0] if bad else 'no engine'} is not an engine; allowed: "
            f"all, or a comma-separated list of {', '.join(known)}")
    return picked


def workers_arg(value: str) -> int:
    try:
        n = int(value)
    except ValueError:
        n = 0
    if not 1 <= n <= MAX_WORKERS:
        raise argparse.ArgumentTypeError(f"--workers {value!r} is out of range; allowed: an "
                                         f"integer 1..{MAX_WORKERS}")
    return n


def add_engine(p: argparse.ArgumentParser, default: str = "all") -> None:
    p.add_argument("--engine", type=engines_arg, default=engines_arg(default),
                   metavar="NAME[,NAME...]|all",
                   help=f"engines to run (default {default}); registered: "
                        f"{', '.join(adapters.names())}")


def add_runner(p: argparse.ArgumentParser) -> None:
    p.add_argument("--workers", type=workers_arg, default=1, metavar="N",
                   help="local processes to spread impacts over (used when the work pays for "
                        "them)")
    p.add_argument("--scheduler", default=None, metavar="ADDRESS",
                   help="run impacts on a Dask cluster: its scheduler address (tcp://host:8786) "
                        "or 'local' for a LocalCluster of --workers processes")


def add_out(p: argparse.ArgumentParser, default: Path) -> None:
    p.add_argument("--out", type=Path, default=default, metavar="DIR",
                   help=f"output directory (default {default})")


def engine_label(engines: tuple[str, ...]) -> str:
    """'all' for every registered engine, else the names joined by '+' (for file names)."""
    return "all" if engines == adapters.names() else "+".join(engines)


class Progress:
    """A progress bar on stderr (shown on a terminal), to pass to a Runner as ``progress``."""

    def __init__(self, total: int, desc: str) -> None:
        self.bar = tqdm(total=total, desc=desc, unit="impact", disable=None, leave=False)

    def __call__(self, n: int) -> None:
        self.bar.update(n)

    def __enter__(self) -> Progress:
        return self

    def __exit__(self, *exc) -> None:
        self.bar.close()


def runner(args: argparse.Namespace, progress: Progress | None = None) -> _runner.Runner:
    """The runner the options ask for."""
    return _runner.Runner(workers=args.workers, scheduler=args.scheduler, progress=progress)
