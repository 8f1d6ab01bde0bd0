"""Newton's segmented bat (``adapters.segmented``), one world: N links in one articulation, the
knob segment on a free joint, each next one on a revolute joint about z at their common end;
capsules (``add_shape_capsule``, laid as the bat adapter lays its own) and the ball as the bat
adapter makes them (its shape config: e as its solver takes it). Segments never collide with
each other (neighbours filtered by the joints' ``collision_filter_parent``, the rest by filter
pairs); body origins at the COMs, inertias locked.

The spring, by solver (Newton 1.8.0, read in its source):

- ``xpbd`` (the profiles'): SolverXPBD ignores ``joint_stiffness``; its only joint spring is
  the drive, ``joint_target_ke``/``_kd`` with ``target_q`` 0, solved as a position constraint
  (``solve_body_joints``, ``compute_angular_correction`` in ``solvers/xpbd/kernels.py``) of
  compliance 1/ke, its multiplier restarted at 0 in every iteration (no XPBD lambda: the
  stiffness grows with the iteration count, rigid as it tends to infinity), each correction
  scaled by ``joint_angular_relaxation`` (0.4). A revolute joint's angle about z is a swing
  of the swing-twist split about x: below 0.02 rad (sin^2(a/2) < 1e-4) the constraint is
  C = sin(a/2) with gradient 1/2, above it C = a with gradient 1: the torque per radian is
  ke/4 below 0.02 rad, ke above (bends here are milliradians). One joint with angular inverse
  inertia w (1/J_i + 1/J_i+1) then takes, over n iterations of relaxation r, the impulse
  (1 - f^n) a_pred / (w dt), f = 1 - r a/(1 + a), a = (ke/4) w dt^2: ``xpbd_gains`` picks ke
  so that this is implicit Euler's k dt a_end, a torque of k per radian of the step's final
  angle (to first order in k w dt^2: ke = 4 k / (n r)); kd by the same ratio (first order).
- the others: the joint's passive ``stiffness`` and ``damping``, as given (N m/rad, N m s/rad:
  SemiImplicit and Featherstone add -k q - c q' to the joint force, SolverMuJoCo writes them
  into MuJoCo's ``jnt_stiffness``, ``dof_damping``).

Traps (measured with newton 1.8.0, warp-lang 1.19.0 on the CPU, R161 chain, N = 8, dt 1e-5):
- XPBD's joint position constraint scales a correction's linear part by
  ``joint_linear_relaxation`` (0.7) and its angular part by ``joint_angular_relaxation`` (0.4)
  (``solve_body_joints``): a transverse anchor correction is no force at the anchor. It
  changes the chain's angular momentum (free lowest mode at 1 m/s: 8.4e-4 kg m^2/s in 150
  steps; 1.9e-8 with both relaxations 0.4) and stiffens the springs: the lowest mode's period
  is 0.787 T_1 (0.824 at dt 3e-6); with both at 0.4 it is 1.012 T_1 (1.001 at 3e-6), the
  drive conversion's O(k w dt^2) remainder. The adapter keeps Newton's relaxations.
- XPBD's restitution pass solves each contact with its two bodies' own effective mass
  (``build_restitution_manifolds``), after the position iterations: the struck segment
  bounces as if free, the joints drag the rest along over the next steps and the ball
  touches again. First touch at x = 0.66 m: ball vy -7.49 m/s (the chain through rigid
  joints: -2.20; the segment alone: -11.00); 20 iterations -4.33, 200 at relaxation 1 -4.84.
- The drive cannot reach k once k w dt^2 > (1 - r)^-n - 1 (1.78: every joint at N >= 32 at
  dt 1e-5, every joint at the cradle's 1/600 s): ``xpbd_gains`` raises.
- SemiImplicit holds joints by explicit penalty attachments (``joint_attach_ke`` 1e4,
  ``_kd`` 100): the lowest mode dies in about a period (4e-5 to 1e-6 rad), no period
  measured, joint gaps of 5 mm. MuJoCo and Featherstone keep T_1 to 8e-6 relative.
- ``finalize`` "corrects" inertias that break the triangle inequality: from N = 32 a short
  segment's axial 0.5 m r^2 exceeds 2 J and Newton raised J 8.8 times (N = 64); the adapter
  skips that validation (the links turn about z only).
- A step costs 22 Warp launches (14 ms on a loaded CPU, 3/4 of it in ``wp.launch``).
"""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np

