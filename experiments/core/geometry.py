"""Sphere against capsule, on one world or on a batch of them.

A batch of states is an array of shape (n, 20), one row per world in ``adapters.STATE_FIELDS``
order (m, m/s, rad, rad/s); one world's state is an ``adapters.State``. An impact that stays in
the swing plane is measured on the 11 planar columns alone, as it always was; one that leaves
it (``spatial``: an undercut, a spin about x or y) in 3D. The functions below take
an array namespace ``xp`` and the state's columns (``xp.cols(states)``), so the same code runs
on a batch in numpy and on one world in Python floats (``SCALARS``): numpy's overhead per call
on arrays of one row is ten times what an engine's step costs.
"""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np

from adapters import PLANAR_FIELDS, STATE_FIELDS, State
from analytic import Ball, Bat
from analytic.batch_ends import free_flight_many, separates_for_good_many
from analytic.collide import PlanarState, free_flight, separates_for_good
from analytic.spatial import free_flight_3d

(
    BALL_X,
    BALL_Y,
    BALL_VX,
    BALL_VY,
    BALL_W,
    BAT_X,
    BAT_Y,
    BAT_ANGLE,
    BAT_VX,
    BAT_VY,
    BAT_W,
    BALL_Z,
    BALL_VZ,
    BALL_WX,
    BALL_WY,
    BAT_Z,
    BAT_TILT,
    BAT_VZ,
    BAT_WX,
    BAT_WY,
) = range(len(STATE_FIELDS))
#: The bat's columns (the planar ones, then those out of the plane).
BAT_COLUMNS = (*range(BAT_X, BAT_W + 1), *range(BAT_Z, BAT_WY + 1))


def padded(states: np.ndarray) -> np.ndarray:
    """A batch of states with every column: a planar engine's 11 columns padded with zeros (in
    Fortran order: its columns read without a copy)."""
    return _from_cols(states.T) if states.shape[1] == len(PLANAR_FIELDS) else states


def _from_cols(cols) -> np.ndarray:
    """A batch of states from its first columns (arrays of n values), the rest 0, in Fortran
    order (``padded``)."""
    out = np.zeros((len(STATE_FIELDS), len(cols[0])))
    for row, col in zip(out, cols):
        row[:] = col
    return out.T


def _pick(mask: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """``np.where(mask, a, b)`` over columns (a world each), with no copy where the mask is all
    or none (the stepper never writes into an array it holds)."""
    if mask.all():
        return a
    if not mask.any():
        return b
    out = b.copy()
    np.copyto(out, a, where=mask)  # (a quarter of np.where's time on 20 rows of 1e4)
    return out


def _ended_at(start: np.ndarray, ends: list) -> np.ndarray:
    """Each world's state at the end of its episode (columns): its reading in ``ends``, a list
    of (mask, columns) in which each world is in one mask at most, else its ``start``."""
    if len(ends) == 1 and ends[0][0].all():
        return ends[0][1]
    out = start.copy()
    for mask, cols in ends:
        np.copyto(out, cols, where=mask)  # (a fifth of out[:, mask] = cols[:, mask]'s time)
    return out


def _select(conditions: list, values: list, default) -> np.ndarray:
    """``np.select`` of values (strings) as an array of Python objects: chosen by code, so that
    no array of fixed-width strings is made (pandas reads those ten times slower)."""
    code = np.select(conditions, list(range(len(values))), len(values))
    return np.array([*values, default], dtype=object)[code]


def _indices(mask) -> np.ndarray | tuple:
    return np.flatnonzero(mask) if mask.any() else ()


def _with_bat(starts: np.ndarray, swung: np.ndarray) -> np.ndarray:
    out = starts.copy()
    out[:, BAT_COLUMNS] = swung[:, BAT_COLUMNS]
    return out


def _state_with_bat(start: State, swung: State) -> State:
    return start._replace(**{STATE_FIELDS[i]: swung[i] for i in BAT_COLUMNS})


def _planar_cols(S) -> tuple:
    return (
        S[BALL_X],
        S[BALL_Y],
        S[BALL_VX],
        S[BALL_VY],
        S[BAT_X],
        S[BAT_Y],
        S[BAT_VX],
        S[BAT_VY],
        S[BAT_ANGLE],
        S[BAT_W],
    )


def _free_flights(S, mask, **kw) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``free_flight_many`` from the worlds in ``mask``: per world the time, whether a contact
    is ahead and whether the ball leaves the cylinder's span first (0, False, False where not
    searched)."""
    n = len(mask)
    t, ahead, left = np.zeros(n), np.zeros(n, dtype=bool), np.zeros(n, dtype=bool)
    idx = np.flatnonzero(mask)
    if len(idx):
        t[idx], why = free_flight_many(np.array(_planar_cols(S))[:, idx], **kw)
        ahead[idx], left[idx] = why == "contact", why == "left_cylinder"
    return t, ahead, left


def _free_flight(S, flag: bool, **kw) -> tuple[float, bool, bool]:
    """``_free_flights`` for one world."""
    if not flag:
        return 0.0, False, False
    t, why = free_flight(planar(S), **kw)
    return t, why == "contact", why == "left_cylinder"


def _hypot(x: float, y: float) -> float:
    """numpy's hypot on two floats: math.hypot rounds otherwise in about 1 case in 300, and a
    world's numbers must not depend on whether it was stepped alone or in a batch."""
    return float(np.hypot(x, y))


