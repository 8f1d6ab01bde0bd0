"""The contract every engine adapter fulfils, and the engine-independent half of firing.

An adapter builds the scene (bat capsule with SET mass properties, ball sphere, nothing else)
and knows how to put a state into its engine, step it and read the state back: the public
methods under "the engine-specific half" of ``Engine``, which experiments and tests may call
too. ``Engine.simulate`` does the rest the same way for every engine: it places the bodies from
the analytic free motion so that contact happens at ``s`` with the bat aligned with x (swinging
the bat into place first if asked), steps until they separate, and classifies the outcome. A
physical failure is a status, never an exception. An engine holds no state from one impact to
the next: the same case gives the same bits on a fresh engine and on a used one.

World frame = the contact frame at the contact instant: x along the bat (knob to barrel), y from
the bat toward the ball, rotation about z. Every engine keeps the motion in the x-y plane.
"""

from __future__ import annotations

import abc
import contextlib
import dataclasses
import math
import time
from dataclasses import dataclass
from enum import Enum
from typing import ClassVar, Iterator, NamedTuple

from analytic import Ball, Bat, ImpactCase, Outcome
from analytic import _checks
from analytic.collide import PlanarState, free_flight, separates_for_good
from analytic.dynamics import Drive, HingedSwing, MotionState

from ._record import ContactReference, EngineRecord, RestitutionRule


class Status(str, Enum):
    """How a simulated impact ended. Only ``ok`` rows carry trustworthy numbers."""

    OK = "ok"
    TUNNELLED = "tunnelled"          #: the ball passed through the bat (or no contact was seen)
    NON_FINITE = "non_finite"        #: NaN or inf in the state
    ENERGY_GAINED = "energy_gained"  #: kinetic energy after > before (beyond float noise)
    PENETRATION = "penetration"      #: ball centre crossed the bat's axis (> r_ball + r_bat deep)
    NO_SEPARATION = "no_separation"  #: still touching when the step budget ran out
    #: Sound, but v1 misses the rigid-body answer by more than the row's tolerance (given by
    #: the harness's judge, experiments._verdict, never by simulate)
    INACCURATE = "inaccurate"
    #: Sound, but its contact converges to another model than the rigid impulse (a soft
    #: contact), against which the harness does not judge it yet (given by experiments._verdict)
    UNJUDGED = "unjudged"


class SceneMismatch(RuntimeError):
    """The engine holds mass properties other than the scene's (an adapter bug, not physics)."""


@dataclass(frozen=True, kw_only=True)
class Settings:
    """Knobs common to every engine; each adapter extends this with its own.

    ``dt_s``: time step (s). ``contact_phase``: where in a step the true contact instant falls,
    0 = on a step boundary (the harness's exact placement), 0.5 = mid-step (what an unaligned
    simulation meets on average). ``overlap_m``: overlap at the first step that sees the contact
    (m). ``approach_steps``: free steps before contact. ``max_contact_s``: an impact episode
    (first contact to its end, as ``analytic.collide`` ends it) longer than this is reported
    ``no_separation`` (s); 0.1 s covers every plastic impact on the barrel of our bats but those
    where the ball rides the bat near its COM for longer (the rigid episode too then).
    """

    dt_s: float
    contact_phase: float = 0.0
    overlap_m: float = 1e-9
    approach_steps: int = 2
    max_contact_s: float = 0.1

    def __post_init__(self) -> None:
        _checks.positive("dt_s", self.dt_s)
        _checks.in_range("contact_phase", self.contact_phase, 0.0, 1.0, hi_open=True)
        _checks.non_negative("overlap_m", self.overlap_m)
        _checks.integer("approach_steps", self.approach_steps, 1, 1000)
        _checks.positive("max_contact_s", self.max_contact_s)

    def as_dict(self) -> dict:
        """Flat dict of every setting, for tables and provenance."""
        return dataclasses.asdict(self)


