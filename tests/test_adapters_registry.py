"""The registry: records read without importing any engine, one record per engine, plug-ins by
entry point, clear errors for unknown names, bad settings and conflicting plug-ins."""

from __future__ import annotations

import dataclasses
import subprocess
import sys
from pathlib import Path

import pytest

import adapters
from analytic import ImpactCase, presets
from experiments.core import Job, fire_jobs
from experiments.core.io import ROOT

ENGINES = adapters.names()


def _run(code: str) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, "-c", code],
        capture_output=True,
        text=True,
        timeout=120,
        check=False,
        cwd=ROOT,
    )


def test_registry_and_engine_validation_load_no_engine():
    # Listing, reading every record, asking what is installed, making settings, parsing
    # --engine and drawing nothing yet: neither an engine's package nor its adapter module is
    # imported (sys.modules in a fresh interpreter).
    watched = sorted(
        {adapters.record(n).install.import_name.split(".")[0] for n in ENGINES}
        | {adapters.record(n).adapter.split(":")[0] for n in ENGINES}
    )
    code = (
        "import sys, adapters\n"
        "for n in adapters.names():\n"
        "    adapters.record(n).install_hint, adapters.settings_for(n, 'default')\n"
        "adapters.available(), adapters.missing()\n"
        "from experiments import sweep\n"
        "for engines in ('all', ','.join(adapters.names())):\n"
        "    sweep.sweep_from_args(sweep.build_parser().parse_args(['--engine', engines]))\n"
        f"print([m for m in {watched!r} if m in sys.modules])"
    )
    res = _run(code)
    assert res.returncode == 0, res.stderr
    assert res.stdout.strip() == "[]"


def test_loading_a_missing_engine_raises_its_install_hint():
    # the API's side (the command line's, engine by engine: test_cli): with the engine's
    # module hidden in a fresh interpreter, load() raises EngineNotInstalled with the hint
    rec = adapters.record(ENGINES[0])
    res = _run(
        f"import sys; sys.modules[{rec.install.import_name!r}] = None\n"
        "import adapters\n"
        f"try:\n    adapters.load({rec.name!r})\n"
        "except adapters.EngineNotInstalled as err:\n    print(err)"
    )
    assert res.returncode == 0, res.stderr
    assert res.stdout.strip() == rec.install_hint


def test_builtins_are_the_adapter_packages():
    # Every subpackage of adapters is an engine named after it, in name order, whose adapter
    # class carries the same record; the record says whether it is batched as the class does
    # (the runner keeps a batched engine's jobs in its own process).
    here = Path(adapters.__file__).parent
    packages = sorted(p.parent.name for p in here.glob("*/__init__.py"))
    assert ENGINES[: len(packages)] == tuple(packages)
    for name in packages:
        rec = adapters.record(name)
        assert adapters.engine_class(name).record == rec and rec.name == name
        assert rec.batched == issubclass(adapters.engine_class(name), adapters.BatchedEngine)
        assert set(adapters.PROFILES) <= set(rec.profiles)
        assert rec.version()


def test_plot_styles_are_distinct():
    styles = [(adapters.record(n).look.color, adapters.record(n).look.marker) for n in ENGINES]
    assert len(set(styles)) == len(styles)


@pytest.mark.parametrize(
    "call,match",
    [
        (
            lambda n: adapters.load(n, profile="fast"),
            "profile='fast' is unknown; allowed: reference, default",
        ),
        (lambda n: adapters.load(n, timestep=1e-3), "setting 'timestep' is unknown for "),
    ],
    ids=["profile", "setting"],
)
def test_bad_profiles_and_settings(call, match):
    # the registry's checks, the same for every engine: refused before any engine is made
    with pytest.raises(ValueError, match=match):
        call(ENGINES[0])


def test_unknown_engine_lists_the_registered_ones():
    with pytest.raises(
        ValueError, match=f"engine='bullet' is unknown; allowed: {', '.join(ENGINES)}"
    ):
        adapters.load("bullet")


@pytest.mark.parametrize("name", ENGINES)
def test_every_setting_of_an_engine_overrides_alone(name):
    # each engine's own settings class: any one field overridden (here set to its reference
    # value's twin from the default profile) leaves every other field as the profile has it
    ref, default = (adapters.settings_for(name, p) for p in adapters.PROFILES)
    fields = [f.name for f in dataclasses.fields(ref)]
    assert "dt_s" in fields
    for field in fields:
        got = adapters.settings_for(name, "reference", **{field: getattr(default, field)})
        assert getattr(got, field) == getattr(default, field)
        assert all(getattr(got, f) == getattr(ref, f) for f in fields if f != field), field


