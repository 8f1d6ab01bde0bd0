"""The scene as a Newton model, its solver and its collision pipeline (imports Newton)."""

from __future__ import annotations

import math
import os
import warnings

import numpy as np

from ..interface import Scene
from ..loading import import_engine, stdout_silenced
from ..mujoco.model import contact_parameters
from . import PENALTY_SOLVERS, RECORD, NewtonSettings

newton = import_engine(RECORD)

import warp as wp  # noqa: E402  (after Newton, which it comes with)

wp.config.log_level = wp.LOG_WARNING  # no banner, no line per compiled module on stdout
with stdout_silenced():  # Warp's CUDA probe writes to stderr when there is no driver
    wp.init()
#: Warp's device for every model: the CPU unless the environment's BATSIM_WARP_DEVICE names
#: another ("cuda:0"), as for MuJoCo Warp.
DEVICE = os.environ.get("BATSIM_WARP_DEVICE") or "cpu"
#: Bodies and shapes of one world, in the order added.
BAT, BALL = 0, 1
#: Newton's capsule lies along its shape's z axis: a quarter turn about y lays it along -x, so
#: that its axis starts at the barrel end. Newton projects a point onto the axis with t =
#: (p - a).(b - a) / (|b - a|^2 + 1e-6 m^2): the foot lands 1.6e-6 |p - a| short of the true
#: one (0.9 um at the COM of a 0.78 m axis started at the knob, tilting the normal 1.3e-5 rad),
#: least near the axis start, here the barrel, where balls are hit.
Z_TO_MINUS_X = (0.0, -math.sin(math.pi / 4), 0.0, math.cos(math.pi / 4))


def _shape_config(scene: Scene, st: NewtonSettings):
    """Massless shapes bouncing with e (the penalty solvers' ke, kd for e), each with friction
    mu (every solver combines two shapes' into the same mu: the mean, MuJoCo's max), no
    torsional or rolling friction; frictionless, the penalty's friction gain kf is 0 too."""
    cfg = newton.ModelBuilder.ShapeConfig(
        density=0.0,
        mu=scene.mu,
        mu_torsional=0.0,
        mu_rolling=0.0,
        restitution=scene.e,
        gap=st.contact_gap_m,
    )
    if st.solver in PENALTY_SOLVERS:
        cfg.ke, cfg.kd = st.penalty_gains(scene.e)
        if scene.mu == 0.0:
            cfg.kf = 0.0
        elif st.friction_gain_nspm is not None:
            cfg.kf = st.friction_gain_nspm
    return cfg


def world_builder(scene: Scene, st: NewtonSettings):
    """One world: the bat (body 0, its capsule along x) and the ball (body 1), body frames at
    the COMs, inertias locked (shapes of density 0 add nothing anyway)."""
    bat, ball = scene.bat, scene.ball
    b = newton.ModelBuilder(gravity=(0.0, 0.0, 0.0))
    if st.solver == "mujoco":
        newton.solvers.SolverMuJoCo.register_custom_attributes(b)
    cfg = _shape_config(scene, st)
    ia, ic, ib = bat.axial_inertia_kgm2, bat.inertia_cm_kgm2, ball.inertia_kgm2
    body = b.add_body(
        mass=bat.mass_kg,
        inertia=wp.mat33(ia, 0, 0, 0, ic, 0, 0, 0, ic),
        label="bat",
        lock_inertia=True,
    )
    mid, half = 0.5 * (bat.s_min_m + bat.s_max_m), 0.5 * (bat.s_max_m - bat.s_min_m)
    b.add_shape_capsule(
        body,
        xform=wp.transform(wp.vec3(mid, 0.0, 0.0), wp.quat(*Z_TO_MINUS_X)),
        radius=bat.radius_m,
        half_height=half,
        cfg=cfg,
        label="bat",
    )
    body = b.add_body(
        mass=ball.mass_kg,
        inertia=wp.mat33(ib, 0, 0, 0, ib, 0, 0, 0, ib),
        xform=wp.transform(wp.vec3(0.0, 1.0, 0.0), wp.quat_identity()),
        label="ball",
        lock_inertia=True,
    )
    b.add_shape_sphere(body, radius=ball.radius_m, cfg=cfg, label="ball")
    return b


