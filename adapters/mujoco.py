"""MuJoCo adapter: two free bodies, a capsule bat and a sphere ball, no gravity, no friction.

MuJoCo has no restitution parameter: contacts are soft constraints shaped by ``solref`` and
``solimp``. The adapter maps the target e in one of three ways (``contact_model``):
- ``impulse``: solref = (0, -(1+e)/dt) in MuJoCo's direct (-stiffness, -damping) form, constant
  impedance and exact constraint diagonals (``diagexact``): in one Euler step the reference
  acceleration -(1+e) v_n/dt reverses the normal velocity exactly as Newton's law asks.
- ``soft``: a spring-damper, solref = (-k, -b) with k = w^2 and b = 2 zeta w, zeta chosen so
  that a linear spring-damper released when its force reaches zero bounces with e
  (``damping_ratio_for``). With constant impedance and ``diagexact`` the contact's normal
  coordinate obeys x'' = -b x' - k x whatever the masses and whatever d (measured: e = 0.49995
  at w = 3000 rad/s, dt = 1e-7 s for every d in 0.5..0.99). Needs w*dt << 1, and the finite
  contact time while the bat turns makes it approximate.
- ``native``: solref/solimp as given (MuJoCo's defaults in the ``default`` profile): e is not
  mapped at all, which is what an untuned model gets.
Free-joint velocities: qvel[0:3] is the world velocity of the body frame (put at the COM) and
qvel[3:6] the angular velocity in the body frame (= world for rotation about z).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from analytic import Ball, Bat
from analytic import _checks
from analytic.compliant import ContactSpaceSpringDamper, damping_ratio_for

from ._record import ContactReference, EngineRecord, Integrator, KnobFamily, RestitutionRule, import_engine
from .base import BodyLoad, Engine, MassProperties, Reading, Settings

INTEGRATORS = ("Euler", "implicitfast", "implicit", "RK4")
CONTACT_MODELS = ("impulse", "soft", "native")
DEFAULT_SOLREF = (0.02, 1.0)                       # MuJoCo's documented defaults
DEFAULT_SOLIMP = (0.9, 0.95, 0.001, 0.5, 2.0)


@dataclass(frozen=True, kw_only=True)
class MujocoSettings(Settings):
    """MuJoCo's knobs. ``integrator`` one of INTEGRATORS; ``contact_model`` one of
    CONTACT_MODELS; ``soft_omega_radps`` the soft contact's natural frequency w (rad/s);
    ``impedance`` the constant solimp d for impulse/soft; ``solref``/``solimp`` used as given by
    the native model; ``diagexact`` exact constraint diagonals; ``iterations``/``tolerance`` of
    the Newton solver; ``speculative`` MuJoCo's speculative contacts (margin ahead of touching);
    ``hinge_solref`` of the hands' releasable connect constraint (None: (2 dt, 1), the stiffest
    MuJoCo recommends)."""

    integrator: str = "Euler"
    contact_model: str = "impulse"
    soft_omega_radps: float = 3000.0
    impedance: float = 0.99
    solref: tuple[float, float] = DEFAULT_SOLREF
    solimp: tuple[float, float, float, float, float] = DEFAULT_SOLIMP
    diagexact: bool = True
    iterations: int = 100
    tolerance: float = 1e-8
    speculative: bool = False
    hinge_solref: tuple[float, float] | None = None

    def __post_init__(self) -> None:
        super().__post_init__()
        if self.integrator not in INTEGRATORS:
            raise ValueError(f"integrator={self.integrator!r} is unknown; allowed: "
                             f"{', '.join(INTEGRATORS)}")
        if self.contact_model not in CONTACT_MODELS:
            raise ValueError(f"contact_model={self.contact_model!r} is unknown; allowed: "
                             f"{', '.join(CONTACT_MODELS)}")
        _checks.positive("soft_omega_radps", self.soft_omega_radps)
        _checks.in_range("impedance", self.impedance, 0.0001, 0.9999)
        _checks.integer("iterations", self.iterations, 1, 10_000)
        _checks.non_negative("tolerance", self.tolerance)


def _mjcf(bat: Bat, ball: Ball) -> str:
    """The scene as MJCF: body frames at the COMs, mass properties set explicitly."""
    a, b = bat.s_min_m, bat.s_max_m
    ib = ball.inertia_kgm2
    return f"""<mujoco model="bat_ball">
  <compiler angle="radian" inertiafromgeom="false"/>
  <option gravity="0 0 0"/>
  <default><geom condim="1" friction="0 0 0" margin="0" gap="0"/></default>
  <worldbody>
    <body name="bat">
      <freejoint name="bat"/>
      <inertial pos="0 0 0" mass="{bat.mass_kg!r}"
                diaginertia="{bat.axial_inertia_kgm2!r} {bat.inertia_cm_kgm2!r} {bat.inertia_cm_kgm2!r}"/>
      <geom name="bat" type="capsule" fromto="{a!r} 0 0 {b!r} 0 0" size="{bat.radius_m!r}"/>
      <site name="load" pos="0 0 0"/>
    </body>
    <body name="ball" pos="0 1 0">
      <freejoint name="ball"/>
      <inertial pos="0 0 0" mass="{ball.mass_kg!r}" diaginertia="{ib!r} {ib!r} {ib!r}"/>
      <geom name="ball" type="sphere" size="{ball.radius_m!r}"/>
    </body>
  </worldbody>
  <equality><connect name="hands" body1="bat" anchor="0 0 0" active="false"/></equality>
  <actuator>
    <motor name="fx" site="load" gear="1 0 0 0 0 0"/>
    <motor name="fy" site="load" gear="0 1 0 0 0 0"/>
    <motor name="tz" site="load" gear="0 0 0 0 0 1"/>
  </actuator>
