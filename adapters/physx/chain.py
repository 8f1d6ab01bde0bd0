"""PhysX's segmented bat (``adapters.segmented``), through SAPIEN 3: one PhysX articulation
(reduced coordinates, Featherstone) of capsule links, the knob segment its free root, each
child hinged to its parent by a revolute joint about z whose joint drive is the torsional
spring and damper; the ball a rigid dynamic body as in the bat adapter.

Why an articulation and not rigid bodies joined by D6 joints: the articulation keeps its
joints exactly (reduced coordinates) and its drive is an implicit spring in the joint
coordinate; a D6 joint is one more iterative constraint row beside the contact, and measured
worse (below).

The spring: SAPIEN's ``set_drive_properties(stiffness, damping, force_limit, mode)`` with
``mode="force"`` is ``PxArticulationDrive(stiffness, damping, maxForce, eFORCE)`` (SAPIEN's
``include/sapien/physx/articulation_link_component.h``); PhysX's
``include/solver/PxSolverDefs.h`` gives its stiffness in torque/rad and damping in
torque/(rad/s) for eFORCE on a rotational axis (per unit of the joint's inertia, rad/s^2/rad,
for eACCELERATION). So k_j and d_j go in unconverted, drive target 0 (straight), no force
limit. SAPIEN's own default drive mode is also "force" (read from its API stubs).

Traps, beyond those of the bat adapter (package docstring), measured with SAPIEN 3.0.3:
- A revolute joint of PhysX turns about its joint frame's x axis: both joint frames are turned
  by -90 degrees about y so that x becomes world z (a positive joint angle turns the child
  counter-clockwise about z, as ``angle_rad``).
- Articulation links and joints come with their own defaults, unlike rigid bodies (read back):
  links capped at 10 m/s and 50 rad/s (the 10 m/s cap took 40% of a bending mode's energy in
  one step at 30 m/s), damped 0.05; joints with friction 0.05, a 100 rad/s velocity cap and
  limits [0, 0]. Links get a rigid dynamic body's caps (then the settings' spin cap), no
  damping; joints no friction, no armature, free limits, the cap lifted.
- Neighbouring links never collide in PhysX; links two or more apart would where capsules
  reach past their segment (N >= 16 on R161): every segment shape gets collision groups that
  let it meet the ball only (g0 = 1, g1 = 2 on segments, g0 = 2, g1 = 1 on the ball).
- The articulation's solver iterations are its own (``set_solver_position_iterations``), set
  from the settings as the bodies' are.
- TGS does not solve a contact on an articulation in one iteration, as it does between two
  rigid bodies: with springs made negligible (k x 1e-4), N = 8, 40 m/s, e = 0.5, the ball's
  first-touch speed is 2.8 m/s off with 1 position iteration, 0.05-0.10 with 10 (SAPIEN's),
  1e-4 with 50, 1e-5 with 100, whatever dt (the same at 1 us); worst when the gap closes at
  the step's end (the harness's placement; 4e-3 to 9e-3 mid-step at 10 iterations).
- The drive is an implicit spring solved inside each TGS sub-step, so the springs act within
  the impact step: 100 iterations leave the first touch 5e-3 to 4.2e-2 m/s off at dt = 10 us,
  2e-4 at 1 us (as dt^2); PGS is 0.43 off at 10 us. The same implicit sub-steps bleed a free
  bending mode's energy by about (omega dt)^2 / iterations per step (0.7% per period for
  the lowest mode, 19% for the highest, at the reference): the energy left in bending after an
  impact is 6-38 J against the linear chain's 24-50.
- Rigid bodies joined by D6 joints with a twist drive (the alternative) keep the period as
  well (8e-5) but their impact is worse: 0.17-0.72 m/s off at the first touch at 10
  iterations, against 0.02-0.09 for the articulation: so an articulation.
- At the reference (N = 8, 40 m/s, e = 0.5) single touches land 2e-3 to 9.4e-2 m/s off, the
  tolerance being float32 rounding alone (4.8e-2): x = 0.78 and 0.80 fail by the first
  point's contact convergence. SAPIEN's 10 ms default step bends joints by 0.8 rad in the
  contact step and gains energy at every point.
"""

