"""``experiments.history``: release environments made once and reused (an interrupted or a
damaged one made again, offline: a row that says so), the engine's own pins freed, a candidate
that loses a verdict or lets an error grow past its tolerance exits 1, as does one checked
against a release that was not judged (a probe failed, hung, garbled), with no install (stand-in
environments); then, in the full tier, the README's lines as a user runs them: two releases
installed on a cold cache and judged, and a version that does not exist is a row that says so."""

from __future__ import annotations

import json
import re
import shlex
import shutil
import subprocess
import sys
import time
from pathlib import Path

import pandas as pd
import pytest

import adapters
from experiments import history
from experiments.core import releases
from experiments.core.judge import Status
from experiments.parts import history_probe

from .conftest import ROOT, cheapest, run_command

#: uv pointed at an index that cannot be reached, at once: nothing is downloaded.
OFFLINE = {
    "UV_DEFAULT_INDEX": "http://127.0.0.1:1/simple",
    "UV_INDEX_URL": "http://127.0.0.1:1/simple",
    "UV_NO_CONFIG": "1",
    "UV_HTTP_RETRIES": "0",
}
README = (ROOT / "README.md").read_text()
#: The README's history lines: the spread of two releases, and a candidate checked.
LINES = [
    shlex.split(m.group(0))
    for lang, text in re.findall(r"```(\w+)\n(.*?)```", README, re.S)
    if lang == "sh"
    for m in re.finditer(r"python -m experiments\.history[^\n#]*", text)
]
#: The most the README's two-release line may take on a cold cache (the issue's bar: 10 min).
COLD_LIMIT_S = 600.0


def _release(version: str = "1.0") -> releases.Release:
    return releases.Release(engine=cheapest(batched=False), version=version)


def fake_environment(target, installed: dict) -> dict:
    """What an install leaves (``releases.fault`` finds it whole): a python, pyvenv.cfg and a
    dist-info per distribution installed; ``installed``, as an installer returns it."""
    (target / "bin").mkdir(parents=True)
    (target / "bin" / "python").write_text("#!/bin/sh\n")
    (target / "bin" / "python").chmod(0o755)
    (target / "pyvenv.cfg").write_text("home = /usr/bin\n")
    site = target / "lib" / f"python{sys.version_info.major}.{sys.version_info.minor}"
    for name, version in installed.items():
        (site / "site-packages" / f"{name.replace('-', '_')}-{version}.dist-info").mkdir(
            parents=True
        )
    return installed


def test_an_environment_is_made_once_then_reused(tmp_path):
    made = []

    def installer(release, target):
        made.append(release.version)
        return fake_environment(target, {"made": release.version})

    first = releases.environment(_release(), tmp_path, installer)
    again = releases.environment(_release(), tmp_path, installer)
    assert first == again and made == ["1.0"]
    assert releases.installed(first) == {"made": "1.0"}


def test_an_interrupted_install_is_made_again(tmp_path):
    def interrupted(release, target):
        (target / "bin").mkdir(parents=True)
        raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        releases.environment(_release(), tmp_path, interrupted)
    assert not any(p.is_dir() for p in (tmp_path / releases.python_tag()).iterdir()), (
        "a partial environment left"
    )
    made = []
    releases.environment(_release(), tmp_path, lambda r, t: made.append(t) or {})
    assert len(made) == 1


def _made(tmp_path: Path) -> tuple[releases.Release, Path]:
    """A release's environment made in a scratch cache, whole, by a stand-in installer."""
    release = releases.Release(engine=cheapest(batched=False), version="1.0")
    python = releases.environment(
        release, tmp_path, lambda r, t: fake_environment(t, {"numpy": "2.0", "b-c": "1"})
    )
    return release, python.parent.parent


BREAK = {
    "its python deleted": lambda env: (env / "bin" / "python").unlink(),
    "its python a link to nothing": lambda env: (
        (env / "bin" / "python").unlink(),
        (env / "bin" / "python").symlink_to(env / "x"),
    ),
    "half deleted": lambda env: shutil.rmtree(env / "lib"),
    "a distribution gone": lambda env: shutil.rmtree(next(env.rglob("b_c-1.dist-info"))),
    "no pyvenv.cfg": lambda env: (env / "pyvenv.cfg").unlink(),
    "ready.json garbled": lambda env: (env / releases.READY).write_text("{"),
}


