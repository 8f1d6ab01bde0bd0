"""The engine interface: everything an engine adapter implements, on one page.

An engine is two things, kept apart so that the harness can read about an engine without
importing it (``--engine`` validation, charts, tolerances):

- a **record** (``adapters.EngineRecord``, in a module that imports no engine): its
  name, ``adapter = "module:Class"`` (where the adapter lives), ``install`` (its package),
  ``profiles`` (instances of its ``Settings`` subclass) and ``can`` (what it can do); the
  other parts have defaults (``adapters.parts``: error model, cost, presentation, studies);
- an **adapter class**, one of the two forms below, which imports the engine.

The harness does the rest the same way for every engine (``experiments.core``): it places the
bodies from the analytic free motion so that contact happens at the intended point, steps until
the impact episode is over, classifies it and judges it. An adapter only builds, sets, steps
and reads. It holds no state from one impact to the next that could change the next one's bits:
``set_state`` forgets every contact the engine remembers (warm starts, cached impulses).

**Single-world form** (``Engine``): one world at a time; the harness loops over impacts. Seven
members: ``record``, ``build``, ``mass_properties``, ``set_state``, ``step``, ``read`` and
``in_contact`` (plus ``__init__(settings)``, inherited). Six optional: ``set_drive`` (the
hands: without it the engine sits out the swing studies), ``failed``, ``set_body_restitution``,
``set_body_friction``, ``close`` and ``read_back_defaults``.

**Batched form** (``BatchedEngine``): the same members over ``n`` independent worlds at once,
arrays of floats in and out, one row per world in ``STATE_FIELDS`` order (a planar engine may
leave the out-of-plane columns out), but ``set_body_restitution``; six optional more:
``retire``, the worlds whose episode is over (it may stop stepping them), ``derivative``,
the engine's own automatic differentiation through an impact (by its start state and the
bat's inertia), ``knob_derivative``, the same by its settings' contact knobs (a fit of the
contact to a measured law), ``device``, where its worlds live, ``anchor_s``, its library's
own batched call timed bare, and ``device_episode``, the episode observed
where the worlds live (``adapters.device``).

What the harness holds an adapter to, whatever it does (``experiments.core.fire.guarded``): a
read of the wrong shape or kind, a contact flag its own state denies, an exception, an exit or
a hang past the record's ``cost.impact_limit_s`` each fails its own impacts' rows (``error``,
``timeout``), never the run.

Frame and units: the world frame is the contact frame at the contact instant: x along the bat
(knob to barrel), y from the bat toward the ball, z = x cross y. A frictionless impact in the
swing plane keeps both bodies in the x-y plane; an undercut ball (its centre off the plane) or
one spinning about x or y leaves it, and a planar engine (its record's ``planar``) is not
asked to fire those. SI units; the bat's position is its centre of mass (COM), its velocity the
COM's; angular velocities are in the world frame. The bat's axis points along
(cos a cos b, sin a cos b, sin b), a = ``bat_angle_rad``, b = ``bat_tilt_rad``: its orientation
is the rotation by a about z after the rotation by -b about y (``adapters.frames``); its roll
about its own axis is not part of the state (the bat is axisymmetric: set_state puts it at 0).
Check an adapter with ``experiments.core.check_engine`` before you use it.
"""

from __future__ import annotations

import abc
import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, ClassVar, NamedTuple

if TYPE_CHECKING:
    import numpy as np

    from analytic import Ball, Bat

    from .device import ArrayDevice, DeviceEpisode, EpisodeConstants
    from .records import EngineRecord, Settings


class State(NamedTuple):
    """Both bodies at one instant, world frame (m, m/s, rad, rad/s). Build it with keywords.

    The first 11 fields are the swing plane's (``PLANAR_FIELDS``; ``*_omega_radps`` the spins
    about z); the rest, out of the plane, default to 0 (``SPATIAL_FIELDS``)."""

    ball_x_m: float
    ball_y_m: float
    ball_vx_mps: float
    ball_vy_mps: float
    ball_omega_radps: float
    bat_x_m: float
    bat_y_m: float
    bat_angle_rad: float
    bat_vx_mps: float
    bat_vy_mps: float
    bat_omega_radps: float
    ball_z_m: float = 0.0
    ball_vz_mps: float = 0.0
    ball_wx_radps: float = 0.0
    ball_wy_radps: float = 0.0
    bat_z_m: float = 0.0
    bat_tilt_rad: float = 0.0
    bat_vz_mps: float = 0.0
    bat_wx_radps: float = 0.0
    bat_wy_radps: float = 0.0


#: Column order of a batch of states (an array of shape (n, 20)).
STATE_FIELDS = State._fields
#: The swing plane's columns, first: a planar batched engine may read and return only these.
PLANAR_FIELDS = STATE_FIELDS[:11]
#: The columns out of the swing plane (0 for an impact that stays in it).
SPATIAL_FIELDS = STATE_FIELDS[11:]


