"""Files handed to commands are checked against what they must be before any work
(``experiments.core.inputs``): a damaged one (missing, a directory, empty, binary, cut mid-line,
of another kind, text where numbers belong) is refused in one line naming it, what is wrong and
what is allowed, exit 2, nothing written; never a traceback, never read as data. Tried as a user
would: compare's sweep tables (a column added, dropped or renamed is a change, exit 1; a whole
one without its last newline is read), bench_engines' --keep-rows (a device of an unknown kind
or a row twice is refused), gpu's --runs, history's --cache (outside results/), --against and
wheels. Nothing here downloads."""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
import zipfile
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from experiments import bench_engines, compare, gpu, history, sweep
from experiments.core import inputs, releases

from .conftest import COMMAND_TIMEOUT_S, ROOT, cheapest, run_command

GOOD = ROOT / "results" / "sweep_all_reference_r161_still.csv"
THROUGHPUT = ROOT / "results" / "bench_batches.csv"
GPU_RUNS = ROOT / "results" / "gpu_runs"
ENGINE = cheapest(batched=False)


def _code(main, argv: list[str]) -> int:
    try:
        return main(argv)
    except SystemExit as stop:
        return stop.code


def _refused(main, argv: list[str], capsys, path: Path, allowed: str) -> str:
    """``main(argv)`` exits 2 with one line on stderr naming ``path`` and what is allowed."""
    code = _code(main, argv)
    err = capsys.readouterr().err
    assert code == 2, err
    assert err.count("\n") == 1 and str(path) in err and f"allowed: {allowed}" in err, err
    assert "Traceback" not in err and "internal error" not in err, err
    return err


# -- sweep tables: compare ---------------------------------------------------------------------


def _good() -> pd.DataFrame:
    return pd.read_csv(GOOD)


