"""Every command survives what a user types. For command lines drawn from the command's own
parser (its options, with values in range, out of range, of the wrong kind, empty; options
repeated or unknown; flags; files that are not tables), a command either refuses with exit 2
and one line before any work, or checks everything and starts the work; never a traceback.
The work is where every command hands its body to ``cli.main_guard``: the test stops it there
(compare, which only reads its two files, runs whole: a column dropped or added is a change)."""

from __future__ import annotations

import argparse
import csv
import io
import shutil
from pathlib import Path

import pytest
from hypothesis import HealthCheck, event, given, settings
from hypothesis import strategies as st

import adapters
from experiments import compare
from experiments.core import cli
from experiments.core.io import ROOT
from experiments.core.tables import TIMING_COLUMNS
from experiments.parts.sweep_options import build_parser

from .conftest import COMMANDS, examples

PARSERS = {"sweep": build_parser}
#: Values of the wrong kind or out of any range, beside each option's own.
JUNK = [
    "",
    " ",
    "nan",
    "inf",
    "-inf",
    "-1",
    "0",
    "1e300",
    "-1e-300",
    "x",
    "1,2",
    "0x10",
    "--",
    "🦇",
    "1" * 400,
]
#: Engine lists: registered names, 'all', and names no engine has (a registered one in capitals)
ENGINES = st.lists(
    st.sampled_from([*adapters.names(), "all", "nope", "", adapters.names()[0].upper()]),
    min_size=1,
    max_size=3,
).map(",".join)


class Started(BaseException):
    """The command checked every option and handed its body to cli.main_guard (a
    BaseException, as a signal is: the command's error boundary lets it through)."""


def _parser(name: str) -> argparse.ArgumentParser:
    if name in PARSERS:
        return PARSERS[name]()
    module = COMMANDS[name]
    return module.COMMAND.parser() if hasattr(module, "COMMAND") else module.build_parser()


def _value(action: argparse.Action, tmp: str) -> st.SearchStrategy[str]:
    """A value for an option: one it offers, a number of any size, or junk."""
    own = [st.sampled_from(list(map(str, action.choices)))] if action.choices else []
    if isinstance(action.default, int | float) and not isinstance(action.default, bool):
        own.append(st.just(str(action.default)))  # the default: most lines get far
    if action.dest == "engine":
        own.append(ENGINES)
    if action.dest in ("out", "results"):
        own.append(st.sampled_from([tmp, f"{tmp}/new", "/proc/x", "~nosuchuser/x", "a" * 300]))
    if action.dest == "scheduler":
        own.append(st.sampled_from(["local", "tcp://127.0.0.1:1", "tcp://[::1", "x:y"]))
    numbers = st.one_of(
        st.integers(-(10**6), 10**6).map(str),
        st.floats(allow_nan=True, allow_infinity=True).map(repr),
    )
    return st.one_of(*own, numbers, st.sampled_from(JUNK))


@st.composite
def command_lines(draw, parser: argparse.ArgumentParser, tmp: str) -> list[str]:
    options = [a for a in parser._actions if a.option_strings and a.dest != "help"]
    argv: list[str] = []
    for action in draw(st.lists(st.sampled_from(options), max_size=6)):  # repeats included
        argv.append(draw(st.sampled_from(action.option_strings)))
        if action.nargs == 0:
            continue
        count = action.nargs if isinstance(action.nargs, int) else 1
        argv += [draw(_value(action, tmp)) for _ in range(count)]
    if draw(st.booleans()):
        argv.insert(
            draw(st.integers(0, len(argv))), draw(st.sampled_from(["--nope", "-x", "stray"]))
        )
    return argv


def _outcome(main, argv: list[str], capsys) -> tuple[object, str]:
    try:
        code = main(argv)
    except SystemExit as stop:
        code = stop.code
    except Started:
        code = "started"
    return code, capsys.readouterr().err


@pytest.mark.parametrize("name", sorted(set(COMMANDS) - {"compare"}))
def test_a_command_refuses_in_one_line_or_starts(name, tmp_path, monkeypatch, capsys):
    def stop(body):
        raise Started

    monkeypatch.setattr(cli, "main_guard", stop)
    monkeypatch.setenv("BATSIM_QUIET", "1")
    monkeypatch.chdir(tmp_path)  # a relative --out drawn (a run's folder is made) lands here
    parser = _parser(name)
    has_out = any("--out" in a.option_strings for a in parser._actions)
    for mine in (".mydata.old-2019", ".photos.ab12cd34.tmp"):  # a user's, named like ours
        (tmp_path / mine).mkdir()
        (tmp_path / mine / "keep.txt").write_text("the user's")
    kept = _snapshot(tmp_path, ROOT / "results")

    @settings(
        max_examples=examples(100),
        deadline=None,
        derandomize=False,
        suppress_health_check=[HealthCheck.function_scoped_fixture],
    )
    @given(argv=command_lines(parser, str(tmp_path)))
    def check(argv):
        if has_out and "--out" not in argv:  # a run that starts would go to tmp_path
            argv = [*argv, "--out", str(tmp_path)]
        code, err = _outcome(COMMANDS[name].main, argv, capsys)
        event(f"exit {code}")
        assert code in ("started", 2), (argv, code, err)
        assert "Traceback" not in err, (argv, err)
        if code == 2:  # one line, the command's
            assert err.count("\n") == 1 and err.startswith(parser.prog), (argv, err)
        now = _snapshot(tmp_path, ROOT / "results")  # what was there is as it was
        assert {p: now.get(p) for p in kept} == kept, argv

    check()