@pytest.mark.parametrize("how", list(BREAK))
def test_a_damaged_environment_is_made_again(how, tmp_path, capsys):
    release, env = _made(tmp_path)
    assert releases.fault(env) is None
    BREAK[how](env)
    assert releases.fault(env) is not None
    made = []
    releases.environment(
        release, tmp_path, lambda r, t: made.append(t) or fake_environment(t, {"numpy": "2.0"})
    )
    assert made == [env] and releases.fault(env) is None
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and f"{env} is broken" in err and "made again" in err


def test_the_engines_own_pins_are_freed_and_the_harness_pins_kept():
    pinned = {releases._name(ln) for ln in (ROOT / "constraints.txt").read_text().split()}
    name = next(
        n for n in adapters.names() if releases._name(adapters.record(n).install.package) in pinned
    )
    package = releases._name(adapters.record(name).install.package)
    kept = {
        releases._name(ln)
        for ln in releases.constraints(releases.Release(engine=name, version="0")).split()
    }
    assert package not in kept and "numpy" in kept
    assert not any(p.startswith(package + "-") for p in kept)  # nor its family (package-core)


def _result(version: str, err_mps: float, status: str = "ok") -> dict:
    rows = [
        {
            "grid": "swing",
            "s_m": s,
            "status": status,
            "err_mps": err_mps,
            "tol_mps": 1e-6,
            "wall_s": 1e-4,
        }
        for s in (-0.1, 0.1)
    ]
    return {
        "engine": "e",
        "release": version,
        "state": "judged",
        "version": version,
        "rows": rows,
        "checks": [{"check": "still_bat", "passed": True, "detail": "ok"}],
        "defaults": {"dt_s": "0.01"},
    }


@pytest.mark.parametrize(
    "candidate, code",
    [
        (_result("2", 1e-9), 0),  # within 1e-6 m/s of the reference's error
        (_result("2", 5e-6), 1),  # grew past its tolerance
        (_result("2", 1e-9, status="inaccurate"), 1),  # a verdict lost
        ({**_result("2", 1e-9), "rows": []}, 1),  # every grid raised, the checks ran
        ({**_result("2", 1e-9), "rows": [], "checks": []}, 1),  # nothing judged: not checked
    ],
    ids=["unchanged", "error grew", "verdict lost", "no grid fired", "nothing judged"],
)
def test_a_candidate_exits_1_on_a_regression(monkeypatch, tmp_path, candidate, code):
    # |err candidate - err reference| > tol is a moved error; a grown one regresses
    results = {"1": _result("1", 1e-9), "2": candidate}
    monkeypatch.setattr(history, "fire_release", lambda e, v, cache: {**results[v], "engine": e})
    name = cheapest(batched=False)
    out = tmp_path / "out"
    assert (
        history.main(
            [
                "--engine",
                name,
                "--versions",
                "1,2",
                "--cache",
                str(tmp_path),
                "--out",
                str(out),
                "--name",
                "h",
            ]
        )
        == code
    )
    page = (out / "h" / "history.md").read_text()
    assert ("(regression)" in page) == bool(code)
    assert len(pd.read_csv(out / "h" / "history.csv")) == 2


def test_a_spread_that_judged_nothing_fails(monkeypatch, tmp_path, capsys):
    # no --versions: every release of the record's spread failed its probe: exit 1, one line
    monkeypatch.setattr(
        history,
        "fire_release",
        lambda e, v, cache: {
            "engine": e,
            "release": v,
            "state": "probe_failed",
            "reason": "exit 3: boom",
        },
    )
    name = cheapest(batched=False)
    first = adapters.record(name).install.history[0]
    assert (
        history.main(["--engine", name, "--cache", str(tmp_path), "--out", str(tmp_path / "out")])
        == 1
    )
    assert capsys.readouterr().err == (
        f"history: no release could be judged ({name} {first}: probe_failed: exit 3: boom); "
        "history.csv has each release's reason\n"
    )


def test_a_release_that_imports_what_it_does_not_declare_is_judged_with_it(monkeypatch):
    # a build against NumPy 1 fails to import under NumPy 2: judged again with numpy<2 added
    made = []

    def fire(release, cache):
        made.append(release.extras)
        if not release.extras:
            return {
                "state": Status.UNSUPPORTED.value,
                "reason": "ImportError: numpy.core.multiarray failed to import",
            }
        return {"state": "judged", "reason": ""}

    monkeypatch.setattr(history, "_fire", fire)
    result = history.fire_release(cheapest(batched=False), "1.0", ROOT)
    assert made == [(), ("numpy<2",)] and result["extras"] == "numpy<2"
    assert result["state"] == "judged"


