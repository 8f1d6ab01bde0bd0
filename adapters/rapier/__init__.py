"""Rapier (PyPI ``rapier3d``, 3D, f32): two dynamic bodies in one ``PhysicsWorld``.

The bat is a dynamic body whose origin is its COM, carrying a massless capsule collider along
its x axis (``capsule_from_endpoints``: no rotated y capsule), its mass, COM and principal
inertia (axial, I_cm, I_cm) set as additional mass properties; the ball likewise with a sphere.
Traps this adapter handles (measured with rapier3d 0.36.1, the binding pinned by the extra):
- Mass properties set on a body are folded in at the next step: read back 0 kg before it, so
  the adapter recomputes them at once. Rapier stores them in f32 (0.871 kg reads back as
  0.87099999189): the read-back check allows a few f32 ulps (``check_mass_properties``).
- Speculative contacts: a pair closer than ``prediction_distance_m`` (0.02 m by default) gets a
  contact whose normal and lever arms are those of the step's start; the impact is then solved
  one step early, with the swinging bat's geometry omega dt out of date: |dv1| 2.5e-3 m/s over
  the paper's swing at 10 us (2.7e-2 at 100 us, first order), against 1e-5 with 1 um.
- Contact recycling (on by default) keeps a pair's contact points while it moved less than
  0.05 m, i.e. for ~100 steps at 10 us: the reference recomputes them every step.
- Contact softness (30 Hz, damping ratio 10) does not touch a bounce: restitution is applied
  rigidly after the substeps (e = 0.5 within 2e-7 from 0.01 to 40 m/s at every profile, no
  restitution velocity threshold), and issue #974 (restitution lost in a 0.35 beta) does not
  show. It rules a sustained contact: a plastic ball riding the turning bat sinks 0.8 mm into it
  and v1 is 0.18 m/s off the rigid answer (e = 0 sweep), against 9e-3 m/s at 10 kHz, ratio 1.
- The relax pass (``stabilization_iterations``) removes the velocity that corrects position
  errors: needed for contacts (without it a plastic slide turns into a bounce, |dv1| 8 m/s), but
  it makes an impulse joint lose omega at first order (about 0.3 omega dt / n relative after a
  0.1 s swing from rest, n substeps: 1.1e-3 at dt = 1e-4 s, n = 1). The reference hinge is a
  multibody (reduced coordinates) revolute joint instead: omega exact to f32 rounding, the
  angle off by exactly the semi-implicit Euler term. Multibody links are damped (0.1) by
  default: zeroed. The link's rigid body holds the velocity of one step before: ``unpin``
  releases the joint's own.
- Substeps: each of ``solver_iterations`` (4 by default) integrates dt/n, so the swing's angle
  error is alpha t dt/(2n); the reference takes one, the semi-implicit Euler the harness models.
- Rotation per step is 2 atan(omega dt/2), not omega dt (a normalised first-order quaternion
  update): 0.012 rad short at 32 rad/s and 1/60 s, 3e-12 at 10 us.
- Speed caps: linear speed clamped to 400 m/s, angular to (pi/4)/dt unless the body allows fast
  rotation (60 rad/s becomes 47.1 at 1/60 s): both lifted in the reference.
- CCD: ``ccd_enabled`` bodies ("bullets") sweep against dynamic bodies but never against other
  bullets, so both bodies enabled tunnel 41 of 41 impacts at 1/60 s (issue #984's two fast
  bodies); the ball alone enabled catches 30. ``ccd_bodies`` picks which.
- Restitution combines as the mean of the two colliders' values (Average, the default rule):
  ``set_restitution`` gives both e. User forces persist across steps until reset; the world runs
  on one thread (a shared machine; results then do not depend on a pool).

Out of the swing plane: a rigid body's ``angvel`` is the world's (measured: omega_x on a body
turned by pi/2 about z turns its x axis, the world's y, toward z), so both bodies' angular
velocities go in and out as they are; ``Rotation3`` takes (w, x, y, z) and reads back as .w,
.i, .j, .k. A bat in the swing plane keeps the f32 rotation Rapier makes about z (bit for bit
what planar runs always had); a tilted one takes ``frames.bat_quaternion``.

Friction (rapier's source at 0.35.2, the binding's stubs and measurements):
- each collider's ``friction`` (1 by default) combines by the stronger of the two colliders'
  ``friction_combine_rule`` (GeometricMean > ClampedSum > Max > Multiply > Min > Average),
  Average by default (read back from ``ColliderMaterial``): bat 0.1 and ball 0.3, either way
  round, slide at 0.2 against the compression impulse (below), so both get mu. One coefficient
  (no static/dynamic pair); colliders have no rolling or spinning friction. A frictionless
  scene is built as before (both 0, Rapier's own friction model);
- the cone is circular: in 3D each point's two tangent impulses are solved together (an exact
  2x2 solve) and the pair is capped at mu times that point's normal impulse (measured: a slide
  at 45 degrees to the bat's axis gets the same mu as one along it, not the pyramid's sqrt(2)
  mu). ``friction_model`` picks one such constraint per point (``coulomb``) or one per manifold
  at its friction centre plus a twist constraint (``simplified``, Rapier's default): a ball on
  a capsule is a one-point manifold, whose twist has no lever, so both give the same bits here.
  Friction is solved in each substep's relax pass only unless ``friction_in_bias_pass`` (then
  4e-4 m/s and 0.03 rad/s apart on the paper's swing at mu = 0.5);
- the defect: restitution is applied once after the substeps (rapier 0.35.0's end-of-step pass,
  the fix of issue #974), and that pass carries no friction, so the cone is bounded by the
  compression impulse alone: a slide gets mu P / (1 + e) of tangential impulse where Coulomb
  gives mu P (measured on the heavy wall, 20 m/s at theta 0.5, e = 0.5, mu = 0.05: spin 59.935
  rad/s for Routh's 89.903, 2/3 of it; vt1 0.44 m/s high), and rows that stick are off too
  (vt1 0.19 m/s, spin 13 rad/s on the paper's swing at mu = 0.5, theta = 0.3). At e = 0 (no
  restitution pass) an undercut row there is within 1e-2 m/s and 0.5 rad/s of Routh's answer.
  No setting changes it.
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

#: The hands' releasable hinge: an impulse joint, or a multibody (reduced-coordinate) joint.
HINGES = ("impulse", "multibody")
#: Which bodies are CCD bullets (``ccd_enabled``).
CCD_BODIES = ("none", "ball", "both")
#: Rapier's friction models (``IntegrationParameters.friction_model``): one friction constraint
#: per group of up to four contact points plus a twist constraint (its default), or one Coulomb
#: friction constraint per point.
FRICTION_MODELS = ("simplified", "coulomb")
#: f32's largest value: Rapier's "no cap" for its linear speed clamp.
F32_MAX = 3.4028234663852886e38


@dataclass(frozen=True, kw_only=True)
class RapierSettings(Settings):
    """Rapier's knobs (its ``IntegrationParameters``, per-body CCD and the hinge).

    ``solver_iterations``: substeps per step; ``pgs_iterations`` and
    ``stabilization_iterations``: the biased and the relax (unbiased) solver passes of each
    substep; ``contact_frequency_hz``/``contact_damping_ratio``: the contact's softness, the
    spring that drives penetration out in the biased pass; ``allowed_linear_error_m`` (m): the
    CCD clamp's standoff; ``max_corrective_velocity_mps`` (m/s): the push-out speed cap;
    ``prediction_distance_m`` (m): speculative contacts are made this far apart;
    ``max_linear_velocity_mps`` (m/s): every body's speed cap (F32_MAX: none);
    ``allow_fast_rotation``: lift the (pi/4)/dt angular speed cap; ``warmstart_coefficient`` in
    [0, 1]; ``contact_recycling``: keep contact points while the pair moved under 0.05 m;
    ``max_ccd_substeps``: the world's CCD switch (0: off); ``ccd_bodies`` one of CCD_BODIES;
    ``soft_ccd_prediction_m`` (m): both bodies' soft-CCD distance; ``hinge`` one of HINGES,
    ``hinge_frequency_hz``/``hinge_damping_ratio`` the impulse joint's softness;
    ``friction_model`` one of FRICTION_MODELS; ``friction_in_bias_pass``: friction solved in the
    biased pass too, not only in the relax pass (both set only for a scene with friction).
    """

    solver_iterations: int = 4
    pgs_iterations: int = 1
    stabilization_iterations: int = 1
    contact_frequency_hz: float = 30.0
    contact_damping_ratio: float = 10.0
    allowed_linear_error_m: float = 0.005
    max_corrective_velocity_mps: float = 3.0
    prediction_distance_m: float = 0.02
    max_linear_velocity_mps: float = 400.0
    allow_fast_rotation: bool = False
    warmstart_coefficient: float = 1.0
    contact_recycling: bool = True
    max_ccd_substeps: int = 1
    ccd_bodies: str = "none"
    soft_ccd_prediction_m: float = 0.0
    hinge: str = "impulse"
    hinge_frequency_hz: float = 1.0e6
    hinge_damping_ratio: float = 1.0
    friction_model: str = "simplified"
    friction_in_bias_pass: bool = False

    def __post_init__(self) -> None:
        super().__post_init__()
        checks.integer("solver_iterations", self.solver_iterations, 1, 10_000)
        checks.integer("pgs_iterations", self.pgs_iterations, 1, 10_000)
        checks.integer("stabilization_iterations", self.stabilization_iterations, 0, 10_000)
        checks.integer("max_ccd_substeps", self.max_ccd_substeps, 0, 10_000)
        for name in (
            "contact_frequency_hz",
            "contact_damping_ratio",
            "max_linear_velocity_mps",
            "hinge_frequency_hz",
            "hinge_damping_ratio",
        ):
            checks.positive(name, getattr(self, name))
        for name in (
            "allowed_linear_error_m",
            "max_corrective_velocity_mps",
            "prediction_distance_m",
            "soft_ccd_prediction_m",
        ):
            checks.non_negative(name, getattr(self, name))
        checks.in_range("warmstart_coefficient", self.warmstart_coefficient, 0.0, 1.0)
        for name in ("allow_fast_rotation", "contact_recycling", "friction_in_bias_pass"):
            if not isinstance(getattr(self, name), bool):
                raise ValueError(
                    f"{name}={getattr(self, name)!r} is not a bool; allowed: True, False"
                )
        for name, allowed in (
            ("ccd_bodies", CCD_BODIES),
            ("hinge", HINGES),
            ("friction_model", FRICTION_MODELS),
        ):
            if getattr(self, name) not in allowed:
                raise ValueError(
                    f"{name}={getattr(self, name)!r} is unknown; allowed: {', '.join(allowed)}"
                )


class RapierErrors(ErrorModel):
    """Rapier: speculative contact and its friction's cone."""

    def speculative_margin_m(self, s) -> float:
        return s.prediction_distance_m

    def friction_cone(self, s) -> str:
        # a ball on a capsule is a one-point manifold: no twist lever, both models alike
        model = "one per point" if s.friction_model == "coulomb" else "one per manifold + twist"
        return (
            f"circular, |P_t| <= mu P_n of the substeps ({model}); the restitution "
            "impulse frictionless"
        )


