"""Engine adapters behind one contract, loaded by name. Importing this package loads no engine.

    import adapters
    adapters.names()                                               # every registered engine
    adapters.record("mujoco").color                                # an engine's facts
    eng = adapters.load("mujoco")                                  # profile="reference"
    eng = adapters.load("pybullet", profile="default", dt_s=1e-4)  # override any setting
    out = eng.simulate(case)                                       # an adapters.SimOutcome

Engines are registered two ways, the same to the rest of the harness:
- built in: every module of this package not named ``base`` or ``_*`` is an engine whose name is
  the module's name and whose adapter class is the module's ``ENGINE``;
- plug-ins: an installed distribution declaring, in its pyproject.toml,
  ``[project.entry-points."batsim.engines"]`` ``NAME = "module:Class"``; the entry point's name
  is the engine's name (it may not be a built-in's).
"""

from __future__ import annotations

import dataclasses
import functools
import importlib
import pkgutil
import sys
from importlib import metadata
from pathlib import Path
from types import MappingProxyType

from ._record import (PROFILES, ContactReference, EngineNotInstalled, EngineRecord, Integrator,
                      KnobFamily,
                      RestitutionRule, import_engine)
from .base import (BodyLoad, Engine, MassProperties, Reading, SceneMismatch, Settings,
                   SimOutcome, Status, SwingPlan, start_reading, swing_case)

ENTRY_POINT_GROUP = "batsim.engines"
#: Colours for engines whose record names none (plug-ins), in registry order: none of them a
#: built-in's (blue, orange, green, purple, brown, red, black).
PALETTE = ("tab:pink", "tab:gray", "tab:olive", "tab:cyan", "gold", "teal", "navy", "magenta")
_NOT_ENGINES = frozenset({"base"})


class PluginConflict(ValueError):
    """A plug-in's entry point would shadow a built-in engine or another plug-in."""


@functools.cache
def _registry() -> MappingProxyType:
    """Engine name -> "module:attribute" of its adapter class; built-ins first, by name."""
    here = Path(__file__).parent
    found = {m.name: f"{__name__}.{m.name}:ENGINE" for m in pkgutil.iter_modules([str(here)])
             if not m.name.startswith("_") and m.name not in _NOT_ENGINES}
    builtins = dict(sorted(found.items()))
    plugins: dict[str, str] = {}
    for ep in sorted(metadata.entry_points(group=ENTRY_POINT_GROUP), key=lambda e: e.name):
        dist = ep.dist.name if ep.dist is not None else "an unknown distribution"
        if ep.name in builtins:
            raise PluginConflict(
                f"plug-in engine {ep.name!r} ({ep.value} from {dist}) shadows the built-in "
                f"engine {ep.name!r} ({builtins[ep.name]}); allowed: a name that is not one of "
                f"{', '.join(builtins)}")
        if ep.name in plugins and plugins[ep.name] != ep.value:
            raise PluginConflict(
                f"plug-in engine {ep.name!r} is declared twice ({plugins[ep.name]} and "
                f"{ep.value} from {dist}); allowed: one entry point per name")
        plugins[ep.name] = ep.value
    return MappingProxyType({**builtins, **plugins})


def reload_plugins() -> None:
    """Forget the registry so that the next call looks for entry points again."""
    importlib.invalidate_caches()
    _registry.cache_clear()
    record.cache_clear()
    missing.cache_clear()
    available.cache_clear()


def names() -> tuple[str, ...]:
    """Registered engine names: built-ins by name, then plug-ins by name."""
    return tuple(_registry())


def loaded() -> tuple[str, ...]:
    """Registered engines whose adapter (and so engine) this process has imported."""
    return tuple(n for n, target in _registry().items() if target.split(":")[0] in sys.modules)


@functools.cache
def available() -> tuple[str, ...]:
    """Registered engines whose package is installed (checking imports each engine), in
    registry order; ``missing()`` says why the others are not."""
    return tuple(n for n in names() if n not in missing())


@functools.cache
def missing() -> MappingProxyType:
    """Registered engine name -> its install hint, for engines whose package is not installed."""
    out = {}
    for n in names():
        try:
            engine_class(n)
        except EngineNotInstalled as err:
            out[n] = str(err)
    return MappingProxyType(out)


def _check_name(name: str) -> str:
    if name not in _registry():
        raise ValueError(f"engine={name!r} is unknown; allowed: {', '.join(names())}")
    return name


def engine_class(name: str) -> type[Engine]:
    """The adapter class for ``name``, importing its engine now (EngineNotInstalled if missing)."""
    target = _registry()[_check_name(name)]
    module_name, attr = target.split(":")
    try:
        module = importlib.import_module(module_name)
    except EngineNotInstalled:
        raise
    except ModuleNotFoundError as err:
        raise EngineNotInstalled(f"engine {name!r} ({target}) could not be imported: {err}; "
                                 "allowed: an installed plug-in") from err
    cls = getattr(module, attr)
    if not (isinstance(cls, type) and issubclass(cls, Engine)):
        raise TypeError(f"engine {name!r}: {target} is not an adapters.Engine subclass")
    return cls


@functools.cache
def record(name: str) -> EngineRecord:
    """The engine's record, named as registered and with a plot colour filled in."""
    rec = engine_class(name).record
    changes = {}
    if rec.name != name:  # a plug-in reusing an adapter under its own name gets its own style
        changes = {"name": name, "color": None}
    if (changes.get("color", rec.color)) is None:
        changes["color"] = PALETTE[names().index(name) % len(PALETTE)]
    return dataclasses.replace(rec, **changes) if changes else rec


def settings_for(name: str, profile: str = "reference", **overrides) -> Settings:
    """The named profile's settings for an engine, with any field overridden."""
    rec = record(name)
    if profile not in rec.profiles:
        raise ValueError(f"profile={profile!r} is unknown; allowed: {', '.join(rec.profiles)}")
    base = rec.profiles[profile]
    valid = {f.name for f in dataclasses.fields(base)}
    unknown = sorted(set(overrides) - valid)
    if unknown:
        raise ValueError(f"setting {unknown[0]!r} is unknown for {name}; allowed: "
                         f"{', '.join(sorted(valid))}")
    return dataclasses.replace(base, **overrides)


def create(name: str, settings: Settings) -> Engine:
    """An engine adapter with these settings."""
    return engine_class(name)(settings, name=name)


def load(name: str, profile: str = "reference", **overrides) -> Engine:
    """An engine adapter with the named profile's settings, any of them overridden."""
    return create(name, settings_for(name, profile, **overrides))


__all__ = ["BodyLoad", "ContactReference", "ENTRY_POINT_GROUP", "Engine", "EngineNotInstalled",
           "EngineRecord", "Integrator", "KnobFamily", "MassProperties", "PROFILES", "PluginConflict",
           "Reading", "RestitutionRule", "SceneMismatch", "Settings", "SimOutcome", "Status",
           "SwingPlan", "available", "create", "engine_class", "import_engine", "load", "loaded", "missing", "names", "record",
           "reload_plugins", "settings_for", "start_reading", "swing_case"]
