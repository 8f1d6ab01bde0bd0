"""Drake's segmented bat (``adapters.segmented``): a MultibodyPlant tree of capsules, the root
segment on a ``PlanarJoint`` to the world (x, y and the yaw about z: the single-bat adapter's
prismatic/revolute chain less its z, tilt and roll, which stay exactly 0 in a planar impact),
each child on a ``RevoluteJoint`` about z whose frames sit at the child's knob end (the
parent's ``FixedOffsetFrame`` at its far end), with the joint's own damping d (N m s/rad,
tau = -d w) and a ``RevoluteSpring`` force element. Its stiffness IS the torque per radian
(``drake/multibody/tree/revolute_spring.h``: "tau = -k (theta - theta0)", k in N m/rad), so
k_j is passed unchanged, theta0 = 0. The ball is a free body, as in the bat adapter. Segments
are excluded from colliding with each other by one ``CollisionFilterDeclaration``
(``ExcludeWithin`` their geometries): Drake filters only bodies joined by a joint by itself,
and from N = 16 on a capsule overlaps the one two along.

Contact: each geometry carries the single-bat adapter's proximity properties (its
``_properties``: 2k each, the Hunt-Crossley d for e at ``restitution_speed_mps``, SAP's half
tau), so the law is the settings' ``contact_law(e)`` and the harness judges against the
compliant reference. The reference profile is the continuous plant under RK3 with error
control: spring, damper and contact are integrated alike, to ``accuracy``.

Measured with Drake 1.51.1 (R161, N = 8, 40 m/s, e = 0.5):
- A ``RevoluteSpring`` is a ForceElement, evaluated at the step's start: explicit in every
  discrete approximation. Each (lagged, similar, SAP, TAMSI) is stable at 50 us (omega_max
  dt = 1.7) and diverges at 100 us (3.5, past semi-implicit Euler's 2), the default 1 ms
  included; SAP with the spring as a ``JointActuator``'s PD gain instead is stable at 1 ms
  (implicit; not used: PD gains exist only for a discrete plant, not the continuous reference).
  The joint damping is implicit in the SAP family (lagged, similar, SAP: d = 50 N m s/rad at
  1 ms, d dt / J ~ 1e3, decays 7x a step) and explicit in TAMSI (diverges there).
  A diverging update is refused (``_advance``): Drake would abort the process on its NaN.
- The reference (continuous RK3, accuracy 1e-6) takes ~30 steps per 10 us reading throughout
  (the error control follows the chain's fastest mode, 34559 rad/s), ~0.6 ms each: ~15 s an
  impact; v1 agrees to 1e-6 m/s with accuracy 1e-4 (6 s).
- Against the linear chain the engine's error scales as v0^2 (2e-6, 2e-4, 1e-2 m/s at 0.4, 4
  and 40 m/s, mid-segment): the geometric nonlinearity (tilted normals, cos of the bends) of an
  exact multibody model, 1e-3 of v1 at 40 m/s. Near a joint a 40 m/s ball sinks ~9 mm into the
  k = 1e6 N/m contact and overlaps the neighbour's hemispherical cap too (up to 3.4 mm at
  x = 0.5 m, 25 mm from the joint): two point contacts, the second's normal tilted, v1 0.9 m/s
  off the reference's single contact (any point within sqrt(2 (R + r) depth) ~ 34 mm of a joint).
"""

from __future__ import annotations

import math

import numpy as np

from ..loading import import_engine
from ..segmented import ChainEngine, ChainScene
from . import RECORD, dissipation_spm
from .adapter import DrakeEngine

pydrake = import_engine(RECORD)
from pydrake.geometry import Capsule, CollisionFilterDeclaration, Sphere  # noqa: E402
from pydrake.math import RigidTransform, RotationMatrix  # noqa: E402
from pydrake.multibody.plant import (  # noqa: E402
    AddMultibodyPlant,
    CoulombFriction,
    MultibodyPlantConfig,
)
from pydrake.multibody.tree import (  # noqa: E402
    FixedOffsetFrame,
    PlanarJoint,
    RevoluteJoint,
    RevoluteSpring,
    RotationalInertia,
    SpatialInertia,
)
from pydrake.systems.analysis import ResetIntegratorFromFlags, Simulator  # noqa: E402
from pydrake.systems.framework import DiagramBuilder  # noqa: E402

Z_AXIS = np.array([0.0, 0.0, 1.0])


