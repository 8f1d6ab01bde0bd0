"""What the machine does to a run, as a user meets it: a full device or a closed pipe as
stdout, no stderr at all, a file size or memory limit, an encoding that cannot show a path, a
path that is not UTF-8, a matplotlib backend that does not exist. Each command ends with a
one-line message and exit 1 (2 for a setting refused before any work), or does its work; never
a traceback (but under --debug), and a run whose files were written keeps them."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

from .conftest import ROOT, cheapest

ENGINE = cheapest(batched=False)
SWEEP = ["-m", "experiments.sweep", "--engine", ENGINE, "--points", "3", "--no-locate"]


def _run(
    argv: list[str],
    *,
    shell_prefix: str = "",
    env: dict | None = None,
    stdout=None,
    stderr=subprocess.PIPE,
) -> subprocess.CompletedProcess:
    """``python argv`` as a user types it, under ``shell_prefix`` (ulimit ...; a redirection)."""
    line = " ".join([shell_prefix, sys.executable, *map(_quoted, argv)]).strip()
    return subprocess.run(
        ["bash", "-c", line],
        cwd=ROOT,
        stdout=stdout or subprocess.PIPE,
        stderr=stderr,
        timeout=120,
        env={**os.environ, "BATSIM_QUIET": "1", **(env or {})},
    )


def _quoted(arg: str) -> str:
    return "'" + arg.replace("'", "'\\''") + "'"


def _one_line(res: subprocess.CompletedProcess, code: int, *pieces: str) -> str:
    err = res.stderr.decode(errors="replace")
    assert res.returncode == code, err
    assert "Traceback" not in err and err.count("\n") == 1, err
    assert all(p in err for p in pieces), err
    return err


def test_stdout_on_a_full_device_is_one_line_and_the_run_is_kept(tmp_path):
    res = _run([*SWEEP, "--out", str(tmp_path), "--name", "r"], shell_prefix="exec >/dev/full;")
    _one_line(res, 1, "stdout could not be written", "No space left on device")
    assert json.loads((tmp_path / "r" / "run.json").read_text())["files"]


def test_a_closed_pipe_ends_quietly_and_the_run_is_kept(tmp_path):
    # `| head -1` once head has gone (here a reader that reads nothing): nothing more said,
    # exit 141 as a shell tells a closed pipe (not 1, which compare gives a change)
    res = subprocess.run(
        [
            "bash",
            "-c",
            f"{sys.executable} "
            + " ".join(map(_quoted, [*SWEEP, "--out", str(tmp_path), "--name", "r"]))
            + " | true; "
            "echo ${PIPESTATUS[0]} >&2",
        ],
        cwd=ROOT,
        capture_output=True,
        text=True,
        timeout=120,
        env={**os.environ, "BATSIM_QUIET": "1"},
    )
    assert res.stderr.strip() == "141", res.stderr
    assert (tmp_path / "r" / "sweep.csv").is_file()


def test_no_stderr_at_all_still_runs(tmp_path):
    res = _run(
        [*SWEEP, "--out", str(tmp_path), "--name", "r"],
        shell_prefix="exec 2>&-;",
        env={"BATSIM_QUIET": "0"},
        stderr=subprocess.DEVNULL,
    )
    assert res.returncode == 0 and (tmp_path / "r" / "sweep.csv").is_file()


def test_a_file_size_limit_is_one_line_and_leaves_nothing_half_written(tmp_path):
    res = _run([*SWEEP, "--out", str(tmp_path), "--name", "r"], shell_prefix="ulimit -f 40;")
    _one_line(res, 1, "File too large", "ulimit -f")
    assert not (tmp_path / "r").exists()
    assert not [p for p in (tmp_path / ".batsim").iterdir() if p.is_dir()]


def test_a_memory_limit_too_small_to_import_is_one_line():
    # 300 MB of address space: numpy and scipy's libraries cannot all be mapped
    res = _run(SWEEP, shell_prefix="ulimit -v 300000;")
    err = res.stderr.decode(errors="replace")
    assert res.returncode == 1 and "Traceback" not in err, err
    assert err.count("\n") == 1 and ("memory" in err or "ulimit -v" in err), err


def test_debug_shows_the_traceback():
    res = _run([*SWEEP, "--debug"], shell_prefix="ulimit -v 300000;")
    assert res.returncode == 1 and b"Traceback" in res.stderr, res.stderr


@pytest.mark.parametrize("env", [{"PYTHONIOENCODING": "ascii"}, {"LC_ALL": "C"}])
def test_a_path_the_terminal_cannot_encode_is_shown_escaped(tmp_path, env):
    out = os.fsencode(tmp_path) + b"/caf\xc3\xa9-\xe9"  # UTF-8 and not: both exist on Linux
    res = subprocess.run(
        [sys.executable, *SWEEP, "--out", out, "--name", "r"],
        cwd=ROOT,
        capture_output=True,
        timeout=120,
        env={**os.environ, "BATSIM_QUIET": "1", **env},
    )
    assert res.returncode == 0, res.stderr
    assert Path(os.fsdecode(out + b"/r/sweep.csv")).is_file()
    assert b"\\udce9" in res.stdout or b"\\xe9" in res.stdout, res.stdout


def test_an_unknown_matplotlib_backend_is_refused_a_known_one_is_not_needed(tmp_path):
    _one_line(_run(SWEEP, env={"MPLBACKEND": "nope"}), 2, "MPLBACKEND='nope'")
    res = _run([*SWEEP, "--out", str(tmp_path)], env={"MPLBACKEND": "tkagg", "DISPLAY": ""})
    assert res.returncode == 0, res.stderr  # charts go to files: Agg, whatever it says
