"""The PhysX adapter (see the package docstring for the scene and its traps)."""

from __future__ import annotations

import contextlib
import math
import warnings
from collections.abc import Iterator

from ..frames import angle_and_tilt, bat_quaternion, in_the_plane
from ..interface import Engine, Hands, MassProperties, Scene, State
from ..loading import feature, import_engine
from . import RECORD, PhysxSettings

with warnings.catch_warnings():  # SAPIEN warns that it uses its own Vulkan: we never render
    warnings.filterwarnings("ignore", message=".*libvulkan", category=UserWarning)
    sapien = import_engine(RECORD)
physx = sapien.physx


@contextlib.contextmanager
def _sapien_defaults(st: PhysxSettings) -> Iterator[None]:
    """Within the block, SAPIEN creates systems, bodies and shapes with these settings (None:
    its own); its process-wide defaults are restored afterwards."""
    scene, body, shape = (
        physx.get_scene_config(),
        physx.get_body_config(),
        physx.get_shape_config(),
    )
    try:
        physx.set_scene_config(
            gravity=[0.0, 0.0, 0.0],
            bounce_threshold=_or(st.bounce_threshold_mps, scene.bounce_threshold),
            enable_pcm=_or(st.enable_pcm, scene.enable_pcm),
            enable_tgs=scene.enable_tgs if st.solver is None else st.solver == "TGS",
            enable_ccd=scene.enable_ccd,
            enable_enhanced_determinism=scene.enable_enhanced_determinism,
            enable_friction_every_iteration=_or(
                st.friction_every_iteration, scene.enable_friction_every_iteration
            ),
        )
        physx.set_body_config(
            solver_position_iterations=_or(st.position_iterations, body.solver_position_iterations),
            solver_velocity_iterations=_or(st.velocity_iterations, body.solver_velocity_iterations),
            sleep_threshold=_or(st.sleep_threshold, body.sleep_threshold),
        )
        physx.set_shape_config(
            contact_offset=_or(st.contact_offset_m, shape.contact_offset),
            rest_offset=_or(st.rest_offset_m, shape.rest_offset),
        )
        yield
    finally:
        physx.set_scene_config(scene)
        physx.set_body_config(body)
        physx.set_shape_config(shape)


def _or(value, default):
    return default if value is None else value


def setup_body(body, shape, mass: float, inertia: tuple[float, float, float], st):
    """A rigid body or articulation link with ``shape``, these mass properties and the
    settings' body values: no torsional friction, no damping, no gravity, the caps on spin
    and depenetration (the segmented bat's links too)."""
    shape.patch_radius = shape.min_patch_radius = 0.0
    body.attach(shape)
    body.mass = mass
    body.inertia = inertia
    body.cmass_local_pose = sapien.Pose()
    body.linear_damping = body.angular_damping = 0.0
    body.disable_gravity = True
    if st.max_angular_velocity_radps is not None:  # a property from SAPIEN 3.0.2
        feature(type(body), "max_angular_velocity", "max_angular_velocity_radps")
        body.max_angular_velocity = st.max_angular_velocity_radps
    if st.max_depenetration_velocity_mps is not None:
        body.max_depenetration_velocity = st.max_depenetration_velocity_mps
    return body