#: numpy over a batch: arrays of n values, n rows (``columns``: them as 20 rows of n, each
#: contiguous: a copy, or the rows themselves where their columns are contiguous already (an
#: adapter's ``read`` hands over a new array each call)). The two namespaces round alike
#: (``sqrt``, not ``** 0.5``: Python's pow and numpy's differ in the last bit).
ARRAYS = SimpleNamespace(
    cos=np.cos,
    sin=np.sin,
    hypot=np.hypot,
    sqrt=np.sqrt,
    clip=np.clip,
    where=np.where,
    maximum=np.maximum,
    any=np.ndarray.any,
    not_=np.logical_not,
    full=np.full,
    pick=_pick,
    ended_at=_ended_at,
    select=_select,
    cols=lambda states: states.T,
    row=lambda states, i: states[i],
    columns=lambda states: np.ascontiguousarray(states.T),
    stack=lambda rows: np.array(rows, dtype=float),
    finite=lambda cols: np.isfinite(cols).all(axis=0),
    indices=_indices,
    with_bat=_with_bat,
    from_cols=_from_cols,
    separates=lambda S, **kw: separates_for_good_many(_planar_cols(S), **kw),
    free_flights=_free_flights,
    floor=np.floor,
)

#: Python floats for one world: a value, a bool, one State.
SCALARS = SimpleNamespace(
    cos=math.cos,
    sin=math.sin,
    hypot=_hypot,
    sqrt=math.sqrt,
    clip=lambda x, lo, hi: min(max(x, lo), hi),
    where=lambda c, a, b: a if c else b,
    maximum=max,
    any=bool,
    not_=lambda flag: not flag,
    full=lambda n, value: value,
    pick=lambda flag, a, b: a if flag else b,
    ended_at=lambda start, ends: ends[-1][1] if ends else start,
    select=lambda conditions, values, default: next(
        (v for c, v in zip(conditions, values) if c), default
    ),
    cols=lambda state: state,
    row=lambda state, i: state,
    columns=lambda state: state,
    stack=lambda rows: State(*rows[0]),
    finite=lambda state: math.isfinite(sum(state)),
    indices=lambda flag: (0,) if flag else (),
    with_bat=_state_with_bat,
    from_cols=lambda cols: State(*cols),
    separates=lambda S, **kw: separates_for_good(planar(S), **kw),
    free_flights=_free_flight,
    floor=math.floor,
)


def contact_geometry(xp, bat: Bat, ball: Ball, S, came_from=1.0):
    """Per world: (penetration, separating, off_span, side) in one pass over the closest point
    of the bat's axis; ``S`` the state's columns.

    Penetration is the geometric overlap (m, negative for a gap), measured from the side the
    ball came from: a ball whose centre has crossed the bat's axis is more than r_ball + r_bat
    deep, however close to the axis it sits. Separating: the ball centre moves away from the
    closest point of the bat's axis (the bat point's velocity includes the bat's spin).
    off_span: how far the ball centre is beyond the cylinder's span along the axis (m, <= 0 on
    it). side: the ball centre's distance from the bat's axis line, positive on the side it
    came from (m): ``came_from`` is the sign of (dy cos a - dx sin a) at the start, the bat's
    angle a (-1 where the bat starts more than a quarter turn from its contact angle).
    """
    c, s = xp.cos(S[BAT_ANGLE]), xp.sin(S[BAT_ANGLE])
    dx, dy = S[BALL_X] - S[BAT_X], S[BALL_Y] - S[BAT_Y]
    along = dx * c + dy * s
    t = xp.clip(along, bat.s_min_m, bat.s_max_m)
    nx, ny = dx - t * c, dy - t * s
    dist = xp.hypot(nx, ny)
    side = (dy * c - dx * s) * came_from
    pen = bat.radius_m + ball.radius_m - xp.where(side > 0.0, dist, -dist)
    w = S[BAT_W]
    rvx = S[BALL_VX] - (S[BAT_VX] - w * t * s)
    rvy = S[BALL_VY] - (S[BAT_VY] + w * t * c)
    apart = (rvx * nx + rvy * ny > 0.0) & (dist != 0.0)
    off_span = xp.maximum(bat.s_min_m - along, along - bat.s_max_m)
    return pen, apart, off_span, side


