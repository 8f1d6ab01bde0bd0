"""Every command line the README shows, run as a user would (a fresh interpreter, from the
project root), at small size: each ``python -m experiments...`` line of its shell blocks with
``--points`` cut to 3 and a scratch ``--out``; the Dask line with a real scheduler and worker;
the plug-in line on the toy plug-in; the ten-line Python block, whose commented numbers must
be what it computes. A traceback fails a test."""

from __future__ import annotations

import re
import shlex
import socket
import subprocess
import sys
import time
from pathlib import Path

import pytest

from .conftest import ROOT, run_command

README = (ROOT / "README.md").read_text()
BLOCKS = re.findall(r"```(\w+)\n(.*?)```", README, re.S)
#: The `python -m experiments...` lines of the shell blocks, comments included (`make sweep`
#: is spelled out in its comment), as argument lists.
LINES = [
    shlex.split(m.group(0).split("->")[0])
    for lang, text in BLOCKS
    if lang == "sh"
    for m in re.finditer(r"python -m experiments\.[^\n#&]*", text)
]
SMALL_POINTS = "3"


def _small(argv: list[str], out: str) -> list[str]:
    """The line at small size: --points 3, and its run written to ``out``."""
    argv = list(argv[1:])  # "python" is this interpreter
    if "--points" in argv:
        argv[argv.index("--points") + 1] = SMALL_POINTS
    return [*argv, "--out", out] if not argv[1].endswith("check_engine") else argv


def test_the_readme_shows_command_lines():
    assert len(LINES) >= 3, LINES


#: Lines run in the full tier: their JAX traces take 40 s (the fast tier runs the command on a
#: single-world engine in test_commands, and an engine's own derivative in test_gradients).
SLOW = ("experiments.gradients",)


@pytest.mark.parametrize(
    "argv",
    [
        a
        for a in LINES
        if "myengine" not in a
        # installs releases: run on a cold cache by test_history.py
        and a[2] != "experiments.history"
        and a[2] not in SLOW
    ],
    ids=lambda a: " ".join(a[2:]),
)
def test_a_readme_command_line_runs(argv, tmp_path):
    run_command(_small(argv, str(tmp_path)))


@pytest.mark.full
@pytest.mark.parametrize("argv", [a for a in LINES if a[2] in SLOW], ids=lambda a: " ".join(a[2:]))
def test_a_slow_readme_command_line_runs(argv, tmp_path):
    run_command(_small(argv, str(tmp_path)))


def test_the_plugin_check_line_runs_on_a_plugin(toy_site):
    # `python -m experiments.check_engine --engine myengine`, myengine being the toy plug-in
    (line,) = [a for a in LINES if "myengine" in a]
    argv = [a.replace("myengine", "toyengine") for a in line[1:]]
    res = run_command(argv, env={"PYTHONPATH": str(toy_site)})
    assert "FAILED" not in res.stdout and "ok " in res.stdout


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def _listening(port: int, timeout_s: float) -> bool:
    """Whether something accepts connections on the port within ``timeout_s``."""
    deadline = time.monotonic() + timeout_s
    while time.monotonic() < deadline:
        with socket.socket() as s:
            if s.connect_ex(("127.0.0.1", port)) == 0:
                return True
        time.sleep(0.1)
    return False


def test_the_dask_line_runs_a_sweep_on_a_cluster(tmp_path):
    # `dask scheduler & dask worker tcp://HOST:8786 --nthreads 1`, then the sweep line with
    # --scheduler tcp://HOST:8786 instead of --workers: here, on a free port
    (line,) = [
        m.group(0)
        for lang, text in BLOCKS
        if lang == "sh"
        for m in re.finditer(r"dask scheduler & dask worker [^\n#]*", text)
    ]
    port = _free_port()
    dask = str(Path(sys.executable).parent / "dask")
    scheduler, worker = (
        shlex.split(part.replace("HOST:8786", f"127.0.0.1:{port}")) for part in line.split("&")
    )
    procs = [
        subprocess.Popen(
            [dask, *scheduler[1:], "--port", str(port), "--no-dashboard"],
            cwd=ROOT,
            stdout=subprocess.DEVNULL,
            stderr=subprocess.DEVNULL,
        )
    ]
    try:
        assert _listening(port, 60.0), "the scheduler never listened"
        procs.append(
            subprocess.Popen(
                [dask, *worker[1:], "--no-dashboard"],
                cwd=ROOT,
                stdout=subprocess.DEVNULL,
                stderr=subprocess.DEVNULL,
            )
        )
        sweep = next(a for a in LINES if a[2] == "experiments.sweep" and "--workers" in a)
        argv = _small(sweep, str(tmp_path))
        at = argv.index("--workers")
        run_command([*argv[:at], *argv[at + 2 :], "--scheduler", f"tcp://127.0.0.1:{port}"])
    finally:
        for proc in procs:
            proc.terminate()
            proc.wait(timeout=30)


def test_the_python_block_computes_what_its_comments_say():
    (code,) = [text for lang, text in BLOCKS if lang == "python"]
    quoted = {
        "v1_mps": re.search(r"v1_mps=([\d.]+)", code).group(1),
        "sweet": re.search(r"# ([\d.]+) m from the COM", code).group(1),
    }
    probe = (
        f"\nprint(f'{{out.v1_mps:.{len(quoted['v1_mps'].split('.')[1])}f}}')"
        f"\nprint(f'{{sweet_spot(bat, ball, 46.9, 17.87, 32.0):."
        f"{len(quoted['sweet'].split('.')[1])}f}}')"
    )
    res = run_command(["-c", code + probe])
    assert res.stdout.split()[-2:] == [quoted["v1_mps"], quoted["sweet"]]
