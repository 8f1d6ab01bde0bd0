"""The Newton adapter: many worlds per call (see the package docstring for solvers and traps)."""

from __future__ import annotations

import numpy as np

from ..frames import angles_and_tilts, bat_quaternions, in_plane
from ..interface import STATE_FIELDS, BatchedEngine, MassProperties, Scene
from . import RECORD, NewtonSettings
from . import device as on_device
from . import scene as sc
from .defaults import read_back
from .gradients import derivative

newton, wp = sc.newton, sc.wp
(BX, BY, BVX, BVY, BW, CX, CY, CA, CVX, CVY, CW, BZ, BVZ, BWX, BWY, CZ, CT, CVZ, CWX, CWY) = range(
    len(STATE_FIELDS)
)


class StateRows(np.ndarray):
    """(n, 20) states whose columns also read by ``State`` field name (a batch of one then
    reads like a ``State``)."""

    def __getattr__(self, name: str):
        if name in STATE_FIELDS:
            return self[..., STATE_FIELDS.index(name)]
        raise AttributeError(name)


class NewtonEngine(BatchedEngine):
    """Newton behind the batched interface: world i holds bodies 2i (bat) and 2i + 1 (ball)."""

    record = RECORD
    settings: NewtonSettings

    def __init__(self, settings: NewtonSettings) -> None:
        super().__init__(settings)
        self.model = None

    @classmethod
    def read_back_defaults(cls) -> dict:
        return read_back()

    def build(self, scene: Scene, worlds: int) -> None:
        st = self.settings
        self.close()
        self.scene, self.n = scene, worlds
        self.model = sc.model(scene, worlds, st)
        self.solver = sc.solver(self.model, st, scene.mu)
        self.pipeline = sc.pipeline(self.model, st)
        self.contacts = self.pipeline.contacts() if self.pipeline is not None else None
        self.control = self.model.control()
        self.states = [self.model.state(), self.model.state()]
        self.shape_world_on = self.model.shape_world
        self.shape_world = self.shape_world_on.numpy()
        self.watched = False
        self.touching, self.planar = np.zeros(worlds, dtype=bool), np.ones(worlds, dtype=bool)
        self.ball_v = np.zeros((worlds, 2), dtype=np.float32)

    def device(self) -> str:
        alias = sc.DEVICE
        return alias if alias == "cpu" else f"{alias}: {wp.get_device(alias).name}"

    def mass_properties(self) -> MassProperties:
        m = self.model
        mass, inertia = m.body_mass.numpy(), m.body_inertia.numpy()
        com = m.body_com.numpy()
        # the capsule's ends: its centre +- (half length + radius) along the axis its transform
        # turns the shape's z onto; the knob is the one at lower x
        xf, scale = m.shape_transform.numpy()[sc.BAT], m.shape_scale.numpy()[sc.BAT]
        x, y, z, w = xf[3:]
        axis_x = 2 * (x * z + w * y)
        knob_x = xf[0] - (scale[1] + scale[0]) * abs(axis_x)
        return MassProperties(
            bat_mass_kg=float(mass[sc.BAT]),
            bat_com_from_knob_m=float(com[sc.BAT][0] - knob_x),
            bat_inertia_kgm2=float(inertia[sc.BAT][2, 2]),
            ball_mass_kg=float(mass[sc.BALL]),
            ball_inertia_kgm2=float(inertia[sc.BALL][2, 2]),
        )

    def set_state(self, states: np.ndarray) -> None:
        """Both bodies of every world; Newton's twists are (v_com, omega), both in the world
        frame (a free joint's too), and its quaternions (x, y, z, w)."""
        s = np.atleast_2d(np.asarray(states, dtype=float))
        s = np.pad(s, ((0, 0), (0, len(STATE_FIELDS) - s.shape[1])))
        n = self.n
        q = np.zeros((n, 2, 7))
        q[:, sc.BAT, :3], q[:, sc.BALL, :3] = s[:, [CX, CY, CZ]], s[:, [BX, BY, BZ]]
        q[:, sc.BAT, 3:] = bat_quaternions(s[:, CA], s[:, CT])[:, [1, 2, 3, 0]]
        q[:, sc.BALL, 6] = 1.0
        qd = np.zeros((n, 2, 6))
        qd[:, sc.BAT] = s[:, [CVX, CVY, CVZ, CWX, CWY, CW]]
        qd[:, sc.BALL] = s[:, [BVX, BVY, BVZ, BWX, BWY, BW]]
        q, qd = q.reshape(-1).astype(np.float32), qd.reshape(-1).astype(np.float32)
        for state in self.states:
            # free joints at the world origin: joint coordinates = body pose and twist
            state.body_q.assign(q.reshape(-1, 7))
            state.body_qd.assign(qd.reshape(-1, 6))
            state.joint_q.assign(q)
            state.joint_qd.assign(qd)
            state.clear_forces()
        if self.settings.solver == "mujoco":
            self.solver.mjw_data.qacc_warmstart.zero_()
        self.touching[:] = False
        self.ball_v = qd.reshape(n, 2, 6)[:, sc.BALL, :3].copy()
        self.planar = in_plane(s)
        self.watched = False  # (a device episode lasts until the next set_state)

    def step(self) -> None:
        s0, s1 = self.states
        if self.pipeline is not None:
            self.pipeline.collide(s0, self.contacts)
        self.solver.step(s0, s1, self.control, self.contacts, self.settings.dt_s)
        self.states = [s1, s0]
        if self.watched:  # the contact flags are the device episode's (``device_episode``)
            return
        v = s1.body_qd.numpy().reshape(self.n, 2, 6)[:, sc.BALL, :3]
        # only a contact changes the ball's velocity: no gravity, no damping on it (its vz
        # counts only out of the plane: in it, it is float32 rounding, never read before)
        moved = np.any(v[:, :2] != self.ball_v[:, :2], axis=1) | (
            ~self.planar & (v[:, 2] != self.ball_v[:, 2])
        )
        self.touching = self._listed() & moved
        self.ball_v = v.copy()

    def _listed(self) -> np.ndarray:
        """Per world, whether the engine held a bat-ball contact in the last step (MuJoCo: one
        closer than its margin, i.e. in the constraint solve)."""
        out = np.zeros(self.n, dtype=bool)
        if self.contacts is None:
            c = self.solver.mjw_data.contact
            count = int(self.solver.mjw_data.nacon.numpy()[0])
            active = c.dist.numpy()[:count] < c.includemargin.numpy()[:count]
            out[c.worldid.numpy()[:count][active]] = True
            return out
        count = int(self.contacts.rigid_contact_count.numpy()[0])
        shapes = self.contacts.rigid_contact_shape0.numpy()[:count]
        out[self.shape_world[shapes[shapes >= 0]]] = True
        return out

    def read(self) -> np.ndarray:
        s = self.states[0]
        q = s.body_q.numpy().astype(float).reshape(self.n, 2, 7)
        qd = s.body_qd.numpy().astype(float).reshape(self.n, 2, 6)
        out = np.empty((len(STATE_FIELDS), self.n)).T  # columns contiguous: no copy in the harness
        out[:, [BX, BY, BZ]] = q[:, sc.BALL, :3]
        out[:, [BVX, BVY, BVZ, BWX, BWY, BW]] = qd[:, sc.BALL]
        out[:, [CX, CY, CZ]] = q[:, sc.BAT, :3]
        out[:, [CVX, CVY, CVZ, CWX, CWY, CW]] = qd[:, sc.BAT]
        yaw, out[:, CT] = angles_and_tilts(q[:, sc.BAT, [6, 3, 4, 5]])
        # a world set in the plane: its yaw as it was always read (``frames_batch``)
        out[:, CA] = np.where(self.planar, 2.0 * np.arctan2(q[:, sc.BAT, 5], q[:, sc.BAT, 6]), yaw)
        return out.view(StateRows)

    def in_contact(self) -> np.ndarray:
        """Per world, the contact flag of the last step (in a device episode, its kernels
        compute it on the device instead: ``device_episode``)."""
        return self.touching.copy()

    def device_episode(self, constants):
        """The episode observed in Warp kernels where the worlds live (``adapters.device``),
        the contact flags computed there too until the next ``set_state``."""
        self.watched = True
        return on_device.episode(self, constants, sc.DEVICE)

    def derivative(self, states, tangents, steps: int, inertia_tangent_kgm2: float = 0.0):
        return derivative(  # wp.Tape through XPBD (its docstring)
            self, states, tangents, steps, inertia_tangent_kgm2
        )

    def failed(self) -> np.ndarray:
        s = self.states[0]
        bad = ~(
            np.isfinite(s.body_q.numpy()).all(axis=1) & np.isfinite(s.body_qd.numpy()).all(axis=1)
        )
        return bad.reshape(self.n, 2).any(axis=1)

    def set_body_restitution(self, *, bat: float, ball: float) -> None:
        """Each shape's restitution (XPBD combines them as their mean)."""
        if self.settings.solver != "xpbd":
            raise NotImplementedError(f"{self.settings.solver} has no restitution parameter")
        values = np.tile(np.array([bat, ball], dtype=np.float32), self.n)
        self.model.shape_material_restitution.assign(values)
        self.solver.notify_model_changed(newton.ModelFlags.SHAPE_PROPERTIES)

    def set_body_friction(self, *, bat: float, ball: float) -> None:
        """Each shape's friction coefficient (XPBD and the penalty solvers combine them as
        their mean, MuJoCo's as their max)."""
        values = np.tile(np.array([bat, ball], dtype=np.float32), self.n)
        self.model.shape_material_mu.assign(values)
        self.solver.notify_model_changed(newton.ModelFlags.SHAPE_PROPERTIES)

    def close(self) -> None:
        self.model = self.solver = self.pipeline = self.contacts = None
