"""Drake: a MultibodyPlant with a free sphere ball and a capsule bat on a six-joint chain.

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
- The bat hangs on a chain of massless links (x, y, z prismatic, then revolutes: the yaw about
  z, the tilt about -y, the roll about x, ``adapters.frames``' order) whose last child frame is
  a ``FixedOffsetFrame`` on the bat: its pose is a context parameter, so ``pin`` moves the
  hinge to the hands and locks every joint but the yaw (Joint.Lock), ``unpin`` unlocks; no
  rebuild, every solver, continuous too. The revolutes' rates are Euler-angle rates: the
  adapter turns the state's world angular velocity into them and back (exact to 1e-15 rad/s;
  the orientation and angular velocity Drake then reports equal ``frames.bat_quaternion`` and
  the state's). In the swing plane the extra joints stay at exactly 0: every frictionless
  planar impact gives the bits of the former planar chain (x, y, yaw; 41-point sweeps, both
  profiles). The ball's free joint takes (w, x, y, z, position) and its velocities are the
  spatial velocity in the world frame, angular first.
- A body-frame load is an ExternallyAppliedSpatialForce expressed in the world: the adapter
  turns it with the bat at the start of every step (what a first-order step samples anyway;
  the continuous mode holds it over each reading interval, which is why it is not one of the
  swing study's integrators).
- Friction: each geometry carries ``CoulombFriction(mu, mu)`` (static and dynamic both mu);
  Drake combines two geometries' values as 2 mu1 mu2 / (mu1 + mu2), static and dynamic apart
  (``CalcContactFrictionFromSurfaceProperties``; measured: bat 0.1 and ball 0.3 slide at
  0.15000 on the heavy wall, either way round). The properties live in SceneGraph's context,
  where ``set_body_friction`` replaces them. No rolling or torsional friction (Drake's point
  contact has none). A frictionless scene is built as before (CoulombFriction(0, 0)).
- The friction model: the continuous plant's is Stribeck's regularised Coulomb law, mu rising
  from 0 at no slip to mu_s at the stiction tolerance v_s and settling to mu_d by 3 v_s (Drake's
  documentation), circular in the tangent plane (measured: a slide at 45 degrees to the axis
  gets 0.99 of the mu of one along it, the surface's curve the rest, not a pyramid's sqrt(2)
  mu); TAMSI, lagged and similar regularise theirs with the same v_s and SAP with its own sigma
  (1e-3, a constant of Drake's SAP driver); the discrete ones use mu_d alone. v_s is the plant
  config's ``stiction_tolerance``, 1e-4 m/s out of the box (read back), set only for a scene
  with friction. A small v_s makes a sticking contact stiff: the reference's RK3 took 35 s an
  impact at 1e-4 on the paper's swing (mu 0.5, theta 0.3) and 2.6 s at 1e-3, the reference's,
  which moves vt1 by 3e-4 m/s and the spin by 0.02 rad/s. The lagged approximation bounds
  friction with the normal force of the step's start (its "lagged" one): at Drake's 1 ms a slide
  on the heavy wall (8 m/s along, 2 m/s in) gets 3.3 times mu's impulse, exact at 10 us and with
  SAP or similar at 1 ms. A compliant contact has no frictional law here: its frictional rows
  are unjudged, and its errors against Routh's answer follow its own normal impulse (e falls
  with speed).
- Drake raises when a solver fails (TAMSI not converging, the integrator's step underflowing):
  the adapter counts it as a numerical failure and the impact ends ``non_finite``. TAMSI is
  deprecated (Drake logs a warning when a TAMSI plant is built).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from analytic import checks
from analytic.compliant import (
    HuntCrossley,
    LinearSpringDamper,
    damping_ratio_for,
    hunt_crossley_dissipation,
)
from analytic.presets import BASEBALL

from ..records import (
    BallContact,
    Batching,
    Capabilities,
    ContactKnob,
    ContactReference,
    Cost,
    EngineRecord,
    ErrorModel,
    FrictionRule,
    Install,
    Integrator,
    KnobFamily,
    Presentation,
    ReportNotes,
    RestitutionRule,
    Settings,
    Studies,
)

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
#: The combined point stiffness of two geometries that declare none (N/m): SceneGraph's default
#: per geometry, 1e6 N/m, in series (read back by ``read_back_defaults``; a test pins it).
DEFAULT_POINT_STIFFNESS_NPM = 5e5
#: MultibodyPlantConfig's stiction tolerance (m/s): the slip speed at which a regularised
#: friction reaches mu (read back by ``read_back_defaults``; a test pins it).
DEFAULT_STICTION_TOLERANCE_MPS = 1e-4
#: SAP's friction regularisation, a constant of Drake's SAP driver (sigma = 1e-3, "consider
#: exposing": not a knob), quoted in ``friction_cone``.
SAP_SIGMA = 1e-3


def dissipation_spm(e: float, speed_mps: float) -> float:
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
    ``relaxation_mass_kg`` the reduced mass (kg) at which SAP's linear damper gives e;
    ``stiction_tolerance_mps`` the slip speed (m/s) below which a regularised friction falls
    short of mu (None: Drake's own): the continuous Stribeck model, TAMSI, lagged, similar;
    set only for a scene with friction."""

    solver: str = "lagged"
    contact_model: str = "point"
    point_stiffness_npm: float | None = 1e6
    restitution_speed_mps: float = 40.0
    hydroelastic_modulus_pa: float = 1e8
    resolution_hint_m: float = 0.01
    sap_near_rigid_threshold: float | None = None
    accuracy: float = 1e-8
    relaxation_mass_kg: float = 0.125
    stiction_tolerance_mps: float | None = None

    def __post_init__(self) -> None:
        super().__post_init__()
        if self.solver not in SOLVERS:
            raise ValueError(f"solver={self.solver!r} is unknown; allowed: {', '.join(SOLVERS)}")
        if self.contact_model not in CONTACT_MODELS:
            raise ValueError(
                f"contact_model={self.contact_model!r} is unknown; allowed: "
                f"{', '.join(CONTACT_MODELS)}"
            )
        if self.point_stiffness_npm is not None:
            checks.positive("point_stiffness_npm", self.point_stiffness_npm)
        checks.positive("restitution_speed_mps", self.restitution_speed_mps)
        checks.positive("hydroelastic_modulus_pa", self.hydroelastic_modulus_pa)
        checks.positive("resolution_hint_m", self.resolution_hint_m)
        if self.sap_near_rigid_threshold is not None:
            checks.non_negative("sap_near_rigid_threshold", self.sap_near_rigid_threshold)
        checks.in_range("accuracy", self.accuracy, 0.0, 0.1, lo_open=True)
        checks.positive("relaxation_mass_kg", self.relaxation_mass_kg)
        if self.stiction_tolerance_mps is not None:
            checks.positive("stiction_tolerance_mps", self.stiction_tolerance_mps)

    def stiffness_npm(self) -> float:
        """The contact's combined point stiffness (N/m)."""
        if self.point_stiffness_npm is not None:
            return self.point_stiffness_npm
        return DEFAULT_POINT_STIFFNESS_NPM

    def relaxation_time_s(self, e: float) -> float:
        """SAP's combined tau (s): the linear spring-damper k, k tau bounces with e when its
        reduced mass is ``relaxation_mass_kg`` (zeta = tau w / 2, w = sqrt(k / m))."""
        w = math.sqrt(self.stiffness_npm() / self.relaxation_mass_kg)
        return 2.0 * damping_ratio_for(max(e, E_FLOOR)) / w


