"""Engines by name: the registry. Importing it, listing engines and reading their records load
no engine; an engine is imported when an adapter is made (``load``, ``create``).

    import adapters
    adapters.names()                                    # every registered engine
    adapters.record("mujoco").look.color                     # an engine's facts (adapters.record)
    adapters.available(), adapters.missing()            # installed or not (without importing)
    eng = adapters.load("pybullet", profile="default", dt_s=1e-4)   # an adapter, any override

Engines are registered three ways, the same to the rest of the harness:
- built in: every subpackage of this package is an engine named after it; its ``__init__``
  declares ``RECORD`` (and imports no engine), its ``adapter`` module the adapter class;
- plug-ins: an installed distribution declaring, in its pyproject.toml,
  ``[project.entry-points."batsim.engines"]`` ``NAME = "module:RECORD"``; the entry point's name
  is the engine's name (it may not be a built-in's);
- in this process: ``register(record)`` (an adapter under development, before it is packaged).
A plug-in that cannot be loaded (its module fails to import, it names a missing module or
attribute, its entry point shadows another engine's name) is not registered: ``broken()`` says
why, and no other engine is touched.
The interface an adapter implements is ``adapters.interface``; ``experiments.core.check_engine``
checks one.
"""

from __future__ import annotations

import dataclasses
import functools
import importlib
import importlib.util
import pkgutil
import sys
from importlib import metadata
from pathlib import Path
from types import MappingProxyType

from . import clock
from .interface import (
    PLANAR_FIELDS,
    SPATIAL_FIELDS,
    STATE_FIELDS,
    BatchedEngine,
    Engine,
    Hands,
    MassProperties,
    Scene,
    State,
)
from .loading import engine_threads, import_engine, set_engine_threads
from .records import (
    PROFILES,
    RESTITUTION_KNOB,
    BallContact,
    Batching,
    Capabilities,
    ContactKnob,
    ContactReference,
    Cost,
    EngineNotInstalled,
    EngineRecord,
    ErrorModel,
    FrictionRule,
    Install,
    Integrator,
    KnobFamily,
    MissingFeature,
    Presentation,
    ReportNotes,
    RestitutionRule,
    Settings,
    Studies,
    TwinStep,
)

ENTRY_POINT_GROUP = "batsim.engines"
#: Colours for engines whose record names none (plug-ins), in registry order: none of them a
#: built-in's (blue, orange, green, purple, brown, red, black).
PALETTE = ("tab:pink", "tab:gray", "tab:olive", "tab:cyan", "gold", "teal", "navy", "magenta")
_REGISTERED: dict[str, EngineRecord] = {}


class PluginConflict(ValueError):
    """A name registered in this process is taken already."""


class BrokenPlugin(EngineNotInstalled):
    """An installed plug-in that cannot be loaded (``broken()`` says why)."""


@functools.cache
def _registry() -> tuple[MappingProxyType, MappingProxyType]:
    """Engine name -> where its record is ("module:RECORD" for a built-in, the record itself
    for a plug-in or one registered in this process), built-ins first, by name, then plug-ins,
    then registered ones; and the broken plug-ins' names -> why each is left out."""
    here = Path(__file__).parent
    builtins = {
        m.name: f"{__name__}.{m.name}:RECORD"
        for m in sorted(pkgutil.iter_modules([str(here)]), key=lambda m: m.name)
        if m.ispkg
    }
    plugins: dict[str, EngineRecord] = {}
    broken: dict[str, str] = {}
    for ep in sorted(metadata.entry_points(group=ENTRY_POINT_GROUP), key=lambda e: e.name):
        dist = ep.dist.name if ep.dist is not None else "an unknown distribution"
        if ep.name in builtins:
            broken[ep.name] = (
                f"plug-in {ep.value} from {dist} shadows the built-in engine "
                f"{ep.name!r}; allowed: a name that is not one of "
                f"{', '.join(builtins)}"
            )
        elif ep.name in plugins or ep.name in broken:
            broken[ep.name] = (
                f"declared twice (the second: {ep.value} from {dist}); allowed: "
                "one entry point per name"
            )
            plugins.pop(ep.name, None)
        else:
            try:
                plugins[ep.name] = _plugin_record(ep.name, ep.value)
            except Exception as err:  # noqa: BLE001 - a plug-in may fail any way; it is left out
                broken[ep.name] = f"{ep.value} from {dist} cannot be loaded: {_said(err)}"
    return (MappingProxyType({**builtins, **plugins, **_REGISTERED}), MappingProxyType(broken))


#: How long a plug-in's record may take to import (s): a module that imports no engine takes
#: milliseconds; one that blocks would hang every command, --help too.
IMPORT_LIMIT_S = 20.0


