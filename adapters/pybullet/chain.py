"""PyBullet's segmented bat (``adapters.segmented``): one multibody, segment 0 its floating
base and segment i its link i, each child on a revolute joint about z at its knob end; the ball
a base-only multibody as in the bat adapter. A multibody built without
``URDF_USE_SELF_COLLISION`` does not collide with itself: segments meet only the ball.

The joints' springs: Bullet's multibody joints have no spring. PyBullet's ``PD_CONTROL`` (its
statically linked pdControlPlugin) is the engine's own joint drive: before every step it reads
each joint and applies the torque kp (q* - q) + kd (qd* - qd), clamped to +-maxForce, as a
joint torque (bullet3 examples/SharedMemory/plugins/pdControlPlugin/pdControlPlugin.cpp,
``preTickPluginCallback_pdControlPlugin``). With q* = qd* = 0, kp = k_j and kd = c_j it IS
the spring-damper in N m/rad and N m s/rad (no conversion), but EXPLICIT: the torque is the
step's start state's, integrated by the multibody's semi-implicit Euler. Measured: bit for bit
the same as a TORQUE_CONTROL of -k q - c qd set from Python before each step, and its damping
as Bullet's own ``jointDamping`` (also explicit). Default velocity motors (a constraint row
each) are switched off with VELOCITY_CONTROL at force 0. Being explicit, the springs are
stable only while omega_max dt < 2 (omega_max the chain's stiffest mode): at dt = 1e-5 s
N = 20 (1.67) runs, N = 24 (2.14) and N = 64 (6.7) blow up at the first touch, as does N = 8
at the default 1/240 s (omega_1 dt = 4.8); N = 64 at dt = 2e-6 s runs. The multibody beats
separate bodies joined by JOINT_POINT2POINT: its joints are coordinates, so a touch's impulse
sees the chain exactly (one touch at N = 8: 5e-14 m/s off the reference, the constraint chain
solved iteratively 1.1e-5 m/s).

Other quirks (measured): ``createMultiBody`` takes each link's position in its parent's link
frame, ``getJointInfo`` gives it back in the parent's inertial (COM) frame, and
``getDynamicsInfo`` each link's COM in its own link frame; ``getLinkState``'s link-frame
position is float32-rounded (its COM position is not: read the COM). ``maxJointVelocity``
(100 unless raised) is per multibody and clamps every coordinate rate, base linear velocity
too (a ball at 150 m/s leaves the step at 100): raised as the bat adapter raises it, and a rate
at the cap is a failure (``failed``). A link's ``changeDynamics`` that also names a multibody
value (linearDamping, angularDamping, maxJointVelocity) puts the link's mass and inertia on
the base: those are set apart, on the base, without mass. Restitution and friction are set
per link: bat 1, ball e (Bullet multiplies them), all friction and damping 0.
"""

from __future__ import annotations

import math

import numpy as np

from ..loading import import_engine
from ..segmented import ChainEngine, ChainScene
from . import ENGINE_PARAMETERS, RECORD, PybulletSettings
from .adapter import PybulletEngine

pb = import_engine(RECORD)

#: The PD drive's torque clamp (N m): none in effect.
NO_CLAMP_NM = 1e30
#: Bullet's own ``maxJointVelocity`` (btMultiBody's default), where settings leave it.
ENGINE_RATE_CAP = 100.0