@dataclass(frozen=True, kw_only=True)
class SimOutcome(Outcome):
    """An engine's outcome: the fields of ``analytic.Outcome`` measured from the engine, plus how
    the simulation went. Units: s, m, and as in ``Outcome``. Fields are NaN where not measurable.

    ``q`` is measured as (v1 - V)/(v0n + V), V = u0n + omega0 s, the inverse of
    v1 = q v0n + (1 + q) V; ``impulse_ns`` is the ball's momentum change m (v1 + v0n).
    """

    engine: str
    status: Status
    contact_duration_s: float
    peak_penetration_m: float
    steps: int
    wall_s: float
    settings: Settings
    #: With a swing before the impact: the engine's bat at release (rad/s, rad); NaN without.
    release_omega_radps: float = math.nan
    release_angle_rad: float = math.nan

    @property
    def ok(self) -> bool:
        """True when the outcome is physically sound (status ok)."""
        return self.status is Status.OK


@dataclass(frozen=True, kw_only=True)
class BodyLoad:
    """A ``Drive``'s loads resolved on one bat, as an adapter applies them: ``force_n`` (N) at
    ``arm_m`` (m from the COM along the axis, barrel side positive), at ``angle_rad`` to the
    axis and turning with the bat, plus ``torque_nm`` (N m) about z."""

    force_n: float
    angle_rad: float
    arm_m: float
    torque_nm: float

    @classmethod
    def of(cls, drive: Drive, bat: Bat) -> BodyLoad:
        return cls(force_n=drive.force_n, angle_rad=drive.force_angle_rad,
                   arm_m=drive.force_arm_m(bat), torque_nm=drive.torque_nm)

    @property
    def torque_about_com_nm(self) -> float:
        """torque + arm f sin(angle): the same force moved to the COM plus its moment (N m)."""
        return self.torque_nm + self.arm_m * self.force_n * math.sin(self.angle_rad)


class Reading(NamedTuple):
    """One instant of the scene, world frame (m, m/s, rad, rad/s)."""

    ball_x: float
    ball_y: float
    ball_vx: float
    ball_vy: float
    ball_w: float
    bat_x: float
    bat_y: float
    bat_angle: float
    bat_vx: float
    bat_vy: float
    bat_w: float


@dataclass(frozen=True, kw_only=True)
class MassProperties:
    """What an engine holds for the two bodies. Units: kg, m (COM from the knob), kg m^2."""

    bat_mass_kg: float
    bat_com_from_knob_m: float
    bat_inertia_kgm2: float
    ball_mass_kg: float
    ball_inertia_kgm2: float


#: Slack on the hittable range: L - r - x_cm rounds to within a few ulps of the intended value.
HITTABLE_SLACK_M = 1e-12


def check_hittable(case: ImpactCase) -> None:
    """Raise ValueError unless s lies on the capsule's cylinder, where the contact normal is
    perpendicular to the axis as the impact model assumes (the caps would tilt it)."""
    bat = case.bat
    _checks.in_range("s_m", case.s_m, bat.s_min_m - HITTABLE_SLACK_M,
                     bat.s_max_m + HITTABLE_SLACK_M)


def start_reading(case: ImpactCase, settings: Settings) -> tuple[Reading, float]:
    """The state ``T`` seconds before contact, from the analytic free motion run backwards.

    At t = 0 the bat's COM is at the origin with its axis along +x and the ball touches it at s.
    T = (approach_steps - contact_phase) dt - overlap/v_c, so that after ``approach_steps``
    steps the bodies overlap by ``overlap_m`` plus ``contact_phase`` steps of closing.
    Returns (reading, T).
    """
    bat, ball = case.bat, case.ball
    vc = case.closing_speed_mps
    T = (settings.approach_steps - settings.contact_phase) * settings.dt_s - settings.overlap_m / vc
    v_t, v_n = case.v0_mps * math.sin(case.theta_rad), -case.v0n_mps
    u_t, u_n = case.u0_mps * math.sin(case.phi_rad), case.u0n_mps
    reach = bat.radius_m + ball.radius_m
    return Reading(
        ball_x=case.s_m - T * v_t, ball_y=reach - T * v_n, ball_vx=v_t, ball_vy=v_n, ball_w=0.0,
        bat_x=-T * u_t, bat_y=-T * u_n, bat_angle=-T * case.omega0_radps,
        bat_vx=u_t, bat_vy=u_n, bat_w=case.omega0_radps,
    ), T


