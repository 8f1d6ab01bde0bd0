"""What the harness knows about an engine, readable without importing the engine.

Each engine declares one ``EngineRecord`` and a ``Settings`` subclass (its knobs) in a module
that imports no engine; the record names the adapter class (``adapter = "module:Class"``),
imported only when an impact is fired. Experiments and tests read engine facts only from here
(through ``adapters.record(name)``): the install hint, the version, the profiles, the plot style,
the knob grid of the speed-vs-accuracy study, the integrators of the swing study, the float
precision the tolerances derive from and the contact model each setting converges to (its
error model, ``adapters.errors``).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping
from dataclasses import dataclass, field
from importlib import metadata
from types import MappingProxyType
from typing import Any

from analytic import checks

from .errors import ContactReference, ErrorModel
from .parts import (
    RESTITUTION_KNOB,
    BallContact,
    Batching,
    Capabilities,
    ContactKnob,
    Cost,
    Install,
    Integrator,
    KnobFamily,
    Presentation,
    ReportNotes,
    Studies,
    TwinStep,
)
from .rules import FrictionRule, RestitutionRule

#: The record's vocabulary, for the engines' record modules: this module and ``parts``.
__all__ = [
    "PROFILES",
    "RESTITUTION_KNOB",
    "BallContact",
    "Batching",
    "Capabilities",
    "ContactKnob",
    "ContactReference",
    "Cost",
    "EngineNotInstalled",
    "EngineRecord",
    "ErrorModel",
    "FrictionRule",
    "Install",
    "Integrator",
    "KnobFamily",
    "MissingFeature",
    "Presentation",
    "ReportNotes",
    "RestitutionRule",
    "Settings",
    "Studies",
    "TwinStep",
]

#: Profiles every engine must offer: tuned for fidelity, and the engine's own defaults.
PROFILES = ("reference", "default")


class EngineNotInstalled(ImportError):
    """The chosen engine's Python package is missing."""


class MissingFeature(NotImplementedError):
    """The installed release of the engine lacks what these settings ask of it (an older
    release, met by ``experiments.history``): its impacts are ``unsupported``, and say why."""


@dataclass(frozen=True, kw_only=True)
class Settings:
    """Knobs common to every engine; each engine's settings class extends it with its own.

    ``dt_s``: time step (s). ``contact_phase``: where in a step the true contact instant falls,
    0 = on a step boundary (the harness's exact placement), 0.5 = mid-step (what an unaligned
    simulation meets on average). ``overlap_m``: overlap at the first step that sees the contact
    (m). ``approach_steps``: free steps before contact. ``max_contact_s``: an impact episode
    (first contact to its end, as ``analytic.collide`` ends it) longer than this is reported
    ``no_separation`` (s); 0.1 s covers every plastic impact on the barrel of our bats but those
    where the ball rides the bat near its COM for longer (the rigid episode too then).

    Settings are knobs only: what contact they make, and how far from theory it may land, the
    engine's error model says (``adapters.errors.ErrorModel``, the record's ``errors``).
    """

    dt_s: float
    contact_phase: float = 0.0
    overlap_m: float = 1e-9
    approach_steps: int = 2
    max_contact_s: float = 0.1

    def __post_init__(self) -> None:
        checks.positive("dt_s", self.dt_s)
        checks.in_range("contact_phase", self.contact_phase, 0.0, 1.0, hi_open=True)
        checks.non_negative("overlap_m", self.overlap_m)
        checks.integer("approach_steps", self.approach_steps, 1, 1000)
        checks.positive("max_contact_s", self.max_contact_s)

    def as_dict(self) -> dict:
        """Flat dict of every setting, for tables and provenance."""
        return dataclasses.asdict(self)


@dataclass(frozen=True, kw_only=True)
class EngineRecord:
    """Everything the harness knows about one engine, in parts (``adapters.parts``).

    ``name``: what ``--engine`` takes. ``adapter``: "module:Class" of its adapter (an
    ``adapters.interface`` Engine or BatchedEngine), imported only to fire. ``install``: where
    the engine comes from. ``profiles``: at least PROFILES (instances of its ``Settings``
    subclass); the ``default`` profile is the engine out of the box (its own time step and
    solver values). ``can``: what it can do. An adapter author fills these five; the rest have
    defaults. ``errors``: its error model beyond the settings (precision, declared defects).
    ``engine_defaults``: the engine's own out-of-the-box values of settings fields (what the
    README quotes), each read back (``read_back_defaults``) or measured: a test pins both.
    ``cost``: what a step costs, for estimates. ``look``: how charts and the report show it.
    ``studies``: what the studies vary in it. ``balls``: the contact models a real ball is
    fitted in, each with its knobs (``experiments.realball`` fits every one and names the
    best; one or more, labels unique). ``batching``: what its library
    offers to step many worlds at once and whether the harness uses it (None: the record
    does not say; every built-in engine says).
    """

    name: str
    adapter: str
    install: Install
    profiles: Mapping[str, Settings]
    can: Capabilities = Capabilities(integrators=(Integrator(label="semi-implicit Euler"),))
    errors: ErrorModel = ErrorModel()
    engine_defaults: Mapping[str, Any] = field(default_factory=dict)
    cost: Cost = Cost()
    look: Presentation = Presentation()
    studies: Studies = Studies()
    batching: Batching | None = None
    balls: tuple[BallContact, ...] = (BallContact(),)

    def __post_init__(self) -> None:
        missing = [p for p in PROFILES if p not in self.profiles]
        if missing:
            raise ValueError(
                f"engine {self.name!r} has no {missing[0]!r} profile; allowed: "
                f"profiles that include {', '.join(PROFILES)}"
            )
        if ":" not in self.adapter:
            raise ValueError(
                f"adapter={self.adapter!r} is not 'module:Class'; allowed: the "
                "adapter class's module and name, joined by ':'"
            )
        if self.cost.pool_world_make_s is not None and self.can.pool_adapter is None:
            raise ValueError(
                f"engine {self.name!r}: cost.pool_world_make_s without can.pool_adapter; "
                "allowed: a pool world's cost for an engine that has a pool adapter"
            )
        labels = [b.label for b in self.balls]
        if not labels or len(set(labels)) != len(labels):
            raise ValueError(
                f"engine {self.name!r}: balls labelled {labels}; allowed: one or more ball "
                "models, each label once"
            )
        object.__setattr__(self, "profiles", MappingProxyType(dict(self.profiles)))
        object.__setattr__(self, "engine_defaults", MappingProxyType(dict(self.engine_defaults)))

    @property
    def eps(self) -> float:
        """Unit roundoff of the engine's float type (2.2e-16 for float64, 1.2e-7 for float32)."""
        return self.errors.eps

    @property
    def install_hint(self) -> str:
        """What to run when the engine's package is missing."""
        i = self.install
        target = f"'batsim[{i.extra}]'" if i.extra else i.package
        return (
            f"engine {self.name!r} needs the package {i.package!r}: pip install {target}  "
            "(or `make test`, which installs every engine)"
        )

    @property
    def batched(self) -> bool:
        """Whether the engine steps many worlds per call (``BatchedEngine``): a batched record
        prices its worlds (``cost.world_step_cost_s``), a single-world one does not."""
        return self.cost.world_step_cost_s is not None

    @property
    def drives_bat(self) -> bool:
        """Whether the engine can swing the bat (its adapter implements ``set_drive``)."""
        return bool(self.can.integrators)

    def version(self) -> str:
        """The installed version of the engine's package."""
        return metadata.version(self.install.package)
