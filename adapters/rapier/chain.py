"""Rapier's segmented bat (``adapters.segmented``): N dynamic bodies hinged about z, each
hinge's angular motor the torsional spring; the hinges the kind ``settings.hinge`` names:
revolute impulse joints ("impulse", the default profile's) or one multibody whose links are
revolute joints ("multibody", the reference profile's; segment 0 its free root).

The world, its integration parameters and the ball are the bat adapter's own: ``RapierEngine``
builds its one-bat scene and the bat body is removed, the segments taking its place (each a
dynamic body with its COM at its origin, its mass properties set as additional ones, a massless
capsule collider along x, restitution e like the ball's: the mean of e and e is e). Segments
collide with the ball only (collision groups: segments in group 1 filtering group 2, the ball
the other way round; the joints' ``contacts_enabled`` off as well).

The spring: the joint's motor, position target 0, ``stiffness`` k_j and ``damping`` d_j in
Rapier's FORCE-based motor model. Rapier's default motor model is acceleration-based: its
(k, d) become an impulse per unit of the row's effective inverse inertia (cfm_coeff scaled by
J M^-1 J^T), so the torque per radian would be k times the effective inertia. ForceBased adds
cfm_gain = 1 / (dt^2 k + dt d) to the row's J M^-1 J^T with erp_inv_dt = k / (dt k + d)
(``MotorModel::combine_coefficients``, src/dynamics/joint/motor_model.rs;
``JointConstraintHelper::motor_angular``/``finalize_constraints``,
src/dynamics/solver/joint_constraint/joint_constraint_helper.rs; multibody links:
``unit_joint_motor_constraint``, src/dynamics/joint/multibody_joint/unit_multibody_joint.rs;
rapier 0.35.2): the impulse the row converges to is -dt (k (theta + dt omega') + d omega'), a
backward-Euler spring-damper whose torque per radian is k itself: k and d go in unconverted.
Rapier's inv(0) is 0, so a motor with k = d = 0 would lock its joint rigidly: none is made.

Traps (measured with rapier3d 0.36.1, the r161 chain, v0 = 40 m/s, e = 0.5, dt = 10 us):
- The end-of-step restitution pass solves the contacts alone, not the joints: on impulse
  joints the bounce sees the hit segment by itself (one step at 0.72 m: ball -10.25 m/s, the
  chain's Newton answer -7.39, the segment alone's -17.29; 2 to 3 m/s off at N = 8). A
  multibody contact's rows carry the whole chain's inverse mass, so its bounce is the chain's.
- The motors are implicit and solved in the same PGS passes as the contact, so the touch sees
  M + dt^2 K, not the free joints of Newton's impact: converged, v1 = -1.90722 m/s at 0.66 m
  where M + dt^2 K predicts -1.90724 and the reference is -2.19599 (the reference profile's
  single relax sweep gets -2.01). v1 is off by O((omega_max dt)^2): 0.18 to 0.29 m/s at N = 8
  (omega_max dt = 0.35), 2e-2 at N = 4, 4e-4 at dt = 1 us.
- One Gauss-Seidel sweep is not the implicit step when omega_max dt > 1: a free chain gains
  energy (N = 24: 8 %, N = 40: 50 % in 100 steps) and N = 64 blows up even at 200 PGS
  iterations; 50 iterations at N = 32 give backward Euler's decay (-12 % in 1000 steps).
- A multibody link's rigid body holds the velocities of the step before (Rapier writes them
  before integrating): ``read`` takes the multibody's generalized velocity instead (matches
  ``body_jacobian`` to 4e-7 relative). Multibody dofs are damped (0.1) by default: zeroed.
"""

from __future__ import annotations

import numpy as np

from analytic import checks

from ..interface import Scene
from ..loading import import_engine
from ..segmented import ChainEngine, ChainScene
from . import RECORD
from .adapter import RapierEngine

rapier = import_engine(RECORD)


def _izz(mp) -> float:
    """I_zz of the body-frame tensor R diag(I) R^T, R the principal frame."""
    frame = mp.principal_inertia_local_frame.to_matrix().reshape(3, 3)
    return float(sum(frame[2, k] ** 2 * mp.principal_inertia[k] for k in range(3)))


