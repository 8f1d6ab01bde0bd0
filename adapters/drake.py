"""Drake adapter: a MultibodyPlant with a free sphere ball and a planar capsule bat.

Drake has no coefficient of restitution: its contact is compliant. Point contact pushes with
Hunt-Crossley's F = k x (1 + d x') (x the overlap, x' its rate), k and d combined from the two
geometries' ``point_contact_stiffness`` and ``hunt_crossley_dissipation`` (k = kA kB / (kA +
kB), d = (kB dA + kA dB) / (kA + kB)); the SAP approximation replaces d by a linear Kelvin-Voigt
damper k tau x' (``relaxation_time``, tau = tauA + tauB). ``contact_law`` states the law each
setting converges to; the harness judges Drake against it (``analytic.compliant.predict``), not
against rigid theory. Traps this adapter handles (measured with Drake 1.51.1):
- e maps onto d at one stated speed (``restitution_speed_mps``, 40 m/s, where the bat-ball COR
  is quoted): Hunt-Crossley's e falls with speed (d for e = 0.5 gives 0.67 at 20 m/s, 0.36 at
  68 m/s), so only a 40 m/s impact bounces with the case's e. SAP's linear damper gets the tau
  that gives e at the reduced mass ``relaxation_mass_kg`` (its e does not depend on speed).
- Both geometries carry 2k and the same d (and tau / 2): the combination is exactly k, d, tau.
  Checked by measurement: the continuous plant follows HuntCrossley(k, 1, d) to 2e-9 m/s on
  the paper's swing at s = 0.1 m (k = 1e6 and 2e6 N/m; a wrong k moves v1 by 4e-3 m/s).
- e below E_FLOOR (0.1) is mapped as 0.1: Hunt-Crossley lets go with the overlap still open,
  the bodies parting at no more than 1/d (drake#19320), and at e = 0.01 a turning bat meets the
  ball again and again for 65-100 ms. Drake's own default d = 50 s/m gives e = 5e-4 at 40 m/s:
  the ``default`` profile keeps Drake's step, solver and stiffness but maps e like the reference.
- Every discrete approximation is first order (v1 off by -3.9/-0.39/-0.038 m/s at dt = 1e-4,
  1e-5, 1e-6 s on the paper's swing at s = 0.1 m, lagged, similar and TAMSI alike; SAP
  -8.6/-1.06/-0.109 from its own law), so the reference is the continuous plant under RK3 with
  error control (1e-6 relative: 2e-8 m/s from the law, ~20 ms an impact); its dt_s is only the
  interval at which the harness reads the state. Beyond dt ~ the contact time (1.2-1.6 ms) an
  impact can begin and end between two readings, which the harness calls ``tunnelled``.
- At Drake's default 1 ms step an elastic contact (d = 0, k = 5e5 N/m, 1.6 ms long) bounces
  with e = 0.28 at 40 m/s (0.75 at 0.1 ms, 0.97 at 10 us): the implicit step's own damping.
- ``use_sampled_output_ports`` is off, so a discrete step is exactly one periodic update
  (computed and written by the adapter: the Simulator would add an update at t = 0).
- The continuous integrator is made afresh by ``set_state``: its step-size guess would
  otherwise carry over from the last impact (a used engine then differs in the last bits).
- The bat hangs on a planar chain (x, y prismatic, z revolute) whose revolute child frame is a
  ``FixedOffsetFrame`` on the bat: its pose is a context parameter, so ``pin`` moves the hinge
  to the hands and locks x and y (Joint.Lock), ``unpin`` unlocks; no rebuild, every solver,
  continuous too (hinged torque: omega exact to 6e-13 rad/s after 0.1 s at 0.1 ms).
- A body-frame load is an ExternallyAppliedSpatialForce expressed in the world: the adapter
  turns it with the bat at the start of every step (what a first-order step samples anyway;
  the continuous mode holds it over each reading interval, which is why it is not one of the
  swing study's integrators).
- Drake raises when a solver fails (TAMSI not converging, the integrator's step underflowing):
  the adapter counts it as a numerical failure and the impact ends ``non_finite``. TAMSI is
  deprecated (Drake logs a warning when a TAMSI plant is built).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from analytic import Ball, Bat
from analytic import _checks
from analytic.compliant import (HuntCrossley, LinearSpringDamper, damping_ratio_for,
                                hunt_crossley_dissipation)

from ._record import (ContactReference, EngineRecord, Integrator, KnobFamily, RestitutionRule,
                      import_engine)
from .base import BodyLoad, Engine, MassProperties, Reading, Settings

#: Discrete contact approximations (Drake's DiscreteContactApproximation) and "continuous" (an
#: error-controlled integrator driving a continuous plant).
SOLVERS = ("lagged", "similar", "sap", "tamsi", "continuous")
CONTACT_MODELS = ("point", "hydroelastic", "hydroelastic_with_fallback")
#: Smaller e are mapped as this e. Hunt-Crossley lets go with the overlap still open, the bodies
#: parting at no more than 1/d (drake#19320): at e = 0.01 (d = 2.5 s/m) on the paper's swing
#: Drake's contact re-engages on the turning bat for 65-100 ms against its law's 6.5 ms, and
#: ``hunt_crossley_dissipation`` loses its bracket near e = 0.03; at e = 0.1 Drake follows the
#: law to 3e-7 m/s.
E_FLOOR = 0.1


#: Within this of e = 1, d comes from Hunt-Crossley's expansion e = 1 - 2 d v / 3 + O((d v)^2)
#: (relative error below 1e-6 in d): ``hunt_crossley_dissipation`` fails to converge at
#: e = 1 - 1e-16 and is noisy below 1 - e = 1e-9 (4.6e-12 s/m for an expected 3.75e-11).
NEAR_ELASTIC = 1e-6


def _dissipation(e: float, speed_mps: float) -> float:
    """Hunt-Crossley d (s/m) that bounces with e (floored at E_FLOOR) at ``speed_mps``."""
    e = max(e, E_FLOOR)
    if 1.0 - e < NEAR_ELASTIC:
        return 1.5 * (1.0 - e) / speed_mps
    return hunt_crossley_dissipation(e, speed_mps)


@dataclass(frozen=True, kw_only=True)
class DrakeSettings(Settings):
    """Drake's knobs. ``solver`` one of SOLVERS; ``contact_model`` one of CONTACT_MODELS;
    ``point_stiffness_npm`` the contact's combined point stiffness k (N/m; None: Drake's
    default per geometry, combined in series); ``restitution_speed_mps`` the impact speed at
    which the Hunt-Crossley d gives the case's e (m/s); ``hydroelastic_modulus_pa`` the ball's
    hydroelastic modulus (Pa; the bat is rigid); ``resolution_hint_m`` the ball's hydroelastic
    mesh size (m); ``sap_near_rigid_threshold`` SAP's beta (1; None: Drake's); ``accuracy``
    the relative error target of the continuous mode's RK3 (its largest step is dt_s);
    ``relaxation_mass_kg`` the reduced mass (kg) at which SAP's linear damper gives e."""

    solver: str = "lagged"
    contact_model: str = "point"
    point_stiffness_npm: float | None = 1e6
    restitution_speed_mps: float = 40.0
    hydroelastic_modulus_pa: float = 1e8
    resolution_hint_m: float = 0.01
    sap_near_rigid_threshold: float | None = None
    accuracy: float = 1e-8
    relaxation_mass_kg: float = 0.125

    def __post_init__(self) -> None:
        super().__post_init__()
        if self.solver not in SOLVERS:
            raise ValueError(f"solver={self.solver!r} is unknown; allowed: {', '.join(SOLVERS)}")
        if self.contact_model not in CONTACT_MODELS:
            raise ValueError(f"contact_model={self.contact_model!r} is unknown; allowed: "
                             f"{', '.join(CONTACT_MODELS)}")
        if self.point_stiffness_npm is not None:
            _checks.positive("point_stiffness_npm", self.point_stiffness_npm)
        _checks.positive("restitution_speed_mps", self.restitution_speed_mps)
        _checks.positive("hydroelastic_modulus_pa", self.hydroelastic_modulus_pa)
        _checks.positive("resolution_hint_m", self.resolution_hint_m)
        if self.sap_near_rigid_threshold is not None:
            _checks.non_negative("sap_near_rigid_threshold", self.sap_near_rigid_threshold)
        _checks.in_range("accuracy", self.accuracy, 0.0, 0.1, lo_open=True)
        _checks.positive("relaxation_mass_kg", self.relaxation_mass_kg)


