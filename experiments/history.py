"""Each engine's agreement with theory, release by release.

    python -m experiments.history [--engine NAME[,NAME...]] [--versions V[,V...]|WHEEL]
                                  [--against V] [--cache DIR]

Every release (by default the spread its record lists, ``Install.history``) is installed by uv
in its own cached environment (``experiments.core.releases``) and judged there by this
checkout's code (``experiments.parts.history_probe``): the still, swing and hinged grids at the
reference profile, the swing at the engine's defaults, the conformance suite (the friction wall
among its checks), the defaults read back. A release that does not exist or has no wheel for
this Python is a row that says so (``not_installable``), as is one that could not be fetched
because the package index could not be reached (``index_unreachable``); one whose API the
adapter does not drive is ``unsupported``, with the reason. An environment found damaged in the
cache (its python or a distribution gone) is made again.

Between each release and the one before it, whatever moved is listed: a verdict lost or won, an
error that moved by more than its tolerance, a check that changed, a default that changed.
With --versions the last version named (a release, or a wheel's path: a candidate) is checked
against the one named before it, or, named alone, against the newest release of the spread:
exit 1 if it lost a verdict or a check, or an error grew past its tolerance; exit 1 too, the
check not made, where either release could not be judged (no environment, a probe that failed,
hung or judged nothing), said in one line on stderr, as is a run that judged no release at all.
A probe still running after a minute is said on stderr; it is stopped at PROBE_TIMEOUT_S.

Writes history.csv (a row per release and grid), history_rows.csv (every impact),
history_checks.csv, history.md, history.json and a chart per engine (history_<engine>.png).
"""

from __future__ import annotations

import argparse
import contextlib
import json
import os
import re
import signal
import subprocess
import sys
import tempfile
from pathlib import Path

import adapters

from .core import cli, inputs, releases, runs
from .core.cli import Command
from .core.io import ROOT
from .core.judge import Status
from .errors import BadInput
from .parts import history_probe, history_report

#: A release's state when uv could not reach the package index: nothing known of it.
UNREACHABLE = "index_unreachable"
#: The slowest probe of a release measured (s): the whole probe of mjx (its grids compile for
#: each size, then the conformance suite) took 50.5 s on a 2-core machine running another job,
#: 30 s of it in its grids' impacts; results/history_rows.csv puts the grids of its slowest
#: release at 24 s, of every other engine's under 14 s (pymunk's whole probe: 1.6 s).
PROBE_SLOWEST_S = 51.0
#: A probe is stopped past this (a row: probe_failed): 10x the slowest measured, for a slower
#: or busier machine, an older release that compiles slower, two probes sharing the cores.
PROBE_TIMEOUT_S = 10 * PROBE_SLOWEST_S
#: A probe still running after this is said on stderr, once, with its limit.
PROBE_NOTICE_S = 60.0
VERSION = re.compile(r"^[0-9][0-9A-Za-z.+!-]*$")


def versions_arg(value: str, option: str = "--versions") -> tuple[str, ...]:
    """Comma-separated versions, or paths of wheels (each checked: ``inputs.wheel``), each
    once."""
    picked = tuple(v.strip() for v in value.split(",") if v.strip())
    for v in picked:
        if v.endswith(".whl"):
            try:
                inputs.wheel(Path(v))
            except BadInput as err:
                raise argparse.ArgumentTypeError(str(err)) from None
        elif not VERSION.match(v):
            raise argparse.ArgumentTypeError(
                f"{option} {v!r} is not a version; allowed: versions like 3.2.7 or 4.1.0rc1, "
                "or the path of a .whl file, comma-separated"
            )
    if not picked:
        raise argparse.ArgumentTypeError(f"{option} names no version")
    twice = [v for i, v in enumerate(picked) if _same(v, picked[:i])]
    if twice:
        raise argparse.ArgumentTypeError(
            f"{option} names {twice[0]!r} twice; allowed: each release once"
        )
    return picked


def against_arg(value: str) -> str:
    """One version, or the path of a wheel: the release a candidate is checked against."""
    picked = tuple(v for v in value.split(",") if v.strip())
    picked = versions_arg(value, "--against") if len(picked) == 1 else picked
    if len(picked) != 1:
        raise argparse.ArgumentTypeError(
            f"--against {value!r} names {len(picked)} versions; allowed: one version (or a "
            "wheel's path), the release the candidate is checked against"
        )
    return picked[0]


def _same(version: str, others) -> bool:
    """Whether ``version`` is one of ``others``: the same version, or the same wheel's path."""
    return _key(version) in {_key(v) for v in others}


def _key(version: str) -> str:
    """A version, or a wheel's resolved path (as it was given where that cannot be told)."""
    try:
        return str(Path(version).resolve()) if version.endswith(".whl") else version
    except (OSError, RuntimeError):
        return version


CACHE = "a directory for the release environments (made if absent) that you can write to"


