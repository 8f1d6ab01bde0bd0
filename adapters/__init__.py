"""Engine adapters behind one contract, loaded by name. Importing this package loads no engine.

    import adapters
    eng = adapters.load("mujoco")                                  # profile="reference"
    eng = adapters.load("pybullet", profile="default", dt_s=1e-4)  # override any setting
    out = eng.simulate(case)                                       # an adapters.SimOutcome
"""

from __future__ import annotations

import dataclasses
import importlib
from types import MappingProxyType

from .base import Engine, MassProperties, SceneMismatch, Settings, SimOutcome, Status

#: Engine name -> "module:class", imported only when the engine is chosen.
ENGINES = MappingProxyType({
    "pymunk": "adapters.pymunk:PymunkEngine",
    "pybullet": "adapters.pybullet:PybulletEngine",
    "mujoco": "adapters.mujoco:MujocoEngine",
})
#: The PyPI package that provides each engine, for the install hint.
PACKAGES = MappingProxyType({"pymunk": "pymunk", "pybullet": "pybullet", "mujoco": "mujoco"})
PROFILES = ("reference", "default")


class EngineNotInstalled(ImportError):
    """The chosen engine's Python package is missing."""


def names() -> tuple[str, ...]:
    """Registered engine names, in a stable order."""
    return tuple(ENGINES)


def engine_class(name: str) -> type[Engine]:
    """The adapter class for ``name``, importing its engine now."""
    if name not in ENGINES:
        raise ValueError(f"engine={name!r} is unknown; allowed: {', '.join(ENGINES)}")
    module_name, cls_name = ENGINES[name].split(":")
    try:
        module = importlib.import_module(module_name)
    except ModuleNotFoundError as err:
        if err.name != PACKAGES[name]:
            raise
        raise EngineNotInstalled(
            f"engine {name!r} needs the package {PACKAGES[name]!r}: "
            f"pip install {PACKAGES[name]}  (or `make test`, which installs every engine)"
        ) from err
    return getattr(module, cls_name)


def settings_for(name: str, profile: str = "reference", **overrides) -> Settings:
    """The named profile's settings for an engine, with any field overridden."""
    cls = engine_class(name)
    if profile not in cls.profiles:
        raise ValueError(f"profile={profile!r} is unknown; allowed: {', '.join(cls.profiles)}")
    base = cls.profiles[profile]
    valid = {f.name for f in dataclasses.fields(base)}
    unknown = sorted(set(overrides) - valid)
    if unknown:
        raise ValueError(f"setting {unknown[0]!r} is unknown for {name}; allowed: "
                         f"{', '.join(sorted(valid))}")
    return dataclasses.replace(base, **overrides)


def load(name: str, profile: str = "reference", **overrides) -> Engine:
    """An engine adapter with the named profile's settings, any of them overridden."""
    return engine_class(name)(settings_for(name, profile, **overrides))


__all__ = ["ENGINES", "Engine", "EngineNotInstalled", "MassProperties", "PROFILES", "SceneMismatch",
           "Settings", "SimOutcome", "Status", "engine_class", "load", "names", "settings_for"]
