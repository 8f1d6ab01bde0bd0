"""The MuJoCo adapter (see the package docstring for the contact mappings and their traps)."""

from __future__ import annotations

import copy
import functools
import math

import numpy as np

from ..frames import angle_and_tilt, bat_quaternion, in_the_plane, rotate
from ..interface import Engine, Hands, MassProperties, Scene, State
from ..loading import feature, import_engine
from . import INTEGRATORS, RECORD
from .model import contact_parameters, mjcf, pair_parameters

mujoco = import_engine(RECORD)
# MuJoCo's own warning handler prints and appends to MUJOCO_LOG.TXT in the working directory;
# the adapter reads the warning counters instead (``failed``), so the text is dropped.
mujoco.set_mju_user_warning(lambda text: None)
#: Warnings that mean the state blew up. MuJoCo resets the state after them, and with it the
#: counters, before it counts the warning again: so a counter reads 1 however many blow-ups
#: came before; ``set_state`` zeroes them and any count since is a failure.
BLOW_UPS = tuple(
    int(w)
    for w in (
        mujoco.mjtWarning.mjWARN_BADQPOS,
        mujoco.mjtWarning.mjWARN_BADQVEL,
        mujoco.mjtWarning.mjWARN_BADQACC,
    )
)


@functools.lru_cache(maxsize=16)
def compiled(xml: str):
    """The model compiled from ``xml``, shared read-only: each adapter steps its own copy (a
    copy costs a sixth of a compile, so that many engines of one scene are cheap to make)."""
    return mujoco.MjModel.from_xml_string(xml)


def apply_options(m, st, cone: bool = True) -> None:
    """The settings' solver options on a compiled model (the segmented bat's too); without
    ``cone``, the model's own cone (a frictionless model: its ports, MJX, refuse condim 1 in
    an elliptic cone, as ``model.port_model`` knows)."""
    if cone:
        m.opt.cone = getattr(mujoco.mjtCone, f"mjCONE_{st.cone.upper()}")
    m.opt.timestep = st.dt_s
    m.opt.integrator = getattr(mujoco.mjtIntegrator, f"mjINT_{st.integrator.upper()}")
    m.opt.iterations = st.iterations
    m.opt.tolerance = st.tolerance
    if st.diagexact:
        m.opt.enableflags |= feature(mujoco.mjtEnableBit, "mjENBL_DIAGEXACT", "diagexact=True")
    if st.speculative:
        m.opt.enableflags |= feature(mujoco.mjtEnableBit, "mjENBL_SPECULATIVE", "speculative=True")


