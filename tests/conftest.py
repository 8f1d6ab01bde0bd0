"""Shared hypothesis strategies, numeric constants and the tiers' plumbing for the tests.

Tiers: `make test` runs every test not marked ``full``; `make test-all` runs them all, with the
``ci`` hypothesis profile (``--hypothesis-profile=ci``). A test over a batched engine is in the
full tier unless it is a conformance essential (``pytest_collection_modifyitems``). Under
pytest-xdist (``--dist loadgroup``) each batched engine's tests share a worker: its compiled
steps (JAX traces, Warp modules) are made once per worker, not once per test.
"""

from __future__ import annotations

import importlib
import math
import os
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from hypothesis import HealthCheck, settings
from hypothesis import strategies as st

import adapters
from analytic import Ball, Bat, ImpactCase
from experiments.core import Status, runs

os.environ["BATSIM_QUIET"] = "1"  # no progress lines in test output (subprocesses too)

#: Examples per property in the CI profile; the fast tier draws FAST_EXAMPLES.
CI_EXAMPLES, FAST_EXAMPLES = 200, 25
for _name, _n in (("ci", CI_EXAMPLES), ("fast", FAST_EXAMPLES)):
    settings.register_profile(
        _name, deadline=None, max_examples=_n, suppress_health_check=[HealthCheck.too_slow]
    )
settings.load_profile("fast")  # --hypothesis-profile=ci (make test-all) replaces it


