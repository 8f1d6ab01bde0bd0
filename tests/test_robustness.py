"""What users type and do to a run: overlapping runs, --force, dead runs' leftovers, a scheduler
address that is not a scheduler, libraries' messages. Each is an exact behaviour of
experiments.core.runs / cli / runner, checked through the command a user runs."""

from __future__ import annotations

import json
import os
import socket
import subprocess
import sys
import threading
import time
import warnings

import pytest

from experiments import sweep
from experiments.core import cli, runner, runs
from experiments.core.io import ROOT

from .conftest import cheapest

ENGINE = cheapest(batched=False)
SWEEP = [
    sys.executable,
    "-m",
    "experiments.sweep",
    "--engine",
    ENGINE,
    "--points",
    "3",
    "--no-locate",
]


def _sweep(*args: str, engine: str = ENGINE, **kw) -> subprocess.CompletedProcess:
    argv = [*SWEEP[:4], engine, *SWEEP[5:], *args]
    return subprocess.run(
        argv,
        cwd=ROOT,
        capture_output=True,
        text=True,
        env={**os.environ, "BATSIM_QUIET": "1"},
        **kw,
    )


def test_two_identical_runs_at_once_keep_both_results(tmp_path):
    # Started together into one --out, with the same default name: each holds the name it
    # picked (runs.reserve) until it has published, so they land in distinct folders.
    procs = [
        subprocess.Popen(
            [*SWEEP, "--out", str(tmp_path)],
            cwd=ROOT,
            text=True,
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            env={**os.environ, "BATSIM_QUIET": "1"},
        )
        for _ in range(2)
    ]
    outs = [p.communicate(timeout=120) for p in procs]
    assert [p.returncode for p in procs] == [0, 0], outs
    folders = sorted(p.name for p in tmp_path.iterdir() if p.name != runs.STAGING)
    assert folders == [
        f"sweep-engine={ENGINE}_points=3_no_locate",
        f"sweep-engine={ENGINE}_points=3_no_locate.2",
    ]
    for folder in folders:  # every file whole, as its manifest's digests say
        listed = json.loads((tmp_path / folder / runs.MANIFEST).read_text())["files"]
        assert set(listed) == {"sweep.csv", "sweep.json", "sweep.png"}


def test_a_name_another_run_holds_is_refused(tmp_path):
    target = tmp_path / "same"
    assert runs.reserve(target)  # this process plays the first run, still working
    try:
        res = _sweep("--out", str(tmp_path), "--name", "same")
    finally:
        runs.release(target)
    assert res.returncode == 2 and "another run is writing" in res.stderr, res.stderr
    assert not target.exists()


@pytest.mark.parametrize(
    "kind", ["foreign folder", "plain file", "a run.json of its own", "a run with a file added"]
)
def test_force_replaces_only_a_run(tmp_path, kind):
    # a run is its run.json and exactly the files it lists: replacing anything else would
    # delete what a user put there
    target = tmp_path / "mine"
    if kind == "plain file":
        target.write_text("notes")
    elif kind == "a run with a file added":
        assert _sweep("--out", str(tmp_path), "--name", "mine").returncode == 0
        (target / "thesis.tex").write_text("notes")
    else:
        target.mkdir()
        (target / "thesis.tex").write_text("notes")
        if kind == "a run.json of its own":
            (target / "run.json").write_text("hello")
    res = _sweep("--out", str(tmp_path), "--name", "mine", "--force")
    assert res.returncode == 2, res.stderr
    assert ("is not a run" in res.stderr) or ("is a file" in res.stderr), res.stderr
    assert (
        target.read_text() if kind == "plain file" else (target / "thesis.tex").read_text()
    ) == "notes"
    assert _sweep("--out", str(tmp_path), "--name", "run").returncode == 0
    assert _sweep("--out", str(tmp_path), "--name", "run", "--force").returncode == 0