class MujocoEngine(Engine):
    """MuJoCo behind the single-world interface."""

    record = RECORD

    @classmethod
    def read_back_defaults(cls) -> dict:
        m = mujoco.MjModel.from_xml_string(
            '<mujoco><worldbody><geom size="1"/></worldbody></mujoco>'
        )
        return {
            "solref": tuple(m.geom_solref[0].tolist()),
            "solimp": tuple(m.geom_solimp[0].tolist()),
            "iterations": int(m.opt.iterations),
            "tolerance": float(m.opt.tolerance),
            "dt_s": float(m.opt.timestep),
            "integrator": next(
                i
                for i in INTEGRATORS
                if m.opt.integrator == getattr(mujoco.mjtIntegrator, f"mjINT_{i.upper()}")
            ),
            "cone": "elliptic" if m.opt.cone == mujoco.mjtCone.mjCONE_ELLIPTIC else "pyramidal",
        }

    def build(self, scene: Scene, contact_sensor: bool = False) -> None:
        """The scene's model and a data; ``contact_sensor``: with ``model.CONTACT_SENSOR``
        (the worlds pool's model, ``worlds``)."""
        st = self.settings
        paired = st.contact_model != "native"
        m = copy.copy(compiled(mjcf(scene.bat, scene.ball, scene.mu, paired, contact_sensor)))
        apply_options(m, st)
        self.model, self.data = m, mujoco.MjData(m)
        self._bat_id = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_BODY, "bat")
        self._ball_id = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_BODY, "ball")
        self._bat_geom = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_GEOM, "bat")
        self._ball_geom = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_GEOM, "ball")
        self._qpos, self._qvel = self.data.qpos, self.data.qvel
        self._site = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_SITE, "load")
        m.site_sameframe[self._site] = 0  # else kinematics ignores site_pos set at run time
        m.eq_solref[0] = st.hinge_solref if st.hinge_solref is not None else (2 * st.dt_s, 1.0)
        m.geom_solref[:], m.geom_solimp[:] = contact_parameters(st, scene.e)
        if m.npair:
            m.pair_solref[0], m.pair_solimp[0], m.pair_solreffriction[0] = pair_parameters(
                st, scene.e
            )

    def sibling(self) -> MujocoEngine:
        """Another world on this one's model (a data of its own): what a pool holds
        (``worlds.MujocoWorlds``)."""
        twin = copy.copy(self)
        twin.data = mujoco.MjData(self.model)
        twin._qpos, twin._qvel = twin.data.qpos, twin.data.qvel
        return twin

    def driven_twin(self, hands: Hands) -> MujocoEngine:
        """Another world on a copy of this one's model, driven by ``hands`` (their pivot and
        load site are the model's): a pool world's drive where the worlds' hands differ
        (``worlds.MujocoWorlds.set_drive``)."""
        twin = copy.copy(self)
        twin.model = copy.copy(self.model)
        twin.data = mujoco.MjData(twin.model)
        twin._qpos, twin._qvel = twin.data.qpos, twin.data.qvel
        twin.set_drive(hands)
        return twin

    def set_body_friction(self, *, bat: float, ball: float) -> None:
        self.model.geom_friction[self._bat_geom][0] = bat
        self.model.geom_friction[self._ball_geom][0] = ball

    def mass_properties(self) -> MassProperties:
        m = self.model

        def tensor(body: int) -> np.ndarray:
            rot = np.zeros(9)
            mujoco.mju_quat2Mat(rot, m.body_iquat[body])
            rot = rot.reshape(3, 3)
            return rot @ np.diag(m.body_inertia[body]) @ rot.T

        g = self._bat_geom
        knob_x = m.geom_pos[g][0] - m.geom_size[g][1] - m.geom_size[g][0]
        return MassProperties(
            bat_mass_kg=float(m.body_mass[self._bat_id]),
            bat_com_from_knob_m=float(m.body_ipos[self._bat_id][0] - knob_x),
            bat_inertia_kgm2=float(tensor(self._bat_id)[2, 2]),
            ball_mass_kg=float(m.body_mass[self._ball_id]),
            ball_inertia_kgm2=float(tensor(self._ball_id)[2, 2]),
        )

    def set_state(self, state: State) -> None:
        self._planar = in_the_plane(state)  # read back as set (frames.angle_and_tilt)
        data = self.data
        data.time = 0.0
        data.qacc_warmstart[:] = 0.0
        for w in BLOW_UPS:
            data.warning[w].number = 0
        q = bat_quaternion(state.bat_angle_rad, state.bat_tilt_rad)
        # free joints: qvel[3:6] is the angular velocity in the body's frame (the ball's is
        # the world's: it starts unturned)
        w = rotate(q, (state.bat_wx_radps, state.bat_wy_radps, state.bat_omega_radps), True)
        self._qpos[:] = (
            state.bat_x_m,
            state.bat_y_m,
            state.bat_z_m,
            *q,
            state.ball_x_m,
            state.ball_y_m,
            state.ball_z_m,
            1.0,
            0.0,
            0.0,
            0.0,
        )
        self._qvel[:] = (
            state.bat_vx_mps,
            state.bat_vy_mps,
            state.bat_vz_mps,
            *w,
            state.ball_vx_mps,
            state.ball_vy_mps,
            state.ball_vz_mps,
            state.ball_wx_radps,
            state.ball_wy_radps,
            state.ball_omega_radps,
        )

    def set_drive(self, hands: Hands | None) -> None:
        # Site actuators act in the bat's frame and are evaluated at every integrator stage;
        # the hands are a connect equality: eq_data[0:3] the anchor in the bat's frame, [3:6]
        # the point in the world's.
        if hands is None:
            self.data.ctrl[:] = 0.0
            self.data.eq_active[0] = 0
            return
        if hands.pivot_from_com_m is not None:
            self.model.eq_data[0][:6] = (hands.pivot_from_com_m, 0.0, 0.0, *hands.pivot_xy_m, 0.0)
            self.data.eq_active[0] = 1
        self.model.site_pos[self._site] = (hands.arm_m, 0.0, 0.0)
        q = hands.angle_rad
        self.data.ctrl[:] = (
            hands.force_n * math.cos(q),
            hands.force_n * math.sin(q),
            hands.torque_nm,
        )

    def step(self) -> None:
        mujoco.mj_step(self.model, self.data)

    def read(self) -> State:
        q, v = self._qpos.tolist(), self._qvel.tolist()  # Python floats: cheaper downstream
        bat_w = rotate(q[3:7], v[3:6])
        ball_w = rotate(q[10:14], v[9:12])
        angle, tilt = angle_and_tilt(*q[3:7], self._planar)
        return State(
            ball_x_m=q[7],
            ball_y_m=q[8],
            ball_vx_mps=v[6],
            ball_vy_mps=v[7],
            ball_omega_radps=ball_w[2],
            bat_x_m=q[0],
            bat_y_m=q[1],
            bat_angle_rad=angle,
            bat_vx_mps=v[0],
            bat_vy_mps=v[1],
            bat_omega_radps=bat_w[2],
            ball_z_m=q[9],
            ball_vz_mps=v[8],
            ball_wx_radps=ball_w[0],
            ball_wy_radps=ball_w[1],
            bat_z_m=q[2],
            bat_tilt_rad=tilt,
            bat_vz_mps=v[2],
            bat_wx_radps=bat_w[0],
            bat_wy_radps=bat_w[1],
        )

    def in_contact(self) -> bool:
        return self.data.ncon > 0

    def failed(self) -> bool:
        return any(self.data.warning[w].number for w in BLOW_UPS)