def model(scene: Scene, worlds: int, st: NewtonSettings, requires_grad: bool = False):
    """``worlds`` copies of the world, each its own Newton world (no contact across them);
    ``requires_grad``: its arrays keep gradients (for a ``wp.Tape``)."""
    top = newton.ModelBuilder(gravity=(0.0, 0.0, 0.0))
    if st.solver == "mujoco":
        newton.solvers.SolverMuJoCo.register_custom_attributes(top)
    top.replicate(world_builder(scene, st), worlds)
    m = top.finalize(device=DEVICE, requires_grad=requires_grad)
    if st.solver == "mujoco":
        _mujoco_contact(m, scene, st)
    return m


def _mujoco_contact(m, scene: Scene, st: NewtonSettings) -> None:
    """Frictionless (condim 1) contacts, else Newton's condim 3; impulse/soft: solref and
    solimp as for MuJoCo C, raw (``native`` keeps Newton's ke, kd, which it turns into solref
    (0.02, 1)). A geom contact has no solreffriction: its friction rows take that solref."""
    attrs = m.mujoco
    if scene.mu == 0.0:
        attrs.condim.fill_(1)
    if st.contact_model == "native":
        return
    solref, solimp = contact_parameters(st, scene.e)
    attrs.solref.assign(np.tile(np.array(solref, dtype=np.float32), (m.shape_count, 1)))
    attrs.solref_mode.fill_(1)  # SOLREF_MODE_RAW: the solref above, as MuJoCo takes it
    attrs.geom_solimp.assign(np.tile(np.array(solimp, dtype=np.float32), (m.shape_count, 1)))


def _given(**kw) -> dict:
    """The keyword arguments set (None: leave it to Newton)."""
    return {k: v for k, v in kw.items() if v is not None}


def solver(m, st: NewtonSettings, mu: float = 0.0):
    """The settings' solver on model ``m`` (None: Newton's own value); ``mu``: the contact's
    friction (MuJoCo's cone is set only with friction)."""
    solvers = newton.solvers
    if st.solver == "xpbd":
        return solvers.SolverXPBD(
            m,
            enable_restitution=st.enable_restitution,
            **_given(
                iterations=st.iterations,
                rigid_contact_relaxation=st.contact_relaxation,
                rigid_contact_restitution_iterations=st.restitution_iterations,
                angular_damping=st.angular_damping,
            ),
        )
    if st.solver == "mujoco":
        return _mujoco_solver(m, st, st.cone if mu > 0.0 else None)
    cls = solvers.SolverSemiImplicit if st.solver == "semi_implicit" else solvers.SolverFeatherstone
    return cls(m, **_given(angular_damping=st.angular_damping))


def _mujoco_solver(m, st: NewtonSettings, cone: str | None):
    """SolverMuJoCo on MuJoCo Warp, its own collision (``mujoco_solver``); MuJoCo Warp prints
    a line per step that reaches its iteration limit (a float32 solve at a small tolerance
    often does): dropped."""
    from mujoco_warp import OverflowType

    out = mujoco_solver(m, **_given(iterations=st.iterations, integrator=st.integrator, cone=cone))
    if st.tolerance is not None:  # MuJoCo Warp raises a model's tolerance to 1e-6 as it loads it
        out.mjw_model.opt.tolerance.fill_(st.tolerance)
    quiet = ~int(OverflowType.ITERATIONS | OverflowType.LS_ITERATIONS)
    out.mjw_model.opt.warn_overflow = int(out.mjw_model.opt.warn_overflow) & quiet
    return out


def mujoco_solver(m, **kwargs):
    """``SolverMuJoCo(m, **kwargs)``; it warns that the mujoco installed (4.0) is not the one
    Newton 1.8 declares (3.17), which the project pins on purpose: dropped."""
    with warnings.catch_warnings():
        warnings.filterwarnings("ignore", message="MuJoCo dependency version mismatch")
        return newton.solvers.SolverMuJoCo(m, **kwargs)


def pipeline(m, st: NewtonSettings):
    """Newton's collision pipeline (None for MuJoCo, which collides on its own)."""
    if st.solver == "mujoco":
        return None
    return newton.CollisionPipeline(
        m, broad_phase="explicit", rigid_contact_max=4 * m.world_count, verify_buffers=False
    )