def cache_arg(value: str) -> Path:
    """--cache as an absolute path (each probe starts in a folder of its own), outside
    results/ (the environments are hundreds of MB; results/ is committed)."""
    if not value.strip():
        raise argparse.ArgumentTypeError(f"{value!r} is not a directory; allowed: {CACHE}")
    path = cli.resolved_path(value)
    if path == runs.RESULTS or runs.RESULTS in path.parents:
        raise argparse.ArgumentTypeError(
            f"{value!r} is inside results/, which only `python -m experiments.baselines` "
            f"writes; allowed: {CACHE}, outside results/"
        )
    return path


def _options(p: argparse.ArgumentParser) -> None:
    p.add_argument(
        "--versions",
        type=versions_arg,
        default=None,
        metavar="V[,V...]|WHEEL",
        help="these releases (or a local wheel) instead of each record's spread; the "
        "last is checked against the one before (exit 1 on a regression)",
    )
    p.add_argument(
        "--against",
        type=against_arg,
        default=None,
        metavar="V",
        help="with --versions: the one release the candidate is checked against "
        "(default: the version named before it, or the newest of the engine's "
        "spread)",
    )
    p.add_argument(
        "--cache",
        type=cache_arg,
        default=str(releases.DEFAULT_CACHE),
        metavar="DIR",
        help=f"where the environments are kept, outside results/ (default "
        f"{releases.DEFAULT_CACHE})",
    )


def _check(p: argparse.ArgumentParser, args: argparse.Namespace) -> None:
    if args.versions and len(args.engine) != 1:
        p.error(
            f"--versions names releases of one engine; --engine named {len(args.engine)}: "
            f"{', '.join(args.engine)}"
        )
    if (
        args.versions
        and len(args.versions) == 1
        and not args.against
        and not adapters.record(args.engine[0]).install.history
    ):
        p.error(
            f"--versions {args.versions[0]}: {args.engine[0]} lists no release to check it "
            "against (Install.history); allowed: add --against V, or name two versions"
        )
    if args.against and not args.versions:
        p.error("--against checks the candidate --versions names; allowed: add --versions")
    _check_cache(p, args.cache)
    if args.versions:
        _check_wheels(p, args)
        reference, candidate = plan(args)[1]
        if _same(candidate, [reference]):
            p.error(
                f"--versions {candidate} would be checked against itself; allowed: "
                "another release to check it against (--against V, or two versions)"
            )
    else:
        bare = [n for n in args.engine if not adapters.record(n).install.history]
        args.engine = tuple(n for n in args.engine if n not in bare)
        for name in bare if args.engine else ():
            print(f"skipped: {name} lists no release (Install.history)", file=sys.stderr)
        if not args.engine:
            p.error(
                f"no release is listed for {', '.join(bare)} (Install.history); allowed: --versions"
            )


def _check_cache(p: argparse.ArgumentParser, cache: Path) -> None:
    """--cache: a directory one can write to, whose folder for this Python is a folder."""
    try:
        inputs.writable_directory(cache, CACHE)
    except BadInput as err:
        p.error(f"--cache: {err}")
    tagged = cache / releases.python_tag()
    if tagged.exists() and not tagged.is_dir():
        p.error(
            f"--cache: {str(tagged)!r} is a file, where this Python's environments go; "
            f"allowed: {CACHE}, with no file named {tagged.name} (move it away)"
        )


def _check_wheels(p: argparse.ArgumentParser, args: argparse.Namespace) -> None:
    """Each wheel named must be one of the engine's package."""
    package = adapters.record(args.engine[0]).install.package
    for v in (*args.versions, *([args.against] if args.against else [])):
        held = inputs.wheel(Path(v)) if v.endswith(".whl") else None
        if held is not None and held != inputs.distribution(package):
            p.error(
                f"--versions: {v!r} is a wheel of {held}; allowed: a wheel of {package}, "
                f"which {args.engine[0]} runs on"
            )


def plan(args: argparse.Namespace) -> tuple[list[tuple[str, str]], tuple[str, str] | None]:
    """The (engine, release) pairs to fire, and the (reference, candidate) to check, if any."""
    if not args.versions:
        return [(n, v) for n in args.engine for v in adapters.record(n).install.history], None
    name, listed = args.engine[0], list(args.versions)
    candidate = listed[-1]
    reference = (
        args.against
        if args.against
        else listed[-2]
        if len(listed) > 1
        else adapters.record(name).install.history[-1]
    )
    if reference not in listed:
        listed.insert(0, reference)
    return [(name, v) for v in listed], (reference, candidate)


#: What a release says on import when its environment lacks something it did not declare, and
#: what it is given then: a build against NumPy 1 (under NumPy 2), one that imports
#: pkg_resources (setuptools 81 removed it).
UNDECLARED = (
    (re.compile(r"numpy.core.multiarray failed to import|compiled using NumPy 1"), "numpy<2"),
    (re.compile(r"No module named 'pkg_resources'"), "setuptools<81"),
)


