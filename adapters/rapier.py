"""Rapier adapter (PyPI ``rapier3d``, 3D, f32): two dynamic bodies in one ``PhysicsWorld``.

The bat is a dynamic body whose origin is its COM, carrying a massless capsule collider along
its x axis (``capsule_from_endpoints``: no rotated y capsule), its mass, COM and principal
inertia (axial, I_cm, I_cm) set as additional mass properties; the ball likewise with a sphere.
Traps this adapter handles (measured with rapier3d 0.36.1, the binding pinned by the extra):
- Mass properties set on a body are folded in at the next step: read back 0 kg before it, so
  the adapter recomputes them at once. Rapier stores them in f32 (0.871 kg reads back as
  0.87099999189): the read-back check allows a few f32 ulps (``check_mass_properties``).
- Speculative contacts: a pair closer than ``prediction_distance_m`` (0.02 m by default) gets a
  contact whose normal and lever arms are those of the step's start; the impact is then solved
  one step early, with the swinging bat's geometry omega dt out of date: |dv1| 2.5e-3 m/s over
  the paper's swing at 10 us (2.7e-2 at 100 us, first order), against 1e-5 with 1 um.
- Contact recycling (on by default) keeps a pair's contact points while it moved less than
  0.05 m, i.e. for ~100 steps at 10 us: the reference recomputes them every step.
- Contact softness (30 Hz, damping ratio 10) does not touch a bounce: restitution is applied
  rigidly after the substeps (e = 0.5 within 2e-7 from 0.01 to 40 m/s at every profile, no
  restitution velocity threshold), and issue #974 (restitution lost in a 0.35 beta) does not
  show. It rules a sustained contact: a plastic ball riding the turning bat sinks 0.8 mm into it
  and v1 is 0.18 m/s off the rigid answer (e = 0 sweep), against 9e-3 m/s at 10 kHz, ratio 1.
- The relax pass (``stabilization_iterations``) removes the velocity that corrects position
  errors: needed for contacts (without it a plastic slide turns into a bounce, |dv1| 8 m/s), but
  it makes an impulse joint lose omega at first order (about 0.3 omega dt / n relative after a
  0.1 s swing from rest, n substeps: 1.1e-3 at dt = 1e-4 s, n = 1). The reference hinge is a multibody (reduced
  coordinates) revolute joint instead: omega exact to f32 rounding, the angle off by exactly the
  semi-implicit Euler term. Multibody links are damped (0.1) by default: zeroed. The link's
  rigid body holds the velocity of one step before: ``unpin`` releases the joint's own.
- Substeps: each of ``solver_iterations`` (4 by default) integrates dt/n, so the swing's angle
  error is alpha t dt/(2n); the reference takes one, the semi-implicit Euler the harness models.
- Rotation per step is 2 atan(omega dt/2), not omega dt (a normalised first-order quaternion
  update): 0.012 rad short at 32 rad/s and 1/60 s, 3e-12 at 10 us.
- Speed caps: linear speed clamped to 400 m/s, angular to (pi/4)/dt unless the body allows fast
  rotation (60 rad/s becomes 47.1 at 1/60 s): both lifted in the reference.
- CCD: ``ccd_enabled`` bodies ("bullets") sweep against dynamic bodies but never against other
  bullets, so both bodies enabled tunnel 41 of 41 impacts at 1/60 s (issue #984's two fast
  bodies); the ball alone enabled catches 30. ``ccd_bodies`` picks which.
- Restitution combines as the mean of the two colliders' values (Average, the default rule):
  ``set_restitution`` gives both e. User forces persist across steps until reset; the world runs
  on one thread (a shared machine; results then do not depend on a pool).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from analytic import Ball, Bat
from analytic import _checks

from ._record import EngineRecord, Integrator, KnobFamily, RestitutionRule, import_engine
from .base import BodyLoad, Engine, MassProperties, Reading, Settings

#: The hands' releasable hinge: an impulse joint, or a multibody (reduced-coordinate) joint.
HINGES = ("impulse", "multibody")
#: Which bodies are CCD bullets (``ccd_enabled``).
CCD_BODIES = ("none", "ball", "both")
#: f32's largest value: Rapier's "no cap" for its linear speed clamp.
F32_MAX = 3.4028234663852886e38


@dataclass(frozen=True, kw_only=True)
class RapierSettings(Settings):
    """Rapier's knobs (its ``IntegrationParameters``, per-body CCD and the hinge).

    ``solver_iterations``: substeps per step; ``pgs_iterations`` and
    ``stabilization_iterations``: the biased and the relax (unbiased) solver passes of each
    substep; ``contact_frequency_hz``/``contact_damping_ratio``: the contact's softness, the
    spring that drives penetration out in the biased pass; ``allowed_linear_error_m`` (m): the
    CCD clamp's standoff; ``max_corrective_velocity_mps`` (m/s): the push-out speed cap;
    ``prediction_distance_m`` (m): speculative contacts are made this far apart;
    ``max_linear_velocity_mps`` (m/s): every body's speed cap (F32_MAX: none);
    ``allow_fast_rotation``: lift the (pi/4)/dt angular speed cap; ``warmstart_coefficient`` in
    [0, 1]; ``contact_recycling``: keep contact points while the pair moved under 0.05 m;
    ``max_ccd_substeps``: the world's CCD switch (0: off); ``ccd_bodies`` one of CCD_BODIES;
    ``soft_ccd_prediction_m`` (m): both bodies' soft-CCD distance; ``hinge`` one of HINGES,
    ``hinge_frequency_hz``/``hinge_damping_ratio`` the impulse joint's softness.
    """

    solver_iterations: int = 4
    pgs_iterations: int = 1
    stabilization_iterations: int = 1
    contact_frequency_hz: float = 30.0
    contact_damping_ratio: float = 10.0
    allowed_linear_error_m: float = 0.005
    max_corrective_velocity_mps: float = 3.0
    prediction_distance_m: float = 0.02
    max_linear_velocity_mps: float = 400.0
    allow_fast_rotation: bool = False
    warmstart_coefficient: float = 1.0
    contact_recycling: bool = True
    max_ccd_substeps: int = 1
    ccd_bodies: str = "none"
    soft_ccd_prediction_m: float = 0.0
    hinge: str = "impulse"
    hinge_frequency_hz: float = 1.0e6
    hinge_damping_ratio: float = 1.0

    def __post_init__(self) -> None:
        super().__post_init__()
        _checks.integer("solver_iterations", self.solver_iterations, 1, 10_000)
        _checks.integer("pgs_iterations", self.pgs_iterations, 1, 10_000)
        _checks.integer("stabilization_iterations", self.stabilization_iterations, 0, 10_000)
        _checks.integer("max_ccd_substeps", self.max_ccd_substeps, 0, 10_000)
        for name in ("contact_frequency_hz", "contact_damping_ratio", "max_linear_velocity_mps",
                     "hinge_frequency_hz", "hinge_damping_ratio"):
            _checks.positive(name, getattr(self, name))
        for name in ("allowed_linear_error_m", "max_corrective_velocity_mps",
                     "prediction_distance_m", "soft_ccd_prediction_m"):
            _checks.non_negative(name, getattr(self, name))
        _checks.in_range("warmstart_coefficient", self.warmstart_coefficient, 0.0, 1.0)
        for name in ("allow_fast_rotation", "contact_recycling"):
            if not isinstance(getattr(self, name), bool):
                raise ValueError(f"{name}={getattr(self, name)!r} is not a bool; allowed: "
                                 "True, False")
        for name, allowed in (("ccd_bodies", CCD_BODIES), ("hinge", HINGES)):
            if getattr(self, name) not in allowed:
                raise ValueError(f"{name}={getattr(self, name)!r} is unknown; allowed: "
                                 f"{', '.join(allowed)}")


RECORD = EngineRecord(
    name="rapier", package="rapier3d", import_name="rapier3d", extra="rapier",
    profiles={
        # Fidelity, each value measured on the paper's swing (41 points) and its e = 0 slide:
        # 10 us step; one substep (the semi-implicit Euler step the swing tolerances model;
        # 4 give the same impacts); a 1 um prediction distance (the impact then sees the geometry
        # of its own step: |dv1| 1e-5 m/s instead of 2.5e-3 at 0.02 m, yet a gap left by f32
        # rounding still makes a contact); contact points recomputed every step; a stiff contact
        # (10 kHz, damping ratio 1: penetration removed within a few steps; e = 0 slide |dv1|
        # 9e-3 m/s instead of 0.18, bounces unchanged); the speed caps lifted so that a blow-up
        # shows as it is; the hands a multibody joint (omega exact, see the module docstring).
        "reference": RapierSettings(dt_s=1e-5, solver_iterations=1, prediction_distance_m=1e-6,
                                    contact_frequency_hz=1e4, contact_damping_ratio=1.0,
                                    contact_recycling=False, max_linear_velocity_mps=F32_MAX,
                                    allow_fast_rotation=True, hinge="multibody"),
        # Out of the box: 1/60 s, every solver value Rapier's own, the hands an impulse joint
        # (Rapier's usual joint) of default softness; the contact instant mid-step as in any
        # unaligned simulation.
        "default": RapierSettings(dt_s=1 / 60, contact_phase=0.5),
    },
    color="tab:purple", marker="v",
    speed_accuracy=(
        KnobFamily(label="reference solver", quick=True),
        KnobFamily(label="4 substeps", overrides=(("solver_iterations", 4),)),
        KnobFamily(label="speculative 0.02 m", overrides=(("prediction_distance_m", 0.02),),
                   quick=True),
        KnobFamily(label="soft contact 30 Hz",
                   overrides=(("contact_frequency_hz", 30.0), ("contact_damping_ratio", 10.0))),
        KnobFamily(label="CCD on the ball", overrides=(("ccd_bodies", "ball"),)),
    ),
    integrators=(Integrator(label="semi-implicit Euler"),),
    precision="float32",
    restitution_rule=RestitutionRule.MEAN,
    # Every value read back from a fresh IntegrationParameters, rigid body and joint.
    engine_defaults={"dt_s": 1 / 60, "solver_iterations": 4, "pgs_iterations": 1,
                     "stabilization_iterations": 1, "contact_frequency_hz": 30.0,
                     "contact_damping_ratio": 10.0, "allowed_linear_error_m": 0.005,
                     "max_corrective_velocity_mps": 3.0, "prediction_distance_m": 0.02,
                     "max_linear_velocity_mps": 400.0, "allow_fast_rotation": False,
                     "warmstart_coefficient": 1.0, "contact_recycling": True,
                     "max_ccd_substeps": 1, "ccd_bodies": "none", "soft_ccd_prediction_m": 0.0,
                     "hinge_frequency_hz": 1.0e6, "hinge_damping_ratio": 1.0},
)
rapier = import_engine(RECORD)


class RapierEngine(Engine):
    """Rapier behind the common contract."""

    record = RECORD

    @classmethod
    def speculative_margin_m(cls, settings: RapierSettings) -> float:
        return settings.prediction_distance_m

    @classmethod
    def read_back_defaults(cls) -> dict:
        p = rapier.IntegrationParameters()
        unit = p.length_unit
        body = rapier.RigidBody.dynamic().build()
        joint = rapier.SphericalJoint().softness
        return {"dt_s": p.dt, "solver_iterations": p.num_solver_iterations,
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
                "contact_recycling": p.contact_recycling, "max_ccd_substeps": p.max_ccd_substeps,
                "ccd_bodies": "both" if body.ccd_enabled else "none",
                "soft_ccd_prediction_m": body.soft_ccd_prediction,
                "hinge_frequency_hz": joint.natural_frequency,
                "hinge_damping_ratio": joint.damping_ratio}

    def __init__(self, settings: RapierSettings, *, name: str | None = None) -> None:
        super().__init__(settings, name=name)
        self._world = None
        self._load: tuple[float, float, float] | None = None
        self._joint = None
        self._pivot: tuple[float, float] = (0.0, 0.0)
        self._failures = 0

    def build_scene(self, bat: Bat, ball: Ball) -> None:
        st = self.settings
        w = rapier.PhysicsWorld(gravity=(0.0, 0.0, 0.0))
        w.set_num_threads(1)
        p = w.integration_parameters  # a live view: set in place
        p.dt = st.dt_s
        p.num_solver_iterations = st.solver_iterations
        p.num_internal_pgs_iterations = st.pgs_iterations
        p.num_internal_stabilization_iterations = st.stabilization_iterations
        p.contact_softness = rapier.SpringCoefficients(st.contact_frequency_hz,
                                                       st.contact_damping_ratio)
        p.length_unit = 1.0
        p.normalized_allowed_linear_error = st.allowed_linear_error_m
        p.normalized_max_corrective_velocity = st.max_corrective_velocity_mps
        p.normalized_prediction_distance = st.prediction_distance_m
        p.normalized_max_linear_velocity = st.max_linear_velocity_mps
        p.warmstart_coefficient = st.warmstart_coefficient
        p.contact_recycling = st.contact_recycling
        p.max_ccd_substeps = st.max_ccd_substeps
        self._world = w
        ib = ball.inertia_kgm2
        self._bat = self._add_body(
            rapier.MassProperties(local_com=(0.0, 0.0, 0.0), mass=bat.mass_kg,
                                  principal_inertia=(bat.axial_inertia_kgm2, bat.inertia_cm_kgm2,
                                                     bat.inertia_cm_kgm2)),
            rapier.Collider.capsule_from_endpoints((bat.s_min_m, 0.0, 0.0),
                                                   (bat.s_max_m, 0.0, 0.0), bat.radius_m),
            ccd=st.ccd_bodies == "both")
        self._ball = self._add_body(
            rapier.MassProperties(local_com=(0.0, 0.0, 0.0), mass=ball.mass_kg,
                                  principal_inertia=(ib, ib, ib)),
            rapier.Collider.ball(ball.radius_m), ccd=st.ccd_bodies != "none")
        self._bat_col = w.rigid_bodies[self._bat].colliders[0]
        self._ball_col = w.rigid_bodies[self._ball].colliders[0]
        self._anchor = w.add_body(rapier.RigidBody.fixed())  # the world end of the hinge
        self._joint = self._load = None

    def _add_body(self, mprops, collider, ccd: bool):
        """A dynamic body with exactly ``mprops`` (its collider massless), undamped, awake."""
        st, w = self.settings, self._world
        body = (rapier.RigidBody.dynamic().additional_mass_properties(mprops).can_sleep(False)
                .linear_damping(0.0).angular_damping(0.0).ccd_enabled(ccd)
                .soft_ccd_prediction(st.soft_ccd_prediction_m)
                .allow_fast_rotation(st.allow_fast_rotation))
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
            bat_mass_kg=mb.mass, bat_com_from_knob_m=mb.local_com.x - knob_x,
            bat_inertia_kgm2=izz(mb), ball_mass_kg=ms.mass, ball_inertia_kgm2=izz(ms))

    def set_restitution(self, e: float) -> None:
        self.set_body_restitution(bat=e, ball=e)  # the mean of e and e is e

    def set_body_restitution(self, *, bat: float, ball: float) -> None:
        super().set_body_restitution(bat=bat, ball=ball)
        self._world.colliders[self._bat_col].restitution = bat
        self._world.colliders[self._ball_col].restitution = ball

    def set_state(self, r: Reading) -> None:
        w = self._world
        bat, ball = w.rigid_bodies[self._bat], w.rigid_bodies[self._ball]
        bat.translation = (r.bat_x, r.bat_y, 0.0)
        bat.rotation = rapier.Rotation3.from_axis_angle((0.0, 0.0, 1.0), r.bat_angle)
        bat.linvel = (r.bat_vx, r.bat_vy, 0.0)
        bat.angvel = (0.0, 0.0, r.bat_w)
        ball.translation = (r.ball_x, r.ball_y, 0.0)
        ball.rotation = rapier.Rotation3.identity()
        ball.linvel = (r.ball_vx, r.ball_vy, 0.0)
        ball.angvel = (0.0, 0.0, r.ball_w)
        # Re-inserting the ball's collider drops the pair's contact manifold and the impulses
        # it keeps for warm starts: without it a used engine differs from a fresh one.
        self._ball_col = w.add_collider(w.remove_collider(self._ball_col), self._ball)

    def set_load(self, load: BodyLoad | None) -> None:
        self._load = None if load is None else (load.force_n, load.angle_rad,
                                                load.torque_about_com_nm)
        if load is None:  # user forces persist across steps until reset
            bat = self._world.rigid_bodies[self._bat]
            bat.reset_forces()
            bat.reset_torques()

    def pin(self, pivot_from_com_m: float, pivot_xy_m: tuple[float, float]) -> None:
        st, w = self.settings, self._world
        bat = w.rigid_bodies[self._bat]
        self._pivot = pivot_xy_m
        if st.hinge == "impulse":
            joint = (rapier.SphericalJoint.builder()
                     .local_anchor1((pivot_xy_m[0], pivot_xy_m[1], 0.0))
                     .local_anchor2((pivot_from_com_m, 0.0, 0.0))
                     .softness(rapier.SpringCoefficients(st.hinge_frequency_hz,
                                                         st.hinge_damping_ratio))
                     .build())
            self._joint = w.impulse_joints.insert(self._anchor, self._bat, joint)
            return
        # A revolute joint about z in reduced coordinates: a new link sits at coordinate 0, so
        # the frames put the bat's present pose there.
        free_z = (rapier.JointAxesMask.LIN_AXES | rapier.JointAxesMask.ANG_X
                  | rapier.JointAxesMask.ANG_Y)
        joint = (rapier.GenericJointBuilder(free_z)
                 .local_frame1(rapier.Isometry3((pivot_xy_m[0], pivot_xy_m[1], 0.0),
                                                bat.rotation))
                 .local_frame2(rapier.Isometry3((pivot_from_com_m, 0.0, 0.0),
                                                rapier.Rotation3.identity()))
                 .build())
        self._joint = w.multibody_joints.insert(self._anchor, self._bat, joint)
        links = w.multibody_joints.multibody(self._joint)
        links.set_damping([0.0] * links.ndofs)  # multibody links are damped (0.1) by default
        velocity = links.generalized_velocity()
        velocity[-1] = bat.angvel.z
        links.set_generalized_velocity(velocity)

    def unpin(self) -> None:
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
        self._failures += len(w.quarantine.bodies)  # non-finite bodies Rapier reset

    def read(self) -> Reading:
        bodies = self._world.rigid_bodies
        bat, ball = bodies[self._bat], bodies[self._ball]
        bx, by, _ = ball.translation.to_tuple()
        bvx, bvy, _ = ball.linvel.to_tuple()
        cx, cy, _ = bat.translation.to_tuple()
        cvx, cvy, _ = bat.linvel.to_tuple()
        rot = bat.rotation
        return Reading(bx, by, bvx, bvy, ball.angvel.z, cx, cy, 2.0 * math.atan2(rot.k, rot.w),
                       cvx, cvy, bat.angvel.z)

    def in_contact(self) -> bool:
        # A speculative contact (bodies apart, no impulse) is not a touch.
        pair = self._world.narrow_phase.contact_pair(self._bat_col, self._ball_col)
        if pair is None:
            return False
        return any(pt.impulse > 0.0 or pt.dist < 0.0 for m in pair.manifolds for pt in m.points)

    def numerical_failures(self) -> int:
        return self._failures


ENGINE = RapierEngine