def side_of_axis(xp, S):
    """The ball centre's side of the bat's axis line in the swing plane, dy cos a - dx sin a
    (m), as both geometries measure ``side`` before ``came_from`` signs it."""
    c, s = xp.cos(S[BAT_ANGLE]), xp.sin(S[BAT_ANGLE])
    return (S[BALL_Y] - S[BAT_Y]) * c - (S[BALL_X] - S[BAT_X]) * s


def kinetic_energy_j(bat: Bat, ball: Ball, S):
    """Kinetic energy of both bodies with the scene's mass properties (J); ``S`` the columns."""
    return 0.5 * (
        ball.mass_kg * (S[BALL_VX] ** 2 + S[BALL_VY] ** 2)
        + ball.inertia_kgm2 * S[BALL_W] ** 2
        + bat.mass_kg * (S[BAT_VX] ** 2 + S[BAT_VY] ** 2)
        + bat.inertia_cm_kgm2 * S[BAT_W] ** 2
    )


def jumped(xp, before, after, elapsed_s, limit_m: float):
    """Whether a body's centre moved farther between two readings (columns) than twice its
    larger speed over the time between them, plus ``limit_m``: a reset of the state."""
    out = False
    for x, y, vx, vy in ((BALL_X, BALL_Y, BALL_VX, BALL_VY), (BAT_X, BAT_Y, BAT_VX, BAT_VY)):
        dx, dy = after[x] - before[x], after[y] - before[y]
        speed2 = xp.maximum(before[vx] ** 2 + before[vy] ** 2, after[vx] ** 2 + after[vy] ** 2)
        allowed = 2.0 * elapsed_s * xp.sqrt(speed2) + limit_m
        out = out | (dx * dx + dy * dy > allowed * allowed)  # squared: no square root per body
    return out


def planar(row) -> PlanarState:
    """One world's state as ``analytic.collide`` takes it."""
    r = [float(v) for v in row]
    return PlanarState(
        ball_x_m=r[BALL_X],
        ball_y_m=r[BALL_Y],
        ball_vx_mps=r[BALL_VX],
        ball_vy_mps=r[BALL_VY],
        bat_x_m=r[BAT_X],
        bat_y_m=r[BAT_Y],
        bat_vx_mps=r[BAT_VX],
        bat_vy_mps=r[BAT_VY],
        bat_angle_rad=r[BAT_ANGLE],
        bat_omega_radps=r[BAT_W],
    )


def contact_geometry_3d(xp, bat: Bat, ball: Ball, S, came_from=1.0):
    """``contact_geometry`` out of the swing plane: the bat's axis tilted by ``bat_tilt_rad``,
    the ball centre's z, and the bat's angular velocity in 3D. ``side`` stays the coordinate
    along the swing plane's normal to the axis, (dy cos a - dx sin a) times ``came_from``."""
    ca, sa = xp.cos(S[BAT_ANGLE]), xp.sin(S[BAT_ANGLE])
    cb, sb = xp.cos(S[BAT_TILT]), xp.sin(S[BAT_TILT])
    ax, ay, az = ca * cb, sa * cb, sb
    dx, dy, dz = S[BALL_X] - S[BAT_X], S[BALL_Y] - S[BAT_Y], S[BALL_Z] - S[BAT_Z]
    along = dx * ax + dy * ay + dz * az
    t = xp.clip(along, bat.s_min_m, bat.s_max_m)
    nx, ny, nz = dx - t * ax, dy - t * ay, dz - t * az
    dist = xp.sqrt(nx * nx + ny * ny + nz * nz)
    side = (dy * ca - dx * sa) * came_from
    pen = bat.radius_m + ball.radius_m - xp.where(side > 0.0, dist, -dist)
    wx, wy, wz = S[BAT_WX], S[BAT_WY], S[BAT_W]
    # the axis point's velocity: V + w x (t a)
    rvx = S[BALL_VX] - (S[BAT_VX] + t * (wy * az - wz * ay))
    rvy = S[BALL_VY] - (S[BAT_VY] + t * (wz * ax - wx * az))
    rvz = S[BALL_VZ] - (S[BAT_VZ] + t * (wx * ay - wy * ax))
    apart = (rvx * nx + rvy * ny + rvz * nz > 0.0) & (dist != 0.0)
    off_span = xp.maximum(bat.s_min_m - along, along - bat.s_max_m)
    return pen, apart, off_span, side


