"""Newton's own values of the settings the record quotes, read from fresh Newton objects and,
for the time step, from the source of Newton's restitution example (imports Newton)."""

from __future__ import annotations

import ast
from pathlib import Path

from . import scene as sc

newton, wp = sc.newton, sc.wp
#: Newton's example of rigid impacts with restitution (XPBD, ``enable_restitution=True``).
EXAMPLE = Path(newton.__file__).parent / "examples" / "contacts" / "example_newton_cradle.py"


def example_dt_s(solver: str = "xpbd") -> float:
    """The cradle example's step: 1 / (fps * SUBSTEPS[solver]), both read from its source."""
    tree = ast.parse(EXAMPLE.read_text())
    fps = substeps = None
    for node in ast.walk(tree):
        if not isinstance(node, ast.Assign):
            continue
        target = node.targets[0]
        if isinstance(target, ast.Name) and target.id == "SUBSTEPS":
            substeps = ast.literal_eval(node.value)[solver]
        if isinstance(target, ast.Attribute) and target.attr == "fps":
            fps = ast.literal_eval(node.value)
    if fps is None or substeps is None:
        raise RuntimeError(f"{EXAMPLE} no longer sets fps and SUBSTEPS")
    return 1.0 / (fps * substeps)


def read_back() -> dict:
    """XPBD's constructor defaults on a one-body model, the builder's contact gap and shape
    friction gain, SolverMuJoCo's cone, and the example's time step."""
    builder = newton.ModelBuilder(gravity=(0.0, 0.0, 0.0))
    builder.add_body(mass=1.0, inertia=wp.mat33(1, 0, 0, 0, 1, 0, 0, 0, 1))
    solver = newton.solvers.SolverXPBD(builder.finalize(device=sc.DEVICE))
    return {
        "dt_s": example_dt_s(),
        "iterations": solver.iterations,
        "contact_relaxation": solver.rigid_contact_relaxation,
        "restitution_iterations": solver.rigid_contact_restitution_iterations,
        "contact_gap_m": newton.ModelBuilder().rigid_gap,
        "angular_damping": solver.angular_damping,
        "friction_gain_nspm": newton.ModelBuilder.ShapeConfig().kf,
        "cone": _mujoco_cone(),
    }


def _mujoco_cone() -> str:
    """The cone of a SolverMuJoCo left to choose it, on a one-body model."""
    import mujoco

    builder = newton.ModelBuilder(gravity=(0.0, 0.0, 0.0))
    newton.solvers.SolverMuJoCo.register_custom_attributes(builder)
    body = builder.add_body(mass=1.0, inertia=wp.mat33(1, 0, 0, 0, 1, 0, 0, 0, 1))
    builder.add_shape_sphere(body, radius=0.1)
    solver = sc.mujoco_solver(builder.finalize(device=sc.DEVICE))
    return (
        "elliptic"
        if int(solver.mjw_model.opt.cone) == mujoco.mjtCone.mjCONE_ELLIPTIC
        else "pyramidal"
    )
