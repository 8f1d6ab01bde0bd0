"""The Box2D v3 adapter (see the package docstring for the scene and its traps)."""

from __future__ import annotations

import math

from ..interface import Engine, Hands, MassProperties, Scene, State
from ..loading import import_engine
from . import RECORD

b2 = import_engine(RECORD)


def _rot(angle: float):
    """A Box2D rotation from cos/sin in double precision (b2MakeRot approximates them)."""
    q = b2.Rot()
    q.c, q.s = math.cos(angle), math.sin(angle)
    return q


def make_world(st):
    """A world with these settings' values (gravity 0, sleeping off); the segmented bat's too."""
    given = {
        "restitution_threshold": st.restitution_threshold_mps,
        "maximum_linear_speed": st.maximum_linear_speed_mps,
        "contact_hertz": st.contact_hertz,
        "contact_damping_ratio": st.contact_damping_ratio,
    }
    world = b2.World(gravity=(0.0, 0.0), **{k: v for k, v in given.items() if v is not None})
    world.sleeping_enabled = False
    world.continuous_enabled = st.continuous
    if st.contact_push_mps is not None:
        wd = b2.WorldDef()
        world.set_contact_tuning(
            wd.contact_hertz if st.contact_hertz is None else st.contact_hertz,
            wd.contact_damping_ratio
            if st.contact_damping_ratio is None
            else st.contact_damping_ratio,
            st.contact_push_mps,
        )
    return world


