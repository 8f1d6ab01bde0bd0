"""NVIDIA PhysX 5, through SAPIEN 3 (CPU): two rigid dynamic bodies in a PhysX scene.

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

3-D state: SAPIEN's poses take (w, x, y, z) quaternions, as ``adapters.frames``; velocities,
angular ones included, are the world frame's both ways (a tilted bat turning about a world axis
keeps its axis on the world-frame rotation to 5e-5, float32, after 0.1 s). An undercut
contact, speculative like every other, is solved with the normal of the step's start: the
frictionless undercut of 2 cm on the paper's swing leaves 0.146 m/s off at 10 us, 0.0148 at
1 us (first order in the step).

Friction (measured on a ball sliding across a heavy still bat; PhysX 5.3.1's source agrees):
- combined as the MEAN of the two materials' values (PhysX's default combine mode, eAVERAGE,
  which SAPIEN neither sets nor exposes: 0.2 and 0.8 slide as 0.5, 0 and 1 as 0.5); both
  materials get mu, static and dynamic alike. Frictionless, both stay at 0, as before.
- SAPIEN's scene uses PhysX's patch friction (``frictionType`` is not set: ePATCH) with
  eIMPROVED_PATCH_FRICTION on; the ball meets the bat at one point, one anchor with two
  friction rows, the first along the tangential part of the bodies' relative COM velocity at
  the step's start (not the contact point's slip). Torsional friction, PhysX's only kind
  besides these (it has no rolling friction), is off: both shapes' ``patch_radius`` and
  ``min_patch_radius`` are set to 0, SAPIEN's default (read back).
- How the two rows are bounded depends on the solver (``solver``). TGS: the pair's impulse is
  scaled back to mu N (a cone: a slip at 45 degrees is resisted by mu N, opposite the slip),
  solved in every position iteration whatever ``friction_every_iteration`` says (same bits).
  PGS: each row is clamped to mu N alone (a box: a slip at 45 degrees to the first row gets
  sqrt(2) mu N, one at 18 degrees 1.12 mu N turned 8.5 degrees off the slip); with
  ``friction_every_iteration`` False, friction only in the last 3 position iterations (SAPIEN
  turns it on; PhysX's own default is off).
- TGS's friction rows also pull each anchor back toward where it was when the step began
  (their target carries a bias proportional to the anchors' tangential drift since then:
  PhysX's "strong friction", whose eDISABLE_STRONG_FRICTION material flag SAPIEN does not
  expose). A contact that slides
  throughout is exact (mu = 0.05 at 20 m/s on the still bat: 8e-6 m/s off), but one that slips
  then sticks within a step does not stop where the slip stops: at mu = 1 (20 m/s, theta 0.5,
  e = 0.5, Routh's spin -187.12 rad/s) the ball leaves spinning at -158 to -315 rad/s as the
  contact instant moves through the step (``contact_phase`` 0 to 0.99), -269, -193 and -69
  with 1, 10 and 50 position iterations; the step size does not matter (the same at 1 us).
  PGS, whose friction bias is fixed when the step begins, gives -187.1218.
"""

from __future__ import annotations

from dataclasses import dataclass

from analytic import checks

