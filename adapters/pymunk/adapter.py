"""The pymunk adapter (see the package docstring for the scene and its traps)."""

from __future__ import annotations

import math

from ..interface import Engine, Hands, MassProperties, Scene, State
from ..loading import import_engine
from . import RECORD

pymunk = import_engine(RECORD)


def make_space(st) -> pymunk.Space:
    """A space with these settings' solver values, no gravity, no damping; the segmented
    bat's too."""
    space = pymunk.Space()
    space.gravity = (0.0, 0.0)
    space.damping = 1.0
    space.iterations = st.iterations
    space.collision_slop = st.collision_slop
    space.collision_bias = st.collision_bias
    return space


class PymunkEngine(Engine):
    """pymunk behind the single-world interface."""

    record = RECORD

    @classmethod
    def read_back_defaults(cls) -> dict:
        space = pymunk.Space()
        joint = pymunk.PivotJoint(space.static_body, pymunk.Body(1.0, 1.0), (0.0, 0.0))
        return {
            "iterations": space.iterations,
            "collision_slop": space.collision_slop,
            "collision_bias": space.collision_bias,
            "joint_error_bias": joint.error_bias,
        }

    def build(self, scene: Scene) -> None:
        st, bat, ball = self.settings, scene.bat, scene.ball
        space = make_space(st)
        self._bat = pymunk.Body(bat.mass_kg, bat.inertia_cm_kgm2)
        self._bat_shape = pymunk.Segment(
            self._bat, (bat.s_min_m, 0.0), (bat.s_max_m, 0.0), bat.radius_m
        )
        self._ball = pymunk.Body(ball.mass_kg, ball.inertia_kgm2)
        self._ball_shape = pymunk.Circle(self._ball, ball.radius_m)
        space.add(self._bat, self._bat_shape, self._ball, self._ball_shape)
        self._space = space
        self._joint: pymunk.PivotJoint | None = None
        self.set_body_restitution(bat=1.0, ball=scene.e)  # arbiter e = 1.0 * e
        bat_mu, ball_mu = RECORD.can.friction_rule.per_body(scene.mu)  # arbiter u = mu * 1.0
        self.set_body_friction(bat=bat_mu, ball=ball_mu)

    def close(self) -> None:
        # a space left to the interpreter's exit is freed after pymunk's C library (one
        # "Exception ignored" traceback per space): dropped here, freed while it is loaded
        self._space = self._bat = self._ball = self._bat_shape = self._ball_shape = None
        self._joint = None

    def mass_properties(self) -> MassProperties:
        knob_x = self._bat_shape.a.x - self._bat_shape.radius
        return MassProperties(
            bat_mass_kg=self._bat.mass,
            bat_com_from_knob_m=self._bat.center_of_gravity.x - knob_x,
            bat_inertia_kgm2=self._bat.moment,
            ball_mass_kg=self._ball.mass,
            ball_inertia_kgm2=self._ball.moment,
        )

    def set_body_restitution(self, *, bat: float, ball: float) -> None:
        self._bat_shape.elasticity, self._ball_shape.elasticity = bat, ball

    def set_body_friction(self, *, bat: float, ball: float) -> None:
        self._bat_shape.friction, self._ball_shape.friction = bat, ball

    def set_state(self, state: State) -> None:
        bat, ball = self._bat, self._ball
        bat.position, bat.angle = (state.bat_x_m, state.bat_y_m), state.bat_angle_rad
        bat.velocity = (state.bat_vx_mps, state.bat_vy_mps)
        bat.angular_velocity = state.bat_omega_radps
        ball.position, ball.angle = (state.ball_x_m, state.ball_y_m), 0.0
        ball.velocity = (state.ball_vx_mps, state.ball_vy_mps)
        ball.angular_velocity = state.ball_omega_radps
        # Removing a shape drops its cached arbiters, whose accumulated impulses would
        # warm-start the next contact: without this a used engine differs from a fresh one.
        self._space.remove(self._ball_shape)
        self._space.add(self._ball_shape)
        self._space.reindex_shapes_for_body(bat)

    def set_drive(self, hands: Hands | None) -> None:
        if hands is None:
            self._bat.velocity_func = pymunk.Body.update_velocity
            if self._joint is not None:
                self._space.remove(self._joint)
                self._joint = None
            return
        if hands.pivot_from_com_m is not None:
            self._joint = pymunk.PivotJoint(
                self._space.static_body, self._bat, hands.pivot_xy_m, (hands.pivot_from_com_m, 0.0)
            )
            self._joint.collide_bodies = False
            self._joint.error_bias = self.settings.joint_error_bias
            self._space.add(self._joint)
        # Chipmunk moves positions before it updates velocities, so a body-frame force must be
        # turned with the angle it has at that moment: inside the body's velocity function.
        f, q = hands.force_n, hands.angle_rad
        torque = hands.torque_about_com_nm  # the force moved to the COM, plus its moment

        def driven(body, gravity, damping, dt):
            angle = body.angle + q
            body.force = (f * math.cos(angle), f * math.sin(angle))
            body.torque = torque
            pymunk.Body.update_velocity(body, gravity, damping, dt)

        self._bat.velocity_func = driven

    def step(self) -> None:
        self._space.step(self.settings.dt_s)

    def read(self) -> State:
        ball, bat = self._ball, self._bat
        (bx, by), (bvx, bvy) = ball.position, ball.velocity
        (cx, cy), (cvx, cvy) = bat.position, bat.velocity
        return State(
            ball_x_m=bx,
            ball_y_m=by,
            ball_vx_mps=bvx,
            ball_vy_mps=bvy,
            ball_omega_radps=ball.angular_velocity,
            bat_x_m=cx,
            bat_y_m=cy,
            bat_angle_rad=bat.angle,
            bat_vx_mps=cvx,
            bat_vy_mps=cvy,
            bat_omega_radps=bat.angular_velocity,
        )

    def in_contact(self) -> bool:
        # Chipmunk lists only the arbiters that touched in the last step (cached ones are not).
        found = []
        self._bat.each_arbiter(found.append)
        return bool(found)