def test_the_readme_shows_the_history_lines():
    assert len(LINES) == 2 and all("--versions" in line for line in LINES), LINES


def _history(argv: list[str], out, code: int = 0) -> pd.DataFrame:
    """``python -m experiments.history ARGV`` with a scratch cache and ``out``: its rows."""
    run_command([*argv, "--cache", str(out.parent / "cache"), "--out", str(out)], code=code)
    (table,) = out.rglob("history_rows.csv")
    return pd.read_csv(table).drop(columns="wall_s")


@pytest.mark.full
def test_the_readme_history_lines_on_a_cold_cache(tmp_path):
    # two releases judged, the same on a Dask cluster; the candidate line; the candidate's own
    # wheel judged as its release is; a version that does not exist: a row that says so, and
    # every verdict lost against the release before it (exit 1)
    spread, candidate = LINES
    t0 = time.perf_counter()
    rows = _history(spread[1:], tmp_path / "serial")
    assert time.perf_counter() - t0 < COLD_LIMIT_S
    (table,) = (tmp_path / "serial").rglob("history.csv")
    judged = pd.read_csv(table).query("state == 'judged'")
    assert judged.release.nunique() == 2 and (judged.ok > 0).any()
    pd.testing.assert_frame_equal(
        rows, _history([*spread[1:], "--workers", "2", "--scheduler", "local"], tmp_path / "dask")
    )
    _history(candidate[1:], tmp_path / "candidate")
    engine = spread[spread.index("--engine") + 1]
    released = candidate[candidate.index("--versions") + 1]
    wheels = tmp_path / "wheels"
    subprocess.run(
        [
            sys.executable,
            "-m",
            "pip",
            "download",
            "--quiet",
            "--no-deps",
            "--only-binary",
            ":all:",
            "-d",
            str(wheels),
            f"{adapters.record(engine).install.package}=={released}",
        ],
        check=True,
        timeout=COLD_LIMIT_S,
    )
    (wheel,) = wheels.glob("*.whl")
    both = _history(
        [*spread[1:3], "--engine", engine, "--versions", str(wheel), "--against", released],
        tmp_path / "wheel",
    )
    as_released, as_wheel = (
        g.drop(columns="release").reset_index(drop=True)
        for _, g in both.groupby("release", sort=False)
    )
    pd.testing.assert_frame_equal(as_released, as_wheel)
    bad = released + ".999"
    _history([*spread[1:3], "--engine", engine, "--versions", bad], tmp_path / "bad", code=1)
    (table,) = (tmp_path / "bad").rglob("history.csv")
    rows = pd.read_csv(table).set_index("release")
    assert rows.loc[bad, "state"] == "not_installable" and "no version" in rows.loc[bad, "reason"]


def test_each_records_oldest_release_is_the_first_the_history_judged():
    # results/history.csv (python -m experiments.baselines --only history): every release a
    # record lists was fired, and the oldest release it says its adapter drives is the first
    # one there that was judged (older ones: not installable, or not driven, with the reason)
    table = pd.read_csv(ROOT / "results" / "history.csv", dtype={"release": str})
    for name in adapters.names():
        install = adapters.record(name).install
        rows = table[table.engine == name]
        assert list(dict.fromkeys(rows.release)) == list(install.history), name
        if install.history:
            judged = rows[rows.state == "judged"].release
            assert judged.iloc[0] == install.oldest, (name, install.oldest)


# -- a candidate check that judged nothing, the cache, a probe that hangs (no install) ---------

#: What a release's stand-in python does when probed (a shell script, given the probe's argv),
#: and why the release could not be judged.
GARBLED = "probe_failed: its result is not the probe's: "
PROBES = {
    "exits 3": ("echo 'no such module' >&2; exit 3", "probe_failed: exit 3: no such module"),
    "writes a list": ('printf "[1,2,3]" > "$OUT"', GARBLED + "a JSON list, not an object"),
    "writes an empty object": (
        'printf "{}" > "$OUT"',
        GARBLED + "an object with neither 'rows' nor 'not_driven'",
    ),
    "judges nothing": (
        'printf \'{"rows": [], "errors": {"still": "ValueError: boom"}}\' > "$OUT"',
        "its probe judged no impact and no check (ValueError: boom)",
    ),
    "hangs": ('sleep 600 & echo $! >> "$PIDS"; wait', "probe_failed: the probe ran past 2 s"),
}


