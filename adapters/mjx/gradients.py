"""MJX's own derivative of an impact: forward-mode automatic differentiation (``jax.jvp``)
through ``mjx.step``, every world at once (``jax.vmap``).

Forward mode, because MJX's constraint solver stops on a tolerance inside
``jax.lax.while_loop``, which JAX differentiates forward but not in reverse. A tangent is a
direction in the start state (the 11 planar fields: the harness's placement turns an impact
point or a pitch speed into one) and in the bat's moment of inertia about its COM, which
MJX holds in ``body_inertia`` and turns into the mass matrix at every step. What the model
derives once as it is put on the device (``body_invweight0``, the regulariser's scale) does
not follow the inertia's tangent: it is scaled down to near nothing at the reference profile
(``invweight_scale``), and the rows say so where it is not.

``knob_derivative`` differentiates the same steps with respect to the contact's settings knobs
(solref, solimp; the soft contact's w and d): each knob's tangent is the direction it moves
the model's contact arrays in (``mujoco.model.contact_tangents``, the chain rule through the
adapter's mapping), and all k directions go through one compiled call (``jax.vmap`` of the
``jax.jvp`` over them, the start rows fixed). MJX reads those arrays afresh at every step's
collision (the geoms' mixed, a pair's as they are) and derives nothing from them as the model is
put on the device, so the tangent is the whole derivative.
"""

from __future__ import annotations

import functools

import mujoco
import numpy as np

from ..mujoco.model import CONTACT_ARRAYS, contact_tangents
from .runtime import bucket, jax, jnp, mjx

#: Steps are padded up to a multiple of this (free flight after the contact leaves the
#: velocities as they are): one compile serves episodes of nearby lengths.
STEP_BUCKET = 8
#: Worlds are padded up to the adapter's bucket, and at least this many: one compile serves
#: the study's calls of one world (a root search) and of a few dozen (a fit).
MIN_ROWS = 32
#: ``knob_derivative``'s least padded world count: a fit of the contact to a COR-vs-speed law
#: takes a handful of speeds, each carrying k tangents (padding to MIN_ROWS would cost 16
#: times the work of 2 speeds on a CPU).
KNOB_MIN_ROWS = 4


def _coordinates(row, dtype):
    """qpos and qvel of one world from its planar state row (``frames.mujoco_coordinates``
    for a row in the swing plane, in jnp so that JAX can differentiate it)."""
    bx, by, bvx, bvy, bw, cx, cy, a, cvx, cvy, cw = (row[i] for i in range(11))
    zero, one = jnp.zeros((), dtype), jnp.ones((), dtype)
    qpos = jnp.stack(
        [
            cx,
            cy,
            zero,
            jnp.cos(a / 2),
            zero,
            zero,
            jnp.sin(a / 2),
            bx,
            by,
            zero,
            one,
            zero,
            zero,
            zero,
        ]
    )
    qvel = jnp.stack([cvx, cvy, zero, zero, zero, cw, bvx, bvy, zero, zero, zero, bw])
    return qpos.astype(dtype), qvel.astype(dtype)


def _row(d):
    """The planar state row of one world's data (``adapter._advance``'s)."""
    q, v = d.qpos, d.qvel
    return jnp.stack(
        [q[7], q[8], v[6], v[7], v[11], q[0], q[1], 2.0 * jnp.arctan2(q[6], q[3]), v[0], v[1], v[5]]
    )


@functools.lru_cache(maxsize=16)
def _traced(model_def, steps: int, bat: int, perpendicular: tuple[int, ...]):
    """The jitted, vmapped jvp of ``steps`` steps for a model structure: (end rows, their
    tangents) from start rows, their tangents, and the inertia's tangent (kg m^2)."""

    def run(m_leaves, data, rows, d_rows, d_inertia):
        model = jax.tree_util.tree_unflatten(model_def, m_leaves)
        inertia = model.body_inertia

        def episode(row, inertia):
            m = model.replace(body_inertia=inertia)
            qpos, qvel = _coordinates(row, data.qpos.dtype)
            d = data.replace(qpos=qpos, qvel=qvel)
            d = jax.lax.fori_loop(0, steps, lambda _, d: mjx.step(m, d), d)
            return _row(d)

        d_J = jnp.zeros_like(inertia)
        for axis in perpendicular:
            d_J = d_J.at[bat, axis].set(d_inertia)
        return jax.vmap(lambda r, dr: jax.jvp(episode, (r, inertia), (dr, d_J)))(rows, d_rows)

    return jax.jit(run)


