"""pymunk (Chipmunk2D) adapter: the planar scene maps one to one.

The bat is a Body with SET mass and moment, its origin at the COM, carrying a Segment shape (a
capsule) with no mass of its own; the ball a Body with a Circle. Restitution is the product of the
two shapes' ``elasticity`` (bat 1, ball e). Chipmunk resolves penetration with separate bias
velocities, so ``collision_slop``/``collision_bias`` do not touch the outgoing velocities; there
are no swept collisions (Chipmunk2D #212). ``body.velocity`` is the COM's velocity.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from analytic import Ball, Bat
from analytic import _checks

from ._record import EngineRecord, KnobFamily, RestitutionRule, import_engine
from .base import BodyLoad, Engine, MassProperties, Reading, Settings

# pymunk.Space() defaults (length unit: m here), as Chipmunk computes them, in single precision:
# 0.1f, and pow(1 - 0.1f, 60) for the bias; the record's engine_defaults and a test pin them.
CHIPMUNK_SLOP = 0.10000000149011612
CHIPMUNK_BIAS = 0.0017970074436457143


@dataclass(frozen=True, kw_only=True)
class PymunkSettings(Settings):
    """Chipmunk's knobs: solver ``iterations``; ``collision_slop`` (m) of allowed overlap;
    ``collision_bias``, the fraction of overlap left after 1 s of correction;
    ``joint_error_bias``, the same for the hands' pivot joint (0: corrected fully every step)."""

    iterations: int = 10
    collision_slop: float = CHIPMUNK_SLOP
    collision_bias: float = CHIPMUNK_BIAS
    joint_error_bias: float = CHIPMUNK_BIAS

    def __post_init__(self) -> None:
        super().__post_init__()
        _checks.integer("iterations", self.iterations, 1, 10_000)
        _checks.non_negative("collision_slop", self.collision_slop)
        _checks.in_range("collision_bias", self.collision_bias, 0.0, 1.0)
        _checks.in_range("joint_error_bias", self.joint_error_bias, 0.0, 1.0)


RECORD = EngineRecord(
    name="pymunk", package="pymunk", import_name="pymunk",
    profiles={
        # Chipmunk's own solver values are already exact for one frictionless contact (a single
        # constraint is solved in the first iteration); fidelity only needs a short step
        # (10 us: the contact normal tilts by omega*dt while the bat turns) and aligned contact.
        # The hands' pivot is corrected fully every step (joint_error_bias 0): the hinge's drift
        # is then second order (6e-8 of omega after a 0.1 s swing at 10 us) instead of first.
        "reference": PymunkSettings(dt_s=1e-5, joint_error_bias=0.0),
        # Out of the box: the 1/60 s step of pymunk's examples, Chipmunk's defaults, the contact
        # instant mid-step as in any unaligned simulation.
        "default": PymunkSettings(dt_s=1 / 60, contact_phase=0.5),
    },
    color="tab:blue", marker="o",
    speed_accuracy=(KnobFamily(label="iterations 1", overrides=(("iterations", 1),)),
                    KnobFamily(label="iterations 10", overrides=(("iterations", 10),),
                               quick=True),
                    KnobFamily(label="iterations 100", overrides=(("iterations", 100),))),
    restitution_rule=RestitutionRule.PRODUCT,
    engine_defaults={"iterations": 10, "collision_slop": CHIPMUNK_SLOP,
                     "collision_bias": CHIPMUNK_BIAS, "joint_error_bias": CHIPMUNK_BIAS},
)
pymunk = import_engine(RECORD)


