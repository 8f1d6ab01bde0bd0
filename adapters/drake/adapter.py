"""The Drake adapter (see the package docstring for the contact law and its traps)."""

from __future__ import annotations

import math

import numpy as np

from ..interface import Engine, Hands, MassProperties, Scene, State
from ..loading import import_engine
from . import RECORD, dissipation_spm

pydrake = import_engine(RECORD)
from pydrake.geometry import (  # noqa: E402
    AddCompliantHydroelasticProperties,
    AddContactMaterial,
    AddRigidHydroelasticProperties,
    Capsule,
    DefaultProximityProperties,
    ProximityProperties,
    RoleAssign,
    Sphere,
)
from pydrake.math import RigidTransform, RotationMatrix  # noqa: E402
from pydrake.multibody.math import SpatialForce  # noqa: E402
from pydrake.multibody.plant import (  # noqa: E402
    AddMultibodyPlant,
    CoulombFriction,
    ExternallyAppliedSpatialForce,
    MultibodyPlantConfig,
)
from pydrake.multibody.tree import (  # noqa: E402
    FixedOffsetFrame,
    PrismaticJoint,
    RevoluteJoint,
    RotationalInertia,
    SpatialInertia,
)
from pydrake.systems.analysis import ResetIntegratorFromFlags, Simulator  # noqa: E402
from pydrake.systems.framework import DiagramBuilder  # noqa: E402


def joint_rates(
    angle: float, tilt: float, w: tuple[float, float, float]
) -> tuple[float, float, float]:
    """The rates of the bat's yaw, tilt and roll joints that turn it at the world angular
    velocity ``w``: w = yaw' z + tilt' h + roll' u, with u the bat's axis and h = (sin a,
    -cos a, 0) the tilt joint's axis (-y after the yaw). A turn about z alone is the yaw's."""
    if tilt == 0.0 and w[0] == 0.0 and w[1] == 0.0:
        return w[2], 0.0, 0.0
    ca, sa, cb, sb = math.cos(angle), math.sin(angle), math.cos(tilt), math.sin(tilt)
    along = w[0] * ca * cb + w[1] * sa * cb + w[2] * sb  # w . u (h is normal to u and z)
    yaw = (w[2] - sb * along) / (cb * cb)
    return yaw, w[0] * sa - w[1] * ca, along - yaw * sb


def world_rates(angle: float, tilt: float, rates) -> tuple[float, float, float]:
    """The bat's world angular velocity from its yaw, tilt and roll joint rates (the inverse
    of ``joint_rates``)."""
    yaw, tilt_rate, roll = rates
    if tilt == 0.0 and tilt_rate == 0.0 and roll == 0.0:
        return 0.0, 0.0, yaw
    ca, sa, cb, sb = math.cos(angle), math.sin(angle), math.cos(tilt), math.sin(tilt)
    return (tilt_rate * sa + roll * ca * cb, -tilt_rate * ca + roll * sa * cb, yaw + roll * sb)


def pivot_to_com(offset_m: float, angle: float, tilt: float, w) -> tuple[float, ...]:
    """(position, velocity) of the bat's COM less those of the chain's pivot, ``offset_m``
    along the axis from it: -offset u and w x (-offset u). In the swing plane, as the planar
    chain computed them (bit for bit)."""
    p = offset_m
    c, s = math.cos(angle), math.sin(angle)
    if tilt == 0.0 and w[0] == 0.0 and w[1] == 0.0:
        return -(p * c), -(p * s), 0.0, w[2] * p * s, -(w[2] * p * c), 0.0
    cb, sb = math.cos(tilt), math.sin(tilt)
    r = (-p * c * cb, -p * s * cb, -p * sb)
    return (*r, w[1] * r[2] - w[2] * r[1], w[2] * r[0] - w[0] * r[2], w[0] * r[1] - w[1] * r[0])