class PybulletChain(ChainEngine):
    """PyBullet's segmented bat, at the bat adapter's settings and restitution mapping."""

    record = RECORD

    def __init__(self, settings: PybulletSettings) -> None:
        super().__init__(settings)
        self._client: int | None = None
        self._scene: ChainScene | None = None
        self._stepped = False

    def build(self, scene: ChainScene) -> None:
        self._scene = scene
        if self._client is None:
            self._client = pb.connect(pb.DIRECT)
        c, st = self._client, self.settings
        pb.resetSimulation(physicsClientId=c)
        pb.setGravity(0, 0, 0, physicsClientId=c)
        params = {
            kw: getattr(st, name)
            for name, kw in ENGINE_PARAMETERS.items()
            if getattr(st, name) is not None
        }
        pb.setPhysicsEngineParameter(
            fixedTimeStep=st.dt_s, numSubSteps=0, physicsClientId=c, **params
        )
        self._bat = self._chain_body(scene)
        ball = scene.ball
        shape = pb.createCollisionShape(pb.GEOM_SPHERE, radius=ball.radius_m, physicsClientId=c)
        self._ball = pb.createMultiBody(
            ball.mass_kg, shape, basePosition=[0.0, 1.0, 0.0], physicsClientId=c
        )
        ib = ball.inertia_kgm2
        self._dynamics(self._ball, -1, ball.mass_kg, [ib, ib, ib], restitution=scene.e)
        self._springs(scene)
        self._stepped = False

    def _chain_body(self, scene: ChainScene) -> int:
        """The multibody: every frame at its segment's knob end, the COM offset along x."""
        c, chain = self._client, scene.chain
        ell, r, n = chain.segment_length_m, chain.bat.radius_m, chain.segments
        along_x = pb.getQuaternionFromEuler([0.0, math.pi / 2, 0.0])  # capsules lie along z
        shapes = [
            pb.createCollisionShape(
                pb.GEOM_CAPSULE,
                radius=r,
                height=ell,
                collisionFramePosition=[ell / 2, 0.0, 0.0],
                collisionFrameOrientation=along_x,
                physicsClientId=c,
            )
            for _ in range(n)
        ]
        offsets = [[com - i * ell, 0.0, 0.0] for i, com in enumerate(chain.coms_m)]
        links = n - 1
        body = pb.createMultiBody(
            chain.masses_kg[0],
            shapes[0],
            basePosition=[-chain.bat.com_from_knob_m, 0.0, 0.0],
            baseInertialFramePosition=offsets[0],
            linkMasses=list(chain.masses_kg[1:]),
            linkCollisionShapeIndices=shapes[1:],
            linkVisualShapeIndices=[-1] * links,
            linkPositions=[[ell, 0.0, 0.0]] * links,
            linkOrientations=[[0, 0, 0, 1]] * links,
            linkInertialFramePositions=offsets[1:],
            linkInertialFrameOrientations=[[0, 0, 0, 1]] * links,
            linkParentIndices=list(range(links)),
            linkJointTypes=[pb.JOINT_REVOLUTE] * links,
            linkJointAxis=[[0.0, 0.0, 1.0]] * links,
            physicsClientId=c,
        )
        for i, (m, inertia) in enumerate(zip(chain.masses_kg, chain.inertias_kgm2, strict=True)):
            axial = min(0.5 * m * r * r, 2.0 * inertia)  # a valid tensor (adapters.segmented)
            self._dynamics(body, i - 1, m, [axial, inertia, inertia], restitution=1.0)
        return body

    def _dynamics(
        self, body: int, link: int, mass: float, inertia: list[float], restitution: float
    ) -> None:
        """The bat adapter's per-body values: mass, inertia, no friction, restitution (bat 1,
        ball e: Bullet multiplies them); the multibody's own values set apart (see
        ``_multibody``)."""
        if link == -1:
            self._multibody(body)
        extra = {}
        if self.settings.ccd_swept_sphere_radius > 0.0:  # per collider
            extra["ccdSweptSphereRadius"] = self.settings.ccd_swept_sphere_radius
        pb.changeDynamics(
            body,
            link,
            mass=mass,
            localInertiaDiagonal=inertia,
            lateralFriction=0.0,
            spinningFriction=0.0,
            rollingFriction=0.0,
            jointDamping=0.0,
            restitution=restitution,
            physicsClientId=self._client,
            **extra,
        )

    def _multibody(self, body: int) -> None:
        """No damping, the angular cap lifted: values of the whole multibody, set on its base
        with no mass (measured: a link's ``changeDynamics`` that also names linearDamping,
        angularDamping or maxJointVelocity puts that link's mass and inertia on the BASE)."""
        cap = self.settings.max_joint_velocity_radps
        extra = {} if cap is None else {"maxJointVelocity": cap}
        pb.changeDynamics(
            body, -1, linearDamping=0.0, angularDamping=0.0, physicsClientId=self._client, **extra
        )

    def _springs(self, scene: ChainScene) -> None:
        """Velocity motors off; the PD drive kp = k_j (N m/rad), kd = c_j (N m s/rad) toward
        the straight chain (pdControlPlugin: torque = kp (q* - q) + kd (qd* - qd))."""
        chain, c = scene.chain, self._client
        joints = list(range(chain.segments - 1))
        zeros = [0.0] * len(joints)
        pb.setJointMotorControlArray(
            self._bat, joints, pb.VELOCITY_CONTROL, forces=zeros, physicsClientId=c
        )
        pb.setJointMotorControlArray(
            self._bat,
            joints,
            pb.PD_CONTROL,
            targetPositions=zeros,
            targetVelocities=zeros,
            positionGains=list(chain.stiffnesses_nmprad),
            velocityGains=list(chain.dampings_nmsprad),
            forces=[NO_CLAMP_NM] * len(joints),
            physicsClientId=c,
        )

    def mass_properties(self) -> np.ndarray:
        """Masses and inertias as held; each COM from the knob chained through the joints'
        frames as held (base COM in its frame at the knob, then parent COM + joint offset
        in the parent's COM frame + the link's COM in its joint frame)."""
        c, n = self._client, self._scene.chain.segments
        rows, com = [], 0.0
        for link in range(-1, n - 1):
            info = pb.getDynamicsInfo(self._bat, link, physicsClientId=c)
            if link >= 0:
                com += pb.getJointInfo(self._bat, link, physicsClientId=c)[14][0]
            com += info[3][0]
            rows.append((info[0], com, info[2][2]))
        return np.array(rows, dtype=float)

    def set_state(self, ball: np.ndarray, segments: np.ndarray) -> None:
        if self._stepped:  # a fresh world: no contact manifold or warm start survives
            self.build(self._scene)
        c = self._client
        x, y, a, vx, vy, w = segments[0]
        pb.resetBasePositionAndOrientation(  # base calls refer to the COM; (x, y, z, w)
            self._bat, [x, y, 0.0], [0.0, 0.0, math.sin(a / 2), math.cos(a / 2)], physicsClientId=c
        )
        pb.resetBaseVelocity(self._bat, [vx, vy, 0.0], [0.0, 0.0, w], physicsClientId=c)
        for j, (q, qd) in enumerate(
            zip(np.diff(segments[:, 2]), np.diff(segments[:, 5]), strict=True)
        ):
            pb.resetJointState(self._bat, j, float(q), float(qd), physicsClientId=c)
        pb.resetBasePositionAndOrientation(
            self._ball, [ball[0], ball[1], 0.0], [0.0, 0.0, 0.0, 1.0], physicsClientId=c
        )
        pb.resetBaseVelocity(
            self._ball, [ball[2], ball[3], 0.0], [0.0, 0.0, 0.0], physicsClientId=c
        )

    def step(self) -> None:
        pb.stepSimulation(physicsClientId=self._client)
        self._stepped = True

    def read(self) -> tuple[np.ndarray, np.ndarray]:
        c, n = self._client, self._scene.chain.segments
        pos, orn = pb.getBasePositionAndOrientation(self._bat, physicsClientId=c)
        vel, omega = pb.getBaseVelocity(self._bat, physicsClientId=c)
        frames = [(pos, orn, vel, omega)]
        if n > 1:
            states = pb.getLinkStates(
                self._bat,
                list(range(n - 1)),
                computeLinkVelocity=1,
                computeForwardKinematics=1,
                physicsClientId=c,
            )
            frames += [(s[0], s[1], s[6], s[7]) for s in states]  # COM frame, world velocity
        rows = [(p[0], p[1], _yaw(q), v[0], v[1], w[2]) for p, q, v, w in frames]
        (bx, by, _), _ = pb.getBasePositionAndOrientation(self._ball, physicsClientId=c)
        (bvx, bvy, _), _ = pb.getBaseVelocity(self._ball, physicsClientId=c)
        return np.array([bx, by, bvx, bvy]), np.array(rows, dtype=float)

    def in_contact(self) -> bool:
        # the bat adapter's test on self._bat (here the whole chain, every link) and self._ball
        return PybulletEngine.in_contact(self)  # type: ignore[arg-type]

    def failed(self) -> bool:
        """True if a coordinate rate sits at the multibody's cap: Bullet clamps every base and
        joint rate to +-maxJointVelocity each step, which hides a blow-up (measured: the
        explicit springs at omega_max dt > 2 saturate at the cap, finite, not diverging)."""
        c, cap = self._client, self.settings.max_joint_velocity_radps or ENGINE_RATE_CAP
        rates = [
            q[1]
            for q in pb.getJointStates(
                self._bat, list(range(self._scene.chain.segments - 1)), physicsClientId=c
            )
        ]
        for body in (self._bat, self._ball):
            rates += [x for part in pb.getBaseVelocity(body, physicsClientId=c) for x in part]
        return max(abs(x) for x in rates) >= cap

    def close(self) -> None:
        if self._client is not None:
            pb.disconnect(physicsClientId=self._client)
            self._client = None

    def __del__(self) -> None:
        try:
            self.close()
        except Exception:  # interpreter shutdown: the module may be gone already
            pass


def _yaw(q: tuple[float, float, float, float]) -> float:
    """The rotation about z of a Bullet quaternion (x, y, z, w)."""
    x, y, z, w = q
    return math.atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z))