from ..records import (
    Batching,
    Capabilities,
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

SOLVERS = ("TGS", "PGS")
#: SAPIEN's contact offset per shape (m), read back from a fresh shape (a test pins it).
DEFAULT_CONTACT_OFFSET_M = 0.01


@dataclass(frozen=True, kw_only=True)
class PhysxSettings(Settings):
    """PhysX's knobs (None: keep SAPIEN's default). ``solver`` one of SOLVERS (temporal
    Gauss-Seidel or projected Gauss-Seidel); ``bounce_threshold_mps``: normal speeds below it
    get no restitution; ``enable_pcm`` persistent contact manifolds; ``contact_offset_m``: the
    distance at which contacts are generated ahead of touching (speculative); ``rest_offset_m``:
    the separation the solver keeps; ``position_iterations``/``velocity_iterations`` of the
    solver per body; ``max_angular_velocity_radps`` the bodies' spin cap;
    ``max_depenetration_velocity_mps`` the cap on the speed that removes overlap;
    ``sleep_threshold`` (J/kg, kinetic energy per mass below which a body may sleep);
    ``friction_every_iteration``: PGS solves friction in every position iteration, not only in
    the last 3 (TGS always does)."""

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
    friction_every_iteration: bool | None = None

    def __post_init__(self) -> None:
        super().__post_init__()
        if self.solver is not None and self.solver not in SOLVERS:
            raise ValueError(f"solver={self.solver!r} is unknown; allowed: {', '.join(SOLVERS)}")
        for name in ("enable_pcm", "friction_every_iteration"):
            if getattr(self, name) is not None and not isinstance(getattr(self, name), bool):
                raise ValueError(
                    f"{name}={getattr(self, name)!r} is not a bool; allowed: True, False"
                )
        for name in ("bounce_threshold_mps", "rest_offset_m", "sleep_threshold"):
            if getattr(self, name) is not None:
                checks.non_negative(name, getattr(self, name))
        for name in (
            "contact_offset_m",
            "max_angular_velocity_radps",
            "max_depenetration_velocity_mps",
        ):
            if getattr(self, name) is not None:
                checks.positive(name, getattr(self, name))
        if self.position_iterations is not None:
            checks.integer("position_iterations", self.position_iterations, 1, 255)
        if self.velocity_iterations is not None:
            checks.integer("velocity_iterations", self.velocity_iterations, 0, 255)
        if (
            self.contact_offset_m is not None
            and self.rest_offset_m is not None
            and self.rest_offset_m >= self.contact_offset_m
        ):
            raise ValueError(
                f"rest_offset_m={self.rest_offset_m!r} is not below contact_offset_m"
                f"={self.contact_offset_m!r}; allowed: rest_offset_m < "
                "contact_offset_m (PhysX rejects the shape otherwise)"
            )


class PhysxErrors(ErrorModel):
    """PhysX: speculative contact and its friction's cone."""

    def friction_cone(self, s) -> str:
        if s.solver == "PGS":
            late = "" if s.friction_every_iteration is not False else ", last 3 iterations"
            return f"patch friction, PGS box: 2 directions each clamped to mu N{late}"
        # None: SAPIEN's choice, TGS (read_back_defaults)
        return "patch friction, TGS cone: 2 directions scaled back to mu N, anchors pulled back"

    def speculative_margin_m(self, s) -> float:
        # each shape makes contacts contact_offset ahead of touching: the pair, both offsets
        offset = s.contact_offset_m
        return 2 * (DEFAULT_CONTACT_OFFSET_M if offset is None else offset)


RECORD = EngineRecord(
    name="physx",
    adapter="adapters.physx.adapter:PhysxEngine",
    install=Install(
        package="sapien",
        import_name="sapien",
        extra="physx",
        oldest="3.0.0",
        history=("3.0.0", "3.0.1", "3.0.2", "3.0.3"),
    ),
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
        # a 10 us step; friction in every iteration (SAPIEN's choice; TGS ignores it).
        "reference": PhysxSettings(
            dt_s=1e-5,
            bounce_threshold_mps=0.0,
            max_angular_velocity_radps=1e4,
            sleep_threshold=0.0,
            friction_every_iteration=True,
        ),
        # Out of the box: SAPIEN's 10 ms step and every solver value left to SAPIEN (TGS,
        # bounce threshold 2 m/s, 10 mm contact offset), the contact instant mid-step as in any
        # unaligned simulation.
        "default": PhysxSettings(dt_s=0.01, contact_phase=0.5),
    },
    can=Capabilities(
        integrators=(Integrator(label="semi-implicit Euler"),),
        chain_adapter="adapters.physx.chain:PhysxChain",
        restitution_rule=RestitutionRule.MEAN,
        friction_rule=FrictionRule.MEAN,
        threshold_setting="bounce_threshold_mps",
    ),
    errors=PhysxErrors(
        precision="float32",  # PhysX computes and stores in single precision
        friction_defect="TGS ends an impact that slips then sticks within a step wrong (on a wall "
        "at mu = 1 the spin comes out -158 to -315 rad/s for -187.1, by where the "
        "contact falls in the step and the iteration count, not dt; a slide "
        "throughout is exact): its strong friction pulls the anchors back, and "
        "SAPIEN exposes no flag to turn it off (package docstring); PGS is right",
    ),
    # All read back from a fresh system, body and shape (SAPIEN's process-wide defaults, which
    # PhysX copies at creation; the adapter restores them after building its own scene).
    engine_defaults={
        "dt_s": 0.01,
        "solver": "TGS",
        "bounce_threshold_mps": 2.0,
        "enable_pcm": True,
        "contact_offset_m": DEFAULT_CONTACT_OFFSET_M,
        "rest_offset_m": 0.0,
        "position_iterations": 10,
        "velocity_iterations": 1,
        "max_angular_velocity_radps": 100.0,
        "max_depenetration_velocity_mps": 1e32,
        "sleep_threshold": 0.005,
        "friction_every_iteration": True,
    },
    cost=Cost(
        step_cost_s=2.3e-5,
    ),
    look=Presentation(
        color="tab:brown",
        marker="P",
        label="PhysX",
        notes=ReportNotes(
            profile=(
                "dt = {dt_s}, TGS, bounce threshold 0, spin cap lifted "
                "({default_max_angular_velocity_radps} rad/s by default), no sleeping"
            ),
            restitution=(
                "mean of both bodies' restitution (both set to e); 0 below "
                "`bounce_threshold` ({default_bounce_threshold_mps} m/s)"
            ),
            handled=(
                "restitution is dropped below the {default_bounce_threshold_mps} m/s bounce "
                "threshold (PhysX #351); the default spin cap of "
                "{default_max_angular_velocity_radps} rad/s clips a bat hit at the barrel "
                "after a fast swing; PGS splits an impact that falls late in a step over two "
                "steps, losing part of the rebound, where TGS is exact; contacts are made "
                "`contact_offset` ({default_contact_offset_m} per shape) ahead and solved "
                "with "
                "the step's starting geometry (a speculative contact, see the judge); "
                "SAPIEN's "
                "scene CCD flag does nothing without the per-body flag it does not expose."
            ),
        ),
    ),
    studies=Studies(
        speed_accuracy=(
            KnobFamily(label="reference solver (TGS, 10 position iterations)", quick=True),
            *(
                KnobFamily(
                    label=f"TGS, {n} position iterations", overrides=(("position_iterations", n),)
                )
                for n in (1, 4, 50)
            ),
            KnobFamily(label="PGS", overrides=(("solver", "PGS"),)),
        ),
        friction_families=(KnobFamily(label="PGS", overrides=(("solver", "PGS"),)),),
    ),
    batching=Batching(
        call="sapien.physx:PhysxGpuSystem",
        worlds=True,
        why="PhysX's GPU pipeline steps many scenes in one call, on CUDA only, with the GPU's "
        "own solver; the adapter steps a PhysxCpuSystem a world (the CPU solvers the profiles "
        "tune), so the GPU system would not give the same bits: not used",
    ),
)
