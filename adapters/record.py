"""What the harness knows about an engine, readable without importing the engine.

Each engine declares one ``EngineRecord`` and a ``Settings`` subclass (its knobs) in a module
that imports no engine; the record names the adapter class (``adapter = "module:Class"``),
imported only when an impact is fired. Experiments and tests read engine facts only from here
(through ``adapters.record(name)``): the install hint, the version, the profiles, the plot style,
the knob grid of the speed-vs-accuracy study, the integrators of the swing study, the float
precision the tolerances derive from; the settings say which contact model they converge to.
"""

from __future__ import annotations

import contextlib
import dataclasses
import importlib
import math
import os
import sys
from collections.abc import Iterator, Mapping
from dataclasses import dataclass, field
from enum import Enum
from importlib import metadata
from types import MappingProxyType, ModuleType
from typing import Any

import numpy as np

from analytic import checks

from .parts import (
    Capabilities,
    Cost,
    ErrorModel,
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
__all__ = ["PROFILES", "Capabilities", "ContactReference", "Cost", "EngineNotInstalled",
           "EngineRecord", "ErrorModel", "FrictionRule", "Install", "Integrator", "KnobFamily",
           "Presentation", "ReportNotes", "RestitutionRule", "Settings", "Studies", "TwinStep",
           "import_engine"]

#: Profiles every engine must offer: tuned for fidelity, and the engine's own defaults.
PROFILES = ("reference", "default")


class EngineNotInstalled(ImportError):
    """The chosen engine's Python package is missing."""


class ContactReference(str, Enum):
    """The continuous model an engine's contact converges to as its time step shrinks."""

    RIGID_IMPULSE = "rigid impulse"  #: Newton's restitution law, instantaneous (analytic.predict)
    LINEAR_SPRING_DAMPER = "linear spring-damper"  #: x'' = -b x' - k x in the contact coordinate
    #: F = k x^n (1 + d x'): a penalty force with Hunt-Crossley dissipation (analytic.compliant)
    HUNT_CROSSLEY = "Hunt-Crossley"


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

    The methods say what contact these settings make; an engine whose contact is not a rigid
    impulse, or is solved ahead of touching, overrides them.
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

    def contact_reference(self) -> ContactReference:
        """The continuous model the contact converges to as the step shrinks."""
        return ContactReference.RIGID_IMPULSE

    def contact_law(self, e: float):
        """The continuous contact law (``analytic.compliant``) the contact converges to at
        restitution ``e``, or None for a rigid contact."""
        return None

    def law_restitution_error(self, dt_over_contact: float) -> float:
        """The relative error of the restitution a step of ``dt_over_contact`` contact times
        leaves in a compliant contact (its leading term; the judge allows a multiple of it).
        Semi-implicit Euler through a spring-damper: (pi/3) dt/t_c (measured -5.0e-3 for MuJoCo
        at w = 3000 rad/s, dt = 1e-5 s, against 5.2e-3 from the formula)."""
        return math.pi / 3.0 * dt_over_contact

    def untuned_contact_s(self) -> float | None:
        """How long a contact lasts when the engine's contact is not tuned to any model (its
        own soft constraint, say), for estimating a run's cost; None: as long as in the model
        it converges to."""
        return None

    def mapping_error_rel(self) -> float:
        """The relative error the engine's mapping of e leaves in a contact's impulse (a known
        bias of the mapping, not a precision); 0 for an exact mapping."""
        return 0.0

    def solve_conditioning(self) -> float:
        """How much the engine's contact solve amplifies its rounding (a condition number): a
        stiff regulariser's solve in float32 loses that many ulps; 1 for a well-posed one."""
        return 1.0

    def collision_slide_m(self, bat) -> float:
        """How far along the bat's axis (m) the engine's collision routine may put the contact
        foot from the true closest point (a bias of its own, not a precision), which the judge
        adds to the foot's slide; 0 for an exact routine."""
        return 0.0

    def speculative_margin_m(self) -> float:
        """The gap (m) below which the engine already solves a contact (speculative contact):
        such a contact is solved from the geometry at the start of the step that closes it, up
        to a whole step early; 0 for engines that see a contact once the bodies overlap."""
        return 0.0

    def friction_law(self) -> str:
        """The frictional impulse law (``analytic.friction.LAWS``) the contact converges to as
        its step shrinks: an impulse engine's 'one_step' (Newton's restitution and Coulomb's
        cone on the total impulse), or a convex solver's 'relaxed' one (a slide leaves faster
        by mu times its final slip)."""
        return "one_step"

    def friction_mapping_error_rel(self) -> float:
        """The share of a slip the engine's friction mapping leaves where Coulomb's law would
        stop it within the step (a regularised friction row); 0 for an exact one."""
        return 0.0

    def friction_cone(self) -> str:
        """How the engine's contact approximates Coulomb's cone with these settings, in words
        (tables and the friction study record it); '' for an engine without friction."""
        return ""


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
    ``studies``: what the studies vary in it.
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

    def __post_init__(self) -> None:
        missing = [p for p in PROFILES if p not in self.profiles]
        if missing:
            raise ValueError(f"engine {self.name!r} has no {missing[0]!r} profile; allowed: "
                             f"profiles that include {', '.join(PROFILES)}")
        if ":" not in self.adapter:
            raise ValueError(f"adapter={self.adapter!r} is not 'module:Class'; allowed: the "
                             "adapter class's module and name, joined by ':'")
        object.__setattr__(self, "profiles", MappingProxyType(dict(self.profiles)))
        object.__setattr__(self, "engine_defaults", MappingProxyType(dict(self.engine_defaults)))

    @property
    def eps(self) -> float:
        """Unit roundoff of the engine's float type (2.2e-16 for float64, 1.2e-7 for float32)."""
        return float(np.finfo(self.errors.precision).eps)

    @property
    def install_hint(self) -> str:
        """What to run when the engine's package is missing."""
        i = self.install
        target = f"'batsim[{i.extra}]'" if i.extra else i.package
        return (f"engine {self.name!r} needs the package {i.package!r}: pip install {target}  "
                "(or `make test`, which installs every engine)")

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


def import_engine(record: EngineRecord) -> ModuleType:
    """Import the engine's module, or raise EngineNotInstalled with the install hint. Whatever
    the engine prints to the process's stdout while it loads (PyBullet's build-time banner) is
    dropped, so that it never mixes with a command's own output."""
    try:
        with _stdout_silenced():
            for name in record.install.requires:
                importlib.import_module(name)
            return importlib.import_module(record.install.import_name)
    except ModuleNotFoundError as err:
        tops = {m.split(".")[0] for m in (record.install.import_name, *record.install.requires)}
        if err.name is None or err.name.split(".")[0] not in tops:
            raise
        raise EngineNotInstalled(record.install_hint) from err


@contextlib.contextmanager
def _stdout_silenced() -> Iterator[None]:
    """Point file descriptors 1 and 2 at /dev/null for the block (C libraries print there
    directly); an import error still arrives as a Python exception."""
    streams = []
    for stream in (sys.stdout, sys.stderr):
        try:
            streams.append(stream.fileno())
            stream.flush()
        except (AttributeError, OSError, ValueError):  # no real stream (captured by pytest)
            continue
    saved = [os.dup(fd) for fd in streams]
    try:
        with open(os.devnull, "wb") as null:
            for fd in streams:
                os.dup2(null.fileno(), fd)
        yield
    finally:
        _flush_c_stdio()  # C's buffered output would otherwise reach the real streams later
        for fd, copy in zip(streams, saved):
            os.dup2(copy, fd)
            os.close(copy)


def _flush_c_stdio() -> None:
    import ctypes

    try:
        ctypes.CDLL(None).fflush(None)
    except (OSError, AttributeError):
        pass
