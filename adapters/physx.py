"""NVIDIA PhysX 5 adapter, through SAPIEN 3 (CPU): two rigid dynamic bodies in a PhysX scene.

Traps this adapter handles (measured with this adapter, SAPIEN 3.0.3 / PhysX 5.3.1):
- SAPIEN keeps scene, body and shape settings in process-wide defaults that PhysX copies when a
  system, body or shape is created; the adapter sets them for its own objects and restores them
  at once, so that a fresh engine (``read_back_defaults``) still reports SAPIEN's values.
- PhysX stores masses, inertias and poses in float32 (0.871 kg reads back as 0.87099999189,
  9e-9 off): the mass check allows 8 float32 ulps (``check_mass_properties``).
- PhysX capsules lie along the body's x axis, as our bat does; the body frame is put at the COM
  (``cmass_local_pose`` identity), so poses and linear velocities are the COM's.
- Restitution is the mean of the two materials' values (PhysX's default combine mode, which
  SAPIEN does not expose; bat 0.3 and ball 0.9 bounce at 0.6): both get e. It is dropped below
  ``bounce_threshold_mps`` (2 m/s by default: e = 0.5 becomes 0 at 1.9 m/s, stays at 2.1 m/s;
  PhysX issue #351), 0 in the reference.
- Contacts are generated ``contact_offset_m`` (10 mm per shape by default) ahead of touching
  and solved as speculative; ``in_contact`` counts only points touching or carrying an impulse.
  TGS bounces a speculative contact in the step its gap closes in, with the geometry of that
  step's start: exact on a still bat, up to one step early on a turning one (2.4e-3 m/s on the
  paper's swing). A contact first seen overlapping (gap above the pair's 20 mm at the start of
  the step, e.g. 100 m/s at 0.4 ms) is bounced short by TGS: 1.6e-3 of v1 with 10 position
  iterations, less with more, but at 150 a ball riding the turning bat chatters.
- PGS, the other solver, splits a speculative impact over two steps when the gap closes late in
  a step (40 m/s on a still bat, contact at 0.9 of the step: -40 -> -35.88 -> +9.38 m/s against
  +11.44, 18% of the rebound lost), and its hands' hinge leaves omega 1.1e-3 short after a 0.1 s
  swing at 0.1 ms: the reference keeps TGS, SAPIEN's choice.
- Bodies turn at most ``max_angular_velocity_radps`` (100 rad/s by default: a 60 rad/s swing's
  bat leaves a barrel hit at 100.00 rad/s instead of 118.0), lifted in the reference; bodies
  may sleep, which the reference forbids (sleep threshold 0).
- SAPIEN's ``enable_ccd`` scene flag is inert (same bits with and without it): the per-body
  CCD flag it needs is not exposed.
- Importing SAPIEN warns about Vulkan on stderr; ``import_engine`` silences it (and the
  adapter filters the Python warning), and no renderer is ever created (the scene holds a
  PhysX system only).
"""

from __future__ import annotations

import contextlib
import math
import warnings
from dataclasses import dataclass
from typing import Iterator

from analytic import Ball, Bat
from analytic import _checks

from ._record import EngineRecord, KnobFamily, RestitutionRule, import_engine
from .base import BodyLoad, Engine, MassProperties, Reading, Settings

SOLVERS = ("TGS", "PGS")


