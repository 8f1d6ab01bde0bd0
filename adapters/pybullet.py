"""PyBullet adapter: two base-only multibodies (PyBullet's default) in a DIRECT client.

Traps this adapter handles (measured, see ENGINE_NOTES.md): ``contactSlop`` (1e-5 m by default)
and ``contactERP`` feed position error back into the velocity (slop/dt alone costs 8% at
dt = 1e-5 s), so the reference profile zeroes both; default damping 0.04 is zeroed for the scene;
restitution is the product of both bodies' values (bat 1, ball e) and is dropped below
``restitutionVelocityThreshold``; base position and velocity calls refer to the COM; multibody
angular speed is capped at ``maxJointVelocity`` (100 rad/s unless raised).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from analytic import Ball, Bat
from analytic import _checks

from ._record import EngineRecord, KnobFamily, RestitutionRule, import_engine
from .base import BodyLoad, Engine, MassProperties, Reading, Settings

#: setting name -> setPhysicsEngineParameter keyword; a None value leaves the engine default.
ENGINE_PARAMETERS = {
    "solver_iterations": "numSolverIterations",
    "contact_erp": "contactERP",
    "erp": "erp",
    "friction_erp": "frictionERP",
    "contact_slop": "contactSlop",
    "restitution_velocity_threshold": "restitutionVelocityThreshold",
    "contact_breaking_threshold": "contactBreakingThreshold",
    "split_impulse": "useSplitImpulse",
}


@dataclass(frozen=True, kw_only=True)
class PybulletSettings(Settings):
    """Bullet's knobs (None: keep the engine's own default). ``contact_erp``/``erp``/
    ``friction_erp``: fraction of position error corrected per step; ``contact_slop`` (m):
    overlap allowed before correction; ``restitution_velocity_threshold`` (m/s); 
    ``contact_breaking_threshold`` (m): contact margin; ``split_impulse`` 0/1;
    ``max_joint_velocity_radps``: the multibody angular-speed cap; ``ccd_swept_sphere_radius``
    (m): continuous collision detection, 0 = off."""

    solver_iterations: int | None = None
    contact_erp: float | None = None
    erp: float | None = None
    friction_erp: float | None = None
    contact_slop: float | None = None
    restitution_velocity_threshold: float | None = None
    contact_breaking_threshold: float | None = None
    split_impulse: int | None = None
    max_joint_velocity_radps: float | None = None
    ccd_swept_sphere_radius: float = 0.0

    def __post_init__(self) -> None:
        super().__post_init__()
        if self.solver_iterations is not None:
            _checks.integer("solver_iterations", self.solver_iterations, 1, 10_000)
        for name in ("contact_erp", "erp", "friction_erp"):
            if getattr(self, name) is not None:
                _checks.in_range(name, getattr(self, name), 0.0, 1.0)
        for name in ("contact_slop", "restitution_velocity_threshold",
                     "contact_breaking_threshold", "ccd_swept_sphere_radius"):
            if getattr(self, name) is not None:
                _checks.non_negative(name, getattr(self, name))
        if self.max_joint_velocity_radps is not None:
            _checks.positive("max_joint_velocity_radps", self.max_joint_velocity_radps)


RECORD = EngineRecord(
    name="pybullet", package="pybullet", import_name="pybullet",
    profiles={
        # No position feedback into contact velocities (contactERP = 0, contactSlop = 0): the
        # sequential-impulse solver then meets Newton's law exactly for one contact; the hands'
        # pivot (a joint, governed by erp) fully corrected every step, erp = 1: its drift is
        # then second order (2e-6 rad/s after a 0.1 s swing at 10 us, 4e-3 with erp = 0); no
        # restitution threshold; the angular cap lifted so a blow-up shows as it is; 10 us step.
        "reference": PybulletSettings(dt_s=1e-5, contact_erp=0.0, erp=1.0, friction_erp=0.0,
                                      contact_slop=0.0, restitution_velocity_threshold=0.0,
                                      max_joint_velocity_radps=1e4),
        # Out of the box: 1/240 s, every solver parameter left at Bullet's value, the contact
        # instant mid-step as in any unaligned simulation.
        "default": PybulletSettings(dt_s=1 / 240, contact_phase=0.5),
    },
    color="tab:orange", marker="s",
    speed_accuracy=(
        KnobFamily(label="reference solver (ERP 0, slop 0)", quick=True),
        *(KnobFamily(label=f"reference solver, {n} iterations",
                     overrides=(("solver_iterations", n),)) for n in (1, 10, 200)),
    ),
    restitution_rule=RestitutionRule.PRODUCT,
    threshold_setting="restitution_velocity_threshold",
    # Bullet reports neither contact value: both measured (setting them explicitly reproduces
    # the default solver's impacts bit for bit); the iteration count it reports.
    engine_defaults={"contact_erp": 0.08, "contact_slop": 1e-5, "solver_iterations": 50,
                     "dt_s": 1 / 240},
)
pb = import_engine(RECORD)


class PybulletEngine(Engine):
    """PyBullet behind the common contract."""

    record = RECORD

    @classmethod
    def read_back_defaults(cls) -> dict:
        client = pb.connect(pb.DIRECT)
        try:
            got = pb.getPhysicsEngineParameters(physicsClientId=client)
        finally:
            pb.disconnect(physicsClientId=client)
        return {"solver_iterations": got["numSolverIterations"], "dt_s": got["fixedTimeStep"]}

    def __init__(self, settings: PybulletSettings, *, name: str | None = None) -> None:
        super().__init__(settings, name=name)
        self._client: int | None = None
        self._load: tuple[float, float, float] | None = None
        self._joint: int | None = None

    def close(self) -> None:
        if self._client is not None:
            pb.disconnect(physicsClientId=self._client)
            self._client = None
            self.scene = None

    def __del__(self) -> None:
        try:
            self.close()
        except Exception:  # interpreter shutdown: the module may be gone already
            pass

    def build_scene(self, bat: Bat, ball: Ball) -> None:
        st = self.settings
        if self._client is None:
            self._client = pb.connect(pb.DIRECT)
        c = self._client
        pb.resetSimulation(physicsClientId=c)
        self._joint = None
        pb.setGravity(0, 0, 0, physicsClientId=c)
        params = {kw: getattr(st, name) for name, kw in ENGINE_PARAMETERS.items()
                  if getattr(st, name) is not None}
        pb.setPhysicsEngineParameter(fixedTimeStep=st.dt_s, numSubSteps=0, physicsClientId=c,
                                     **params)
        a, b = bat.s_min_m, bat.s_max_m
        along_x = pb.getQuaternionFromEuler([0.0, math.pi / 2, 0.0])  # capsules lie along z
        bat_shape = pb.createCollisionShape(pb.GEOM_CAPSULE, radius=bat.radius_m, height=b - a,
                                            collisionFramePosition=[(a + b) / 2, 0.0, 0.0],
                                            collisionFrameOrientation=along_x, physicsClientId=c)
        ball_shape = pb.createCollisionShape(pb.GEOM_SPHERE, radius=ball.radius_m,
                                             physicsClientId=c)
        self._bat = pb.createMultiBody(bat.mass_kg, bat_shape, physicsClientId=c)
        self._ball = pb.createMultiBody(ball.mass_kg, ball_shape, basePosition=[0.0, 1.0, 0.0],
                                        physicsClientId=c)
        ib = ball.inertia_kgm2
        inertia = {self._bat: [bat.axial_inertia_kgm2, bat.inertia_cm_kgm2, bat.inertia_cm_kgm2],
                   self._ball: [ib, ib, ib]}
        for body, mass in ((self._bat, bat.mass_kg), (self._ball, ball.mass_kg)):
            extra = {}
            if st.max_joint_velocity_radps is not None:
                extra["maxJointVelocity"] = st.max_joint_velocity_radps
            if st.ccd_swept_sphere_radius > 0.0:
                extra["ccdSweptSphereRadius"] = st.ccd_swept_sphere_radius
            pb.changeDynamics(body, -1, mass=mass, localInertiaDiagonal=inertia[body],
                              lateralFriction=0.0, spinningFriction=0.0, rollingFriction=0.0,
                              linearDamping=0.0, angularDamping=0.0, restitution=1.0,
                              physicsClientId=c, **extra)

    def mass_properties(self) -> MassProperties:
        c = self._client
        bat = pb.getDynamicsInfo(self._bat, -1, physicsClientId=c)
        ball = pb.getDynamicsInfo(self._ball, -1, physicsClientId=c)
        shape = pb.getCollisionShapeData(self._bat, -1, physicsClientId=c)[0]
        height, radius = shape[3][0], shape[3][1]
        knob_x = shape[5][0] - height / 2 - radius
        return MassProperties(
            bat_mass_kg=bat[0], bat_com_from_knob_m=bat[3][0] - knob_x,
            bat_inertia_kgm2=bat[2][2], ball_mass_kg=ball[0], ball_inertia_kgm2=ball[2][2],
        )

    def set_restitution(self, e: float) -> None:
        self.set_body_restitution(bat=1.0, ball=e)  # Bullet multiplies the two

    def set_body_restitution(self, *, bat: float, ball: float) -> None:
        super().set_body_restitution(bat=bat, ball=ball)
        for body, value in ((self._bat, bat), (self._ball, ball)):
            pb.changeDynamics(body, -1, restitution=value, physicsClientId=self._client)

    def set_state(self, r: Reading) -> None:
        c = self._client
        half = 0.5 * r.bat_angle
        pb.resetBasePositionAndOrientation(self._bat, [r.bat_x, r.bat_y, 0.0],
                                           [0.0, 0.0, math.sin(half), math.cos(half)],
                                           physicsClientId=c)
        pb.resetBaseVelocity(self._bat, [r.bat_vx, r.bat_vy, 0.0], [0.0, 0.0, r.bat_w],
                             physicsClientId=c)
        pb.resetBasePositionAndOrientation(self._ball, [r.ball_x, r.ball_y, 0.0],
                                           [0.0, 0.0, 0.0, 1.0], physicsClientId=c)
        pb.resetBaseVelocity(self._ball, [r.ball_vx, r.ball_vy, 0.0], [0.0, 0.0, r.ball_w],
                             physicsClientId=c)

    def set_load(self, load: BodyLoad | None) -> None:
        self._load = None if load is None else (load.force_n, load.angle_rad,
                                                load.torque_about_com_nm)

    def pin(self, pivot_from_com_m: float, pivot_xy_m: tuple[float, float]) -> None:
        self._joint = pb.createConstraint(
            self._bat, -1, -1, -1, pb.JOINT_POINT2POINT, [0.0, 0.0, 0.0],
            [pivot_from_com_m, 0.0, 0.0], [pivot_xy_m[0], pivot_xy_m[1], 0.0],
            physicsClientId=self._client)

    def unpin(self) -> None:
        if self._joint is not None:
            pb.removeConstraint(self._joint, physicsClientId=self._client)
            self._joint = None

    def step(self) -> None:
        c = self._client
        if self._load is not None:
            f, q, torque = self._load  # force through the COM + its constant torque
            pos, (_, _, qz, qw) = pb.getBasePositionAndOrientation(self._bat, physicsClientId=c)
            angle = 2.0 * math.atan2(qz, qw) + q
            pb.applyExternalForce(self._bat, -1, [f * math.cos(angle), f * math.sin(angle), 0.0],
                                  pos, pb.WORLD_FRAME, physicsClientId=c)
            pb.applyExternalTorque(self._bat, -1, [0.0, 0.0, torque], pb.WORLD_FRAME,
                                   physicsClientId=c)
        pb.stepSimulation(physicsClientId=c)

    def read(self) -> Reading:
        c = self._client
        (bx, by, _), _ = pb.getBasePositionAndOrientation(self._ball, physicsClientId=c)
        (bvx, bvy, _), (_, _, bw) = pb.getBaseVelocity(self._ball, physicsClientId=c)
        (cx, cy, _), (_, _, qz, qw) = pb.getBasePositionAndOrientation(self._bat,
                                                                       physicsClientId=c)
        (cvx, cvy, _), (_, _, cw) = pb.getBaseVelocity(self._bat, physicsClientId=c)
        return Reading(bx, by, bvx, bvy, bw, cx, cy, 2.0 * math.atan2(qz, qw), cvx, cvy, cw)

    def in_contact(self) -> bool:
        points = pb.getContactPoints(self._bat, self._ball, physicsClientId=self._client)
        return any(pt[8] < 0.0 or pt[9] > 0.0 for pt in points)


ENGINE = PybulletEngine
