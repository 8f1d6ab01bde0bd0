"""The registry: lazy engine imports, clear errors for unknown names and bad settings."""

from __future__ import annotations

import subprocess
import sys

import pytest

import adapters


def _run(code: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          timeout=120, check=False)


def test_import_adapters_loads_no_engine():
    res = _run("import sys, adapters; "
               "print(sorted(m for m in ('mujoco', 'pybullet', 'pymunk') if m in sys.modules))")
    assert res.returncode == 0, res.stderr
    assert res.stdout.strip() == "[]"


def test_missing_engine_gives_install_hint():
    res = _run("import sys; sys.modules['mujoco'] = None\n"
               "import adapters\n"
               "try:\n    adapters.load('mujoco')\n"
               "except adapters.EngineNotInstalled as err:\n    print(err)")
    assert res.returncode == 0, res.stderr
    assert "pip install mujoco" in res.stdout


def test_names_are_the_registry_keys():
    assert adapters.names() == ("pymunk", "pybullet", "mujoco")
    for name in adapters.names():
        assert adapters.engine_class(name).name == name


@pytest.mark.parametrize("call,match", [
    (lambda: adapters.load("bullet"), "engine='bullet' is unknown; allowed: pymunk, pybullet, mujoco"),
    (lambda: adapters.load("mujoco", profile="fast"), "profile='fast' is unknown; allowed: reference, default"),
    (lambda: adapters.load("mujoco", timestep=1e-3), "setting 'timestep' is unknown for mujoco; allowed: "),
    (lambda: adapters.load("pymunk", dt_s=-1e-3), "dt_s=-0.001 is out of range"),
    (lambda: adapters.load("mujoco", integrator="Verlet"), "integrator='Verlet' is unknown; allowed: Euler"),
    (lambda: adapters.load("pybullet", contact_erp=2.0), "contact_erp=2.0 is out of range"),
    (lambda: adapters.load("mujoco", contact_phase=1.0), "contact_phase=1.0 is out of range"),
])
def test_bad_names_and_settings(call, match):
    with pytest.raises(ValueError, match=match.replace("(", r"\(").replace(")", r"\)")):
        call()


def test_overrides_keep_the_rest_of_the_profile():
    eng = adapters.load("pybullet", profile="default", dt_s=1e-4)
    assert eng.settings.dt_s == 1e-4
    assert eng.settings.contact_phase == adapters.settings_for("pybullet", "default").contact_phase


def test_impact_point_off_the_cylinder_is_a_value_error():
    from analytic import ImpactCase, presets

    case = ImpactCase(bat=presets.R161, ball=presets.BASEBALL, s_m=0.27, v0_mps=40.0)
    with pytest.raises(ValueError, match="s_m=0.27 is out of range"):
        adapters.load("pymunk").simulate(case)