@dataclass(frozen=True, kw_only=True)
class Scene:
    """What an engine builds: the bat (a capsule with SET mass, COM and inertia about the COM,
    diag(I_axial, J, J) in its own frame, axis from ``bat.s_min_m`` to ``bat.s_max_m`` along x
    from the COM), the ball (a sphere), the coefficient of restitution ``e`` their contact must
    have (mapped onto whatever the engine offers) and its Coulomb coefficient of friction
    ``mu`` (0: frictionless; set through the engine's own combine rule, the record's
    ``friction_rule``). No gravity, nothing else."""

    bat: Bat
    ball: Ball
    e: float
    mu: float = 0.0


@dataclass(frozen=True, kw_only=True)
class MassProperties:
    """What an engine holds for the two bodies. Units: kg, m (COM from the knob), kg m^2 (the
    moment of inertia about z through each body's COM)."""

    bat_mass_kg: float
    bat_com_from_knob_m: float
    bat_inertia_kgm2: float
    ball_mass_kg: float
    ball_inertia_kgm2: float


@dataclass(frozen=True, kw_only=True)
class Hands:
    """The bat driven during a swing: a force ``force_n`` (N) at ``angle_rad`` to the bat's axis,
    turning with the bat, applied ``arm_m`` (m) from the COM along the axis (barrel side
    positive), plus a torque ``torque_nm`` (N m) about z; and, unless ``pivot_from_com_m`` is
    None, the axis point that far from the COM (m) hinged to the world point ``pivot_xy_m`` (m)
    by the engine's own releasable joint."""

    force_n: float = 0.0
    angle_rad: float = 0.0
    arm_m: float = 0.0
    torque_nm: float = 0.0
    pivot_from_com_m: float | None = None
    pivot_xy_m: tuple[float, float] = (0.0, 0.0)

    @property
    def torque_about_com_nm(self) -> float:
        """torque + arm f sin(angle): the force moved to the COM plus its moment (N m)."""
        return self.torque_nm + self.arm_m * self.force_n * math.sin(self.angle_rad)


class Engine(abc.ABC):
    """An engine that steps one world at a time (the single-world form)."""

    #: Everything the harness knows about the engine (``adapters.EngineRecord``).
    record: ClassVar[EngineRecord]

    def __init__(self, settings: Settings) -> None:
        self.settings = settings

    @abc.abstractmethod
    def build(self, scene: Scene) -> None:
        """Create (or re-create) the world holding ``scene``: the bat and the ball with exactly
        their mass properties, their contact bouncing with ``scene.e``."""

    @abc.abstractmethod
    def mass_properties(self) -> MassProperties:
        """Read back what the engine holds for both bodies (the harness compares it with the
        scene before any impact)."""

    @abc.abstractmethod
    def set_state(self, state: State) -> None:
        """Put both bodies at these positions and velocities and forget any contact the engine
        remembers from before."""

    @abc.abstractmethod
    def step(self) -> None:
        """Advance the world by one time step, ``settings.dt_s``."""

    @abc.abstractmethod
    def read(self) -> State:
        """Both bodies now (COM positions and velocities)."""

    @abc.abstractmethod
    def in_contact(self) -> bool:
        """True if the engine holds an active bat-ball contact after the last step (one that
        acts: not a speculative contact between bodies still apart that exerted nothing)."""

    def set_drive(self, hands: Hands | None) -> None:
        """Drive the bat with ``hands`` on every following step; None: let go (remove the loads
        and release the hinge). Optional: an engine without it does not run swings."""
        raise NotImplementedError(f"{type(self).__name__} cannot drive the bat")

    def failed(self) -> bool:
        """True if the engine met a numerical failure since the last ``set_state`` (NaN, inf,
        a solver that gave up, a blow-up it caught and perhaps reset its state after).
        Optional: the harness also catches non-finite states and states that jump."""
        return False

    def set_body_restitution(self, *, bat: float, ball: float) -> None:
        """Set each body's own restitution value, for an engine that combines two (the record's
        ``restitution_rule``); a test pins the rule with it. Optional."""
        raise NotImplementedError(f"{type(self).__name__} has no per-body restitution")

    def set_body_friction(self, *, bat: float, ball: float) -> None:
        """Set each body's own friction coefficient, for an engine that combines two (the
        record's ``friction_rule``); a test pins the rule with it. Optional."""
        raise NotImplementedError(f"{type(self).__name__} has no per-body friction")

    def close(self) -> None:
        """Release engine resources (connections, worlds). Optional."""

    @classmethod
    def read_back_defaults(cls) -> dict:
        """The engine's own values of settings fields, as a fresh engine reports them (the
        record's ``engine_defaults`` quotes them; a test compares). Optional."""
        return {}


