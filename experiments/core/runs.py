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

from filelock import FileLock, Timeout

import adapters

from ..errors import UserError
from .io import ROOT, make_public

RUNS = ROOT / "runs"
RESULTS = ROOT / "results"
#: Options that say how or where a run goes, not what it computes: left out of run names.
NOT_IN_NAME = frozenset(
    {"help", "out", "name", "force", "workers", "scheduler", "compare", "budget_h"}
)
PROGRESS_EVERY_S = 5.0


def engine_label(engines: tuple[str, ...]) -> str:
    """'all' for every installed engine, else the names joined by '+' (for file names)."""
    return "all" if engines == adapters.available() else "+".join(engines)


def configuration(p: argparse.ArgumentParser, args: argparse.Namespace) -> dict:
    """Every option that decides what a run computes, with its value (for names and JSON)."""
    return {
        a.dest: _plain(getattr(args, a.dest))
        for a in p._actions
        if a.dest not in NOT_IN_NAME and a.dest != argparse.SUPPRESS
    }


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
        parts.append(
            key
            if value is True
            else f"{key}={value:g}"
            if isinstance(value, float)
            else f"{key}={value}"
        )
    label = re.sub(r"[^A-Za-z0-9._=+,-]", "", "_".join(parts)) or "defaults"
    if len(label) > 60:
        label = hashlib.sha1(json.dumps(conf, sort_keys=True, default=str).encode()).hexdigest()[:8]
    return f"{experiment}-{label}"


def run_dir(p: argparse.ArgumentParser, args: argparse.Namespace, experiment: str) -> Path:
    """Where this run's files go (not created yet), held for this process until it publishes
    (``reserve``). An explicit --name that exists is an error without --force, and --force
    replaces only a run (a directory with its MANIFEST); a default name that exists or that
    another run is writing gets the first free .2, .3 ... suffix. Temporary directories of
    runs that died are swept first."""
    sweep_stale(args.out)
    if args.name is not None:
        target = args.out / args.name
        if target.exists() and not args.force:  # (refused before anything is made)
            p.error(
                f"--name {args.name!r}: {target} exists; allowed: --force to replace it, or "
                "another --name"
            )
        if not reserve(target):
            p.error(
                f"--name {args.name!r}: another run is writing {target} now; allowed: "
                "another --name, or wait for it"
            )
        # (looked at once held: a run that published just before cannot be replaced unasked)
        if target.exists() and not args.force:
            release(target)
            p.error(
                f"--name {args.name!r}: {target} exists; allowed: --force to replace it, or "
                "another --name"
            )
        if target.exists() and (foreign := not_a_run(target)):
            release(target)
            p.error(
                f"--force --name {args.name!r}: {target} is not a run ({foreign}); "
                "allowed: another --name (--force replaces only a run)"
            )
        return target
    base = args.out / run_name(p, args, experiment)
    if args.force and reserve(base):
        if not base.exists() or not not_a_run(base):
            return base
        release(base)
    n = 1
    while True:
        target = base if n == 1 else args.out / f"{base.name}.{n}"
        if not target.exists() and reserve(target):
            if not target.exists():
                return target
            release(target)
        n += 1


#: Each run directory holds this file: the command, its files' digests, what libraries said.
MANIFEST = "run.json"
#: The folder a run directory's parent holds for the harness alone: runs being written
#: (``<name>.<random>.tmp``), a run being replaced (``<name>.old-<pid>``) and each name's lock
#: (``<name>.lock``). Nothing outside it but finished runs is made, and nothing outside it is
#: ever deleted, whatever its name.
STAGING = ".batsim"
#: The file that marks a staging folder as the harness's (one a user made is left alone).
STAGING_MARK = "MADE_BY_BATSIM"
#: The locks this process holds on the run directories it will write (target -> lock).
_HELD: dict[Path, FileLock] = {}
_STAGED = re.compile(r"^(?P<name>.+)\.(?:[A-Za-z0-9_]{8}\.tmp|old-\d+)$")


