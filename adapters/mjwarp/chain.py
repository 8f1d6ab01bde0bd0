"""MuJoCo Warp's segmented bat (``adapters.segmented``): MuJoCo C's chain
(``adapters.mujoco.chain``: a kinematic tree of capsules, the root free, each child hinged
about z at its knob end with the hinge's own ``stiffness`` and ``damping``, segments colliding
with the ball only) at the port's settings (``adapters.mjx._port_chain.host_chain``, shared
with MJX's chain), put on a Warp device with ``mujoco_warp.put_model`` (the settings'
tolerance written back, as the bat adapter does) and stepped one world at a time.

Springs: MuJoCo Warp's passive force on hinge j is -stiffness (q_j - qpos_spring_j) - damping
qd_j (``mujoco_warp/_src/passive.py``, ``_spring_damper_dof_passive``; as C's
``engine_passive.c``), in N m per rad: the MJCF's ``stiffness`` IS k_j, no conversion. Its
Euler integrates the damping implicitly (``forward.py``: ``_euler_damp_qfrc``, M + dt D), the
spring explicitly, as C's.

The state is set and read through the host's MuJoCo C data (``MujocoChain.set_state``, and
C's kinematics in float64 on the port's float32 qpos and qvel for the COM rows). Kernels
compile once into Warp's cache (15 s cold); a step of one N = 8 chain world costs 15-25 ms
on a loaded 2-core CPU (a host loop of ~100 launches).

Quirks (mujoco-warp 4.0.0, warp-lang 1.19.0, CPU): at N = 8 the reference matches the linear
chain on single touches to 1e-3..6e-3 m/s; at N = 16 and 64 the float32 solve of the first
touch (the regulariser d = 0.9998 on segments of 1e-5 kg m^2 and less) returns NaN qpos,
qvel and qacc (MuJoCo C without diagexact and MJX in float64 stay finite). ``failed`` counts a
non-finite qacc as MuJoCo C does (``mjWARN_BADQACC``).
"""

from __future__ import annotations

import numpy as np

from ..mjx._port_chain import host_chain, read_through, segment_rows
from ..segmented import ChainEngine, ChainScene
from . import RECORD
from .adapter import LOST, CapturedStep, _device, mjw, wp


class MjwarpChain(ChainEngine):
    """MuJoCo Warp's segmented bat, one world, in float32."""

    record = RECORD

    def build(self, scene: ChainScene) -> None:
        st = self.settings
        self._host = host_chain(st, scene)
        self.n, self._dev = scene.chain.segments, _device(st)
        m = self._host.model
        with wp.ScopedDevice(self._dev):
            self.model = mjw.put_model(m)
            self.model.opt.tolerance.fill_(st.tolerance)  # put_model raised it to >= 1e-6
            self.model.opt.warn_overflow = 0
            # one contact row per touching segment (condim 1): at most every segment
            self.data = mjw.make_data(m, nworld=1, nconmax=self.n, njmax=self.n)
        self._step = CapturedStep(self.model, self.data, self._dev)

    def mass_properties(self) -> np.ndarray:
        mw = self.model
        return segment_rows(
            self._host, mw.body_mass.numpy()[0], mw.body_ipos.numpy()[0], mw.body_inertia.numpy()[0]
        )

    def set_state(self, ball: np.ndarray, segments: np.ndarray) -> None:
        h, d = self._host, self.data
        h.set_state(ball, segments)
        d.qpos.assign(h.data.qpos[None, :].astype(np.float32))
        d.qvel.assign(h.data.qvel[None, :].astype(np.float32))
        for arr in (d.time, d.qacc_warmstart, d.qacc, d.act, d.overflow, d.nacon):
            arr.zero_()

    def step(self) -> None:
        self._step()

    def read(self) -> tuple[np.ndarray, np.ndarray]:
        return read_through(self._host, self.data.qpos.numpy(), self.data.qvel.numpy())

    def in_contact(self) -> bool:
        """A contact in the list and overlapping (margin 0: the list holds only those)."""
        c = self.data.contact
        k = min(int(self.data.nacon.numpy()[0]), self.data.naconmax)
        return bool(np.any(c.dist.numpy()[:k] < 0.0))

    def failed(self) -> bool:
        """A non-finite qpos, qvel or qacc (MuJoCo C's chain: mjWARN_BADQPOS/QVEL/QACC) or
        an overflow that lost contacts or constraints (the bat adapter's bits)."""
        d = self.data
        finite = all(np.isfinite(a.numpy()).all() for a in (d.qpos, d.qvel, d.qacc))
        return not finite or bool(d.overflow.numpy()[0] & LOST)

    def close(self) -> None:
        self.model = self.data = None
