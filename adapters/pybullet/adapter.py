"""The PyBullet adapter (see the package docstring for the scene and its traps)."""

from __future__ import annotations

import dataclasses
import math

from analytic import Ball, Bat

from ..frames import angle_and_tilt, bat_quaternion, in_the_plane
from ..interface import Engine, Hands, MassProperties, Scene, State
from ..loading import import_engine
from . import ENGINE_PARAMETERS, RECORD

pb = import_engine(RECORD)


class PybulletEngine(Engine):
    """PyBullet behind the single-world interface."""

    record = RECORD

    @classmethod
    def read_back_defaults(cls) -> dict:
        client = pb.connect(pb.DIRECT)
        try:
            got = pb.getPhysicsEngineParameters(physicsClientId=client)
        finally:
            pb.disconnect(physicsClientId=client)
        return {
            "solver_iterations": got["numSolverIterations"],
            "dt_s": got["fixedTimeStep"],
            "cone_friction": _measured_cone_friction(),
        }

    def __init__(self, settings) -> None:
        super().__init__(settings)
        # connected now: a build then costs what one more world does (the harness times it)
        self._client: int | None = pb.connect(pb.DIRECT)
        self._fresh = True  # nothing built in the client yet: no reset needed
        self._load: tuple[float, float, float] | None = None
        self._joint: int | None = None

    def close(self) -> None:
        if self._client is not None:
            pb.disconnect(physicsClientId=self._client)
            self._client = None

    def __del__(self) -> None:
        try:
            self.close()
        except Exception:  # interpreter shutdown: the module may be gone already
            pass

    def build(self, scene: Scene) -> None:
        if self._client is None:
            self._client, self._fresh = pb.connect(pb.DIRECT), True
        c = self._client
        if not self._fresh:
            pb.resetSimulation(physicsClientId=c)
        self._fresh = False
        self._joint = self._load = None
        configure(c, self.settings)
        self._bat, self._ball = add_pair(c, scene, self.settings)

    def mass_properties(self) -> MassProperties:
        return pair_mass_properties(self._client, self._bat, self._ball)

    def set_body_restitution(self, *, bat: float, ball: float) -> None:
        set_restitution(self._client, (self._bat, self._ball), bat=bat, ball=ball)

    def set_body_friction(self, *, bat: float, ball: float) -> None:
        set_friction(self._client, (self._bat, self._ball), bat=bat, ball=ball)

    def set_state(self, state: State) -> None:
        self._planar = in_the_plane(state)  # read back as set (frames.angle_and_tilt)
        set_pair(self._client, self._bat, self._ball, state)

    def set_drive(self, hands: Hands | None) -> None:
        if self._joint is not None:
            pb.removeConstraint(self._joint, physicsClientId=self._client)
        self._joint, self._load = drive_pair(self._client, self._bat, hands)

    def step(self) -> None:
        if self._load is not None:
            load_pair(self._client, self._bat, self._load)
        pb.stepSimulation(physicsClientId=self._client)

    def read(self) -> State:
        return read_pair(self._client, self._bat, self._ball, self._planar)

    def in_contact(self) -> bool:
        points = pb.getContactPoints(self._bat, self._ball, physicsClientId=self._client)
        return any(acting(pt) for pt in points)


def pair_mass_properties(c: int, bat: int, ball: int) -> MassProperties:
    """The pair's mass properties as Bullet holds them (the knob from the capsule's frame)."""
    bat_info = pb.getDynamicsInfo(bat, -1, physicsClientId=c)
    ball_info = pb.getDynamicsInfo(ball, -1, physicsClientId=c)
    shape = pb.getCollisionShapeData(bat, -1, physicsClientId=c)[0]
    height, radius = shape[3][0], shape[3][1]
    knob_x = shape[5][0] - height / 2 - radius
    return MassProperties(
        bat_mass_kg=bat_info[0],
        bat_com_from_knob_m=bat_info[3][0] - knob_x,
        bat_inertia_kgm2=bat_info[2][2],
        ball_mass_kg=ball_info[0],
        ball_inertia_kgm2=ball_info[2][2],
    )


def acting(point) -> bool:
    """Whether a contact point of ``getContactPoints`` acts: overlapping, or pushing."""
    return point[8] < 0.0 or point[9] > 0.0


def configure(c: int, st) -> None:
    """A reset client's world: no gravity, the settings' step (no substeps) and parameters."""
    pb.setGravity(0, 0, 0, physicsClientId=c)
    params = {
        kw: getattr(st, name)
        for name, kw in ENGINE_PARAMETERS.items()
        if getattr(st, name) is not None
    }
    pb.setPhysicsEngineParameter(fixedTimeStep=st.dt_s, numSubSteps=0, physicsClientId=c, **params)


