"""MuJoCo's segmented bat (``adapters.segmented``): a kinematic tree of capsules, each child
hinged about z at its start with the joint's own ``stiffness`` and ``damping`` (MuJoCo
integrates both implicitly in its implicit integrators, explicitly in Euler's and RK4), the
root free. Segments collide with the ball only (contype/conaffinity bits)."""

from __future__ import annotations

import numpy as np

from ..loading import import_engine
from ..segmented import ChainEngine, ChainScene
from . import RECORD
from .adapter import BLOW_UPS, apply_options
from .model import contact_parameters

mujoco = import_engine(RECORD)


def chain_mjcf(scene: ChainScene) -> str:
    """Nested bodies, each framed at its segment's knob end; the ball last."""
    chain, ball = scene.chain, scene.ball
    ell, r = chain.segment_length_m, chain.bat.radius_m
    ib = ball.inertia_kgm2
    opened, closed = [], []
    for i, (m, c, J) in enumerate(
        zip(chain.masses_kg, chain.coms_m, chain.inertias_kgm2, strict=True)
    ):
        axial = min(0.5 * m * r * r, 2.0 * J)  # a valid tensor (adapters.segmented)
        joint = (
            '<freejoint name="root"/>'
            if i == 0
            else f'<joint name="j{i}" type="hinge" axis="0 0 1" '
            f'stiffness="{chain.stiffnesses_nmprad[i - 1]!r}" '
            f'damping="{chain.dampings_nmsprad[i - 1]!r}"/>'
        )
        opened.append(
            f'<body name="s{i}" pos="{0.0 if i == 0 else ell!r} 0 0">{joint}'
            f'<inertial pos="{c - i * ell!r} 0 0" mass="{m!r}" '
            f'diaginertia="{axial!r} {J!r} {J!r}"/>'
            f'<geom name="g{i}" type="capsule" fromto="0 0 0 {ell!r} 0 0" '
            f'size="{r!r}" contype="1" conaffinity="2"/>'
        )
        closed.append("</body>")
    return f"""<mujoco model="chain_ball">
  <compiler angle="radian" inertiafromgeom="false"/>
  <option gravity="0 0 0"/>
  <default><geom condim="1" friction="0 0 0" margin="0" gap="0"/></default>
  <worldbody>
    {"".join(opened)}{"".join(closed)}
    <body name="ball" pos="0 1 0">
      <freejoint name="ball"/>
      <inertial pos="0 0 0" mass="{ball.mass_kg!r}" diaginertia="{ib!r} {ib!r} {ib!r}"/>
      <geom name="ball" type="sphere" size="{ball.radius_m!r}" contype="2" conaffinity="1"/>
    </body>
  </worldbody>
</mujoco>"""


class MujocoChain(ChainEngine):
    """MuJoCo C's segmented bat, at the bat adapter's settings and contact mapping."""

    record = RECORD

    def build(self, scene: ChainScene) -> None:
        st = self.settings
        m = mujoco.MjModel.from_xml_string(chain_mjcf(scene))
        apply_options(m, st, cone=False)  # frictionless: condim 1
        m.geom_solref[:], m.geom_solimp[:] = contact_parameters(st, scene.e)
        self.model, self.data = m, mujoco.MjData(m)
        self.n = scene.chain.segments
        self._ell = scene.chain.segment_length_m
        self._ball = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_BODY, "ball")
        self._segs = [
            mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_BODY, f"s{i}") for i in range(self.n)
        ]

    def mass_properties(self) -> np.ndarray:
        m = self.model
        rows = [
            (m.body_mass[b], m.body_ipos[b][0] + i * self._ell, m.body_inertia[b][2])
            for i, b in enumerate(self._segs)
        ]
        return np.array(rows, dtype=float)

    def set_state(self, ball: np.ndarray, segments: np.ndarray) -> None:
        d, m = self.data, self.model
        d.time = 0.0
        d.qacc_warmstart[:] = 0.0
        for w in BLOW_UPS:
            d.warning[w].number = 0
        x, y, a, vx, vy, w = segments[0]
        c, s = np.cos(a), np.sin(a)
        off = m.body_ipos[self._segs[0]][0]  # COM from the root's frame (its knob end)
        knob = np.array([x - c * off, y - s * off])
        v_knob = np.array([vx + w * s * off, vy - w * c * off])
        d.qpos[:] = 0.0
        d.qpos[0:7] = (*knob, 0.0, np.cos(a / 2), 0.0, 0.0, np.sin(a / 2))
        d.qpos[-7:] = (ball[0], ball[1], 0.0, 1.0, 0.0, 0.0, 0.0)
        d.qpos[7 : 7 + self.n - 1] = np.diff(segments[:, 2])
        d.qvel[:] = 0.0
        d.qvel[0:6] = (*v_knob, 0.0, 0.0, 0.0, w)  # angular velocity in the body's frame: z
        d.qvel[6 : 6 + self.n - 1] = np.diff(segments[:, 5])
        d.qvel[-6:] = (ball[2], ball[3], 0.0, 0.0, 0.0, 0.0)
        mujoco.mj_forward(m, d)

    def step(self) -> None:
        mujoco.mj_step(self.model, self.data)

    def read(self) -> tuple[np.ndarray, np.ndarray]:
        m, d = self.model, self.data
        for stage in (mujoco.mj_kinematics, mujoco.mj_comPos, mujoco.mj_comVel):
            stage(m, d)  # mj_step leaves them at the step's start
        vel = np.zeros(6)
        rows = []
        for b in self._segs:
            mujoco.mj_objectVelocity(m, d, mujoco.mjtObj.mjOBJ_BODY, b, vel, 0)
            xmat = d.xmat[b]
            rows.append(
                (d.xipos[b][0], d.xipos[b][1], np.arctan2(xmat[3], xmat[0]), vel[3], vel[4], vel[2])
            )
        mujoco.mj_objectVelocity(m, d, mujoco.mjtObj.mjOBJ_BODY, self._ball, vel, 0)
        ball = np.array([d.xipos[self._ball][0], d.xipos[self._ball][1], vel[3], vel[4]])
        return ball, np.array(rows)

    def in_contact(self) -> bool:
        return self.data.ncon > 0

    def failed(self) -> bool:
        return any(self.data.warning[w].number for w in BLOW_UPS)