class Box2dEngine(Engine):
    """Box2D v3 behind the single-world interface."""

    record = RECORD

    @classmethod
    def read_back_defaults(cls) -> dict:
        d = b2.WorldDef()
        return {
            "contact_hertz": d.contact_hertz,
            "contact_damping_ratio": d.contact_damping_ratio,
            "restitution_threshold_mps": d.restitution_threshold,
            "maximum_linear_speed_mps": d.maximum_linear_speed,
        }

    def __init__(self, settings) -> None:
        super().__init__(settings)
        self._world = None
        self._joint = None
        self._load: tuple[float, float, float] | None = None

    def close(self) -> None:
        if self._world is not None:
            self._world.destroy()
            self._world = None

    def build(self, scene: Scene) -> None:
        st, bat, ball = self.settings, scene.bat, scene.ball
        self.close()
        self._world = world = make_world(st)
        self._sub_steps = st.sub_step_count
        self._joint = None
        self._anchor = world.create_static_body(position=(0.0, 0.0))
        self._bat = world.create_dynamic_body(position=(0.0, 0.0), enable_sleep=False)
        self._ball = world.create_dynamic_body(
            position=(0.0, 1.0), enable_sleep=False, is_bullet=st.bullet
        )
        sd = b2.ShapeDef()
        sd.density = 1.0
        sd.update_body_mass = True  # shapes set the extents continuous collision uses
        sd.enable_contact_events = False
        mat = b2.SurfaceMaterial()
        mat.friction = 0.0
        mat.restitution = 1.0
        mat.rolling_resistance = 0.0  # Box2D's default already: no rolling friction
        sd.material = mat
        self._bat_shape = self._bat.create_capsule_shape(
            sd, b2.capsule((bat.s_min_m, 0.0), (bat.s_max_m, 0.0), bat.radius_m)
        )
        self._ball_shape = self._ball.create_circle_shape(sd, b2.circle((0.0, 0.0), ball.radius_m))
        for body, mass, inertia in (
            (self._bat, bat.mass_kg, bat.inertia_cm_kgm2),
            (self._ball, ball.mass_kg, ball.inertia_kgm2),
        ):
            md = b2.MassData()
            md.mass, md.center, md.rotational_inertia = mass, (0.0, 0.0), inertia
            body.mass_data = md
        self._v_before: tuple[float, float, float] | None = None
        self.set_body_restitution(bat=0.0, ball=scene.e)  # Box2D takes the larger of the two
        bat_mu, ball_mu = RECORD.can.friction_rule.per_body(scene.mu)  # sqrt(mu mu) = mu
        self.set_body_friction(bat=bat_mu, ball=ball_mu)

    def mass_properties(self) -> MassProperties:
        bat, ball = self._bat.mass_data, self._ball.mass_data
        cap = self._bat.shapes[0].capsule
        knob_x = cap.center1.x - cap.radius
        return MassProperties(
            bat_mass_kg=bat.mass,
            bat_com_from_knob_m=bat.center.x - knob_x,
            bat_inertia_kgm2=bat.rotational_inertia,
            ball_mass_kg=ball.mass,
            ball_inertia_kgm2=ball.rotational_inertia,
        )

    def set_body_restitution(self, *, bat: float, ball: float) -> None:
        self._bat_shape.restitution, self._ball_shape.restitution = bat, ball

    def set_body_friction(self, *, bat: float, ball: float) -> None:
        # Box2D mixes the shapes' values into the contact's every step (b2UpdateContact)
        self._bat_shape.friction, self._ball_shape.friction = bat, ball

    def set_state(self, state: State) -> None:
        for body in (self._ball, self._bat):
            body.enabled = False  # destroys the pair's contact (its warm-start impulse)
            body.enabled = True
        self._bat.set_transform((state.bat_x_m, state.bat_y_m), _rot(state.bat_angle_rad))
        self._bat.linear_velocity = (state.bat_vx_mps, state.bat_vy_mps)
        self._bat.angular_velocity = state.bat_omega_radps
        self._ball.set_transform((state.ball_x_m, state.ball_y_m), _rot(0.0))
        self._ball.linear_velocity = (state.ball_vx_mps, state.ball_vy_mps)
        self._ball.angular_velocity = state.ball_omega_radps
        self._v_before = None

    def set_drive(self, hands: Hands | None) -> None:
        if hands is None:
            self._load = None
            if self._joint is not None:
                self._joint.destroy()
                self._joint = None
            return
        if hands.pivot_from_com_m is not None:
            jd = b2.RevoluteJointDef()
            jd.body_a, jd.body_b = self._anchor, self._bat
            jd.local_anchor_a = hands.pivot_xy_m
            jd.local_anchor_b = (hands.pivot_from_com_m, 0.0)
            jd.collide_connected = False
            self._joint = self._world.create_joint(jd)
        self._load = (hands.force_n, hands.angle_rad, hands.torque_about_com_nm)

    def step(self) -> None:
        if self._load is not None:
            f, q, torque = self._load
            rot = self._bat.rotation
            angle = math.atan2(rot.s, rot.c) + q
            self._bat.apply_force_to_center((f * math.cos(angle), f * math.sin(angle)))
            self._bat.apply_torque(torque)
        v = self._ball.linear_velocity
        self._v_before = (v.x, v.y, self._ball.angular_velocity)
        # One force per step: Box2D applies it in every sub-step in the world direction it has
        # at the step's start.
        self._world.step(self.settings.dt_s, self._sub_steps)

    def read(self) -> State:
        ball, bat = self._ball, self._bat
        bp, bv = ball.position, ball.linear_velocity
        cp, cv = bat.position, bat.linear_velocity
        rot = bat.rotation
        return State(
            ball_x_m=bp.x,
            ball_y_m=bp.y,
            ball_vx_mps=bv.x,
            ball_vy_mps=bv.y,
            ball_omega_radps=ball.angular_velocity,
            bat_x_m=cp.x,
            bat_y_m=cp.y,
            bat_angle_rad=math.atan2(rot.s, rot.c),
            bat_vx_mps=cv.x,
            bat_vy_mps=cv.y,
            bat_omega_radps=bat.angular_velocity,
        )

    def in_contact(self) -> bool:
        # Only the bat's contact acts on the ball: a contact impulse in the last step changed
        # its velocity (Box2D's own "touching" includes speculative points up to 2 cm apart).
        if self._v_before is None:
            return False
        v = self._ball.linear_velocity
        return (v.x, v.y, self._ball.angular_velocity) != self._v_before
