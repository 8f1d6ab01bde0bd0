"""PyBullet adapter: two base-only multibodies (PyBullet's default) in a DIRECT client.

Traps this adapter handles (measured): ``contactSlop`` (1e-5 m by default)
and ``contactERP`` feed position error back into the velocity (slop/dt alone costs 8% at
dt = 1e-5 s), so the reference profile zeroes both; default damping 0.04 is zeroed for the scene;
restitution is the product of both bodies' values (bat 1, ball e) and is dropped below
``restitutionVelocityThreshold``; base position and velocity calls refer to the COM; multibody
angular speed is capped at ``maxJointVelocity`` (100 rad/s unless raised). A pair whose
bounding boxes overlap gets contacts up to ``contactBreakingThreshold`` (0.02 m by default)
before touching, and Bullet gives such a contact its restitution target while still apart: it
pushes once the gap is below (1 + e) v_n dt and the bounce smears over many steps (an undercut
ball, whose box overlaps the bat's early: v1 4.05 m/s for Newton's 30.17 at s = 0.1 m on the
paper's swing). The reference sets the threshold to 1 um, far inside a step's approach, so a
contact is solved once touching (v1 30.165841); 0 would lose contacts (the ball passes through
the barrel end at s = 0.25 m); the frictionless planar baselines (swing, still bat, hinged,
default profile) are the same bit for bit either way.

3-D state: quaternions are (x, y, z, w); a base-only multibody's angular velocity is the world
frame's, both ways (``resetBaseVelocity``/``getBaseVelocity``: a tilted bat turning about a
world axis keeps its axis on the world-frame rotation to 1e-14 after 0.1 s).

Friction (measured on a ball sliding across a heavy still bat; Bullet 3.2.7's source agrees):
- combined as the PRODUCT of the bodies' ``lateralFriction`` (0.2 and 0.8 slide as 0.16),
  clamped to 10 (4 x 4 slides as 10); the bat gets mu and the ball 1. A body's own value is 0.5
  unless set: the scene sets both to 0 when mu = 0, as every frictionless run was built.
- spinning and rolling friction are 0 (Bullet's default, set explicitly); they combine as
  spinning_a lateral_b + spinning_b lateral_a, so 0 on both bodies switches them off.
- two friction rows per contact along tangent directions fixed by the normal alone (Bullet's
  ``btPlaneSpace1``: x and z for a normal along y), not along the slip, solved in every
  iteration after the normal row with its current impulse as bound. ``enableConeFriction``
  (``cone_friction``) picks how they are bounded: 1, an implicit cone (the pair's impulse
  scaled back radially to mu N: a slip at 45 degrees out of the swing plane is resisted by
  exactly mu N, opposite the slip); 0, a box (each row clamped to mu N alone: 45 degrees gets
  sqrt(2) mu N, 17 degrees gets 1.10 mu N turned 7 degrees off the slip). The cone is Bullet's
  default, which ``getPhysicsEngineParameters`` does not report (its Python binding returns 8
  keys, not this one): ``read_back_defaults`` measures it by firing that oblique slide.
- friction anchors (``changeDynamics(frictionAnchor=1)``, corrected by ``frictionERP``) are off,
  Bullet's default (its source sets the flag only on request); no friction warm start (the
  multibody solver starts each row at 0).
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

#: setting name -> setPhysicsEngineParameter keyword; a None value leaves the engine default.
ENGINE_PARAMETERS = {
    "solver_iterations": "numSolverIterations",
    "contact_erp": "contactERP",
    "erp": "erp",
    "friction_erp": "frictionERP",
    "contact_slop": "contactSlop",
    "restitution_velocity_threshold": "restitutionVelocityThreshold",
    "contact_breaking_threshold": "contactBreakingThreshold",
    "split_impulse": "useSplitImpulse",
    "cone_friction": "enableConeFriction",
}


@dataclass(frozen=True, kw_only=True)
class PybulletSettings(Settings):
    """Bullet's knobs (None: keep the engine's own default). ``contact_erp``/``erp``/
    ``friction_erp``: fraction of position error corrected per step; ``contact_slop`` (m):
    overlap allowed before correction; ``restitution_velocity_threshold`` (m/s);
    ``contact_breaking_threshold`` (m): contact margin; ``split_impulse`` 0/1;
    ``max_joint_velocity_radps``: the multibody angular-speed cap; ``ccd_swept_sphere_radius``
    (m): continuous collision detection, 0 = off; ``cone_friction``: ``enableConeFriction``,
    friction bounded by a cone (True) or a box (False)."""

    solver_iterations: int | None = None
    contact_erp: float | None = None
    erp: float | None = None
    friction_erp: float | None = None
    contact_slop: float | None = None
    restitution_velocity_threshold: float | None = None
    contact_breaking_threshold: float | None = None
    split_impulse: int | None = None
    max_joint_velocity_radps: float | None = None
    ccd_swept_sphere_radius: float = 0.0
    cone_friction: bool | None = None

    def __post_init__(self) -> None:
        super().__post_init__()
        if self.solver_iterations is not None:
            checks.integer("solver_iterations", self.solver_iterations, 1, 10_000)
        for name in ("contact_erp", "erp", "friction_erp"):
            if getattr(self, name) is not None:
                checks.in_range(name, getattr(self, name), 0.0, 1.0)
        for name in (
            "contact_slop",
            "restitution_velocity_threshold",
            "contact_breaking_threshold",
            "ccd_swept_sphere_radius",
        ):
            if getattr(self, name) is not None:
                checks.non_negative(name, getattr(self, name))
        if self.max_joint_velocity_radps is not None:
            checks.positive("max_joint_velocity_radps", self.max_joint_velocity_radps)
        if self.cone_friction is not None and not isinstance(self.cone_friction, bool):
            raise ValueError(
                f"cone_friction={self.cone_friction!r} is not a bool; allowed: True, False, None"
            )


class PybulletErrors(ErrorModel):
    """PyBullet: an exact rigid impulse; its friction's cone."""

    def friction_cone(self, s) -> str:
        # None: Bullet's own choice, the cone (read_back_defaults measures it)
        if s.cone_friction is False:
            return "box: 2 directions fixed by the normal, each clamped to mu N"
        return "implicit cone: 2 directions fixed by the normal, scaled back to mu N"