def add_pair(c: int, scene: Scene, st) -> tuple[int, int]:
    """The bat (a capsule along x about its COM, the bat's inertia) and the ball in client
    ``c``: restitution by the product rule (bat 1, ball e), frictionless unless the scene has
    friction, no damping. Returns their body ids."""
    bat, ball = scene.bat, scene.ball
    a, b = bat.s_min_m, bat.s_max_m
    along_x = pb.getQuaternionFromEuler([0.0, math.pi / 2, 0.0])  # capsules lie along z
    bat_shape = pb.createCollisionShape(
        pb.GEOM_CAPSULE,
        radius=bat.radius_m,
        height=b - a,
        collisionFramePosition=[(a + b) / 2, 0.0, 0.0],
        collisionFrameOrientation=along_x,
        physicsClientId=c,
    )
    ball_shape = pb.createCollisionShape(pb.GEOM_SPHERE, radius=ball.radius_m, physicsClientId=c)
    bat_id = pb.createMultiBody(bat.mass_kg, bat_shape, physicsClientId=c)
    ball_id = pb.createMultiBody(
        ball.mass_kg, ball_shape, basePosition=[0.0, 1.0, 0.0], physicsClientId=c
    )
    ib = ball.inertia_kgm2
    inertia = {
        bat_id: [bat.axial_inertia_kgm2, bat.inertia_cm_kgm2, bat.inertia_cm_kgm2],
        ball_id: [ib, ib, ib],
    }
    extra = {}
    if st.max_joint_velocity_radps is not None:
        extra["maxJointVelocity"] = st.max_joint_velocity_radps
    if st.ccd_swept_sphere_radius > 0.0:
        extra["ccdSweptSphereRadius"] = st.ccd_swept_sphere_radius
    for body, mass in ((bat_id, bat.mass_kg), (ball_id, ball.mass_kg)):
        pb.changeDynamics(
            body,
            -1,
            mass=mass,
            localInertiaDiagonal=inertia[body],
            lateralFriction=0.0,
            spinningFriction=0.0,
            rollingFriction=0.0,
            linearDamping=0.0,
            angularDamping=0.0,
            restitution=1.0,
            physicsClientId=c,
            **extra,
        )
    set_restitution(c, (bat_id, ball_id), bat=1.0, ball=scene.e)  # Bullet multiplies the two
    if scene.mu > 0.0:  # frictionless: both stay at 0, as every frictionless run was built
        bat_mu, ball_mu = RECORD.can.friction_rule.per_body(scene.mu)  # mu * 1.0 = mu
        set_friction(c, (bat_id, ball_id), bat=bat_mu, ball=ball_mu)
    return bat_id, ball_id


def set_restitution(c: int, pair: tuple[int, int], *, bat: float, ball: float) -> None:
    for body, value in zip(pair, (bat, ball)):
        pb.changeDynamics(body, -1, restitution=value, physicsClientId=c)


def set_friction(c: int, pair: tuple[int, int], *, bat: float, ball: float) -> None:
    for body, value in zip(pair, (bat, ball)):
        pb.changeDynamics(body, -1, lateralFriction=value, physicsClientId=c)


def set_pair(c: int, bat: int, ball: int, state: State) -> None:
    """Both bodies' poses and twists (Bullet's quaternions are x, y, z, w; a base's angular
    velocity is the world's)."""
    w, x, y, z = bat_quaternion(state.bat_angle_rad, state.bat_tilt_rad)
    pb.resetBasePositionAndOrientation(
        bat, [state.bat_x_m, state.bat_y_m, state.bat_z_m], [x, y, z, w], physicsClientId=c
    )
    pb.resetBaseVelocity(
        bat,
        [state.bat_vx_mps, state.bat_vy_mps, state.bat_vz_mps],
        [state.bat_wx_radps, state.bat_wy_radps, state.bat_omega_radps],
        physicsClientId=c,
    )
    pb.resetBasePositionAndOrientation(
        ball,
        [state.ball_x_m, state.ball_y_m, state.ball_z_m],
        [0.0, 0.0, 0.0, 1.0],
        physicsClientId=c,
    )
    pb.resetBaseVelocity(
        ball,
        [state.ball_vx_mps, state.ball_vy_mps, state.ball_vz_mps],
        [state.ball_wx_radps, state.ball_wy_radps, state.ball_omega_radps],
        physicsClientId=c,
    )


