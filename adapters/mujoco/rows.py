"""State rows to MuJoCo's physics rows and back, over many worlds, bit for bit as the one-world
adapter converts one (``MujocoEngine.set_state`` and ``read``): the worlds pool's conversions
(``worlds``). Imports no engine.

A physics row is what ``mj_getState(mjSTATE_FULLPHYSICS)`` gives for the scene: the time, qpos
(bat then ball: position and quaternion) and qvel (bat then ball: velocity and the angular
velocity in the body's frame). The arithmetic is numpy's in the one-world adapter's order (each
operation rounded alike); the transcendental functions are ``math``'s, called row by row, since
numpy's own (SIMD) ``arctan2``, ``cos`` or ``hypot`` may round otherwise than the C library's.
"""

from __future__ import annotations

import math

import numpy as np

from ..frames import rotate_many

#: Columns of a physics row: the time, qpos (14), qvel (12).
TIME, QPOS, QVEL = 0, slice(1, 15), slice(15, 27)
WIDTH = 27


def _each(fn, *columns: np.ndarray) -> np.ndarray:
    """``fn`` (a ``math`` function) over the rows of its argument columns."""
    n = len(columns[0])
    return np.fromiter(map(fn, *(c.tolist() for c in columns)), float, n)


def _turned(q: np.ndarray, v: np.ndarray, inverse: bool = False) -> np.ndarray:
    """``frames.rotate_many``, whose rows turned about z alone with v along z come back
    unchanged: where every row is one (a batch in the swing plane) that is a copy, its
    arithmetic skipped (a third of the pool's conversions at 1e3 worlds)."""
    if not (np.any(q[:, 1:3]) or np.any(v[:, 0:2])):  # (-0.0 counts as 0, as there)
        return v.copy()
    return rotate_many(q, v, inverse=inverse)


def physics_rows(states: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Physics rows (n, 27) at time 0 from state rows (n, 20, or the 11 planar columns) as
    ``MujocoEngine.set_state`` puts one world, and whether each was set in the swing plane
    (``frames.in_the_plane``: read back as set)."""
    s = np.asarray(states, dtype=float)
    if s.shape[1] < 20:
        s = np.hstack([s, np.zeros((len(s), 20 - s.shape[1]))])
    n = len(s)
    planar = ~np.any(s[:, 11:] != 0.0, axis=1)
    half = 0.5 * s[:, 7]
    ca, sa = _each(math.cos, half), _each(math.sin, half)
    q = np.zeros((n, 4))
    q[:, 0], q[:, 3] = ca, sa
    tilted = s[:, 16] != 0.0
    if tilted.any():  # frames.bat_quaternion: q_z(a) q_y(-b)
        hb = 0.5 * s[tilted, 16]
        cb, sb = _each(math.cos, hb), _each(math.sin, hb)
        ct, st = ca[tilted], sa[tilted]
        q[tilted] = np.stack([ct * cb, st * sb, -ct * sb, st * cb], axis=1)
    w = _turned(q, s[:, [18, 19, 10]], inverse=True)  # the bat's spin in its own frame
    rows = np.empty((n, WIDTH))
    rows[:, TIME] = 0.0
    rows[:, 1:4] = s[:, [5, 6, 15]]
    rows[:, 4:8] = q
    rows[:, 8:11] = s[:, [0, 1, 11]]
    rows[:, 11:15] = (1.0, 0.0, 0.0, 0.0)
    rows[:, 15:18] = s[:, [8, 9, 17]]
    rows[:, 18:21] = w
    rows[:, 21:24] = s[:, [2, 3, 12]]
    rows[:, 24:27] = s[:, [13, 14, 4]]
    return rows, planar


def state_rows(rows: np.ndarray, planar: np.ndarray) -> np.ndarray:
    """State rows (n, 20, each column contiguous) from physics rows, as ``MujocoEngine.read``
    reads one world (``frames.rotate``, ``frames.angle_and_tilt``)."""
    q, v = rows[:, QPOS], rows[:, QVEL]
    n = len(rows)
    # both bodies' spins turned in one call (row by row, the same arithmetic: half the calls)
    both_w = _turned(np.vstack([q[:, 3:7], q[:, 10:14]]), np.vstack([v[:, 3:6], v[:, 9:12]]))
    bat_w, ball_w = both_w[:n], both_w[n:]
    w, x, y, z = q[:, 3], q[:, 4], q[:, 5], q[:, 6]
    yaw = 2.0 * _each(math.atan2, z, w)
    tilt = np.zeros(n)
    off = (x != 0.0) | (y != 0.0)  # out of the plane, or drifted off it by rounding
    if off.any():
        wo, xo, yo, zo = w[off], x[off], y[off], z[off]
        ax = 1.0 - 2.0 * (yo * yo + zo * zo)
        ay = 2.0 * (xo * yo + wo * zo)
        az = 2.0 * (xo * zo - wo * yo)
        set_off = ~planar[off]  # (a world set in the plane keeps the yaw above)
        if set_off.any():
            yaw[np.flatnonzero(off)[set_off]] = _each(math.atan2, ay[set_off], ax[set_off])
        tilt[off] = _each(math.atan2, az, _each(math.hypot, ax, ay))
    return np.stack(
        [
            q[:, 7],
            q[:, 8],
            v[:, 6],
            v[:, 7],
            ball_w[:, 2],
            q[:, 0],
            q[:, 1],
            yaw,
            v[:, 0],
            v[:, 1],
            bat_w[:, 2],
            q[:, 9],
            v[:, 8],
            ball_w[:, 0],
            ball_w[:, 1],
            q[:, 2],
            tilt,
            v[:, 2],
            bat_w[:, 0],
            bat_w[:, 1],
        ]
    ).T