def fake_release(cache: Path, version: str, probe: str) -> Path:
    """A release's environment in ``cache``, whole, whose python runs ``probe`` (a shell
    script: $OUT is the file the probe writes, $PIDS where it may leave its children's)."""
    env = releases.place(_release(version), cache)
    fake_environment(env, {"numpy": "2.0"})
    (env / releases.READY).write_text('{"numpy": "2.0"}')
    (env / "bin" / "python").write_text(
        '#!/bin/sh\nwhile [ "$1" != "--out" ]; do shift; done\nOUT="$2"\n'
        f'PIDS="{cache}/pids"\n{probe}\n'
    )
    return env


def _candidate(tmp_path: Path, capsys, probe: str) -> tuple[int, list[str], pd.DataFrame]:
    """``history --versions 1.0,2.0`` in-process, each release probed as ``probe`` says: its
    exit code, stderr's lines and history.csv."""
    for version in ("1.0", "2.0"):
        fake_release(tmp_path / "cache", version, PROBES[probe][0])
    code = history.main(
        [
            "--engine",
            cheapest(batched=False),
            "--versions",
            "1.0,2.0",
            "--cache",
            str(tmp_path / "cache"),
            "--out",
            str(tmp_path / "out"),
            "--name",
            "h",
        ]
    )
    table = pd.read_csv(tmp_path / "out" / "h" / "history.csv", dtype={"release": str})
    return code, capsys.readouterr().err.splitlines(), table


def _not_checked(probe: str) -> str:
    return (
        f"history: {cheapest(batched=False)} 2.0 against 1.0: not checked: the reference "
        f"1.0 could not be judged ({PROBES[probe][1]}); history.csv has each release's reason"
    )


@pytest.mark.parametrize("probe", [p for p in PROBES if p != "hangs"])
def test_a_candidate_check_that_judged_nothing_fails(probe, tmp_path, capsys):
    # the reference could not be judged: the check is not made (exit 1), in one line that
    # says which release and why; a garbled result is a row that says so, never a crash
    code, err, table = _candidate(tmp_path, capsys, probe)
    assert code == 1 and err == [_not_checked(probe)], err
    judged = probe == "judges nothing"  # (its errors: in history.json)
    assert list(table.state) == ["judged" if judged else "probe_failed"] * 2
    assert judged or (PROBES[probe][1].split(": ", 1)[1] == table.reason).all(), table.reason


def test_a_probe_that_hangs_is_said_once_and_stopped_whole(monkeypatch, tmp_path, capsys):
    monkeypatch.setattr(history, "PROBE_NOTICE_S", 0.5)
    monkeypatch.setattr(history, "PROBE_TIMEOUT_S", 2.0)
    t0 = time.perf_counter()
    code, err, table = _candidate(tmp_path, capsys, "hangs")
    assert code == 1 and time.perf_counter() - t0 < 20 and err[-1] == _not_checked("hangs")
    name, slowest = cheapest(batched=False), f"{history.PROBE_SLOWEST_S:g}"
    assert err[:-1] == [
        f"history: the probe of {name} {v} has run 0.5 s and is still running; "
        f"it is stopped at 2 s (the slowest release's takes about {slowest} s)"
        for v in ("1.0", "2.0")
    ], err
    left = [int(p) for p in (tmp_path / "cache" / "pids").read_text().split()]
    assert len(left) == 2 and not any(map(_running, left)), "the probe's child outlived it"


def _running(pid: int) -> bool:
    """Whether process ``pid`` runs 5 s on (a zombie, killed and not reaped yet, does not)."""
    for _ in range(100):
        try:
            if Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0] in "ZX":
                return False
        except FileNotFoundError:
            return False
        time.sleep(0.05)
    return True


@pytest.mark.parametrize(
    "result, said",
    [
        ([1, 2], "a JSON list, not an object"),
        ({"version": "1"}, "neither 'rows' nor 'not_driven'"),
        ({"rows": "x"}, "its 'rows' is a JSON string, not list"),
        ({"rows": [{"grid": "swing"}]}, "its rows item 1 is not an object with grid, s_m"),
        ({"rows": [], "checks": [1]}, "its checks item 1 is not an object with check"),
        (
            {
                "rows": [
                    {
                        "grid": "swing",
                        "s_m": 0.1,
                        "status": "ok",
                        "err_mps": "abc",
                        "tol_mps": 1e-3,
                        "wall_s": 0.1,
                    }
                ]
            },
            "its rows item 1 has err_mps a JSON string, not number",
        ),
        ({"not_driven": "ImportError: x"}, None),
        ({"rows": [], "checks": [], "defaults": {}}, None),
    ],
    ids=[
        "a list",
        "no rows",
        "rows a string",
        "a row without keys",
        "a check a number",
        "an error a string",
        "not driven",
        "nothing fired",
    ],
)
def test_a_probes_result_is_read_only_if_it_is_the_probes(result, said):
    found = history_probe.fault(result)
    assert found == said if said is None else said in found
    assert history.PROBE_NOTICE_S < history.PROBE_SLOWEST_S * 10 == history.PROBE_TIMEOUT_S


