"""Newton's own derivative of an impact: reverse mode, ``wp.Tape`` over the collision pipeline
and ``SolverXPBD.step``, every world at once.

A separate model, finalized with ``requires_grad``, a state per step and a contact buffer per
step (the tape replays each step's kernels backward with the arrays they read then). Newton's
narrow phase is compiled without adjoints: each step's contacts (the normal and both bodies'
contact points, in the bodies' frames) are frozen as found, and the gradient flows through
the bodies' poses and twists alone. The bat's moment of inertia enters XPBD as
``body_inertia`` (its body deltas read it) and as ``body_inv_inertia``, which the solver
copies into ``body_inv_inertia_effective`` (I_cm about the body's y and z): dv1/dJ =
g(I)_yy + g(I)_zz - (g(I^-1)_yy + g(I^-1)_zz) / J^2.
Only XPBD is wired (the reference); MuJoCo Warp's step has no adjoints
(``adapters.mjwarp.adapter.no_adjoints``), the penalty solvers are not wired here.
"""

from __future__ import annotations

import numpy as np

from ..frames import bat_quaternions
from . import scene as sc

wp = sc.wp


@wp.kernel
def _ball_vy(body_qd: wp.array(dtype=wp.spatial_vector), out: wp.array(dtype=float)):
    """out[0] += every world's ball vy (worlds are independent: its gradient is each one's)."""
    w = wp.tid()
    wp.atomic_add(out, 0, body_qd[2 * w + 1][1])


def _poses(states: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """body_q (2n, 7) and body_qd (2n, 6) of planar rows (``NewtonEngine.set_state``'s)."""
    n = len(states)
    q, qd = np.zeros((n, 2, 7)), np.zeros((n, 2, 6))
    q[:, sc.BAT, :2], q[:, sc.BALL, :2] = states[:, [5, 6]], states[:, [0, 1]]
    q[:, sc.BAT, 3:] = bat_quaternions(states[:, 7], np.zeros(n))[:, [1, 2, 3, 0]]
    q[:, sc.BALL, 6] = 1.0
    qd[:, sc.BAT, :2], qd[:, sc.BAT, 5] = states[:, [8, 9]], states[:, 10]
    qd[:, sc.BALL, :2], qd[:, sc.BALL, 5] = states[:, [2, 3]], states[:, 4]
    return q.reshape(-1, 7), qd.reshape(-1, 6)


def _state_tangent(states: np.ndarray, g_q: np.ndarray, g_qd: np.ndarray) -> np.ndarray:
    """d(ball vy)/d(planar row) (n, 11) from the gradients on body_q and body_qd."""
    n = len(states)
    g_q, g_qd = g_q.reshape(n, 2, 7), g_qd.reshape(n, 2, 6)
    half = 0.5 * states[:, 7]
    out = np.zeros((n, 11))
    out[:, [0, 1]], out[:, [5, 6]] = g_q[:, sc.BALL, :2], g_q[:, sc.BAT, :2]
    out[:, 7] = 0.5 * (g_q[:, sc.BAT, 5] * np.cos(half) - g_q[:, sc.BAT, 6] * np.sin(half))
    out[:, [2, 3]], out[:, 4] = g_qd[:, sc.BALL, :2], g_qd[:, sc.BALL, 5]
    out[:, [8, 9]], out[:, 10] = g_qd[:, sc.BAT, :2], g_qd[:, sc.BAT, 5]
    return out


def derivative(engine, states, tangents, steps: int, inertia_tangent_kgm2: float = 0.0):
    """``BatchedEngine.derivative`` for a Newton engine built with its scene (module docstring);
    the tangents' derivative of the ball's vy alone (the other columns NaN)."""
    st = engine.settings
    states, tangents = np.asarray(states, float), np.asarray(tangents, float)
    if st.solver != "xpbd":
        raise NotImplementedError(f"Newton's {st.solver} solver is not wired to a wp.Tape here")
    if np.any(states[:, 11:] != 0.0) or np.any(tangents[:, 11:] != 0.0):
        raise NotImplementedError("Newton's derivative here takes impacts in the swing plane only")
    n = len(states)
    m = sc.model(engine.scene, n, st, requires_grad=True)
    solver, pipeline = sc.solver(m, st, engine.scene.mu), sc.pipeline(m, st)
    chain = [m.state(requires_grad=True) for _ in range(steps + 1)]
    contacts = [pipeline.contacts() for _ in range(steps)]
    q, qd = _poses(states)
    chain[0].body_q.assign(q.astype(np.float32))
    chain[0].body_qd.assign(qd.astype(np.float32))
    out = wp.zeros(1, dtype=float, requires_grad=True)
    tape = wp.Tape()
    with tape:
        for i in range(steps):
            pipeline.collide(chain[i], contacts[i])
            solver.step(chain[i], chain[i + 1], m.control(), contacts[i], st.dt_s)
        wp.launch(_ball_vy, dim=n, inputs=[chain[-1].body_qd], outputs=[out])
    tape.backward(out)
    grad = _state_tangent(states, chain[0].body_q.grad.numpy(), chain[0].body_qd.grad.numpy())
    g_inv = solver.body_inv_inertia_effective.grad.numpy().reshape(n, 2, 3, 3)[:, sc.BAT]
    g_j = m.body_inertia.grad.numpy().reshape(n, 2, 3, 3)[:, sc.BAT]
    j = engine.scene.bat.inertia_cm_kgm2
    d_j = g_j[:, 1, 1] + g_j[:, 2, 2] - (g_inv[:, 1, 1] + g_inv[:, 2, 2]) / j**2
    d_vy = np.sum(grad * tangents[:, :11], axis=1) + d_j * inertia_tangent_kgm2
    ends = np.full((n, 11), np.nan)
    ends[:, 3] = chain[-1].body_qd.numpy().reshape(n, 2, 6)[:, sc.BALL, 1]
    d_ends = np.full((n, 11), np.nan)
    d_ends[:, 3] = d_vy
    return ends, d_ends
