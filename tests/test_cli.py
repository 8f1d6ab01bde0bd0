"""The command-line convention, for every experiment: bad input exits 2 with one line naming
the option, the value and what is allowed, before anything runs or any file is touched;
--help only prints; runs go to their own directory and never overwrite another."""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
from pathlib import Path

import pytest

import adapters
from experiments import sweep
from experiments.core import cli, runs
from experiments.core.io import ROOT

from .conftest import COMMANDS, runs_in

NOT_SOFT = [n for n in adapters.names() if adapters.record(n).can.soft_contact is None]


def _bad_inputs(tmp: Path) -> list[tuple[str, list[str], str]]:
    """(command, argv, a piece the one-line error must hold)."""
    a_file = ROOT / "README.md"
    existing = tmp / "taken"
    existing.mkdir()
    cases = [*_bad_sweeps(tmp, a_file), *_bad_studies(tmp, a_file)]
    soft = [n for n in adapters.names() if n not in NOT_SOFT]
    if NOT_SOFT:
        cases.append(("calibrate_soft", ["--engine", NOT_SOFT[0]], "has no soft contact"))
    if NOT_SOFT and soft:  # named beside a soft one, it would be dropped without a word
        cases.append(
            (
                "calibrate_soft",
                ["--engine", f"{soft[0]},{NOT_SOFT[0]}"],
                f"{NOT_SOFT[0]} has no soft contact",
            )
        )
    return cases


def _bad_sweeps(tmp: Path, a_file: Path) -> list[tuple[str, list[str], str]]:
    """The sweep's options, one bad value each; the edges of what can run: a step too small
    to place an impact (refused with the smallest that works), a run over its budget (refused
    with its estimate), a directory that cannot be made, a scheduler that does not answer."""
    return [
        ("sweep", ["--engine", "bullet"], "--engine"),
        ("sweep", ["--engine", ""], "--engine"),
        ("sweep", ["--engine", f"{adapters.names()[0]},bullet"], "bullet"),
        ("sweep", ["--bat", "maple"], "--bat"),
        ("sweep", ["--profile", "fast"], "--profile"),
        ("sweep", ["--e", "1.5"], "--e"),
        ("sweep", ["--e", "-0.1"], "--e"),
        ("sweep", ["--e", "abc"], "--e"),
        ("sweep", ["--dt", "-1e-5"], "--dt"),
        ("sweep", ["--dt", "0"], "--dt"),
        ("sweep", ["--dt", "nan"], "--dt"),
        ("sweep", ["--dt", "2"], "--dt"),
        ("sweep", ["--points", "1"], "--points"),
        ("sweep", ["--points", "100000000"], "an integer 2..10000"),
        ("sweep", ["--points", "2.5"], "--points"),
        ("sweep", ["--s-range", "-0.2", "0.4"], "--s-range MAX=0.4 m is off the bat"),
        ("sweep", ["--s-range", "0.2", "-0.2"], "--s-range MIN=0.2 >= --s-range MAX=-0.2"),
        ("sweep", ["--corked", "--hole-depth", "2"], "--hole-depth=2.0 is out of range"),
        ("sweep", ["--hole-radius", "0.01"], "--hole-radius 0.01 without --corked"),
        ("sweep", ["--corked", "--hole-radius", "0.05"], "--hole-radius=0.05 is out of range"),
        ("sweep", ["--corked", "--fill-density", "-5"], "--fill-density"),
        ("sweep", ["--swing", "--swing-angle", "0"], "--swing-angle"),
        ("sweep", ["--swing", "--theta", "0.3"], "--swing with --theta 0.3"),
        ("sweep", ["--swing", "--hands", "0.6"], "--hands 0.6 m is not allowed"),
        ("sweep", ["--hands", "0.9"], "--hands 0.9 m is not allowed"),
        ("sweep", ["--theta", "2"], "--theta"),
        ("sweep", ["--v0", "-3"], "--v0"),
        ("sweep", ["--v0", "1e9"], "--v0"),
        ("sweep", ["--omega0", "1e9"], "--omega0"),
        ("sweep", ["--hands", "-1"], "--hands"),
        ("sweep", ["--v0", "0", "--u0", "0", "--omega0", "0"], "closing speed"),
    ] + _bad_sweep_runs(tmp, a_file)