def test_a_killed_runs_temporary_folder_is_swept_and_its_old_run_restored(tmp_path):
    # Left in the staging folder by runs that died: a half-written new run
    # (<name>.<8 chars>.tmp) and, killed between publish's two renames, the previous run moved
    # aside (<name>.old-<pid>) with nothing in its place. The next run in that folder sweeps
    # the first and puts the second back.
    staging = runs.staging(tmp_path)
    (staging / "a.abcd1234.tmp").mkdir()
    (staging / "a.abcd1234.tmp" / "sweep.csv").write_text("half")
    (staging / "b.old-99999").mkdir()
    (staging / "b.old-99999" / "sweep.csv").write_text("previous")
    assert _sweep("--out", str(tmp_path), "--name", "c").returncode == 0
    assert sorted(p.name for p in tmp_path.iterdir()) == [runs.STAGING, "b", "c"]
    assert (tmp_path / "b" / "sweep.csv").read_text() == "previous"
    assert not (staging / "a.abcd1234.tmp").exists()


def test_a_run_deletes_nothing_it_did_not_make(tmp_path):
    # A user's files in --out whose names look like a run's temporary ones (the pattern the
    # clean-up matched before runs staged in a folder of their own), a folder named as the
    # staging one but not the harness's: a run (replacing another with --force) leaves all.
    mine = {".mydata.old-2019": "thesis", ".photos.ab12cd34.tmp": "holiday", ".c.old-1": "notes"}
    for name, text in mine.items():
        (tmp_path / name).mkdir()
        (tmp_path / name / "keep.txt").write_text(text)
    assert _sweep("--out", str(tmp_path), "--name", "c").returncode == 0
    assert _sweep("--out", str(tmp_path), "--name", "c", "--force").returncode == 0
    for name, text in mine.items():
        assert (tmp_path / name / "keep.txt").read_text() == text
    foreign = tmp_path / "other"
    (foreign / runs.STAGING).mkdir(parents=True)
    (foreign / runs.STAGING / "x.abcd1234.tmp").write_text("mine")
    res = _sweep("--out", str(foreign))
    assert res.returncode == 1 and res.stderr.count("\n") == 1, res.stderr
    assert "not the harness's" in res.stderr
    assert (foreign / runs.STAGING / "x.abcd1234.tmp").read_text() == "mine"


def test_a_file_where_the_staging_folder_goes_is_named(tmp_path):
    (tmp_path / runs.STAGING).write_text("mine")
    res = _sweep("--out", str(tmp_path))
    assert res.returncode == 1 and res.stderr.count("\n") == 1, res.stderr
    assert "is a file, not the harness's staging folder" in res.stderr
    assert (tmp_path / runs.STAGING).read_text() == "mine"


def test_the_run_lock_is_beside_the_runs_whatever_tmpdir_says(tmp_path):
    # Two runs of one --name started together, each with its own TMPDIR: they see one lock
    # (in the staging folder of --out), so one writes and the other is refused.
    procs = []
    for k in range(2):
        tmp = tmp_path / f"tmp{k}"
        tmp.mkdir()
        procs.append(
            subprocess.Popen(
                [*SWEEP, "--out", str(tmp_path / "out"), "--name", "x"],
                cwd=ROOT,
                text=True,
                stdout=subprocess.PIPE,
                stderr=subprocess.PIPE,
                env={**os.environ, "BATSIM_QUIET": "1", "TMPDIR": str(tmp)},
            )
        )
    outs = [p.communicate(timeout=120) for p in procs]
    assert sorted(p.returncode for p in procs) == [0, 2], outs
    refused = outs[[p.returncode for p in procs].index(2)][1]
    assert "another run is writing" in refused or "exists" in refused, refused


def _listener(reply: bytes | None) -> tuple[socket.socket, int]:
    """A local TCP server that accepts and then says ``reply`` (None: nothing) and waits."""
    srv = socket.socket()
    srv.bind(("127.0.0.1", 0))
    srv.listen(4)

    def serve() -> None:
        conns = []
        while True:
            try:
                conn, _ = srv.accept()
            except OSError:
                return
            conns.append(conn)
            if reply:
                conn.sendall(reply)

    threading.Thread(target=serve, daemon=True).start()
    return srv, srv.getsockname()[1]