@dataclass(frozen=True, kw_only=True)
class PhysxSettings(Settings):
    """PhysX's knobs (None: keep SAPIEN's default). ``solver`` one of SOLVERS (temporal
    Gauss-Seidel or projected Gauss-Seidel); ``bounce_threshold_mps``: normal speeds below it
    get no restitution; ``enable_pcm`` persistent contact manifolds; ``contact_offset_m``: the
    distance at which contacts are generated ahead of touching (speculative); ``rest_offset_m``:
    the separation the solver keeps; ``position_iterations``/``velocity_iterations`` of the
    solver per body; ``max_angular_velocity_radps`` the bodies' spin cap;
    ``max_depenetration_velocity_mps`` the cap on the speed that removes overlap;
    ``sleep_threshold`` (J/kg, kinetic energy per mass below which a body may sleep)."""

    solver: str | None = None
    bounce_threshold_mps: float | None = None
    enable_pcm: bool | None = None
    contact_offset_m: float | None = None
    rest_offset_m: float | None = None
    position_iterations: int | None = None
    velocity_iterations: int | None = None
    max_angular_velocity_radps: float | None = None
    max_depenetration_velocity_mps: float | None = None
    sleep_threshold: float | None = None

    def __post_init__(self) -> None:
        super().__post_init__()
        if self.solver is not None and self.solver not in SOLVERS:
            raise ValueError(f"solver={self.solver!r} is unknown; allowed: {', '.join(SOLVERS)}")
        if self.enable_pcm is not None and not isinstance(self.enable_pcm, bool):
            raise ValueError(f"enable_pcm={self.enable_pcm!r} is not a bool; allowed: True, False")
        for name in ("bounce_threshold_mps", "rest_offset_m", "sleep_threshold"):
            if getattr(self, name) is not None:
                _checks.non_negative(name, getattr(self, name))
        for name in ("contact_offset_m", "max_angular_velocity_radps",
                     "max_depenetration_velocity_mps"):
            if getattr(self, name) is not None:
                _checks.positive(name, getattr(self, name))
        if self.position_iterations is not None:
            _checks.integer("position_iterations", self.position_iterations, 1, 255)
        if self.velocity_iterations is not None:
            _checks.integer("velocity_iterations", self.velocity_iterations, 0, 255)
        if (self.contact_offset_m is not None and self.rest_offset_m is not None
                and self.rest_offset_m >= self.contact_offset_m):
            raise ValueError(f"rest_offset_m={self.rest_offset_m!r} is not below contact_offset_m"
                             f"={self.contact_offset_m!r}; allowed: rest_offset_m < "
                             "contact_offset_m (PhysX rejects the shape otherwise)")


RECORD = EngineRecord(
    name="physx", package="sapien", import_name="sapien", extra="physx",
    profiles={
        # TGS, as SAPIEN chooses it: the hands' hinge keeps omega within 4.5e-5 after a 0.1 s
        # swing at 0.1 ms (PGS: 1.1e-3 short, whatever its iterations). Contacts speculative,
        # as SAPIEN sets them (10 mm ahead): TGS then bounces in the step the gap closes in,
        # exactly on a still bat (1.7e-6 m/s at 40 m/s), with the geometry of that step's
        # start on a turning one (2.4e-3 m/s off on the paper's swing). Found only once
        # touching (1 um) the contact is worse: 0.014 m/s off on the still bat with 10
        # position iterations; 150 iterations bring that to 6e-6 but make a ball riding the
        # turning bat chatter (0.52 m/s off on the fuzz's plastic slide, tolerance 0.24).
        # SAPIEN's 10 position iterations: 100 change the paper's swing by < 1e-5 m/s, and
        # 150 break the plastic slide even with speculative contacts (2.45 m/s off). No bounce
        # threshold; the spin cap lifted so that a blow-up shows as it is; no body may sleep;
        # a 10 us step.
        "reference": PhysxSettings(dt_s=1e-5, bounce_threshold_mps=0.0,
                                   max_angular_velocity_radps=1e4, sleep_threshold=0.0),
        # Out of the box: SAPIEN's 10 ms step and every solver value left to SAPIEN (TGS,
        # bounce threshold 2 m/s, 10 mm contact offset), the contact instant mid-step as in any
        # unaligned simulation.
        "default": PhysxSettings(dt_s=0.01, contact_phase=0.5),
    },
    color="tab:brown", marker="P",
    speed_accuracy=(
        KnobFamily(label="reference solver (TGS, 10 position iterations)", quick=True),
        *(KnobFamily(label=f"TGS, {n} position iterations",
                     overrides=(("position_iterations", n),)) for n in (1, 4, 50)),
        KnobFamily(label="PGS", overrides=(("solver", "PGS"),)),
    ),
    precision="float32",  # PhysX computes and stores in single precision
    restitution_rule=RestitutionRule.MEAN,
    threshold_setting="bounce_threshold_mps",
    # All read back from a fresh system, body and shape (SAPIEN's process-wide defaults, which
    # PhysX copies at creation; the adapter restores them after building its own scene).
    engine_defaults={"dt_s": 0.01, "solver": "TGS", "bounce_threshold_mps": 2.0,
                     "enable_pcm": True, "contact_offset_m": 0.01, "rest_offset_m": 0.0,
                     "position_iterations": 10, "velocity_iterations": 1,
                     "max_angular_velocity_radps": 100.0,
                     "max_depenetration_velocity_mps": 1e32, "sleep_threshold": 0.005},
)
with warnings.catch_warnings():  # SAPIEN warns that it uses its own Vulkan: we never render
    warnings.filterwarnings("ignore", message=".*libvulkan", category=UserWarning)
    sapien = import_engine(RECORD)