def _bad_sweep_runs(tmp: Path, a_file: Path) -> list[tuple[str, list[str], str]]:
    """The sweep's runner, output and comparison options, and refusals that need the run."""
    return [
        ("sweep", ["--workers", "0"], "--workers"),
        ("sweep", ["--workers", "1000"], "--workers"),
        ("sweep", ["--workers", "two"], "--workers"),
        ("sweep", ["--out", str(a_file)], "is a file"),
        ("sweep", ["--out", str(a_file / "sub")], "is a file"),
        ("sweep", ["--out", str(ROOT / "results")], "inside results/"),
        ("sweep", ["--out", str(ROOT / "results" / "x")], "inside results/"),
        ("sweep", ["--name", "../escaped"], "--name"),
        ("sweep", ["--name", "a/b"], "--name"),
        ("sweep", ["--name", ""], "--name"),
        ("sweep", ["--name", ".hidden"], "--name"),
        ("sweep", ["--name", "taken"], "exists; allowed: --force"),
        ("sweep", ["--compare", str(tmp / "no.csv"), str(tmp / "no.csv")], "is not a file"),
        ("sweep", ["--compare", str(a_file), str(a_file)], "is not a CSV table"),
        ("sweep", ["--compare", *[str(ROOT / "results" / "pareto.csv")] * 2], "not a sweep table"),
        ("sweep", ["--compare", *[str(ROOT / "results" / "pareto.png")] * 2], "is not a"),
        ("sweep", ["--dt", "1e-12"], "too small to place"),
        ("sweep", ["--points", "10000", "--budget-h", "1e-6"], "would take about"),
        ("sweep", ["--out", "/proc/x"], "cannot create files in /proc"),
        ("sweep", ["--scheduler", "tcp://127.0.0.1:1"], "answered at tcp://127.0.0.1:1"),
        ("sweep", ["--out", ""], "'' is not a directory"),
        ("sweep", ["--out", "~nosuchuser/x"], "cannot be resolved"),
        ("sweep", ["--out", "n" * 300], "at most 255 bytes"),
        ("sweep", ["--s-range", "nan", "0"], "a finite number"),
        ("sweep", ["--undercut", "1"], "--undercut=1.0 is out of range"),
        ("sweep", ["--corked", "--fill-density", "30000"], "--fill-density=30000.0"),
        ("sweep", ["--corked", "--wood-density", "0"], "--wood-density=0.0"),
        ("sweep", ["--swing", "--u0", "5"], "--u0 5.0 with --swing does nothing"),
        ("sweep", ["--v0", "1e-300", "--u0", "0", "--omega0", "0"], "reference profile's step ("),
        ("sweep", ["--omega0", "1e5"], ">= -1000 and <= 1000 rad/s"),
        ("sweep", ["--omega0", "-900", "--u0", "0"], "comes from --v0, --u0, --omega0"),
        ("sweep", ["--e", "0.5", "--e", "0.6"], "--e given 2 times"),
        ("sweep", ["--eng", "mujoco"], "unrecognized arguments: --eng"),
        # the flight model's drag and lift hold to 200 m/s: a faster ball has no carry
        (
            "sweep",
            ["--flight", "--v0", "1000", "--u0", "1000", "--omega0", "1000"],
            "over the 200 m/s",
        ),
        (
            "sweep",
            ["--compare", str(a_file), str(a_file), "--friction", "0.5"],
            "--compare with --friction",
        ),
    ]


def _bad_studies(tmp: Path, a_file: Path) -> list[tuple[str, list[str], str]]:
    """The other commands' options, one bad value each."""
    return [
        ("compare", [str(tmp / "no.csv"), str(tmp / "no.csv")], "is not a file"),
        ("pareto", ["--repeats", "0"], "--repeats"),
        ("pareto", ["--engine", "nope"], "--engine"),
        ("stability", ["--workers", "-1"], "--workers"),
        ("stability", ["--out", str(a_file)], "is a file"),
        ("swing", ["--engine", "nope"], "--engine"),
        ("swing", ["--quick", "--name", "x/y"], "--name"),
        ("baselines", ["--only", "nothing"], "--only"),
        # one engine's run would drop the other engines' rows from whole-suite files
        (
            "baselines",
            ["--only", "sweeps,report", "--engine", adapters.names()[0]],
            "rewrites whole-suite files",
        ),
        (
            "baselines",
            ["--only", "defaults", "--engine", adapters.names()[-1]],
            f"leaves out {adapters.names()[0]}",
        ),
        ("bench_engines", ["--points", "1"], "--points"),
        ("bench_engines", ["--repeats", "0"], "--repeats"),
        ("bench_analytic", ["--points", "0"], "--points"),
        ("findings", ["--name", "../x"], "--name"),
        ("defaults", ["--phases", "1"], "--phases"),
        ("check_engine", ["--check", "nope"], "--check"),
        ("check_engine", ["--engine", "nope"], "--engine"),
        ("flex", ["--engine", "nope"], "--engine"),
    ]


