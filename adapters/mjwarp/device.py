"""MuJoCo Warp's worlds observed on their device (``adapters.device``): its qpos and qvel turned
into the harness's state columns and its contact list into per-world flags, in kernels that
feed ``adapters.warp_episode``."""

from __future__ import annotations

import warp as wp

from ..device import EpisodeConstants
from ..warp_episode import WarpEpisode

F = wp.float64


@wp.func
def _turned(q: wp.vec4d, v: wp.vec3d) -> wp.vec3d:
    """``frames.rotate_many`` for one row: v turned by the unit quaternion q (w, x, y, z)."""
    w, x, y, z = q[0], q[1], q[2], q[3]
    if x == F(0.0) and y == F(0.0) and v[0] == F(0.0) and v[1] == F(0.0):
        return v
    cx, cy, cz = y * v[2] - z * v[1], z * v[0] - x * v[2], x * v[1] - y * v[0]
    return wp.vec3d(
        v[0] + F(2.0) * (w * cx + y * cz - z * cy),
        v[1] + F(2.0) * (w * cy + z * cx - x * cz),
        v[2] + F(2.0) * (w * cz + x * cy - y * cx),
    )


@wp.kernel
def _columns(
    qpos: wp.array2d(dtype=wp.float32),
    qvel: wp.array2d(dtype=wp.float32),
    planar: wp.array(dtype=wp.int32),
    S: wp.array2d(dtype=F),
):
    """``frames.mujoco_rows`` for world i, in float64 from the engine's float32."""
    i = wp.tid()
    q = wp.vector(length=14, dtype=F)
    v = wp.vector(length=12, dtype=F)
    for j in range(14):
        q[j] = F(qpos[i, j])
    for j in range(12):
        v[j] = F(qvel[i, j])
    bat_q = wp.vec4d(q[3], q[4], q[5], q[6])
    bat_w = _turned(bat_q, wp.vec3d(v[3], v[4], v[5]))
    ball_w = _turned(wp.vec4d(q[10], q[11], q[12], q[13]), wp.vec3d(v[9], v[10], v[11]))
    w, x, y, z = q[3], q[4], q[5], q[6]
    ax, ay, az = w * w + x * x - y * y - z * z, F(2.0) * (x * y + w * z), F(2.0) * (x * z - w * y)
    yaw, tilt = wp.atan2(ay, ax), wp.atan2(az, wp.sqrt(ax * ax + ay * ay))
    ball_wz, bat_wz = ball_w[2], bat_w[2]
    if planar[i] != 0:
        yaw, ball_wz, bat_wz = F(2.0) * wp.atan2(q[6], q[3]), v[11], v[5]
    S[0, i] = q[7]
    S[1, i] = q[8]
    S[2, i] = v[6]
    S[3, i] = v[7]
    S[4, i] = ball_wz
    S[5, i] = q[0]
    S[6, i] = q[1]
    S[7, i] = yaw
    S[8, i] = v[0]
    S[9, i] = v[1]
    S[10, i] = bat_wz
    S[11, i] = q[9]
    S[12, i] = v[8]
    S[13, i] = ball_w[0]
    S[14, i] = ball_w[1]
    S[15, i] = q[2]
    S[16, i] = tilt
    S[17, i] = v[2]
    S[18, i] = bat_w[0]
    S[19, i] = bat_w[1]


@wp.kernel
def _touching(
    nacon: wp.array(dtype=wp.int32),
    worldid: wp.array(dtype=wp.int32),
    dist: wp.array(dtype=wp.float32),
    touching: wp.array(dtype=wp.int32),
):
    """``MjwarpEngine.in_contact``: a listed contact of the world, overlapping."""
    k = wp.tid()
    if k < nacon[0] and dist[k] < wp.float32(0.0):
        touching[worldid[k]] = 1


def episode(engine, k: EpisodeConstants) -> WarpEpisode:
    """The engine's worlds' episode observed in Warp kernels on its device."""
    d, device = engine.data, engine._dev
    with wp.ScopedDevice(device):
        planar = wp.array(engine._planar.astype("int32"), dtype=wp.int32)

    def fill(S: wp.array, touching: wp.array) -> None:
        wp.launch(_columns, dim=engine.n, inputs=[d.qpos, d.qvel, planar, S], device=device)
        touching.zero_()
        c = d.contact
        wp.launch(
            _touching,
            dim=d.naconmax,
            inputs=[d.nacon, c.worldid, c.dist, touching],
            device=device,
        )

    return WarpEpisode(k, engine.n, device, fill)
