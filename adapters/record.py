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

from .rules import FrictionRule, RestitutionRule

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
class KnobFamily:
    """One family of settings in the speed-vs-accuracy study; the study crosses it with its time
    steps. ``overrides`` are settings fields and values; ``quick`` keeps it in ``--quick``."""

    label: str
    overrides: tuple[tuple[str, Any], ...] = ()
    profile: str = "reference"
    quick: bool = False


@dataclass(frozen=True, kw_only=True)
class Integrator:
    """One of an engine's time integrators, for the swing study: its ``label``, the settings
    ``overrides`` that choose it, and its global ``order`` (1: the semi-implicit Euler family,
    which leaves a constant angular acceleration's angle off by alpha t dt / 2; 4: RK4)."""

    label: str
    overrides: tuple[tuple[str, Any], ...] = ()
    order: int = 1
    #: How the hands' hinge error shrinks with dt: 2 for a pivot re-projected every step (a
    #: relative (omega dt)^2), 1 for a soft joint whose drift is corrected at a fixed rate
    #: (Box2D's 60 Hz joints).
    hinge_order: int = 2


@dataclass(frozen=True, kw_only=True)
class TwinStep:
    """One comparison of an engine with the engine whose model it implements (its record's
    ``twin_of``), for ``experiments.twins``: the engine at its reference profile with
    ``overrides``, the twin at its own reference profile, with every settings field the two
    share copied over when ``shared`` (the same model, as far as the twin can express it), then
    ``twin_overrides``. Steps go from as-configured to every known cause removed."""

    label: str
    overrides: tuple[tuple[str, Any], ...] = ()
    twin_overrides: tuple[tuple[str, Any], ...] = ()
    shared: bool = True


@dataclass(frozen=True, kw_only=True)
class ReportNotes:
    """What the results report says of an engine, in the engine's own words. Each text is a
    format string filled with the reference settings the baseline sweep recorded (by field
    name), the record's ``engine_defaults`` (``default_`` + field name), ``version``, and the
    sweep's ``err_mps`` (largest |v1 - rigid theory|) and ``law_err_mps`` (against its own
    contact law); times, lengths and other numbers come formatted by their unit suffix.
    ``profile``: the reference profile in words; ``restitution``: what plays the role of e;
    ``handled``: what the adapter had to work around ('' for nothing worth a line);
    ``defaults``: how its quoted defaults were read back or measured."""

    profile: str
    restitution: str
    handled: str = ""
    defaults: str = ""


