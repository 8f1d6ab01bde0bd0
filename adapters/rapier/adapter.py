"""The Rapier adapter (see the package docstring for the scene and its traps)."""

from __future__ import annotations

import math

from ..frames import angle_and_tilt, bat_quaternion, in_the_plane
from ..interface import Engine, Hands, MassProperties, Scene, State
from ..loading import import_engine
from . import FRICTION_MODELS, RECORD

rapier = import_engine(RECORD)


class RapierEngine(Engine):
    """Rapier behind the single-world interface."""

    record = RECORD

    @classmethod
    def read_back_defaults(cls) -> dict:
        p = rapier.IntegrationParameters()
        unit = p.length_unit
        body = rapier.RigidBody.dynamic().build()
        joint = rapier.SphericalJoint().softness
        return {
            "dt_s": p.dt,
            "solver_iterations": p.num_solver_iterations,
            "pgs_iterations": p.num_internal_pgs_iterations,
            "stabilization_iterations": p.num_internal_stabilization_iterations,
            "contact_frequency_hz": p.contact_softness.natural_frequency,
            "contact_damping_ratio": p.contact_softness.damping_ratio,
            "allowed_linear_error_m": p.normalized_allowed_linear_error * unit,
            "max_corrective_velocity_mps": p.normalized_max_corrective_velocity * unit,
            "prediction_distance_m": p.normalized_prediction_distance * unit,
            "max_linear_velocity_mps": p.normalized_max_linear_velocity * unit,
            "allow_fast_rotation": body.allow_fast_rotation,
            "warmstart_coefficient": p.warmstart_coefficient,
            "contact_recycling": p.contact_recycling,
            "max_ccd_substeps": p.max_ccd_substeps,
            "ccd_bodies": "both" if body.ccd_enabled else "none",
            "soft_ccd_prediction_m": body.soft_ccd_prediction,
            "hinge_frequency_hz": joint.natural_frequency,
            "hinge_damping_ratio": joint.damping_ratio,
            "friction_model": FRICTION_MODELS[int(p.friction_model)],
            "friction_in_bias_pass": p.friction_in_bias_pass,
        }

    def __init__(self, settings) -> None:
        super().__init__(settings)
        self._world = None
        self._load: tuple[float, float, float] | None = None
        self._joint = None
        self._pivot: tuple[float, float] = (0.0, 0.0)
        self._failed = False

    def build(self, scene: Scene) -> None:
        st, bat, ball = self.settings, scene.bat, scene.ball
        w = rapier.PhysicsWorld(gravity=(0.0, 0.0, 0.0))
        w.set_num_threads(1)
        p = w.integration_parameters  # a live view: set in place
        p.dt = st.dt_s
        p.num_solver_iterations = st.solver_iterations
        p.num_internal_pgs_iterations = st.pgs_iterations
        p.num_internal_stabilization_iterations = st.stabilization_iterations
        p.contact_softness = rapier.SpringCoefficients(
            st.contact_frequency_hz, st.contact_damping_ratio
        )
        p.length_unit = 1.0
        p.normalized_allowed_linear_error = st.allowed_linear_error_m
        p.normalized_max_corrective_velocity = st.max_corrective_velocity_mps
        p.normalized_prediction_distance = st.prediction_distance_m
        p.normalized_max_linear_velocity = st.max_linear_velocity_mps
        p.warmstart_coefficient = st.warmstart_coefficient
        p.contact_recycling = st.contact_recycling
        p.max_ccd_substeps = st.max_ccd_substeps
        if scene.mu > 0.0:  # frictionless: Rapier's own model, as every frictionless run had it
            p.friction_model = getattr(rapier.FrictionModel, st.friction_model.upper())
            p.friction_in_bias_pass = st.friction_in_bias_pass
        self._world = w
        ib = ball.inertia_kgm2
        self._bat = self._add_body(
            rapier.MassProperties(
                local_com=(0.0, 0.0, 0.0),
                mass=bat.mass_kg,
                principal_inertia=(
                    bat.axial_inertia_kgm2,
                    bat.inertia_cm_kgm2,
                    bat.inertia_cm_kgm2,
                ),
            ),
            rapier.Collider.capsule_from_endpoints(
                (bat.s_min_m, 0.0, 0.0), (bat.s_max_m, 0.0, 0.0), bat.radius_m
            ),
            ccd=st.ccd_bodies == "both",
        )
        self._ball = self._add_body(
            rapier.MassProperties(
                local_com=(0.0, 0.0, 0.0), mass=ball.mass_kg, principal_inertia=(ib, ib, ib)
            ),
            rapier.Collider.ball(ball.radius_m),
            ccd=st.ccd_bodies != "none",
        )
        self._bat_col = w.rigid_bodies[self._bat].colliders[0]
        self._ball_col = w.rigid_bodies[self._ball].colliders[0]
        self._anchor = w.add_body(rapier.RigidBody.fixed())  # the world end of the hinge
        self._joint = self._load = None
        self.set_body_restitution(bat=scene.e, ball=scene.e)  # the mean of e and e is e
        if scene.mu > 0.0:
            bat_mu, ball_mu = RECORD.can.friction_rule.per_body(scene.mu)
            self.set_body_friction(bat=bat_mu, ball=ball_mu)

    def _add_body(self, mprops, collider, ccd: bool):
        """A dynamic body with exactly ``mprops`` (its collider massless), undamped, awake."""
        st, w = self.settings, self._world
        body = (
            rapier.RigidBody.dynamic()
            .additional_mass_properties(mprops)
            .can_sleep(False)
            .linear_damping(0.0)
            .angular_damping(0.0)
            .ccd_enabled(ccd)
            .soft_ccd_prediction(st.soft_ccd_prediction_m)
            .allow_fast_rotation(st.allow_fast_rotation)
        )
        handle = w.add_body(body, [collider.density(0.0).friction(0.0).restitution(0.0)])
        # Rapier folds additional mass properties in at the next step; read-back needs them now.
        w.rigid_bodies[handle].recompute_mass_properties_from_colliders(w.colliders)
        return handle

    def mass_properties(self) -> MassProperties:
        w = self._world
        mb = w.rigid_bodies[self._bat].mass_properties
        ms = w.rigid_bodies[self._ball].mass_properties
        capsule = w.colliders[self._bat_col].shape.as_capsule()
        knob_x = capsule.a.x - capsule.radius

        def izz(mp) -> float:
            """I_zz of the body-frame tensor R diag(I) R^T, R the principal frame."""
            frame = mp.principal_inertia_local_frame.to_matrix().reshape(3, 3)
            return float(sum(frame[2, k] ** 2 * mp.principal_inertia[k] for k in range(3)))

        return MassProperties(
            bat_mass_kg=mb.mass,
            bat_com_from_knob_m=mb.local_com.x - knob_x,
            bat_inertia_kgm2=izz(mb),
            ball_mass_kg=ms.mass,
            ball_inertia_kgm2=izz(ms),
        )

    def set_body_restitution(self, *, bat: float, ball: float) -> None:
        self._world.colliders[self._bat_col].restitution = bat
        self._world.colliders[self._ball_col].restitution = ball

    def set_body_friction(self, *, bat: float, ball: float) -> None:
        self._world.colliders[self._bat_col].friction = bat
        self._world.colliders[self._ball_col].friction = ball

    def set_state(self, state: State) -> None:
        self._planar = in_the_plane(state)  # read back as set (frames.angle_and_tilt)
        w = self._world
        self._failed = False
        bat, ball = w.rigid_bodies[self._bat], w.rigid_bodies[self._ball]
        bat.translation = (state.bat_x_m, state.bat_y_m, state.bat_z_m)
        if state.bat_tilt_rad == 0.0:  # Rapier's own f32 rotation, as planar runs always had
            bat.rotation = rapier.Rotation3.from_axis_angle((0.0, 0.0, 1.0), state.bat_angle_rad)
        else:
            q = bat_quaternion(state.bat_angle_rad, state.bat_tilt_rad)
            bat.rotation = rapier.Rotation3.from_quaternion(*q)
        bat.linvel = (state.bat_vx_mps, state.bat_vy_mps, state.bat_vz_mps)
        # a rigid body's angvel is the world's (measured: omega_x on a body turned about z by
        # pi/2 turns its x axis, the world's y, toward z)
        bat.angvel = (state.bat_wx_radps, state.bat_wy_radps, state.bat_omega_radps)
        ball.translation = (state.ball_x_m, state.ball_y_m, state.ball_z_m)
        ball.rotation = rapier.Rotation3.identity()
        ball.linvel = (state.ball_vx_mps, state.ball_vy_mps, state.ball_vz_mps)
        ball.angvel = (state.ball_wx_radps, state.ball_wy_radps, state.ball_omega_radps)
        # Re-inserting the ball's collider drops the pair's contact manifold and the impulses
        # it keeps for warm starts: without it a used engine differs from a fresh one.
        self._ball_col = w.add_collider(w.remove_collider(self._ball_col), self._ball)

    def set_drive(self, hands: Hands | None) -> None:
        if hands is None:
            self._load = None
            bat = self._world.rigid_bodies[self._bat]
            bat.reset_forces()  # user forces persist across steps until reset
            bat.reset_torques()
            self._unpin()
            return
        if hands.pivot_from_com_m is not None:
            self._pin(hands.pivot_from_com_m, hands.pivot_xy_m)
        self._load = (hands.force_n, hands.angle_rad, hands.torque_about_com_nm)

    def _pin(self, pivot_from_com_m: float, pivot_xy_m: tuple[float, float]) -> None:
        st, w = self.settings, self._world
        bat = w.rigid_bodies[self._bat]
        self._pivot = pivot_xy_m
        if st.hinge == "impulse":
            joint = (
                rapier.SphericalJoint.builder()
                .local_anchor1((pivot_xy_m[0], pivot_xy_m[1], 0.0))
                .local_anchor2((pivot_from_com_m, 0.0, 0.0))
                .softness(rapier.SpringCoefficients(st.hinge_frequency_hz, st.hinge_damping_ratio))
                .build()
            )
            self._joint = w.impulse_joints.insert(self._anchor, self._bat, joint)
            return
        # A revolute joint about z in reduced coordinates: a new link sits at coordinate 0, so
        # the frames put the bat's present pose there.
        free_z = (
            rapier.JointAxesMask.LIN_AXES | rapier.JointAxesMask.ANG_X | rapier.JointAxesMask.ANG_Y
        )
        joint = (
            rapier.GenericJointBuilder(free_z)
            .local_frame1(rapier.Isometry3((pivot_xy_m[0], pivot_xy_m[1], 0.0), bat.rotation))
            .local_frame2(
                rapier.Isometry3((pivot_from_com_m, 0.0, 0.0), rapier.Rotation3.identity())
            )
            .build()
        )
        self._joint = w.multibody_joints.insert(self._anchor, self._bat, joint)
        links = w.multibody_joints.multibody(self._joint)
        links.set_damping([0.0] * links.ndofs)  # multibody links are damped (0.1) by default
        velocity = links.generalized_velocity()
        velocity[-1] = bat.angvel.z
        links.set_generalized_velocity(velocity)

    def _unpin(self) -> None:
        if self._joint is None:
            return
        w = self._world
        if self.settings.hinge == "impulse":
            w.impulse_joints.remove(self._joint)
        else:
            # The link's rigid body holds the velocity of the step before (Rapier copies the
            # multibody's state into it before integrating): release the joint's own velocity.
            omega = w.multibody_joints.multibody(self._joint).generalized_velocity()[-1]
            w.multibody_joints.remove(self._joint)
            bat = w.rigid_bodies[self._bat]
            x, y, _ = bat.translation.to_tuple()
            px, py = self._pivot
            bat.linvel = (-omega * (y - py), omega * (x - px), 0.0)
            bat.angvel = (0.0, 0.0, omega)
        self._joint = None

    def step(self) -> None:
        w = self._world
        if self._load is not None:
            f, q, torque = self._load  # force through the COM + its constant torque
            bat = w.rigid_bodies[self._bat]
            rot = bat.rotation
            angle = 2.0 * math.atan2(rot.k, rot.w) + q
            bat.reset_forces()
            bat.reset_torques()
            bat.add_force((f * math.cos(angle), f * math.sin(angle), 0.0))
            bat.add_torque((0.0, 0.0, torque))
        w.step()
        if len(w.quarantine.bodies):  # non-finite bodies Rapier reset
            self._failed = True

    def read(self) -> State:
        bodies = self._world.rigid_bodies
        bat, ball = bodies[self._bat], bodies[self._ball]
        bx, by, bz = ball.translation.to_tuple()
        bvx, bvy, bvz = ball.linvel.to_tuple()
        bwx, bwy, bwz = ball.angvel.to_tuple()
        cx, cy, cz = bat.translation.to_tuple()
        cvx, cvy, cvz = bat.linvel.to_tuple()
        cwx, cwy, cwz = bat.angvel.to_tuple()
        rot = bat.rotation
        angle, tilt = angle_and_tilt(rot.w, rot.i, rot.j, rot.k, self._planar)
        return State(
            ball_x_m=bx,
            ball_y_m=by,
            ball_vx_mps=bvx,
            ball_vy_mps=bvy,
            ball_omega_radps=bwz,
            bat_x_m=cx,
            bat_y_m=cy,
            bat_angle_rad=angle,
            bat_vx_mps=cvx,
            bat_vy_mps=cvy,
            bat_omega_radps=cwz,
            ball_z_m=bz,
            ball_vz_mps=bvz,
            ball_wx_radps=bwx,
            ball_wy_radps=bwy,
            bat_z_m=cz,
            bat_tilt_rad=tilt,
            bat_vz_mps=cvz,
            bat_wx_radps=cwx,
            bat_wy_radps=cwy,
        )

    def in_contact(self) -> bool:
        # A speculative contact (bodies apart, no impulse) is not a touch.
        pair = self._world.narrow_phase.contact_pair(self._bat_col, self._ball_col)
        if pair is None:
            return False
        return any(pt.impulse > 0.0 or pt.dist < 0.0 for m in pair.manifolds for pt in m.points)

    def failed(self) -> bool:
        return self._failed