from __future__ import annotations

import numpy as np

from ..segmented import ChainEngine, ChainScene
from . import RECORD
from .adapter import PhysxEngine, _or, _sapien_defaults, physx, sapien, setup_body

#: Joint frames: the joint's x axis (PhysX's revolute axis) along world z.
_X_TO_Z = sapien.Pose([0.0, 0.0, 0.0], [np.sqrt(0.5), 0.0, -np.sqrt(0.5), 0.0])
#: Collision groups (g0 contact type, g1 affinity): segments meet the ball, never each other.
_SEGMENT_GROUPS = [1, 2, 0, 0]
_BALL_GROUPS = [2, 1, 0, 0]
#: Joint velocity cap lifted (PhysX's default is 100 rad/s).
_MAX_JOINT_VELOCITY = 1e6


def _planar(pose, v, w) -> tuple[float, ...]:
    """(x, y, angle about z, vx, vy, omega) of a body whose frame is at its COM."""
    p, q = pose.p, pose.q
    angle = 2.0 * np.arctan2(float(q[3]), float(q[0]))
    return (
        float(p[0]),
        float(p[1]),
        float(np.arctan2(np.sin(angle), np.cos(angle))),
        float(v[0]),
        float(v[1]),
        float(w[2]),
    )


def _as_rigid_body(link) -> None:
    """Lift a link's caps to a rigid dynamic body's (links have their own: 10 m/s and
    50 rad/s, read back); a spin cap the settings name is set afterwards, as on any body."""
    body = physx.PhysxRigidDynamicComponent()
    link.max_linear_velocity = body.max_linear_velocity
    link.max_angular_velocity = body.max_angular_velocity