@pytest.mark.parametrize(
    "reply", [None, b"SSH-2.0-OpenSSH_9.2\r\n" + b"\xff" * 64], ids=["silent", "foreign banner"]
)
def test_a_scheduler_address_that_is_no_scheduler_is_refused_in_seconds(reply, capsys):
    srv, port = _listener(reply)
    t0 = time.perf_counter()
    try:
        with pytest.raises(SystemExit) as exit_:
            sweep.main(["--engine", ENGINE, "--scheduler", f"tcp://127.0.0.1:{port}"])
    finally:
        srv.close()
    err = capsys.readouterr().err
    assert exit_.value.code == 2 and err.count("\n") == 1 and "--scheduler" in err, err
    assert time.perf_counter() - t0 < runner.CONNECT_TIMEOUT_S + 5.0


def test_library_messages_go_to_the_manifest_not_the_terminal(capsys):
    # A warning and an error raised where Python can only report it (a callback, a __del__)
    # during a run: kept for the run's manifest, nothing printed.
    class Noisy:
        def __del__(self):
            raise RuntimeError("from a callback")

    with cli.library_messages_kept():
        warnings.warn("overflow in exp", RuntimeWarning, stacklevel=1)
        Noisy()
        said = runs.library_messages()
        manifest = json.loads(runs.manifest({"a.csv": b"x"}))
    assert capsys.readouterr().err == ""
    assert any("RuntimeWarning: overflow in exp" in m for m in said), said
    assert any("RuntimeError" in m and "from a callback" in m for m in said), said
    assert manifest["library_messages"] == said
    assert (
        manifest["files"]["a.csv"]
        == "2d711642b726b04401627ca9fbac32f5c8530fb1903cc4db02258717921a4881"
    )  # sha256 of b"x"


@pytest.mark.parametrize(
    "value,quiet",
    [
        ("1", True),
        ("TRUE", True),
        ("yes", True),
        ("0", False),
        ("false", False),
        ("No", False),
        ("", False),
    ],
)
def test_batsim_quiet_values(monkeypatch, value, quiet):
    monkeypatch.setenv("BATSIM_QUIET", value)
    assert runs.quiet() is quiet and runs.quiet_error() is None


@pytest.mark.parametrize("value", ["00", "off", "2", "quiet"])
def test_batsim_quiet_refuses_other_values(value):
    res = subprocess.run(
        [*SWEEP],
        cwd=ROOT,
        capture_output=True,
        text=True,
        env={**os.environ, "BATSIM_QUIET": value},
    )
    assert res.returncode == 2 and f"BATSIM_QUIET={value!r}" in res.stderr, res.stderr
    assert "Traceback" not in res.stderr


@pytest.fixture(scope="module")
def sweep_csv(tmp_path_factory) -> str:
    """A real sweep table's text (3 points of the cheapest engine)."""
    out = tmp_path_factory.mktemp("cmp")
    assert _sweep("--out", str(out), "--name", "t").returncode == 0
    return (out / "t" / "sweep.csv").read_text()


def _compare(tmp_path, old: str, new: str) -> subprocess.CompletedProcess:
    (tmp_path / "old.csv").write_text(old)
    (tmp_path / "new.csv").write_text(new)
    return subprocess.run(
        [
            sys.executable,
            "-m",
            "experiments.compare",
            str(tmp_path / "old.csv"),
            str(tmp_path / "new.csv"),
        ],
        cwd=ROOT,
        capture_output=True,
        text=True,
    )


def _edit_v1(text: str, value: str) -> str:
    """The table with the first row's v1_engine_mps set to ``value``."""
    head, first, *rest = text.splitlines()
    col = head.split(",").index("v1_engine_mps")
    cells = first.split(",")
    cells[col] = value
    return "\n".join([head, ",".join(cells), *rest]) + "\n"


@pytest.mark.parametrize("change", ["nan", "blank", "duplicated", "moved"])
def test_compare_counts_every_damage_as_a_change(tmp_path, sweep_csv, change):
    lines = sweep_csv.splitlines(keepends=True)
    new = {
        "nan": lambda: _edit_v1(sweep_csv, "nan"),
        "blank": lambda: _edit_v1(sweep_csv, ""),
        "duplicated": lambda: sweep_csv + lines[-1],
        "moved": lambda: _edit_v1(sweep_csv, "-1.0"),
    }[change]()  # no engine returns -1 m/s
    res = _compare(tmp_path, sweep_csv, new)
    assert res.returncode == 1 and "Traceback" not in res.stderr, res.stdout + res.stderr
    assert "no change apart from timing" not in res.stdout
    assert _compare(tmp_path, sweep_csv, sweep_csv).returncode == 0


