"""PyBullet adapter: two base-only multibodies (PyBullet's default) in a DIRECT client.

Traps this adapter handles (measured): ``contactSlop`` (1e-5 m by default)
and ``contactERP`` feed position error back into the velocity (slop/dt alone costs 8% at
dt = 1e-5 s), so the reference profile zeroes both; default damping 0.04 is zeroed for the scene;
restitution is the product of both bodies' values (bat 1, ball e) and is dropped below
``restitutionVelocityThreshold``; base position and velocity calls refer to the COM; multibody
angular speed is capped at ``maxJointVelocity`` (100 rad/s unless raised).
"""

from __future__ import annotations

from dataclasses import dataclass

from analytic import checks

from ..record import EngineRecord, KnobFamily, ReportNotes, RestitutionRule, Settings

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
}


@dataclass(frozen=True, kw_only=True)
class PybulletSettings(Settings):
    """Bullet's knobs (None: keep the engine's own default). ``contact_erp``/``erp``/
    ``friction_erp``: fraction of position error corrected per step; ``contact_slop`` (m):
    overlap allowed before correction; ``restitution_velocity_threshold`` (m/s);
    ``contact_breaking_threshold`` (m): contact margin; ``split_impulse`` 0/1;
    ``max_joint_velocity_radps``: the multibody angular-speed cap; ``ccd_swept_sphere_radius``
    (m): continuous collision detection, 0 = off."""

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

    def __post_init__(self) -> None:
        super().__post_init__()
        if self.solver_iterations is not None:
            checks.integer("solver_iterations", self.solver_iterations, 1, 10_000)
        for name in ("contact_erp", "erp", "friction_erp"):
            if getattr(self, name) is not None:
                checks.in_range(name, getattr(self, name), 0.0, 1.0)
        for name in ("contact_slop", "restitution_velocity_threshold",
                     "contact_breaking_threshold", "ccd_swept_sphere_radius"):
            if getattr(self, name) is not None:
                checks.non_negative(name, getattr(self, name))
        if self.max_joint_velocity_radps is not None:
            checks.positive("max_joint_velocity_radps", self.max_joint_velocity_radps)


RECORD = EngineRecord(
    name="pybullet", adapter="adapters.pybullet.adapter:PybulletEngine", package="pybullet",
    import_name="pybullet",
    profiles={
        # No position feedback into contact velocities (contactERP = 0, contactSlop = 0): the
        # sequential-impulse solver then meets Newton's law exactly for one contact; the hands'
        # pivot (a joint, governed by erp) fully corrected every step, erp = 1: its drift is
        # then second order (2e-6 rad/s after a 0.1 s swing at 10 us, 4e-3 with erp = 0); no
        # restitution threshold; the angular cap lifted so a blow-up shows as it is; 10 us step.
        "reference": PybulletSettings(dt_s=1e-5, contact_erp=0.0, erp=1.0, friction_erp=0.0,
                                      contact_slop=0.0, restitution_velocity_threshold=0.0,
                                      max_joint_velocity_radps=1e4),
        # Out of the box: 1/240 s, every solver parameter left at Bullet's value, the contact
        # instant mid-step as in any unaligned simulation.
        "default": PybulletSettings(dt_s=1 / 240, contact_phase=0.5),
    },
    color="tab:orange", marker="s",
    speed_accuracy=(
        KnobFamily(label="reference solver (ERP 0, slop 0)", quick=True),
        *(KnobFamily(label=f"reference solver, {n} iterations",
                     overrides=(("solver_iterations", n),)) for n in (1, 10, 200)),
    ),
    restitution_rule=RestitutionRule.PRODUCT,
    threshold_setting="restitution_velocity_threshold",
    # Bullet reports neither contact value: both measured (setting them explicitly reproduces
    # the default solver's impacts bit for bit); the iteration count it reports.
    engine_defaults={"contact_erp": 0.08, "contact_slop": 1e-5, "solver_iterations": 50,
                     "dt_s": 1 / 240},
    step_cost_s=2e-6,
    label="PyBullet",
    notes=ReportNotes(
        profile=("dt = {dt_s}, `contactERP = erp = 0`, `contactSlop = 0`, no restitution "
                 "threshold, no damping"),
        restitution=("product of both bodies' `restitution`; 0 below "
                     "`restitutionVelocityThreshold`"),
        defaults=("PyBullet's {default_solver_iterations} solver iterations and {default_dt_s} "
                  "step, read back; its contactERP {default_contact_erp} and contactSlop "
                  "{default_contact_slop} m, measured (set explicitly, they reproduce the "
                  "default solver's impacts bit for bit, and another value changes them)")),
)
