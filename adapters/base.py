"""The contract every engine adapter fulfils, and the engine-independent half of firing.

An adapter builds the scene (bat capsule with SET mass properties, ball sphere, nothing else),
and knows how to put a state into its engine, step it, and read the state back. ``Engine.simulate``
does the rest the same way for every engine: it places the bodies from the analytic free motion
so that contact happens at ``s`` with the bat aligned with x, steps until they separate, measures
penetration and contact time, and classifies the outcome. A physical failure is a status.

World frame = the contact frame at the contact instant: x along the bat (knob to barrel), y from
the bat toward the ball, rotation about z. Every engine keeps the motion in the x-y plane.
"""

from __future__ import annotations

import abc
import dataclasses
import math
import time
from dataclasses import dataclass
from enum import Enum
from typing import ClassVar, NamedTuple

from analytic import Ball, Bat, ImpactCase, Outcome
from analytic import _checks
from analytic.dynamics import Drive, HingedSwing, MotionState


class Status(str, Enum):
    """How a simulated impact ended. Only ``ok`` rows carry trustworthy numbers."""

    OK = "ok"
    TUNNELLED = "tunnelled"          #: the ball passed through the bat (or no contact was seen)
    NON_FINITE = "non_finite"        #: NaN or inf in the state
    ENERGY_GAINED = "energy_gained"  #: kinetic energy after > before (beyond float noise)
    PENETRATION = "penetration"      #: ball centre crossed the bat's axis (> r_ball + r_bat deep)
    NO_SEPARATION = "no_separation"  #: still touching when the step budget ran out


class SceneMismatch(RuntimeError):
    """The engine holds mass properties other than the scene's (an adapter bug, not physics)."""


@dataclass(frozen=True, kw_only=True)
class Settings:
    """Knobs common to every engine; each adapter extends this with its own.

    ``dt_s``: time step (s). ``contact_phase``: where in a step the true contact instant falls,
    0 = on a step boundary (the harness's exact placement), 0.5 = mid-step (what an unaligned
    simulation meets on average). ``overlap_m``: overlap at the first step that sees the contact
    (m). ``approach_steps``: free steps before contact. ``max_contact_s``: contact longer than
    this is a ``no_separation`` failure (s).
    """

    dt_s: float
    contact_phase: float = 0.0
    overlap_m: float = 1e-9
    approach_steps: int = 2
    max_contact_s: float = 0.02

    def __post_init__(self) -> None:
        _checks.positive("dt_s", self.dt_s)
        _checks.in_range("contact_phase", self.contact_phase, 0.0, 1.0, hi_open=True)
        _checks.non_negative("overlap_m", self.overlap_m)
        _checks.in_range("approach_steps", self.approach_steps, 1, 1000)
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


def _closest(bat: Bat, r: Reading) -> tuple[float, float, float, float]:
    """Closest point of the bat's axis segment to the ball centre: (px, py, dist, t_axis)."""
    c, s = math.cos(r.bat_angle), math.sin(r.bat_angle)
    dx, dy = r.ball_x - r.bat_x, r.ball_y - r.bat_y
    along = dx * c + dy * s
    t = min(max(along, bat.s_min_m), bat.s_max_m)
    px, py = r.bat_x + t * c, r.bat_y + t * s
    return px, py, math.hypot(r.ball_x - px, r.ball_y - py), t


def penetration_m(bat: Bat, ball: Ball, r: Reading) -> float:
    """Geometric overlap of sphere and capsule (m), negative for a gap, measured from the side
    the ball came from: a ball whose centre has crossed the bat's axis is more than
    r_ball + r_bat deep, however close to the axis it sits."""
    dist = _closest(bat, r)[2]
    return bat.radius_m + ball.radius_m - (dist if ball_side_m(r) > 0.0 else -dist)


def separating(bat: Bat, r: Reading) -> bool:
    """True if the ball centre moves away from the closest point of the bat's axis."""
    px, py, dist, t = _closest(bat, r)
    if dist == 0.0:
        return False
    nx, ny = (r.ball_x - px) / dist, (r.ball_y - py) / dist
    # velocity of the bat point at distance t from the COM along the axis
    c, s = math.cos(r.bat_angle), math.sin(r.bat_angle)
    pvx, pvy = r.bat_vx - r.bat_w * t * s, r.bat_vy + r.bat_w * t * c
    return (r.ball_vx - pvx) * nx + (r.ball_vy - pvy) * ny > 0.0


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
#: Kinetic energy may grow by this fraction before ``energy_gained``: float64 rounding over
#: thousands of steps stays far below it, the defects we look for (+1% and more) far above.
ENERGY_GAIN_REL = 1e-6