#: Where the ball waits while the bat swings: far from anything it could touch (m).
PARKED_BALL_Y_M = 100.0


@dataclass(frozen=True, kw_only=True)
class SwingPlan:
    """How to swing the bat into an impact: ``steps`` steps under ``swing.torque_nm`` about the
    hands pinned at ``pivot_xy_m`` (world, m), from rest at ``bat_start`` (world), then release."""

    swing: HingedSwing
    steps: int
    pivot_xy_m: tuple[float, float]
    bat_start: Reading
    omega_release_radps: float
    angle_release_rad: float
    dt_s: float


def swing_case(bat: Bat, ball: Ball, *, s_m: float, v0_mps: float, e: float,
               swing: HingedSwing, settings: Settings) -> tuple[ImpactCase, SwingPlan]:
    """The impact that a hinged swing delivers, and the plan to simulate it in one run.

    The swing lasts a whole number of steps n = round(t/dt); at release (t_r = n dt, torque off,
    hands let go) the bat turns at omega0 = tau t_r / I_p and its COM moves at u0 = omega0 d on
    the hands' circle. ``approach_steps`` later the free bat meets the ball at s: by then it has
    turned omega0 T, so the impact frame sees the COM velocity tilted by phi = omega0 T (its
    straight-line motion from release). The ball waits far away during the swing.
    """
    dt = settings.dt_s
    steps = max(1, round(swing.duration_s(bat) / dt))
    t_r = steps * dt
    w0 = swing.omega_at(bat, t_r)
    d = swing.arm_m(bat)
    phi = 0.0
    for _ in range(3):  # T depends on the closing speed, which depends on phi; converges at once
        case = ImpactCase(bat=bat, ball=ball, s_m=s_m, v0_mps=v0_mps, u0_mps=w0 * d,
                          omega0_radps=w0, e=e, phi_rad=phi, hands_from_knob_m=swing.hands_from_knob_m)
        release, T = start_reading(case, settings)
        phi = w0 * T
    case = ImpactCase(bat=bat, ball=ball, s_m=s_m, v0_mps=v0_mps, u0_mps=w0 * d, omega0_radps=w0,
                      e=e, phi_rad=phi, hands_from_knob_m=swing.hands_from_knob_m)
    release, _ = start_reading(case, settings)
    px = release.bat_x - d * math.cos(release.bat_angle)
    py = release.bat_y - d * math.sin(release.bat_angle)
    a0 = release.bat_angle - swing.angle_swept(bat, t_r)
    start = release._replace(bat_x=px + d * math.cos(a0), bat_y=py + d * math.sin(a0),
                             bat_angle=a0, bat_vx=0.0, bat_vy=0.0, bat_w=0.0, ball_x=0.0,
                             ball_y=PARKED_BALL_Y_M, ball_vx=0.0, ball_vy=0.0, ball_w=0.0)
    return case, SwingPlan(swing=swing, steps=steps, pivot_xy_m=(px, py), bat_start=start,
                           omega_release_radps=w0, angle_release_rad=release.bat_angle, dt_s=dt)


def contact_geometry(bat: Bat, ball: Ball, r: Reading) -> tuple[float, bool]:
    """(penetration, separating) of sphere and capsule in one pass over the closest point.

    Penetration is the geometric overlap (m, negative for a gap), measured from the side the
    ball came from: a ball whose centre has crossed the bat's axis is more than r_ball + r_bat
    deep, however close to the axis it sits. Separating: the ball centre moves away from the
    closest point of the bat's axis (the bat point's velocity includes the bat's spin).
    """
    c, s = math.cos(r.bat_angle), math.sin(r.bat_angle)
    dx, dy = r.ball_x - r.bat_x, r.ball_y - r.bat_y
    t = min(max(dx * c + dy * s, bat.s_min_m), bat.s_max_m)
    nx, ny = dx - t * c, dy - t * s
    dist = math.hypot(nx, ny)
    side = dy * c - dx * s
    pen = bat.radius_m + ball.radius_m - (dist if side > 0.0 else -dist)
    if dist == 0.0:
        return pen, False
    rvx = r.ball_vx - (r.bat_vx - r.bat_w * t * s)
    rvy = r.ball_vy - (r.bat_vy + r.bat_w * t * c)
    return pen, rvx * nx + rvy * ny > 0.0


