"""Box2D v3 (pyb2d3 0.11.1, Box2D's 3.1 API, single precision): the planar scene maps one
to one, as in pymunk.

The bat is a dynamic body with a capsule shape from s_min to s_max (body origin at the COM), the
ball one with a circle; the shapes' own density first sets the mass, so that Box2D computes the
body extents its continuous collision needs (a mass set on a shapeless body leaves them at zero,
box2d #1009), then ``mass_data`` overwrites it with the scene's mass, COM and rotational inertia
(about the COM, as b2Body_SetMassData stores it), which ``mass_properties`` reads back: in
float32, so 0.871 kg reads back as 0.8709999919 (relative 9e-9 to 6e-8 off the scene's values).

Traps this adapter handles (measured on the R161 bat unless said otherwise):
- restitution is the larger of the two shapes' values (bat 0.6 and ball 0.5 bounce at 0.600000,
  either way round), so the bat gets 0 and the ball e;
- restitution is dropped below ``restitution_threshold`` (1 m/s by default: a 0.99 m/s central
  impact separates at 1.5e-8 of its approach speed, a 1.01 m/s one at 0.4999999); the reference
  sets it to 0; the bounce is an impulse after the sub-steps that restores -e times the relative
  normal velocity stored when the step began (box2d #1094: with forces acting during the step
  that is not the approach speed; none act during our impacts);
- ``maximum_linear_speed`` clamps every body (400 m/s by default, above our 80 m/s; the reference
  lifts it to 1e4 m/s so that a blow-up shows as it is);
- speculative contact: a manifold is made as soon as the gap is below 4 linear slops (2 cm, a
  compile-time constant) and resolves the impact in the step in which the bodies meet, with the
  normal and anchors of that step's start: the swinging bat's normal is then a step's turn
  (omega dt) off, which leaves an error first order in dt (the paper's swing at s = 0.1 m, contact
  on a step boundary: omega1 off by 0.073, 0.0067, 0.00066 rad/s at dt = 1e-4, 1e-5, 1e-6 s, half
  that mid-step). Box2D's own "touching" includes these speculative points, and pyb2d3 exposes no
  per-body contact data, so ``in_contact`` reports whether the ball's velocity changed in the last
  step: only the bat's contact acts on the ball;
- rotation: each sub-step turns a body by atan(omega h), not omega h (b2IntegrateRotation
  normalises q + omega h q'); at 1/60 s with 4 sub-steps the swinging bat meets the ball 6 mrad
  behind, which puts omega1 0.13 rad/s off at s = 0.1 m (0.033 with 8, 0.0081 with 16 sub-steps).
  ``b2MakeRot`` approximates cos/sin (1.7e-3 rad off) and ``b2Rot_GetAngle`` atan2 (2.7e-5 rad
  off): the adapter builds and reads rotations from cos/sin itself;
- the hands' revolute joint is soft (60 Hz, damping ratio 2 in Box2D 3.1, fixed: pyb2d3 does not
  bind b2Joint_SetConstraintTuning), and its drift is first order in the sub-step h: after a 0.1 s
  hinged swing at dt = 1e-4 s the bat's omega is 0.26% low with 1 sub-step and its angle 8.4 mrad
  ahead (3.3, 1.8, 0.92, 0.48 mrad with 4, 8, 16, 32 sub-steps);
- float32 positions and rotations: a sub-step adds v h to a coordinate whose ulp is 6e-8 m, so
  many tiny sub-steps lose a long motion (a 0.1 s swing at dt = 1e-6 s with 8 or 16 sub-steps
  leaves the bat where the ball misses it); ``max_sub_step_s`` adds sub-steps only where the
  step is long;
- contacts (with their warm-start impulses) outlive ``set_transform``: ``set_state`` disables and
  re-enables both bodies, which destroys them (b2Body_Disable), so that no impulse of one impact
  can warm-start the next (in the cases measured the stale impulse happened to cancel within the
  first step, so a used engine gave a fresh one's bits even without it);
- sleeping is off (a body at rest would fall asleep) and gravity zero;
- out of the box (1/60 s, 4 sub-steps) the ball tunnels: a step's travel (about 1 m) dwarfs the
  2 cm speculative margin, and time of impact between two dynamic bodies needs ``bullet``, which
  does not save the mid-step contact either (measured: tunnelled both ways).
The soft contact (contact_hertz, contact_damping_ratio, contact push speed) moves only positions:
the relax iterations and the restitution impulse set the velocities (the paper's swing at s = 0.1
gives the same bits with 30 or 1e4 Hz, damping ratio 10 or 1, push speed 3 or 100 m/s).

A 2-D engine (the record's ``planar``): impacts out of the swing plane are 'unsupported'. The
ball's spin is its ``angular_velocity``, counter-clockwise positive, as the State's.

Friction (Box2D 3.1.1's source, which pyb2d3's headers match, and measurements):
- the contact's coefficient is sqrt(f_a f_b) of the shapes' ``friction`` (b2DefaultFrictionCallback;
  pyb2d3 does not bind b2World_SetFrictionCallback), mixed anew every step (b2UpdateContact):
  bat 0.02 and ball 0.08, either way round, slide at mu = 0.0399996 (e = 0), so both get mu. One
  coefficient (no static/dynamic pair), no friction threshold; rolling resistance 0 (Box2D's
  default, read back from b2SurfaceMaterial, set explicitly) and tangent speed 0;
- the law is Coulomb's, exact in the plane (one tangent): in each sub-step's solve and relax
  passes the tangent impulse is accumulated after the normal's and clamped to mu times it. No
  knob selects another model, and the soft step's values hardly touch it (the sliding wall impact
  below: the same bits with 1e4 Hz, damping ratio 1 or push speed 100 m/s at e = 0.5; at e = 0,
  damping ratio 1 moves the spin by 6e-8 of itself);
- but the restitution impulse, applied once after the sub-steps, carries no friction, and the
  speculative contact has the relax pass of the sub-step before the bodies touch stop only the share
  of the approach that would overlap them in the next sub-step, p = 1 - gap / (v_n h), the gap being
  what that sub-step leaves (p = ``contact_phase`` at one sub-step a step); restitution then adds
  the rest and the bounce. A sliding impact so gets mu p P / (1 + e) of tangential impulse where
  Coulomb gives mu P (measured on a heavy wall, 20 m/s at theta 0.5, e = 0.5, mu = 0.05: the spin
  Routh's times 0.1670, 0.3337, 0.5004 at p = 0.25, 0.5, 0.75, 0.667 where the contact falls on a
  sub-step boundary of a longer step; with e = 0 the rest is solved in the next step, with friction:
  1.0002). At p = 0 (the reference's contact on a step boundary) rounding decides: a relax pass that
  leaves any normal impulse lets the restitution bounce the ball a step's closing before it touches,
  without friction (7 of 11 impacts of the paper's swing at mu 0.05, theta 0.5: spin 0 where Routh's
  is -98 to -265 rad/s), one that leaves none gives the next step the whole compression (the other
  4: 2/3 of Routh's spin). A ball that leaves rolling (mu = 1) still does at p = 0.5 (vt1 1.4e-3 m/s
  off); the adapter cannot change any of this;
- the lever arms are fixed at the manifold point of the step's start, midway across the gap: a
  ball's spin from a sliding impulse is (r + gap / 2) / r of Coulomb's (measured 1 + 1.45e-4 at a
  10 m/s approach with 1 us steps).
"""