class DrakeChain(ChainEngine):
    """Drake's segmented bat, at the bat adapter's settings and contact mapping."""

    record = RECORD

    # Borrowed from the bat adapter: they read only ``settings``, ``_friction``, ``_failed``,
    # ``_load``, ``_discrete``, ``plant``, ``_plant_ctx``, ``_ctx``, ``_simulator`` and
    # ``_query_port``, all of which this class holds with the same meaning.
    _properties = DrakeEngine._properties
    step = DrakeEngine.step  # which calls ``_advance`` and marks a RuntimeError as failed
    failed = DrakeEngine.failed
    in_contact = DrakeEngine.in_contact

    def __init__(self, settings) -> None:
        super().__init__(settings)
        self._failed = False
        self._load = None  # no hands on a chain
        mu_bat, mu_ball = RECORD.can.friction_rule.per_body(0.0)
        self._friction = (CoulombFriction(mu_bat, mu_bat), CoulombFriction(mu_ball, mu_ball))

    # -- building ------------------------------------------------------------------------------

    def build(self, scene: ChainScene) -> None:
        st = self.settings
        self._discrete = st.solver != "continuous"
        config = MultibodyPlantConfig(
            time_step=st.dt_s if self._discrete else 0.0,
            contact_model=st.contact_model,
            use_sampled_output_ports=False,
        )
        if self._discrete:
            config.discrete_contact_approximation = st.solver
        if st.sap_near_rigid_threshold is not None:
            config.sap_near_rigid_threshold = st.sap_near_rigid_threshold
        builder = DiagramBuilder()
        plant, sg = AddMultibodyPlant(config, builder)
        plant.mutable_gravity_field().set_gravity_vector([0.0, 0.0, 0.0])
        self.plant, self.n = plant, scene.chain.segments
        self._ell = scene.chain.segment_length_m
        self._segs = self._add_segments(scene)
        self._add_joints(scene)
        ib = scene.ball.inertia_kgm2
        self._ball = plant.AddRigidBody(
            "ball",
            SpatialInertia.MakeFromCentralInertia(
                scene.ball.mass_kg, np.zeros(3), RotationalInertia(ib, ib, ib)
            ),
        )
        plant.RegisterCollisionGeometry(
            self._ball,
            RigidTransform(),
            Sphere(scene.ball.radius_m),
            "ball",
            self._contact_properties(False, scene.e),
        )
        plant.Finalize()
        sg.collision_filter_manager().Apply(
            CollisionFilterDeclaration().ExcludeWithin(
                plant.CollectRegisteredGeometries(self._segs)
            )
        )
        self._finish(builder, plant)

    def _add_segments(self, scene: ChainScene) -> list:
        """N rigid bodies, each framed at its segment's knob end, with its capsule."""
        chain, plant = scene.chain, self.plant
        ell, r = self._ell, chain.bat.radius_m
        along_x = RigidTransform(RotationMatrix.MakeYRotation(math.pi / 2), [ell / 2, 0.0, 0.0])
        bodies = []
        for i, (m, c, J) in enumerate(
            zip(chain.masses_kg, chain.coms_m, chain.inertias_kgm2, strict=True)
        ):
            # m r^2 / 2, but from N = 32 on a handle slice's own J (its radius well under the
            # capsule's) is below m r^2 / 4: the moments would break the triangle inequality
            # (Ixx <= Iyy + Izz) and Drake refuses the body ("Spatial inertia fails
            # SpatialInertia::IsPhysicallyValid()"). No planar impact turns a segment about its
            # axis: the largest valid value, 2 J, changes nothing judged.
            axial = min(0.5 * m * r * r, 2.0 * J)
            inertia = SpatialInertia.MakeFromCentralInertia(
                m, np.array([c - i * ell, 0.0, 0.0]), RotationalInertia(axial, J, J)
            )
            body = plant.AddRigidBody(f"s{i}", inertia)
            plant.RegisterCollisionGeometry(
                body, along_x, Capsule(r, ell), f"s{i}", self._contact_properties(True, scene.e)
            )
            bodies.append(body)
        return bodies

    def _add_joints(self, scene: ChainScene) -> None:
        """The root's planar joint to the world; a revolute joint about z with its spring and
        damper between each pair of neighbours, at their common end."""
        chain, plant = scene.chain, self.plant
        self._root = plant.AddJoint(
            PlanarJoint("root", plant.world_frame(), self._segs[0].body_frame())
        )
        self._hinges = []
        for j, (k, d) in enumerate(
            zip(chain.stiffnesses_nmprad, chain.dampings_nmsprad, strict=True)
        ):
            end = plant.AddFrame(
                FixedOffsetFrame(
                    f"end{j}", self._segs[j].body_frame(), RigidTransform([self._ell, 0.0, 0.0])
                )
            )
            hinge = plant.AddJoint(
                RevoluteJoint(f"j{j + 1}", end, self._segs[j + 1].body_frame(), Z_AXIS, d)
            )
            plant.AddForceElement(RevoluteSpring(hinge, 0.0, k))  # tau = -k theta, N m/rad
            self._hinges.append(hinge)

    def _contact_properties(self, rigid: bool, e: float):
        """The bat adapter's proximity properties for e (its ``_properties`` and, for SAP,
        half the combined relaxation time, as its ``_set_restitution`` adds it)."""
        st = self.settings
        props = self._properties(rigid, dissipation=dissipation_spm(e, st.restitution_speed_mps))
        if st.solver == "sap":
            props.AddProperty("material", "relaxation_time", 0.5 * st.relaxation_time_s(e))
        return props

    def _finish(self, builder: DiagramBuilder, plant) -> None:
        """Build the diagram and its simulator; keep the contexts and ports used."""
        self.diagram = builder.Build()
        self._simulator = Simulator(self.diagram)
        self._ctx = self._simulator.get_mutable_context()
        self._plant_ctx = plant.GetMyMutableContextFromRoot(self._ctx)
        plant.get_applied_spatial_force_input_port().FixValue(self._plant_ctx, [])
        self._query_port = plant.get_geometry_query_input_port()
        self._q_root, self._v_root = self._root.position_start(), self._root.velocity_start()
        self._q_hinge = [h.position_start() for h in self._hinges]
        self._v_hinge = [h.velocity_start() for h in self._hinges]
        self._q_ball = self._ball.floating_positions_start()
        self._v_ball = self._ball.floating_velocities_start_in_v()

    def mass_properties(self) -> np.ndarray:
        ctx = self.plant.CreateDefaultContext()
        rows = []
        for i, body in enumerate(self._segs):
            M = body.CalcSpatialInertiaInBodyFrame(ctx)  # about the body's origin, its knob end
            com = M.get_com()
            central = M.Shift(com).CalcRotationalInertia()  # about the segment's COM
            rows.append((M.get_mass(), com[0] + i * self._ell, central.get_moments()[2]))
        return np.array(rows, dtype=float)

    # -- state ---------------------------------------------------------------------------------

    def set_state(self, ball: np.ndarray, segments: np.ndarray) -> None:
        plant, pc = self.plant, self._plant_ctx
        self._ctx.SetTime(0.0)
        self._failed = False
        off = self._segs[0].default_com()[0]  # the root's COM from its frame (its knob end)
        x, y, a, vx, vy, w = segments[0]
        c, s = math.cos(a), math.sin(a)
        q = np.zeros(plant.num_positions())
        v = np.zeros(plant.num_velocities())
        q[self._q_root : self._q_root + 3] = (x - c * off, y - s * off, a)
        v[self._v_root : self._v_root + 3] = (vx + w * s * off, vy - w * c * off, w)
        q[self._q_hinge] = np.diff(segments[:, 2])
        v[self._v_hinge] = np.diff(segments[:, 5])
        # the ball's free joint: quaternion (w, x, y, z) then position; its velocities are the
        # spatial velocity in the world frame, angular first
        i, j = self._q_ball, self._v_ball
        q[i : i + 7] = (1.0, 0.0, 0.0, 0.0, ball[0], ball[1], 0.0)
        v[j : j + 6] = (0.0, 0.0, 0.0, ball[2], ball[3], 0.0)
        plant.SetPositions(pc, q)
        plant.SetVelocities(pc, v)
        if not self._discrete:
            # a fresh integrator: the last impact's step-size guess would otherwise carry over
            integ = ResetIntegratorFromFlags(self._simulator, "runge_kutta3", self.settings.dt_s)
            integ.set_target_accuracy(self.settings.accuracy)
            integ.set_maximum_step_size(self.settings.dt_s)
            self._simulator.Initialize()

    def _advance(self) -> None:
        """The bat adapter's step, but a discrete update that is not finite is refused: an
        explicit spring past its stability limit overflows, and Drake then aborts the process
        (``MakeZRotation``: 'isfinite(theta)' failed) on the next pose it computes."""
        if not self._discrete:
            DrakeEngine._advance(self)
            return
        pc = self._plant_ctx
        update = self.plant.EvalUniquePeriodicDiscreteUpdate(pc)
        if not np.all(np.isfinite(update.value())):
            raise RuntimeError("the discrete update diverged")
        pc.get_mutable_discrete_state().SetFrom(update)
        self._ctx.SetTime(self._ctx.get_time() + self.settings.dt_s)

    def read(self) -> tuple[np.ndarray, np.ndarray]:
        if self._failed:
            return np.full(4, math.nan), np.full((self.n, 6), math.nan)
        plant, pc = self.plant, self._plant_ctx
        rows = []
        for body in self._segs:
            X = body.EvalPoseInWorld(pc)
            V = body.EvalSpatialVelocityInWorld(pc)  # of the body's origin, world frame
            R = X.rotation().matrix()
            r = R @ body.default_com()
            p, w = X.translation() + r, V.rotational()
            v = V.translational() + np.cross(w, r)
            rows.append((p[0], p[1], math.atan2(R[1, 0], R[0, 0]), v[0], v[1], w[2]))
        q, v = plant.GetPositions(pc), plant.GetVelocities(pc)
        i, j = self._q_ball, self._v_ball
        ball = np.array([q[i + 4], q[i + 5], v[j + 3], v[j + 4]])
        return ball, np.array(rows, dtype=float)
