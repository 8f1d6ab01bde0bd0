"""MuJoCo Warp: MuJoCo's model in Warp kernels, many worlds per call, on Warp's CPU (or a GPU).

The same MJCF and e-mapping as MuJoCo C (``adapters.mujoco.model``); what MuJoCo Warp lacks or
changes decides the rest (measured with mujoco-warp 4.0.0, warp-lang 1.19.0, on the CPU):
- It computes in float32 only (Warp's ``float``).
- No ``diagexact`` (``put_model`` refuses the flag), nor ``speculative``: as in MJX, a
  contact's regulariser R = (1-d)/d W takes W from ``body_invweight0``, not the exact inverse
  inertia A along the normal, and the impulse mapping reverses the approach by
  A/(d A + (1-d) W) instead of 1 (for the R161 and a baseball A - W <= 0.17 A: at most
  (1-d) 0.17 relative). ``invweight_scale`` multiplies ``body_invweight0`` before the model is
  put on the device and the impulse solref carries d + (1-d) scale, as the MJX adapter does;
  1 is MuJoCo Warp's own model, MuJoCo C's without ``diagexact`` (its twin).
- Its float32 Newton solve of a stiff contact (R << A) gets J qacc right to float32 but the
  split of the impulse between the bodies (the part of qacc that J does not see) only to what
  the gradient, dominated by the D-amplified rounding of J qacc - aref, can resolve: stopped
  at MuJoCo's tolerance 1e-8 it ends after one Newton step up to 1e-3 off (0.045 m/s, energy
  +2e-3 at e = 1, d = 0.9999); at tolerance 0 it iterates until its line search stalls and
  rare misses remain that grow as 1/R (18018 impacts: 0.014 m/s at d = 0.9998, 0.025 m/s at
  0.9999, 0.115 m/s at 0.9999 with R x 0.1).
- ``put_model`` raises the solver tolerance to at least 1e-6 (a float32 solve); the adapter
  writes the settings' tolerance back into the device model.
- The solver's iterations are a ``capture_while`` that ends when every world has converged: at
  tolerance 0 a world with a constraint runs them all. Launched from Python a step costs
  2.5-18 ms on the CPU at one world (hundreds of kernel launches; a hinged step 8.3 ms with
  100 iterations, 3.4 ms with 10), so the adapter records one step with Warp's graph capture
  (CPU graphs since Warp 1.13) and replays it: about 0.06 ms at one world, the same bits (the
  baselines reproduce to 1e-11).
- Contacts of every world share one list (``Contact.worldid``, ``nacon``); at margin 0 only
  overlapping pairs are written. Overflows and the solver's iteration limits are per-world bits
  (``Data.overflow``); a state that blows up stays non-finite (no reset, unlike MuJoCo C).
- Model fields have a leading batch dimension: the hands' site position and hinge anchors are
  put per world, so every world may have its own hands.
- Its sphere-capsule routine projects onto the segment exactly (no guard term, unlike MJX).
- Friction (scene mu > 0), MuJoCo C's MJCF and parameters as in MJX (``adapters.mjx``): a
  tuned contact an explicit ``<pair>`` (condim 3) with C's solref, solimp and solreffriction
  (0, -1/dt), each times d + (1-d) ``invweight_scale``; a native one the geoms' condim 3,
  their friction combined by max (``contact_material_params``: ``wp.max`` of the two geoms'
  friction, priorities aside), floored at MJ_MINMU. ``put_model`` takes pairs, solreffriction
  and both cones (``cone``: elliptic at the reference, its pyramid by default, read back);
  it warns that the pair's geoms (condim 3, friction 0) "may cause NaN": they never make a
  contact of their own (the pair replaces it), the warning is dropped. As in C and MJX,
  solreffriction acts only in an elliptic cone (a pyramid's edges take the contact's solref),
  and an explicit pair keeps the friction it was compiled with (``set_body_friction`` sets
  the geoms'). Free joints keep their angular velocity in the body's frame (``frames_batch``).
Kernels compile once into Warp's cache (~/.cache/warp; 36 modules, 16 s cold for an Euler
step): the world count, dt, solref, tolerance and ``iterations`` are launch arguments;
``ls_iterations``, the integrator (implicitfast: 2 modules) and the overflow print mask are
compile constants (a new value compiles its kernels once).
"""

from __future__ import annotations

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

INTEGRATORS = ("Euler", "implicitfast", "implicit", "RK4")
#: MuJoCo Warp's out-of-the-box values, read back from a freshly put model
#: (``read_back_defaults``): MuJoCo C's, but the tolerance raised to 1e-6.
ENGINE_DEFAULTS = {
    "solref": (0.02, 1.0),
    "solimp": (0.9, 0.95, 0.001, 0.5, 2.0),
    "iterations": 100,
    "tolerance": 1e-6,
    "ls_iterations": 50,
    "dt_s": 0.002,
    "integrator": "Euler",
    "cone": "pyramidal",
}


@dataclass(frozen=True, kw_only=True)
class MjwarpSettings(RegularisedSettings):
    """MuJoCo's knobs as MuJoCo Warp takes them (``RegularisedSettings``: no ``diagexact``,
    with ``invweight_scale``, package docstring) and ``device`` (Warp's device name, e.g.
    "cpu" or "cuda:0"; None: the environment's BATSIM_WARP_DEVICE, else Warp's default)."""

    device: str | None = None

    def __post_init__(self) -> None:
        super().__post_init__()
        if self.device is not None and not self.device:
            raise ValueError("device='' is not a Warp device; allowed: None, 'cpu', 'cuda:N'")