</mujoco>"""


SOFT_OMEGAS_RADPS = (1000.0, 3000.0, 10000.0)  # soft-contact stiffnesses of the speed study


def _speed_accuracy() -> tuple[KnobFamily, ...]:
    """Impulse and soft contact under each integrator (Euler and RK4 with w = 3000 in --quick)."""
    out = []
    for integrator in ("Euler", "implicitfast", "RK4"):
        quick = integrator != "implicitfast"
        out.append(KnobFamily(label=f"impulse, {integrator}", quick=quick,
                              overrides=(("integrator", integrator),)))
        out += [KnobFamily(label=f"soft w={w:g}, {integrator}", quick=quick and w == 3000.0,
                           overrides=(("integrator", integrator), ("contact_model", "soft"),
                                      ("soft_omega_radps", w))) for w in SOFT_OMEGAS_RADPS]
    return tuple(out)


RECORD = EngineRecord(
    name="mujoco", package="mujoco", import_name="mujoco",
    profiles={
        # Fidelity to the impulse model: a 10 us step (contact tilt while the bat turns stays
        # ~1e-10), Euler (the impulse mapping is exact for one explicit step), impulse contact.
        "reference": MujocoSettings(dt_s=1e-5, integrator="Euler", contact_model="impulse",
                                    impedance=0.99, diagexact=True),
        # Out of the box: 2 ms step, Euler, solref (0.02, 1), default solimp, no diagexact; the
        # contact instant falls mid-step as it would in an unaligned simulation.
        "default": MujocoSettings(dt_s=0.002, integrator="Euler", contact_model="native",
                                  diagexact=False, contact_phase=0.5),
    },
    color="tab:green", marker="^",
    speed_accuracy=_speed_accuracy(),
    integrators=tuple(Integrator(label=name, overrides=(("integrator", name),),
                                 order=4 if name == "RK4" else 1)
                      for name in ("Euler", "implicitfast", "RK4")),
    restitution_rule=RestitutionRule.MAPPED,
    soft_contact={"contact_model": "soft"}, stiffness_setting="soft_omega_radps",
    engine_defaults={"solref": DEFAULT_SOLREF, "solimp": DEFAULT_SOLIMP, "iterations": 100,
                     "tolerance": 1e-8, "dt_s": 0.002, "integrator": "Euler"},
)
mujoco = import_engine(RECORD)
# MuJoCo's own warning handler prints and appends to MUJOCO_LOG.TXT in the working directory;
# the adapter reads the warning counters instead (numerical_failures), so the text is dropped.
mujoco.set_mju_user_warning(lambda text: None)
#: Warnings that mean the state blew up (MuJoCo resets it after them).
BLOW_UPS = (mujoco.mjtWarning.mjWARN_BADQPOS, mujoco.mjtWarning.mjWARN_BADQVEL,
            mujoco.mjtWarning.mjWARN_BADQACC)


class MujocoEngine(Engine):
    """MuJoCo behind the common contract."""

    record = RECORD

    @classmethod
    def converges_to(cls, settings: MujocoSettings) -> ContactReference:
        # impulse: one Euler step reverses the normal velocity as Newton's law asks; soft: a
        # spring-damper acting on the contact coordinate; native: untuned, judged as impulse
        if settings.contact_model == "soft":
            return ContactReference.LINEAR_SPRING_DAMPER
        return ContactReference.RIGID_IMPULSE

    @classmethod
    def contact_law(cls, settings: MujocoSettings, e: float):
        # soft: solref (-w^2, -2 zeta w) acts on J qacc, in contact space (module docstring)
        if settings.contact_model != "soft":
            return None
        return ContactSpaceSpringDamper(omega_radps=settings.soft_omega_radps,
                                        damping_ratio=damping_ratio_for(max(e, 1e-9)))

    @classmethod
    def read_back_defaults(cls) -> dict:
        m = mujoco.MjModel.from_xml_string(
            '<mujoco><worldbody><geom size="1"/></worldbody></mujoco>')
        return {"solref": tuple(m.geom_solref[0].tolist()),
                "solimp": tuple(m.geom_solimp[0].tolist()), "iterations": int(m.opt.iterations),
                "tolerance": float(m.opt.tolerance), "dt_s": float(m.opt.timestep),
                "integrator": next(i for i in INTEGRATORS if m.opt.integrator
                                   == getattr(mujoco.mjtIntegrator, f"mjINT_{i.upper()}"))}

    def build_scene(self, bat: Bat, ball: Ball) -> None:
        st = self.settings
        m = mujoco.MjModel.from_xml_string(_mjcf(bat, ball))
        m.opt.timestep = st.dt_s
        m.opt.integrator = getattr(mujoco.mjtIntegrator, f"mjINT_{st.integrator.upper()}")
        m.opt.iterations = st.iterations
        m.opt.tolerance = st.tolerance
        if st.diagexact:
            m.opt.enableflags |= mujoco.mjtEnableBit.mjENBL_DIAGEXACT
        if st.speculative:
            m.opt.enableflags |= mujoco.mjtEnableBit.mjENBL_SPECULATIVE
        self.model, self.data = m, mujoco.MjData(m)
        self._bat_id = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_BODY, "bat")
        self._ball_id = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_BODY, "ball")
        self._bat_geom = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_GEOM, "bat")
        self._qpos, self._qvel = self.data.qpos, self.data.qvel
        self._site = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_SITE, "load")
        m.site_sameframe[self._site] = 0  # else kinematics ignores site_pos set at run time
        m.eq_solref[0] = st.hinge_solref if st.hinge_solref is not None else (2 * st.dt_s, 1.0)

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

    def set_restitution(self, e: float) -> None:
        st = self.settings
        d = st.impedance
        if st.contact_model == "impulse":
            solref = (0.0, -(1.0 + e) / st.dt_s)
            solimp = (d, d, 0.001, 0.5, 2.0)
        elif st.contact_model == "soft":
            w, zeta = st.soft_omega_radps, damping_ratio_for(max(e, 1e-9))
            solref = (-w * w, -2.0 * zeta * w)
            solimp = (d, d, 0.001, 0.5, 2.0)
        else:
            solref, solimp = st.solref, st.solimp
        self.model.geom_solref[:] = solref
        self.model.geom_solimp[:] = solimp

    def set_state(self, r: Reading) -> None:
        data = self.data
        data.time = 0.0
        data.qacc_warmstart[:] = 0.0
        half = 0.5 * r.bat_angle
        self._qpos[:] = (r.bat_x, r.bat_y, 0.0, math.cos(half), 0.0, 0.0, math.sin(half),
                         r.ball_x, r.ball_y, 0.0, 1.0, 0.0, 0.0, 0.0)
        self._qvel[:] = (r.bat_vx, r.bat_vy, 0.0, 0.0, 0.0, r.bat_w,
                         r.ball_vx, r.ball_vy, 0.0, 0.0, 0.0, r.ball_w)

    def set_load(self, load: BodyLoad | None) -> None:
        # Site actuators act in the bat's frame and are evaluated at every integrator stage.
        if load is None:
            self.data.ctrl[:] = 0.0
            return
        self.model.site_pos[self._site] = (load.arm_m, 0.0, 0.0)
        q = load.angle_rad
        self.data.ctrl[:] = (load.force_n * math.cos(q), load.force_n * math.sin(q),
                             load.torque_nm)

    def pin(self, pivot_from_com_m: float, pivot_xy_m: tuple[float, float]) -> None:
        # connect: eq_data[0:3] is the anchor in the bat's frame, [3:6] the point in the world's
        self.model.eq_data[0][:6] = (pivot_from_com_m, 0.0, 0.0, pivot_xy_m[0], pivot_xy_m[1], 0.0)
        self.data.eq_active[0] = 1

    def unpin(self) -> None:
        self.data.eq_active[0] = 0

    def step(self) -> None:
        mujoco.mj_step(self.model, self.data)

    def read(self) -> Reading:
        q, v = self._qpos.tolist(), self._qvel.tolist()  # Python floats: cheaper downstream
        return Reading(q[7], q[8], v[6], v[7], v[11], q[0], q[1], 2.0 * math.atan2(q[6], q[3]),
                       v[0], v[1], v[5])

    def in_contact(self) -> bool:
        return self.data.ncon > 0

    def numerical_failures(self) -> int:
        warnings = self.data.warning
        return sum(warnings[int(w)].number for w in BLOW_UPS)


ENGINE = MujocoEngine