RECORD = EngineRecord(
    name="pybullet",
    adapter="adapters.pybullet.adapter:PybulletEngine",
    install=Install(
        package="pybullet",
        import_name="pybullet",
        oldest="3.2.6",
        history=("3.2.5", "3.2.6", "3.2.7"),
    ),
    profiles={
        # No position feedback into contact velocities (contactERP = 0, contactSlop = 0): the
        # sequential-impulse solver then meets Newton's law exactly for one contact; the hands'
        # pivot (a joint, governed by erp) fully corrected every step, erp = 1: its drift is
        # then second order (2e-6 rad/s after a 0.1 s swing at 10 us, 4e-3 with erp = 0); no
        # restitution threshold; the angular cap lifted so a blow-up shows as it is; friction
        # bounded by Bullet's cone, whose bound is Coulomb's (its box lets a slip across both
        # friction directions take up to sqrt(2) mu N); contacts made only within 1 um, so
        # none is solved before touching (see the package docstring); 10 us step.
        "reference": PybulletSettings(
            dt_s=1e-5,
            contact_erp=0.0,
            erp=1.0,
            friction_erp=0.0,
            contact_slop=0.0,
            restitution_velocity_threshold=0.0,
            max_joint_velocity_radps=1e4,
            cone_friction=True,
            contact_breaking_threshold=1e-6,
        ),
        # Out of the box: 1/240 s, every solver parameter left at Bullet's value, the contact
        # instant mid-step as in any unaligned simulation.
        "default": PybulletSettings(dt_s=1 / 240, contact_phase=0.5),
    },
    can=Capabilities(
        integrators=(Integrator(label="semi-implicit Euler"),),
        chain_adapter="adapters.pybullet.chain:PybulletChain",
        restitution_rule=RestitutionRule.PRODUCT,
        friction_rule=FrictionRule.PRODUCT,
        threshold_setting="restitution_velocity_threshold",
        # each physics client takes 27 MB (measured: 50 clients, peak RSS); a long run's pool
        # holds 16 worlds a client (``worlds.PAIRS_PER_CLIENT``): 256 worlds, 16 clients, 0.4 GB
        max_worlds=256,
        pool_adapter="adapters.pybullet.worlds:PybulletWorlds",
    ),
    # Bullet reports neither contact value: both measured (setting them explicitly reproduces
    # the default solver's impacts bit for bit); the iteration count it reports; the cone
    # measured by read_back_defaults (an oblique slide, bit for bit the cone's, not the box's).
    errors=PybulletErrors(),
    engine_defaults={
        "contact_erp": 0.08,
        "contact_slop": 1e-5,
        "solver_iterations": 50,
        "dt_s": 1 / 240,
        "cone_friction": True,
    },
    cost=Cost(
        step_cost_s=5.8e-6,
    ),
    look=Presentation(
        color="tab:orange",
        marker="s",
        label="PyBullet",
        notes=ReportNotes(
            profile=(
                "dt = {dt_s}, `contactERP = erp = 0`, `contactSlop = 0`, no restitution "
                "threshold, no damping, `contactBreakingThreshold = 1 um`, cone friction"
            ),
            restitution=(
                "product of both bodies' `restitution`; 0 below `restitutionVelocityThreshold`"
            ),
            defaults=(
                "PyBullet's {default_solver_iterations} solver iterations and {default_dt_s} "
                "step, read back; its contactERP {default_contact_erp} and contactSlop "
                "{default_contact_slop} m, measured (set explicitly, they reproduce the "
                "default solver's impacts bit for bit, and another value changes them)"
            ),
        ),
    ),
    studies=Studies(
        speed_accuracy=(
            KnobFamily(label="reference solver (ERP 0, slop 0)", quick=True),
            *(
                KnobFamily(
                    label=f"reference solver, {n} iterations", overrides=(("solver_iterations", n),)
                )
                for n in (1, 10, 200)
            ),
        ),
        friction_families=(
            KnobFamily(label="box friction (cone off)", overrides=(("cone_friction", False),)),
        ),
    ),
    batching=Batching(
        why="none: a physics client steps the bodies it holds, one client per call; a long "
        "run's pool adapter (PybulletWorlds) puts many worlds' pairs in each client, each pair "
        "its own island, stepped by that client's one stepSimulation",
        not_it=(
            "pybullet:rayTestBatch",  # ray casts, not a step
            "pybullet:MAX_RAY_INTERSECTION_BATCH_SIZE",
            "pybullet:GUI_MAIN_THREAD",  # connection modes of the GUI
            "pybullet:GRAPHICS_SERVER_MAIN_THREAD",
        ),
    ),
)