class DrakeErrors(ErrorModel):
    """Drake's compliant contact: Hunt-Crossley (TAMSI, continuous) or SAP's linear law."""

    def contact_reference(self, s) -> ContactReference:
        return ContactReference.HUNT_CROSSLEY

    def contact_law(self, s, e: float):
        if s.contact_model == "hydroelastic":
            return None  # a pressure field over a contact patch: no closed law stated here
        k = s.stiffness_npm()
        if s.solver == "sap":
            return LinearSpringDamper(stiffness_npm=k, damping_nspm=k * s.relaxation_time_s(e))
        d = dissipation_spm(e, s.restitution_speed_mps)
        return HuntCrossley(stiffness=k, exponent=1.0, dissipation_spm=d)

    def law_restitution_error(self, s, dt_over_contact: float) -> float:
        # continuous: RK3's error control holds each step's error to ``accuracy`` (relative);
        # 10x that bounds the contact's (measured at 1e-6: v1 within 9e-7 m/s of the law on the
        # reference baselines, about 1e-8 of e). Discrete: an implicit step damps the contact's
        # oscillation by about (w dt)^2 / 2 a step, (pi^2/2) dt/t_c over its half period
        # (measured: lagged at 10 us, 40 m/s central, 0.34 of it).
        if s.solver == "continuous":
            return 10.0 * s.accuracy
        return math.pi**2 / 2.0 * dt_over_contact

    def friction_cone(self, s) -> str:
        vs = s.stiction_tolerance_mps or DEFAULT_STICTION_TOLERANCE_MPS
        if s.solver == "continuous":
            return f"circular, Stribeck-regularised (mu_s to v_s = {vs:g} m/s, mu_d beyond 3 v_s)"
        if s.solver == "sap":
            return f"circular, SAP's convex regularised cone (sigma = {SAP_SIGMA:g})"
        return f"circular, {s.solver}: friction regularised below v_s = {vs:g} m/s"