class Engine(abc.ABC):
    """One physics engine behind the common contract: build once, fire many impacts."""

    name: ClassVar[str]
    profiles: ClassVar[dict[str, Settings]]

    def __init__(self, settings: Settings) -> None:
        self.settings = settings
        self._scene_key: tuple | None = None

    # -- the engine-specific half -------------------------------------------------------------

    @classmethod
    @abc.abstractmethod
    def version(cls) -> str:
        """The engine library's version string."""

    @abc.abstractmethod
    def _build(self, bat: Bat, ball: Ball) -> None:
        """Create (or re-create) the world with this bat and ball; called when either changes."""

    @abc.abstractmethod
    def _mass_properties(self) -> MassProperties:
        """Read back the mass properties the engine holds for both bodies."""

    @abc.abstractmethod
    def _configure(self, case: ImpactCase) -> None:
        """Set per-impact parameters (restitution, friction) without rebuilding."""

    @abc.abstractmethod
    def _set_state(self, r: Reading) -> None:
        """Put both bodies at the given positions and velocities (world frame)."""

    @abc.abstractmethod
    def _step(self) -> None:
        """Advance the engine by one time step ``settings.dt_s``."""

    @abc.abstractmethod
    def _read(self) -> Reading:
        """Current positions and velocities of both bodies (world frame, COM velocities)."""

    @abc.abstractmethod
    def _in_contact(self) -> bool:
        """True if the engine holds an active contact between bat and ball after the last step."""

    @abc.abstractmethod
    def _set_load(self, drive: Drive | None) -> None:
        """Apply ``drive``'s force and torque (fixed in the bat's frame) on every following step
        until called with None. The hinge in ``drive`` is not this method's business."""

    @abc.abstractmethod
    def _pin(self, pivot_from_com_m: float, pivot_xy_m: tuple[float, float]) -> None:
        """Hinge the bat's axis point ``pivot_from_com_m`` (m from the COM) to the world point
        ``pivot_xy_m`` with the engine's own joint or constraint, releasable by ``_unpin``."""

    @abc.abstractmethod
    def _unpin(self) -> None:
        """Let go of the hinge set by ``_pin`` (the hands release the bat)."""

    def close(self) -> None:
        """Release engine resources (a no-op unless the engine holds a connection)."""

    # -- the shared half ----------------------------------------------------------------------

    def check_mass_properties(self, bat: Bat, ball: Ball) -> None:
        """Raise SceneMismatch unless the engine holds exactly the scene's mass properties."""
        got = self._mass_properties()
        want = MassProperties(bat_mass_kg=bat.mass_kg, bat_com_from_knob_m=bat.com_from_knob_m,
                              bat_inertia_kgm2=bat.inertia_cm_kgm2, ball_mass_kg=ball.mass_kg,
                              ball_inertia_kgm2=ball.inertia_kgm2)
        for field in dataclasses.fields(MassProperties):
            a, b = getattr(got, field.name), getattr(want, field.name)
            if not math.isclose(a, b, rel_tol=MASS_CHECK_REL, abs_tol=1e-15):
                raise SceneMismatch(f"{self.name}: {field.name} read back as {a!r}, the scene "
                                    f"has {b!r} (allowed relative difference {MASS_CHECK_REL:g})")

    def _ensure_scene(self, bat: Bat, ball: Ball) -> None:
        key = (bat, ball)
        if key != self._scene_key:
            self.scene_bat = bat
            self._build(bat, ball)
            self.check_mass_properties(bat, ball)
            self._scene_key = key

    def run_motion(self, bat: Bat, drive: Drive, t_s: float, angle_rad: float = 0.0,
                   ball: Ball | None = None) -> MotionState:
        """Drive the bat alone (the ball parked far away) from rest for round(t/dt) steps."""
        from analytic import presets
        from analytic.dynamics import start_state

        drive.check(bat)
        ball = ball or presets.BASEBALL
        self._ensure_scene(bat, ball)
        s0 = start_state(bat, drive, angle_rad)
        self._set_state(Reading(0.0, PARKED_BALL_Y_M, 0.0, 0.0, 0.0, s0.x_m, s0.y_m, angle_rad,
                                0.0, 0.0, 0.0))
        if drive.pivot_from_knob_m is not None:
            self._pin(drive.pivot_from_knob_m - bat.com_from_knob_m, (0.0, 0.0))
        self._set_load(drive)
        steps = round(t_s / self.settings.dt_s)
        try:
            for _ in range(steps):
                self._step()
        finally:
            self._set_load(None)
            if drive.pivot_from_knob_m is not None:
                self._unpin()
        r = self._read()
        return MotionState(t_s=steps * self.settings.dt_s, x_m=r.bat_x, y_m=r.bat_y,
                           angle_rad=r.bat_angle, vx_mps=r.bat_vx, vy_mps=r.bat_vy,
                           omega_radps=r.bat_w)

    def simulate(self, case: ImpactCase, swing: SwingPlan | None = None) -> SimOutcome:
        """Fire one impact and measure it. Never raises for a physical failure.

        With a ``swing`` (from ``swing_case``) the bat is first swung about the hands in the
        engine and released; the impact then meets the bat the engine delivers.
        """
        t_wall = time.perf_counter()
        st = self.settings
        check_hittable(case)
        self._ensure_scene(case.bat, case.ball)
        self._configure(case)
        start, _ = start_reading(case, st)
        release_w = release_angle = math.nan
        swing_steps = 0
        if swing is not None:
            if swing.dt_s != st.dt_s:
                raise ValueError(f"swing plan made for dt_s={swing.dt_s!r}, engine steps "
                                 f"dt_s={st.dt_s!r}; allowed: a plan from swing_case with this "
                                 "engine's settings")
            self._set_state(swing.bat_start)
            self._pin(swing.swing.hands_from_knob_m - case.bat.com_from_knob_m, swing.pivot_xy_m)
            self._set_load(swing.swing.drive())
            try:
                for _ in range(swing.steps):
                    self._step()
            finally:
                self._set_load(None)
                self._unpin()
            bat_now = self._read()
            release_w, release_angle = bat_now.bat_w, bat_now.bat_angle
            swing_steps = swing.steps
            start = start._replace(bat_x=bat_now.bat_x, bat_y=bat_now.bat_y,
                                   bat_angle=bat_now.bat_angle, bat_vx=bat_now.bat_vx,
                                   bat_vy=bat_now.bat_vy, bat_w=bat_now.bat_w)
        self._set_state(start)
        ke0 = kinetic_energy_j(case, start)
        max_steps = st.approach_steps + math.ceil(st.max_contact_s / st.dt_s) + 2
        bat, ball = case.bat, case.ball
        first = last = -1
        peak = -math.inf
        status = None
        r = start
        step = 0
        # Free flight before the planned contact step cannot go wrong but by a blow-up, which
        # the final reading still catches: the state is read from that step on.
        while step < max_steps:
            self._step()
            step += 1
            touching = self._in_contact()
            if not touching and first < 0 and step < st.approach_steps:
                continue
            r = self._read()
            if not math.isfinite(sum(r)):
                break
            peak = max(peak, penetration_m(bat, ball, r))
            if touching:
                if first < 0:
                    first = step
                last = step
            elif first >= 0:
                if separating(bat, r):
                    break
            elif step > st.approach_steps + 1:
                status = Status.TUNNELLED
                break
        else:
            r = self._read()
            status = Status.NO_SEPARATION if first >= 0 else Status.TUNNELLED
        if not math.isfinite(sum(r)):
            status = Status.NON_FINITE
            peak = peak if math.isfinite(peak) else math.nan
        else:
            peak = max(peak, penetration_m(bat, ball, r))
        out = self._outcome(case, start, r, ke0, status, first, last, peak, step + swing_steps,
                            time.perf_counter() - t_wall)
        if swing is not None:
            out = dataclasses.replace(out, release_omega_radps=release_w,
                                      release_angle_rad=release_angle)
        return out

    def _outcome(self, case, start, r, ke0, status, first, last, peak, steps, wall) -> SimOutcome:
        bat, ball = case.bat, case.ball
        ke1 = kinetic_energy_j(case, r)
        if status is None:
            if ball_side_m(r) <= 0.0:
                status = Status.TUNNELLED
            elif peak > bat.radius_m + ball.radius_m:
                status = Status.PENETRATION
            elif ke1 > ke0 * (1.0 + ENERGY_GAIN_REL):
                status = Status.ENERGY_GAINED
            else:
                status = Status.OK
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
            ke_before_j=ke0,
            ke_after_j=ke1,
            v1_t_mps=r.ball_vx,
            u1_t_mps=r.bat_vx,
            engine=self.name,
            status=status,
            contact_duration_s=(last - first + 1) * self.settings.dt_s if first >= 0 else 0.0,
            peak_penetration_m=peak,
            steps=steps,
            wall_s=wall,
            settings=self.settings,
        )
