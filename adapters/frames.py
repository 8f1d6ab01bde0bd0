"""The bat's orientation as the state gives it (yaw about z, tilt out of the swing plane) and
as engines hold it (a unit quaternion w, x, y, z), both ways; imports no engine.

The axis points along (cos a cos b, sin a cos b, sin b): the rotation by a about z after the
rotation by -b about y, q = q_z(a) q_y(-b), roll about the axis 0 (``adapters.interface``).
A rotation about z alone keeps x = y = 0 exactly, and is read back with 2 atan2(z, w), as the
planar adapters always did: a planar state goes through both ways bit for bit.
"""

from __future__ import annotations

import math

import numpy as np


def bat_quaternion(angle_rad: float, tilt_rad: float = 0.0) -> tuple[float, float, float, float]:
    """(w, x, y, z) of the bat turned by ``angle_rad`` about z and tilted ``tilt_rad`` up."""
    ca, sa = math.cos(0.5 * angle_rad), math.sin(0.5 * angle_rad)
    if tilt_rad == 0.0:
        return ca, 0.0, 0.0, sa
    cb, sb = math.cos(0.5 * tilt_rad), math.sin(0.5 * tilt_rad)
    return ca * cb, sa * sb, -ca * sb, sa * cb


def angle_and_tilt(
    w: float, x: float, y: float, z: float, planar: bool = False
) -> tuple[float, float]:
    """The bat's yaw and tilt (rad) from its orientation quaternion (any roll about its axis).
    ``planar``: the world was set in the swing plane, so its yaw is read as the planar
    adapters always read it, 2 atan2(z, w), whatever rounding put into x and y (the tilt
    still reports that drift)."""
    if x == 0.0 and y == 0.0:
        return 2.0 * math.atan2(z, w), 0.0
    ax = 1.0 - 2.0 * (y * y + z * z)  # the body x axis in the world: R e_x
    ay = 2.0 * (x * y + w * z)
    az = 2.0 * (x * z - w * y)
    yaw = 2.0 * math.atan2(z, w) if planar else math.atan2(ay, ax)
    return yaw, math.atan2(az, math.hypot(ax, ay))


def in_the_plane(state) -> bool:
    """Whether a ``State`` lies in the swing plane (every out-of-plane field 0)."""
    return not any(state[11:])


def rotate(
    q: tuple[float, float, float, float], v: tuple[float, float, float], inverse: bool = False
) -> tuple[float, float, float]:
    """v turned by the rotation of the unit quaternion q = (w, x, y, z) (its inverse if asked):
    an angular velocity from a body's frame to the world's, or back. A rotation about z leaves
    a vector along z as it is (returned unchanged: planar states stay bit for bit)."""
    w, x, y, z = q
    if x == 0.0 and y == 0.0 and v[0] == 0.0 and v[1] == 0.0:
        return tuple(v)
    if inverse:
        x, y, z = -x, -y, -z
    # v + 2 w (u x v) + 2 u x (u x v), u = (x, y, z)
    cx, cy, cz = y * v[2] - z * v[1], z * v[0] - x * v[2], x * v[1] - y * v[0]
    return (
        v[0] + 2.0 * (w * cx + y * cz - z * cy),
        v[1] + 2.0 * (w * cy + z * cx - x * cz),
        v[2] + 2.0 * (w * cz + x * cy - y * cx),
    )


# -- over batches (the batched MuJoCo ports and Newton) -----------------------------------------
# The same over batches: the bat's quaternion from its yaw and tilt, a rotation of
# angular velocities between body and world frames, and MuJoCo's free-joint coordinates turned
# into state rows; numpy only, no engine (the batched MuJoCo ports and Newton share it).
#
# A world set in the swing plane (its out-of-plane columns all 0) is read as the planar adapters
# always read it, bit for bit: the bat's yaw 2 atan2(z, w) and the spins about z as the engine
# holds them. Float32 engines leave the plane by rounding in a planar impact (measured on a
# 40 m/s impact at 10 us: the bat's spin about x reaches 8e-5 rad/s in MuJoCo Warp, 1.5e-4 in
# Newton, the ball's vz 3e-6 and 6e-6 m/s; MuJoCo Warp's bat quaternion x, y ~ 1e-7 at 2 ms),
# and the 3-D formulas read such a state with other rounding than the planar ones (read with
# them, the frictionless 41-point sweeps' peak penetration and ball side moved by 2e-10 to
# 6e-8 m in MuJoCo Warp and Newton). The out-of-plane columns report that drift as the engine
# has it. Other worlds get the 3-D formulas, which reduce to the planar ones (up to rounding)
# for a rotation about z alone.

#: MuJoCo's free joints, bat first: qpos (x, y, z, qw, qx, qy, qz) per body, qvel (v, omega)
#: with omega in the BODY frame.
BAT_Q, BALL_Q = slice(3, 7), slice(10, 14)
BAT_W, BALL_W = slice(3, 6), slice(9, 12)


