"""The Drake adapter (see the package docstring for the contact law and its traps)."""

from __future__ import annotations

import math

import numpy as np

from ..interface import Engine, Hands, MassProperties, Scene, State
from ..record import import_engine
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

_NO_FRICTION = CoulombFriction(0.0, 0.0)


class DrakeEngine(Engine):
    """Drake behind the single-world interface."""

    record = RECORD

    @classmethod
    def read_back_defaults(cls) -> dict:
        config = MultibodyPlantConfig()
        return {"dt_s": config.time_step, "solver": config.discrete_contact_approximation,
                "contact_model": config.contact_model,
                "sap_near_rigid_threshold": config.sap_near_rigid_threshold,
                "point_stiffness_npm": 0.5 * DefaultProximityProperties().point_stiffness}

    def __init__(self, settings) -> None:
        super().__init__(settings)
        self._load: Hands | None = None
        self._failed = False    # the current state is lost to a step Drake refused

    # -- building ------------------------------------------------------------------------------

    def build(self, scene: Scene) -> None:
        st, bat, ball = self.settings, scene.bat, scene.ball
        continuous = st.solver == "continuous"
        config = MultibodyPlantConfig(time_step=0.0 if continuous else st.dt_s,
                                      contact_model=st.contact_model,
                                      use_sampled_output_ports=False)
        if not continuous:
            config.discrete_contact_approximation = st.solver
        if st.sap_near_rigid_threshold is not None:
            config.sap_near_rigid_threshold = st.sap_near_rigid_threshold
        builder = DiagramBuilder()
        plant, sg = AddMultibodyPlant(config, builder)
        plant.mutable_gravity_field().set_gravity_vector([0.0, 0.0, 0.0])
        world = plant.world_body()
        massless = SpatialInertia.Zero()
        slider = plant.AddRigidBody("bat_slider", massless)
        hand = plant.AddRigidBody("bat_hand", massless)
        bat_body = plant.AddRigidBody("bat", SpatialInertia.MakeFromCentralInertia(
            bat.mass_kg, np.zeros(3), RotationalInertia(bat.axial_inertia_kgm2,
                                                        bat.inertia_cm_kgm2,
                                                        bat.inertia_cm_kgm2)))
        ib = ball.inertia_kgm2
        ball_body = plant.AddRigidBody("ball", SpatialInertia.MakeFromCentralInertia(
            ball.mass_kg, np.zeros(3), RotationalInertia(ib, ib, ib)))
        pivot = plant.AddFrame(FixedOffsetFrame("pivot", bat_body.body_frame(),
                                                RigidTransform()))
        self._x = plant.AddJoint(PrismaticJoint("bat_x", world.body_frame(),
                                                slider.body_frame(), [1.0, 0.0, 0.0]))
        self._y = plant.AddJoint(PrismaticJoint("bat_y", slider.body_frame(),
                                                hand.body_frame(), [0.0, 1.0, 0.0]))
        self._turn = plant.AddJoint(RevoluteJoint("bat_turn", hand.body_frame(), pivot,
                                                  [0.0, 0.0, 1.0]))
        a, b = bat.s_min_m, bat.s_max_m
        along_x = RigidTransform(RotationMatrix.MakeYRotation(math.pi / 2),
                                 [(a + b) / 2, 0.0, 0.0])  # Drake's capsules lie along z
        self._geoms = (
            plant.RegisterCollisionGeometry(bat_body, along_x, Capsule(bat.radius_m, b - a),
                                            "bat", self._properties(rigid=True)),
            plant.RegisterCollisionGeometry(ball_body, RigidTransform(), Sphere(ball.radius_m),
                                            "ball", self._properties(rigid=False)))
        plant.Finalize()
        self._bat, self._ball, self._pivot = bat_body, ball_body, pivot
        self._finish(builder, plant, sg)
        self._discrete = not continuous
        self._set_restitution(scene.e)

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
        self._q_bat = [j.position_start() for j in (self._x, self._y, self._turn)]
        self._v_bat = [j.velocity_start() for j in (self._x, self._y, self._turn)]
        self._q_ball = self._ball.floating_positions_start()
        self._v_ball = self._ball.floating_velocities_start_in_v()
        self._query_port = plant.get_geometry_query_input_port()
        self._offset = 0.0
        self._load = None

    def _properties(self, rigid: bool, dissipation: float | None = None) -> ProximityProperties:
        """Proximity properties of one geometry: both carry 2k (in series: k), the same d and
        tau (d combines to d; tau adds up, so each carries half), no friction."""
        st = self.settings
        props = ProximityProperties()
        k = None if st.point_stiffness_npm is None else 2.0 * st.point_stiffness_npm
        AddContactMaterial(dissipation=dissipation, point_stiffness=k, friction=_NO_FRICTION,
                           properties=props)
        if st.contact_model != "point" and (st.contact_model == "hydroelastic"):
            if rigid:
                AddRigidHydroelasticProperties(st.resolution_hint_m, props)
            else:
                AddCompliantHydroelasticProperties(st.resolution_hint_m,
                                                   st.hydroelastic_modulus_pa, props)
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
                props.AddProperty("material", "relaxation_time",
                                  0.5 * st.relaxation_time_s(e))
            self.sg.AssignRole(self._sg_ctx, self._source, geom, props, RoleAssign.kReplace)

    # -- state ---------------------------------------------------------------------------------

    def _set_offset(self, offset_m: float) -> None:
        self._pivot.SetPoseInParentFrame(self._plant_ctx, RigidTransform([offset_m, 0.0, 0.0]))
        self._offset = offset_m

    def set_state(self, state: State) -> None:
        plant, pc = self.plant, self._plant_ctx
        self._ctx.SetTime(0.0)
        self._failed = False
        for joint in (self._x, self._y):
            joint.Unlock(pc)
        self._set_offset(0.0)
        q = np.zeros(plant.num_positions())
        v = np.zeros(plant.num_velocities())
        q[self._q_bat] = (state.bat_x_m, state.bat_y_m, state.bat_angle_rad)
        v[self._v_bat] = (state.bat_vx_mps, state.bat_vy_mps, state.bat_omega_radps)
        i, j = self._q_ball, self._v_ball
        q[i:i + 7] = (1.0, 0.0, 0.0, 0.0, state.ball_x_m, state.ball_y_m, 0.0)
        v[j:j + 6] = (0.0, 0.0, state.ball_omega_radps, state.ball_vx_mps, state.ball_vy_mps, 0.0)
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
        x, y, th = q[self._q_bat]
        vx, vy, w = v[self._v_bat]
        p = self._offset
        c, s = math.cos(th), math.sin(th)
        return State(ball_x_m=float(q[i + 4]), ball_y_m=float(q[i + 5]),
                     ball_vx_mps=float(v[j + 3]), ball_vy_mps=float(v[j + 4]),
                     ball_omega_radps=float(v[j + 2]), bat_x_m=float(x - p * c),
                     bat_y_m=float(y - p * s), bat_angle_rad=float(th),
                     bat_vx_mps=float(vx + w * p * s), bat_vy_mps=float(vy - w * p * c),
                     bat_omega_radps=float(w))

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
        th = self.plant.GetPositions(self._plant_ctx)[self._q_bat[2]]
        q = th + load.angle_rad
        f = ExternallyAppliedSpatialForce()
        f.body_index = self._bat.index()
        f.p_BoBq_B = np.array([load.arm_m, 0.0, 0.0])
        f.F_Bq_W = SpatialForce([0.0, 0.0, load.torque_nm],
                                [load.force_n * math.cos(q), load.force_n * math.sin(q), 0.0])
        self._force_port.FixValue(self._plant_ctx, [f])

    def set_drive(self, hands: Hands | None) -> None:
        self._load = hands
        if hands is None:
            self._apply_load()
            for joint in (self._x, self._y):
                joint.Unlock(self._plant_ctx)
            return
        if hands.pivot_from_com_m is not None:
            # The bat turns about the pivot frame: moved to the hands, with the chain's x and y
            # now those of the hands (the bat itself does not move: its angle is kept).
            angle = self.read().bat_angle_rad
            self._set_offset(hands.pivot_from_com_m)
            q = self.plant.GetPositions(self._plant_ctx)
            q[self._q_bat] = (hands.pivot_xy_m[0], hands.pivot_xy_m[1], angle)
            self.plant.SetPositions(self._plant_ctx, q)
            for joint in (self._x, self._y):
                joint.Lock(self._plant_ctx)
        self._apply_load()