from __future__ import annotations

import math
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

#: Box2D's speculative distance, 4 linear slops of 5 mm (compile-time, with 1 length unit = 1 m):
#: a pair closer than this gets a contact; the stability map's theory and a test measure it.
SPECULATIVE_M = 0.02


@dataclass(frozen=True, kw_only=True)
class Box2dSettings(Settings):
    """Box2D's knobs (None: keep the engine's own default). ``sub_steps``: sub-steps per step,
    raised where needed so that none lasts longer than ``max_sub_step_s`` (s; None: no bound);
    ``contact_hertz`` (Hz) and ``contact_damping_ratio``: the soft contact's stiffness and
    damping in the sub-steps' overlap correction; ``contact_push_mps`` (m/s): the cap on the
    speed that correction pushes overlapping bodies apart with; ``restitution_threshold_mps``
    (m/s): approach speeds below it do not bounce; ``maximum_linear_speed_mps`` (m/s): the
    speed every body is clamped to; ``continuous``: time of impact against static bodies;
    ``bullet``: the ball also does time of impact against the (dynamic) bat."""

    sub_steps: int = 4
    max_sub_step_s: float | None = None
    contact_hertz: float | None = None
    contact_damping_ratio: float | None = None
    contact_push_mps: float | None = None
    restitution_threshold_mps: float | None = None
    maximum_linear_speed_mps: float | None = None
    continuous: bool = True
    bullet: bool = False

    def __post_init__(self) -> None:
        super().__post_init__()
        checks.integer("sub_steps", self.sub_steps, 1, 10_000)
        if self.max_sub_step_s is not None:
            checks.positive("max_sub_step_s", self.max_sub_step_s)
        for name in (
            "contact_hertz",
            "contact_damping_ratio",
            "contact_push_mps",
            "restitution_threshold_mps",
        ):
            if getattr(self, name) is not None:
                checks.non_negative(name, getattr(self, name))
        if self.maximum_linear_speed_mps is not None:
            checks.positive("maximum_linear_speed_mps", self.maximum_linear_speed_mps)
        for name in ("continuous", "bullet"):
            if not isinstance(getattr(self, name), bool):
                raise ValueError(
                    f"{name}={getattr(self, name)!r} is not a bool; allowed: True, False"
                )

    @property
    def sub_step_count(self) -> int:
        """The sub-steps each step takes: ``sub_steps``, more if ``max_sub_step_s`` asks."""
        if self.max_sub_step_s is None:
            return self.sub_steps
        # (1 - 1e-12): a step of exactly k bounds takes k sub-steps despite division noise
        return max(self.sub_steps, math.ceil(self.dt_s / self.max_sub_step_s * (1 - 1e-12)))


