"""The MuJoCo Warp adapter: MuJoCo's MJCF put on a Warp device, every world stepped by one
``mujoco_warp.step`` (see the package docstring for the regulariser and the precision).

The hands' site position and hinge anchors are model fields: the model is put with one copy of
each per world (``put_model(batch_sizes=...)``), so each world drives its own bat. Overflow
messages are not printed (the print mask is zero): ``failed`` reads the per-world bits.
"""

from __future__ import annotations

import os
import warnings
from collections.abc import Sequence

import mujoco
import numpy as np

from ..frames import in_plane, mujoco_coordinates, mujoco_rows
from ..interface import STATE_FIELDS, BatchedEngine, Hands, MassProperties, Scene
from ..loading import import_engine, stdout_silenced
from ..mujoco.model import port_model
from . import INTEGRATORS, RECORD

mjw = import_engine(RECORD)
import warp as wp  # noqa: E402  (mujoco_warp brings Warp; imported after the install check)

from . import device as on_device  # noqa: E402  (Warp's kernels: after the check too)

wp.config.log_level = wp.LOG_WARNING  # no banner, no line per loaded module on stdout
with stdout_silenced():  # Warp's native init warns on stderr where no CUDA driver is found
    wp.init()

#: Overflows that lose contacts or constraints: the worlds' results are then wrong. The solver's
#: iteration limits are not among them (a float32 solve at a small tolerance often meets them).
LOST = int(mjw.OverflowType.ALL & ~(mjw.OverflowType.ITERATIONS | mjw.OverflowType.LS_ITERATIONS))
#: Per world: one contact (bat-ball) and, with the hands, three connect rows.
NCONMAX, NJMAX = 4, 8
#: Model fields put once per world, so that each world has its own hands.
PER_WORLD = ("site_pos", "eq_data")


def _device(settings) -> str:
    """The Warp device the settings ask for (package docstring)."""
    return settings.device or os.environ.get("BATSIM_WARP_DEVICE") or str(wp.get_device())


class CapturedStep:
    """``mujoco_warp.step`` of one model and data, recorded once (Warp's graph capture, on a
    CPU too since Warp 1.13) and replayed: the same kernels in the same order, the solver's
    convergence loop a recorded ``capture_while``, so the same bits. On a CPU the step's ~370
    launches cost 10-18 ms from Python and 0.05 ms replayed. The arrays are recorded, not
    their values: a new model or data needs a new capture."""

    def __init__(self, model, data, device: str) -> None:
        self.device = device
        with wp.ScopedDevice(device), wp.ScopedCapture() as capture:
            mjw.step(model, data)  # recorded, not run
        self.graph = capture.graph

    def __call__(self) -> None:
        with wp.ScopedDevice(self.device):
            wp.capture_launch(self.graph)