def kinetic_energy_3d(bat: Bat, ball: Ball, S):
    """Kinetic energy of both bodies in 3D (J): the ball's spin about every axis, the bat's
    about its own axis with I_axial and across it with J."""
    cb = np.cos(S[BAT_TILT])
    ax, ay, az = np.cos(S[BAT_ANGLE]) * cb, np.sin(S[BAT_ANGLE]) * cb, np.sin(S[BAT_TILT])
    wx, wy, wz = S[BAT_WX], S[BAT_WY], S[BAT_W]
    w_axial = wx * ax + wy * ay + wz * az
    w2 = wx * wx + wy * wy + wz * wz
    return 0.5 * (
        ball.mass_kg * (S[BALL_VX] ** 2 + S[BALL_VY] ** 2 + S[BALL_VZ] ** 2)
        + ball.inertia_kgm2 * (S[BALL_W] ** 2 + S[BALL_WX] ** 2 + S[BALL_WY] ** 2)
        + bat.mass_kg * (S[BAT_VX] ** 2 + S[BAT_VY] ** 2 + S[BAT_VZ] ** 2)
        + bat.axial_inertia_kgm2 * w_axial**2
        + bat.inertia_cm_kgm2 * (w2 - w_axial**2)
    )


def jumped_3d(xp, before, after, elapsed_s, limit_m: float):
    """``jumped`` with the bodies' z in their displacement and speed."""
    out = False
    for x, y, z, vx, vy, vz in (
        (BALL_X, BALL_Y, BALL_Z, BALL_VX, BALL_VY, BALL_VZ),
        (BAT_X, BAT_Y, BAT_Z, BAT_VX, BAT_VY, BAT_VZ),
    ):
        dx, dy, dz = after[x] - before[x], after[y] - before[y], after[z] - before[z]
        speed2 = xp.maximum(
            before[vx] ** 2 + before[vy] ** 2 + before[vz] ** 2,
            after[vx] ** 2 + after[vy] ** 2 + after[vz] ** 2,
        )
        allowed = 2.0 * elapsed_s * xp.sqrt(speed2) + limit_m
        out = out | (dx * dx + dy * dy + dz * dz > allowed * allowed)
    return out


def free_flights_3d(xp, S, mask, **kw) -> tuple:
    """``analytic.spatial.free_flight_3d`` from each world in ``mask``, in the batch's
    namespace: as ``_free_flights`` gives it (time, contact ahead, off the span first)."""
    rows = [S] if xp is SCALARS else list(np.asarray(S).T)
    flags = [mask] if xp is SCALARS else list(mask)
    out = []
    for r, flag in zip(rows, flags):
        if not flag:
            out.append((0.0, ""))
            continue
        cb = math.cos(r[BAT_TILT])
        axis = np.array(
            [math.cos(r[BAT_ANGLE]) * cb, math.sin(r[BAT_ANGLE]) * cb, math.sin(r[BAT_TILT])]
        )
        rel = np.array([r[BALL_X] - r[BAT_X], r[BALL_Y] - r[BAT_Y], r[BALL_Z] - r[BAT_Z]])
        rv = np.array([r[BALL_VX] - r[BAT_VX], r[BALL_VY] - r[BAT_VY], r[BALL_VZ] - r[BAT_VZ]])
        omega = np.array([r[BAT_WX], r[BAT_WY], r[BAT_W]])
        out.append(free_flight_3d(rel, rv, axis, omega, **kw))
    t, why = np.array([t for t, _ in out]), np.array([w for _, w in out], dtype=object)
    ahead, left = why == "contact", why == "left_cylinder"
    return (float(t[0]), bool(ahead[0]), bool(left[0])) if xp is SCALARS else (t, ahead, left)
