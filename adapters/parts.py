"""The parts of an engine's record (``adapters.EngineRecord``), each read by one kind of
reader: where the engine comes from (``Install``) and what it can do (``Capabilities``), what
an adapter author declares; what it gets wrong and in which float type (``ErrorModel``, in
``adapters.errors``), what the judge reads; what a step costs (``Cost``), for the estimates;
how it is shown (``Presentation``), for charts and the report; what the studies vary
(``Studies``); and what its library offers to step many worlds at once (``Batching``)."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from types import MappingProxyType
from typing import Any

from analytic import checks

from .rules import FrictionRule, RestitutionRule


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
class Install:
    """``package``: the PyPI distribution that provides the engine, ``import_name`` the module
    it imports (they differ, e.g. sapien vs physx), ``extra`` the batsim extra that installs it
    (None: a core dependency); ``requires``: other modules its adapter imports, another
    engine's among them (MJX and MuJoCo Warp load MJCF through ``mujoco``): without one, the
    engine counts as not installed. ``oldest``: the oldest release its adapter drives (older
    ones have other APIs); ``history``: the releases ``experiments.history`` fires by default,
    oldest first; ``release_notes``: release -> what its notes say of a change the history
    marks there, with their source; ``released_with``: distributions released in step with the
    engine, installed at the same version (MJX and MuJoCo Warp beside MuJoCo)."""

    package: str
    import_name: str
    extra: str | None = None
    requires: tuple[str, ...] = ()
    oldest: str = ""
    history: tuple[str, ...] = ()
    release_notes: Mapping[str, str] = field(default_factory=dict)
    released_with: tuple[str, ...] = ()


@dataclass(frozen=True, kw_only=True)
class Capabilities:
    """What the engine can do. ``integrators``: for the swing study (empty: it cannot drive the
    bat). ``planar``: a 2-D engine, which cannot fire an impact out of the swing plane.
    ``restitution_rule``/``friction_rule``: how it combines two bodies' restitution and
    friction (``friction_rule`` None: its adapter sets no friction, and an impact with friction
    is ``unsupported``); ``threshold_setting``: the settings field of its restitution velocity
    threshold, if any. ``soft_contact``: the overrides that switch it to a spring-damper
    contact, if it has one, whose natural frequency (rad/s) is the settings field
    ``stiffness_setting``. ``chain_adapter``: "module:Class" of its segmented-bat adapter
    (``adapters.segmented.ChainEngine``), if any. ``twin_of``: the engine whose model it
    implements (MJX of MuJoCo C); its settings class extends the twin's. ``max_worlds``: the
    most of its worlds the harness holds in one process (a hard limit of the engine, or its
    memory), None for no limit: a long run's batch of engines (``experiments.core.hosting``)
    stays within it. ``autodiff``: how its adapter's ``derivative`` differentiates an impact
    ("" for none: the harness takes finite differences); ``knob_autodiff``: how its adapter's
    ``knob_derivative`` differentiates one by the settings' contact knobs ("" for none: the
    member refuses, saying why). ``pool_adapter``: "module:Class" of
    a ``BatchedEngine`` that holds many of a single-world engine's worlds in one instance, each
    bit for bit as alone (a long run's pool is stepped on it, not on one adapter a world)."""

    integrators: tuple[Integrator, ...] = ()
    planar: bool = False
    restitution_rule: RestitutionRule = RestitutionRule.PRODUCT
    friction_rule: FrictionRule | None = None
    threshold_setting: str | None = None
    soft_contact: Mapping[str, Any] | None = None
    stiffness_setting: str | None = None
    chain_adapter: str | None = None
    twin_of: str | None = None
    max_worlds: int | None = None
    autodiff: str = ""
    knob_autodiff: str = ""
    pool_adapter: str | None = None

    def __post_init__(self) -> None:
        if (self.soft_contact is None) != (self.stiffness_setting is None):
            raise ValueError(
                "soft_contact and stiffness_setting go together; allowed: both or neither"
            )


@dataclass(frozen=True, kw_only=True)
class Batching:
    """What the engine's library offers to step many worlds at once, and whether the harness
    steps through it (issue 60: no silent gap). ``call``: the library's batched or threaded
    step as "module:attribute.path", "" where it has none; ``worlds``: whether that call steps
    many worlds in one call (``mujoco.rollout``, a batched engine's step) rather than spreading
    one world's step over threads (which a two-body world has nothing to give); ``used``:
    whether the harness steps through it (the engine's batched adapter, or its pool adapter);
    ``why``: what it is, and why it is used or not; ``not_it``: the names in the library's own
    namespace that sound like such a step and are not (a batch of ray casts, a GUI thread), as
    "module:attribute.path". Every name is read back from the installed library, and its
    namespace holds no other such name (``tests/test_library_batching.py``)."""

    call: str = ""
    worlds: bool = False
    used: bool = False
    why: str
    not_it: tuple[str, ...] = ()

    def __post_init__(self) -> None:
        if not self.call and (self.used or self.worlds):
            raise ValueError(
                "Batching: used or worlds without a call; allowed: a call ('module:name') "
                "for a step the library offers"
            )
        for target in (self.call, *self.not_it):
            if target and ":" not in target:
                raise ValueError(f"Batching: {target!r} is not 'module:attribute.path'")


@dataclass(frozen=True, kw_only=True)
class Cost:
    """For run-time estimates only. ``step_cost_s``: one reference step of one world (s,
    ``experiments.bench_engines``' one-world step, every engine measured in the same run on one
    2-core host like CI's: only their ratios carry over to another host); a batched engine's
    ``world_step_cost_s`` is what each further world adds to a step (None for a single-world
    engine: ``EngineRecord.batched`` says which), and ``start_s`` what each new batch size
    first costs in a process (s: JAX's trace and compile, Warp's module load).
    ``coast_step_cost_s``: a step with the bodies apart (the approach, a hinged swing's steps),
    where it costs much less than a contact step (None: ``step_cost_s``).
    ``impact_limit_s``: the longest one impact may take on the wall clock before it is a
    ``timeout`` (s; a batch of a batched engine's worlds, stepped together, as long, plus
    ``start_s``); None: derived from the costs above (``experiments.core.watchdog``).
    ``pool_world_make_s``: what one more world of the pool adapter (``Capabilities.pool_adapter``)
    costs to make (s), where that is a fixed figure far below what a pooled impact saves (worlds
    that are rows of arrays on one model): a long run's pool is then sized from it alone, the
    same on a loaded machine (``experiments.core.hosting``); None: timed, as the pool's first
    build's share a world."""

    step_cost_s: float = 1e-5
    world_step_cost_s: float | None = None
    start_s: float = 0.0
    coast_step_cost_s: float | None = None
    impact_limit_s: float | None = None
    pool_world_make_s: float | None = None

    @property
    def coast_s(self) -> float:
        """What a step with the bodies apart costs (s)."""
        return self.step_cost_s if self.coast_step_cost_s is None else self.coast_step_cost_s

    def __post_init__(self) -> None:
        checks.positive("step_cost_s", self.step_cost_s)
        if self.coast_step_cost_s is not None:
            checks.positive("coast_step_cost_s", self.coast_step_cost_s)
        if self.world_step_cost_s is not None:
            checks.positive("world_step_cost_s", self.world_step_cost_s)
        checks.non_negative("start_s", self.start_s)
        if self.impact_limit_s is not None:
            checks.positive("impact_limit_s", self.impact_limit_s)
        if self.pool_world_make_s is not None:
            checks.positive("pool_world_make_s", self.pool_world_make_s)


@dataclass(frozen=True, kw_only=True)
class Presentation:
    """How the engine is shown: ``label`` the name as prose spells it ('' for the name),
    ``color``/``marker`` its plot style (None: one from the registry's palette), ``notes`` what
    the report says of it (``adapters.ReportNotes``)."""

    label: str = ""
    color: str | None = None
    marker: str = "o"
    notes: ReportNotes | None = None


@dataclass(frozen=True, kw_only=True)
class Studies:
    """What the studies vary: ``speed_accuracy`` its knob families besides the two profiles
    (the Pareto study), ``friction_families`` its friction models besides the reference's,
    ``friction_rule_overrides`` the reference settings overridden so that the two bodies' own
    friction values make the contact's (for the test that pins ``friction_rule``), and
    ``twin_steps`` the comparisons with its twin that find what makes them differ."""

    speed_accuracy: tuple[KnobFamily, ...] = ()
    friction_families: tuple[KnobFamily, ...] = ()
    friction_rule_overrides: Mapping[str, Any] = field(default_factory=dict)
    twin_steps: tuple[TwinStep, ...] = ()

    def __post_init__(self) -> None:
        object.__setattr__(
            self, "friction_rule_overrides", MappingProxyType(dict(self.friction_rule_overrides))
        )


#: The pseudo-setting of a ``ContactKnob`` that is the impact's restitution e (it lives on the
#: ``ImpactCase``, not the settings).
RESTITUTION_KNOB = "e"


@dataclass(frozen=True, kw_only=True)
class ContactKnob:
    """One contact parameter a ball's fit may move: the settings field ``setting`` (or, with
    ``element``, one element of a tuple field such as MuJoCo's ``solref``; ``setting`` "e":
    the impact's restitution, RESTITUTION_KNOB), allowed from ``lo`` to ``hi`` (in ``unit``),
    searched on a log scale where ``log``."""

    setting: str
    lo: float
    hi: float
    unit: str
    element: int | None = None
    log: bool = False

    def __post_init__(self) -> None:
        if not self.lo < self.hi:
            raise ValueError(f"ContactKnob {self.label}: lo={self.lo!r}; allowed: below hi")
        if self.log:
            checks.positive("lo", self.lo)

    @property
    def label(self) -> str:
        """The knob as a column name: ``solref[0]``, ``point_stiffness_npm``."""
        return self.setting if self.element is None else f"{self.setting}[{self.element}]"


@dataclass(frozen=True, kw_only=True)
class BallContact:
    """A contact model a real ball is fitted in (``experiments.realball``), named by ``label``
    (a few words, unique within its record: a table's ``model`` column): the settings
    ``overrides`` that switch the engine to it (applied to its reference profile; ``dt_s``
    the fit's step, None: the profile's), the ``knobs`` fitted and ``start`` their first
    guess (one per knob, a sound contact), whether its COR depends on impact speed
    (``speed_dependent``, checked by a test), whether the knobs set how long the contact
    lasts (``lasts``: a soft contact, fitted to the ball's contact time too) and ``why``, in
    words. The default:
    one restitution e, the same at every speed (a rigid impulse)."""

    label: str = "restitution e"
    overrides: Mapping[str, Any] = field(default_factory=dict)
    knobs: tuple[ContactKnob, ...] = (
        ContactKnob(setting=RESTITUTION_KNOB, lo=0.05, hi=1.0, unit="1"),
    )
    start: tuple[float, ...] = (0.5,)
    speed_dependent: bool = False
    lasts: bool = False
    dt_s: float | None = None
    why: str = "one restitution e applied as a rigid impulse: the same COR at every speed"

    def __post_init__(self) -> None:
        object.__setattr__(self, "overrides", MappingProxyType(dict(self.overrides)))
        if not self.label:
            raise ValueError("BallContact: label=''; allowed: a few words naming the model")
        if len(self.start) != len(self.knobs) or not self.knobs:
            raise ValueError(
                f"BallContact: {len(self.start)} start values for {len(self.knobs)} knobs; "
                "allowed: one per knob, at least one knob"
            )
        for k, x in zip(self.knobs, self.start):
            checks.in_range(k.label, x, k.lo, k.hi)
