"""``collide``'s end-of-episode tests over many states at once (the engines' batches).

Each function gives, state by state, what its one-state counterpart in ``collide`` gives:
``separates_for_good_many`` the same bool, ``free_flight_many`` the same samples of the gap
(a contact's time is the sample before it: no root is polished). The search evaluates each
round of ``_CHUNK`` samples on many states in two halves, the second only for the states
still in flight after the first: the same samples, at about half the trigonometry where most
flights end early.
"""

from __future__ import annotations

import numpy as np

from .collide import _CHUNK, APEX_M, EPISODE_GAP_RADII, MIN_SAMPLE_FRACTION, _gap


def separates_for_good_many(
    x, *, reach_m: float, ball_radius_m: float, t_max_s: float
) -> np.ndarray:
    """``separates_for_good`` for many states at once: ``x`` holds arrays (ball x, y, vx, vy,
    bat x, y, vx, vy, angle, omega), in PlanarState's order; one bool per state."""
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        return separates_for_good_xp(
            np, x, reach_m=reach_m, ball_radius_m=ball_radius_m, t_max_s=t_max_s
        )


def separates_for_good_xp(xp, x, *, reach_m: float, ball_radius_m: float, t_max_s):
    """``separates_for_good_many`` in any numpy-like module ``xp`` (numpy, ``jax.numpy``:
    the harness's episode on a device), the same operations in the same order."""
    bx, by, bvx, bvy, cx, cy, cvx, cvy, angle, w = x
    c, s = xp.cos(angle), xp.sin(angle)
    dx, dy = bx - cx, by - cy
    rvx, rvy = bvx - cvx, bvy - cvy
    opening = rvy * c - rvx * s - w * (dx * c + dy * s)
    gap = dy * c - dx * s - reach_m
    end = EPISODE_GAP_RADII * ball_radius_m
    horizon = 2.0 * end / opening
    v_rel = xp.hypot(rvx, rvy)
    bound = 2.0 * xp.abs(w) * v_rel + w * w * (xp.hypot(dx, dy) + v_rel * horizon)
    return (
        (opening > 0.0)
        & (gap >= 0.0)
        & (horizon <= t_max_s)
        & (0.5 * bound * horizon * horizon <= end + gap)
    )


#: How ``free_flight_many``'s searches end, by code (Python strings: numpy's are slow to pick).
_ENDS = np.array(["left_cylinder", "separated", "contact", "time_limit"], dtype=object)
_HALF = _CHUNK // 2
#: States below which a round is sampled whole: on fewer, numpy's cost per call outweighs the
#: samples a split saves (measured: pools of 91 paid more split, 976 states less).
SPLIT_MIN = 256


def _sample_steps(Y, t0, h_max):
    """Each state's sample interval from its state at ``t0`` (``collide._sample_step``)."""
    zero = np.zeros((2, Y.shape[1]))
    now = Y + np.concatenate([Y[2:4], zero, Y[6:8], zero, Y[9:10], zero[:1]]) * t0
    rv, c, s = now[2:4] - now[6:8], np.cos(now[8]), np.sin(now[8])
    dx, dy = now[0] - now[4], now[1] - now[5]
    opening = -rv[0] * s + rv[1] * c - now[9] * (dx * c + dy * s)
    curving = -2 * now[9] * (rv[0] * c + rv[1] * s) - now[9] ** 2 * (dy * c - dx * s)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        return np.where(
            (opening > 0.0) & (-curving * h_max > 0.5 * opening),
            np.maximum(0.5 * opening / -curving, MIN_SAMPLE_FRACTION * h_max),
            h_max,
        )


def _samples(Y, t0, h, first: int, count: int, reach_m: float, t_max_s: float):
    """Samples ``first`` .. ``first + count - 1`` of each state's round: times, gaps, axial
    coordinates, each (states, count)."""
    t = np.minimum(t0[:, None] + h[:, None] * np.arange(first, first + count), t_max_s)
    return (t, *_gap(Y[:, :, None], t, reach_m))


def _round(Y, t0, g0, h, ends, reach_m: float, t_max_s: float):
    """One round of ``_CHUNK`` samples per state (times, gaps, axial coordinates), on many
    states in two halves: the second only where the first holds no end (elsewhere zeros,
    never read, for a round ends at its first end)."""
    if len(t0) < SPLIT_MIN:
        return _samples(Y, t0, h, 1, _CHUNK, reach_m, t_max_s)
    t, g, ax = (np.zeros((len(t0), _CHUNK)) for _ in range(3))
    t[:, :_HALF], g[:, :_HALF], ax[:, :_HALF] = _samples(Y, t0, h, 1, _HALF, reach_m, t_max_s)
    prev = np.concatenate((g0[:, None], g[:, : _HALF - 1]), axis=1)
    late = np.flatnonzero(~ends(t[:, :_HALF], g[:, :_HALF], ax[:, :_HALF], prev)[3].any(axis=1))
    t[late, _HALF:], g[late, _HALF:], ax[late, _HALF:] = _samples(
        Y[:, late], t0[late], h[late], _HALF + 1, _HALF, reach_m, t_max_s
    )
    return t, g, ax


def free_flight_many(
    y, *, reach_m: float, ball_radius_m: float, s_min_m: float, s_max_m: float, t_max_s: float
) -> tuple[np.ndarray, np.ndarray]:
    """``free_flight`` for many states at once, ``y`` of shape (10, m) in PlanarState's order,
    sampled as ``_next_contact`` samples one; a contact's time is the sample before it (no
    root is polished). Returns (time, why) arrays."""
    t_out, why = np.full(y.shape[1], t_max_s), np.full(y.shape[1], "time_limit", dtype=object)
    w = np.abs(y[9])
    h_max = np.where(w * 1e-4 > 0.02, 0.02 / np.maximum(w, 1e-300), 1e-4)
    live = np.arange(y.shape[1] if t_max_s > 0.0 else 0)
    t0, g0 = np.zeros(len(live)), _gap(y[:, live], 0.0, reach_m)[0]
    gap_end = EPISODE_GAP_RADII * ball_radius_m

    def ends(t, g, ax, prev):
        off = ~((s_min_m <= ax) & (ax <= s_max_m))
        sep = g > gap_end
        touch = ((prev > 0.0) & (g <= 0.0)) | ((prev <= 0.0) & (g < -APEX_M))
        return off, sep, touch, off | sep | touch | (t >= t_max_s)

    while len(live):
        Y = y[:, live]
        h = _sample_steps(Y, t0, h_max[live])
        t, g, ax = _round(Y, t0, g0, h, ends, reach_m, t_max_s)
        prev = np.concatenate((g0[:, None], g[:, :-1]), axis=1)
        off, sep, touch, end = ends(t, g, ax, prev)
        done, k = end.any(axis=1), end.argmax(axis=1)
        rows, at = live[done], k[done]
        pick = (np.flatnonzero(done), at)
        before = np.where(at > 0, t[pick[0], np.maximum(at - 1, 0)], t0[done])
        kind = np.select([off[pick], sep[pick], touch[pick]], [0, 1, 2], 3)  # _ENDS' order
        t_out[rows] = np.where(kind == 2, before, np.where(kind == 3, t_max_s, t[pick]))
        why[rows] = _ENDS[kind]
        live, t0, g0 = live[~done], t[~done, -1], g[~done, -1]
    return t_out, why