RECORD = EngineRecord(
    name="rapier",
    adapter="adapters.rapier.adapter:RapierEngine",
    install=Install(
        package="rapier3d",
        import_name="rapier3d",
        extra="rapier",
        oldest="0.36.0",
        history=("0.36.0", "0.36.1"),
    ),
    profiles={
        # Fidelity, each value measured on the paper's swing (41 points) and its e = 0 slide:
        # 10 us step; one substep (the semi-implicit Euler step the swing tolerances model;
        # 4 give the same impacts); a 1 um prediction distance (the impact then sees the geometry
        # of its own step: |dv1| 1e-5 m/s instead of 2.5e-3 at 0.02 m, yet a gap left by f32
        # rounding still makes a contact); contact points recomputed every step; a stiff contact
        # (10 kHz, damping ratio 1: penetration removed within a few steps; e = 0 slide |dv1|
        # 9e-3 m/s instead of 0.18, bounces unchanged); the speed caps lifted so that a blow-up
        # shows as it is; the hands a multibody joint (omega exact, see the module docstring);
        # Coulomb's friction constraint at each contact point.
        "reference": RapierSettings(
            dt_s=1e-5,
            solver_iterations=1,
            prediction_distance_m=1e-6,
            contact_frequency_hz=1e4,
            contact_damping_ratio=1.0,
            contact_recycling=False,
            max_linear_velocity_mps=F32_MAX,
            allow_fast_rotation=True,
            hinge="multibody",
            friction_model="coulomb",
        ),
        # Out of the box: 1/60 s, every solver value Rapier's own, the hands an impulse joint
        # (Rapier's usual joint) of default softness; the contact instant mid-step as in any
        # unaligned simulation.
        "default": RapierSettings(dt_s=1 / 60, contact_phase=0.5),
    },
    can=Capabilities(
        chain_adapter="adapters.rapier.chain:RapierChain",
        integrators=(Integrator(label="semi-implicit Euler"),),
        restitution_rule=RestitutionRule.MEAN,
        friction_rule=FrictionRule.MEAN,
    ),
    errors=RapierErrors(
        precision="float32",
        friction_defect="the restitution impulse, applied once after the substeps, carries no "
        "friction: a slide gets mu P / (1 + e) of tangential impulse for "
        "Coulomb's "
        "mu P (2/3 of the spin at e = 0.5; package docstring)",
    ),
    # Every value read back from a fresh IntegrationParameters, rigid body and joint.
    engine_defaults={
        "dt_s": 1 / 60,
        "solver_iterations": 4,
        "pgs_iterations": 1,
        "stabilization_iterations": 1,
        "contact_frequency_hz": 30.0,
        "contact_damping_ratio": 10.0,
        "allowed_linear_error_m": 0.005,
        "max_corrective_velocity_mps": 3.0,
        "prediction_distance_m": 0.02,
        "max_linear_velocity_mps": 400.0,
        "allow_fast_rotation": False,
        "warmstart_coefficient": 1.0,
        "contact_recycling": True,
        "max_ccd_substeps": 1,
        "ccd_bodies": "none",
        "soft_ccd_prediction_m": 0.0,
        "hinge_frequency_hz": 1.0e6,
        "hinge_damping_ratio": 1.0,
        "friction_model": "simplified",
        "friction_in_bias_pass": False,
    },
    cost=Cost(
        step_cost_s=2.7e-5,
    ),
    look=Presentation(
        color="tab:purple",
        marker="v",
        label="Rapier",
        notes=ReportNotes(
            profile=(
                "dt = {dt_s}, {solver_iterations} substep, prediction distance "
                "{prediction_distance_m}, contact recycling off, speed caps lifted, hinge a "
                "{hinge} joint"
            ),
            restitution=(
                "mean of both colliders' restitution (the default combine rule; both "
                "set to e); no threshold"
            ),
            handled=(
                "speculative contacts (prediction distance {default_prediction_distance_m} by "
                "default) solve the impact from the step start's geometry (with "
                "{prediction_distance_m}, the reference is {err_mps} m/s off on the swing); "
                "contact recycling keeps stale points; a free body turns 2 atan(omega dt/2) "
                "per step, not omega dt; angular speed is clamped to (pi/4)/dt unless fast "
                'rotation is allowed; CCD between two "bullets" never sweeps (rapier#984); '
                "the relax pass costs an impulse joint first-order spin (hence the multibody "
                "hinge). Restitution works in {version} (rapier#974's loss is gone)."
            ),
        ),
    ),
    studies=Studies(
        speed_accuracy=(
            KnobFamily(label="reference solver", quick=True),
            KnobFamily(label="4 substeps", overrides=(("solver_iterations", 4),)),
            KnobFamily(
                label="speculative 0.02 m", overrides=(("prediction_distance_m", 0.02),), quick=True
            ),
            KnobFamily(
                label="soft contact 30 Hz",
                overrides=(("contact_frequency_hz", 30.0), ("contact_damping_ratio", 10.0)),
            ),
            KnobFamily(label="CCD on the ball", overrides=(("ccd_bodies", "ball"),)),
        ),
        friction_families=(
            KnobFamily(label="simplified friction", overrides=(("friction_model", "simplified"),)),
            KnobFamily(
                label="friction in the bias pass", overrides=(("friction_in_bias_pass", True),)
            ),
        ),
    ),
    batching=Batching(
        call="rapier3d:PhysicsWorld.set_num_threads",
        why="rayon workers for one world's parallel stages; the adapter runs each world on "
        "its calling thread (set_num_threads(1)): a two-body world has no parallel work. A "
        "world's step releases the GIL, so several worlds could be stepped from Python "
        "threads at once: not used, Rapier has no pool adapter yet",
    ),
)