def drive_pair(c: int, bat: int, hands: Hands | None):
    """(the hinge's constraint id or None, the load (force, its angle, torque) or None)."""
    if hands is None:
        return None, None
    joint = None
    if hands.pivot_from_com_m is not None:
        joint = pb.createConstraint(
            bat,
            -1,
            -1,
            -1,
            pb.JOINT_POINT2POINT,
            [0.0, 0.0, 0.0],
            [hands.pivot_from_com_m, 0.0, 0.0],
            [*hands.pivot_xy_m, 0.0],
            physicsClientId=c,
        )
    return joint, (hands.force_n, hands.angle_rad, hands.torque_about_com_nm)


def load_pair(c: int, bat: int, load: tuple[float, float, float]) -> None:
    """The hands' force through the COM, turning with the bat, and its constant torque."""
    f, q, torque = load
    pos, (_, _, qz, qw) = pb.getBasePositionAndOrientation(bat, physicsClientId=c)
    angle = 2.0 * math.atan2(qz, qw) + q
    pb.applyExternalForce(
        bat,
        -1,
        [f * math.cos(angle), f * math.sin(angle), 0.0],
        pos,
        pb.WORLD_FRAME,
        physicsClientId=c,
    )
    pb.applyExternalTorque(bat, -1, [0.0, 0.0, torque], pb.WORLD_FRAME, physicsClientId=c)


def read_pair(c: int, bat: int, ball: int, planar: bool) -> State:
    (bx, by, bz), _ = pb.getBasePositionAndOrientation(ball, physicsClientId=c)
    (bvx, bvy, bvz), (bwx, bwy, bw) = pb.getBaseVelocity(ball, physicsClientId=c)
    (cx, cy, cz), (qx, qy, qz, qw) = pb.getBasePositionAndOrientation(bat, physicsClientId=c)
    (cvx, cvy, cvz), (cwx, cwy, cw) = pb.getBaseVelocity(bat, physicsClientId=c)
    angle, tilt = angle_and_tilt(qw, qx, qy, qz, planar)
    return State(
        ball_x_m=bx,
        ball_y_m=by,
        ball_vx_mps=bvx,
        ball_vy_mps=bvy,
        ball_omega_radps=bw,
        bat_x_m=cx,
        bat_y_m=cy,
        bat_angle_rad=angle,
        bat_vx_mps=cvx,
        bat_vy_mps=cvy,
        bat_omega_radps=cw,
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


def _oblique_slide(cone: bool | None) -> State:
    """The state after a ball slides across a heavy still bat at 45 degrees out of the swing
    plane (both friction directions loaded, slipping throughout), with ``cone_friction``
    set to ``cone``."""
    wall = Bat(
        name="wall",
        length_m=0.84,
        radius_m=0.03,
        mass_kg=1e3,
        com_from_knob_m=0.42,
        inertia_cm_kgm2=1e3,
        inertia_axial_kgm2=1e3,
    )
    ball = Ball(name="ball", radius_m=0.0366, mass_kg=0.145)
    settings = dataclasses.replace(RECORD.profiles["reference"], cone_friction=cone)
    engine = PybulletEngine(settings)
    try:
        engine.build(Scene(bat=wall, ball=ball, e=0.5, mu=0.5))
        v, dt = 10.0, settings.dt_s
        engine.set_state(
            State(
                ball_x_m=-6 * v * dt,
                ball_y_m=wall.radius_m + ball.radius_m + 2 * v * dt,
                ball_z_m=-6 * v * dt,
                ball_vx_mps=3 * v,
                ball_vy_mps=-v,
                ball_vz_mps=3 * v,
                ball_omega_radps=0.0,
                bat_x_m=0.0,
                bat_y_m=0.0,
                bat_angle_rad=0.0,
                bat_vx_mps=0.0,
                bat_vy_mps=0.0,
                bat_omega_radps=0.0,
            )
        )
        for _ in range(4):
            engine.step()
        return engine.read()
    finally:
        engine.close()


def _measured_cone_friction() -> bool:
    """Bullet's own ``enableConeFriction``, which it does not report: the slide it gives left
    alone is, bit for bit, the cone's (True) or the box's (False); they differ by sqrt(2)."""
    untouched, cone, box = (_oblique_slide(c) for c in (None, True, False))
    if cone == box or untouched not in (cone, box):
        raise RuntimeError("Bullet's friction model is neither its cone nor its box")
    return untouched == cone