SOFT = (("contact_model", "soft"), ("soft_omega_radps", 3000.0), ("impedance", 0.99))

#: MuJoCo Warp against MuJoCo C, cause by cause (``experiments.twins``): each at its reference;
#: the soft contact as each is configured (C with diagexact); the same model with MuJoCo
#: Warp's solver stopping at MuJoCo's tolerance (its float32 solve then splits the impulse
#: between the bodies up to 1e-3 wrong); the same model with 100 iterations (no change: the
#: solve has converged in 10); the soft contact, same model; then the same model as the
#: reference, every known cause removed (MuJoCo Warp's regulariser in both, C without
#: diagexact): float32 rounding is what is left.
TWIN_STEPS = (
    TwinStep(label="each at its reference profile", shared=False),
    TwinStep(
        label="soft w=3000, each as configured (C with diagexact)",
        overrides=SOFT,
        twin_overrides=(("diagexact", True),),
    ),
    TwinStep(
        label="same model, solver stopping at tolerance 1e-8", overrides=(("tolerance", 1e-8),)
    ),
    TwinStep(label="same model, 100 solver iterations", overrides=(("iterations", 100),)),
    TwinStep(label="soft w=3000, same model", overrides=SOFT),
    TwinStep(label="same model: MuJoCo Warp's regulariser, C without diagexact"),
)

RECORD = EngineRecord(
    name="mjwarp",
    adapter="adapters.mjwarp.adapter:MjwarpEngine",
    install=Install(
        package="mujoco-warp",
        import_name="mujoco_warp",
        extra="mujoco-warp",
        requires=("mujoco", "warp"),
        released_with=("mujoco",),
        oldest="4.0.0",  # the overflow bits it reads (OverflowType) are 4.0's
        history=("3.8.1", "3.11.0", "4.0.0"),
    ),
    profiles={
        # Fidelity: MuJoCo C's reference (10 us, Euler, impulse contact) with MuJoCo Warp's
        # own regulariser at d = 0.9998: a bias of 3.4e-5 relative on the R161 (stated, loosely:
        # mapping_error_rel = 2e-4), against which the float32 solve's rare misses are
        # smallest (package docstring; at 0.9999 e = 1 impacts reach 94% of the energy
        # allowance). Tolerance 0: the solver iterates until its line search stalls; 10
        # iterations give the bits of 100 at a third of a hinged step's cost. Placed 1 um
        # deep: float32 positions near 0.3 m are 3e-8 m apart.
        "reference": MjwarpSettings(
            dt_s=1e-5,
            contact_model="impulse",
            impedance=0.9998,
            tolerance=0.0,
            iterations=10,
            overlap_m=1e-6,
        ),
        # Out of the box: MuJoCo's 2 ms step, Euler, solref (0.02, 1), default solimp, MuJoCo
        # Warp's tolerance (1e-6) and regulariser, the contact instant mid-step.
        "default": MjwarpSettings(
            dt_s=0.002, contact_model="native", tolerance=1e-6, contact_phase=0.5, cone="pyramidal"
        ),
    },
    can=Capabilities(
        chain_adapter="adapters.mjwarp.chain:MjwarpChain",
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
        twin_of="mujoco",
    ),
    errors=RegularisedErrors(
        precision="float32",
    ),
    engine_defaults=ENGINE_DEFAULTS,
    cost=Cost(
        step_cost_s=1.0e-4,
        world_step_cost_s=2e-5,
        start_s=0.5,
    ),
    look=Presentation(
        color="seagreen",
        marker="<",
        label="MuJoCo Warp",
        notes=ReportNotes(
            profile=(
                "dt = {dt_s}, {integrator}, `impulse` contact (d = {impedance}), MuJoCo "
                "Warp's regulariser, solver tolerance {tolerance} and {iterations} "
                "iterations, placed {overlap_m} deep, on Warp's CPU device"
            ),
            restitution="none: mapped by the adapter, as for MuJoCo C",
            handled=(
                "no `diagexact` in MuJoCo Warp: the impulse is up to 3.4e-5 relative off "
                "on the R161 at d = {impedance} (stated); its tolerance is raised to "
                "{default_tolerance} as the model is put on the device, and its float32 "
                "solve stopped there splits the impulse between the bodies up to 1e-3 "
                "wrong: tolerance 0 instead"
            ),
            defaults=(
                "MuJoCo Warp's solref {default_solref}, iterations, tolerance "
                "{default_tolerance} and {default_dt_s} step, read back"
            ),
        ),
    ),
    studies=Studies(
        speed_accuracy=(
            KnobFamily(label="impulse, Euler", quick=True),
            KnobFamily(label="soft w=3000, Euler", quick=True, overrides=SOFT),
            # no RK4 family: RK4 under the impulse solref holds the contact for ~5e4 steps at
            # dt = 1e-6 s, as MuJoCo C's does (its pareto rows), and a batch steps until its
            # last world ends: an hour of a 20 ms RK4 step on a CPU for a failure MuJoCo C shows
        ),
        friction_families=(KnobFamily(label="pyramidal cone", overrides=(("cone", "pyramidal"),)),),
        friction_rule_overrides=NATIVE_FRICTION,
        twin_steps=TWIN_STEPS,
    ),
    batching=Batching(
        call="mujoco_warp:step",
        worlds=True,
        used=True,
        why="one Data holds every world (nworld) and each step is one captured call of "
        "mujoco_warp.step: batched by design",
    ),  # MJX's own regulariser (its reference's, 1e-7, would make the soft constraint rigid)
    balls=(PORT_BALL,),
)