class RapierChain(ChainEngine):
    """Rapier's segmented bat, at the bat adapter's settings and contact mapping; the joints
    the kind ``settings.hinge`` names (impulse joints or one multibody)."""

    record = RECORD

    def build(self, scene: ChainScene) -> None:
        st, chain = self.settings, scene.chain
        rig = RapierEngine(st)  # the world, its parameters, the ball and its restitution
        rig.build(Scene(bat=chain.bat, ball=scene.ball, e=scene.e))
        w = self._world = rig._world
        w.remove_body(rig._bat)  # the rigid bat's place goes to the segments
        self._rig, self._ball, self._ball_col = rig, rig._ball, rig._ball_col
        w.colliders[self._ball_col].collision_groups = rapier.InteractionGroups(
            rapier.Group.GROUP_2, rapier.Group.GROUP_1
        )
        ell, r = chain.segment_length_m, chain.bat.radius_m
        self._segs, self._cols = [], []
        for i, (m, c, J) in enumerate(
            zip(chain.masses_kg, chain.coms_m, chain.inertias_kgm2, strict=True)
        ):
            mprops = rapier.MassProperties(
                local_com=(0.0, 0.0, 0.0),
                mass=m,
                principal_inertia=(min(0.5 * m * r * r, 2.0 * J), J, J),
            )
            capsule = rapier.Collider.capsule_from_endpoints(
                (i * ell - c, 0.0, 0.0), ((i + 1) * ell - c, 0.0, 0.0), r
            ).collision_groups(rapier.InteractionGroups(rapier.Group.GROUP_1, rapier.Group.GROUP_2))
            handle = rig._add_body(mprops, capsule, ccd=st.ccd_bodies == "both")
            self._segs.append(handle)
            self._cols.append(w.rigid_bodies[handle].colliders[0])
            w.colliders[self._cols[-1]].restitution = scene.e  # as set_body_restitution
        self._anchors = [
            ((j + 1) * ell - chain.coms_m[j], (j + 1) * ell - chain.coms_m[j + 1])
            for j in range(chain.segments - 1)
        ]
        self._joints = [
            self._join(j, k, d)
            for j, (k, d) in enumerate(
                zip(chain.stiffnesses_nmprad, chain.dampings_nmsprad, strict=True)
            )
        ]
        if st.hinge == "multibody":
            links = self._multibody()
            links.set_damping([0.0] * links.ndofs)  # multibody links are damped (0.1) by default

    def _join(self, j: int, k: float, d: float):
        """Segments j and j+1 hinged about z at their common end, the motor their spring."""
        st, w = self.settings, self._world
        a1, a2 = self._anchors[j]
        joint = (
            rapier.RevoluteJoint.builder((0.0, 0.0, 1.0))
            .local_anchor1((a1, 0.0, 0.0))
            .local_anchor2((a2, 0.0, 0.0))
            .contacts_enabled(False)
            .softness(rapier.SpringCoefficients(st.hinge_frequency_hz, st.hinge_damping_ratio))
        )
        if k > 0.0 or d > 0.0:  # k = d = 0 would lock the joint (module docstring)
            joint = joint.motor_position(
                0.0, k, d
            ).motor_model(  # target 0: no torque when straight
                rapier.MotorModel.FORCE_BASED
            )  # torque k theta
        joint = joint.build()
        joints = w.impulse_joints if st.hinge == "impulse" else w.multibody_joints
        return joints.insert(self._segs[j], self._segs[j + 1], joint)

    def _multibody(self):
        return self._world.multibody_joints.multibody(self._joints[0])

    def mass_properties(self) -> np.ndarray:
        w = self._world
        rows, knob = [], 0.0  # each segment's knob end, from the knob (capsule lengths summed)
        for h, col in zip(self._segs, self._cols, strict=True):
            mp = w.rigid_bodies[h].mass_properties
            capsule = w.colliders[col].shape.as_capsule()  # its axis, in the body's frame
            rows.append((mp.mass, knob + mp.local_com.x - capsule.a.x, _izz(mp)))
            knob += capsule.b.x - capsule.a.x
        return np.array(rows, dtype=float)

    def set_state(self, ball: np.ndarray, segments: np.ndarray) -> None:
        checks.integer("segments", len(segments), len(self._segs), len(self._segs))
        w = self._world
        self._rig._failed = False
        for h, (x, y, a, vx, vy, om) in zip(self._segs, segments, strict=True):
            body = w.rigid_bodies[h]
            body.translation = (x, y, 0.0)
            body.rotation = rapier.Rotation3.from_axis_angle((0.0, 0.0, 1.0), a)
            body.linvel = (vx, vy, 0.0)
            body.angvel = (0.0, 0.0, om)
        if self.settings.hinge == "multibody":
            self._set_links(segments)
        b = w.rigid_bodies[self._ball]
        b.translation = (ball[0], ball[1], 0.0)
        b.rotation = rapier.Rotation3.identity()
        b.linvel = (ball[2], ball[3], 0.0)
        b.angvel = (0.0, 0.0, 0.0)
        # Re-inserting the ball's collider drops its contact manifolds and their warm starts
        # (the bat adapter's way); joints are not warm-started (warmstart_joints off).
        self._ball_col = w.add_collider(w.remove_collider(self._ball_col), self._ball)

    def _set_links(self, segments: np.ndarray) -> None:
        """The multibody's own state: the root's pose read from segment 0's body, each
        joint's angle and rate the difference of its segments'."""
        links = self._multibody()
        q = np.asarray(links.generalized_position())
        bends = np.diff(segments[:, 2])
        links.apply_displacements([0.0] * 6 + list(bends - q[6:]))
        links.forward_kinematics(self._world.rigid_bodies, True)
        _, _, _, vx, vy, om = segments[0]
        links.set_generalized_velocity([vx, vy, 0.0, 0.0, 0.0, om, *np.diff(segments[:, 5])])

    def step(self) -> None:
        self._rig.step()  # no hands: a plain world step and the quarantine check

    def read(self) -> tuple[np.ndarray, np.ndarray]:
        bodies = self._world.rigid_bodies
        rows = []
        for h in self._segs:
            body = bodies[h]
            x, y, _ = body.translation.to_tuple()
            vx, vy, _ = body.linvel.to_tuple()
            rot = body.rotation
            rows.append((x, y, 2.0 * np.arctan2(rot.k, rot.w), vx, vy, body.angvel.z))
        segs = np.array(rows)
        if self.settings.hinge == "multibody":
            self._link_velocities(segs)
        b = bodies[self._ball]
        bx, by, _ = b.translation.to_tuple()
        bvx, bvy, _ = b.linvel.to_tuple()
        return np.array([bx, by, bvx, bvy]), segs

    def _link_velocities(self, segs: np.ndarray) -> None:
        """Overwrite the links' velocities with the multibody's (their rigid bodies hold the
        step before's): the root's, then each joint's rate added across its hinge."""
        qd = self._multibody().generalized_velocity()
        segs[0, 3:6] = (qd[0], qd[1], qd[5])
        for j, (a1, _) in enumerate(self._anchors):
            x, y, a, vx, vy, om = segs[j]
            px, py = x + a1 * np.cos(a), y + a1 * np.sin(a)  # the hinge, in the world
            om2 = om + qd[6 + j]
            rx, ry = px - x, py - y
            sx, sy = segs[j + 1, 0] - px, segs[j + 1, 1] - py
            segs[j + 1, 3:6] = (vx - om * ry - om2 * sy, vy + om * rx + om2 * sx, om2)

    def in_contact(self) -> bool:
        # The bat adapter's test: a speculative contact (apart, no impulse) is not a touch.
        narrow = self._world.narrow_phase
        for col in self._cols:
            pair = narrow.contact_pair(col, self._ball_col)
            if pair is not None and any(
                pt.impulse > 0.0 or pt.dist < 0.0 for m in pair.manifolds for pt in m.points
            ):
                return True
        return False

    def failed(self) -> bool:
        return self._rig.failed()