physx = sapien.physx


@contextlib.contextmanager
def _sapien_defaults(st: PhysxSettings) -> Iterator[None]:
    """Within the block, SAPIEN creates systems, bodies and shapes with these settings (None:
    its own); its process-wide defaults are restored afterwards."""
    scene, body, shape = (physx.get_scene_config(), physx.get_body_config(),
                          physx.get_shape_config())
    try:
        physx.set_scene_config(
            gravity=[0.0, 0.0, 0.0],
            bounce_threshold=_or(st.bounce_threshold_mps, scene.bounce_threshold),
            enable_pcm=_or(st.enable_pcm, scene.enable_pcm),
            enable_tgs=scene.enable_tgs if st.solver is None else st.solver == "TGS",
            enable_ccd=scene.enable_ccd,
            enable_enhanced_determinism=scene.enable_enhanced_determinism,
            enable_friction_every_iteration=scene.enable_friction_every_iteration)
        physx.set_body_config(
            solver_position_iterations=_or(st.position_iterations,
                                           body.solver_position_iterations),
            solver_velocity_iterations=_or(st.velocity_iterations,
                                           body.solver_velocity_iterations),
            sleep_threshold=_or(st.sleep_threshold, body.sleep_threshold))
        physx.set_shape_config(contact_offset=_or(st.contact_offset_m, shape.contact_offset),
                               rest_offset=_or(st.rest_offset_m, shape.rest_offset))
        yield
    finally:
        physx.set_scene_config(scene)
        physx.set_body_config(body)
        physx.set_shape_config(shape)


def _or(value, default):
    return default if value is None else value