class MjwarpEngine(BatchedEngine):
    """MuJoCo Warp behind the batched interface, in float32."""

    record = RECORD

    @classmethod
    def read_back_defaults(cls) -> dict:
        m = mujoco.MjModel.from_xml_string(
            '<mujoco><worldbody><geom size="1"/></worldbody></mujoco>'
        )
        with wp.ScopedDevice("cpu"):
            mw = mjw.put_model(m)
        o = mw.opt
        return {
            "solref": tuple(mw.geom_solref.numpy()[0, 0].tolist()),
            "solimp": tuple(mw.geom_solimp.numpy()[0, 0].tolist()),
            "iterations": int(o.iterations),
            "tolerance": float(o.tolerance.numpy()[0]),
            "ls_iterations": int(o.ls_iterations),
            "dt_s": float(o.timestep.numpy()[0]),
            "integrator": next(
                i
                for i in INTEGRATORS
                if int(o.integrator) == getattr(mujoco.mjtIntegrator, f"mjINT_{i.upper()}")
            ),
            "cone": "elliptic" if int(o.cone) == mujoco.mjtCone.mjCONE_ELLIPTIC else "pyramidal",
        }

    def device(self) -> str:
        alias = _device(self.settings)
        return alias if alias == "cpu" else f"{alias}: {wp.get_device(alias).name}"

    def derivative(self, states, tangents, steps: int, inertia_tangent_kgm2: float = 0.0):
        raise NotImplementedError(no_adjoints())

    def device_episode(self, constants):
        """The episode observed in Warp kernels where the worlds live (``adapters.device``)."""
        return on_device.episode(self, constants)

    def build(self, scene: Scene, worlds: int) -> None:
        st = self.settings
        m = port_model(mujoco, scene, st)
        ids = {
            (obj, name): mujoco.mj_name2id(m, obj, name)
            for obj, name in (
                (mujoco.mjtObj.mjOBJ_BODY, "bat"),
                (mujoco.mjtObj.mjOBJ_BODY, "ball"),
                (mujoco.mjtObj.mjOBJ_GEOM, "bat"),
                (mujoco.mjtObj.mjOBJ_SITE, "load"),
            )
        }
        self._bat, self._ball, self._geom, self._site = ids.values()
        self._ball_geom = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_GEOM, "ball")
        self.n, self._dev = worlds, _device(st)
        with wp.ScopedDevice(self._dev), warnings.catch_warnings():
            # a pair's geoms carry condim 3 and friction 0, never combined (the pair is the
            # contact): put_model's warning that such a geom "may cause NaN" does not apply
            warnings.filterwarnings("ignore", message=r"geom \d+: friction\[0\]")
            self.model = mjw.put_model(m, batch_sizes={f: worlds for f in PER_WORLD})
            self.model.opt.tolerance.fill_(st.tolerance)  # put_model raised it to >= 1e-6
            self.model.opt.warn_overflow = 0
            self.data = mjw.make_data(m, nworld=worlds, nconmax=NCONMAX, njmax=NJMAX)
        self._site_pos0 = self.model.site_pos.numpy()
        self._eq_data0 = self.model.eq_data.numpy()
        self._planar = np.ones(worlds, dtype=bool)
        self._step = CapturedStep(self.model, self.data, self._dev)

    def set_body_friction(self, *, bat: float, ball: float) -> None:
        """Each geom's own sliding friction (MuJoCo Warp combines them by max); as in MuJoCo
        C, an explicit pair (a tuned contact with friction) keeps the friction it was built
        with."""
        friction = self.model.geom_friction.numpy()
        friction[:, [self._geom, self._ball_geom], 0] = (bat, ball)
        self.model.geom_friction.assign(friction)

    def mass_properties(self) -> MassProperties:
        mw = self.model
        mass, ipos = mw.body_mass.numpy()[0], mw.body_ipos.numpy()[0]
        iquat, inertia = mw.body_iquat.numpy()[0], mw.body_inertia.numpy()[0]

        def about_z(body: int) -> float:
            rot = np.zeros(9)
            mujoco.mju_quat2Mat(rot, iquat[body].astype(float))  # stored (w, x, y, z)
            rot = rot.reshape(3, 3)
            return float((rot @ np.diag(inertia[body].astype(float)) @ rot.T)[2, 2])

        pos, size = mw.geom_pos.numpy()[0, self._geom], mw.geom_size.numpy()[0, self._geom]
        knob_x = float(pos[0]) - float(size[1]) - float(size[0])
        return MassProperties(
            bat_mass_kg=float(mass[self._bat]),
            bat_com_from_knob_m=float(ipos[self._bat][0]) - knob_x,
            bat_inertia_kgm2=about_z(self._bat),
            ball_mass_kg=float(mass[self._ball]),
            ball_inertia_kgm2=about_z(self._ball),
        )

    def set_state(self, states: np.ndarray) -> None:
        """Every world's pose and velocity; time, warm starts and overflow bits zeroed, the
        hands let go (the harness sets a drive after the state)."""
        s = np.asarray(states, dtype=float)
        s = np.pad(s, ((0, 0), (0, len(STATE_FIELDS) - s.shape[1])))
        qpos, qvel = mujoco_coordinates(s)
        self._planar = in_plane(s)
        d = self.data
        d.qpos.assign(qpos.astype(np.float32))
        d.qvel.assign(qvel.astype(np.float32))
        for arr in (d.time, d.qacc_warmstart, d.qacc, d.act, d.overflow, d.nacon):
            arr.zero_()
        self.set_drive(None)

    def set_drive(self, hands: Sequence[Hands] | None) -> None:
        # Site motors act in the bat's frame; the hands' hinge is the connect equality:
        # eq_data[0:3] the anchor in the bat's frame, [3:6] the point in the world's.
        d, mw = self.data, self.model
        if hands is None:
            d.ctrl.zero_()
            d.eq_active.zero_()
            return
        if len(hands) != self.n:
            raise ValueError(f"{len(hands)} hands for {self.n} worlds; allowed: one per world")
        arm = np.array([h.arm_m for h in hands])
        pivot = np.array(
            [np.nan if h.pivot_from_com_m is None else h.pivot_from_com_m for h in hands]
        )
        pivot_xy = np.array([h.pivot_xy_m for h in hands], dtype=float).reshape(-1, 2)
        angle = np.array([h.angle_rad for h in hands])
        force = np.array([h.force_n for h in hands])
        hinged = ~np.isnan(pivot)
        site_pos, eq_data = self._site_pos0.copy(), self._eq_data0.copy()
        site_pos[:, self._site, 0] = arm
        zero = np.zeros(len(hands))
        anchors = np.stack([pivot, zero, zero, pivot_xy[:, 0], pivot_xy[:, 1], zero], axis=1)
        eq_data[:, 0, :6] = np.where(hinged[:, None], anchors, eq_data[:, 0, :6])
        mw.site_pos.assign(site_pos)
        mw.eq_data.assign(eq_data)
        d.eq_active.assign(hinged[:, None])
        d.ctrl.assign(
            np.stack(
                [force * np.cos(angle), force * np.sin(angle), [h.torque_nm for h in hands]], axis=1
            ).astype(np.float32)
        )

    def step(self) -> None:
        self._step()

    def read(self) -> np.ndarray:
        return mujoco_rows(
            self.data.qpos.numpy().astype(float), self.data.qvel.numpy().astype(float), self._planar
        )

    def in_contact(self) -> np.ndarray:
        """A contact of the world in the list and overlapping (margin 0: the list holds only
        those; the distance test keeps that true whatever the margin)."""
        c = self.data.contact
        k = min(int(self.data.nacon.numpy()[0]), self.data.naconmax)
        touching = c.worldid.numpy()[:k][c.dist.numpy()[:k] < 0.0]
        return np.bincount(touching, minlength=self.n)[: self.n] > 0

    def failed(self) -> np.ndarray:
        d = self.data
        finite = np.isfinite(d.qpos.numpy()).all(axis=1) & np.isfinite(d.qvel.numpy()).all(axis=1)
        return ~finite | (d.overflow.numpy() & LOST != 0)

    def close(self) -> None:
        self.model = self.data = None


#: The modules of ``mjw.step`` (forward dynamics, collision, constraints, solver).
STEP_MODULES = ("forward", "smooth", "collision_primitive", "constraint", "solver")


def no_adjoints() -> str:
    """Why Warp's tape cannot differentiate ``mjw.step``: the modules of the step that
    MuJoCo Warp compiles without adjoints, as Warp reports their options."""
    off = [
        n
        for n in STEP_MODULES
        if not wp.get_module(f"mujoco_warp._src.{n}").options.get("enable_backward", True)
    ]
    if not off:
        return "MuJoCo Warp compiles its step with adjoints; this adapter records no wp.Tape"
    return (
        f"MuJoCo Warp compiles {', '.join(off)} without adjoints (Warp's enable_backward "
        "False): wp.Tape cannot differentiate mjw.step"
    )