def test_bad_inputs_exit_2_with_one_line_before_any_work(tmp_path, capsys):
    cases = _bad_inputs(tmp_path)
    assert len(cases) >= 40
    before = sorted(tmp_path.rglob("*"))
    for command, argv, piece in cases:
        with pytest.raises(SystemExit) as exit_:
            writes = (
                command not in ("compare", "baselines", "check_engine") and "--compare" not in argv
            )
            COMMANDS[command].main(
                [*argv, *(["--out", str(tmp_path)] if writes and "--out" not in argv else [])]
            )
        err = capsys.readouterr().err.strip()
        assert exit_.value.code == 2, (command, argv, err)
        assert piece in err and "\n" not in err, (command, argv, err)
        assert "Traceback" not in err
    assert sorted(tmp_path.rglob("*")) == before  # nothing written, not even a directory


@pytest.mark.parametrize("command", sorted(COMMANDS))
def test_help_only_prints(command, capsys, tmp_path):
    before = sorted(runs.RUNS.glob("*")) if runs.RUNS.exists() else []
    results = {p: p.stat().st_mtime_ns for p in (ROOT / "results").iterdir()}
    with pytest.raises(SystemExit) as exit_:
        COMMANDS[command].main(["--help"])
    assert exit_.value.code == 0
    assert "usage:" in capsys.readouterr().out
    assert (sorted(runs.RUNS.glob("*")) if runs.RUNS.exists() else []) == before
    assert {p: p.stat().st_mtime_ns for p in (ROOT / "results").iterdir()} == results


def test_runs_never_overwrite_each_other(tmp_path):
    # The default name carries the options that differ from the defaults; a second run gets
    # .2; an explicit --name is refused when taken, and --force replaces it.
    args = ["--engine", adapters.names()[0], "--points", "3", "--no-locate", "--out", str(tmp_path)]
    assert sweep.main(args) == 0
    assert sweep.main(args) == 0
    name = f"sweep-engine={adapters.names()[0]}_points=3_no_locate"
    assert sorted(runs_in(tmp_path)) == [name, f"{name}.2"]
    first = (tmp_path / name / "sweep.csv").read_bytes()
    assert sweep.main([*args, "--name", name, "--force", "--e", "0.6"]) == 0
    assert (tmp_path / name / "sweep.csv").read_bytes() != first
    assert sorted(runs_in(tmp_path)) == [name, f"{name}.2"]


@pytest.mark.parametrize("umask,mode", [(0o022, 0o644), (0o027, 0o640), (0o077, 0o600)])
def test_files_follow_the_umask(tmp_path, umask, mode):
    # A run's files and the committed ones get 0666 & ~umask, as any program's files do.
    code = (
        "import sys; from pathlib import Path; from experiments.core import io, runs; "
        "p = Path(sys.argv[1]); runs.publish(p / 'run', {'a.txt': b'x'}); "
        "io.atomic_write_bytes(p / 'b.txt', b'y')"
    )
    subprocess.run(
        [sys.executable, "-c", code, str(tmp_path)],
        cwd=ROOT,
        check=True,
        preexec_fn=lambda: os.umask(umask),
    )
    for path in (tmp_path / "run" / "a.txt", tmp_path / "b.txt"):
        assert path.stat().st_mode & 0o777 == mode, path
    assert (tmp_path / "run").stat().st_mode & 0o777 == 0o777 & ~umask


def test_runs_are_ignored_by_git():
    res = subprocess.run(
        ["git", "check-ignore", "-q", "runs/anything/sweep.csv"], cwd=ROOT, check=False
    )
    assert res.returncode == 0