def derivative(
    engine, states: np.ndarray, tangents: np.ndarray, steps: int, inertia_tangent_kgm2: float = 0.0
) -> tuple[np.ndarray, np.ndarray]:
    """``BatchedEngine.derivative`` for an MJX engine built with its scene (module docstring)."""
    states, tangents = np.asarray(states, float), np.asarray(tangents, float)
    if np.any(states[:, 11:] != 0.0) or np.any(tangents[:, 11:] != 0.0):
        raise NotImplementedError("MJX's derivative here takes impacts in the swing plane only")
    steps = STEP_BUCKET * -(-steps // STEP_BUCKET)
    n = len(states)
    rows = max(MIN_ROWS, bucket(n))  # padded with copies of the first world
    states = np.concatenate([states, np.repeat(states[:1], rows - n, axis=0)])
    tangents = np.concatenate([tangents, np.repeat(tangents[:1], rows - n, axis=0)])
    bat = engine._ids["body"]
    with engine._scope():
        model = engine.model
        dtype = model.body_inertia.dtype
        m_leaves, model_def = jax.tree_util.tree_flatten(model)
        run = _traced(model_def, steps, bat, _perpendicular(model, bat))
        data = mjx.make_data(model, impl="jax")
        ends, d_ends = run(
            m_leaves,
            data,
            jnp.asarray(states[:, :11], dtype),
            jnp.asarray(tangents[:, :11], dtype),
            jnp.asarray(inertia_tangent_kgm2, dtype),
        )
        return np.asarray(ends, float)[:n], np.asarray(d_ends, float)[:n]


def _perpendicular(model, bat: int) -> tuple[int, ...]:
    """The bat's principal axes across its length (``body_inertia``'s entries that are I_cm:
    its long axis is x, and ``body_iquat`` may order the axes otherwise)."""
    rot = np.zeros(9)
    mujoco.mju_quat2Mat(rot, np.asarray(model.body_iquat[bat], dtype=float))
    along_x = np.abs(rot.reshape(3, 3)[0])
    return tuple(int(k) for k in np.flatnonzero(along_x < 0.5))


@functools.lru_cache(maxsize=16)
def _traced_knobs(model_def, steps: int):
    """The jitted jvp of ``steps`` steps for a model structure, vmapped over the worlds and,
    inside each, over the k tangent directions of the contact arrays: (end rows (rows, 11),
    their tangents (rows, 11, k)) from start rows and the arrays' tangents (k, *shape)."""
    fields = tuple(CONTACT_ARRAYS)

    def run(m_leaves, data, rows, t_arrays):
        model = jax.tree_util.tree_unflatten(model_def, m_leaves)
        arrays = tuple(getattr(model, f) for f in fields)

        def episode(row, values):
            m = model.replace(**dict(zip(fields, values)))
            qpos, qvel = _coordinates(row, data.qpos.dtype)
            d = data.replace(qpos=qpos, qvel=qvel)
            d = jax.lax.fori_loop(0, steps, lambda _, d: mjx.step(m, d), d)
            return _row(d)

        def world(row):
            along = lambda t: jax.jvp(lambda v: episode(row, v), (arrays,), (t,))  # noqa: E731
            end, d_end = jax.vmap(along)(t_arrays)  # (k, 11) each, the end the same k times
            return end[0], d_end.T

        return jax.vmap(world)(rows)

    return jax.jit(run)


def knob_derivative(engine, states: np.ndarray, steps: int, knobs) -> tuple[np.ndarray, np.ndarray]:
    """``BatchedEngine.knob_derivative`` for an MJX engine built with its scene (module
    docstring): the end rows (n, 11) and their derivatives (n, 11, k) by each knob."""
    knobs = [(str(name), None if i is None else int(i)) for name, i in knobs]
    if not knobs:
        raise ValueError("knobs is empty; allowed: one or more (settings field, index) pairs")
    rows_t = [contact_tangents(engine.settings, engine._e, k) for k in knobs]  # may refuse
    states = np.asarray(states, float)
    if np.any(states[:, 11:] != 0.0):
        raise NotImplementedError(
            "MJX's knob derivative here takes impacts in the swing plane only"
        )
    steps = STEP_BUCKET * -(-steps // STEP_BUCKET)
    n = len(states)
    rows = max(KNOB_MIN_ROWS, bucket(n))  # padded with copies of the first world
    states = np.concatenate([states, np.repeat(states[:1], rows - n, axis=0)])
    with engine._scope():
        model = engine.model
        dtype = model.geom_solref.dtype
        t_arrays = tuple(
            jnp.asarray(
                np.stack([np.broadcast_to(t[f], getattr(model, f).shape) for t in rows_t]).astype(
                    float
                ),
                dtype,
            )
            for f in CONTACT_ARRAYS
        )
        m_leaves, model_def = jax.tree_util.tree_flatten(model)
        run = _traced_knobs(model_def, steps)
        data = mjx.make_data(model, impl="jax")
        ends, d_ends = run(m_leaves, data, jnp.asarray(states[:, :11], dtype), t_arrays)
        return np.asarray(ends, float)[:n], np.asarray(d_ends, float)[:n]
