"""pymunk (Chipmunk2D): the planar scene maps one to one.

The bat is a Body with SET mass and moment, its origin at the COM, carrying a Segment shape (a
capsule) with no mass of its own; the ball a Body with a Circle. Restitution is the product of the
two shapes' ``elasticity`` (bat 1, ball e). Chipmunk resolves penetration with separate bias
velocities, so ``collision_slop``/``collision_bias`` do not touch the outgoing velocities; there
are no swept collisions (Chipmunk2D #212). ``body.velocity`` is the COM's velocity.

A 2-D engine (the record's ``planar``): impacts out of the swing plane are 'unsupported'. The
ball's spin is its ``angular_velocity``, counter-clockwise positive, as the State's (a ball
sliding along +x over the bat below it leaves spinning clockwise: measured negative).

Friction is each shape's ``friction``, multiplied into the contact's (``arb->u = a->u * b->u``,
cpArbiter.c; measured: bat 0.02 and ball 0.08, either way round, slide at mu = 0.0016000), so the
bat gets mu and the ball 1 (at mu = 0 the contact's is 0 * 1 = 0, as before). Chipmunk has one
coefficient (no static/dynamic pair), no rolling friction, and ``surface_velocity`` stays 0. Its
friction is Coulomb's law in the plane, exact there (one tangent, no cone to approximate): in each
of the ``iterations`` passes the normal impulse, whose target is the bounce (e times the approach
speed), is accumulated and clamped, then the tangent's, clamped to mu times that accumulated normal
impulse, so friction acts on the whole impulse, restitution's share included. That is Newton's
restitution with Coulomb's law on the total impulse (the one-step law): on the paper's swing with
mu 0.5, theta 0.3 it matches that law to 4e-8 m/s in v1 and 3e-6 rad/s in the spin with 10
iterations (as with 1000; 1 iteration leaves vt1 0.5 m/s off: a pass computes both impulses from
the same velocities), and a sliding impact (mu 0.05, theta 0.5) Routh's answer to 4e-7 (m/s,
rad/s). No knob selects another friction model.
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

# pymunk.Space() defaults (length unit: m here), as Chipmunk computes them, in single precision:
# 0.1f, and pow(1 - 0.1f, 60) for the bias; the record's engine_defaults and a test pin them.
CHIPMUNK_SLOP = 0.10000000149011612
CHIPMUNK_BIAS = 0.0017970074436457143


@dataclass(frozen=True, kw_only=True)
class PymunkSettings(Settings):
    """Chipmunk's knobs: solver ``iterations``; ``collision_slop`` (m) of allowed overlap;
    ``collision_bias``, the fraction of overlap left after 1 s of correction;
    ``joint_error_bias``, the same for the hands' pivot joint (0: corrected fully every step)."""

    iterations: int = 10
    collision_slop: float = CHIPMUNK_SLOP
    collision_bias: float = CHIPMUNK_BIAS
    joint_error_bias: float = CHIPMUNK_BIAS

    def __post_init__(self) -> None:
        super().__post_init__()
        checks.integer("iterations", self.iterations, 1, 10_000)
        checks.non_negative("collision_slop", self.collision_slop)
        checks.in_range("collision_bias", self.collision_bias, 0.0, 1.0)
        checks.in_range("joint_error_bias", self.joint_error_bias, 0.0, 1.0)


class PymunkErrors(ErrorModel):
    """pymunk: an exact rigid impulse; its planar friction."""

    def friction_cone(self, s) -> str:
        return "planar, one tangent: |P_t| <= mu P_n on the whole impulse (exact Coulomb)"


RECORD = EngineRecord(
    name="pymunk",
    adapter="adapters.pymunk.adapter:PymunkEngine",
    install=Install(
        package="pymunk",
        import_name="pymunk",
        oldest="6.5.2",
        history=("6.5.2", "6.8.1", "6.11.1", "7.0.0", "7.3.1"),
    ),
    profiles={
        # Chipmunk's own solver values are already exact for one frictionless contact (a single
        # constraint is solved in the first iteration); fidelity only needs a short step
        # (10 us: the contact normal tilts by omega*dt while the bat turns) and aligned contact.
        # The hands' pivot is corrected fully every step (joint_error_bias 0): the hinge's drift
        # is then second order (6e-8 of omega after a 0.1 s swing at 10 us) instead of first.
        "reference": PymunkSettings(dt_s=1e-5, joint_error_bias=0.0),
        # Out of the box: the 1/60 s step of pymunk's examples, Chipmunk's defaults, the contact
        # instant mid-step as in any unaligned simulation.
        "default": PymunkSettings(dt_s=1 / 60, contact_phase=0.5),
    },
    can=Capabilities(
        integrators=(Integrator(label="semi-implicit Euler"),),
        chain_adapter="adapters.pymunk.chain:PymunkChain",
        restitution_rule=RestitutionRule.PRODUCT,
        friction_rule=FrictionRule.PRODUCT,
        planar=True,
    ),
    errors=PymunkErrors(),
    engine_defaults={
        "iterations": 10,
        "collision_slop": CHIPMUNK_SLOP,
        "collision_bias": CHIPMUNK_BIAS,
        "joint_error_bias": CHIPMUNK_BIAS,
    },
    cost=Cost(
        step_cost_s=3.2e-6,
    ),
    look=Presentation(
        color="tab:blue",
        marker="o",
        label="pymunk",
        notes=ReportNotes(
            profile="dt = {dt_s}, Chipmunk's own solver values (exact for one contact)",
            restitution="product of the shapes' `elasticity` (bat 1, ball e)",
            defaults=(
                "pymunk's slop ({default_collision_slop}) and bias ({default_collision_bias},"
                " not 0.9^60: Chipmunk computes them in single precision), read back"
            ),
        ),
    ),
    studies=Studies(
        speed_accuracy=(
            KnobFamily(label="iterations 1", overrides=(("iterations", 1),)),
            KnobFamily(label="iterations 10", overrides=(("iterations", 10),), quick=True),
            KnobFamily(label="iterations 100", overrides=(("iterations", 100),)),
        ),
    ),
    batching=Batching(
        call="pymunk:Space.threads",
        why="Chipmunk's threaded solver spreads one space's step over threads "
        "(Space(threaded=True)), off by default to keep the simulation deterministic; a "
        "two-body space has nothing to spread, so each world steps on one thread and the "
        "runner's processes spread the worlds",
    ),
)