class PhysxEngine(Engine):
    """PhysX (through SAPIEN) behind the single-world interface."""

    record = RECORD

    @classmethod
    def read_back_defaults(cls) -> dict:
        system = physx.PhysxCpuSystem()
        body = physx.PhysxRigidDynamicComponent()
        shape = physx.PhysxCollisionShapeSphere(1.0, physx.get_default_material())
        cfg = system.config
        return {
            "dt_s": system.timestep,
            "solver": "TGS" if cfg.enable_tgs else "PGS",
            "friction_every_iteration": cfg.enable_friction_every_iteration,
            "bounce_threshold_mps": cfg.bounce_threshold,
            "enable_pcm": cfg.enable_pcm,
            "contact_offset_m": shape.contact_offset,
            "rest_offset_m": shape.rest_offset,
            "position_iterations": body.solver_position_iterations,
            "velocity_iterations": body.solver_velocity_iterations,
            "max_angular_velocity_radps": getattr(body, "max_angular_velocity", None),
            "max_depenetration_velocity_mps": body.max_depenetration_velocity,
            "sleep_threshold": body.sleep_threshold,
        }

    def __init__(self, settings) -> None:
        super().__init__(settings)
        self._scene = None
        self._load: tuple[float, float, float] | None = None
        self._hinge = None

    def close(self) -> None:
        if self._scene is not None:
            self._scene.clear()
            self._scene = self._system = None

    def build(self, scene: Scene) -> None:
        st, bat, ball = self.settings, scene.bat, scene.ball
        self.close()
        self._hinge = None
        with _sapien_defaults(st):
            self._system = physx.PhysxCpuSystem()
            self._scene = sapien.Scene([self._system])
            self._system.timestep = st.dt_s
            a, b, r = bat.s_min_m, bat.s_max_m, bat.radius_m
            self._bat_material = physx.PhysxMaterial(0.0, 0.0, 1.0)
            self._ball_material = physx.PhysxMaterial(0.0, 0.0, 1.0)
            capsule = physx.PhysxCollisionShapeCapsule(r, 0.5 * (b - a), self._bat_material)
            capsule.set_local_pose(sapien.Pose([0.5 * (a + b), 0.0, 0.0]))
            sphere = physx.PhysxCollisionShapeSphere(ball.radius_m, self._ball_material)
            self._bat = self._body(
                capsule,
                bat.mass_kg,
                (bat.axial_inertia_kgm2, bat.inertia_cm_kgm2, bat.inertia_cm_kgm2),
            )
            self._ball = self._body(sphere, ball.mass_kg, (ball.inertia_kgm2,) * 3)
        self._pair = {id(self._bat), id(self._ball)}
        self.set_body_restitution(bat=scene.e, ball=scene.e)  # PhysX averages the two
        if scene.mu > 0.0:  # frictionless: both stay at 0, as every frictionless run was built
            bat_mu, ball_mu = RECORD.can.friction_rule.per_body(scene.mu)  # (mu + mu) / 2
            self.set_body_friction(bat=bat_mu, ball=ball_mu)

    def _body(self, shape, mass: float, inertia: tuple[float, float, float]):
        body = setup_body(physx.PhysxRigidDynamicComponent(), shape, mass, inertia, self.settings)
        entity = sapien.Entity()
        entity.add_component(body)
        self._scene.add_entity(entity)
        return body

    def mass_properties(self) -> MassProperties:
        bat, ball = self._bat, self._ball
        shape = bat.collision_shapes[0]
        knob_x = float(shape.local_pose.p[0]) - shape.half_length - shape.radius
        com_x = float(bat.cmass_local_pose.p[0])
        return MassProperties(
            bat_mass_kg=bat.mass,
            bat_com_from_knob_m=com_x - knob_x,
            bat_inertia_kgm2=float(bat.inertia[2]),
            ball_mass_kg=ball.mass,
            ball_inertia_kgm2=float(ball.inertia[2]),
        )

    def set_body_restitution(self, *, bat: float, ball: float) -> None:
        self._bat_material.restitution = bat
        self._ball_material.restitution = ball

    def set_body_friction(self, *, bat: float, ball: float) -> None:
        for material, value in ((self._bat_material, bat), (self._ball_material, ball)):
            material.static_friction = material.dynamic_friction = value

    def set_state(self, state: State) -> None:
        self._planar = in_the_plane(state)  # read back as set (frames.angle_and_tilt)
        # SAPIEN's quaternions are (w, x, y, z), as ours; velocities are the world frame's
        q = bat_quaternion(state.bat_angle_rad, state.bat_tilt_rad)
        for body, pose, v, w in (
            (
                self._bat,
                sapien.Pose([state.bat_x_m, state.bat_y_m, state.bat_z_m], q),
                (state.bat_vx_mps, state.bat_vy_mps, state.bat_vz_mps),
                (state.bat_wx_radps, state.bat_wy_radps, state.bat_omega_radps),
            ),
            (
                self._ball,
                sapien.Pose([state.ball_x_m, state.ball_y_m, state.ball_z_m]),
                (state.ball_vx_mps, state.ball_vy_mps, state.ball_vz_mps),
                (state.ball_wx_radps, state.ball_wy_radps, state.ball_omega_radps),
            ),
        ):
            body.entity.pose = pose
            body.linear_velocity = v
            body.angular_velocity = w

    def set_drive(self, hands: Hands | None) -> None:
        if hands is None:
            self._load = None
            if self._hinge is not None:
                self._bat.entity.remove_component(self._hinge)
                self._hinge = None
            return
        if hands.pivot_from_com_m is not None:
            hinge = physx.PhysxDriveComponent(self._bat)
            hinge.pose_in_child = sapien.Pose([hands.pivot_from_com_m, 0.0, 0.0])
            hinge.pose_in_parent = sapien.Pose([*hands.pivot_xy_m, 0.0])
            for lock in (hinge.set_limit_x, hinge.set_limit_y, hinge.set_limit_z):
                lock(0.0, 0.0)  # all three translations locked: a ball joint at the hands
            self._bat.entity.add_component(hinge)
            self._hinge = hinge
        self._load = (hands.force_n, hands.angle_rad, hands.torque_about_com_nm)

    def step(self) -> None:
        if self._load is not None:
            f, q, torque = self._load  # force through the COM + its constant torque
            qw, _, _, qz = self._bat.entity.pose.q.tolist()
            angle = 2.0 * math.atan2(qz, qw) + q
            self._bat.add_force_torque(
                [f * math.cos(angle), f * math.sin(angle), 0.0], [0.0, 0.0, torque]
            )
        self._system.step()

    def read(self) -> State:
        bat, ball = self._bat, self._ball
        pose = bat.entity.pose
        bp, bq = pose.p.tolist(), pose.q.tolist()
        cp = ball.entity.pose.p.tolist()
        bv, bw = bat.linear_velocity.tolist(), bat.angular_velocity.tolist()
        cv, cw = ball.linear_velocity.tolist(), ball.angular_velocity.tolist()
        angle, tilt = angle_and_tilt(*bq, self._planar)
        return State(
            ball_x_m=cp[0],
            ball_y_m=cp[1],
            ball_vx_mps=cv[0],
            ball_vy_mps=cv[1],
            ball_omega_radps=cw[2],
            bat_x_m=bp[0],
            bat_y_m=bp[1],
            bat_angle_rad=angle,
            bat_vx_mps=bv[0],
            bat_vy_mps=bv[1],
            bat_omega_radps=bw[2],
            ball_z_m=cp[2],
            ball_vz_mps=cv[2],
            ball_wx_radps=cw[0],
            ball_wy_radps=cw[1],
            bat_z_m=bp[2],
            bat_tilt_rad=tilt,
            bat_vz_mps=bv[2],
            bat_wx_radps=bw[0],
            bat_wy_radps=bw[1],
        )

    def in_contact(self) -> bool:
        for contact in self._system.get_contacts():
            for point in contact.points:
                if point.separation <= 0.0 or any(point.impulse):
                    return True
        return False