@pytest.mark.parametrize("name", [n for n in adapters.names() if adapters.record(n).drives_bat])
def test_a_real_sigint_stops_a_swing_sweep_and_keeps_the_earlier_run(name, tmp_path):
    # SIGINT sent to the process while it swings bats in the engine (pymunk's swings call
    # Python back on every step, and its callback swallows KeyboardInterrupt, so the run must
    # stop through the flag checked after each impact): exit 130, the run that was there
    # untouched, no temporary directory left. The signal goes once the run says it has
    # started firing (600 swings take 10 s or more in every engine).
    import signal

    args = [
        "-m",
        "experiments.sweep",
        "--engine",
        name,
        "--out",
        str(tmp_path),
        "--name",
        "r",
        "--force",
    ]
    subprocess.run(
        [sys.executable, *args, "--points", "3", "--no-locate"],
        cwd=ROOT,
        capture_output=True,
        check=True,
    )
    kept = {p.name: p.read_bytes() for p in (tmp_path / "r").iterdir()}
    env = {**os.environ, "BATSIM_QUIET": "0", "PYTHONUNBUFFERED": "1"}
    # (interrupted within seconds: the estimate, an hour for Drake, must not refuse it)
    proc = subprocess.Popen(
        [sys.executable, *args, "--swing", "--points", "600", "--budget-h", "100"],
        cwd=ROOT,
        env=env,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    seen = []
    for line in proc.stderr:
        seen.append(line)
        if "started" in line:
            break
    proc.send_signal(signal.SIGINT)
    out, err = proc.communicate(timeout=120)
    err = "".join(seen) + err
    assert proc.returncode == 130, (name, err[-2000:])
    assert "interrupted" in err
    assert "Traceback" not in err and "Exception ignored" not in err, err[-2000:]
    assert {p.name: p.read_bytes() for p in (tmp_path / "r").iterdir()} == kept
    assert runs_in(tmp_path) == ["r"]


def _needs(rec: adapters.EngineRecord, module: str) -> bool:
    """Whether the engine imports ``module`` (or a module inside it)."""
    return any(
        m == module or m.startswith(module + ".")
        for m in (rec.install.import_name, *rec.install.requires)
    )


@pytest.mark.parametrize("name", adapters.names())
def test_a_missing_engine_is_named_with_its_install_hint(name, tmp_path, monkeypatch, capsys):
    # With the engine's module hidden, the engines that need it (MJX and MuJoCo Warp need
    # mujoco's too) are missing, each with its install hint, and the rest available; naming the
    # engine is a bad input (exit 2, the hint, nothing written).
    rec = adapters.record(name)
    monkeypatch.setitem(sys.modules, rec.install.import_name, None)
    gone = {n for n in adapters.names() if _needs(adapters.record(n), rec.install.import_name)}
    assert name in gone
    assert set(adapters.missing()) == gone
    assert adapters.missing()[name] == rec.install_hint
    assert set(adapters.available()) == set(adapters.names()) - gone
    with pytest.raises(SystemExit) as exit_:
        sweep.main(["--points", "2", "--out", str(tmp_path), "--engine", name])
    assert exit_.value.code == 2 and rec.install_hint in capsys.readouterr().err
    assert not any(tmp_path.iterdir())


@pytest.mark.full
def test_engine_all_skips_a_missing_engine_and_runs_the_rest(tmp_path):
    # In a fresh process with the last engine's module hidden: --engine all runs every other
    # engine (a row each in the summary), and says which it skipped and how to install it.
    rec = adapters.record(adapters.names()[-1])
    code = (
        f"import sys; sys.modules[{rec.install.import_name!r}] = None\n"
        "from experiments import sweep\n"
        f"sweep.main(['--points', '2', '--out', {str(tmp_path)!r}, '--name', 'x', "
        "'--engine', 'all'])"
    )
    res = subprocess.run(
        [sys.executable, "-c", code],
        capture_output=True,
        text=True,
        cwd=ROOT,
        timeout=600,
        check=False,
    )
    assert res.returncode == 0, res.stderr
    assert f"skipped: {rec.install_hint}" in res.stderr
    others = [
        n for n in adapters.names() if not _needs(adapters.record(n), rec.install.import_name)
    ]
    assert all(f"\n{n} " in res.stdout for n in others) and f"\n{rec.name} " not in res.stdout


@pytest.mark.parametrize("command", sorted(COMMANDS))
def test_help_is_whole(command, capsys):
    # The description is a whole sentence (not a docstring's first line cut mid-sentence), every
    # option says what it is, and the exit codes are given.
    with pytest.raises(SystemExit):
        COMMANDS[command].main(["--help"])
    text = capsys.readouterr().out
    assert "exit codes: 0" in text
    description = text.split("\n\n")[1]
    assert description.rstrip().endswith((".", ")", "?")), description
    options = text.split("options:", 1)[1].split("\n\n")[0].splitlines()
    # an option line with no help text is alone on its line and the next line is another option
    for line, after in zip(options, [*options[1:], ""]):
        if line.startswith("  -") and "  " not in line.strip():
            assert after.startswith(" " * 20) and not after.strip().startswith("-"), line


@pytest.mark.parametrize(
    "text,value",
    [("1000", 1000), ("1e3", 1000), ("1.0e2", 100), ("1.5", None), ("1e9", None), ("nan", None)],
)
def test_an_integer_option_takes_what_its_help_writes(text, value):
    # bench_analytic's --help writes its range as 1..1e8: 1e3 is an integer written so
    parse = cli.integer(1, 10**8)
    if value is None:
        with pytest.raises(argparse.ArgumentTypeError, match="an integer 1..100000000"):
            parse(text)
    else:
        assert parse(text) == value