def test_a_relative_cache_is_the_cwds(tmp_path):
    # the probe starts in a folder of its own: a relative --cache is resolved at once
    name = cheapest(batched=False)
    result = json.dumps(
        {
            "engine": name,
            "version": "x",
            "rows": [
                {
                    "grid": "swing",
                    "s_m": 0.1,
                    "status": Status.OK.value,
                    "err_mps": 1e-9,
                    "tol_mps": 1e-6,
                    "wall_s": 1e-4,
                }
            ],
            "checks": [],
            "defaults": {},
        }
    )
    for version in ("1.0", "2.0"):
        fake_release(tmp_path / "cache", version, f"printf '%s' '{result}' > \"$OUT\"")
    res = run_command(
        [
            "-m",
            "experiments.history",
            "--engine",
            name,
            "--versions",
            "1.0,2.0",
            "--cache",
            "cache",
            "--out",
            "out",
            "--name",
            "h",
        ],
        cwd=tmp_path,
    )
    assert f"{name} 2.0 against 1.0: no regression" in res.stdout, res.stdout
    table = pd.read_csv(tmp_path / "out" / "h" / "history.csv")
    assert list(table.state) == ["judged"] * 2


NEWEST = adapters.record(cheapest(batched=False)).install.history[-1]


@pytest.mark.parametrize(
    "argv, said",
    [
        (
            ["--versions", "2.0", "--against", "2.0"],
            "--versions 2.0 would be checked against itself",
        ),
        (["--versions", NEWEST], f"--versions {NEWEST} would be checked against itself"),
        (["--versions", "2.0,2.0"], "--versions names '2.0' twice"),
        (["--versions", "3.0", "--against", "1.0,2.0"], "--against '1.0,2.0' names 2 versions"),
    ],
    ids=["against itself", "the newest alone", "named twice", "against two"],
)
def test_a_release_is_not_checked_against_itself(argv, said, tmp_path, capsys):
    with pytest.raises(SystemExit) as stop:
        history.main(
            [
                "--engine",
                cheapest(batched=False),
                *argv,
                "--cache",
                str(tmp_path),
                "--out",
                str(tmp_path / "out"),
            ]
        )
    err = capsys.readouterr().err
    assert stop.value.code == 2 and err.count("\n") == 1 and said in err, err
    assert not (tmp_path / "out").exists()


def test_offline_with_a_damaged_environment_as_a_user_runs_it(tmp_path):
    """The cache holds the first release's environment without its python, and the index
    cannot be reached: the environment is said broken and made again, which fails; every
    release is a row saying the index could not be reached, and the candidate is not
    checked (exit 1). No traceback, nothing downloaded."""
    name = cheapest(batched=False)
    first, second = adapters.record(name).install.history[-2:]
    cache = tmp_path / "cache"
    env = releases.place(releases.Release(engine=name, version=first), cache)
    fake_environment(env, {"numpy": "2.0"})
    (env / releases.READY).write_text("{}")
    (env / "bin" / "python").unlink()
    res = run_command(
        [
            "-m",
            "experiments.history",
            "--engine",
            name,
            "--versions",
            f"{first},{second}",
            "--cache",
            str(cache),
            "--out",
            str(tmp_path / "out"),
            "--name",
            "h",
        ],
        env=OFFLINE,
        code=1,
    )
    assert f"{env} is broken (its bin/python is missing): made again" in res.stderr
    assert (
        f"not checked: the reference {first} could not be judged ({history.UNREACHABLE}: "
        "the package index could not be reached" in res.stdout
    )
    table = pd.read_csv(tmp_path / "out" / "h" / "history.csv", dtype={"release": str})
    assert list(table.state) == [history.UNREACHABLE] * 2, table
    assert (tmp_path / "out" / "h" / f"history_{name}.png").is_file()