def _plugin_record(name: str, target: str) -> EngineRecord:
    """A plug-in's record, loaded (its module imports no engine) within IMPORT_LIMIT_S;
    whatever goes wrong, an exception (an exit, a block, a KeyboardInterrupt at its import
    too: no Ctrl-C lands in these milliseconds but by chance)."""
    try:
        with clock.limited(IMPORT_LIMIT_S), clock.exits_raise():
            rec = _load_target(name, target)
    except (SystemExit, clock.ProcessExit) as stop:
        call = "sys.exit" if isinstance(stop, SystemExit) else "os._exit"
        raise RuntimeError(f"its import called {call}({stop.code!r})") from None
    except clock.TimedOut:
        raise RuntimeError(f"its import did not end within {IMPORT_LIMIT_S:g} s") from None
    except KeyboardInterrupt:
        raise RuntimeError("its import raised KeyboardInterrupt") from None
    if not isinstance(rec, EngineRecord):
        raise TypeError(f"{target} is a {type(rec).__name__}, not an adapters.EngineRecord")
    return rec


def _said(err: BaseException) -> str:
    """An exception in one line (type and message)."""
    return f"{type(err).__name__}: {' '.join(str(err).split())}"[:300]


def broken() -> MappingProxyType:
    """Installed plug-ins that are left out, by their entry point's name -> why (a module that
    fails to import, a missing attribute, a name another engine has)."""
    return _registry()[1]


def reload_plugins() -> None:
    """Forget what the registry found, so that the next call looks for entry points again."""
    importlib.invalidate_caches()
    _registry.cache_clear()
    record.cache_clear()


def register(rec: EngineRecord) -> None:
    """Register an engine in this process under ``rec.name`` (for an adapter under development;
    a packaged one declares an entry point). Raises PluginConflict for a name already taken."""
    if rec.name in _registry()[0] and _REGISTERED.get(rec.name) is not rec:
        raise PluginConflict(
            f"engine {rec.name!r} is registered already; allowed: a name that "
            f"is not one of {', '.join(names())}"
        )
    _REGISTERED[rec.name] = rec
    reload_plugins()


def unregister(name: str) -> None:
    """Forget an engine registered with ``register``."""
    _REGISTERED.pop(name, None)
    reload_plugins()


def names() -> tuple[str, ...]:
    """Registered engine names: built-ins by name, then plug-ins by name."""
    return tuple(_registry()[0])


def _check_name(name: str) -> str:
    if name in broken() and name not in _registry()[0]:
        raise BrokenPlugin(f"engine {name!r} is a broken plug-in: {broken()[name]}")
    if name not in _registry()[0]:
        raise ValueError(f"engine={name!r} is unknown; allowed: {', '.join(names())}")
    return name


@functools.cache
def record(name: str) -> EngineRecord:
    """The engine's record, named as registered and with a plot colour filled in (imports the
    module that declares it, never the engine)."""
    target = _registry()[0][_check_name(name)]
    rec = target if isinstance(target, EngineRecord) else _load_target(name, target)
    if not isinstance(rec, EngineRecord):
        raise TypeError(f"engine {name!r}: {target} is not an adapters.EngineRecord")
    color = rec.look.color
    if rec.name != name:  # a plug-in reusing a record under its own name gets its own style
        rec, color = dataclasses.replace(rec, name=name), None
    if color is None:
        color = PALETTE[names().index(name) % len(PALETTE)]
        rec = dataclasses.replace(rec, look=dataclasses.replace(rec.look, color=color))
    return rec


def _load_target(name: str, target: str):
    module_name, attr = target.split(":")
    try:
        return getattr(importlib.import_module(module_name), attr)
    except ModuleNotFoundError as err:
        raise EngineNotInstalled(
            f"engine {name!r} ({target}) could not be imported: {err}; "
            "allowed: an installed plug-in"
        ) from err


def _installed(rec: EngineRecord) -> bool:
    """Its modules (``import_name`` and ``requires``) are found and its distribution installed
    (MJX's ``mujoco.mjx`` comes from ``mujoco-mjx`` into the ``mujoco`` package: finding
    ``mujoco`` is not enough)."""
    if not all(_found(m) for m in (rec.install.import_name, *rec.install.requires)):
        return False
    if rec.install.import_name == rec.install.import_name.split(".")[0]:
        return True
    try:
        metadata.distribution(rec.install.package)
    except metadata.PackageNotFoundError:
        return False
    return True