class PhysxChain(ChainEngine):
    """PhysX's segmented bat: an articulation with drive springs, at the bat adapter's
    settings and restitution mapping (mean of two materials, both set to e)."""

    record = RECORD

    #: The bat adapter's test: a contact point touching or carrying an impulse.
    in_contact = PhysxEngine.in_contact

    def __init__(self, settings) -> None:
        super().__init__(settings)
        self._scene = None

    def close(self) -> None:
        if self._scene is not None:
            self._scene.clear()
            self._scene = self._system = None

    def build(self, scene: ChainScene) -> None:
        st = self.settings
        self.close()
        with _sapien_defaults(st):
            self._system = physx.PhysxCpuSystem()
            self._scene = sapien.Scene([self._system])
            self._system.timestep = st.dt_s
            self._bat_material = physx.PhysxMaterial(0.0, 0.0, scene.e)
            self._ball_material = physx.PhysxMaterial(0.0, 0.0, scene.e)  # PhysX: the mean
            self._links = self._build_links(scene)
            sphere = physx.PhysxCollisionShapeSphere(scene.ball.radius_m, self._ball_material)
            sphere.set_collision_groups(_BALL_GROUPS)
            self._ball = self._ball_body(sphere, scene.ball.mass_kg, scene.ball.inertia_kgm2)
        self._articulation = self._links[0].articulation
        self._configure_articulation()

    def _build_links(self, scene: ChainScene) -> list:
        """One link per segment, framed at its COM; joint i at x = i l from the knob."""
        chain = scene.chain
        ell, r = chain.segment_length_m, chain.bat.radius_m
        links, entities = [], []
        for i, (m, c, inertia) in enumerate(
            zip(chain.masses_kg, chain.coms_m, chain.inertias_kgm2, strict=True)
        ):
            capsule = physx.PhysxCollisionShapeCapsule(r, 0.5 * ell, self._bat_material)
            capsule.set_local_pose(sapien.Pose([(i + 0.5) * ell - c, 0.0, 0.0]))
            capsule.set_collision_groups(_SEGMENT_GROUPS)
            link = physx.PhysxArticulationLinkComponent(links[-1] if links else None)
            _as_rigid_body(link)
            axial = min(0.5 * m * r * r, 2.0 * inertia)  # a valid tensor (adapters.segmented)
            setup_body(link, capsule, m, (axial, inertia, inertia), self.settings)
            if i > 0:
                self._hinge(
                    link.joint,
                    i * ell - chain.coms_m[i - 1],
                    i * ell - c,
                    chain.stiffnesses_nmprad[i - 1],
                    chain.dampings_nmsprad[i - 1],
                )
            entity = sapien.Entity()
            entity.add_component(link)
            entity.pose = sapien.Pose([c - chain.bat.com_from_knob_m, 0.0, 0.0])
            links.append(link)
            entities.append(entity)
        for entity in entities:
            self._scene.add_entity(entity)
        return links

    @staticmethod
    def _hinge(joint, in_parent: float, in_child: float, k: float, d: float) -> None:
        """A free revolute joint about z; its force-mode drive is the spring k, damper d."""
        joint.type = "revolute"
        joint.pose_in_parent = sapien.Pose([in_parent, 0.0, 0.0], _X_TO_Z.q)
        joint.pose_in_child = sapien.Pose([in_child, 0.0, 0.0], _X_TO_Z.q)
        joint.limit = np.array([[-np.inf, np.inf]])
        joint.friction = 0.0
        joint.armature = np.zeros(1)
        joint.max_velocity = _MAX_JOINT_VELOCITY
        joint.set_drive_properties(k, d, mode="force")  # N m/rad, N m s/rad: PxSolverDefs.h
        joint.set_drive_target(0.0)
        joint.set_drive_velocity_target(0.0)

    def _ball_body(self, shape, mass: float, inertia: float):
        body = setup_body(
            physx.PhysxRigidDynamicComponent(), shape, mass, (inertia,) * 3, self.settings
        )
        entity = sapien.Entity()
        entity.add_component(body)
        entity.pose = sapien.Pose([0.0, 10.0, 0.0])
        self._scene.add_entity(entity)
        return body

    def _configure_articulation(self) -> None:
        """Solver iterations and sleeping as the bodies get them (articulations keep their
        own copies)."""
        st, art = self.settings, self._articulation
        body = physx.get_body_config()
        art.set_solver_position_iterations(
            _or(st.position_iterations, body.solver_position_iterations)
        )
        art.set_solver_velocity_iterations(
            _or(st.velocity_iterations, body.solver_velocity_iterations)
        )
        art.set_sleep_threshold(_or(st.sleep_threshold, body.sleep_threshold))

    def mass_properties(self) -> np.ndarray:
        rows = []
        for i, link in enumerate(self._links):
            shape = link.collision_shapes[0]
            ell = 2.0 * float(shape.half_length)  # the capsule's cylinder is the segment
            start = float(shape.local_pose.p[0]) - 0.5 * ell  # knob end of segment i
            com = float(link.cmass_local_pose.p[0]) - start + i * ell
            rows.append((link.mass, com, float(link.inertia[2])))
        return np.array(rows, dtype=float)

    def set_state(self, ball: np.ndarray, segments: np.ndarray) -> None:
        art = self._articulation
        x, y, a, vx, vy, w = segments[0]
        art.set_root_pose(sapien.Pose([x, y, 0.0], [np.cos(a / 2), 0.0, 0.0, np.sin(a / 2)]))
        art.set_qpos(np.diff(segments[:, 2]).astype(np.float32))
        art.set_root_linear_velocity([vx, vy, 0.0])  # the root link's COM: its frame's origin
        art.set_root_angular_velocity([0.0, 0.0, w])
        art.set_qvel(np.diff(segments[:, 5]).astype(np.float32))
        art.set_qf(np.zeros(len(self._links) - 1, dtype=np.float32))
        self._ball.entity.pose = sapien.Pose([ball[0], ball[1], 0.0])
        self._ball.linear_velocity = [ball[2], ball[3], 0.0]
        self._ball.angular_velocity = [0.0, 0.0, 0.0]

    def step(self) -> None:
        self._system.step()

    def read(self) -> tuple[np.ndarray, np.ndarray]:
        segs = np.array(
            [
                _planar(link.entity.pose, link.linear_velocity, link.angular_velocity)
                for link in self._links
            ]
        )
        b = self._ball
        p, v = b.entity.pose.p, b.linear_velocity
        return np.array([p[0], p[1], v[0], v[1]], dtype=float), segs