@pytest.mark.parametrize(
    "damage", ["binary", "extra field", "truncated", "text in s_m", "text in v1 err"]
)
def test_compare_refuses_a_malformed_table_in_one_line(tmp_path, sweep_csv, damage):
    head, first, *rest = sweep_csv.splitlines()
    cols = head.split(",")

    def with_cell(name: str) -> str:
        cells = first.split(",")
        cells[cols.index(name)] = "abc"
        return "\n".join([head, ",".join(cells), *rest]) + "\n"

    bad = {
        "binary": lambda: head + "\n" + "\x00\xff\xfe garbage \x01\n",
        "extra field": lambda: "\n".join([head, first + ",1,2", *rest]) + "\n",
        "truncated": lambda: sweep_csv[: len(sweep_csv) - len(rest[-1]) // 2],
        "text in s_m": lambda: with_cell("s_m"),
        "text in v1 err": lambda: with_cell("v1_abs_err_mps"),
    }[damage]()
    res = _compare(tmp_path, sweep_csv, bad)
    assert res.returncode == 2, res.stdout + res.stderr
    assert res.stderr.count("\n") == 1 and "Traceback" not in res.stderr, res.stderr


@pytest.mark.parametrize("damage", ["junk csv", "truncated json"])
def test_report_on_a_damaged_results_directory_says_which_file(tmp_path, damage):
    # A copy of results/ with one file damaged: the report is written, the sections that read
    # the file say it is damaged, and stderr names it; no traceback.
    import shutil

    results = tmp_path / "results"
    shutil.copytree(ROOT / "results", results)
    name = {"junk csv": "sweep_all_reference_r161_swing.csv", "truncated json": "defaults.json"}[
        damage
    ]
    text = (results / name).read_bytes()
    (results / name).write_bytes(b"junk,\x00\xff\n1\n" if damage == "junk csv" else text[:100])
    res = subprocess.run(
        [
            sys.executable,
            "-m",
            "experiments.report",
            "--results",
            str(results),
            "--out",
            str(tmp_path / "out"),
        ],
        cwd=ROOT,
        capture_output=True,
        text=True,
        env={**os.environ, "BATSIM_QUIET": "1"},
    )
    assert res.returncode == 0 and "Traceback" not in res.stderr, res.stderr
    assert "damaged" in res.stderr
    (report,) = (tmp_path / "out").glob("*/report.md")
    assert "a results file it reads is damaged" in report.read_text()


def test_a_run_of_unsupported_impacts_says_why(tmp_path):
    # An undercut leaves the swing plane: a planar engine cannot fire it. The run still ends
    # (exit 0, every row 'unsupported') and its summary gives the reason, not just the count.
    import adapters

    planar = [n for n in adapters.available() if adapters.record(n).can.planar]
    assert planar  # pymunk and Box2D are core and planar
    res = _sweep("--undercut", "0.02", "--out", str(tmp_path), engine=planar[0])
    assert res.returncode == 0, res.stderr
    assert f"{planar[0]}: 3 unsupported (" in res.stdout and "plane" in res.stdout, res.stdout


def test_a_plastic_sweep_names_the_sweet_spot_its_rows_are_judged_by(tmp_path):
    # At e = 0 the rows are judged against the whole rigid episode, whose sustained contact
    # moves the sweet spot off the single impulse's closed form (76.07 mm for the paper's
    # swing): the summary prints the episode's (analytic.episode_sweet_spot, checked against
    # an independent grid in test_analytic_collide), to the 4 decimals of a mm it shows.
    from analytic import ImpactCase, episode_sweet_spot, presets

    res = _sweep("--e", "0", "--out", str(tmp_path))
    assert res.returncode == 0, res.stderr
    swing = presets.PAPER_SWING
    case = ImpactCase(
        bat=presets.R161,
        ball=presets.BASEBALL,
        s_m=0.0,
        v0_mps=presets.PAPER_PITCH_MPS,
        u0_mps=swing.u0_mps,
        omega0_radps=swing.omega0_radps,
        e=0.0,
    )
    assert f"analytic: sweet spot {episode_sweet_spot(case) * 1e3:.4f} mm," in res.stdout, (
        res.stdout
    )
