"""Newton's worlds observed on their device (``adapters.device``): its bodies' poses and twists
turned into the harness's state columns, and its contacts and the ball's velocity into the
per-world contact flags ``NewtonEngine.step`` computes on the host, in kernels that feed
``adapters.warp_episode``. World i holds bodies 2i (bat) and 2i + 1 (ball)."""

from __future__ import annotations

import numpy as np

from ..device import EpisodeConstants
from ..warp_episode import WarpEpisode
from .scene import wp

F = wp.float64


@wp.kernel
def _columns(
    body_q: wp.array(dtype=wp.transformf),
    body_qd: wp.array(dtype=wp.spatial_vectorf),
    planar: wp.array(dtype=wp.int32),
    S: wp.array2d(dtype=F),
):
    """``NewtonEngine.read`` for world i, in float64 from the engine's float32."""
    i = wp.tid()
    bat, ball = body_q[2 * i], body_q[2 * i + 1]
    pb, pc = wp.transform_get_translation(ball), wp.transform_get_translation(bat)
    rc = wp.transform_get_rotation(bat)  # (x, y, z, w)
    vb, vc = body_qd[2 * i + 1], body_qd[2 * i]
    x, y, z, w = F(rc[0]), F(rc[1]), F(rc[2]), F(rc[3])
    ax, ay, az = w * w + x * x - y * y - z * z, F(2.0) * (x * y + w * z), F(2.0) * (x * z - w * y)
    yaw = wp.atan2(ay, ax)
    if planar[i] != 0:
        yaw = F(2.0) * wp.atan2(z, w)
    S[0, i] = F(pb[0])
    S[1, i] = F(pb[1])
    S[2, i] = F(vb[0])
    S[3, i] = F(vb[1])
    S[4, i] = F(vb[5])
    S[5, i] = F(pc[0])
    S[6, i] = F(pc[1])
    S[7, i] = yaw
    S[8, i] = F(vc[0])
    S[9, i] = F(vc[1])
    S[10, i] = F(vc[5])
    S[11, i] = F(pb[2])
    S[12, i] = F(vb[2])
    S[13, i] = F(vb[3])
    S[14, i] = F(vb[4])
    S[15, i] = F(pc[2])
    S[16, i] = wp.atan2(az, wp.sqrt(ax * ax + ay * ay))
    S[17, i] = F(vc[2])
    S[18, i] = F(vc[3])
    S[19, i] = F(vc[4])


@wp.kernel
def _listed_pipeline(
    count: wp.array(dtype=wp.int32),
    shape0: wp.array(dtype=wp.int32),
    shape_world: wp.array(dtype=wp.int32),
    listed: wp.array(dtype=wp.int32),
):
    """``NewtonEngine._listed`` on Newton's collision pipeline's contacts."""
    k = wp.tid()
    if k < count[0] and shape0[k] >= 0:
        listed[shape_world[shape0[k]]] = 1


@wp.kernel
def _listed_mujoco(
    count: wp.array(dtype=wp.int32),
    dist: wp.array(dtype=wp.float32),
    margin: wp.array(dtype=wp.float32),
    worldid: wp.array(dtype=wp.int32),
    listed: wp.array(dtype=wp.int32),
):
    """``NewtonEngine._listed`` on the MuJoCo solver's contacts (closer than its margin)."""
    k = wp.tid()
    if k < count[0] and dist[k] < margin[k]:
        listed[worldid[k]] = 1


@wp.kernel
def _touching(
    body_qd: wp.array(dtype=wp.spatial_vectorf),
    planar: wp.array(dtype=wp.int32),
    ball_v: wp.array(dtype=wp.vec3f),
    touching: wp.array(dtype=wp.int32),
):
    """``NewtonEngine.step``'s flag: listed, and the ball's velocity changed in the step
    (``touching`` holds the listing on entry)."""
    i = wp.tid()
    qd = body_qd[2 * i + 1]
    v = wp.vec3f(qd[0], qd[1], qd[2])
    moved = v[0] != ball_v[i][0] or v[1] != ball_v[i][1]
    if planar[i] == 0 and v[2] != ball_v[i][2]:
        moved = True
    if not moved:
        touching[i] = 0
    ball_v[i] = v


def episode(engine, k: EpisodeConstants, device: str) -> WarpEpisode:
    """The engine's worlds' episode observed in Warp kernels on ``device`` (from its last
    ``set_state``: its ball velocities)."""
    n = engine.n
    with wp.ScopedDevice(device):
        planar = wp.array(engine.planar.astype(np.int32), dtype=wp.int32)
        ball_v = wp.array(engine.ball_v.astype(np.float32), dtype=wp.vec3f)

    def fill(S: wp.array, touching: wp.array) -> None:
        state = engine.states[0]
        wp.launch(_columns, dim=n, inputs=[state.body_q, state.body_qd, planar, S], device=device)
        touching.zero_()
        if engine.contacts is None:
            c, d = engine.solver.mjw_data.contact, engine.solver.mjw_data
            inputs = [d.nacon, c.dist, c.includemargin, c.worldid, touching]
            wp.launch(_listed_mujoco, dim=c.dist.shape[0], inputs=inputs, device=device)
        else:
            c = engine.contacts
            inputs = [
                c.rigid_contact_count,
                c.rigid_contact_shape0,
                engine.shape_world_on,
                touching,
            ]
            dim = c.rigid_contact_shape0.shape[0]
            wp.launch(_listed_pipeline, dim=dim, inputs=inputs, device=device)
        wp.launch(_touching, dim=n, inputs=[state.body_qd, planar, ball_v, touching], device=device)

    return WarpEpisode(k, n, device, fill)