class PymunkEngine(Engine):
    """pymunk behind the common contract."""

    record = RECORD

    @classmethod
    def read_back_defaults(cls) -> dict:
        space = pymunk.Space()
        joint = pymunk.PivotJoint(space.static_body, pymunk.Body(1.0, 1.0), (0.0, 0.0))
        return {"iterations": space.iterations, "collision_slop": space.collision_slop,
                "collision_bias": space.collision_bias, "joint_error_bias": joint.error_bias}

    def build_scene(self, bat: Bat, ball: Ball) -> None:
        st = self.settings
        space = pymunk.Space()
        space.gravity = (0.0, 0.0)
        space.damping = 1.0
        space.iterations = st.iterations
        space.collision_slop = st.collision_slop
        space.collision_bias = st.collision_bias
        self._bat = pymunk.Body(bat.mass_kg, bat.inertia_cm_kgm2)
        self._bat_shape = pymunk.Segment(self._bat, (bat.s_min_m, 0.0), (bat.s_max_m, 0.0),
                                         bat.radius_m)
        self._ball = pymunk.Body(ball.mass_kg, ball.inertia_kgm2)
        self._ball_shape = pymunk.Circle(self._ball, ball.radius_m)
        for shape in (self._bat_shape, self._ball_shape):
            shape.friction = 0.0
        self._bat_shape.elasticity = 1.0
        space.add(self._bat, self._bat_shape, self._ball, self._ball_shape)
        self._space = space
        self._joint: pymunk.PivotJoint | None = None

    def mass_properties(self) -> MassProperties:
        knob_x = self._bat_shape.a.x - self._bat_shape.radius
        return MassProperties(
            bat_mass_kg=self._bat.mass,
            bat_com_from_knob_m=self._bat.center_of_gravity.x - knob_x,
            bat_inertia_kgm2=self._bat.moment,
            ball_mass_kg=self._ball.mass,
            ball_inertia_kgm2=self._ball.moment,
        )

    def set_restitution(self, e: float) -> None:
        self.set_body_restitution(bat=1.0, ball=e)  # arbiter e = 1.0 * e

    def set_body_restitution(self, *, bat: float, ball: float) -> None:
        super().set_body_restitution(bat=bat, ball=ball)
        self._bat_shape.elasticity, self._ball_shape.elasticity = bat, ball

    def set_state(self, r: Reading) -> None:
        bat, ball = self._bat, self._ball
        bat.position, bat.angle = (r.bat_x, r.bat_y), r.bat_angle
        bat.velocity, bat.angular_velocity = (r.bat_vx, r.bat_vy), r.bat_w
        ball.position, ball.angle = (r.ball_x, r.ball_y), 0.0
        ball.velocity, ball.angular_velocity = (r.ball_vx, r.ball_vy), r.ball_w
        # Removing a shape drops its cached arbiters, whose accumulated impulses would
        # warm-start the next contact: without this a used engine differs from a fresh one.
        self._space.remove(self._ball_shape)
        self._space.add(self._ball_shape)
        self._space.reindex_shapes_for_body(bat)

    def set_load(self, load: BodyLoad | None) -> None:
        # Chipmunk moves positions before it updates velocities, so a body-frame force must be
        # turned with the angle it has at that moment: inside the body's velocity function.
        if load is None:
            self._bat.velocity_func = pymunk.Body.update_velocity
            return
        f, q = load.force_n, load.angle_rad
        torque = load.torque_about_com_nm  # the force moved to the COM, plus its moment

        def driven(body, gravity, damping, dt):
            angle = body.angle + q
            body.force = (f * math.cos(angle), f * math.sin(angle))
            body.torque = torque
            pymunk.Body.update_velocity(body, gravity, damping, dt)

        self._bat.velocity_func = driven

    def pin(self, pivot_from_com_m: float, pivot_xy_m: tuple[float, float]) -> None:
        self._joint = pymunk.PivotJoint(self._space.static_body, self._bat, pivot_xy_m,
                                        (pivot_from_com_m, 0.0))
        self._joint.collide_bodies = False
        self._joint.error_bias = self.settings.joint_error_bias
        self._space.add(self._joint)

    def unpin(self) -> None:
        if self._joint is not None:
            self._space.remove(self._joint)
            self._joint = None

    def step(self) -> None:
        self._space.step(self.settings.dt_s)

    def read(self) -> Reading:
        ball, bat = self._ball, self._bat
        (bx, by), (bvx, bvy) = ball.position, ball.velocity
        (cx, cy), (cvx, cvy) = bat.position, bat.velocity
        return Reading(bx, by, bvx, bvy, ball.angular_velocity, cx, cy, bat.angle, cvx, cvy,
                       bat.angular_velocity)

    def in_contact(self) -> bool:
        # Chipmunk lists only the arbiters that touched in the last step (cached ones are not).
        found = []
        self._bat.each_arbiter(found.append)
        return bool(found)


ENGINE = PymunkEngine