def _bytes(how: str) -> bytes:
    """A sweep table damaged as ``how`` says."""
    text = GOOD.read_text()
    lines = text.splitlines(keepends=True)
    frames = {
        "engine blank": _good().assign(engine=np.nan),
        "engine numeric": _good().assign(engine=3),
        "engine blank on a row": _good().assign(engine=lambda t: t.engine.mask(t.index == 4)),
        "text in s_m": _good().assign(s_m=lambda t: t.s_m.astype(str).mask(t.index == 2, "x")),
        "a column named twice": _good().rename(columns={"v1_engine_mps": "status"}),
    }
    if how in frames:
        return frames[how].to_csv(index=False).encode()
    return {
        "empty": b"",
        "blank": b"\n\n",
        "binary": bytes(range(256)) * 4,
        "cut mid-line": "".join(lines[:5]).encode() + lines[5][: len(lines[5]) // 2].encode(),
        "cut before its last field": text.rstrip("\n").rsplit(",", 1)[0].encode(),
        "cut mid-number": _good().assign(wall_s=2e-05).to_csv(index=False).rstrip()[:-2].encode(),
        "a NUL": text.replace("\n", "\n\0", 3).encode(),
        "a throughput table": THROUGHPUT.read_bytes(),
        "header only": lines[0].encode(),
    }[how]


@pytest.mark.parametrize(
    "how",
    [
        "empty",
        "blank",
        "binary",
        "cut mid-line",
        "cut before its last field",
        "cut mid-number",
        "a NUL",
        "a throughput table",
        "header only",
        "engine blank",
        "engine numeric",
        "engine blank on a row",
        "text in s_m",
        "a column named twice",
    ],
)
def test_compare_refuses_a_damaged_table(how, tmp_path, capsys):
    bad = tmp_path / "new.csv"
    bad.write_bytes(_bytes(how))
    _refused(compare.main, [str(GOOD), str(bad)], capsys, bad, "a sweep table")
    assert sorted(tmp_path.iterdir()) == [bad]


@pytest.mark.parametrize(
    "what, said",
    [
        ("missing", "it does not exist"),
        ("directory", "it is a directory"),
        ("a link loop", "it is a symbolic link loop"),
        ("a link to nothing", "it is a symbolic link to '"),
    ],
)
def test_compare_refuses_what_is_not_a_file(what, said, tmp_path, capsys):
    path = tmp_path if what == "directory" else tmp_path / "nope.csv"
    if what.startswith("a link"):  # (a link to itself: a loop)
        path.symlink_to(path if what == "a link loop" else tmp_path / "gone.csv")
    err = _refused(compare.main, [str(path), str(GOOD)], capsys, path, "a sweep table")
    assert f"is not a file: {said}" in err, err


def test_a_whole_table_without_its_last_newline_is_compared(tmp_path, capsys):
    # written by another hand: its last line is as wide as its header and its numbers read
    (tmp_path / "new.csv").write_text(GOOD.read_text().rstrip("\n"))
    assert _code(compare.main, [str(GOOD), str(tmp_path / "new.csv")]) == 0
    said = capsys.readouterr()
    assert not said.err and said.out.endswith("no change apart from timing\n"), said


def test_compare_refuses_in_one_line_as_a_user_runs_it(tmp_path):
    (tmp_path / "cut.csv").write_bytes(_bytes("cut mid-line"))
    res = run_command(["-m", "experiments.compare", str(GOOD), str(tmp_path / "cut.csv")], code=2)
    assert res.stderr.count("\n") == 1 and "cut.csv" in res.stderr, res.stderr


def _compared(old: pd.DataFrame, new: pd.DataFrame, tmp_path, capsys) -> tuple[int, str]:
    old.to_csv(tmp_path / "old.csv", index=False)
    new.to_csv(tmp_path / "new.csv", index=False)
    code = _code(compare.main, [str(tmp_path / "old.csv"), str(tmp_path / "new.csv")])
    said = capsys.readouterr()
    assert "Traceback" not in said.err and not said.err, said.err
    return code, said.out


@pytest.mark.parametrize(
    "change, expected",
    [
        (lambda t: t.drop(columns="v1_engine_mps"), "columns dropped (1): v1_engine_mps"),
        (lambda t: t.assign(extra=1.0), "columns added (1): extra"),
        (
            lambda t: t.rename(columns={"v1_engine_mps": "v1_eng"}),
            "column renamed: v1_engine_mps -> v1_eng",
        ),
        (
            lambda t: t.rename(columns={"v1_engine_mps": "v1_eng"}).assign(
                v1_eng=lambda d: d.v1_eng + 1.0
            ),
            "columns dropped (1): v1_engine_mps",
        ),
        (
            lambda t: t.assign(
                status_old="x", status_new="y", _merge="z", s_m_new=0.0, row_old=1, side="left_only"
            ),
            "columns added (6): status_old, status_new, _merge, s_m_new, row_old, side",
        ),
    ],
    ids=["dropped", "added", "renamed", "renamed and changed", "names the comparison makes"],
)
def test_a_column_added_dropped_or_renamed_is_a_change(change, expected, tmp_path, capsys):
    code, out = _compared(_good(), change(_good()), tmp_path, capsys)
    assert code == 1 and expected in out, out


def test_columns_named_as_the_comparison_names_its_own_are_compared(tmp_path, capsys):
    # the same on both sides: no change; one of them moved: that one is said
    odd = _good().assign(status_old="x", _merge="y", s_m_new=0.5)
    code, out = _compared(odd, odd, tmp_path, capsys)
    assert code == 0 and out.endswith("no change apart from timing\n"), out
    code, out = _compared(odd, odd.assign(_merge="z"), tmp_path, capsys)
    assert code == 1 and "_merge: " in out and "status_old" not in out, out


def test_a_timing_column_dropped_is_no_change(tmp_path, capsys):
    code, out = _compared(_good(), _good().drop(columns="wall_s"), tmp_path, capsys)
    assert code == 0 and out.endswith("no change apart from timing\n"), out


def test_a_flight_sweep_against_a_plain_one_names_the_columns_it_adds(tmp_path):
    tables = {}
    for name, extra in (("plain", []), ("flight", ["--flight"])):
        assert (
            sweep.main(
                [
                    "--engine",
                    ENGINE,
                    "--points",
                    "3",
                    *extra,
                    "--out",
                    str(tmp_path),
                    "--name",
                    name,
                ]
            )
            == 0
        )
        tables[name] = tmp_path / name / "sweep.csv"
    res = run_command(
        ["-m", "experiments.compare", str(tables["plain"]), str(tables["flight"])], code=1
    )
    added = [
        c
        for c in pd.read_csv(tables["flight"]).columns
        if c not in pd.read_csv(tables["plain"]).columns
    ]
    assert added and f"columns added ({len(added)}): {', '.join(added)}" in res.stdout


def test_every_committed_table_is_what_it_must_be():
    # no false alarm on the files the project writes
    for path in ROOT.glob("results/sweep_*.csv"):
        inputs.table(path, inputs.SWEEP)
    for path in (THROUGHPUT, *GPU_RUNS.glob("*/bench_batches.csv")):
        inputs.table(path, inputs.THROUGHPUT)
    for run in GPU_RUNS.glob("*/run.json"):
        gpu.check_run(run.parent)
        assert inputs.run_date(run).tzinfo is not None


# -- throughput tables: bench_engines --keep-rows ----------------------------------------------


def _bench(keep: Path, out: Path) -> list[str]:
    return [
        "--batches-only",
        "--quick",
        "--engine",
        ENGINE,
        "--batches",
        "1",
        "--keep-rows",
        str(keep),
        "--out",
        str(out),
    ]


def _throughput(how: str, path: Path) -> Path:
    """A throughput table at ``path``, damaged as ``how`` says (missing: none)."""
    if how == "directory":
        path.mkdir()
        return path
    text = THROUGHPUT.read_text()
    lines = text.splitlines(keepends=True)
    damaged = {
        "sweep table": GOOD.read_text(),
        "empty": "",
        "binary": bytes(range(256)),
        "cut mid-line": "".join(lines[:3]) + lines[3][:20],
        "cut before its last field": text.rstrip("\n").rsplit(",", 1)[0],
        "unknown device": text.replace(",cpu,", ",tpu,"),
        "a row twice": text + "".join(lines[1:3]),
        "unregistered engine": text.replace(lines[1].split(",")[0] + ",", "noengine,", 1),
        "text in batch": pd.read_csv(THROUGHPUT)
        .astype({"batch": str})
        .assign(batch=lambda t: t.batch.mask(t.index == 1, "ten"))
        .to_csv(index=False),
    }.get(how)
    if isinstance(damaged, bytes):
        path.write_bytes(damaged)
    elif damaged is not None:
        path.write_text(damaged)
    return path


@pytest.mark.parametrize(
    "how",
    [
        "missing",
        "directory",
        "sweep table",
        "binary",
        "empty",
        "cut mid-line",
        "cut before its last field",
        "unregistered engine",
        "text in batch",
        "unknown device",
        "a row twice",
    ],
)
def test_keep_rows_must_be_a_throughput_table(how, tmp_path, capsys):
    bad = _throughput(how, tmp_path / "keep.csv")
    out = tmp_path / "out"
    err = _refused(bench_engines.main, _bench(bad, out), capsys, bad, "a throughput table")
    rows = len(THROUGHPUT.read_text().splitlines())
    assert {
        "unknown device": "has device 'tpu' on row ",
        "a row twice": f"has row {rows} the same as row 1 (engine ",
    }.get(how, "") in err, err
    assert not out.exists()


def test_keep_rows_a_directory_as_a_user_runs_it(tmp_path):
    res = run_command(
        ["-m", "experiments.bench_engines", *_bench(tmp_path, tmp_path / "out")], code=2
    )
    assert "it is a directory" in res.stderr and res.stderr.count("\n") == 1


def test_keep_rows_by_default_is_the_committed_table_and_its_absence_is_said(
    monkeypatch, capsys, tmp_path
):
    p = bench_engines.COMMAND.parser()
    args = p.parse_args(["--batches-only", "--engine", ENGINE])
    bench_engines._check(p, args)
    assert args.keep_rows == THROUGHPUT
    monkeypatch.setattr(bench_engines, "KEEP_ROWS", ROOT / "results" / "absent.csv")
    args = p.parse_args(["--batches-only", "--engine", ENGINE])
    bench_engines._check(p, args)
    err = capsys.readouterr().err
    assert args.keep_rows is None and err.count("\n") == 1 and "absent.csv is absent" in err


# -- a GPU machine's runs: gpu --runs ------------------------------------------------------------


def _json(path: Path, change) -> Path:
    path.write_text(json.dumps(change(json.loads(path.read_text()))))
    return path


def _cut(path: Path, keep: float = 0.5) -> Path:
    data = path.read_bytes().rstrip(b"\n")
    path.write_bytes(data[: int(len(data) * keep)])
    return path


DAMAGE = {  # what to break in a copy of results/gpu_runs: the file broken
    "run.json without date_utc": lambda r: _json(
        r / "bench_mjwarp" / "run.json", lambda d: {k: d[k] for k in d if k != "date_utc"}
    ),
    "run.json garbled": lambda r: _cut(r / "twins_mjx" / "run.json"),
    "run.json a list": lambda r: _json(r / "twins_mjx" / "run.json", lambda d: [d]),
    "date_utc not a date": lambda r: _json(
        r / "twins_mjx" / "run.json", lambda d: {**d, "date_utc": "yesterday"}
    ),
    "bench_batches.csv cut mid-line": lambda r: _cut(
        r / "bench_newton_2" / "bench_batches.csv", 0.8
    ),
    "bench_batches.csv with text": lambda r: _text_in(r / "bench_mjx_2" / "bench_batches.csv"),
    "twins.csv of another kind": lambda r: shutil.copy(GOOD, r / "twins_mjx" / "twins.csv"),
    "stability_cells.csv gone": lambda r: _gone(r / "stability_warp" / "stability_cells.csv"),
    "stability.json garbled": lambda r: _cut(r / "stability_warp" / "stability.json"),
    "session.json garbled": lambda r: _cut(r / "session.json"),
}


def _text_in(path: Path) -> Path:
    table = pd.read_csv(path).astype({"impacts_per_s": str})
    table.loc[0, "impacts_per_s"] = "fast"
    table.to_csv(path, index=False)
    return path


def _gone(path: Path) -> Path:
    path.unlink()
    return path


@pytest.fixture
def runs(tmp_path) -> Path:
    shutil.copytree(GPU_RUNS, tmp_path / "runs")
    return tmp_path / "runs"


@pytest.mark.parametrize("how", list(DAMAGE))
def test_gpu_refuses_a_damaged_run(how, runs, tmp_path, capsys):
    bad = Path(DAMAGE[how](runs))
    out = tmp_path / "out"
    _refused(gpu.main, ["--runs", str(runs), "--out", str(out)], capsys, bad, "")
    assert not out.exists()


@pytest.mark.parametrize("what", ["a file", "missing"])
def test_gpu_refuses_runs_that_are_not_a_folder(what, tmp_path, capsys):
    path = tmp_path / "runs"
    if what == "a file":
        path.write_text("x\n")
    _refused(
        gpu.main,
        ["--runs", str(path), "--out", str(tmp_path / "out")],
        capsys,
        path,
        "a folder of the runs",
    )


def test_gpu_gathers_a_copy_and_refuses_it_damaged_as_a_user_runs_it(runs, tmp_path):
    run_command(["-m", "experiments.gpu", "--runs", str(runs), "--out", str(tmp_path / "ok")])
    DAMAGE["run.json garbled"](runs)
    res = run_command(
        ["-m", "experiments.gpu", "--runs", str(runs), "--out", str(tmp_path / "bad")], code=2
    )
    assert "twins_mjx/run.json' is not JSON" in res.stderr and res.stderr.count("\n") == 1
    assert not (tmp_path / "bad").exists()


# -- history: its options and its cache -----------------------------------------------------------


def _history(tmp_path: Path, *argv: str) -> list[str]:
    return ["--engine", ENGINE, *argv, "--out", str(tmp_path / "out")]


@pytest.mark.parametrize(
    "what",
    [
        "a file",
        "under a file",
        "unwritable",
        "empty",
        "results/",
        "under results/",
        "a link into results/",
        "its python's a file",
    ],
)
def test_the_cache_must_be_a_directory_one_can_write_to(what, tmp_path, capsys):
    # one that holds this Python's environments, made by history, outside the committed results/
    (tmp_path / "file").write_text("x\n")
    (tmp_path / "link").symlink_to(ROOT / "results")
    (tmp_path / releases.python_tag()).write_text("x\n")
    cache = {
        "a file": tmp_path / "file",
        "under a file": tmp_path / "file" / "cache",
        "unwritable": Path("/proc/batsim-cache"),
        "empty": "",
        "results/": ROOT / "results",
        "under results/": ROOT / "results" / "x" / ".." / "cache",
        "a link into results/": tmp_path / "link" / "cache",
        "its python's a file": tmp_path,
    }[what]
    err = _refused(
        history.main,
        _history(tmp_path, "--versions", "1.0,2.0", "--cache", str(cache)),
        capsys,
        cache,
        "a directory for the release environments",
    )
    assert "results/" not in what or "is inside results/" in err
    assert not (ROOT / "results" / "cache").exists()


def test_a_file_where_an_environment_goes_is_said_and_left(tmp_path):
    release = releases.Release(engine=ENGINE, version="1.0")
    (env := releases.place(release, tmp_path)).parent.mkdir(parents=True)
    env.write_text("mine\n")
    with pytest.raises(releases.NotInstallable, match="is a file .*: move it away"):
        releases.environment(release, tmp_path, lambda r, t: {})
    assert env.read_text() == "mine\n"


#: Root writes into a read-only directory; without these capabilities it does not.
AS_A_USER = ["setpriv", "--bounding-set", "-dac_override,-dac_read_search", "--"]


@pytest.mark.skipif(
    os.geteuid() == 0 and not shutil.which("setpriv"),
    reason="root writes into a read-only directory",
)
def test_a_read_only_cache_is_refused(tmp_path, capsys):
    cache = tmp_path / "cache"
    cache.mkdir(mode=0o555)
    argv = [
        "-m",
        "experiments.history",
        *_history(tmp_path, "--versions", "1.0,2.0", "--cache", str(cache)),
    ]
    if os.geteuid() != 0:
        res = run_command(argv, code=2)
    else:  # as root, dropping the capabilities that ignore a directory's mode
        res = subprocess.run(
            [*AS_A_USER, sys.executable, *argv],
            cwd=ROOT,
            text=True,
            capture_output=True,
            timeout=COMMAND_TIMEOUT_S,
            check=False,
        )
        assert res.returncode == 2, res.stderr
    assert res.stderr.count("\n") == 1 and "Traceback" not in res.stderr, res.stderr
    assert f"{str(cache)!r} cannot hold new files (Permission denied" in res.stderr
    assert "allowed: a directory for the release environments" in res.stderr
    assert not (tmp_path / "out").exists()


def _wheel(path: Path, name: str) -> Path:
    with zipfile.ZipFile(path, "w") as archive:
        archive.writestr(f"{name}-1.0.dist-info/METADATA", f"Name: {name}\nVersion: 1.0\n")
    return path


@pytest.mark.parametrize("what", ["not a zip", "not a wheel", "another package's"])
def test_a_wheel_must_be_one_of_the_engines_package(what, tmp_path, capsys):
    path = tmp_path / "other-1.0-py3-none-any.whl"
    if what == "not a zip":
        path.write_text("x\n")
    elif what == "not a wheel":
        with zipfile.ZipFile(path, "w") as archive:
            archive.writestr("readme.txt", "x")
    else:
        _wheel(path, "other")
    allowed = "a wheel of" if what == "another package's" else "the path of a wheel"
    _refused(
        history.main,
        _history(
            tmp_path,
            "--versions",
            str(path),
            "--against",
            "1.0",
            "--cache",
            str(tmp_path / "cache"),
        ),
        capsys,
        path,
        allowed,
    )