@dataclass(frozen=True, kw_only=True)
class EngineRecord:
    """Everything the harness knows about one engine.

    ``adapter``: "module:Class" of its adapter (an ``adapters.interface`` Engine or
    BatchedEngine), imported only to fire. ``package``: the PyPI distribution that provides the
    engine, ``import_name`` the module it imports (they differ, e.g. sapien vs physx), ``extra``
    the batsim extra that installs it (None: a core dependency); ``requires``: other modules its
    adapter imports, another engine's among them (MJX and MuJoCo Warp load MJCF through
    ``mujoco``): without one, the engine counts as not installed. ``profiles``: at least
    PROFILES; the ``default`` profile is the engine out of the box (its own time step and
    solver values). ``color``/``marker``: plot style (None: one from the registry's palette).
    ``speed_accuracy``: its knob families besides the two profiles. ``integrators``: for the
    swing study (empty: the engine cannot drive the bat). ``precision``: the float type it
    computes in ("float64" or "float32"). ``restitution_rule``: how it combines two bodies'
    restitution; ``threshold_setting``: the settings field of its restitution velocity
    threshold, if any. ``soft_contact``: the overrides that switch it to a spring-damper
    contact, if it has one, whose natural frequency (rad/s) is the settings field
    ``stiffness_setting``. ``engine_defaults``: the engine's own out-of-the-box values of
    settings fields (what the README quotes), each read back (``read_back_defaults``) or
    measured: a test pins both. ``step_cost_s``: the rough wall time of one reference step
    (s, ``experiments.bench_engines``' one-world step, every engine measured in the same run on
    one 2-core host like CI's: only their ratios carry over to another host), for run-time
    estimates only; a batched engine's
    ``world_step_cost_s`` is what each further world adds to a step (s; ``step_cost_s`` is then
    a step of one world; None for a single-world engine: ``batched`` says which), and
    ``start_s`` what each new batch size first costs in a process (s: JAX's trace and compile,
    Warp's module load; measured from the baseline sweeps' wall times). ``label``: the
    name as prose spells it ('' for ``name``); ``notes``: what the report says of it.
    ``twin_of``: the engine whose model this one implements (MJX of MuJoCo C), for
    ``experiments.twins``; its settings class extends the twin's, so the same fields mean the
    same model; ``twin_steps`` the comparisons that find what makes them differ.
    ``friction_rule``: how it combines two bodies' friction (None: its adapter does not set
    friction, and an impact with friction is ``unsupported``); ``planar``: a 2-D engine, which
    cannot fire an impact out of the swing plane (an undercut, a spin about x or y);
    ``friction_families``: its friction models besides the reference's (another cone, friction
    solved otherwise), for the friction study; ``friction_rule_overrides``: the reference
    settings overridden so that the two bodies' own friction values make the contact's (where
    the reference's contact takes a mu of its own, as MuJoCo's explicit pair does), for the
    test that pins ``friction_rule``; ``friction_defect``: a measured failure of its friction at
    impact that no setting removes ('' for none): the wall tests then pin that the engine still
    misses Coulomb's limits, and the report quotes it. ``host_rounding``: its kernels are
    compiled for the host's CPU (XLA), whose instruction set orders the rounding: its rows differ
    from host to host by rounding (amplified where its solve is ill-conditioned), so a committed
    baseline is reproduced bit for bit only where it was made. ``chain_adapter``: "module:Class"
    of its segmented-bat adapter (``adapters.segmented.ChainEngine``), None where it has none;
    ``chain_defect``: a measured failure of its segmented bat that no setting removes ('' for
    none): the chain tests then pin that the engine still misses the linear chain.
    """

    name: str
    adapter: str
    package: str
    import_name: str
    extra: str | None = None
    requires: tuple[str, ...] = ()
    profiles: Mapping[str, Settings]
    color: str | None = None
    marker: str = "o"
    speed_accuracy: tuple[KnobFamily, ...] = ()
    integrators: tuple[Integrator, ...] = (Integrator(label="semi-implicit Euler"),)
    precision: str = "float64"
    restitution_rule: RestitutionRule = RestitutionRule.PRODUCT
    threshold_setting: str | None = None
    soft_contact: Mapping[str, Any] | None = None
    stiffness_setting: str | None = None
    engine_defaults: Mapping[str, Any] = field(default_factory=dict)
    step_cost_s: float = 1e-5
    world_step_cost_s: float | None = None
    start_s: float = 0.0
    label: str = ""
    notes: ReportNotes | None = None
    twin_of: str | None = None
    twin_steps: tuple[TwinStep, ...] = ()
    friction_rule: FrictionRule | None = None
    planar: bool = False
    friction_families: tuple[KnobFamily, ...] = ()
    friction_rule_overrides: Mapping[str, Any] = field(default_factory=dict)
    friction_defect: str = ""
    host_rounding: bool = False
    chain_adapter: str | None = None
    chain_defect: str = ""

    def __post_init__(self) -> None:
        missing = [p for p in PROFILES if p not in self.profiles]
        if missing:
            raise ValueError(f"engine {self.name!r} has no {missing[0]!r} profile; allowed: "
                             f"profiles that include {', '.join(PROFILES)}")
        if self.precision not in ("float64", "float32"):
            raise ValueError(f"precision={self.precision!r} is unknown; allowed: float64, float32")
        if ":" not in self.adapter:
            raise ValueError(f"adapter={self.adapter!r} is not 'module:Class'; allowed: the "
                             "adapter class's module and name, joined by ':'")
        object.__setattr__(self, "profiles", MappingProxyType(dict(self.profiles)))
        object.__setattr__(self, "engine_defaults", MappingProxyType(dict(self.engine_defaults)))
        object.__setattr__(self, "friction_rule_overrides",
                           MappingProxyType(dict(self.friction_rule_overrides)))
        if (self.soft_contact is None) != (self.stiffness_setting is None):
            raise ValueError(f"engine {self.name!r}: soft_contact and stiffness_setting go "
                             "together; allowed: both or neither")
        checks.positive("step_cost_s", self.step_cost_s)
        if self.world_step_cost_s is not None:
            checks.positive("world_step_cost_s", self.world_step_cost_s)
        checks.non_negative("start_s", self.start_s)

    @property
    def eps(self) -> float:
        """Unit roundoff of the engine's float type (2.2e-16 for float64, 1.2e-7 for float32)."""
        return float(np.finfo(self.precision).eps)

    @property
    def install_hint(self) -> str:
        """What to run when the engine's package is missing."""
        target = f"'batsim[{self.extra}]'" if self.extra else self.package
        return (f"engine {self.name!r} needs the package {self.package!r}: pip install {target}  "
                "(or `make test`, which installs every engine)")

    @property
    def batched(self) -> bool:
        """Whether the engine steps many worlds per call (``BatchedEngine``): a batched record
        prices its worlds (``world_step_cost_s``), a single-world one does not."""
        return self.world_step_cost_s is not None

    @property
    def drives_bat(self) -> bool:
        """Whether the engine can swing the bat (its adapter implements ``set_drive``)."""
        return bool(self.integrators)

    def version(self) -> str:
        """The installed version of the engine's package."""
        return metadata.version(self.package)


def import_engine(record: EngineRecord) -> ModuleType:
    """Import the engine's module, or raise EngineNotInstalled with the install hint. Whatever
    the engine prints to the process's stdout while it loads (PyBullet's build-time banner) is
    dropped, so that it never mixes with a command's own output."""
    try:
        with _stdout_silenced():
            for name in record.requires:
                importlib.import_module(name)
            return importlib.import_module(record.import_name)
    except ModuleNotFoundError as err:
        tops = {m.split(".")[0] for m in (record.import_name, *record.requires)}
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