class BatchedEngine(abc.ABC):
    """An engine that steps ``n`` independent worlds in one call (the batched form). Arrays in,
    arrays out: states are float arrays of shape (n, 20) in ``STATE_FIELDS`` order (a planar
    engine may return the 11 ``PLANAR_FIELDS`` columns alone: the rest are then 0)."""

    record: ClassVar[EngineRecord]

    def __init__(self, settings: Settings) -> None:
        self.settings = settings

    @abc.abstractmethod
    def build(self, scene: Scene, worlds: int) -> None:
        """Create ``worlds`` copies of the world holding ``scene``."""

    @abc.abstractmethod
    def mass_properties(self) -> MassProperties:
        """Read back the mass properties every world holds."""

    @abc.abstractmethod
    def set_state(self, states: np.ndarray) -> None:
        """Put every world in its state (row) and forget every contact remembered."""

    @abc.abstractmethod
    def step(self) -> None:
        """Advance every world by ``settings.dt_s``."""

    @abc.abstractmethod
    def read(self) -> np.ndarray:
        """Every world's state: shape (n, 20) in ``STATE_FIELDS`` order, or (n, 11), the
        ``PLANAR_FIELDS``, for a planar engine (as the class says); a new array each call (the
        harness keeps it). In Fortran order (each field's column contiguous) the harness reads
        it without a copy."""

    @abc.abstractmethod
    def in_contact(self) -> np.ndarray:
        """Per world, whether an active bat-ball contact acted in the last step: bool (n,)."""

    def set_drive(self, hands: Sequence[Hands] | None) -> None:
        """Drive each world's bat with its ``Hands`` (one per world); None: let go."""
        raise NotImplementedError(f"{type(self).__name__} cannot drive the bat")

    def failed(self) -> np.ndarray | None:
        """Per world, a numerical failure since the last ``set_state`` (bool (n,)), or None."""
        return None

    def retire(self, worlds: np.ndarray) -> None:
        """The worlds (bool (n,)) whose episode is over at the step read last: until the next
        ``set_state`` the harness asks nothing of them but ``failed``, which must say what it
        said then; the adapter may stop stepping them (a long contact elsewhere in the batch
        then costs them nothing). Optional: by default they go on being stepped."""

    def derivative(
        self,
        states: np.ndarray,
        tangents: np.ndarray,
        steps: int,
        inertia_tangent_kgm2: float = 0.0,
    ) -> tuple[np.ndarray, np.ndarray]:
        """The engine's own automatic differentiation through ``steps`` steps from ``states``:
        the end states (n, 11: the ``PLANAR_FIELDS``) and their derivatives along
        ``tangents`` (n, 20: a direction in each start state) with the bat's moment of
        inertia about its COM moving at ``inertia_tangent_kgm2`` along it. Optional: an
        engine without it is judged by finite differences alone (the error says why)."""
        raise NotImplementedError(f"{type(self).__name__} has no automatic differentiation")

    def knob_derivative(
        self, states: np.ndarray, steps: int, knobs: Sequence[tuple[str, int | None]]
    ) -> tuple[np.ndarray, np.ndarray]:
        """The engine's own automatic differentiation through ``steps`` steps from ``states``
        (n, 20), the worlds built with these settings, by each of ``knobs``: a settings field
        and its element's index (None: a scalar field), the derivative by the SETTINGS value
        (chained through however the adapter maps it onto the engine). The end states (n, 11:
        the ``PLANAR_FIELDS``) and their derivatives (n, 11, k), one column per knob, all in
        one call. A knob the engine cannot differentiate, or one its contact ignores, is a
        ValueError naming the ones it can, before any work. Optional."""
        raise NotImplementedError(f"{type(self).__name__} has no derivative by its settings")

    def set_body_friction(self, *, bat: float, ball: float) -> None:
        """As ``Engine.set_body_friction``, in every world. Optional."""
        raise NotImplementedError(f"{type(self).__name__} has no per-body friction")

    def close(self) -> None:
        """Release engine resources."""

    def device(self) -> str:
        """Where the worlds are computed, in words (benchmarks record it). Optional."""
        return "cpu"

    def device_episode(self, constants: EpisodeConstants) -> ArrayDevice | DeviceEpisode | None:
        """The worlds' episode observed on their device (``adapters.device``): their state as an
        array library holds it (``ArrayDevice``), or the adapter's own kernels observing it
        (``DeviceEpisode``) with ``constants``. Optional: None, the harness reads every step's
        state into numpy (its reference path, and the faster one on a CPU)."""
        return None

    def anchor_s(self, states: np.ndarray, steps: int) -> float | None:
        """Seconds the engine's library takes, in its own batched call and nothing else, to
        step these worlds ``steps`` steps from ``states`` (n, 20) with the threads this
        adapter uses: the anchor its bare cost is measured against (``bench_engines``).
        Optional: None where the library has no such call."""
        return None

    @classmethod
    def read_back_defaults(cls) -> dict:
        """As ``Engine.read_back_defaults``."""
        return {}
