"""Where a run's files go and how they get there, and its progress on stderr.

A run goes to ``runs/<experiment>-<every option that differs from its default>`` (a short hash
when that is too long), never over another run (``.2``, ``.3`` ...; ``--force`` replaces);
its files are written into a new directory beside it and renamed into place together, so an
interrupted run leaves nothing behind. ``results/`` is written only by
``python -m experiments.baselines``.
"""

from __future__ import annotations

import argparse
import hashlib
import json
import math
import os
import re
import shutil
import sys
import tempfile
import time
from pathlib import Path

import adapters

from .io import ROOT, make_public

RUNS = ROOT / "runs"
RESULTS = ROOT / "results"
#: Options that say how or where a run goes, not what it computes: left out of run names.
NOT_IN_NAME = frozenset({"help", "out", "name", "force", "workers", "scheduler", "compare",
                         "budget_h"})
PROGRESS_EVERY_S = 5.0


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


#: BATSIM_QUIET's values (any case, spaces around ignored): whether progress is silenced.
QUIET_VALUES = {"1": True, "true": True, "yes": True, "0": False, "false": False, "no": False,
                "": False}


def quiet() -> bool:
    """No progress output (BATSIM_QUIET=1, as the tests set); an unknown value, which every
    command refuses first (``quiet_error``), counts as not quiet."""
    return QUIET_VALUES.get(os.environ.get("BATSIM_QUIET", "").strip().lower(), False)


def quiet_error() -> str | None:
    """The one-line complaint about BATSIM_QUIET's value, or None if it is allowed."""
    raw = os.environ.get("BATSIM_QUIET", "")
    if raw.strip().lower() in QUIET_VALUES:
        return None
    return (f"BATSIM_QUIET={raw!r} is not allowed; allowed: 1, true or yes (no progress), "
            "0, false, no or empty (progress)")


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
        elif not quiet():  # a log shows the work has begun (a batch may tick only at its end)
            print(f"{desc}: 0/{total} {unit}, started", file=sys.stderr, flush=True)

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
