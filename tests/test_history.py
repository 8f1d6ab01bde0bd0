"""``experiments.history``: release environments made once and reused (an interrupted or a
damaged one made again), the engine's own pins freed, a candidate that loses a verdict or lets
an error grow past its tolerance exits 1 (all without installing); then, in the full tier, the
README's lines as a user runs them: two releases installed on a cold cache and judged, and a
version that does not exist is a row that says so."""

from __future__ import annotations

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

from .conftest import ROOT, cheapest, run_command

README = (ROOT / "README.md").read_text()
#: The README's history lines: the spread of two releases, and a candidate checked.
LINES = [shlex.split(m.group(0)) for lang, text in re.findall(r"```(\w+)\n(.*?)```", README, re.S)
         if lang == "sh" for m in re.finditer(r"python -m experiments\.history[^\n#]*", text)]
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
            parents=True)
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
    assert not any(p.is_dir() for p in (tmp_path / releases.python_tag()).iterdir()), \
        "a partial environment left"
    made = []
    releases.environment(_release(), tmp_path, lambda r, t: made.append(t) or {})
    assert len(made) == 1


def _made(tmp_path: Path) -> tuple[releases.Release, Path]:
    """A release's environment made in a scratch cache, whole, by a stand-in installer."""
    release = releases.Release(engine=cheapest(batched=False), version="1.0")
    python = releases.environment(release, tmp_path,
                                  lambda r, t: fake_environment(t, {"numpy": "2.0", "b-c": "1"}))
    return release, python.parent.parent


BREAK = {
    "its python deleted": lambda env: (env / "bin" / "python").unlink(),
    "its python a link to nothing": lambda env: ((env / "bin" / "python").unlink(),
                                                 (env / "bin" / "python").symlink_to(env / "x")),
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
    releases.environment(release, tmp_path, lambda r, t: made.append(t) or fake_environment(
        t, {"numpy": "2.0"}))
    assert made == [env] and releases.fault(env) is None
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and f"{env} is broken" in err and "made again" in err


def test_the_engines_own_pins_are_freed_and_the_harness_pins_kept():
    pinned = {releases._name(ln) for ln in (ROOT / "constraints.txt").read_text().split()}
    name = next(n for n in adapters.names()
                if releases._name(adapters.record(n).install.package) in pinned)
    package = releases._name(adapters.record(name).install.package)
    kept = {releases._name(ln) for ln in releases.constraints(
        releases.Release(engine=name, version="0")).split()}
    assert package not in kept and "numpy" in kept
    assert not any(p.startswith(package + "-") for p in kept)  # nor its family (package-core)


def _result(version: str, err_mps: float, status: str = "ok") -> dict:
    rows = [{"grid": "swing", "s_m": s, "status": status, "err_mps": err_mps, "tol_mps": 1e-6,
             "wall_s": 1e-4} for s in (-0.1, 0.1)]
    return {"engine": "e", "release": version, "state": "judged", "version": version,
            "rows": rows, "checks": [{"check": "still_bat", "passed": True, "detail": "ok"}],
            "defaults": {"dt_s": "0.01"}}


@pytest.mark.parametrize("candidate, code", [
    (_result("2", 1e-9), 0),                       # within 1e-6 m/s of the reference's error
    (_result("2", 5e-6), 1),                       # grew past its tolerance
    (_result("2", 1e-9, status="inaccurate"), 1),  # a verdict lost
], ids=["unchanged", "error grew", "verdict lost"])
def test_a_candidate_exits_1_on_a_regression(monkeypatch, tmp_path, candidate, code):
    # |err candidate - err reference| > tol is a moved error; a grown one regresses
    results = {"1": _result("1", 1e-9), "2": candidate}
    monkeypatch.setattr(history, "fire_release", lambda e, v, cache: {**results[v], "engine": e})
    name = cheapest(batched=False)
    out = tmp_path / "out"
    assert history.main(["--engine", name, "--versions", "1,2", "--cache", str(tmp_path),
                         "--out", str(out), "--name", "h"]) == code
    page = (out / "h" / "history.md").read_text()
    assert ("(regression)" in page) == bool(code)
    assert len(pd.read_csv(out / "h" / "history.csv")) == 2


def test_a_release_that_imports_what_it_does_not_declare_is_judged_with_it(monkeypatch):
    # a build against NumPy 1 fails to import under NumPy 2: judged again with numpy<2 added
    made = []

    def fire(release, cache):
        made.append(release.extras)
        if not release.extras:
            return {"state": Status.UNSUPPORTED.value,
                    "reason": "ImportError: numpy.core.multiarray failed to import"}
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
    pd.testing.assert_frame_equal(rows, _history([*spread[1:], "--workers", "2", "--scheduler",
                                                  "local"], tmp_path / "dask"))
    _history(candidate[1:], tmp_path / "candidate")
    engine = spread[spread.index("--engine") + 1]
    released = candidate[candidate.index("--versions") + 1]
    wheels = tmp_path / "wheels"
    subprocess.run([sys.executable, "-m", "pip", "download", "--quiet", "--no-deps",
                    "--only-binary", ":all:", "-d", str(wheels),
                    f"{adapters.record(engine).install.package}=={released}"],
                   check=True, timeout=COLD_LIMIT_S)
    (wheel,) = wheels.glob("*.whl")
    both = _history([*spread[1:3], "--engine", engine, "--versions", str(wheel), "--against",
                     released], tmp_path / "wheel")
    as_released, as_wheel = (g.drop(columns="release").reset_index(drop=True)
                             for _, g in both.groupby("release", sort=False))
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