#: Names a column added to a table may have: any, and those a comparison's merge makes.
ADDED = ["extra", "status_old", "status_new", "_merge", "s_m_new", "row_old", "side"]


def _columns(good: str, drop: int | None, add: str | None) -> bytes:
    """The table with column ``drop`` removed, or a column named ``add`` added (all 1)."""
    rows = list(csv.reader(io.StringIO(good)))
    for i, row in enumerate(rows):
        if drop is not None:
            del row[drop]
        if add is not None:
            row.append(add if i == 0 else "1")
    out = io.StringIO()
    csv.writer(out, lineterminator="\n").writerows(rows)
    return out.getvalue().encode()


@st.composite
def tables(draw, good: str) -> tuple[bytes, str, int]:
    """A sweep table's bytes, damaged or not, and how: cut mid-row, a value blanked or made
    text or NaN, a row repeated, binary junk after the header, nothing at all, a column dropped
    or one added (named as the comparison's own, maybe)."""
    lines = good.splitlines(keepends=True)
    how = draw(
        st.sampled_from(
            [
                "same",
                "cut",
                "blank",
                "text",
                "nan",
                "repeat",
                "junk",
                "empty",
                "drop column",
                "add column",
            ]
        )
    )
    row = draw(st.integers(1, len(lines) - 1))
    cells = lines[row].rstrip("\n").split(",")
    col = draw(st.integers(0, len(cells) - 1))
    if how == "drop column":
        return _columns(good, col, None), how, col
    if how == "add column":
        return _columns(good, None, draw(st.sampled_from(ADDED))), how, 0
    if how == "cut":
        return "".join(lines[:row]).encode() + lines[row][: len(lines[row]) // 2].encode(), how, 0
    if how in ("blank", "text", "nan"):
        if cells[col] in ("", "nan"):  # blank already: not a change; another cell is
            col = next(i for i, c in enumerate(cells) if c not in ("", "nan"))
        cells[col] = {"blank": "", "text": "x", "nan": "nan"}[how]
        lines[row] = ",".join(cells) + "\n"
    if how == "repeat":
        lines.insert(row, lines[row])
    if how == "junk":
        return lines[0].encode() + bytes(range(256)), how, 0
    return ("" if how == "empty" else "".join(lines)).encode(), how, col


def test_compare_judges_any_pair_of_files(tmp_path, capsys):
    good = (ROOT / "results" / "sweep_all_reference_r161_still.csv").read_text()

    @settings(
        max_examples=examples(100),
        deadline=None,
        suppress_health_check=[HealthCheck.function_scoped_fixture],
    )
    @given(new=tables(good), missing=st.booleans())
    def check(new, missing):
        (tmp_path / "new.csv").write_bytes(new[0])
        old = tmp_path / ("absent.csv" if missing else "old.csv")
        (tmp_path / "old.csv").write_text(good)
        code, err = _outcome(compare.main, [str(old), str(tmp_path / "new.csv")], capsys)
        how, col = new[1], good.split("\n", 1)[0].split(",")[new[2]]
        event(f"{how}: exit {code}")
        assert "Traceback" not in err
        if missing or how in ("junk", "empty"):
            assert code == 2 and err.count("\n") == 1, (how, err)
        elif how == "same":
            assert code == 0, err
        elif how == "drop column" and col in compare.KEYS + ["status", "v1_abs_err_mps"]:
            assert code == 2 and f"no column {col!r}" in err, (how, col, err)
        elif how in ("drop column", "add column"):  # a change unless it is timing's
            assert code == (0 if col in TIMING_COLUMNS else 1), (how, col, err)
        elif col not in TIMING_COLUMNS:  # damage anywhere but a timing column: 1 or 2
            assert code in (1, 2), (how, col, err)

    check()


def _snapshot(*roots: Path) -> dict[Path, bytes]:
    """Every file under ``roots`` with its bytes (what a command must leave as it was)."""
    return {p: p.read_bytes() for r in roots for p in sorted(r.rglob("*")) if p.is_file()}


@pytest.mark.parametrize(
    "name,option,good",
    [
        ("bench_engines", "--keep-rows", "bench_batches.csv"),
        ("gpu", "--runs", "gpu_runs/bench_newton_1/bench_batches.csv"),
        ("gpu", "--runs", "gpu_runs/bench_newton_1/run.json"),
    ],
)
def test_a_damaged_file_handed_in_is_refused_in_one_line(
    name, option, good, tmp_path, monkeypatch, capsys
):
    # Files from the generator of damaged tables (and a run.json cut, emptied, made junk),
    # handed to the command that reads them: it refuses in one line (exit 2) before any work,
    # or, for a file still whole, starts; the file and everything beside it is left as it was.
    monkeypatch.setattr(cli, "main_guard", lambda body: (_ for _ in ()).throw(Started()))
    monkeypatch.setenv("BATSIM_QUIET", "1")
    source = ROOT / "results" / good
    text = source.read_text()
    mine = tmp_path / "mine.txt"
    mine.write_text("the user's")

    @settings(
        max_examples=examples(60),
        deadline=None,
        suppress_health_check=[HealthCheck.function_scoped_fixture],
    )
    @given(
        damaged=tables(text)
        if good.endswith(".csv")
        else st.sampled_from(
            [
                text[: len(text) // 2],
                "",
                "\x00\xff",
                "[1, 2]",
                text.replace('"date_utc"', '"date"'),
                text,
            ]
        ).map(lambda t: (t.encode(), "json", 0))
    )
    def check(damaged):
        folder = tmp_path / "in"
        shutil.rmtree(folder, ignore_errors=True)
        if option == "--runs":  # a copy of the run folder, one file of it damaged
            shutil.copytree(source.parent, folder / source.parent.name)
            target, handed = folder / source.parent.name / source.name, folder
        else:
            folder.mkdir()
            target = handed = folder / source.name
        target.write_bytes(damaged[0])
        before = _snapshot(tmp_path)
        code, err = _outcome(
            COMMANDS[name].main, [option, str(handed), "--out", str(tmp_path / "out")], capsys
        )
        event(f"{damaged[1]}: exit {code}")
        assert code in ("started", 2), (damaged[1], code, err)
        assert "Traceback" not in err
        after = _snapshot(tmp_path)
        if code == 2:  # refused before any work: nothing made either
            assert err.count("\n") == 1 and str(target.name) in err, (damaged[1], err)
            assert after == before
        assert {p: after.get(p) for p in before} == before

    check()


#: Environment variables a user may have set, and values for them.
ENVIRONMENT = {
    "BATSIM_QUIET": ["1", "0", "", " yes ", "2", "quiet", "\u00e9"],
    "BATSIM_DEBUG": ["1", "0", "", "TRUE", "verbose", "-1"],
    "MPLBACKEND": ["agg", "Agg", "tkagg", "nope", "", "module://nowhere"],
    "PYTHONIOENCODING": ["ascii", "utf-8", "latin-1"],
    "BATSIM_WARP_DEVICE": ["cpu", "cuda:0", "bogus", "cuda:x", ""],
    "BATSIM_DEVICE_EPISODE": ["auto", "1", "0", "", "yes", "gpu"],
}


@pytest.mark.parametrize("name", ["sweep", "stability", "check_engine", "report"])
def test_the_environment_is_refused_in_one_line_or_used(name, tmp_path, monkeypatch, capsys):
    # Any mix of these variables: the command refuses in one line naming the variable (exit
    # 2) before any work, or starts.
    monkeypatch.setattr(cli, "main_guard", lambda body: (_ for _ in ()).throw(Started()))
    monkeypatch.chdir(tmp_path)

    @settings(
        max_examples=examples(60),
        deadline=None,
        suppress_health_check=[HealthCheck.function_scoped_fixture],
    )
    @given(
        env=st.dictionaries(
            st.sampled_from(sorted(ENVIRONMENT)), st.sampled_from(range(7)), max_size=4
        )
    )
    def check(env):
        chosen = {k: ENVIRONMENT[k][i % len(ENVIRONMENT[k])] for k, i in env.items()}
        with pytest.MonkeyPatch.context() as mp:
            for key in ENVIRONMENT:
                mp.delenv(key, raising=False)
            for key, value in chosen.items():
                mp.setenv(key, value)
            argv = ["--out", str(tmp_path)] if name != "check_engine" else []
            code, err = _outcome(COMMANDS[name].main, argv, capsys)
        event(f"exit {code}")
        assert code in ("started", 2), (chosen, code, err)
        assert "Traceback" not in err
        if code == 2:
            assert err.count("\n") == 1 and any(k in err for k in chosen), (chosen, err)

    check()