from ..segmented import ChainEngine, ChainScene
from . import RECORD, NewtonSettings
from . import scene as sc

newton, wp = sc.newton, sc.wp


def xpbd_gains(
    k: float, c: float, w: float, dt: float, iterations: int, relaxation: float
) -> tuple[float, float]:
    """(target_ke, target_kd) of XPBD's revolute drive giving a torque of k N m/rad (c N m s/rad)
    on a joint of angular inverse inertia w (1/(kg m^2)), small bends (module docstring)."""
    if k == 0.0:
        return 0.0, 4.0 * c / (iterations * relaxation)
    a_k = k * w * dt * dt
    one_less_f = 1.0 - (1.0 + a_k) ** (-1.0 / iterations)
    if one_less_f >= relaxation:  # even a rigid drive (ke infinite) takes less per step
        bound = (1.0 - relaxation) ** -iterations - 1.0
        raise ValueError(
            f"XPBD's joint drive cannot reach k = {k:.4g} N m/rad: k w dt^2 = "
            f"{a_k:.3g} > {bound:.3g} at {iterations} iterations, relaxation "
            f"{relaxation}, dt = {dt:.3g} s"
        )
    ke = 4.0 * one_less_f / (relaxation - one_less_f) / (w * dt * dt)
    return ke, c * ke / k


def chain_builder(scene: ChainScene, st: NewtonSettings):
    """The links (bodies 0..N-1, knob first), the ball (body N); joint springs left at 0 (set
    by ``NewtonChain.build`` once the solver is known)."""
    chain, ball = scene.chain, scene.ball
    ell, r, x_cm = chain.segment_length_m, chain.bat.radius_m, chain.bat.com_from_knob_m
    b = newton.ModelBuilder(gravity=(0.0, 0.0, 0.0))
    if st.solver == "mujoco":
        newton.solvers.SolverMuJoCo.register_custom_attributes(b)
    cfg = sc._shape_config(SimpleNamespace(e=scene.e, mu=0.0), st)
    joints, shapes = [], []
    for i, (m, c, J) in enumerate(
        zip(chain.masses_kg, chain.coms_m, chain.inertias_kgm2, strict=True)
    ):
        ax = 0.5 * m * r * r
        body = b.add_link(
            xform=wp.transform(wp.vec3(c - x_cm, 0.0, 0.0), wp.quat_identity()),
            mass=m,
            inertia=wp.mat33(ax, 0, 0, 0, J, 0, 0, 0, J),
            label=f"s{i}",
            lock_inertia=True,
        )
        shapes.append(
            b.add_shape_capsule(
                body,
                xform=wp.transform(
                    wp.vec3((i + 0.5) * ell - c, 0.0, 0.0), wp.quat(*sc.Z_TO_MINUS_X)
                ),
                radius=r,
                half_height=0.5 * ell,
                cfg=cfg,
                label=f"s{i}",
            )
        )
        if i == 0:
            joints.append(b.add_joint_free(body, label="root"))
            continue
        prev = chain.coms_m[i - 1]
        joints.append(
            b.add_joint_revolute(
                body - 1,
                body,
                parent_xform=wp.transform(wp.vec3(i * ell - prev, 0.0, 0.0), wp.quat_identity()),
                child_xform=wp.transform(wp.vec3(i * ell - c, 0.0, 0.0), wp.quat_identity()),
                axis=(0.0, 0.0, 1.0),
                target_q=0.0,
                target_ke=0.0,
                target_kd=0.0,
                stiffness=0.0,
                damping=0.0,
                label=f"j{i}",
                collision_filter_parent=True,
            )
        )
    b.add_articulation(joints, label="bat")
    for i in range(len(shapes)):
        for j in range(i + 2, len(shapes)):
            b.add_shape_collision_filter_pair(shapes[i], shapes[j])
    ib = ball.inertia_kgm2
    body = b.add_body(
        mass=ball.mass_kg,
        inertia=wp.mat33(ib, 0, 0, 0, ib, 0, 0, 0, ib),
        xform=wp.transform(wp.vec3(0.0, 1.0, 0.0), wp.quat_identity()),
        label="ball",
        lock_inertia=True,
    )
    b.add_shape_sphere(body, radius=ball.radius_m, cfg=cfg, label="ball")
    return b