def test_impact_point_off_the_cylinder_is_a_value_error():
    case = ImpactCase(bat=presets.R161, ball=presets.BASEBALL, s_m=0.27, v0_mps=40.0)
    with pytest.raises(ValueError, match="s_m=0.27 is out of range"):
        fire_jobs([Job(engine=ENGINES[0], settings=adapters.settings_for(ENGINES[0]), case=case)])


def test_settings_carry_knobs_and_the_error_model_the_judges_questions():
    # what contact the settings make (its law, a mapping's bias, a speculative margin...) is
    # asked of the record's error model (adapters/errors.py), never of the settings
    fields = {f.name for f in dataclasses.fields(adapters.ErrorModel)}
    hooks = {n for n in vars(adapters.ErrorModel) if not n.startswith("_")} - fields - {"eps"}
    assert "contact_law" in hooks and len(hooks) == 11
    for name in adapters.names():
        rec = adapters.record(name)
        settings_class = type(rec.profiles["reference"])
        defined = {n for cls in settings_class.__mro__ for n in vars(cls)}
        assert not defined & hooks, f"{name}'s settings define {sorted(defined & hooks)}"
        assert isinstance(rec.errors, adapters.ErrorModel)


# -- plug-ins that reuse a built-in's record ------------------------------------------------

PLUGIN_MODULE = """
import dataclasses
import adapters

RECORD = dataclasses.replace(adapters.record({base!r}), name="borrowed")
"""


def _install_plugin(root: Path, entry: str, base: str) -> Path:
    """A distribution in ``root`` (a dist-info directory and its module) declaring one engine."""
    root.mkdir()
    (root / "batsim_test_plugin.py").write_text(PLUGIN_MODULE.format(base=base))
    info = root / "batsim_test_plugin-0.1.dist-info"
    info.mkdir()
    (info / "METADATA").write_text(
        "Metadata-Version: 2.1\nName: batsim-test-plugin\nVersion: 0.1\n"
    )
    (info / "entry_points.txt").write_text(
        f"[{adapters.ENTRY_POINT_GROUP}]\n{entry} = batsim_test_plugin:RECORD\n"
    )
    return root


def test_a_plugin_takes_its_entry_points_name_and_its_own_style(tmp_path, monkeypatch):
    monkeypatch.syspath_prepend(str(_install_plugin(tmp_path / "site", "plugged", ENGINES[0])))
    adapters.reload_plugins()
    try:
        assert adapters.names() == (*ENGINES, "plugged")
        rec = adapters.record("plugged")
        assert rec.name == "plugged" and rec.adapter == adapters.record(ENGINES[0]).adapter
        assert rec.look.color not in {adapters.record(n).look.color for n in ENGINES}
    finally:
        monkeypatch.undo()
        sys.modules.pop("batsim_test_plugin", None)
        adapters.reload_plugins()


def test_plugin_may_not_shadow_a_builtin(tmp_path, monkeypatch):
    # left out, with the reason; the built-in of that name is untouched
    monkeypatch.syspath_prepend(str(_install_plugin(tmp_path / "site", ENGINES[0], ENGINES[0])))
    adapters.reload_plugins()
    try:
        assert adapters.names() == ENGINES
        assert "shadows the built-in engine" in adapters.broken()[ENGINES[0]]
        assert adapters.record(ENGINES[0]).adapter.startswith(f"adapters.{ENGINES[0]}.")
    finally:
        monkeypatch.undo()
        sys.modules.pop("batsim_test_plugin", None)
        adapters.reload_plugins()


def test_register_refuses_a_taken_name():
    with pytest.raises(adapters.PluginConflict, match="is registered already"):
        adapters.register(adapters.record(ENGINES[0]))


def test_collecting_the_tests_loads_no_engine():
    # the suite's collection reads records only (conftest's tiers and groups, parametrize over
    # adapters.names()): no engine package or adapter module is imported before a test runs
    watched = sorted(
        {adapters.record(n).install.import_name.split(".")[0] for n in ENGINES}
        | {adapters.record(n).adapter.split(":")[0] for n in ENGINES}
    )
    res = _run(
        "import sys, pytest\n"
        "code = pytest.main(['--collect-only', '-q', '-p', 'no:cacheprovider', "
        "'-p', 'no:xdist', 'tests'])\n"
        f"print(code, [m for m in {watched!r} if m in sys.modules])"
    )
    assert res.returncode == 0, res.stderr
    assert res.stdout.strip().splitlines()[-1] == "0 []", res.stdout[-2000:]