def staging(out: Path) -> Path:
    """``out``'s staging folder (``STAGING``), made if need be; UserError if it cannot be, or
    if a folder of that name there is not the harness's."""
    folder = out / STAGING
    if folder.exists() and not folder.is_dir():
        raise UserError(
            f"{folder} is a file, not the harness's staging folder; allowed: move "
            "it away, or choose another --out"
        )
    try:
        folder.mkdir(parents=True, exist_ok=True)
        mark = folder / STAGING_MARK
        if not mark.exists() and any(folder.iterdir()):
            raise UserError(
                f"{folder} exists and is not the harness's (no {STAGING_MARK}); "
                "allowed: move it away, or choose another --out"
            )
        mark.touch()
    except OSError as err:
        raise UserError(
            f"cannot prepare {folder} ({err.strerror or err}); allowed: an --out you can write to"
        ) from None
    return folder


def _lock(target: Path) -> FileLock:
    """The lock on a run directory: a file in the staging folder beside it, so that every run
    into that folder sees it, whatever its TMPDIR."""
    return FileLock(staging(target.parent) / f"{target.name}.lock")


def reserve(target: Path) -> bool:
    """Hold ``target`` for this process (False if another live process holds it). The lock
    goes with the process: a run that dies, even killed, holds nothing."""
    if target in _HELD:
        return True
    lock = _lock(target)
    try:
        lock.acquire(timeout=0)
    except Timeout:
        return False
    except OSError as err:
        raise UserError(
            f"cannot lock {target} ({err.strerror or err}); allowed: an --out you can write to"
        ) from None
    _HELD[target] = lock
    return True


def release(target: Path) -> None:
    """Give up ``target`` (after publishing it)."""
    lock = _HELD.pop(target, None)
    if lock is not None:
        lock.release()


def not_a_run(path: Path) -> str:
    """Why ``path`` is not a run that --force may replace ('' if it is one): a run is a
    directory holding its MANIFEST and exactly the files the MANIFEST lists, so that replacing
    it deletes nothing a user put there."""
    if path.is_symlink() or not path.is_dir():
        return "not a directory"
    try:
        listed = json.loads((path / MANIFEST).read_text())["files"]
        held = {p.name for p in path.iterdir()}
    except (OSError, ValueError, KeyError, TypeError) as err:
        return f"no readable {MANIFEST} ({type(err).__name__})"
    extra = sorted(held - set(listed) - {MANIFEST})
    return f"it holds {', '.join(extra[:3])}, which its {MANIFEST} does not list" if extra else ""


def sweep_stale(out: Path) -> None:
    """In ``out``'s staging folder, what runs that died left: a half-written run is removed,
    a run moved aside to be replaced is put back where nothing replaced it; only for names no
    live process holds. Nothing else in ``out`` is looked at."""
    folder = out / STAGING
    if not (folder / STAGING_MARK).is_file():
        return
    for path in folder.iterdir():
        m = _STAGED.match(path.name)
        if m is None or not path.is_dir():
            continue
        target = out / m["name"]
        if reserve(target):
            if path.name.startswith(f"{m['name']}.old-") and not target.exists():
                os.replace(path, target)  # died between its two renames: the old run is back
            else:
                shutil.rmtree(path, ignore_errors=True)
            release(target)


def publish(target: Path, files: dict[str, bytes]) -> Path:
    """Write a run's files into ``target`` as a whole: all of them (and the MANIFEST) into a
    new directory in the staging folder, then renamed into place (an existing run there is
    moved aside first, and deleted only once the new one is in place); ``target`` is
    released."""
    folder = staging(target.parent)
    reserve(target)
    files = {**files, MANIFEST: manifest(files)}
    tmp = Path(tempfile.mkdtemp(dir=folder, prefix=f"{target.name}.", suffix=".tmp"))
    old = None
    try:
        for name, data in files.items():
            (tmp / name).write_bytes(data)
        make_public(tmp, directory=True)
        if target.exists():
            old = folder / f"{target.name}.old-{os.getpid()}"
            os.replace(target, old)
        os.replace(tmp, target)
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        if old is not None and not target.exists():
            os.replace(old, target)
        raise
    finally:
        release(target)
    if old is not None:
        shutil.rmtree(old, ignore_errors=True)
    return target