class NewtonChain(ChainEngine):
    """Newton's segmented bat at the bat adapter's solver settings and contact mapping."""

    record = RECORD
    settings: NewtonSettings

    def __init__(self, settings: NewtonSettings) -> None:
        super().__init__(settings)
        self.model = None

    def build(self, scene: ChainScene) -> None:
        st = self.settings
        self.close()
        self.n = scene.chain.segments
        # no inertia "correction": from N = 32 a short segment's axial 0.5 m r^2 exceeds 2 J,
        # and Newton would raise J to meet the triangle inequality (x8.8 at N = 64)
        self.model = m = chain_builder(scene, st).finalize(
            device=sc.DEVICE, skip_validation_inertia=True
        )
        if st.solver == "mujoco":
            sc._mujoco_contact(m, SimpleNamespace(e=scene.e, mu=0.0), st)
        self._springs(scene)
        self.solver = sc.solver(m, st)
        if st.solver == "xpbd":
            self._xpbd_springs(scene)
        self.pipeline = (
            None
            if st.solver == "mujoco"
            else newton.CollisionPipeline(
                m, broad_phase="explicit", rigid_contact_max=8 * self.n, verify_buffers=False
            )
        )
        self.contacts = self.pipeline.contacts() if self.pipeline is not None else None
        self.control = m.control()
        self.states = [m.state(), m.state()]
        self.ball_v = np.zeros(2, dtype=np.float32)
        self.touching = False
        self._knob_x = self._read_knob_x()

    def _springs(self, scene: ChainScene) -> None:
        """Passive stiffness and damping (every solver but XPBD, which ignores them)."""
        if self.settings.solver == "xpbd":
            return
        ch = scene.chain
        self.model.joint_stiffness.assign(self._per_dof(ch.stiffnesses_nmprad))
        self.model.joint_damping.assign(self._per_dof(ch.dampings_nmsprad))

    def _xpbd_springs(self, scene: ChainScene) -> None:
        """XPBD's drive gains for k_j, c_j at the solver's iterations and relaxation."""
        ch, s = scene.chain, self.solver
        inv_i = self.model.body_inv_inertia.numpy()[: self.n, 2, 2].astype(float)
        gains = [
            xpbd_gains(
                k,
                c,
                inv_i[j] + inv_i[j + 1],
                self.settings.dt_s,
                s.iterations,
                s.joint_angular_relaxation,
            )
            for j, (k, c) in enumerate(zip(ch.stiffnesses_nmprad, ch.dampings_nmsprad, strict=True))
        ]
        self.model.joint_target_ke.assign(self._per_dof([g[0] for g in gains]))
        self.model.joint_target_kd.assign(self._per_dof([g[1] for g in gains]))
        self.solver.notify_model_changed(newton.ModelFlags.JOINT_DOF_FORCE_PROPERTIES)

    def _per_dof(self, per_joint) -> np.ndarray:
        """Per-joint values at the revolute joints' DOFs (6 free DOFs first, the ball's last)."""
        out = np.zeros(self.model.joint_dof_count, dtype=np.float32)
        out[6 : 6 + self.n - 1] = per_joint
        return out

    def _read_knob_x(self) -> float:
        """The knob end of segment 0's capsule (its axis's lower-x end), world x at build."""
        m = self.model
        xf, scale = m.shape_transform.numpy()[0], m.shape_scale.numpy()[0]
        x, y, z, w = xf[3:]
        axis_x = 2 * (x * z + w * y)
        return float(m.body_q.numpy()[0][0] + xf[0] - scale[1] * abs(axis_x))

    def mass_properties(self) -> np.ndarray:
        m = self.model
        mass, inertia = m.body_mass.numpy()[: self.n], m.body_inertia.numpy()[: self.n]
        com_x = m.body_q.numpy()[: self.n, 0] + m.body_com.numpy()[: self.n, 0]
        return np.column_stack(
            [mass.astype(float), com_x.astype(float) - self._knob_x, inertia[:, 2, 2].astype(float)]
        )

    def set_state(self, ball: np.ndarray, segments: np.ndarray) -> None:
        """Body poses and twists (v_com, omega: world frame), joint coordinates from them."""
        n = self.n
        q = np.zeros((n + 1, 7))
        q[:n, 0:2] = segments[:, 0:2]
        q[:n, 5], q[:n, 6] = np.sin(segments[:, 2] / 2), np.cos(segments[:, 2] / 2)
        q[n, 0:2], q[n, 6] = ball[0:2], 1.0
        qd = np.zeros((n + 1, 6))
        qd[:n, 0:2], qd[:n, 5] = segments[:, 3:5], segments[:, 5]
        qd[n, 0:2] = ball[2:4]
        for state in self.states:
            state.body_q.assign(q.astype(np.float32))
            state.body_qd.assign(qd.astype(np.float32))
            newton.eval_ik(self.model, state, state.joint_q, state.joint_qd)
            state.clear_forces()
        if self.settings.solver == "mujoco":
            self.solver.mjw_data.qacc_warmstart.zero_()
        self.touching = False
        self.ball_v = qd[n, 0:2].astype(np.float32)

    def step(self) -> None:
        s0, s1 = self.states
        if self.pipeline is not None:
            self.pipeline.collide(s0, self.contacts)
        self.solver.step(s0, s1, self.control, self.contacts, self.settings.dt_s)
        self.states = [s1, s0]
        v = s1.body_qd.numpy()[self.n, 0:2]
        # only a contact changes the ball's velocity (no gravity, no damping on it)
        self.touching = self._listed() and bool(np.any(v != self.ball_v))
        self.ball_v = v.copy()

    def _listed(self) -> bool:
        """Whether the engine held a ball-segment contact in the last step (MuJoCo: one
        closer than its margin); segments never meet each other."""
        if self.contacts is None:
            c = self.solver.mjw_data.contact
            count = int(self.solver.mjw_data.nacon.numpy()[0])
            return bool(np.any(c.dist.numpy()[:count] < c.includemargin.numpy()[:count]))
        return int(self.contacts.rigid_contact_count.numpy()[0]) > 0

    def read(self) -> tuple[np.ndarray, np.ndarray]:
        s = self.states[0]
        q, qd = s.body_q.numpy().astype(float), s.body_qd.numpy().astype(float)
        n = self.n
        segs = np.column_stack(
            [
                q[:n, 0],
                q[:n, 1],
                2.0 * np.arctan2(q[:n, 5], q[:n, 6]),
                qd[:n, 0],
                qd[:n, 1],
                qd[:n, 5],
            ]
        )
        return np.array([q[n, 0], q[n, 1], qd[n, 0], qd[n, 1]]), segs

    def in_contact(self) -> bool:
        return self.touching

    def failed(self) -> bool:
        s = self.states[0]
        return not (np.isfinite(s.body_q.numpy()).all() and np.isfinite(s.body_qd.numpy()).all())

    def close(self) -> None:
        self.model = self.solver = self.pipeline = self.contacts = None