DISCRETE = ("lagged", "similar", "sap", "tamsi")
ACCURACIES = (1e-4, 1e-6, 1e-8)  # the continuous mode's error-control targets in the speed study


def _speed_accuracy() -> tuple[KnobFamily, ...]:
    """Each discrete approximation (point contact), the continuous mode at three accuracies, and
    hydroelastic contact with the reference solver (lagged and continuous in --quick)."""
    out = [KnobFamily(label=f"discrete {a}, point", quick=a == "lagged",
                      overrides=(("solver", a),)) for a in DISCRETE]
    out += [KnobFamily(label=f"continuous RK3 accuracy {acc:g}, point", quick=acc == 1e-6,
                       overrides=(("solver", "continuous"), ("accuracy", acc)))
            for acc in ACCURACIES]
    out += [KnobFamily(label="discrete lagged, hydroelastic",
                       overrides=(("solver", "lagged"), ("contact_model", "hydroelastic")))]
    return tuple(out)


RECORD = EngineRecord(
    name="drake", package="drake", import_name="pydrake", extra="drake",
    profiles={
        # Fidelity to Drake's own contact law (Hunt-Crossley point contact, k = 1e6 N/m, d
        # from e at 40 m/s): the continuous plant under RK3 with error control at 1e-6 relative
        # follows the law to 2e-8 m/s (paper's swing, s = 0.1 m; 1e-8 gives 3e-9 m/s at 4x the
        # cost, 1e-4 gives 1e-5 m/s) at about 25 ms an impact; every discrete approximation is
        # first order (-4.1% of v1 at 10 us, -0.4% at 1 us, 10x the cost). dt = 10 us is then
        # only the interval at which the harness reads the state (the contact is still seen
        # 1e-9 m deep); no SAP saturation (beta = 0), though only SAP-based solvers read it.
        "reference": DrakeSettings(dt_s=1e-5, solver="continuous", accuracy=1e-6,
                                   contact_model="point", point_stiffness_npm=1e6,
                                   sap_near_rigid_threshold=0.0),
        # Out of the box: MultibodyPlantConfig's 1 ms step, lagged approximation, hydroelastic
        # with fallback (our geometries declare no hydroelastic properties: point contact),
        # SceneGraph's default point stiffness per geometry; e mapped onto d as in the
        # reference (Drake's own d = 50 s/m would make every impact plastic); contact mid-step.
        "default": DrakeSettings(dt_s=1e-3, solver="lagged",
                                 contact_model="hydroelastic_with_fallback",
                                 point_stiffness_npm=None, contact_phase=0.5),
    },
    color="black", marker="X",
    speed_accuracy=_speed_accuracy(),
    # The swing study's integrators: each discrete approximation steps semi-implicit Euler
    # (v then q); the continuous mode is not one of them, since a body-frame load is held
    # constant over each of its steps (first order, whatever RK3's own order).
    integrators=tuple(Integrator(label=f"discrete {a}", overrides=(("solver", a),))
                      for a in ("lagged", "sap", "tamsi")),
    precision="float64",
    converges_to=ContactReference.HUNT_CROSSLEY,
    restitution_rule=RestitutionRule.MAPPED,
    # Every value read back from a fresh MultibodyPlantConfig / DefaultProximityProperties.
    engine_defaults={"dt_s": 1e-3, "solver": "lagged",
                     "contact_model": "hydroelastic_with_fallback",
                     "sap_near_rigid_threshold": 1.0, "point_stiffness_npm": 5e5},
)
pydrake = import_engine(RECORD)
from pydrake.geometry import (AddCompliantHydroelasticProperties,  # noqa: E402
                              AddContactMaterial, AddRigidHydroelasticProperties, Capsule,
                              DefaultProximityProperties, ProximityProperties, RoleAssign, Sphere)