def manifest(files: dict[str, bytes]) -> bytes:
    """The run's MANIFEST: the command line, each file's SHA-256, and what libraries said while
    it ran (warnings, errors raised inside engine callbacks: ``core.cli.main_guard``)."""
    import datetime

    return json.dumps(
        {
            "command": " ".join([Path(sys.argv[0]).name, *sys.argv[1:]]),
            "date_utc": datetime.datetime.now(datetime.UTC).isoformat(timespec="seconds"),
            "files": {
                name: hashlib.sha256(data).hexdigest() for name, data in sorted(files.items())
            },
            "library_messages": library_messages(),
            "broken_plugins": dict(adapters.broken()),
        },
        indent=1,
    ).encode()


#: Errors raised inside engine callbacks and the warnings caught during this run
#: (``core.cli.library_messages_kept`` fills them).
UNRAISABLE: list[str] = []
WARNINGS: list = []


def library_messages() -> list[str]:
    """What libraries said during this run, each message once."""
    said = [
        f"{w.category.__name__}: {w.message} ({Path(w.filename).name}:{w.lineno})" for w in WARNINGS
    ]
    return list(dict.fromkeys([*UNRAISABLE, *said]))


def shown(path: Path) -> str:
    """A path as the user would type it from the project root."""
    return str(path.relative_to(ROOT)) if path.is_relative_to(ROOT) else str(path)


#: BATSIM_QUIET's values (any case, spaces around ignored): whether progress is silenced.
QUIET_VALUES = {
    "1": True,
    "true": True,
    "yes": True,
    "0": False,
    "false": False,
    "no": False,
    "": False,
}


def quiet() -> bool:
    """No progress output (BATSIM_QUIET=1, as the tests set); an unknown value, which every
    command refuses first (``quiet_error``), counts as not quiet."""
    return QUIET_VALUES.get(os.environ.get("BATSIM_QUIET", "").strip().lower(), False)


def quiet_error() -> str | None:
    """The one-line complaint about BATSIM_QUIET's value, or None if it is allowed."""
    raw = os.environ.get("BATSIM_QUIET", "")
    if raw.strip().lower() in QUIET_VALUES:
        return None
    return (
        f"BATSIM_QUIET={raw!r} is not allowed; allowed: 1, true or yes (no progress), "
        "0, false, no or empty (progress)"
    )


class Progress:
    """Progress of a count on stderr: a bar on a terminal, else a line every few seconds, to
    pass to a Runner as ``progress``."""

    def __init__(self, total: int, desc: str, unit: str = "impacts") -> None:
        self.total, self.desc, self.unit = total, desc, unit
        self.done = 0
        self.t0 = self.last = time.perf_counter()
        self.first: tuple[float, int] | None = None
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
        if self.first is None:  # what came before the first tick (start-up, a compile) is
            self.first = (now, self.done)  # not the rate of the work: it is left out of it
        if quiet() or now - self.last < PROGRESS_EVERY_S:
            return
        self.last = now
        frac = self.done / self.total if self.total else 1.0
        t1, n1 = self.first
        rate = (self.done - n1) / (now - t1) if self.done > n1 and now > t1 else math.nan
        left = f", about {(self.total - self.done) / rate:.0f} s left" if rate > 0 else ""
        print(
            f"{self.desc}: {self.done}/{self.total} {self.unit} ({frac:.0%}), "
            f"{now - self.t0:.0f} s{left}",
            file=sys.stderr,
            flush=True,
        )

    def __enter__(self) -> Progress:
        return self

    def __exit__(self, *exc) -> None:
        if self.bar is not None:
            self.bar.close()
