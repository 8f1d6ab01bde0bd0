"""MuJoCo: two free bodies, a capsule bat and a sphere ball, no gravity, no friction.

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

from dataclasses import dataclass

from analytic import checks
from analytic.compliant import ContactSpaceSpringDamper, damping_ratio_for

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

INTEGRATORS = ("Euler", "implicitfast", "implicit", "RK4")
CONTACT_MODELS = ("impulse", "soft", "native")
#: MuJoCo's friction cones: the pyramid (its default: 2 (condim - 1) edges, each a normal-plus-
#: friction direction) or the elliptic cone (Coulomb's own, the friction's norm bounded by mu).
CONES = ("pyramidal", "elliptic")
#: The geoms' own contact (no pair), stiff and damped at dt = 1e-5 s as the impulse contact:
#: there MuJoCo combines the geoms' friction (max); a slide's friction is mu times its normal
#: force whatever the friction rows' reference (the test of ``friction_rule``).
NATIVE_FRICTION = {
    "contact_model": "native",
    "solref": (0.0, -1.5e5),
    "solimp": (0.99, 0.99, 0.001, 0.5, 2.0),
}
DEFAULT_SOLREF = (0.02, 1.0)  # MuJoCo's documented defaults
DEFAULT_SOLIMP = (0.9, 0.95, 0.001, 0.5, 2.0)


@dataclass(frozen=True, kw_only=True)
class MujocoSettings(Settings):
    """MuJoCo's knobs. ``integrator`` one of INTEGRATORS; ``contact_model`` one of
    CONTACT_MODELS; ``soft_omega_radps`` the soft contact's natural frequency w (rad/s);
    ``impedance`` the constant solimp d for impulse/soft; ``solref``/``solimp`` used as given by
    the native model; ``diagexact`` exact constraint diagonals; ``iterations``/``tolerance`` of
    the Newton solver; ``speculative`` MuJoCo's speculative contacts (margin ahead of touching);
    ``hinge_solref`` of the hands' releasable connect constraint (None: (2 dt, 1), the stiffest
    MuJoCo recommends); ``cone``: one of CONES (friction's); ``friction_impedance``: the
    constant impedance d of a frictional contact (``model.pair_parameters``)."""

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
    cone: str = "elliptic"
    friction_impedance: float = 0.9999

    def __post_init__(self) -> None:
        super().__post_init__()
        if self.integrator not in INTEGRATORS:
            raise ValueError(
                f"integrator={self.integrator!r} is unknown; allowed: {', '.join(INTEGRATORS)}"
            )
        if self.contact_model not in CONTACT_MODELS:
            raise ValueError(
                f"contact_model={self.contact_model!r} is unknown; allowed: "
                f"{', '.join(CONTACT_MODELS)}"
            )
        checks.positive("soft_omega_radps", self.soft_omega_radps)
        checks.in_range("impedance", self.impedance, 0.0001, 0.9999)
        checks.integer("iterations", self.iterations, 1, 10_000)
        checks.non_negative("tolerance", self.tolerance)
        checks.in_range("friction_impedance", self.friction_impedance, 0.0001, 0.9999)
        if self.cone not in CONES:
            raise ValueError(f"cone={self.cone!r} is unknown; allowed: {', '.join(CONES)}")


class MujocoErrors(ErrorModel):
    """MuJoCo's contact as its settings make it: an impulse or native contact is judged as a
    rigid impulse, a soft one against its spring-damper; friction through the convex solver."""

    def friction_law(self, s) -> str:
        # a convex solver (elliptic or pyramidal): a slide separates by mu |v_t'| (measured:
        # v1 +0.344 m/s against the one-step law, 4.7e-5 against the relaxed one; mu = 0.05,
        # theta = 0.5 rad on the paper's swing)
        return "relaxed"

    def friction_mapping_error_rel(self, s) -> float:
        # the frictional pair's rows are regularised at d = friction_impedance: (1 - d) of the
        # slip is left (measured 0.3-0.7 (1 - d) on the paper's swing; model.pair_parameters)
        return 0.0 if s.contact_model == "native" else 1.0 - s.friction_impedance

    def friction_cone(self, s) -> str:
        # a native contact's friction is the geoms' (condim 3); a tuned one is an explicit pair
        # whose solreffriction (0, -1/dt) takes the slip to rest in a step, bounded by the cone
        if s.cone == "pyramidal":
            return "pyramidal, 4 edges (condim 3)"
        return "elliptic (Coulomb's cone, condim 3)"

    def contact_reference(self, s) -> ContactReference:
        # impulse: one Euler step reverses the normal velocity as Newton's law asks; soft: a
        # spring-damper acting on the contact coordinate; native: untuned, judged as impulse
        if s.contact_model == "soft":
            return ContactReference.LINEAR_SPRING_DAMPER
        return ContactReference.RIGID_IMPULSE

    def untuned_contact_s(self, s) -> float | None:
        # native: a soft constraint of time constant solref[0] (0.02 s by default) that a
        # 47 m/s ball sinks through in 14-20 ms (R161, dt = 1e-6 s, measured)
        if s.contact_model != "native" or s.solref[0] <= 0.0:
            return None
        return s.solref[0]

    def contact_law(self, s, e: float):
        # soft: solref (-w^2, -2 zeta w) acts on J qacc, in contact space (package docstring)
        if s.contact_model != "soft":
            return None
        return ContactSpaceSpringDamper(
            omega_radps=s.soft_omega_radps, damping_ratio=damping_ratio_for(max(e, 1e-9))
        )


#: The soft constraint a real ball is fitted in: solref (time constant, damping ratio) and
#: solimp's impedance d0 at zero depth, d_width at depth ``width`` and that width, as given
#: (``native``). MuJoCo's reference acceleration is d (-b v - k d x) with k, b fixed by solref:
#: at constant impedance a scaled spring-damper, whose e is the same at every speed; an
#: impedance that changes with depth makes e change with speed (a deeper, faster impact meets
#: another d). The time constant is at least 2 dt (MuJoCo raises it to that).
NATIVE_KNOBS = (
    ContactKnob(setting="solref", element=0, lo=2e-5, hi=2e-2, unit="s", log=True),
    ContactKnob(setting="solref", element=1, lo=0.05, hi=2.0, unit="1"),
    ContactKnob(setting="solimp", element=0, lo=0.01, hi=0.99, unit="1"),
    ContactKnob(setting="solimp", element=1, lo=0.01, hi=0.99, unit="1"),
    ContactKnob(setting="solimp", element=2, lo=1e-4, hi=0.05, unit="m", log=True),
)


#: Where a fit of NATIVE_KNOBS starts: an impedance rising with depth (d0 < d_width), which
#: MuJoCo C and its ports compute alike; MJX and MuJoCo Warp clip the impedance into
#: [d0, d_width], so a falling one (d0 > d_width) is d_width at every depth there.
NATIVE_START = (1e-3, 0.2, 0.4, 0.95, 0.003)


def native_ball(why: str = "", **overrides) -> BallContact:
    """MuJoCo's soft constraint as the ball's contact (NATIVE_KNOBS, from NATIVE_START), with
    ``overrides`` to the reference profile besides ``contact_model="native"`` (a port's own
    regulariser and solver) and what they are for (``why``)."""
    return BallContact(
        label="native soft constraint",
        overrides={"contact_model": "native", **overrides},
        knobs=NATIVE_KNOBS,
        start=NATIVE_START,
        speed_dependent=True,
        lasts=True,
        dt_s=1e-5,
        why="solref/solimp as given: an impedance that changes with depth makes e change "
        "with speed; solref's time constant sets the contact time" + why,
    )


#: A port's ball on the wall: MJX and MuJoCo Warp stop their solver when its improvement,
#: divided by the mass matrix's trace (4e12 with the wall's 1e12 kg), is under ``tolerance``:
#: at 1e-8 before its first iteration, so the ball's velocity moved in flat steps through
#: the contact. Four iterations, no early stop (eight give the same bits).
PORT_BALL = native_ball(
    ". The port's own regulariser (invweight_scale 1); tolerance 0 and 4 iterations, "
    "the solver's early stop being scaled by the wall's mass",
    invweight_scale=1.0,
    tolerance=0.0,
    iterations=4,
)


SOFT_OMEGAS_RADPS = (1000.0, 3000.0, 10000.0)  # soft-contact stiffnesses of the speed study


def _speed_accuracy() -> tuple[KnobFamily, ...]:
    """Impulse and soft contact under each integrator (Euler and RK4 with w = 3000 in --quick)."""
    out = []
    for integrator in ("Euler", "implicitfast", "RK4"):
        quick = integrator != "implicitfast"
        out.append(
            KnobFamily(
                label=f"impulse, {integrator}", quick=quick, overrides=(("integrator", integrator),)
            )
        )
        out += [
            KnobFamily(
                label=f"soft w={w:g}, {integrator}",
                quick=quick and w == 3000.0,
                overrides=(
                    ("integrator", integrator),
                    ("contact_model", "soft"),
                    ("soft_omega_radps", w),
                ),
            )
            for w in SOFT_OMEGAS_RADPS
        ]
    return tuple(out)


RECORD = EngineRecord(
    name="mujoco",
    adapter="adapters.mujoco.adapter:MujocoEngine",
    install=Install(
        package="mujoco",
        import_name="mujoco",
        oldest="2.3.7",
        history=(
            "2.3.7",
            "3.0.1",
            "3.1.6",
            "3.2.7",
            "3.3.7",
            "3.5.0",
            "3.8.1",
            "3.9.0",
            "3.11.0",
            "3.14.0",
            "3.17.0",
            "4.0.0",
        ),
        release_notes={
            "3.9.0": "added the diagexact enable flag (the exact diagonal of the "
            "constraint-space inertia; the reference profile needs it): "
            "MuJoCo 3.9.0 changelog, General 2 (commit 71d1014e)"
        },
    ),
    profiles={
        # Fidelity to the impulse model: a 10 us step (contact tilt while the bat turns stays
        # ~1e-10), Euler (the impulse mapping is exact for one explicit step), impulse contact.
        "reference": MujocoSettings(
            dt_s=1e-5, integrator="Euler", contact_model="impulse", impedance=0.99, diagexact=True
        ),
        # Out of the box: 2 ms step, Euler, solref (0.02, 1), default solimp, no diagexact; the
        # contact instant falls mid-step as it would in an unaligned simulation.
        "default": MujocoSettings(
            dt_s=0.002,
            integrator="Euler",
            contact_model="native",
            diagexact=False,
            contact_phase=0.5,
            cone="pyramidal",
        ),
    },
    can=Capabilities(
        chain_adapter="adapters.mujoco.chain:MujocoChain",
        integrators=tuple(
            Integrator(
                label=name, overrides=(("integrator", name),), order=4 if name == "RK4" else 1
            )
            for name in ("Euler", "implicitfast", "RK4")
        ),
        restitution_rule=RestitutionRule.MAPPED,
        friction_rule=FrictionRule.MAX,
        soft_contact={"contact_model": "soft"},
        stiffness_setting="soft_omega_radps",
        pool_adapter="adapters.mujoco.worlds:MujocoWorlds",
    ),
    errors=MujocoErrors(),
    engine_defaults={
        "solref": DEFAULT_SOLREF,
        "solimp": DEFAULT_SOLIMP,
        "iterations": 100,
        "tolerance": 1e-8,
        "dt_s": 0.002,
        "integrator": "Euler",
        "cone": "pyramidal",
    },
    cost=Cost(
        step_cost_s=5.3e-6,
        # a pool world is a row of rollout's arrays: 0.2-0.9 us each growing a pool to 256-4096
        # worlds (its model, 1.3 ms, made once per process as one engine's); 2 us is 1/50 of
        # what a pooled impact saves (hosting.POOLED_SAVING_S): any long run repays a full pool
        pool_world_make_s=2e-6,
    ),
    look=Presentation(
        color="tab:green",
        marker="^",
        label="MuJoCo",
        notes=ReportNotes(
            profile=(
                "dt = {dt_s}, {integrator}, `impulse` contact: `solref = (0, -(1+e)/dt)`, "
                "constant impedance, `diagexact`"
            ),
            restitution=(
                "none: mapped by the adapter (`impulse`, or `soft` spring-damper calibrated for e)"
            ),
            defaults=(
                "MuJoCo's solref {default_solref}, solimp, iterations and {default_dt_s} "
                "step, read back"
            ),
        ),
    ),
    studies=Studies(
        speed_accuracy=_speed_accuracy(),
        friction_families=(KnobFamily(label="pyramidal cone", overrides=(("cone", "pyramidal"),)),),
        friction_rule_overrides=NATIVE_FRICTION,
    ),
    batching=Batching(
        call="mujoco.rollout:Rollout",
        worlds=True,
        used=True,
        why="MuJoCo's rollout: many worlds' mj_step in one C call on a persistent thread "
        "pool; a long run's pool adapter (MujocoWorlds) steps its worlds through it, bit for "
        "bit as alone",
        not_it=("mujoco:mju_threadpool",),  # one MjData's own pool: one world's work
    ),
    balls=(native_ball(),),
)


@dataclass(frozen=True, kw_only=True)
class RegularisedSettings(MujocoSettings):
    """MuJoCo's knobs as its JAX and Warp ports (MJX, MuJoCo Warp) take them: no ``diagexact``
    and no ``speculative`` (neither port has them), with ``invweight_scale`` (the factor on
    ``body_invweight0``, whose mean inverse mass W sets the contact's regulariser R = (1-d)/d
    W in place of diagexact's exact one) and ``ls_iterations`` (the line search's; None: the
    port's own)."""

    diagexact: bool = False
    invweight_scale: float = 1.0
    ls_iterations: int | None = None

    def __post_init__(self) -> None:
        super().__post_init__()
        if self.diagexact:
            raise ValueError(
                "diagexact=True is not in MuJoCo's ports; allowed: False (see "
                "invweight_scale for an exact impulse)"
            )
        if self.speculative:
            raise ValueError("speculative=True is not in MuJoCo's ports; allowed: False")
        checks.in_range("invweight_scale", self.invweight_scale, 1e-12, 1.0)
        if self.ls_iterations is not None:
            checks.integer("ls_iterations", self.ls_iterations, 1, 10_000)


class RegularisedErrors(MujocoErrors):
    """MuJoCo's ports (MJX, MuJoCo Warp): the regulariser's bias and stiffness (package
    docstring of ``RegularisedSettings``)."""

    def mapping_error_rel(self, s) -> float:
        # the impulse is c A / (d A + (1-d) s W), c = d + (1-d) s: for free bodies W =
        # 1/m + 1/M <= A, so it is off by at most (1 - d) s
        if s.contact_model == "native":
            return 0.0
        return (1.0 - s.impedance) * s.invweight_scale

    def solve_conditioning(self, s) -> float:
        # the Newton solve's Hessian adds D = 1/R to the contact's inverse mass A: A/R = d A /
        # ((1-d) s W), at least d / ((1-d) s); a native contact's d (0.9-0.95) leaves it small
        if s.contact_model == "native":
            return 1.0
        return s.impedance / ((1.0 - s.impedance) * s.invweight_scale)