from pydrake.math import RigidTransform, RotationMatrix  # noqa: E402
from pydrake.multibody.math import SpatialForce  # noqa: E402
from pydrake.multibody.plant import (AddMultibodyPlant, CoulombFriction,  # noqa: E402
                                     ExternallyAppliedSpatialForce, MultibodyPlantConfig)
from pydrake.multibody.tree import (FixedOffsetFrame, PrismaticJoint,  # noqa: E402
                                   RevoluteJoint, RotationalInertia, SpatialInertia)
from pydrake.systems.analysis import ResetIntegratorFromFlags, Simulator  # noqa: E402
from pydrake.systems.framework import DiagramBuilder  # noqa: E402

_NO_FRICTION = CoulombFriction(0.0, 0.0)


class DrakeEngine(Engine):
    """Drake behind the common contract."""

    record = RECORD

    @classmethod
    def contact_law(cls, settings: DrakeSettings, e: float):
        if settings.contact_model == "hydroelastic":
            return None  # a pressure field over a contact patch: no closed law stated here
        k = cls._stiffness(settings)
        if settings.solver == "sap":
            return LinearSpringDamper(stiffness_npm=k,
                                      damping_nspm=k * cls._relaxation_time(settings, e))
        d = _dissipation(e, settings.restitution_speed_mps)
        return HuntCrossley(stiffness=k, exponent=1.0, dissipation_spm=d)

    @classmethod
    def law_restitution_error(cls, settings: DrakeSettings, dt_over_contact: float) -> float:
        # continuous: RK3's error control holds each step's error to ``accuracy`` (relative);
        # 10x that bounds the contact's (measured at 1e-6: v1 within 9e-7 m/s of the law on the
        # reference baselines, about 1e-8 of e). Discrete: an implicit step damps the contact's
        # oscillation by about (w dt)^2 / 2 a step, (pi^2/2) dt/t_c over its half period
        # (measured: lagged at 10 us, 40 m/s central, 0.34 of it).
        if settings.solver == "continuous":
            return 10.0 * settings.accuracy
        return math.pi**2 / 2.0 * dt_over_contact

    @staticmethod
    def _stiffness(settings: DrakeSettings) -> float:
        """The contact's combined point stiffness (N/m)."""
        if settings.point_stiffness_npm is not None:
            return settings.point_stiffness_npm
        return 0.5 * DefaultProximityProperties().point_stiffness

    @classmethod
    def _relaxation_time(cls, settings: DrakeSettings, e: float) -> float:
        """SAP's combined tau (s): the linear spring-damper k, k tau bounces with e when its
        reduced mass is ``relaxation_mass_kg`` (zeta = tau w / 2, w = sqrt(k / m))."""
        w = math.sqrt(cls._stiffness(settings) / settings.relaxation_mass_kg)
        return 2.0 * damping_ratio_for(max(e, E_FLOOR)) / w

    @classmethod
    def read_back_defaults(cls) -> dict:
        config = MultibodyPlantConfig()
        return {"dt_s": config.time_step, "solver": config.discrete_contact_approximation,
                "contact_model": config.contact_model,
                "sap_near_rigid_threshold": config.sap_near_rigid_threshold,
                "point_stiffness_npm": 0.5 * DefaultProximityProperties().point_stiffness}

    def __init__(self, settings: DrakeSettings, *, name: str | None = None) -> None:
        super().__init__(settings, name=name)
        self._load: BodyLoad | None = None
        self._failures = 0      # steps Drake refused (a solver that did not converge)
        self._failed = False    # the current state is lost to such a step

    # -- building ------------------------------------------------------------------------------

    def build_scene(self, bat: Bat, ball: Ball) -> None:
        st = self.settings
        continuous = st.solver == "continuous"
        config = MultibodyPlantConfig(time_step=0.0 if continuous else st.dt_s,
                                      contact_model=st.contact_model,
                                      use_sampled_output_ports=False)
        if not continuous:
            config.discrete_contact_approximation = st.solver
        if st.sap_near_rigid_threshold is not None:
            config.sap_near_rigid_threshold = st.sap_near_rigid_threshold
        builder = DiagramBuilder()
        plant, sg = AddMultibodyPlant(config, builder)
        plant.mutable_gravity_field().set_gravity_vector([0.0, 0.0, 0.0])
        world = plant.world_body()
        massless = SpatialInertia.Zero()
        slider = plant.AddRigidBody("bat_slider", massless)
        hand = plant.AddRigidBody("bat_hand", massless)
        bat_body = plant.AddRigidBody("bat", SpatialInertia.MakeFromCentralInertia(
            bat.mass_kg, np.zeros(3), RotationalInertia(bat.axial_inertia_kgm2,
                                                        bat.inertia_cm_kgm2,
                                                        bat.inertia_cm_kgm2)))
        ib = ball.inertia_kgm2
        ball_body = plant.AddRigidBody("ball", SpatialInertia.MakeFromCentralInertia(
            ball.mass_kg, np.zeros(3), RotationalInertia(ib, ib, ib)))
        pivot = plant.AddFrame(FixedOffsetFrame("pivot", bat_body.body_frame(),
                                                RigidTransform()))
        self._x = plant.AddJoint(PrismaticJoint("bat_x", world.body_frame(),
                                                slider.body_frame(), [1.0, 0.0, 0.0]))
        self._y = plant.AddJoint(PrismaticJoint("bat_y", slider.body_frame(),
                                                hand.body_frame(), [0.0, 1.0, 0.0]))
        self._turn = plant.AddJoint(RevoluteJoint("bat_turn", hand.body_frame(), pivot,
                                                  [0.0, 0.0, 1.0]))
        a, b = bat.s_min_m, bat.s_max_m
        along_x = RigidTransform(RotationMatrix.MakeYRotation(math.pi / 2),
                                 [(a + b) / 2, 0.0, 0.0])  # Drake's capsules lie along z
        self._geoms = (
            plant.RegisterCollisionGeometry(bat_body, along_x, Capsule(bat.radius_m, b - a),
                                            "bat", self._properties(rigid=True)),
            plant.RegisterCollisionGeometry(ball_body, RigidTransform(), Sphere(ball.radius_m),
                                            "ball", self._properties(rigid=False)))
        plant.Finalize()
        self._source = plant.get_source_id()
        diagram = builder.Build()
        self.plant, self.sg, self.diagram = plant, sg, diagram
        self._bat, self._ball, self._pivot = bat_body, ball_body, pivot
        self._simulator = Simulator(diagram)
        ctx = self._simulator.get_mutable_context()
        self._ctx = ctx
        self._plant_ctx = plant.GetMyMutableContextFromRoot(ctx)
        self._sg_ctx = sg.GetMyMutableContextFromRoot(ctx)
        self._force_port = plant.get_applied_spatial_force_input_port()
        self._force_port.FixValue(self._plant_ctx, [])
        self._q_bat = [j.position_start() for j in (self._x, self._y, self._turn)]
        self._v_bat = [j.velocity_start() for j in (self._x, self._y, self._turn)]
        self._q_ball = ball_body.floating_positions_start()
        self._v_ball = ball_body.floating_velocities_start_in_v()
        self._query_port = plant.get_geometry_query_input_port()
        self._offset = 0.0
        self._discrete = not continuous

    def _properties(self, rigid: bool, dissipation: float | None = None) -> ProximityProperties:
        """Proximity properties of one geometry: both carry 2k (in series: k), the same d and
        tau (d combines to d; tau adds up, so each carries half), no friction."""
        st = self.settings
        props = ProximityProperties()
        k = None if st.point_stiffness_npm is None else 2.0 * st.point_stiffness_npm
        AddContactMaterial(dissipation=dissipation, point_stiffness=k, friction=_NO_FRICTION,
                           properties=props)
        if st.contact_model != "point" and (st.contact_model == "hydroelastic"):
            if rigid:
                AddRigidHydroelasticProperties(st.resolution_hint_m, props)
            else:
                AddCompliantHydroelasticProperties(st.resolution_hint_m,
                                                   st.hydroelastic_modulus_pa, props)
        return props

    def mass_properties(self) -> MassProperties:
        plant = self.plant
        ctx = plant.CreateDefaultContext()
        bat_m = self._bat.CalcSpatialInertiaInBodyFrame(ctx)
        ball_m = self._ball.CalcSpatialInertiaInBodyFrame(ctx)
        inspector = self.sg.model_inspector()
        X_BG = inspector.GetPoseInFrame(self._geoms[0])
        shape = inspector.GetShape(self._geoms[0])
        knob_x = X_BG.translation()[0] - shape.length() / 2 - shape.radius()
        return MassProperties(
            bat_mass_kg=float(bat_m.get_mass()),
            bat_com_from_knob_m=float(bat_m.get_com()[0] - knob_x),
            bat_inertia_kgm2=float(bat_m.CalcRotationalInertia().get_moments()[2]),
            ball_mass_kg=float(ball_m.get_mass()),
            ball_inertia_kgm2=float(ball_m.CalcRotationalInertia().get_moments()[2]),
        )

    def set_restitution(self, e: float) -> None:
        st = self.settings
        d = _dissipation(e, st.restitution_speed_mps)
        for geom, rigid in zip(self._geoms, (True, False)):
            props = self._properties(rigid, dissipation=d)
            if st.solver == "sap":  # tau adds up over the two geometries
                props.AddProperty("material", "relaxation_time",
                                  0.5 * self._relaxation_time(st, e))
            self.sg.AssignRole(self._sg_ctx, self._source, geom, props, RoleAssign.kReplace)

    # -- state ---------------------------------------------------------------------------------

    def _set_offset(self, offset_m: float) -> None:
        self._pivot.SetPoseInParentFrame(self._plant_ctx, RigidTransform([offset_m, 0.0, 0.0]))
        self._offset = offset_m

    def set_state(self, r: Reading) -> None:
        plant, pc = self.plant, self._plant_ctx
        self._ctx.SetTime(0.0)
        self._failed = False
        for joint in (self._x, self._y):
            joint.Unlock(pc)
        self._set_offset(0.0)
        q = np.zeros(plant.num_positions())
        v = np.zeros(plant.num_velocities())
        q[self._q_bat] = (r.bat_x, r.bat_y, r.bat_angle)
        v[self._v_bat] = (r.bat_vx, r.bat_vy, r.bat_w)
        i, j = self._q_ball, self._v_ball
        q[i:i + 7] = (1.0, 0.0, 0.0, 0.0, r.ball_x, r.ball_y, 0.0)
        v[j:j + 6] = (0.0, 0.0, r.ball_w, r.ball_vx, r.ball_vy, 0.0)
        plant.SetPositions(pc, q)
        plant.SetVelocities(pc, v)
        self._apply_load()
        if not self._discrete:
            # a fresh integrator: the last impact's step-size guess would otherwise carry over
            integ = ResetIntegratorFromFlags(self._simulator, "runge_kutta3", self.settings.dt_s)
            integ.set_target_accuracy(self.settings.accuracy)
            integ.set_maximum_step_size(self.settings.dt_s)
            self._simulator.Initialize()

    def read(self) -> Reading:
        if self._failed:
            return Reading(*([math.nan] * len(Reading._fields)))
        plant, pc = self.plant, self._plant_ctx
        q, v = plant.GetPositions(pc), plant.GetVelocities(pc)
        i, j = self._q_ball, self._v_ball
        x, y, th = q[self._q_bat]
        vx, vy, w = v[self._v_bat]
        p = self._offset
        c, s = math.cos(th), math.sin(th)
        return Reading(float(q[i + 4]), float(q[i + 5]), float(v[j + 3]), float(v[j + 4]),
                       float(v[j + 2]), float(x - p * c), float(y - p * s), float(th),
                       float(vx + w * p * s), float(vy - w * p * c), float(w))

    def step(self) -> None:
        if self._failed:
            return
        if self._load is not None:
            self._apply_load()
        try:
            self._advance()
        except RuntimeError:  # TAMSI not converging, the integrator's step below its minimum
            self._failures += 1
            self._failed = True

    def numerical_failures(self) -> int:
        return self._failures

    def _advance(self) -> None:
        if self._discrete:  # one periodic update, as the Simulator would make it
            pc = self._plant_ctx
            pc.get_mutable_discrete_state().SetFrom(self.plant.EvalUniquePeriodicDiscreteUpdate(pc))
            self._ctx.SetTime(self._ctx.get_time() + self.settings.dt_s)
        else:
            self._simulator.AdvanceTo(self._ctx.get_time() + self.settings.dt_s)

    def in_contact(self) -> bool:
        if self._failed:
            return False
        return len(self._query_port.Eval(self._plant_ctx).ComputePointPairPenetration()) > 0

    # -- the swing -----------------------------------------------------------------------------

    def _apply_load(self) -> None:
        load = self._load
        if load is None:
            self._force_port.FixValue(self._plant_ctx, [])
            return
        th = self.plant.GetPositions(self._plant_ctx)[self._q_bat[2]]
        q = th + load.angle_rad
        f = ExternallyAppliedSpatialForce()
        f.body_index = self._bat.index()
        f.p_BoBq_B = np.array([load.arm_m, 0.0, 0.0])
        f.F_Bq_W = SpatialForce([0.0, 0.0, load.torque_nm],
                                [load.force_n * math.cos(q), load.force_n * math.sin(q), 0.0])
        self._force_port.FixValue(self._plant_ctx, [f])

    def set_load(self, load: BodyLoad | None) -> None:
        self._load = load
        self._apply_load()

    def pin(self, pivot_from_com_m: float, pivot_xy_m: tuple[float, float]) -> None:
        # The bat turns about the pivot frame: moved to the hands, with the chain's x and y
        # now those of the hands (the bat itself does not move: its angle is kept).
        angle = self.read().bat_angle
        self._set_offset(pivot_from_com_m)
        q = self.plant.GetPositions(self._plant_ctx)
        q[self._q_bat] = (pivot_xy_m[0], pivot_xy_m[1], angle)
        self.plant.SetPositions(self._plant_ctx, q)
        for joint in (self._x, self._y):
            joint.Lock(self._plant_ctx)

    def unpin(self) -> None:
        for joint in (self._x, self._y):
            joint.Unlock(self._plant_ctx)


ENGINE = DrakeEngine
