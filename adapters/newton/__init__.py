"""Newton (NVIDIA's physics engine on Warp), on Warp's CPU device (another with
BATSIM_WARP_DEVICE=cuda:0): many worlds per call.

Two free bodies per world, replicated with ``ModelBuilder.replicate`` (one Newton world each, so
only the bat and the ball of one world collide): the bat a massless capsule (density 0) on a
body whose origin is its COM, mass and principal inertia (axial, I_cm, I_cm) set on the body;
the ball a sphere. No gravity; friction as below (torsional and rolling friction 0). Solvers
(``solver``), e mapped as each allows:

- ``xpbd``: ``SolverXPBD`` with ``enable_restitution`` (off by default: e is then ignored and
  the bounce is what projecting the overlap out leaves, e = 0.037 for any target, central
  impact at 40 m/s): positions are projected out of contact, then a velocity pass drives
  each contact's normal velocity to -e times its value before the projection, with both bodies'
  effective mass: a rigid impulse (e = 0.3, 0.5, 1 met to 1e-7). Its e is the MEAN of the two
  shapes' restitution (``build_restitution_manifolds``): both get e. No velocity threshold
  but 2 |g| dt (0 here).
- ``mujoco``: ``SolverMuJoCo`` (MuJoCo Warp, its own collision, condim 1), e mapped as for
  MuJoCo C (``adapters.mujoco.model.contact_parameters``): ``impulse`` solref (0, -(1+e)/dt)
  with d = 0.9999 meets e to 1e-7 only with ``tolerance`` 0: at Newton's 1e-6 its Newton
  solver stops after one iteration 3e-4 short (energy gained at e = 1). ``soft``: the contact
  space spring-damper (within 0.03 m/s of its law at 1 us). ``native``: Newton's ke, kd
  turned into solref (0.02, 1). MuJoCo Warp has no ``diagexact`` (its regulariser takes
  body_invweight0: (1-d) relative at most).
- ``semi_implicit`` and ``featherstone``: a penalty contact evaluated at the step's start,
  F = ke x + kd max(x', 0) (x the overlap: damping only while x grows; ke, kd the two shapes'
  mean, Newton's 2.5e3 N/m and 100 N s/m by default). It releases at x = 0 with
  e = exp(-zeta acos(zeta)/sqrt(1 - zeta^2)) (``penalty_restitution``), zeta = kd/(2 sqrt(ke m)),
  m the contact's effective mass: ke, kd are tuned (``soft_omega_radps``) for e at
  ``penalty_mass_kg`` and judged against that law (``PenaltyLaw``) at the real masses.

Friction (scene mu > 0; none, and the model built as before, at mu = 0): each shape's ``mu``
(``ShapeConfig``: one coefficient, static = dynamic), torsional and rolling 0. XPBD and the
penalty solvers combine two shapes' mu as their mean (the contact kernels sum the shapes' and
divide by their count), SolverMuJoCo as their max (Newton writes each shape's mu into MuJoCo
Warp's ``geom_friction``); measured on a sliding impact with (0.02, 0.08): 0.0320 (XPBD: 0.64 of
the mean, below), 0.0500 (SemiImplicit), 0.0800 (MuJoCo). The record's rule is XPBD's.
- ``xpbd``: friction is positional only. The position pass undoes the contact points' slip,
  capped at mu times that pass's normal correction; the restitution (velocity) pass is
  frictionless. In an impact the position pass removes the approach (m v_n), the restitution
  pass adds e m v_n: a sliding impact gets mu/(1+e) of Coulomb's friction impulse (ball on a
  wall, e = 0.5, mu = 0.05: the tangential speed drops 0.878 m/s against 1.316, x 0.667, at
  20 iterations; 0.843 at XPBD's 2 iterations and relaxation 0.8). A sticking impact (mu = 1)
  stops the slip only with relaxation 1 (v_t 6.8488 against 6.8490 m/s; 6.958 at 0.8).
  No knob chooses another friction model.
- ``semi_implicit``, ``featherstone``: regularised Coulomb, F_t = kf v_t up to mu |F_n|, kf
  the shapes' mean ``friction_gain_nspm`` (Newton's 1000 N s/m, read back; 0 when
  frictionless, as before): on the wall, sliding mu 0.0500, rolling (mu = 1) to 2e-4 m/s.
- ``mujoco``: condim 3 (1 when frictionless), ``cone`` (Newton's pyramid by default, read
  back). A geom contact has no solreffriction: its friction rows take the contact's solref,
  the impulse solref's (1+e)/dt reversal, so a sticking contact leaves with its slip reversed
  by e (wall, mu = 1: ball spin -281 rad/s against -187, either cone); MuJoCo C's pair with
  solreffriction (0, -1/dt) would need Newton's ``mujoco:pair`` custom attributes.

Traps (measured with newton 1.8.0, warp-lang 1.19.0, mujoco-warp 4.0.0 on the CPU):
- ``State.body_qd`` is (v_com, omega), world frame, linear first (a body spun with (0, 0, 0,
  0, 0, 1) about a COM 0.5 m off its origin keeps the COM still); ``body_q`` is (p, quat x y z
  w). XPBD and SemiImplicit step body_q/body_qd, MuJoCo and Featherstone joint_q/joint_qd (a
  free joint's: the origin's pose, the COM's twist): body origin = COM here, the adapter
  writes both.
- Contacts are found ``gap`` ahead (``rigid_gap`` 0.1 m per shape, 0.2 m per pair; shape
  ``margin`` 0): XPBD solves such a contact in the step its gap closes, from the geometry of
  the step's start (speculative). The reference gap is 1 um, enough for float32 rounding of a
  1 nm overlap to still make a contact: a contact is solved in the step after it is found,
  from that instant's geometry. MuJoCo Warp acts on a contact only once dist < 0: a 1 nm overlap
  rounds to 0 and is acted on a step later, v dt deep.
- Newton projects the ball's centre onto the capsule's axis as t = (p - a).(b - a) /
  (|b - a|^2 + 1e-6 m^2): the foot falls 1.6e-6 |p - a| short (0.9 um at the COM of R161's
  0.78 m axis started at the knob, the normal tilted 1.3e-5 rad, the COP 1 um off); the
  capsule is laid so that its axis starts at the barrel end (0.25 um at the COP).
- XPBD's velocity pass takes the lever arms of the pose after the step's integration, the bat
  turned omega dt past the contact: first order in dt, 7.6e-4 m/s of v1 at 10 us on the
  paper's swing, 5e-5 at 1 us (where float32 rounding over a long slide's steps costs more).
  XPBD zeroes a body's velocity below 1e-4 m/s (spin below 1e-4 rad/s) in every position
  pass; rotation is a normalised first-order quaternion update.
- ``body_qd`` and a free joint's ``joint_qd`` are world-frame twists: a tilted, spinning bat
  reads back the same through XPBD, Featherstone and MuJoCo (three steps, measured), and
  no frame turn is needed; a world set in the plane reads its yaw as before
  (``adapters.mjx.frames_batch``: float32 rounding leaves the plane, 1.5e-4 rad/s about x).
- SemiImplicit and Featherstone damp every body's spin (``angular_damping`` 0.05 1/s by
  default): 0 in the reference and its knob families.
- Warp prints its banner and a line per compiled module on stdout (``config.log_level``: the
  adapter keeps warnings), and its CUDA probe complains on stderr without a driver (silenced).
  Kernels compile once into Warp's cache (~/.cache/warp), first run from an empty cache: XPBD
  20 s, SemiImplicit 10 s, Featherstone 17 s, MuJoCo Warp 34 s; the world count is a launch
  dimension, never a compile constant (builds at 1, 7, 41 worlds then take 0.05 s).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from scipy import optimize

from analytic import checks
from analytic.compliant import ContactSpaceSpringDamper, damping_ratio_for

from ..records import (
    Batching,
    Capabilities,
    ContactReference,
    Cost,
    EngineRecord,
    ErrorModel,
    FrictionRule,
    Install,
    KnobFamily,
    Presentation,
    ReportNotes,
    RestitutionRule,
    Settings,
    Studies,
)

SOLVERS = ("xpbd", "mujoco", "semi_implicit", "featherstone")
PENALTY_SOLVERS = ("semi_implicit", "featherstone")
MUJOCO_CONTACT_MODELS = ("impulse", "soft", "native")
MUJOCO_INTEGRATORS = ("euler", "implicitfast", "rk4")
#: SolverMuJoCo's friction cones; Newton's own (``SolverMuJoCo(cone=None)``) is the first.
CONES = ("pyramidal", "elliptic")
DEFAULT_CONE = CONES[0]
#: Newton's per-shape contact gap (ModelBuilder.rigid_gap), m.
DEFAULT_GAP_M = 0.1
#: Newton's shape contact stiffness and damping (ModelBuilder.ShapeConfig ke, kd).
DEFAULT_KE, DEFAULT_KD = 2.5e3, 100.0
#: The effective mass of the central impact of the R161 bat (0.871 kg) and a baseball
#: (0.145 kg): 1/(1/m + 1/M), at which the penalty contact is tuned by default.
CENTRAL_MASS_KG = 0.871 * 0.145 / (0.871 + 0.145)


def penalty_restitution(zeta: float) -> float:
    """e of Newton's penalty contact (damping only while the overlap grows) at damping ratio
    zeta: the compression ends at x' = 0 with x = (v/w) exp(-zeta g), g = acos(zeta)/sqrt(1 -
    zeta^2) (acosh/sqrt(zeta^2 - 1) above 1, 1 at 1), and the undamped spring returns w x."""
    if zeta <= 0.0:
        return 1.0
    if zeta < 1.0:
        g = math.acos(zeta) / math.sqrt(1.0 - zeta * zeta)
    elif zeta == 1.0:
        g = 1.0
    else:
        g = math.acosh(zeta) / math.sqrt(zeta * zeta - 1.0)
    return math.exp(-zeta * g)


def penalty_damping_ratio_for(e: float) -> float:
    """The inverse of ``penalty_restitution`` for e in (0, 1]."""
    checks.in_range("e", e, 0.0, 1.0, lo_open=True)
    if e == 1.0:
        return 0.0
    hi = 1.0
    while penalty_restitution(hi) > e:
        hi *= 2.0
    return optimize.brentq(lambda z: penalty_restitution(z) - e, 0.0, hi, xtol=1e-15, rtol=1e-15)


@dataclass(frozen=True, kw_only=True)
class PenaltyLaw:
    """Newton's penalty contact as an ``analytic.compliant`` law: F = k x + c max(x', 0) (N)
    while x > 0, ``stiffness_npm`` k (N/m), ``damping_nspm`` c (N s/m), whatever the masses;
    released at x = 0 (the force is k x once the overlap shrinks)."""

    stiffness_npm: float
    damping_nspm: float

    def force_n(self, x_m: float, rate_mps: float, m_eff_kg: float = 1.0) -> float:
        return self.stiffness_npm * x_m + self.damping_nspm * max(rate_mps, 0.0)

    def release_value(self, x_m: float, rate_mps: float, m_eff_kg: float = 1.0) -> float:
        return self.force_n(x_m, rate_mps, m_eff_kg)


@dataclass(frozen=True, kw_only=True)
class NewtonSettings(Settings):
    """Newton's knobs (None: the solver's own value). ``solver`` one of SOLVERS.
    XPBD: ``iterations`` (also MuJoCo's), ``enable_restitution``, ``contact_relaxation``
    (rigid_contact_relaxation), ``restitution_iterations``. Every solver: ``contact_gap_m``,
    each shape's contact detection gap (m); ``angular_damping`` (1/s). MuJoCo:
    ``contact_model`` one of MUJOCO_CONTACT_MODELS, ``impedance`` (solimp d), ``integrator``
    one of MUJOCO_INTEGRATORS, ``tolerance`` of its solver (0: until no improvement). MuJoCo
    ``soft`` and the penalty solvers: ``soft_omega_radps`` w, the contact's natural frequency
    (rad/s) at ``penalty_mass_kg`` for a penalty (None: Newton's ke, kd). Friction (scene mu >
    0): ``cone`` MuJoCo's, one of CONES; ``friction_gain_nspm`` the penalty solvers' viscous
    friction gain kf (N s/m), below Coulomb's cap (package docstring)."""

    solver: str = "xpbd"
    iterations: int | None = None
    enable_restitution: bool = True
    contact_relaxation: float | None = None
    restitution_iterations: int | None = None
    contact_gap_m: float | None = None
    angular_damping: float | None = None
    contact_model: str = "impulse"
    impedance: float = 0.9999
    integrator: str | None = None
    tolerance: float | None = None
    soft_omega_radps: float | None = 3000.0
    penalty_mass_kg: float = CENTRAL_MASS_KG
    cone: str | None = None
    friction_gain_nspm: float | None = None

    def __post_init__(self) -> None:
        super().__post_init__()
        for name, allowed in (("solver", SOLVERS), ("contact_model", MUJOCO_CONTACT_MODELS)):
            if getattr(self, name) not in allowed:
                raise ValueError(
                    f"{name}={getattr(self, name)!r} is unknown; allowed: {', '.join(allowed)}"
                )
        if self.integrator is not None and self.integrator not in MUJOCO_INTEGRATORS:
            raise ValueError(
                f"integrator={self.integrator!r} is unknown; allowed: "
                f"{', '.join(MUJOCO_INTEGRATORS)}"
            )
        for name in ("iterations", "restitution_iterations"):
            if getattr(self, name) is not None:
                checks.integer(name, getattr(self, name), 1, 10_000)
        if self.contact_relaxation is not None:
            checks.in_range("contact_relaxation", self.contact_relaxation, 0.0, 1.0, lo_open=True)
        for name in ("contact_gap_m", "angular_damping"):
            if getattr(self, name) is not None:
                checks.non_negative(name, getattr(self, name))
        if not isinstance(self.enable_restitution, bool):
            raise ValueError(
                f"enable_restitution={self.enable_restitution!r} is not a bool; "
                "allowed: True, False"
            )
        checks.in_range("impedance", self.impedance, 0.0001, 0.9999)
        if self.tolerance is not None:
            checks.non_negative("tolerance", self.tolerance)
        if self.soft_omega_radps is not None:
            checks.positive("soft_omega_radps", self.soft_omega_radps)
        elif self.solver == "mujoco" and self.contact_model == "soft":
            raise ValueError(
                "soft_omega_radps=None leaves MuJoCo's soft contact without a "
                "frequency; allowed: a positive value (rad/s)"
            )
        checks.positive("penalty_mass_kg", self.penalty_mass_kg)
        if self.cone is not None and self.cone not in CONES:
            raise ValueError(f"cone={self.cone!r} is unknown; allowed: None, {', '.join(CONES)}")
        if self.friction_gain_nspm is not None:
            checks.positive("friction_gain_nspm", self.friction_gain_nspm)

    def penalty_gains(self, e: float) -> tuple[float, float]:
        """ke (N/m) and kd (N s/m) of a penalty solver's contact at restitution e."""
        if self.soft_omega_radps is None:
            return DEFAULT_KE, DEFAULT_KD
        w, m = self.soft_omega_radps, self.penalty_mass_kg
        return w * w * m, 2.0 * penalty_damping_ratio_for(max(e, 1e-9)) * w * m


class NewtonErrors(ErrorModel):
    """Newton's contact by solver: XPBD's and the impulse solvers' rigid impulse, the
    penalty solvers' and MuJoCo Warp's soft contact their spring-damper law."""

    def friction_law(self, s) -> str:
        # its MuJoCo-Warp solver is MuJoCo's convex one: a slide separates by mu |v_t'|
        return "relaxed" if s.solver == "mujoco" else "one_step"

    def friction_cone(self, s) -> str:
        # package docstring: XPBD's restitution pass carries no friction
        if s.solver == "xpbd":
            return "positional, capped by the position pass's normal push (XPBD)"
        if s.solver == "mujoco":
            if (s.cone or DEFAULT_CONE) == "pyramidal":
                return "pyramidal, 4 edges (condim 3)"
            return "elliptic (Coulomb's cone, condim 3)"
        return "regularised: viscous kf v_t up to mu f_n"

    def contact_reference(self, s) -> ContactReference:
        soft = s.solver in PENALTY_SOLVERS or (s.solver, s.contact_model) == ("mujoco", "soft")
        return ContactReference.LINEAR_SPRING_DAMPER if soft else ContactReference.RIGID_IMPULSE

    def contact_law(self, s, e: float):
        if s.solver in PENALTY_SOLVERS:
            k, c = s.penalty_gains(e)
            return PenaltyLaw(stiffness_npm=k, damping_nspm=c)
        if (s.solver, s.contact_model) == ("mujoco", "soft"):
            return ContactSpaceSpringDamper(
                omega_radps=s.soft_omega_radps, damping_ratio=damping_ratio_for(max(e, 1e-9))
            )
        return None

    def law_restitution_error(self, s, dt_over_contact: float) -> float:
        # the penalty is evaluated at the step's start and its damping switches off at the
        # deepest point: measured up to 2.7 times the spring-damper's (pi/3) dt/t_c (R161,
        # s = 0, 5 and 40 m/s, dt = 1e-5..1e-7 s at w = 3000 rad/s)
        if s.solver in PENALTY_SOLVERS:
            return math.pi * dt_over_contact
        return super().law_restitution_error(s, dt_over_contact)

    def untuned_contact_s(self, s) -> float | None:
        # MuJoCo's native solref (0.02, 1): a soft constraint of time constant 0.02 s
        return 0.02 if s.solver == "mujoco" and s.contact_model == "native" else None

    def speculative_margin_m(self, s) -> float:
        # XPBD and the penalty solvers see a contact detected within both shapes' gaps at the
        # step's start; only XPBD solves it before the overlap (the penalty acts once x > 0)
        gap = DEFAULT_GAP_M if s.contact_gap_m is None else s.contact_gap_m
        return 2 * gap if s.solver == "xpbd" else 0.0


def _speed_accuracy() -> tuple[KnobFamily, ...]:
    """XPBD as the reference sets it, with Newton's own gap and with the cradle example's 10
    iterations; MuJoCo Warp's impulse and soft contacts; the two penalty solvers at w = 3000."""
    mujoco = (("solver", "mujoco"), ("tolerance", 0.0))
    return (
        KnobFamily(label="XPBD + restitution, 1 um gap (reference)", quick=True),
        KnobFamily(
            label="XPBD + restitution, Newton's 0.1 m gap (speculative)",
            quick=True,
            overrides=(("contact_gap_m", None),),
        ),
        KnobFamily(label="XPBD + restitution, 10 iterations", overrides=(("iterations", 10),)),
        KnobFamily(
            label="MuJoCo Warp, impulse solref, d = 0.9999, tolerance 0",
            quick=True,
            overrides=mujoco,
        ),
        KnobFamily(
            label="MuJoCo Warp, soft w = 3000",
            overrides=(*mujoco, ("contact_model", "soft"), ("soft_omega_radps", 3000.0)),
        ),
        KnobFamily(
            label="SemiImplicit, penalty w = 3000",
            quick=True,
            overrides=(("solver", "semi_implicit"), ("soft_omega_radps", 3000.0)),
        ),
        KnobFamily(
            label="Featherstone, penalty w = 3000",
            overrides=(("solver", "featherstone"), ("soft_omega_radps", 3000.0)),
        ),
    )


#: Newton's own values, read back by ``adapters.newton.defaults.read_back``: XPBD's constructor
#: defaults, the builder's contact gap, and the cradle example's step (60 fps, 10 substeps).
ENGINE_DEFAULTS = {
    "dt_s": 1 / 600,
    "iterations": 2,
    "contact_relaxation": 0.8,
    "restitution_iterations": 2,
    "contact_gap_m": DEFAULT_GAP_M,
    "angular_damping": 0.0,
    "friction_gain_nspm": 1000.0,
    "cone": DEFAULT_CONE,
}

RECORD = EngineRecord(
    name="newton",
    adapter="adapters.newton.adapter:NewtonEngine",
    install=Install(
        package="newton",
        import_name="newton",
        extra="newton",
        requires=("warp",),
        oldest="1.6.1",
        history=("1.6.1", "1.7.0", "1.8.0"),
    ),
    profiles={
        # XPBD with restitution: a rigid impulse. A 10 us step: the velocity pass takes the
        # lever arms of the pose after the step's integration, the bat turned omega dt past
        # the contact (max |dv1| over the paper's swing 7.6e-4 m/s at 10 us, 5.0e-5 at 1 us),
        # but float32 rounding piles up over a sustained slide's steps (the e = 0 swing: max
        # 0.023 m/s at 10 us, 0.07 at 3 us, 0.21 at 1 us with a row inaccurate). A 1 um gap
        # per shape: contacts found once touching (float32 rounding of the 1 nm overlap still
        # sees them), solved from that instant's geometry. Iterations, relaxation: XPBD's (4
        # iterations or relaxation 1 change the swing's v1 by < 1e-5 m/s). No spin damping
        # (XPBD's 0; the penalty solvers' 0.05).
        "reference": NewtonSettings(dt_s=1e-5, contact_gap_m=1e-6, angular_damping=0.0),
        # Out of the box: XPBD's defaults (2 iterations, relaxation 0.8, gap 0.1 m per shape) at
        # the cradle example's 1/600 s, restitution on (else e = 0.037 whatever the target).
        "default": NewtonSettings(dt_s=1 / 600, contact_phase=0.5),
    },
    can=Capabilities(
        chain_adapter="adapters.newton.chain:NewtonChain",
        integrators=(),  # no set_drive: the engine sits out the swing studies
        restitution_rule=RestitutionRule.MEAN,
        friction_rule=FrictionRule.MEAN,
        autodiff="Warp's reverse mode (wp.Tape) through SolverXPBD, contacts frozen as found",
    ),
    errors=NewtonErrors(
        precision="float32",
        chain_defect="XPBD: a joint's anchor correction is relaxed by 0.7 linearly and 0.4 "
        "angularly (no force at the anchor: the 8-segment chain's lowest mode at "
        "0.79 of its period, angular momentum not kept), and restitution solves a "
        "contact with the struck segment's own mass (first touch at x = 0.66 m: "
        "-7.49 m/s against -2.20 through the joints)",
        friction_defect="XPBD's friction is positional, capped by its position pass's normal "
        "correction: the restitution pass carries none, so a slide gets mu P / "
        "(1 + e) of tangential impulse for Coulomb's mu P (2/3 at e = 0.5; "
        "package docstring)",
        gradient_defect="wp.Tape through XPBD, contacts frozen as found: paper's swing, dv1/ds "
        "0.38 for 14.0 (m/s)/m at s = 0.05 m, 0.014 for -67.0 at 0.24; dv1/dv0 "
        "-0.25 for +0.28; dv1/dJ 0.373 of the closed form everywhere",
    ),
    engine_defaults=ENGINE_DEFAULTS,
    cost=Cost(step_cost_s=2.7e-3, world_step_cost_s=2e-6, start_s=0.3),
    look=Presentation(
        color="crimson",
        marker="X",
        label="Newton",
        notes=ReportNotes(
            profile=(
                "dt = {dt_s}, XPBD with `enable_restitution`, contact gap {contact_gap_m} "
                "per shape ({default_contact_gap_m} by default)"
            ),
            restitution=(
                "each shape's restitution, combined as their mean (XPBD; both set to "
                "e); ignored unless the solver's `enable_restitution` is on (off by "
                "default)"
            ),
            handled=(
                "XPBD's velocity pass uses the lever arms of the pose after the step's "
                "integration (first order in dt); Newton projects the ball onto the "
                "capsule's axis with a 1e-6 m^2 regulariser (a micrometre "
                "off along a 0.78 m bat: the axis starts at the barrel end); contacts are "
                "found {default_contact_gap_m} per shape ahead by default and solved from "
                "that step's start (speculative); no hands (no set_drive)."
            ),
            defaults=(
                "XPBD's iterations, relaxation and the builder's gap read back from fresh "
                "objects; the step from Newton's cradle example's source"
            ),
        ),
    ),
    studies=Studies(
        speed_accuracy=_speed_accuracy(),
        friction_families=(
            KnobFamily(label="XPBD, relaxation 1", overrides=(("contact_relaxation", 1.0),)),
            KnobFamily(
                label="MuJoCo Warp, impulse solref, elliptic cone, tolerance 0",
                overrides=(("solver", "mujoco"), ("tolerance", 0.0), ("cone", "elliptic")),
            ),
            KnobFamily(
                label="SemiImplicit, penalty w = 3000, Newton's kf",
                overrides=(("solver", "semi_implicit"),),
            ),
        ),
    ),
    batching=Batching(
        call="newton.solvers:SolverBase.step",
        worlds=True,
        used=True,
        why="one model holds every world (replicated) and each step is one solver call "
        "over all of them: batched by design",
    ),
)
