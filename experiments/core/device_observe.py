"""The episode's per-step observation as pure array functions, written once against a
numpy-like module: compiled by JAX where an engine's worlds live (``device_episode``), and run
by numpy in the test that holds it to the reference stepper (``episode._Stepper``).

The rules are ``episode``'s, line for line, without its branches: each world's record of its
episode (the carry: a dict of arrays, one value per world; ``prev`` and ``end`` (20, rows)
columns) goes in and comes out; nothing is skipped where nothing would change, so a compiler
sees one straight function. What cannot run there, the rare free-flight search of a world
that left the bat but may meet it again, is flagged (``search``) for the host, and its answer
comes back through ``resolve``. Endings are the integer codes of ``endings.Ending``.
"""

from __future__ import annotations

import functools
import math
from types import SimpleNamespace

import numpy as np

from adapters.device import EpisodeConstants
from analytic.batch_ends import separates_for_good_xp

from . import geometry as g


@functools.lru_cache(maxsize=8)
def namespace(mod) -> SimpleNamespace:
    """The functions the observation (and ``geometry``'s measures) call, from a numpy-like
    module (numpy, ``jax.numpy``)."""
    return SimpleNamespace(
        **{f: getattr(mod, f) for f in ("cos", "sin", "hypot", "sqrt", "clip", "where")},
        **{f: getattr(mod, f) for f in ("maximum", "floor", "abs", "any", "all", "isfinite")},
        not_=mod.logical_not,
        asarray=mod.asarray,
    )


def _bodies(k: EpisodeConstants) -> tuple[SimpleNamespace, SimpleNamespace]:
    """The bat and ball as ``geometry``'s measures read them."""
    bat = SimpleNamespace(radius_m=k.bat_radius_m, s_min_m=k.s_min_m, s_max_m=k.s_max_m)
    return bat, SimpleNamespace(radius_m=k.ball_radius_m)


def start(k: EpisodeConstants, starts: np.ndarray, came_from, ball_v0, n: int) -> dict:
    """The carry before the first step, in numpy (the device puts it there): ``starts`` (rows,
    20), ``came_from`` (rows,), ``ball_v0`` (rows, 3); worlds past ``n`` (padding) are over."""
    rows = len(starts)
    cols = np.ascontiguousarray(starts.T)
    return {
        "ended": np.zeros(rows, dtype=np.int32),
        "steps": np.full(rows, k.max_steps, dtype=np.int32),
        "first": np.full(rows, -1, dtype=np.int32),
        "last": np.full(rows, -1, dtype=np.int32),
        "peak": np.full(rows, -math.inf),
        "off": np.zeros(rows, dtype=np.int32),
        "active": np.arange(rows) < n,
        "prev": cols,
        "prev_step": np.zeros(rows, dtype=np.int32),
        "check_at": np.zeros(rows, dtype=np.int32),
        "side_m": np.full(rows, math.nan),
        "end": cols.copy(),
        "search": np.zeros(rows, dtype=bool),
        "side_now": np.zeros(rows),
        "came_from": np.asarray(came_from, dtype=float),
        "vx0": ball_v0[:, 0],
        "vy0": ball_v0[:, 1],
        "limit2": ball_v0[:, 2],
    }


def _finish(xp, k: EpisodeConstants, c: dict, mask, why: str, step, S, side=None) -> None:
    """``episode._Stepper.finish`` on the carry (in place: the caller's own copy)."""
    m = mask & c["active"]
    c["ended"] = xp.where(m, k.code(why), c["ended"])
    c["steps"] = xp.where(m, step, c["steps"])
    c["end"] = xp.where(m, S, c["end"])
    if side is not None:
        c["side_m"] = xp.where(m, side, c["side_m"])
    c["active"] = c["active"] & xp.not_(m)
    if why in ("non_finite", "jumped"):
        c["peak"] = xp.where(m, math.nan, c["peak"])


def observe(xp, k: EpisodeConstants, c: dict, step, touching, S) -> tuple[dict, object]:
    """One step's look (``episode._Stepper.over`` and ``observe``): the new carry, and
    (any world still going, any due a search) as two booleans in one array. Before the
    planned contact, with no contact anywhere yet, nothing is read (as there)."""
    skip = (step < k.approach_steps) & xp.not_(xp.any(c["first"] >= 0)) & xp.not_(xp.any(touching))
    new = _look(xp, k, dict(c), step, touching, S)
    out = {key: xp.where(skip, c[key], new[key]) for key in c}
    return out, xp.asarray([xp.any(out["active"]), xp.any(out["search"])])


