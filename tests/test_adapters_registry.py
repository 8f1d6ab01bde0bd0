"""The registry: lazy engine imports, one record per engine, plug-ins by entry point, clear
errors for unknown names, bad settings and conflicting plug-ins."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

import adapters

ENGINES = adapters.names()


def _run(code: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          timeout=120, check=False)


def test_import_adapters_loads_no_engine():
    modules = sorted({adapters.record(n).import_name for n in ENGINES})
    res = _run(f"import sys, adapters; print([m for m in {modules!r} if m in sys.modules])")
    assert res.returncode == 0, res.stderr
    assert res.stdout.strip() == "[]"


@pytest.mark.parametrize("name", ENGINES)
def test_missing_engine_gives_install_hint(name):
    rec = adapters.record(name)
    res = _run(f"import sys; sys.modules[{rec.import_name!r}] = None\n"
               "import adapters\n"
               f"try:\n    adapters.load({name!r})\n"
               "except adapters.EngineNotInstalled as err:\n    print(err)")
    assert res.returncode == 0, res.stderr
    assert f"pip install {rec.package}" in res.stdout or f"batsim[{rec.extra}]" in res.stdout


def test_builtins_are_the_adapter_modules():
    # Every module of the package but base and _* is an engine named after it, in name order.
    here = Path(adapters.__file__).parent
    modules = sorted(p.stem for p in here.glob("*.py")
                     if not p.stem.startswith("_") and p.stem != "base")
    assert ENGINES[:len(modules)] == tuple(modules)
    for name in ENGINES:
        rec = adapters.record(name)
        assert adapters.engine_class(name).record.name == name == rec.name
        assert set(adapters.PROFILES) <= set(rec.profiles)
        assert rec.version()
        for family in rec.speed_accuracy:  # every knob is a setting the engine knows
            adapters.settings_for(name, family.profile, **dict(family.overrides))
        for integrator in rec.integrators:
            adapters.settings_for(name, **dict(integrator.overrides))


def test_plot_styles_are_distinct():
    styles = [(adapters.record(n).color, adapters.record(n).marker) for n in ENGINES]
    assert len(set(styles)) == len(styles)


@pytest.mark.parametrize("name", ENGINES)
@pytest.mark.parametrize("call,match", [
    (lambda n: adapters.load(n, profile="fast"), "profile='fast' is unknown; allowed: reference, default"),
    (lambda n: adapters.load(n, timestep=1e-3), "setting 'timestep' is unknown for "),
    (lambda n: adapters.load(n, dt_s=-1e-3), "dt_s=-0.001 is out of range"),
    (lambda n: adapters.load(n, contact_phase=1.0), "contact_phase=1.0 is out of range"),
], ids=["profile", "setting", "dt", "phase"])
def test_bad_profiles_and_settings(name, call, match):
    with pytest.raises(ValueError, match=match.replace("(", r"\(").replace(")", r"\)")):
        call(name)


def test_unknown_engine_lists_the_registered_ones():
    with pytest.raises(ValueError, match=f"engine='bullet' is unknown; allowed: {', '.join(ENGINES)}"):
        adapters.load("bullet")


@pytest.mark.parametrize("name", ENGINES)
def test_overrides_keep_the_rest_of_the_profile(name):
    eng = adapters.load(name, profile="default", dt_s=1e-4)
    assert eng.settings.dt_s == 1e-4
    assert eng.settings.contact_phase == adapters.settings_for(name, "default").contact_phase
    eng.close()


def test_impact_point_off_the_cylinder_is_a_value_error():
    from analytic import ImpactCase, presets

    case = ImpactCase(bat=presets.R161, ball=presets.BASEBALL, s_m=0.27, v0_mps=40.0)
    with pytest.raises(ValueError, match="s_m=0.27 is out of range"):
        adapters.load(ENGINES[0]).simulate(case)


# -- plug-ins -----------------------------------------------------------------------------------

PLUGIN_MODULE = """
import adapters

class Plugged(adapters.engine_class({base!r})):
    '''A third-party engine: an existing adapter under a new name.'''
"""


def _install_plugin(root: Path, entry: str, base: str) -> Path:
    """A distribution in ``root`` (a dist-info directory and its module) declaring one engine."""
    root.mkdir()
    (root / "batsim_test_plugin.py").write_text(PLUGIN_MODULE.format(base=base))
    info = root / "batsim_test_plugin-0.1.dist-info"
    info.mkdir()
    (info / "METADATA").write_text("Metadata-Version: 2.1\nName: batsim-test-plugin\n"
                                   "Version: 0.1\n")
    (info / "entry_points.txt").write_text(
        f"[{adapters.ENTRY_POINT_GROUP}]\n{entry} = batsim_test_plugin:Plugged\n")
    return root


@pytest.fixture
def plugin(tmp_path, monkeypatch):
    """Install a plug-in engine named ``plugged`` for one test."""
    monkeypatch.syspath_prepend(str(_install_plugin(tmp_path / "site", "plugged", ENGINES[0])))
    adapters.reload_plugins()
    yield "plugged"
    monkeypatch.undo()
    sys.modules.pop("batsim_test_plugin", None)
    adapters.reload_plugins()


def test_plugin_is_registered_and_runs_every_study(plugin, tmp_path):
    # The entry point's name is the engine's name, everywhere: registry, rows, --engine.
    from experiments import pareto, stability, sweep, swing

    assert plugin in adapters.names() and adapters.names()[:len(ENGINES)] == ENGINES
    rec = adapters.record(plugin)
    assert rec.name == plugin and rec.color not in {adapters.record(n).color for n in ENGINES}
    assert adapters.load(plugin).name == plugin
    out = tmp_path / "out"
    assert sweep.main(["--engine", plugin, "--points", "3", "--out", str(out), "--name", "p",
                       "--no-locate"]) == 0
    assert "plugged" in (out / "p" / "sweep.csv").read_text()
    for study in (pareto, stability, swing):
        assert study.main(["--quick", "--engine", plugin, "--out", str(out)]) == 0
    meta = json.loads((out / "p" / "sweep.json").read_text())
    assert set(meta["engines"]) == {plugin}


def test_plugin_may_not_shadow_a_builtin(tmp_path, monkeypatch):
    monkeypatch.syspath_prepend(str(_install_plugin(tmp_path / "site", ENGINES[0], ENGINES[0])))
    adapters.reload_plugins()
    try:
        with pytest.raises(adapters.PluginConflict,
                           match=f"plug-in engine '{ENGINES[0]}' .* shadows the built-in"):
            adapters.names()
    finally:
        monkeypatch.undo()
        adapters.reload_plugins()