def _found(module: str) -> bool:
    """The module or its top-level package is findable and not blocked in this process
    (``sys.modules[name] = None``), without importing it."""
    top = module.split(".")[0]
    if any(n in sys.modules and sys.modules[n] is None for n in (module, top)):
        return False
    return top in sys.modules or importlib.util.find_spec(top) is not None


def available() -> tuple[str, ...]:
    """Registered engines whose package is installed (found, not imported), in registry order;
    ``missing()`` says why the others are not."""
    return tuple(n for n in names() if _installed(record(n)))


def missing() -> MappingProxyType:
    """Registered engine name -> its install hint, for engines whose package is not installed."""
    return MappingProxyType(
        {n: record(n).install_hint for n in names() if not _installed(record(n))}
    )


def engine_class(name: str) -> type[Engine] | type[BatchedEngine]:
    """The adapter class for ``name``, importing its engine now (EngineNotInstalled if missing)."""
    rec = record(name)
    if not _installed(rec):
        raise EngineNotInstalled(rec.install_hint)
    cls = _load_target(name, rec.adapter)
    if not (isinstance(cls, type) and issubclass(cls, (Engine, BatchedEngine))):
        raise TypeError(
            f"engine {name!r}: {rec.adapter} is not an adapters.Engine or "
            "adapters.BatchedEngine subclass"
        )
    return cls


def chain_class(name: str):
    """The segmented-bat adapter class for ``name`` (its record's ``chain_adapter``, an
    ``adapters.segmented.ChainEngine``), importing its engine now; None if it has none."""
    return _capability_class(name, "chain_adapter")


def pool_class(name: str):
    """The class holding many of a single-world engine's worlds in one engine instance (its
    record's ``pool_adapter``, an ``adapters.BatchedEngine``), importing its engine now; None
    if it has none."""
    return _capability_class(name, "pool_adapter")


def _capability_class(name: str, field: str):
    """The class a record's capability ``field`` names ("module:Class"), or None."""
    rec = record(name)
    target = getattr(rec.can, field)
    if target is None:
        return None
    if not _installed(rec):
        raise EngineNotInstalled(rec.install_hint)
    return _load_target(name, target)


def is_batched(name: str) -> bool:
    """Whether the engine's adapter steps many worlds in one call (imports the engine)."""
    return issubclass(engine_class(name), BatchedEngine)


def settings_for(name: str, profile: str = "reference", **overrides) -> Settings:
    """The named profile's settings for an engine, with any field overridden (validated)."""
    rec = record(name)
    if profile not in rec.profiles:
        raise ValueError(f"profile={profile!r} is unknown; allowed: {', '.join(rec.profiles)}")
    base = rec.profiles[profile]
    valid = {f.name for f in dataclasses.fields(base)}
    unknown = sorted(set(overrides) - valid)
    if unknown:
        raise ValueError(
            f"setting {unknown[0]!r} is unknown for {name}; allowed: {', '.join(sorted(valid))}"
        )
    return dataclasses.replace(base, **overrides)


def contact_reference(name: str, profile: str = "reference") -> ContactReference:
    """The model the engine's contact converges to at ``profile`` (its error model's answer)."""
    return record(name).errors.contact_reference(settings_for(name, profile))


def create(name: str, settings: Settings) -> Engine | BatchedEngine:
    """An adapter of this engine with these settings (imports the engine)."""
    return engine_class(name)(settings)


def load(name: str, profile: str = "reference", **overrides) -> Engine | BatchedEngine:
    """An adapter with the named profile's settings, any of them overridden."""
    return create(name, settings_for(name, profile, **overrides))


__all__ = [
    "BallContact",
    "BatchedEngine",
    "Batching",
    "Capabilities",
    "ContactKnob",
    "ContactReference",
    "Cost",
    "ENTRY_POINT_GROUP",
    "Engine",
    "EngineNotInstalled",
    "EngineRecord",
    "ErrorModel",
    "FrictionRule",
    "Hands",
    "Install",
    "Integrator",
    "KnobFamily",
    "MassProperties",
    "MissingFeature",
    "BrokenPlugin",
    "PLANAR_FIELDS",
    "PROFILES",
    "PluginConflict",
    "RESTITUTION_KNOB",
    "Presentation",
    "ReportNotes",
    "RestitutionRule",
    "SPATIAL_FIELDS",
    "STATE_FIELDS",
    "Scene",
    "Settings",
    "State",
    "Studies",
    "TwinStep",
    "available",
    "broken",
    "chain_class",
    "contact_reference",
    "create",
    "engine_class",
    "engine_threads",
    "import_engine",
    "is_batched",
    "load",
    "missing",
    "names",
    "record",
    "register",
    "reload_plugins",
    "set_engine_threads",
    "settings_for",
    "unregister",
]