def bat_quaternions(angle_rad: np.ndarray, tilt_rad: np.ndarray) -> np.ndarray:
    """(n, 4) quaternions (w, x, y, z) of ``adapters.frames.bat_quaternion``, row by row."""
    half = 0.5 * angle_rad
    ca, sa = np.cos(half), np.sin(half)
    cb, sb = np.cos(0.5 * tilt_rad), np.sin(0.5 * tilt_rad)
    flat = tilt_rad == 0.0
    zero = np.zeros_like(ca)
    return np.stack(
        [
            np.where(flat, ca, ca * cb),
            np.where(flat, zero, sa * sb),
            np.where(flat, zero, -ca * sb),
            np.where(flat, sa, sa * cb),
        ],
        axis=1,
    )


def rotate_many(q, v, inverse: bool = False, xp=np):
    """(n, 3) vectors v turned by the unit quaternions q (n, 4: w, x, y, z), or by their
    inverses; rows turned about z alone with v along z come back unchanged. ``xp``: the
    arrays' numpy-like module (``jax.numpy`` on an engine's device)."""
    w, x, y, z = (q[:, i] for i in range(4))
    if inverse:
        x, y, z = -x, -y, -z
    cx, cy, cz = y * v[:, 2] - z * v[:, 1], z * v[:, 0] - x * v[:, 2], x * v[:, 1] - y * v[:, 0]
    out = xp.stack(
        [
            v[:, 0] + 2.0 * (w * cx + y * cz - z * cy),
            v[:, 1] + 2.0 * (w * cy + z * cx - x * cz),
            v[:, 2] + 2.0 * (w * cz + x * cy - y * cx),
        ],
        axis=1,
    )
    keep = (q[:, 1] == 0.0) & (q[:, 2] == 0.0) & (v[:, 0] == 0.0) & (v[:, 1] == 0.0)
    return xp.where(keep[:, None], v, out)


def angles_and_tilts(q, xp=np):
    """The bat's yaw and tilt (rad) from its quaternions (n, 4: w, x, y, z), any roll about
    its axis: the axis R e_x in its homogeneous form (w^2 + x^2 - y^2 - z^2, 2 (xy + wz),
    2 (xz - wy)), blind to a float32 quaternion's norm error."""
    w, x, y, z = (q[:, i] for i in range(4))
    ax, ay, az = w * w + x * x - y * y - z * z, 2.0 * (x * y + w * z), 2.0 * (x * z - w * y)
    return xp.arctan2(ay, ax), xp.arctan2(az, xp.hypot(ax, ay))


def in_plane(states: np.ndarray) -> np.ndarray:
    """Per row of states (n, 20), whether every column out of the swing plane is 0."""
    return ~np.any(states[:, 11:] != 0.0, axis=1)


def mujoco_coordinates(s: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """MuJoCo's qpos (n, 14) and qvel (n, 12) of the bat and the ball from state rows (n, 20):
    the bat's angular velocity turned into its own frame, the ball unturned (its body frame
    is the world's)."""
    q = bat_quaternions(s[:, 7], s[:, 16])
    zero, one = np.zeros(len(s)), np.ones(len(s))
    w = rotate_many(q, s[:, [18, 19, 10]], inverse=True)
    qpos = np.stack(
        [s[:, 5], s[:, 6], s[:, 15], *q.T, s[:, 0], s[:, 1], s[:, 11], one, zero, zero, zero],
        axis=1,
    )
    qvel = np.stack(
        [s[:, 8], s[:, 9], s[:, 17], *w.T, s[:, 2], s[:, 3], s[:, 12], s[:, 13], s[:, 14], s[:, 4]],
        axis=1,
    )
    return qpos, qvel


def mujoco_rows(
    qpos: np.ndarray, qvel: np.ndarray, planar: np.ndarray, angle_rad: np.ndarray | None = None
) -> np.ndarray:
    """State rows (n, 20) from MuJoCo's qpos and qvel (float64 copies of the engine's), body-
    frame angular velocities turned into the world's; the rows ``planar`` (set in the plane)
    read as before (module docstring), their yaw ``angle_rad`` where the engine computed it
    itself (MJX, in its own precision), else 2 atan2(qz, qw) here."""
    # stacked as 20 rows of n, handed over transposed: its columns contiguous (no copy in the
    # harness, which reads a batch by columns)
    return np.stack(mujoco_columns(np, qpos, qvel, planar, angle_rad)).T


def mujoco_columns(xp, qpos, qvel, planar, angle_rad=None) -> list:
    """``mujoco_rows``' 20 columns (arrays of n) in the numpy-like module ``xp``: the same
    operations on the engine's own device (MJX's episode there, ``adapters.device``)."""
    q, v = qpos, qvel
    bat_w = rotate_many(q[:, BAT_Q], v[:, BAT_W], xp=xp)
    ball_w = rotate_many(q[:, BALL_Q], v[:, BALL_W], xp=xp)
    yaw, tilt = angles_and_tilts(q[:, BAT_Q], xp=xp)
    flat_yaw = 2.0 * xp.arctan2(q[:, 6], q[:, 3]) if angle_rad is None else angle_rad
    yaw = xp.where(planar, flat_yaw, yaw)
    ball_wz, bat_wz = (
        xp.where(planar, v[:, 11], ball_w[:, 2]),
        xp.where(planar, v[:, 5], bat_w[:, 2]),
    )
    return [
        q[:, 7],
        q[:, 8],
        v[:, 6],
        v[:, 7],
        ball_wz,
        q[:, 0],
        q[:, 1],
        yaw,
        v[:, 0],
        v[:, 1],
        bat_wz,
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