#: While touching, the ball may stay past the cylinder's end for this many steps before the
#: episode ends 'left_cylinder' (an impulse at the grid's very end is seen there for its 1-3
#: steps; a ball sliding off the end in sustained contact is stopped after them).
OFF_SPAN_STEPS = 3


def _planar(r: Reading) -> PlanarState:
    return PlanarState(ball_x_m=r.ball_x, ball_y_m=r.ball_y, ball_vx_mps=r.ball_vx,
                       ball_vy_mps=r.ball_vy, bat_x_m=r.bat_x, bat_y_m=r.bat_y,
                       bat_vx_mps=r.bat_vx, bat_vy_mps=r.bat_vy, bat_angle_rad=r.bat_angle,
                       bat_omega_radps=r.bat_w)


def _flight_end(bat: Bat, ball: Ball, r: Reading, apart: bool, t_left_s: float,
                dt_s: float, search: bool) -> tuple[str | None, int]:
    """After contact, with the bodies not touching: how the episode ends now ('left_cylinder'
    or 'separated', as ``analytic.collide`` would end it from this state), or None and the
    steps until a free-flight search is worth repeating (it predicted a contact that far
    ahead). The search runs only when ``search``; the cheap checks every step."""
    if _off_span_m(bat, ball, r) > 0.0:  # collide's cylinder ends here too
        return "left_cylinder", 0
    if not apart:
        return None, 0
    reach = bat.radius_m + ball.radius_m
    state = _planar(r)
    if separates_for_good(state, reach_m=reach, ball_radius_m=ball.radius_m, t_max_s=t_left_s):
        return "separated", 0
    if not search:
        return None, 0
    t, why = free_flight(state, reach_m=reach, ball_radius_m=ball.radius_m,
                         s_min_m=bat.s_min_m, s_max_m=bat.s_max_m, t_max_s=t_left_s)
    if why != "contact":
        return ("left_cylinder" if why == "left_cylinder" else "separated"), 0
    return None, max(1, int(t / dt_s) - 1)


def _axial_m(r: Reading) -> float:
    return (r.ball_x - r.bat_x) * math.cos(r.bat_angle) + (r.ball_y - r.bat_y) * math.sin(r.bat_angle)


def _off_span_m(bat: Bat, ball: Ball, r: Reading) -> float:
    """How far the ball centre is beyond the cylinder's span along the axis (m, <= 0 on it)."""
    s = _axial_m(r)
    return max(bat.s_min_m - s, s - bat.s_max_m)


def penetration_m(bat: Bat, ball: Ball, r: Reading) -> float:
    """The overlap of ``contact_geometry`` (m)."""
    return contact_geometry(bat, ball, r)[0]


def ball_side_m(r: Reading) -> float:
    """The ball centre's distance from the bat's axis line, positive on the side it came from."""
    return (r.ball_y - r.bat_y) * math.cos(r.bat_angle) - (r.ball_x - r.bat_x) * math.sin(r.bat_angle)


def kinetic_energy_j(case: ImpactCase, r: Reading) -> float:
    """Kinetic energy of both bodies with the scene's mass properties (J)."""
    bat, ball = case.bat, case.ball
    return 0.5 * (ball.mass_kg * (r.ball_vx**2 + r.ball_vy**2) + ball.inertia_kgm2 * r.ball_w**2
                  + bat.mass_kg * (r.bat_vx**2 + r.bat_vy**2) + bat.inertia_cm_kgm2 * r.bat_w**2)