def examples(n: int) -> int:
    """A property's own number of examples (n, chosen for the CI profile), scaled to the loaded
    profile: the fast tier draws the same properties, fewer times."""
    return max(5, n * settings.default.max_examples // CI_EXAMPLES)


@pytest.hookimpl(tryfirst=True)  # before pytest-xdist reads the groups
def pytest_collection_modifyitems(items) -> None:
    """A test parametrized with a batched engine (milliseconds a step on a CPU, seconds to
    compile) goes to that engine's xdist group, and to the full tier unless it is one of the
    conformance essentials (marked ``essential``). Reads records only: no engine is imported at
    collection."""
    batched = {n for n in adapters.names() if adapters.record(n).batched}
    for item in items:
        params = getattr(getattr(item, "callspec", None), "params", {})
        engines = sorted(batched & {v for v in params.values() if isinstance(v, str)})
        if engines:
            item.add_marker(pytest.mark.xdist_group(engines[0]))
            if item.get_closest_marker("essential") is None:
                item.add_marker(pytest.mark.full)


EPS = np.finfo(float).eps  # 2.2e-16: unit roundoff of float64


@st.composite
def bats(draw) -> Bat:
    """Physically plausible bats: J between 0.1 and 1 times a uniform rod's M L^2 / 12."""
    length = draw(st.floats(0.5, 1.2))
    mass = draw(st.floats(0.3, 2.0))
    return Bat(
        name="random",
        length_m=length,
        radius_m=draw(st.floats(0.02, 0.045)),
        mass_kg=mass,
        com_from_knob_m=draw(st.floats(0.35, 0.75)) * length,
        inertia_cm_kgm2=draw(st.floats(0.1, 1.0)) * mass * length**2 / 12,
    )


@st.composite
def cases(draw, oblique: bool = False) -> ImpactCase:
    """Random impacts that approach (closing speed > 1 m/s) on the hittable part of the bat."""
    bat = draw(bats())
    ball = Ball(name="random", mass_kg=draw(st.floats(0.05, 0.5)), radius_m=0.0366)
    s = draw(st.floats(bat.s_min_m, bat.s_max_m))
    v0 = draw(st.floats(1.0, 60.0))
    u0 = draw(st.floats(-5.0, 30.0))
    w0 = draw(st.floats(-50.0, 50.0))
    angle = st.floats(-1.2, 1.2) if oblique else st.just(0.0)
    theta, phi = draw(angle), draw(angle)
    closing = v0 * math.cos(theta) + u0 * math.cos(phi) + w0 * s
    if closing < 1.0:  # keep only impacts; hypothesis.assume would discard too many draws
        u0 += (1.0 - closing) / math.cos(phi) + draw(st.floats(0.0, 20.0))
    return ImpactCase(
        bat=bat,
        ball=ball,
        s_m=s,
        v0_mps=v0,
        u0_mps=u0,
        omega0_radps=w0,
        e=draw(st.floats(0.0, 1.0)),
        theta_rad=theta,
        phi_rad=phi,
    )


def sound(table: pd.DataFrame) -> pd.Series:
    """The rows a reference profile may end with: ok; or still touching at the budget where
    the rigid bodies are too (e = 0 near the COM: 'time_limit'); or, for a compliant contact,
    unjudged beyond its law's single contact (``experiments.core.judge.soft_judgement``)."""
    still_on = (table.status == Status.NO_SEPARATION) & (table.rigid_end == "time_limit")
    beyond_law = (table.status == Status.UNJUDGED) & table.v1_law_mps.notna()
    return (table.status == Status.OK) | still_on | beyond_law


# -- running commands as a user does --------------------------------------------------------

ROOT = Path(__file__).resolve().parents[1]
PLUGIN = Path(__file__).parent / "plugin" / "toy_engine.py"


def _commands() -> dict:
    """Every command, by name: each module of ``experiments`` that runs as ``python -m`` (a
    ``__main__`` guard, or a package's ``__main__.py``), imported."""
    mains = {
        p.stem
        for p in (ROOT / "experiments").glob("*.py")
        if 'if __name__ == "__main__":' in p.read_text()
    }
    packages = {p.parent.name for p in (ROOT / "experiments").glob("*/__main__.py")}
    return {n: importlib.import_module(f"experiments.{n}") for n in sorted(mains | packages)}


COMMANDS = _commands()
#: A command at small size finishes in well under a minute on 2 cores; a hang fails it here.
COMMAND_TIMEOUT_S = 200


def run_command(
    argv: list[str], *, env: dict | None = None, cwd: Path = ROOT, code: int = 0
) -> subprocess.CompletedProcess:
    """``python <argv>`` in a fresh interpreter, as a user types it: it must exit ``code``
    with no traceback on either stream."""
    res = subprocess.run(
        [sys.executable, *argv],
        cwd=cwd,
        capture_output=True,
        text=True,
        timeout=COMMAND_TIMEOUT_S,
        check=False,
        env={**os.environ, **(env or {})},
    )
    shown = (
        f"python {' '.join(argv)} -> {res.returncode}\n{res.stdout[-3000:]}\n{res.stderr[-3000:]}"
    )
    assert res.returncode == code, shown
    assert "Traceback" not in res.stderr + res.stdout, shown
    return res


def runs_in(out: Path) -> list[str]:
    """The runs in a folder runs went to: its entries but the staging folder, which must hold
    nothing a run left (no half-written run, no run moved aside): only locks and its mark."""
    staged = out / runs.STAGING
    if staged.is_dir():
        left = sorted(p.name for p in staged.iterdir() if p.is_dir())
        assert not left, f"left in {staged}: {left}"
    return sorted(p.name for p in out.iterdir() if p.name != runs.STAGING)


def cheapest(batched: bool) -> str:
    """The registered engine of that kind with the smallest measured step cost (records only:
    the tests name no engine)."""
    return min(
        (n for n in adapters.available() if adapters.record(n).batched == batched),
        key=lambda n: adapters.record(n).cost.step_cost_s,
    )


def plugin_site(site: Path, dist: str, entries: dict[str, str]) -> Path:
    """``site`` (a folder) holding the toy plug-in's module and a distribution ``dist`` (a
    dist-info) declaring these engines (name -> "module:RECORD"): on sys.path or PYTHONPATH,
    it registers them."""
    shutil.copy(PLUGIN, site / "toy_engine.py")
    info = site / f"{dist.replace('-', '_')}-0.1.dist-info"
    info.mkdir()
    (info / "METADATA").write_text(f"Metadata-Version: 2.1\nName: {dist}\nVersion: 0.1\n")
    (info / "entry_points.txt").write_text(
        f"[{adapters.ENTRY_POINT_GROUP}]\n" + "".join(f"{n} = {t}\n" for n, t in entries.items())
    )
    return site


@pytest.fixture(scope="session")
def toy_site(tmp_path_factory) -> Path:
    """The toy plug-in installed: the engine ``toyengine``."""
    return plugin_site(
        tmp_path_factory.mktemp("site"), "batsim-toy-engine", {"toyengine": "toy_engine:RECORD"}
    )


#: The engines of ``findings_run``: the cheapest single-world one and the toy plug-in.
FINDINGS_ENGINES = (cheapest(False), "toyengine")


@pytest.fixture(scope="session")
def findings_run(tmp_path_factory, toy_site) -> Path:
    """``python -m experiments.findings --workers 2`` once per test run (its model sections
    take about a minute), over the cheapest single-world engine and the toy plug-in: the
    directory it wrote. Tests that read it share the xdist group "findings" (one worker runs it)."""
    out = tmp_path_factory.mktemp("findings")
    run_command(
        [
            "-m",
            "experiments.findings",
            "--engine",
            ",".join(FINDINGS_ENGINES),
            "--workers",
            "2",
            "--out",
            str(out),
            "--name",
            "f",
        ],
        env={"PYTHONPATH": str(toy_site)},
    )
    return out / "f"