def _look(xp, k: EpisodeConstants, c: dict, step, touching, S) -> dict:
    """``episode._Stepper.observe`` on the carry, the free-flight search left flagged."""
    no = xp.not_
    look = c["active"] & (touching | (c["first"] >= 0) | (step >= k.approach_steps))
    finite = xp.all(xp.isfinite(S), axis=0)
    _finish(xp, k, c, look & no(finite), "non_finite", step, S)
    jumped_fn = g.jumped_3d if k.spatial else g.jumped
    jumped = jumped_fn(xp, c["prev"], S, (step - c["prev_step"]) * k.dt_s, k.jump_limit_m)
    _finish(xp, k, c, look & finite & jumped, "jumped", step, S)
    ok = look & finite & no(jumped)
    c["prev"] = xp.where(ok, S, c["prev"])
    c["prev_step"] = xp.where(ok, step, c["prev_step"])
    geometry = g.contact_geometry_3d if k.spatial else g.contact_geometry
    pen, apart, off_span, side = geometry(xp, *_bodies(k), S, c["came_from"])
    c["peak"] = xp.where(ok, xp.maximum(c["peak"], pen), c["peak"])
    speeds = (
        xp.hypot(S[g.BALL_VX], S[g.BALL_VY])
        + xp.hypot(S[g.BAT_VX], S[g.BAT_VY])
        + xp.abs(S[g.BALL_VZ])
        + xp.abs(S[g.BAT_VZ])
        + xp.abs(S[g.BAT_W]) * k.flag_arm_m
    )
    far = ok & touching & (pen < -k.flag_gap_m)
    moved = 2.0 * k.dt_s * speeds
    _finish(xp, k, c, far & (pen < -(k.flag_gap_m + moved)), "contact_flag", step, S, side)
    dvx, dvy = S[g.BALL_VX] - c["vx0"], S[g.BALL_VY] - c["vy0"]
    deflected = dvx * dvx + dvy * dvy > c["limit2"]
    t = ok & (touching | (deflected & (c["first"] < 0)))
    c["first"] = xp.where(t & (c["first"] < 0), step, c["first"])
    c["last"] = xp.where(t, step, c["last"])
    sliding = k.rigid & (off_span > 0.0)
    c["off"] = xp.where(t, xp.where(sliding, c["off"] + 1, 0), c["off"])
    _finish(xp, k, c, t & (c["off"] > k.off_span_steps), "left_cylinder", step, S, side)
    _flight_end(xp, k, c, ok & no(touching) & (c["first"] >= 0), step, S, apart, off_span, side)
    due = ok & no(touching) & (c["first"] < 0) & (step > k.approach_steps + 1)
    _finish(xp, k, c, due & (side <= 0.0), "passed", step, S, side)
    _finish(xp, k, c, due & (side > 0.0), "missed", step, S, side)
    c["side_now"] = side
    return c


def _flight_end(xp, k: EpisodeConstants, c: dict, after, step, S, apart, off_span, side) -> None:
    """``episode._Stepper.flight_end`` up to its search: the worlds due one are flagged."""
    _finish(xp, k, c, after & (off_span > 0.0), "left_cylinder", step, S, side)
    after = after & c["active"] & apart
    if k.spatial:  # out of the plane there is no cheap bound: the 3D search decides
        gone = after & False
    else:
        planar = [S[i] for i in (g.BALL_X, g.BALL_Y, g.BALL_VX, g.BALL_VY, g.BAT_X, g.BAT_Y)]
        planar += [S[i] for i in (g.BAT_VX, g.BAT_VY, g.BAT_ANGLE, g.BAT_W)]
        gone = after & separates_for_good_xp(
            xp,
            planar,
            reach_m=k.reach_m,
            ball_radius_m=k.ball_radius_m,
            t_max_s=(k.max_steps - step) * k.dt_s,
        )
    _finish(xp, k, c, gone, "separated", step, S, side)
    c["search"] = after & xp.not_(gone) & (c["check_at"] <= step)


def resolve(xp, k: EpisodeConstants, c: dict, step, S, left, ahead, check_at) -> tuple:
    """The host's free-flight answers (per world, read where it was searched: off the span
    first, contact ahead, and the step to look again, worked out in float64 as there):
    ``episode._Stepper.flight_end``'s end. Returns the carry and whether any world is still
    going."""
    c = dict(c)
    search = c["search"]
    _finish(xp, k, c, search & left, "left_cylinder", step, S, c["side_now"])
    _finish(xp, k, c, search & xp.not_(ahead), "separated", step, S, c["side_now"])
    c["check_at"] = xp.where(search & ahead, check_at, c["check_at"])
    c["search"] = search & False
    return c, xp.any(c["active"])


def budget(xp, k: EpisodeConstants, c: dict, S) -> dict:
    """``episode._Stepper.budget_spent``: the last reading ends every world still going."""
    c = dict(c)
    finite = xp.all(xp.isfinite(S), axis=0)
    _finish(xp, k, c, xp.not_(finite), "non_finite", k.max_steps, S)
    geometry = g.contact_geometry_3d if k.spatial else g.contact_geometry
    pen, _, _, side = geometry(xp, *_bodies(k), S, c["came_from"])
    c["peak"] = xp.where(c["active"], xp.maximum(c["peak"], pen), c["peak"])
    _finish(xp, k, c, c["active"], "budget", k.max_steps, S, side)
    return c