#: Relative tolerance of the read-back check: engines store mass properties in float64 and some
#: derive them through a rotation or an eigen-decomposition, which costs a few ulps.
MASS_CHECK_REL = 1e-9
#: Single-precision engines store them in float32 (0.871 kg reads back 9e-9 off): this many of
#: their ulps, where that is more.
MASS_CHECK_ULPS = 8
#: Kinetic energy may grow by this fraction before ``energy_gained``: float64 rounding over
#: thousands of steps stays far below it, the defects we look for (+1% and more) far above.
ENERGY_GAIN_REL = 1e-6
#: In a float32 engine rounding alone moves the energy by a few 1e-6 (PhysX at e = 1: up to
#: 2.5e-6): this many of its ulps, where that is more (1.2e-5 for float32).
ENERGY_GAIN_ULPS = 100


class Episode(NamedTuple):
    """What stepping one impact gave: the last reading, the first and last step that saw the
    contact (-1: none), the deepest penetration (m), steps taken, and how it ended: 'separated',
    'left_cylinder', 'non_finite', 'missed' (no contact when one was due) or 'budget'
    (max_contact_s ran out)."""

    end: Reading
    first: int
    last: int
    peak_m: float
    steps: int
    ended: str


class Engine(abc.ABC):
    """One physics engine behind the common contract: build once, fire many impacts.

    The methods of the engine-specific half are the public contract: an adapter implements them
    and experiments and tests may call them (``use_scene`` first, which builds the scene and
    checks its mass properties). ``name`` is the registry's name for the engine, which a plug-in
    may choose; ``record`` holds the engine's facts.
    """

    record: ClassVar[EngineRecord]

    def __init__(self, settings: Settings, *, name: str | None = None) -> None:
        self.settings = settings
        self.name = name or self.record.name
        self.scene: tuple[Bat, Ball] | None = None  #: the bat and ball the engine holds now
        self._e: float | None = None  # the e set_restitution last set (None: unknown)

    @classmethod
    def version(cls) -> str:
        """The engine library's version string."""
        return cls.record.version()

    @classmethod
    def converges_to(cls, settings: Settings) -> ContactReference:
        """The continuous model this engine's contact converges to with these settings as the
        step shrinks (the record's, unless a setting switches the contact model)."""
        return cls.record.converges_to

    @classmethod
    def speculative_margin_m(cls, settings: Settings) -> float:
        """The gap (m) below which the engine already solves a contact (speculative contact):
        such a contact is solved from the geometry at the start of the step that closes it, up
        to a whole step early; 0 for engines that see a contact once the bodies overlap."""
        return 0.0

    @classmethod
    def contact_law(cls, settings: Settings, e: float):
        """The continuous contact law (``analytic.compliant``) this engine's contact converges
        to at these settings and restitution, or None for a rigid contact (the default)."""
        return None

    @classmethod
    def law_restitution_error(cls, settings: Settings, dt_over_contact: float) -> float:
        """The relative error of the restitution a step of ``dt_over_contact`` contact times
        leaves in a compliant contact (the leading term; the judge allows a multiple of it).
        Semi-implicit Euler through a spring-damper: (pi/3) dt/t_c (measured -5.0e-3 for MuJoCo
        at w = 3000 rad/s, dt = 1e-5 s, against 5.2e-3 from the formula)."""
        return math.pi / 3.0 * dt_over_contact

    @classmethod
    def read_back_defaults(cls) -> dict:
        """The engine's own values of settings fields, as a fresh engine reports them (only
        those it reports; the record's ``engine_defaults`` holds the rest as measured)."""
        return {}

    # -- the engine-specific half -------------------------------------------------------------

    @abc.abstractmethod
    def build_scene(self, bat: Bat, ball: Ball) -> None:
        """Create (or re-create) the world with this bat and ball (use ``use_scene``, which
        calls it only when either changes and checks the mass properties)."""

    @abc.abstractmethod
    def mass_properties(self) -> MassProperties:
        """Read back the mass properties the engine holds for both bodies."""

    @abc.abstractmethod
    def set_restitution(self, e: float) -> None:
        """Make the next contact bounce with coefficient of restitution ``e``, without rebuilding."""

    def set_body_restitution(self, *, bat: float, ball: float) -> None:
        """Set the engine's own restitution value of each body (for engines whose
        ``record.restitution_rule`` combines two; the others raise NotImplementedError). An
        adapter that implements it calls ``super().set_body_restitution`` first."""
        if self.record.restitution_rule is RestitutionRule.MAPPED:
            raise NotImplementedError(f"{self.name} has no per-body restitution")
        self._e = None

    @abc.abstractmethod
    def set_state(self, r: Reading) -> None:
        """Put both bodies at the given positions and velocities (world frame) and forget any
        contact the engine remembers (warm starts, cached impulses)."""

    @abc.abstractmethod
    def step(self) -> None:
        """Advance the engine by one time step ``settings.dt_s``."""

    @abc.abstractmethod
    def read(self) -> Reading:
        """Current positions and velocities of both bodies (world frame, COM velocities)."""

    @abc.abstractmethod
    def in_contact(self) -> bool:
        """True if the engine holds an active contact between bat and ball after the last step."""

    @abc.abstractmethod
    def set_load(self, load: BodyLoad | None) -> None:
        """Apply ``load`` (fixed in the bat's frame) on every following step until called with
        None. Use ``driven``, which pairs it with the hinge."""

    @abc.abstractmethod
    def pin(self, pivot_from_com_m: float, pivot_xy_m: tuple[float, float]) -> None:
        """Hinge the bat's axis point ``pivot_from_com_m`` (m from the COM) to the world point
        ``pivot_xy_m`` with the engine's own joint or constraint, releasable by ``unpin``."""

    @abc.abstractmethod
    def unpin(self) -> None:
        """Let go of the hinge set by ``pin`` (the hands release the bat)."""

    def numerical_failures(self) -> int:
        """How many numerical blow-ups (NaN, inf or huge values the engine caught, and perhaps
        reset its state after) the engine has reported so far; engines that report none
        return 0. ``simulate`` calls an impact ``non_finite`` when this grows during it."""
        return 0

    def close(self) -> None:
        """Release engine resources (a no-op unless the engine holds a connection)."""

    # -- the shared half ----------------------------------------------------------------------

    def check_mass_properties(self, bat: Bat, ball: Ball) -> None:
        """Raise SceneMismatch unless the engine holds exactly the scene's mass properties."""
        got = self.mass_properties()
        want = MassProperties(bat_mass_kg=bat.mass_kg, bat_com_from_knob_m=bat.com_from_knob_m,
                              bat_inertia_kgm2=bat.inertia_cm_kgm2, ball_mass_kg=ball.mass_kg,
                              ball_inertia_kgm2=ball.inertia_kgm2)
        rel = max(MASS_CHECK_REL, MASS_CHECK_ULPS * self.record.eps)
        for field in dataclasses.fields(MassProperties):
            a, b = getattr(got, field.name), getattr(want, field.name)
            if not math.isclose(a, b, rel_tol=rel, abs_tol=1e-15):
                raise SceneMismatch(f"{self.name}: {field.name} read back as {a!r}, the scene "
                                    f"has {b!r} (allowed relative difference {rel:g})")

    def use_scene(self, bat: Bat, ball: Ball) -> None:
        """Hold this bat and ball: build them if they differ from the scene held, and check that
        the engine holds their mass properties (SceneMismatch otherwise)."""
        if self.scene is not None and self.scene[0] is bat and self.scene[1] is ball:
            return
        if (bat, ball) != self.scene:
            self.scene = self._e = None
            self.build_scene(bat, ball)
            self.check_mass_properties(bat, ball)
        self.scene = (bat, ball)

    @contextlib.contextmanager
    def driven(self, drive: Drive, pivot_xy_m: tuple[float, float] = (0.0, 0.0)) -> Iterator[None]:
        """Within the block, the held bat is pinned at ``drive``'s pivot (if it has one) to the
        world point ``pivot_xy_m`` and carries ``drive``'s loads; both go when the block ends."""
        bat = self._held_bat()
        drive.check(bat)
        hinged = drive.pivot_from_knob_m is not None
        if hinged:
            self.pin(drive.pivot_from_knob_m - bat.com_from_knob_m, pivot_xy_m)
        try:
            self.set_load(BodyLoad.of(drive, bat))
            yield
        finally:
            self.set_load(None)
            if hinged:
                self.unpin()

    def run_motion(self, bat: Bat, drive: Drive, t_s: float, angle_rad: float = 0.0,
                   ball: Ball | None = None) -> MotionState:
        """Drive the bat alone (the ball parked far away) from rest for round(t/dt) steps."""
        from analytic import presets
        from analytic.dynamics import start_state

        self.use_scene(bat, ball or presets.BASEBALL)
        s0 = start_state(bat, drive, angle_rad)
        self.set_state(Reading(0.0, PARKED_BALL_Y_M, 0.0, 0.0, 0.0, s0.x_m, s0.y_m, angle_rad,
                               0.0, 0.0, 0.0))
        steps = round(t_s / self.settings.dt_s)
        with self.driven(drive):
            for _ in range(steps):
                self.step()
        r = self.read()
        return MotionState(t_s=steps * self.settings.dt_s, x_m=r.bat_x, y_m=r.bat_y,
                           angle_rad=r.bat_angle, vx_mps=r.bat_vx, vy_mps=r.bat_vy,
                           omega_radps=r.bat_w)

    def simulate(self, case: ImpactCase, swing: SwingPlan | None = None) -> SimOutcome:
        """Fire one impact and measure it. Never raises for a physical failure.

        With a ``swing`` (from ``swing_case``) the bat is first swung about the hands in the
        engine and released; the impact then meets the bat the engine delivers.
        """
        t_wall = time.perf_counter()
        check_hittable(case)
        self.use_scene(case.bat, case.ball)
        if case.e != self._e:  # a parameter, not state: the next impact starts the same
            self.set_restitution(case.e)
            self._e = case.e
        failures = self.numerical_failures()
        start, release = self._place(case, swing)
        episode = self._step_until_separation(case, start)
        if self.numerical_failures() != failures:
            episode = episode._replace(ended="non_finite")
        ke0, ke1 = kinetic_energy_j(case, start), kinetic_energy_j(case, episode.end)
        status = self._classify(case, episode, ke0, ke1)
        return self._outcome(case, start, episode, status, (ke0, ke1), release,
                             time.perf_counter() - t_wall)

    def _held_bat(self) -> Bat:
        if self.scene is None:
            raise RuntimeError(f"{self.name}: no scene held; call use_scene(bat, ball) first")
        return self.scene[0]

    def _place(self, case: ImpactCase, swing: SwingPlan | None) -> tuple[Reading, tuple]:
        """The start state (``start_reading``), with the bat the engine's swing delivers when a
        swing is asked for; returns it and (release omega, release angle, swing steps)."""
        start, _ = start_reading(case, self.settings)
        if swing is None:
            return start, (math.nan, math.nan, 0)
        if swing.dt_s != self.settings.dt_s:
            raise ValueError(f"swing plan made for dt_s={swing.dt_s!r}, engine steps "
                             f"dt_s={self.settings.dt_s!r}; allowed: a plan from swing_case "
                             "with this engine's settings")
        self.set_state(swing.bat_start)
        with self.driven(swing.swing.drive(), swing.pivot_xy_m):
            for _ in range(swing.steps):
                self.step()
        bat = self.read()
        start = start._replace(bat_x=bat.bat_x, bat_y=bat.bat_y, bat_angle=bat.bat_angle,
                               bat_vx=bat.bat_vx, bat_vy=bat.bat_vy, bat_w=bat.bat_w)
        return start, (bat.bat_w, bat.bat_angle, swing.steps)

    def _step_until_separation(self, case: ImpactCase, start: Reading) -> Episode:
        """Step from ``start`` until the episode is over, as ``analytic.collide`` ends it: the
        bodies apart with no contact to come in free flight (``free_flight``), or the ball off
        the cylinder's span, or ``max_contact_s`` of episode spent (budget)."""
        st = self.settings
        bat, ball = case.bat, case.ball
        self.set_state(start)
        max_steps = st.approach_steps + math.ceil(st.max_contact_s / st.dt_s) + 2
        first = last = -1
        check_at = off_steps = 0
        # a rigid contact slides off the cylinder's end only in sustained contact, as in
        # collide; a soft one may be milliseconds long and slide past it within one impact
        rigid = self.converges_to(st) is ContactReference.RIGID_IMPULSE
        peak = -math.inf
        r = start
        for step in range(1, max_steps + 1):
            self.step()
            touching = self.in_contact()
            # Free flight before the planned contact step cannot go wrong but by a blow-up,
            # which the final reading still catches: the state is read from that step on.
            if not touching and first < 0 and step < st.approach_steps:
                continue
            r = self.read()
            if not math.isfinite(sum(r)):
                return Episode(r, first, last, math.nan, step, "non_finite")
            pen, apart = contact_geometry(bat, ball, r)
            if pen > peak:
                peak = pen
            if touching:
                if first < 0:
                    first = step
                last = step
                off_steps = off_steps + 1 if rigid and _off_span_m(bat, ball, r) > 0.0 else 0
                if off_steps > OFF_SPAN_STEPS:
                    return Episode(r, first, last, peak, step, "left_cylinder")
            elif first >= 0:
                ended, wait = _flight_end(bat, ball, r, apart, (max_steps - step) * st.dt_s,
                                          st.dt_s, search=step >= check_at)
                if ended:
                    return Episode(r, first, last, peak, step, ended)
                check_at = max(check_at, step + wait)
            elif step > st.approach_steps + 1:
                return Episode(r, first, last, peak, step, "missed")
        r = self.read()
        ended = "non_finite" if not math.isfinite(sum(r)) else "budget"
        return Episode(r, first, last, max(peak, penetration_m(bat, ball, r)), max_steps, ended)

    def _classify(self, case: ImpactCase, ep: Episode, ke0: float, ke1: float) -> Status:
        """The status of an episode: every verdict on an impact is made here."""
        if ep.ended == "non_finite":
            return Status.NON_FINITE
        if ep.ended == "missed" or (ep.ended == "budget" and ep.first < 0):
            return Status.TUNNELLED
        if ep.ended == "budget":
            return Status.NO_SEPARATION
        if ball_side_m(ep.end) <= 0.0:
            return Status.TUNNELLED
        if ep.peak_m > case.bat.radius_m + case.ball.radius_m:
            return Status.PENETRATION
        if ke1 > ke0 * (1.0 + max(ENERGY_GAIN_REL, ENERGY_GAIN_ULPS * self.record.eps)):
            return Status.ENERGY_GAINED
        return Status.OK

    def _outcome(self, case: ImpactCase, start: Reading, ep: Episode, status: Status,
                 ke: tuple[float, float], release: tuple, wall_s: float) -> SimOutcome:
        bat, ball, r = case.bat, case.ball, ep.end
        du, dw = r.bat_vy - start.bat_vy, r.bat_w - start.bat_w
        V = case.u0n_mps + case.omega0_radps * case.s_m
        v1 = r.ball_vy
        return SimOutcome(
            v1_mps=v1,
            u1_mps=r.bat_vy,
            omega1_radps=r.bat_w,
            impulse_ns=ball.mass_kg * (v1 + case.v0n_mps),
            q=(v1 - V) / (case.v0n_mps + V),
            closing_speed_mps=case.closing_speed_mps,
            hand_dv_mps=du + dw * (case.hands_from_knob_m - bat.com_from_knob_m),
            ke_before_j=ke[0],
            ke_after_j=ke[1],
            v1_t_mps=r.ball_vx,
            u1_t_mps=r.bat_vx,
            engine=self.name,
            status=status,
            contact_duration_s=(ep.last - ep.first + 1) * self.settings.dt_s if ep.first >= 0
            else 0.0,
            peak_penetration_m=ep.peak_m,
            steps=ep.steps + release[2],
            wall_s=wall_s,
            settings=self.settings,
            release_omega_radps=release[0],
            release_angle_rad=release[1],
        )