class DrakeEngine(Engine):
    """Drake behind the single-world interface."""

    record = RECORD

    @classmethod
    def read_back_defaults(cls) -> dict:
        config = MultibodyPlantConfig()
        return {
            "dt_s": config.time_step,
            "solver": config.discrete_contact_approximation,
            "contact_model": config.contact_model,
            "sap_near_rigid_threshold": config.sap_near_rigid_threshold,
            "point_stiffness_npm": 0.5 * DefaultProximityProperties().point_stiffness,
            "stiction_tolerance_mps": config.stiction_tolerance,
        }

    def __init__(self, settings) -> None:
        super().__init__(settings)
        self._load: Hands | None = None
        self._failed = False  # the current state is lost to a step Drake refused

    # -- building ------------------------------------------------------------------------------

    def build(self, scene: Scene) -> None:
        st, bat, ball = self.settings, scene.bat, scene.ball
        continuous = st.solver == "continuous"
        config = MultibodyPlantConfig(
            time_step=0.0 if continuous else st.dt_s,
            contact_model=st.contact_model,
            use_sampled_output_ports=False,
        )
        if not continuous:
            config.discrete_contact_approximation = st.solver
        if st.sap_near_rigid_threshold is not None:
            config.sap_near_rigid_threshold = st.sap_near_rigid_threshold
        if st.stiction_tolerance_mps is not None and scene.mu > 0.0:
            config.stiction_tolerance = st.stiction_tolerance_mps
        builder = DiagramBuilder()
        plant, sg = AddMultibodyPlant(config, builder)
        plant.mutable_gravity_field().set_gravity_vector([0.0, 0.0, 0.0])
        bat_body = plant.AddRigidBody(
            "bat",
            SpatialInertia.MakeFromCentralInertia(
                bat.mass_kg,
                np.zeros(3),
                RotationalInertia(bat.axial_inertia_kgm2, bat.inertia_cm_kgm2, bat.inertia_cm_kgm2),
            ),
        )
        ib = ball.inertia_kgm2
        ball_body = plant.AddRigidBody(
            "ball",
            SpatialInertia.MakeFromCentralInertia(
                ball.mass_kg, np.zeros(3), RotationalInertia(ib, ib, ib)
            ),
        )
        self._add_bat_chain(plant, bat_body)
        a, b = bat.s_min_m, bat.s_max_m
        along_x = RigidTransform(
            RotationMatrix.MakeYRotation(math.pi / 2), [(a + b) / 2, 0.0, 0.0]
        )  # Drake's capsules lie along z
        mu_bat, mu_ball = RECORD.can.friction_rule.per_body(scene.mu)
        self._friction = (CoulombFriction(mu_bat, mu_bat), CoulombFriction(mu_ball, mu_ball))
        self._geoms = (
            plant.RegisterCollisionGeometry(
                bat_body, along_x, Capsule(bat.radius_m, b - a), "bat", self._properties(rigid=True)
            ),
            plant.RegisterCollisionGeometry(
                ball_body,
                RigidTransform(),
                Sphere(ball.radius_m),
                "ball",
                self._properties(rigid=False),
            ),
        )
        plant.Finalize()
        self._bat, self._ball = bat_body, ball_body
        self._finish(builder, plant, sg)
        self._discrete = not continuous
        self._e = scene.e
        self._set_restitution(scene.e)

    def _add_bat_chain(self, plant, bat_body) -> None:
        """The bat's six coordinates, a chain of joints from the world through massless links:
        x, y, z prismatic, then the yaw about z, the tilt about -y and the roll about x
        (``adapters.frames``' order), the last joint's child the movable ``pivot`` frame on
        the bat (its pose a context parameter: ``set_drive`` moves the hinge there)."""
        frames = [plant.world_body().body_frame()]
        for name in ("bat_slider", "bat_hand", "bat_lift", "bat_yaw", "bat_tilted"):
            frames.append(plant.AddRigidBody(name, SpatialInertia.Zero()).body_frame())
        self._pivot = plant.AddFrame(
            FixedOffsetFrame("pivot", bat_body.body_frame(), RigidTransform())
        )
        frames.append(self._pivot)
        x, y, z, minus_y = [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [0.0, -1.0, 0.0]
        kinds = (
            (PrismaticJoint, "bat_x", x),
            (PrismaticJoint, "bat_y", y),
            (PrismaticJoint, "bat_z", z),
            (RevoluteJoint, "bat_turn", z),
            (RevoluteJoint, "bat_tilt", minus_y),
            (RevoluteJoint, "bat_roll", x),
        )
        self._joints = [
            plant.AddJoint(kind(name, frames[i], frames[i + 1], axis))
            for i, (kind, name, axis) in enumerate(kinds)
        ]

    def _finish(self, builder: DiagramBuilder, plant, sg) -> None:
        """Build the diagram and its simulator; keep the contexts, ports and indices used."""
        self._source = plant.get_source_id()
        diagram = builder.Build()
        self.plant, self.sg, self.diagram = plant, sg, diagram
        self._simulator = Simulator(diagram)
        ctx = self._simulator.get_mutable_context()
        self._ctx = ctx
        self._plant_ctx = plant.GetMyMutableContextFromRoot(ctx)
        self._sg_ctx = sg.GetMyMutableContextFromRoot(ctx)
        self._force_port = plant.get_applied_spatial_force_input_port()
        self._force_port.FixValue(self._plant_ctx, [])
        self._q_bat = [j.position_start() for j in self._joints]
        self._v_bat = [j.velocity_start() for j in self._joints]
        self._q_ball = self._ball.floating_positions_start()
        self._v_ball = self._ball.floating_velocities_start_in_v()
        self._query_port = plant.get_geometry_query_input_port()
        self._offset = 0.0
        self._load = None

    def _properties(self, rigid: bool, dissipation: float | None = None) -> ProximityProperties:
        """Proximity properties of one geometry: both carry 2k (in series: k), the same d and
        tau (d combines to d; tau adds up, so each carries half), and their own friction."""
        st = self.settings
        props = ProximityProperties()
        k = None if st.point_stiffness_npm is None else 2.0 * st.point_stiffness_npm
        AddContactMaterial(
            dissipation=dissipation,
            point_stiffness=k,
            friction=self._friction[0 if rigid else 1],
            properties=props,
        )
        if st.contact_model != "point" and (st.contact_model == "hydroelastic"):
            if rigid:
                AddRigidHydroelasticProperties(st.resolution_hint_m, props)
            else:
                AddCompliantHydroelasticProperties(
                    st.resolution_hint_m, st.hydroelastic_modulus_pa, props
                )
        return props

    def mass_properties(self) -> MassProperties:
        plant = self.plant
        ctx = plant.CreateDefaultContext()
        bat_m = self._bat.CalcSpatialInertiaInBodyFrame(ctx)
        ball_m = self._ball.CalcSpatialInertiaInBodyFrame(ctx)
        inspector = self.sg.model_inspector()
        X_BG = inspector.GetPoseInFrame(self._geoms[0])
        shape = inspector.GetShape(self._geoms[0])
        knob_x = X_BG.translation()[0] - shape.length() / 2 - shape.radius()
        return MassProperties(
            bat_mass_kg=float(bat_m.get_mass()),
            bat_com_from_knob_m=float(bat_m.get_com()[0] - knob_x),
            bat_inertia_kgm2=float(bat_m.CalcRotationalInertia().get_moments()[2]),
            ball_mass_kg=float(ball_m.get_mass()),
            ball_inertia_kgm2=float(ball_m.CalcRotationalInertia().get_moments()[2]),
        )

    def _set_restitution(self, e: float) -> None:
        st = self.settings
        d = dissipation_spm(e, st.restitution_speed_mps)
        for geom, rigid in zip(self._geoms, (True, False)):
            props = self._properties(rigid, dissipation=d)
            if st.solver == "sap":  # tau adds up over the two geometries
                props.AddProperty("material", "relaxation_time", 0.5 * st.relaxation_time_s(e))
            self.sg.AssignRole(self._sg_ctx, self._source, geom, props, RoleAssign.kReplace)

    def set_body_friction(self, *, bat: float, ball: float) -> None:
        self._friction = (CoulombFriction(bat, bat), CoulombFriction(ball, ball))
        self._set_restitution(self._e)  # re-assigns both geometries' properties

    # -- state ---------------------------------------------------------------------------------

    def _set_offset(self, offset_m: float) -> None:
        self._pivot.SetPoseInParentFrame(self._plant_ctx, RigidTransform([offset_m, 0.0, 0.0]))
        self._offset = offset_m

    def set_state(self, state: State) -> None:
        plant, pc = self.plant, self._plant_ctx
        self._ctx.SetTime(0.0)
        self._failed = False
        for joint in self._joints:
            joint.Unlock(pc)
        self._set_offset(0.0)
        q = np.zeros(plant.num_positions())
        v = np.zeros(plant.num_velocities())
        a, b = state.bat_angle_rad, state.bat_tilt_rad
        q[self._q_bat] = (state.bat_x_m, state.bat_y_m, state.bat_z_m, a, b, 0.0)
        w = (state.bat_wx_radps, state.bat_wy_radps, state.bat_omega_radps)
        v[self._v_bat] = (
            state.bat_vx_mps,
            state.bat_vy_mps,
            state.bat_vz_mps,
            *joint_rates(a, b, w),
        )
        # the ball's free joint: quaternion (w, x, y, z) then position; its velocities are the
        # spatial velocity in the world frame, angular first
        i, j = self._q_ball, self._v_ball
        q[i : i + 7] = (1.0, 0.0, 0.0, 0.0, state.ball_x_m, state.ball_y_m, state.ball_z_m)
        v[j : j + 6] = (
            state.ball_wx_radps,
            state.ball_wy_radps,
            state.ball_omega_radps,
            state.ball_vx_mps,
            state.ball_vy_mps,
            state.ball_vz_mps,
        )
        plant.SetPositions(pc, q)
        plant.SetVelocities(pc, v)
        self._apply_load()
        if not self._discrete:
            # a fresh integrator: the last impact's step-size guess would otherwise carry over
            integ = ResetIntegratorFromFlags(self._simulator, "runge_kutta3", self.settings.dt_s)
            integ.set_target_accuracy(self.settings.accuracy)
            integ.set_maximum_step_size(self.settings.dt_s)
            self._simulator.Initialize()

    def read(self) -> State:
        if self._failed:
            return State(*([math.nan] * len(State._fields)))
        plant, pc = self.plant, self._plant_ctx
        q, v = plant.GetPositions(pc), plant.GetVelocities(pc)
        i, j = self._q_ball, self._v_ball
        x, y, z, th, tilt, _ = (float(c) for c in q[self._q_bat])
        vx, vy, vz, *rates = (float(c) for c in v[self._v_bat])
        w = world_rates(th, tilt, rates)
        d = pivot_to_com(self._offset, th, tilt, w)
        return State(
            ball_x_m=float(q[i + 4]),
            ball_y_m=float(q[i + 5]),
            ball_vx_mps=float(v[j + 3]),
            ball_vy_mps=float(v[j + 4]),
            ball_omega_radps=float(v[j + 2]),
            bat_x_m=x + d[0],
            bat_y_m=y + d[1],
            bat_angle_rad=th,
            bat_vx_mps=vx + d[3],
            bat_vy_mps=vy + d[4],
            bat_omega_radps=w[2],
            ball_z_m=float(q[i + 6]),
            ball_vz_mps=float(v[j + 5]),
            ball_wx_radps=float(v[j]),
            ball_wy_radps=float(v[j + 1]),
            bat_z_m=z + d[2],
            bat_tilt_rad=tilt,
            bat_vz_mps=vz + d[5],
            bat_wx_radps=w[0],
            bat_wy_radps=w[1],
        )

    def step(self) -> None:
        if self._failed:
            return
        if self._load is not None:
            self._apply_load()
        try:
            self._advance()
        except RuntimeError:  # TAMSI not converging, the integrator's step below its minimum
            self._failed = True

    def failed(self) -> bool:
        return self._failed

    def _advance(self) -> None:
        if self._discrete:  # one periodic update, as the Simulator would make it
            pc = self._plant_ctx
            pc.get_mutable_discrete_state().SetFrom(self.plant.EvalUniquePeriodicDiscreteUpdate(pc))
            self._ctx.SetTime(self._ctx.get_time() + self.settings.dt_s)
        else:
            self._simulator.AdvanceTo(self._ctx.get_time() + self.settings.dt_s)

    def in_contact(self) -> bool:
        if self._failed:
            return False
        return len(self._query_port.Eval(self._plant_ctx).ComputePointPairPenetration()) > 0

    # -- the swing -----------------------------------------------------------------------------

    def _apply_load(self) -> None:
        load = self._load
        if load is None:
            self._force_port.FixValue(self._plant_ctx, [])
            return
        th = self.plant.GetPositions(self._plant_ctx)[self._q_bat[3]]
        q = th + load.angle_rad
        f = ExternallyAppliedSpatialForce()
        f.body_index = self._bat.index()
        f.p_BoBq_B = np.array([load.arm_m, 0.0, 0.0])
        f.F_Bq_W = SpatialForce(
            [0.0, 0.0, load.torque_nm],
            [load.force_n * math.cos(q), load.force_n * math.sin(q), 0.0],
        )
        self._force_port.FixValue(self._plant_ctx, [f])

    def set_drive(self, hands: Hands | None) -> None:
        self._load = hands
        if hands is None:
            self._apply_load()
            for joint in self._joints:
                joint.Unlock(self._plant_ctx)
            return
        if hands.pivot_from_com_m is not None:
            # The bat turns about the pivot frame: moved to the hands, with the chain's x and y
            # now those of the hands (the bat itself does not move: its angle is kept).
            angle = self.read().bat_angle_rad
            self._set_offset(hands.pivot_from_com_m)
            q = self.plant.GetPositions(self._plant_ctx)
            q[self._q_bat[:2]] = hands.pivot_xy_m
            q[self._q_bat[3]] = angle
            self.plant.SetPositions(self._plant_ctx, q)
            for k in (0, 1, 2, 4, 5):  # all but the yaw: a hinge about z
                self._joints[k].Lock(self._plant_ctx)
        self._apply_load()
