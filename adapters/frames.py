"""The bat's orientation as the state gives it (yaw about z, tilt out of the swing plane) and
as engines hold it (a unit quaternion w, x, y, z), both ways; imports no engine.

The axis points along (cos a cos b, sin a cos b, sin b): the rotation by a about z after the
rotation by -b about y, q = q_z(a) q_y(-b), roll about the axis 0 (``adapters.interface``).
A rotation about z alone keeps x = y = 0 exactly, and is read back with 2 atan2(z, w), as the
planar adapters always did: a planar state goes through both ways bit for bit.
"""

from __future__ import annotations

import math


def bat_quaternion(angle_rad: float, tilt_rad: float = 0.0) -> tuple[float, float, float, float]:
    """(w, x, y, z) of the bat turned by ``angle_rad`` about z and tilted ``tilt_rad`` up."""
    ca, sa = math.cos(0.5 * angle_rad), math.sin(0.5 * angle_rad)
    if tilt_rad == 0.0:
        return ca, 0.0, 0.0, sa
    cb, sb = math.cos(0.5 * tilt_rad), math.sin(0.5 * tilt_rad)
    return ca * cb, sa * sb, -ca * sb, sa * cb


def angle_and_tilt(w: float, x: float, y: float, z: float) -> tuple[float, float]:
    """The bat's yaw and tilt (rad) from its orientation quaternion (any roll about its axis)."""
    if x == 0.0 and y == 0.0:
        return 2.0 * math.atan2(z, w), 0.0
    ax = 1.0 - 2.0 * (y * y + z * z)   # the body x axis in the world: R e_x
    ay = 2.0 * (x * y + w * z)
    az = 2.0 * (x * z - w * y)
    return math.atan2(ay, ax), math.atan2(az, math.hypot(ax, ay))



def rotate(q: tuple[float, float, float, float], v: tuple[float, float, float],
           inverse: bool = False) -> tuple[float, float, float]:
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
    return (v[0] + 2.0 * (w * cx + y * cz - z * cy),
            v[1] + 2.0 * (w * cy + z * cx - x * cz),
            v[2] + 2.0 * (w * cz + x * cy - y * cx))
