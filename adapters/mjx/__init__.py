"""MJX (MuJoCo XLA): MuJoCo's model in JAX, many worlds per call (vmap), on a CPU or a GPU.

The same MJCF and e-mapping as MuJoCo C (``adapters.mujoco.model``); what MJX lacks decides the
rest. It has no ``diagexact``: a contact's regulariser R = (1-d)/d W takes W from the bodies'
``body_invweight0`` (a mean of their inverse masses and inertias), not the exact inverse
inertia A = 1/m + 1/M + s^2/J along the contact normal. The impulse mapping then scales the
approach's reversal by A/(d A + (1-d) W) instead of 1 (measured: 1e-4 relative, 5e-3 m/s at
d = 0.9999). ``invweight_scale`` multiplies ``body_invweight0`` as the model is put on the
device: a small value makes R vanish beside A, and the impulse solref carries d (solref =
(0, -(1+e) d/dt) once R ~ 0, which the solver's 1/d cancels) so that one Euler step reverses
the normal velocity exactly, as ``diagexact`` does in C. ``invweight_scale = 1`` is MJX's own
model, MuJoCo C's without ``diagexact`` (its twin).

Two engines share this adapter: ``mjx`` computes in JAX's default float32, ``mjx64`` in
float64 (JAX's x64 mode, scoped to this adapter's calls).

Friction (scene mu > 0; checked with mujoco-mjx 3.17.0): MuJoCo C's MJCF
(``adapters.mujoco.model.mjcf``). A tuned contact (impulse, soft) is an explicit ``<pair>``
(condim 3, mu along both tangents) with C's solref, solimp (d = ``friction_impedance``) and
solreffriction (0, -1/dt) (``model.pair_parameters``), each times d + (1-d)
``invweight_scale`` as the geoms' solref (1 at MJX's own regulariser: C's very values). A
native contact (the default profile) is the geoms' own, condim 3, their friction combined
by max (MJX's collision driver takes ``jp.maximum`` of the two geoms' friction, priorities
aside: the record's ``friction_rule``). ``put_model`` takes pairs, solreffriction and both
cones (``cone``: elliptic at the reference, MJX's pyramid by default, read back). Traps:
- ``make_data`` refuses an elliptic cone with any condim-1 contact ("condim=1 with
  ConeType.ELLIPTIC not implemented"): a frictionless model keeps MJX's default cone,
  whatever ``cone`` says (and is built exactly as before).
- solreffriction acts only in an elliptic cone: a pyramid's edge rows take the contact's
  solref, the impulse reversal (1+e)/dt, so a contact that sticks leaves with its slip
  reversed by e instead of stopped (as in MuJoCo C).
- ``set_body_friction`` sets the geoms' friction, which an explicit pair does not read (its
  friction is fixed when the MJCF compiles): the combine rule shows on a native contact.
- Free joints keep their angular velocity in the body's frame: ``frames_batch`` turns the
  bat's into the world's and back (rows turned about z alone are left bit for bit).
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

from ..mujoco import NATIVE_FRICTION, PORT_BALL, RegularisedErrors, RegularisedSettings
from ..records import (
    Batching,
    Capabilities,
    Cost,
    EngineRecord,
    FrictionRule,
    Install,
    Integrator,
    KnobFamily,
    Presentation,
    ReportNotes,
    RestitutionRule,
    Studies,
    TwinStep,
)

INTEGRATORS = ("Euler", "implicitfast", "RK4")  # MJX has no fully implicit integrator
#: What MJX adds to a segment's squared length in its closest-point routine
#: (``mujoco.mjx._src.math.closest_segment_point``, mujoco-mjx 3.17.0; m^2): a declared defect,
#: MJX's own routine, stepped as it is (``MjxErrors.collision_slide_m`` bounds its effect).
SEGMENT_GUARD_M2 = 1e-6


@dataclass(frozen=True, kw_only=True)
class MjxSettings(RegularisedSettings):
    """MuJoCo's knobs as MJX takes them (``RegularisedSettings``: no ``diagexact``, with
    ``invweight_scale``, package docstring)."""

    def __post_init__(self) -> None:
        super().__post_init__()
        if self.integrator not in INTEGRATORS:
            raise ValueError(
                f"integrator={self.integrator!r} is not in MJX; allowed: {', '.join(INTEGRATORS)}"
            )


class MjxErrors(RegularisedErrors):
    """MJX: its ports' errors and its capsule routine's guard (``SEGMENT_GUARD_M2``)."""

    def collision_slide_m(self, s, bat) -> float:
        # MJX's closest point on the capsule's segment divides by |b - a|^2 + 1e-6 m^2: the
        # foot moves toward a by up to 1e-6 / |b - a| (1.3 um on the R161), the normal tilts
        # by that over r1 + r2, and the impulse's line crosses the axis that far off
        return SEGMENT_GUARD_M2 / (bat.s_max_m - bat.s_min_m)


#: MJX against MuJoCo C, cause by cause: each at its reference; the same model (C without
#: diagexact, MJX with its own regulariser); then the soft contact the issue measured
#: (w = 3000 rad/s) on the same model. What is left is MJX's capsule routine
#: (SEGMENT_GUARD_M2), a declared defect.
TWIN_STEPS = (
    TwinStep(label="each at its reference profile", shared=False),
    TwinStep(
        label="same model: MJX's regulariser, C without diagexact",
        overrides=(("invweight_scale", 1.0),),
    ),
    TwinStep(
        label="soft w=3000, same model",
        overrides=(
            ("invweight_scale", 1.0),
            ("contact_model", "soft"),
            ("soft_omega_radps", 3000.0),
            ("impedance", 0.99),
        ),
    ),
)

#: MJX's out-of-the-box values, read back from a freshly put model (``read_back_defaults``).
ENGINE_DEFAULTS = {
    "solref": (0.02, 1.0),
    "solimp": (0.9, 0.95, 0.001, 0.5, 2.0),
    "iterations": 100,
    "tolerance": 1e-8,
    "ls_iterations": 50,
    "dt_s": 0.002,
    "integrator": "Euler",
    "cone": "pyramidal",
}

#: Why float32 MJX has no ``knob_derivative`` (measured, mujoco-mjx 3.17.0 on a CPU, a
#: baseball at 20 and 50 m/s against a native contact, solref (2e-4, 0.5), solimp (0.5, 0.95,
#: 0.005, 0.5, 2), dt = 1e-5 s).
KNOB_FLOAT32 = (
    "float32 tangents by the contact knobs are NaN with the solver run to its iteration "
    "limit (tolerance 0, which analytic.ball.WALL's 1e12 kg needs: trace(M) scales the stop "
    "test), and at MJX's tolerance against a 10 kg wall differ from float32 finite "
    "differences by 1e-3 to 0.25 relative, those differences noise at every step (float64 "
    "agrees to 1e-5)"
)

RECORD = EngineRecord(
    name="mjx",
    adapter="adapters.mjx.adapter:MjxEngine",
    install=Install(
        package="mujoco-mjx",
        import_name="mujoco.mjx",
        extra="mjx",
        requires=("mujoco", "jax"),
        released_with=("mujoco",),
        oldest="3.8.1",
        history=("3.8.1", "3.11.0", "3.17.0"),
    ),
    profiles={
        # Fidelity: MuJoCo C's reference (10 us, Euler, impulse contact) at d = 0.9999 with
        # MJX's own regulariser: a 1e-4 relative bias (stated: ``mapping_error_rel``); a
        # smaller one leaves the float32 Newton solve ill-conditioned (x 0.1 .. 1e-3: misses
        # of 0.1-1.25 m/s at random points; x 1e-10: NaN). Placed 1 um deep: float32 positions
        # near 1 m are 6e-8 m apart, so a 1 nm overlap may go unseen for a step.
        "reference": MjxSettings(
            dt_s=1e-5, contact_model="impulse", impedance=0.9999, overlap_m=1e-6
        ),
        # Out of the box: MJX's 2 ms step, Euler, solref (0.02, 1), default solimp, its own
        # regulariser, the contact instant mid-step.
        "default": MjxSettings(
            dt_s=0.002, contact_model="native", contact_phase=0.5, cone="pyramidal"
        ),
    },
    can=Capabilities(
        chain_adapter="adapters.mjx.chain:MjxChain",
        integrators=tuple(
            Integrator(
                label=name, overrides=(("integrator", name),), order=4 if name == "RK4" else 1
            )
            for name in ("Euler", "RK4")
        ),
        restitution_rule=RestitutionRule.MAPPED,
        friction_rule=FrictionRule.MAX,
        soft_contact={"contact_model": "soft"},
        stiffness_setting="soft_omega_radps",
        twin_of="mujoco",
        autodiff="JAX's forward mode (jax.jvp) through mjx.step",
    ),
    errors=MjxErrors(
        chain_defect="float32 Newton solve of a touch on a light hinged segment: its matrix's "
        "condition (about 3e8) is past 1/eps, the solve returns a NaN qacc and drops "
        "the contact (2 of 11 points at N = 8 non_finite, every point at N >= 16)",
        precision="float32",
        # measured: float32 rows 0.086 m/s apart (2.8%) between two x86-64 hosts, float64 2e-8 m/s
        host_rounding=True,
    ),
    engine_defaults=ENGINE_DEFAULTS,
    cost=Cost(
        step_cost_s=1.6e-3,
        world_step_cost_s=1e-5,
        start_s=3.0,
    ),
    look=Presentation(
        color="darkgreen",
        marker="v",
        label="MJX",
        notes=ReportNotes(
            profile=(
                "dt = {dt_s}, {integrator}, `impulse` contact (d = {impedance}), MJX's "
                "regulariser, placed {overlap_m} deep"
            ),
            restitution="none: mapped by the adapter, as for MuJoCo C",
            handled=(
                "no `diagexact` in MJX: the regulariser scaled instead (its own leaves the "
                "impulse 1e-4 relative off); its capsule routine adds 1e-6 m^2 to the "
                "segment's squared length (a 1.3 um foot bias, stated)"
            ),
            defaults="MJX's solref {default_solref}, iterations and {default_dt_s} step, read back",
        ),
    ),
    studies=Studies(
        speed_accuracy=(
            KnobFamily(label="impulse, MJX's regulariser", quick=True),
            KnobFamily(
                label="soft w=3000, Euler",
                quick=True,
                overrides=(
                    ("contact_model", "soft"),
                    ("soft_omega_radps", 3000.0),
                    ("impedance", 0.99),
                ),
            ),
        ),
        friction_families=(KnobFamily(label="pyramidal cone", overrides=(("cone", "pyramidal"),)),),
        friction_rule_overrides=NATIVE_FRICTION,
        twin_steps=TWIN_STEPS,
    ),
    batching=Batching(
        call="mujoco.mjx:step",
        worlds=True,
        used=True,
        why="the adapter steps every world in one jitted call of mjx.step vmapped over the "
        "worlds (jax.vmap): batched by design",
    ),  # MJX's own regulariser (its reference's, 1e-7, would make the soft constraint rigid)
    balls=(PORT_BALL,),
)

#: The same engine in float64, its regulariser made negligible, as diagexact does in C (package
#: docstring): 1e-7 leaves 1e-11 relative; smaller ones lose more to the solver's conditioning
#: (1e-8: 3e-8 m/s off at the COM, 1e-9: 5e-6 m/s).
RECORD_64 = dataclasses.replace(
    RECORD,
    name="mjx64",
    adapter="adapters.mjx.adapter:Mjx64Engine",
    errors=dataclasses.replace(RECORD.errors, precision="float64", chain_defect=""),
    can=dataclasses.replace(
        RECORD.can,
        chain_adapter="adapters.mjx.chain:Mjx64Chain",
        knob_autodiff="JAX's forward mode through mjx.step along the contact arrays each "
        "settings knob moves (solref, solimp; soft: w, d), every knob in one vmapped call",
    ),
    profiles={
        **RECORD.profiles,
        "reference": MjxSettings(
            dt_s=1e-5, contact_model="impulse", impedance=0.9999, invweight_scale=1e-7
        ),
    },
    studies=dataclasses.replace(
        RECORD.studies,
        speed_accuracy=(
            KnobFamily(label="impulse, regulariser x 1e-7", quick=True),
            KnobFamily(label="impulse, MJX's regulariser", overrides=(("invweight_scale", 1.0),)),
            KnobFamily(
                label="soft w=3000, Euler",
                quick=True,
                overrides=(
                    ("contact_model", "soft"),
                    ("soft_omega_radps", 3000.0),
                    ("impedance", 0.99),
                    ("invweight_scale", 1.0),
                ),
            ),
        ),
    ),
    look=dataclasses.replace(
        RECORD.look,
        color="yellowgreen",
        label="MJX (float64)",
        notes=dataclasses.replace(
            RECORD.look.notes,
            profile=(
                "dt = {dt_s}, {integrator}, `impulse` contact (`solref = (0, -(1+e) c/dt)`, "
                "d = {impedance}) with `body_invweight0` x {invweight_scale}"
            ),
        ),
    ),
)