#: The ball's knobs in either model: e (at restitution_speed_mps, or SAP's at
#: relaxation_mass_kg) and the point stiffness k, which sets the contact time.
BALL_KNOBS = (
    ContactKnob(setting="e", lo=E_FLOOR, hi=0.95, unit="1"),
    ContactKnob(setting="point_stiffness_npm", lo=1e5, hi=1e8, unit="N/m", log=True),
)
#: SAP's linear damper as the ball's contact: its e is the same at every speed, and with the
#: relaxation mass the ball's own (its reduced mass on the 1e12 kg wall) the e knob is the
#: wall COR. SAP is first order: on the wall (k = 3e6 N/m, e = 0.55) it bounces with 0.5166,
#: 0.5397, 0.5465 at dt = 1e-5, 3e-6, 1e-6 s, the same to 1e-6 at 10, 25.9, 40 and 60 m/s
#: (measured; a linear law stepped linearly scales with the speed). 1e-6 s: the e knob is
#: the wall's COR within a tenth of MLB's half band (-0.0035) and the 0.7 ms contact is
#: resolved to 0.14%, at ~0.1 s an impact (its fit: 108 impacts, 11 s; Drake's whole real-ball
#: study 22 s). 1e-5 s would be 8x cheaper but 0.033 low: the fit would absorb that bias in e,
#: and the knob would no longer read as the ball's COR.
SAP_BALL = BallContact(
    label="SAP linear damper",
    overrides={"solver": "sap", "relaxation_mass_kg": BASEBALL.mass_kg},
    knobs=BALL_KNOBS,
    start=(0.5, 1e6),
    dt_s=1e-6,
    lasts=True,
    why="SAP's linear Kelvin-Voigt damper (tau from e at the ball's mass): one e at every "
    "speed; k sets the contact time",
)


DISCRETE = ("lagged", "similar", "sap", "tamsi")
ACCURACIES = (1e-4, 1e-6, 1e-8)  # the continuous mode's error-control targets in the speed study


def _speed_accuracy() -> tuple[KnobFamily, ...]:
    """Each discrete approximation (point contact), the continuous mode at three accuracies, and
    hydroelastic contact with the reference solver (lagged and continuous in --quick)."""
    out = [
        KnobFamily(label=f"discrete {a}, point", quick=a == "lagged", overrides=(("solver", a),))
        for a in DISCRETE
    ]
    out += [
        KnobFamily(
            label=f"continuous RK3 accuracy {acc:g}, point",
            quick=acc == 1e-6,
            overrides=(("solver", "continuous"), ("accuracy", acc)),
        )
        for acc in ACCURACIES
    ]
    out += [
        KnobFamily(
            label="discrete lagged, hydroelastic",
            overrides=(("solver", "lagged"), ("contact_model", "hydroelastic")),
        )
    ]
    return tuple(out)


