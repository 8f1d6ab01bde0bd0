"""Free flight of the ball and the bat out of the swing plane: when (if) they meet again.

After an undercut or spinning impact the ball leaves the swing plane and the bat turns about a
tilted axis, so the planar gap of ``analytic.collide`` no longer applies. In free flight (no
gravity, no hands) each body moves in closed form: the ball's centre p + v t, the bat's COM
P + V t, and its axis a(t) = a turned by |w| t about w (Rodrigues' formula: the bat is
axisymmetric about its axis, so its angular velocity is not constant in general, but its axis
precesses about the constant angular momentum; over an episode's milliseconds |w| t of the
out-of-plane part stays below 1e-2 rad, and turning a about w itself is what the engines'
first-order steps do too). The gap is the distance from the ball's centre to the nearest point
of the axis segment [s_min, s_max] (from the COM) less the reach r_bat + r_ball.

``free_flight_3d`` samples that gap as ``collide.free_flight`` samples the planar one, every
h = SAMPLE_REACH_FRACTION of the reach over the relative speed (and at most 0.02 rad of the
bat's turn), and ends where the planar search ends: 'contact' (the gap closes, or a gap lost
in float noise sinks below -APEX_M: the time of the sample before it), 'separated' (grown
past EPISODE_GAP_RADII ball radii), 'left_cylinder' (the ball's foot off the span) or
'time_limit'. A contact that closes and opens again within one
sample (a graze shallower than the relative speed times h, 1e-3 of the reach) is missed.
"""

from __future__ import annotations

import math

import numpy as np

from .collide import APEX_M, EPISODE_GAP_RADII

#: The relative motion between two samples of the gap, as a fraction of the reach.
SAMPLE_REACH_FRACTION = 1e-3
#: The bat turns at most this much between two samples (rad).
SAMPLE_TURN_RAD = 0.02
#: Samples evaluated at once.
CHUNK = 256


def turned(axis: np.ndarray, omega: np.ndarray, t: np.ndarray) -> np.ndarray:
    """The unit ``axis`` turned about ``omega`` for each time in ``t`` (Rodrigues): shape
    (len(t), 3)."""
    w = float(np.linalg.norm(omega))
    if w == 0.0:
        return np.broadcast_to(axis, (len(t), 3))
    k = omega / w
    angle = w * np.asarray(t)[:, None]
    return (
        axis * np.cos(angle)
        + np.cross(k, axis) * np.sin(angle)
        + k * float(k @ axis) * (1.0 - np.cos(angle))
    )


def gap_3d(
    rel: np.ndarray, axis: np.ndarray, *, reach_m: float, s_min_m: float, s_max_m: float
) -> tuple[np.ndarray, np.ndarray]:
    """Gap (m) of the ball centre at ``rel`` (from the bat's COM, rows) to the axis segment,
    and its coordinate along the axis (m), for rows of positions and axes."""
    along = np.einsum("ij,ij->i", rel, axis)
    foot = np.clip(along, s_min_m, s_max_m)
    return np.linalg.norm(rel - foot[:, None] * axis, axis=1) - reach_m, along


def free_flight_3d(
    rel_m,
    rel_v_mps,
    axis,
    omega_radps,
    *,
    reach_m: float,
    ball_radius_m: float,
    s_min_m: float,
    s_max_m: float,
    t_max_s: float,
) -> tuple[float, str]:
    """Where free flight leads from the ball centre at ``rel_m`` from the bat's COM, moving at
    ``rel_v_mps`` relative to it, the bat's axis ``axis`` (unit) turning at ``omega_radps``:
    (time, why) as the module docstring says. 3-vectors, world frame."""
    rel, rv = np.asarray(rel_m, float), np.asarray(rel_v_mps, float)
    a0, w = np.asarray(axis, float), np.asarray(omega_radps, float)
    speed = float(np.linalg.norm(rv)) + float(np.linalg.norm(w)) * max(abs(s_min_m), abs(s_max_m))
    h = SAMPLE_REACH_FRACTION * reach_m / max(speed, 1e-300)
    h = min(h, SAMPLE_TURN_RAD / max(float(np.linalg.norm(w)), 1e-300))
    t0 = 0.0
    g0 = float(gap_3d(rel[None], a0[None], reach_m=reach_m, s_min_m=s_min_m, s_max_m=s_max_m)[0][0])
    while t0 < t_max_s:
        t = np.minimum(t0 + h * np.arange(1, CHUNK + 1), t_max_s)
        g, along = gap_3d(
            rel + rv * t[:, None],
            turned(a0, w, t),
            reach_m=reach_m,
            s_min_m=s_min_m,
            s_max_m=s_max_m,
        )
        prev = np.concatenate(([g0], g[:-1]))
        off = (along < s_min_m) | (along > s_max_m)
        sep = g > EPISODE_GAP_RADII * ball_radius_m
        hit = ((prev > 0.0) & (g <= 0.0)) | ((prev <= 0.0) & (g < -APEX_M))
        end = off | sep | hit | (t >= t_max_s)
        if end.any():
            k = int(np.argmax(end))
            if off[k]:
                return float(t[k]), "left_cylinder"
            if sep[k]:
                return float(t[k]), "separated"
            if hit[k]:
                return (t0 if k == 0 else float(t[k - 1])), "contact"
            return t_max_s, "time_limit"
        t0, g0 = float(t[-1]), float(g[-1])
    return t_max_s, "time_limit"


def axis_of(angle_rad: float, tilt_rad: float) -> np.ndarray:
    """The unit vector along a bat at yaw ``angle_rad`` about z, tilted ``tilt_rad`` up."""
    cb = math.cos(tilt_rad)
    return np.array([math.cos(angle_rad) * cb, math.sin(angle_rad) * cb, math.sin(tilt_rad)])