class Box2dErrors(ErrorModel):
    """Box2D v3: speculative contact and its friction's cone."""

    def speculative_margin_m(self, s) -> float:
        return SPECULATIVE_M

    def friction_cone(self, s) -> str:
        return (
            "planar, one tangent: |P_t| <= mu P_n of the sub-steps' passes; the restitution "
            "impulse frictionless"
        )


RECORD = EngineRecord(
    name="box2d",
    adapter="adapters.box2d.adapter:Box2dEngine",
    install=Install(
        package="pyb2d3",
        import_name="pyb2d3",
        extra="box2d",
        oldest="0.8.0",
        history=("0.8.0", "0.9.0", "0.10.0", "0.11.1"),
    ),
    profiles={
        # Fidelity: a 1 us step, because the speculative contact resolves an impact with the
        # geometry of its step's start, an error first order in dt (module docstring): a fuzz
        # draw that meets the cylinder's very end sliding at 11.6 m/s is off by 0.27, 0.029 and
        # 0.0029 m/s in v1 at dt = 1e-4, 1e-5, 1e-6 s (its float32 tolerance is 0.029). One
        # sub-step at 1 us, more where a study coarsens the step, so that none exceeds 5 us:
        # the sub-step h sets the atan(omega h) turn (at 1/60 s, 4 sub-steps leave omega1 0.13
        # rad/s off at s = 0.1 m, 5 us sub-steps 4e-5) and the soft hinge's drift (the bat
        # released after a 0.1 s swing at dt = 1e-4 s: angle 3.3 mrad off with 4 sub-steps,
        # 0.76 with 5 us ones), while float32 positions forbid many tiny ones (16 sub-steps at
        # 1 us leave the swung bat so far off that the ball misses it; 1 sub-step: 1.8e-5 rad).
        # No restitution threshold; the speed clamp lifted. The soft-contact values stay
        # Box2D's: they move no velocity (module docstring).
        "reference": Box2dSettings(
            dt_s=1e-6,
            sub_steps=1,
            max_sub_step_s=5e-6,
            restitution_threshold_mps=0.0,
            maximum_linear_speed_mps=1e4,
        ),
        # Out of the box: the 1/60 s step and 4 sub-steps that box2d.h recommends for
        # b2World_Step, every world value left to Box2D, the contact instant mid-step as in any
        # unaligned simulation.
        "default": Box2dSettings(dt_s=1 / 60, sub_steps=4, contact_phase=0.5),
    },
    can=Capabilities(
        chain_adapter="adapters.box2d.chain:Box2dChain",
        # One sub-step per step: the semi-implicit Euler step is then dt (with n sub-steps it is
        # dt/n), whose first-order terms the swing study and tests/test_dynamics.py derive.
        # Its joints are soft (60 Hz, damping ratio 2, compile-time constants pyb2d3 cannot change):
        # the hinge drifts at first order in the step.
        integrators=(
            Integrator(
                label="semi-implicit Euler, 1 sub-step",
                overrides=(("sub_steps", 1), ("max_sub_step_s", None)),
                hinge_order=1,
            ),
        ),
        restitution_rule=RestitutionRule.MAX,
        friction_rule=FrictionRule.GEOMETRIC,
        planar=True,
        threshold_setting="restitution_threshold_mps",
        # Box2D v3 holds at most B2_MAX_WORLDS = 128 worlds a process: the 129th crashes it
        # (measured, and pinned by tests/test_pool.py); 8 spare for worlds made elsewhere
        max_worlds=120,
    ),
    errors=Box2dErrors(
        chain_defect="segmented bat: one solver sweep per substep and the restitution impulse on "
        "the contact alone, so the ball bounces off the touched segment as if it "
        "were "
        "free (x = 0.65 m: -15.20 m/s for the chain's -5.26) and is struck again; "
        "the "
        "joint spring is a soft constraint on the two segments' own inertias, which "
        "leaves the lowest mode's period 1.7e-4 long at 10 us and damps it by 6% a "
        "period",
        precision="float32",
        friction_defect="the restitution impulse, applied after the sub-steps, carries no "
        "friction: "
        "a slide gets mu p P / (1 + e) of tangential impulse for Coulomb's mu P, "
        "p "
        "the share of the approach the speculative relax pass stops (at the "
        "reference's step-aligned contact 0 or 2/3 of the spin; package "
        "docstring)",
    ),
    # All four read back from a fresh b2DefaultWorldDef; the push speed (3 m/s) is not exposed
    # by pyb2d3 and moves no velocity here, so it is neither quoted nor measurable.
    engine_defaults={
        "contact_hertz": 30.0,
        "contact_damping_ratio": 10.0,
        "restitution_threshold_mps": 1.0,
        "maximum_linear_speed_mps": 400.0,
    },
    cost=Cost(
        step_cost_s=4.8e-6,
    ),
    look=Presentation(
        color="tab:red",
        marker="D",
        label="Box2D",
        notes=ReportNotes(
            profile=(
                "dt = {dt_s}, sub-steps of at most {max_sub_step_s}, restitution threshold "
                "0, speed clamp lifted"
            ),
            restitution=(
                "max of the two shapes' restitution (bat 0, ball e); 0 below "
                "`restitutionThreshold` ({default_restitution_threshold_mps} m/s)"
            ),
            handled=(
                "restitution is the max of the two values and dropped below "
                "{default_restitution_threshold_mps} m/s; the speculative margin "
                "(compile-time) solves an impact with the step start's normal, an error first "
                "order in dt (hence the {dt_s} reference); each sub-step turns a body by "
                "atan(omega h); `b2MakeRot` approximates cos/sin (the adapter builds "
                "rotations "
                "itself); its joints are soft (fixed in pyb2d3), so the hinge drifts at first "
                "order; float32 positions lose a long motion split into many tiny sub-steps; "
                "pyb2d3 exposes no per-body contact data, so the adapter calls a step a "
                "contact when the ball's velocity changed (only the bat acts on it)."
            ),
        ),
    ),
    studies=Studies(
        speed_accuracy=(
            KnobFamily(label="sub-steps of at most 5 us (reference)", quick=True),
            KnobFamily(label="1 sub-step", overrides=(("sub_steps", 1), ("max_sub_step_s", None))),
            KnobFamily(
                label="4 sub-steps (Box2D's)",
                overrides=(("sub_steps", 4), ("max_sub_step_s", None)),
            ),
        ),
        # The rule pinned with the restitution pass off (threshold above every approach speed):
        # that pass is frictionless, so with it an impact's friction is a share of mu (docstring).
        friction_rule_overrides={"restitution_threshold_mps": 1e4},
    ),
    batching=Batching(
        call="pyb2d3:ThreadPool",
        why="Box2D v3's task system spreads one world's step over workers "
        "(World(thread_pool=...)); a world of two bodies is one island with nothing to "
        "spread, and each of a run's worlds is a b2World of its own, stepped one after another",
        not_it=("pyb2d3:WITH_THREADING",),  # whether the binding was built with that pool
    ),
)