RECORD = EngineRecord(
    name="drake",
    adapter="adapters.drake.adapter:DrakeEngine",
    install=Install(
        package="drake",
        import_name="pydrake",
        extra="drake",
        oldest="1.45.0",
        history=("1.45.0", "1.49.0", "1.51.1"),
    ),
    profiles={
        # Fidelity to Drake's own contact law (Hunt-Crossley point contact, k = 1e6 N/m, d
        # from e at 40 m/s): the continuous plant under RK3 with error control at 1e-6 relative
        # follows the law to 2e-8 m/s (paper's swing, s = 0.1 m; 1e-8 gives 3e-9 m/s at 4x the
        # cost, 1e-4 gives 1e-5 m/s) at about 25 ms an impact; every discrete approximation is
        # first order (-4.1% of v1 at 10 us, -0.4% at 1 us, 10x the cost). dt = 10 us is then
        # only the interval at which the harness reads the state (the contact is still seen
        # 1e-9 m deep); no SAP saturation (beta = 0), though only SAP-based solvers read it;
        # friction's stiction tolerance 1e-3 m/s (vt1 3e-4 m/s from 1e-4 at 1/13 of the cost).
        "reference": DrakeSettings(
            dt_s=1e-5,
            solver="continuous",
            accuracy=1e-6,
            contact_model="point",
            point_stiffness_npm=1e6,
            sap_near_rigid_threshold=0.0,
            stiction_tolerance_mps=1e-3,
        ),
        # Out of the box: MultibodyPlantConfig's 1 ms step, lagged approximation, hydroelastic
        # with fallback (our geometries declare no hydroelastic properties: point contact),
        # SceneGraph's default point stiffness per geometry; e mapped onto d as in the
        # reference (Drake's own d = 50 s/m would make every impact plastic); contact mid-step.
        "default": DrakeSettings(
            dt_s=1e-3,
            solver="lagged",
            contact_model="hydroelastic_with_fallback",
            point_stiffness_npm=None,
            contact_phase=0.5,
        ),
    },
    can=Capabilities(
        chain_adapter="adapters.drake.chain:DrakeChain",
        # The swing study's integrators: each discrete approximation steps semi-implicit Euler
        # (v then q); the continuous mode is not one of them, since a body-frame load is held
        # constant over each of its steps (first order, whatever RK3's own order).
        integrators=tuple(
            Integrator(label=f"discrete {a}", overrides=(("solver", a),))
            for a in ("lagged", "sap", "tamsi")
        ),
        restitution_rule=RestitutionRule.MAPPED,
        friction_rule=FrictionRule.HARMONIC,
    ),
    errors=DrakeErrors(
        precision="float64",
    ),
    # Every value read back from a fresh MultibodyPlantConfig / DefaultProximityProperties.
    engine_defaults={
        "dt_s": 1e-3,
        "solver": "lagged",
        "contact_model": "hydroelastic_with_fallback",
        "sap_near_rigid_threshold": 1.0,
        "point_stiffness_npm": DEFAULT_POINT_STIFFNESS_NPM,
        "stiction_tolerance_mps": DEFAULT_STICTION_TOLERANCE_MPS,
    },
    cost=Cost(
        step_cost_s=5.8e-4,
        # the bat alone, swung about the hands: 0.64 s an impact over 9933 steps on the hinged
        # baseline (sweep_all_reference_r161_hinged), against 5.8 s at the contact step's cost
        coast_step_cost_s=6.5e-5,
    ),
    look=Presentation(
        color="black",
        marker="X",
        label="Drake",
        notes=ReportNotes(
            profile=(
                "{solver} plant, RK3 with error control at {accuracy}, read every {dt_s}; "
                "{contact_model} contact k = {point_stiffness_npm} N/m"
            ),
            restitution=(
                "none: Hunt-Crossley dissipation d chosen so that a "
                "{restitution_speed_mps} m/s impact bounces with e; its e then falls "
                "with speed; judged against its own law"
            ),
            handled=(
                "no coefficient of restitution: its point contact is Hunt-Crossley, "
                "F = k x (1 + d x'), whose e falls with the impact speed (d set for e at "
                "{restitution_speed_mps} m/s), so against rigid theory it is up to {err_mps} "
                "m/s off on the paper's swing by design; against its own law "
                "(`analytic.compliant.HuntCrossley`, exponent 1) the reference is within "
                "{law_err_mps} m/s. Every discrete approximation is about first order against "
                "that law (`convergence.csv`); SAP replaces d by a linear damper (the adapter "
                "sets its relaxation time for e and judges it against `LinearSpringDamper`); "
                "hydroelastic contact states no closed law here (`unjudged`). The bat hangs "
                "on "
                "a planar joint chain whose pivot frame moves at run time, so the hands' "
                "hinge "
                "is a lock on that chain. A small e is floored (`E_FLOOR`): a Hunt-Crossley "
                "contact lets go with the overlap still open and cannot separate faster than "
                "1/d (drake#19320), so a near-plastic ball is caught again and again."
            ),
        ),
    ),
    studies=Studies(
        speed_accuracy=_speed_accuracy(),
    ),
    batching=Batching(
        call="pydrake.systems.analysis:BatchEvalUniquePeriodicDiscreteUpdate",
        worlds=True,
        why="Drake evaluates a discrete system's update at many states in one call, on "
        "threads (Parallelism); it takes a discrete plant and gives back the next states "
        "alone, while the reference profile is the continuous plant under an error-controlled "
        "integrator: not used, Drake has no pool adapter yet",
    ),
    balls=(
        # the reference's point contact: e sets d at restitution_speed_mps (E_FLOOR and up), k
        # the contact time (linear: t ~ pi sqrt(m/k), 0.7 ms for a baseball near 3e6 N/m)
        BallContact(
            label="Hunt-Crossley point contact",
            knobs=BALL_KNOBS,
            start=(0.5, 1e6),
            speed_dependent=True,
            lasts=True,
            why="Hunt-Crossley point contact: its e depends on d v alone (d from e at "
            "restitution_speed_mps), falling with speed, too steeply for COR_LAWS; k sets "
            "the contact time",
        ),
        SAP_BALL,
    ),
)