def fire_release(engine: str, version: str, cache: Path) -> dict:
    """One release judged in its environment (made now if the cache has none): the probe's
    result, or a row that says why there is none. A release that fails to import for want of
    something it did not declare (UNDECLARED) is judged again with it, and the row says so."""
    release = releases.Release(engine=engine, version=version)
    result = _fire(release, cache)
    for said, extra in UNDECLARED:
        if result["state"] == Status.UNSUPPORTED and said.search(result["reason"]):
            release = releases.Release(
                engine=engine, version=version, extras=(*release.extras, extra)
            )
            result = {**_fire(release, cache), "extras": ", ".join(release.extras)}
    return result


def _fire(release: releases.Release, cache: Path) -> dict:
    head = {"engine": release.engine, "release": release.version}
    try:
        python = releases.environment(release, cache)
    except releases.IndexUnreachable as err:
        return {**head, "state": UNREACHABLE, "reason": str(err)}
    except releases.NotInstallable as err:
        return {**head, "state": "not_installable", "reason": str(err)}
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "probe.json"
        try:
            done = _run_probe(python, release, out)
        except subprocess.TimeoutExpired:
            return {
                **head,
                "state": "probe_failed",
                "reason": f"the probe ran past {PROBE_TIMEOUT_S:g} s",
            }
        except OSError as err:  # its python went since the environment was checked
            return {
                **head,
                "state": "probe_failed",
                "reason": f"{python} could not be started ({err.strerror or err})",
            }
        if done.returncode or not out.exists():
            tail = (done.stderr or done.stdout).strip().splitlines()[-1:] or ["no output"]
            return {
                **head,
                "state": "probe_failed",
                "reason": f"exit {done.returncode}: {tail[0][:300]}",
            }
        try:
            result = json.loads(out.read_text())
        except (ValueError, OSError) as err:  # (UnicodeDecodeError is a ValueError)
            return {**head, "state": "probe_failed", "reason": f"its result is garbled ({err})"}
    if (why := history_probe.fault(result)) is not None:
        return {**head, "state": "probe_failed", "reason": f"its result is not the probe's: {why}"}
    # a release whose API the adapter does not drive is unsupported, as an impact it cannot fire
    state = Status.UNSUPPORTED.value if "not_driven" in result else "judged"
    return {**result, **head, "state": state, "reason": result.get("not_driven", "")}


def _run_probe(python: Path, release: releases.Release, out: Path) -> subprocess.CompletedProcess:
    """The probe of ``release`` run by ``python`` (writing ``out``), in ``out``'s folder, held
    to PROBE_TIMEOUT_S (TimeoutExpired past it); said on stderr, once, if it runs past
    PROBE_NOTICE_S, so that a hung release is not a silent wait. It runs in a process group
    of its own, stopped whole (what it started would hold its pipes open)."""
    env = {**os.environ, "PYTHONPATH": str(ROOT), "BATSIM_QUIET": "1"}
    argv = [
        str(python),
        "-m",
        "experiments.parts.history_probe",
        "--engine",
        release.engine,
        "--out",
        str(out),
    ]
    with subprocess.Popen(
        argv,
        cwd=out.parent,
        env=env,
        text=True,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        process_group=0,
    ) as proc:
        try:
            try:
                said = proc.communicate(timeout=min(PROBE_NOTICE_S, PROBE_TIMEOUT_S))
            except subprocess.TimeoutExpired:
                if PROBE_NOTICE_S >= PROBE_TIMEOUT_S:
                    raise
                print(
                    f"history: the probe of {release.engine} {release.version} has run "
                    f"{PROBE_NOTICE_S:g} s and is still running; it is stopped at "
                    f"{PROBE_TIMEOUT_S:g} s (the slowest release's takes about "
                    f"{PROBE_SLOWEST_S:g} s)",
                    file=sys.stderr,
                )
                said = proc.communicate(timeout=PROBE_TIMEOUT_S - PROBE_NOTICE_S)
        except BaseException:  # past its limit, or the run stopped (Ctrl-C, SIGTERM)
            _stop(proc)
            raise
    return subprocess.CompletedProcess(argv, proc.returncode, *said)


def _stop(proc: subprocess.Popen) -> None:
    """The probe's process group killed, and the probe reaped (its pipes are closed after)."""
    with contextlib.suppress(ProcessLookupError, PermissionError):
        os.killpg(proc.pid, signal.SIGKILL)
    proc.wait()


def produce(args: argparse.Namespace) -> tuple[dict[str, bytes], str, int]:
    pairs, candidate = plan(args)
    calls = [(fire_release, (n, v, args.cache)) for n, v in pairs]
    with (
        runs.Progress(len(calls), "history", unit="releases") as bar,
        cli.runner(args, bar) as runner,
    ):
        results = runner.call_all(calls)
    report = history_report.Report(results)
    code, verdict, failed = 0, "", report.nothing_judged()
    if candidate:
        code, verdict, failed = report.verdict(args.engine[0], *candidate)
    if failed:
        print(f"history: {failed}; history.csv has each release's reason", file=sys.stderr)
    return report.files(), report.text() + verdict, 1 if failed else code


COMMAND = Command(name="history", doc=__doc__, produce=produce, options=_options, check=_check)
main = COMMAND.main


if __name__ == "__main__":
    sys.exit(main())