class PhysxEngine(Engine):
    """PhysX (through SAPIEN) behind the common contract."""

    record = RECORD

    @classmethod
    def speculative_margin_m(cls, settings: PhysxSettings) -> float:
        # each shape makes contacts contact_offset ahead of touching: the pair, both offsets
        offset = settings.contact_offset_m
        return 2 * (RECORD.engine_defaults["contact_offset_m"] if offset is None else offset)

    @classmethod
    def read_back_defaults(cls) -> dict:
        system = physx.PhysxCpuSystem()
        body = physx.PhysxRigidDynamicComponent()
        shape = physx.PhysxCollisionShapeSphere(1.0, physx.get_default_material())
        cfg = system.config
        return {"dt_s": system.timestep, "solver": "TGS" if cfg.enable_tgs else "PGS",
                "bounce_threshold_mps": cfg.bounce_threshold, "enable_pcm": cfg.enable_pcm,
                "contact_offset_m": shape.contact_offset, "rest_offset_m": shape.rest_offset,
                "position_iterations": body.solver_position_iterations,
                "velocity_iterations": body.solver_velocity_iterations,
                "max_angular_velocity_radps": body.max_angular_velocity,
                "max_depenetration_velocity_mps": body.max_depenetration_velocity,
                "sleep_threshold": body.sleep_threshold}

    def __init__(self, settings: PhysxSettings, *, name: str | None = None) -> None:
        super().__init__(settings, name=name)
        self._scene = None
        self._load: tuple[float, float, float] | None = None
        self._hinge = None

    def close(self) -> None:
        if self._scene is not None:
            self._scene.clear()
            self._scene = self._system = None
            self.scene = None

    def build_scene(self, bat: Bat, ball: Ball) -> None:
        st = self.settings
        self.close()
        self._hinge = None
        with _sapien_defaults(st):
            self._system = physx.PhysxCpuSystem()
            self._scene = sapien.Scene([self._system])
            self._system.timestep = st.dt_s
            a, b, r = bat.s_min_m, bat.s_max_m, bat.radius_m
            self._bat_material = physx.PhysxMaterial(0.0, 0.0, 1.0)
            self._ball_material = physx.PhysxMaterial(0.0, 0.0, 1.0)
            capsule = physx.PhysxCollisionShapeCapsule(r, 0.5 * (b - a), self._bat_material)
            capsule.set_local_pose(sapien.Pose([0.5 * (a + b), 0.0, 0.0]))
            sphere = physx.PhysxCollisionShapeSphere(ball.radius_m, self._ball_material)
            self._bat = self._body(capsule, bat.mass_kg,
                                   (bat.axial_inertia_kgm2, bat.inertia_cm_kgm2,
                                    bat.inertia_cm_kgm2))
            self._ball = self._body(sphere, ball.mass_kg, (ball.inertia_kgm2,) * 3)
        self._pair = {id(self._bat), id(self._ball)}

    def _body(self, shape, mass: float, inertia: tuple[float, float, float]):
        st = self.settings
        body = physx.PhysxRigidDynamicComponent()
        body.attach(shape)
        body.mass = mass
        body.inertia = inertia
        body.cmass_local_pose = sapien.Pose()
        body.linear_damping = body.angular_damping = 0.0
        body.disable_gravity = True
        if st.max_angular_velocity_radps is not None:
            body.max_angular_velocity = st.max_angular_velocity_radps
        if st.max_depenetration_velocity_mps is not None:
            body.max_depenetration_velocity = st.max_depenetration_velocity_mps
        entity = sapien.Entity()
        entity.add_component(body)
        self._scene.add_entity(entity)
        return body

    def mass_properties(self) -> MassProperties:
        bat, ball = self._bat, self._ball
        shape = bat.collision_shapes[0]
        knob_x = float(shape.local_pose.p[0]) - shape.half_length - shape.radius
        com_x = float(bat.cmass_local_pose.p[0])
        return MassProperties(
            bat_mass_kg=bat.mass, bat_com_from_knob_m=com_x - knob_x,
            bat_inertia_kgm2=float(bat.inertia[2]), ball_mass_kg=ball.mass,
            ball_inertia_kgm2=float(ball.inertia[2]))

    def set_restitution(self, e: float) -> None:
        self.set_body_restitution(bat=e, ball=e)  # PhysX averages the two

    def set_body_restitution(self, *, bat: float, ball: float) -> None:
        super().set_body_restitution(bat=bat, ball=ball)
        self._bat_material.restitution = bat
        self._ball_material.restitution = ball

    def set_state(self, r: Reading) -> None:
        half = 0.5 * r.bat_angle
        for body, pose, v, w in (
                (self._bat, sapien.Pose([r.bat_x, r.bat_y, 0.0],
                                        [math.cos(half), 0.0, 0.0, math.sin(half)]),
                 (r.bat_vx, r.bat_vy, 0.0), r.bat_w),
                (self._ball, sapien.Pose([r.ball_x, r.ball_y, 0.0]), (r.ball_vx, r.ball_vy, 0.0),
                 r.ball_w)):
            body.entity.pose = pose
            body.linear_velocity = v
            body.angular_velocity = (0.0, 0.0, w)

    def set_load(self, load: BodyLoad | None) -> None:
        self._load = None if load is None else (load.force_n, load.angle_rad,
                                                load.torque_about_com_nm)

    def pin(self, pivot_from_com_m: float, pivot_xy_m: tuple[float, float]) -> None:
        hinge = physx.PhysxDriveComponent(self._bat)
        hinge.pose_in_child = sapien.Pose([pivot_from_com_m, 0.0, 0.0])
        hinge.pose_in_parent = sapien.Pose([pivot_xy_m[0], pivot_xy_m[1], 0.0])
        for lock in (hinge.set_limit_x, hinge.set_limit_y, hinge.set_limit_z):
            lock(0.0, 0.0)  # all three translations locked: a ball joint at the hands
        self._bat.entity.add_component(hinge)
        self._hinge = hinge

    def unpin(self) -> None:
        if self._hinge is not None:
            self._bat.entity.remove_component(self._hinge)
            self._hinge = None

    def step(self) -> None:
        if self._load is not None:
            f, q, torque = self._load  # force through the COM + its constant torque
            qw, _, _, qz = self._bat.entity.pose.q.tolist()
            angle = 2.0 * math.atan2(qz, qw) + q
            self._bat.add_force_torque([f * math.cos(angle), f * math.sin(angle), 0.0],
                                       [0.0, 0.0, torque])
        self._system.step()

    def read(self) -> Reading:
        bat, ball = self._bat, self._ball
        pose = bat.entity.pose
        bp, bq = pose.p.tolist(), pose.q.tolist()
        cp = ball.entity.pose.p.tolist()
        bv, bw = bat.linear_velocity.tolist(), bat.angular_velocity.tolist()
        cv, cw = ball.linear_velocity.tolist(), ball.angular_velocity.tolist()
        return Reading(cp[0], cp[1], cv[0], cv[1], cw[2], bp[0], bp[1],
                       2.0 * math.atan2(bq[3], bq[0]), bv[0], bv[1], bw[2])

    def in_contact(self) -> bool:
        for contact in self._system.get_contacts():
            for point in contact.points:
                if point.separation <= 0.0 or any(point.impulse):
                    return True
        return False


ENGINE = PhysxEngine
