"""The episode's per-step observation in Warp kernels, for the engines whose worlds live in Warp
arrays (MuJoCo Warp, Newton): ``adapters.device.DeviceEpisode`` on the engine's own device.

One thread per world follows ``experiments.core.episode``'s rules from the harness's numbers
(``EpisodeConstants``), in float64 on the engine's float32 state (its columns cast as ``read``
casts them): failures, the jump check, contact geometry, the contact flag's check, first and
last contact steps, the endings. Each engine fills the columns and its contact flags from its
own arrays (``fill``). Only two counts a step come back (worlds going, worlds due a search),
the searched worlds' rows, and the ends. Where these kernels' rounding differs from numpy's:
``hypot`` is sqrt(x^2 + y^2) here (within an ulp of numpy's), and the compiler may fuse
multiply-adds; decisions at an exact tie could differ, the peak penetration by ~1e-17 m.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
import warp as wp

from .device import EpisodeConstants

F = wp.float64
COLUMNS = 20


@wp.struct
class Rules:
    """``EpisodeConstants`` as a kernel takes them."""

    bat_r: wp.float64
    s_min: wp.float64
    s_max: wp.float64
    dt: wp.float64
    jump_limit: wp.float64
    flag_gap: wp.float64
    flag_arm: wp.float64
    ball_r_end: wp.float64
    reach: wp.float64
    approach: wp.int32
    max_steps: wp.int32
    off_span_steps: wp.int32
    rigid: wp.int32
    spatial: wp.int32
    non_finite: wp.int32
    jumped: wp.int32
    passed: wp.int32
    missed: wp.int32
    budget: wp.int32
    left: wp.int32
    separated: wp.int32
    contact_flag: wp.int32


@wp.struct
class Carry:
    """Each world's record of its episode (``experiments.core.device_observe.start``)."""

    ended: wp.array(dtype=wp.int32)
    steps: wp.array(dtype=wp.int32)
    first: wp.array(dtype=wp.int32)
    last: wp.array(dtype=wp.int32)
    off: wp.array(dtype=wp.int32)
    active: wp.array(dtype=wp.int32)
    prev_step: wp.array(dtype=wp.int32)
    check_at: wp.array(dtype=wp.int32)
    search: wp.array(dtype=wp.int32)
    peak: wp.array(dtype=wp.float64)
    side_m: wp.array(dtype=wp.float64)
    side_now: wp.array(dtype=wp.float64)
    came_from: wp.array(dtype=wp.float64)
    v0: wp.array2d(dtype=wp.float64)
    prev: wp.array2d(dtype=wp.float64)
    end: wp.array2d(dtype=wp.float64)


@wp.func
def _finish(
    c: Carry, r: Rules, i: int, code: int, step: int, S: wp.array2d(dtype=F), side: F, sided: int
):
    """``episode._Stepper.finish`` for world i, if still going."""
    if c.active[i] != 0:
        c.ended[i] = code
        c.steps[i] = step
        for j in range(COLUMNS):
            c.end[j, i] = S[j, i]
        if sided != 0:
            c.side_m[i] = side
        c.active[i] = 0
        if code == r.non_finite or code == r.jumped:
            c.peak[i] = F(wp.nan)


@wp.func
def _finite(S: wp.array2d(dtype=F), i: int) -> bool:
    """Whether every column of world i is finite."""
    for j in range(COLUMNS):
        if not wp.isfinite(S[j, i]):
            return False
    return True


@wp.func
def _hypot(x: F, y: F) -> F:
    return wp.sqrt(x * x + y * y)


@wp.func
def _geometry(r: Rules, S: wp.array2d(dtype=F), i: int, came_from: F):
    """``geometry.contact_geometry`` (or ``_3d``): pen, apart (0/1), off_span, side."""
    ca, sa = wp.cos(S[7, i]), wp.sin(S[7, i])
    cb, sb = F(1.0), F(0.0)
    if r.spatial != 0:
        cb, sb = wp.cos(S[16, i]), wp.sin(S[16, i])
    ax, ay, az = ca * cb, sa * cb, sb
    dx, dy = S[0, i] - S[5, i], S[1, i] - S[6, i]
    dz = F(0.0)
    if r.spatial != 0:
        dz = S[11, i] - S[15, i]
    along = dx * ax + dy * ay + dz * az
    t = wp.min(wp.max(along, r.s_min), r.s_max)
    nx, ny, nz = dx - t * ax, dy - t * ay, dz - t * az
    dist = wp.sqrt(nx * nx + ny * ny + nz * nz)
    if r.spatial == 0:
        dist = _hypot(nx, ny)
    side = (dy * ca - dx * sa) * came_from
    signed = dist
    if not side > F(0.0):
        signed = -dist
    pen = r.reach - signed
    w = S[10, i]
    rvx = S[2, i] - (S[8, i] - w * t * sa)  # the planar formulas, as numpy rounds them
    rvy = S[3, i] - (S[9, i] + w * t * ca)
    rvz = F(0.0)
    if r.spatial != 0:  # the axis point's velocity: V + w x (t a)
        wx, wy = S[18, i], S[19, i]
        rvx = S[2, i] - (S[8, i] + t * (wy * az - w * ay))
        rvy = S[3, i] - (S[9, i] + t * (w * ax - wx * az))
        rvz = S[12, i] - (S[17, i] + t * (wx * ay - wy * ax))
    apart = 0
    if rvx * nx + rvy * ny + rvz * nz > F(0.0) and dist != F(0.0):
        apart = 1
    off_span = wp.max(r.s_min - along, along - r.s_max)
    return pen, apart, off_span, side


@wp.func
def _moved(r: Rules, c: Carry, S: wp.array2d(dtype=F), i: int, body: int, elapsed: F) -> int:
    """``geometry.jumped`` (or ``_3d``) for one body: 0 the ball, 1 the bat."""
    x, y, z, vx, vy, vz = 0, 1, 11, 2, 3, 12
    if body == 1:
        x, y, z, vx, vy, vz = 5, 6, 15, 8, 9, 17
    dx, dy = S[x, i] - c.prev[x, i], S[y, i] - c.prev[y, i]
    before = c.prev[vx, i] * c.prev[vx, i] + c.prev[vy, i] * c.prev[vy, i]
    after = S[vx, i] * S[vx, i] + S[vy, i] * S[vy, i]
    d2 = dx * dx + dy * dy
    if r.spatial != 0:
        dz = S[z, i] - c.prev[z, i]
        d2 = d2 + dz * dz
        before = before + c.prev[vz, i] * c.prev[vz, i]
        after = after + S[vz, i] * S[vz, i]
    allowed = F(2.0) * elapsed * wp.sqrt(wp.max(before, after)) + r.jump_limit
    return wp.where(d2 > allowed * allowed, 1, 0)


@wp.func
def _separates(r: Rules, S: wp.array2d(dtype=F), i: int, t_max: F) -> int:
    """``analytic.batch_ends.separates_for_good_xp`` for world i."""
    c, s = wp.cos(S[7, i]), wp.sin(S[7, i])
    dx, dy = S[0, i] - S[5, i], S[1, i] - S[6, i]
    rvx, rvy, w = S[2, i] - S[8, i], S[3, i] - S[9, i], S[10, i]
    opening = rvy * c - rvx * s - w * (dx * c + dy * s)
    gap = dy * c - dx * s - r.reach
    end = r.ball_r_end
    horizon = F(2.0) * end / opening
    v_rel = _hypot(rvx, rvy)
    bound = F(2.0) * wp.abs(w) * v_rel + w * w * (_hypot(dx, dy) + v_rel * horizon)
    ok = opening > F(0.0) and gap >= F(0.0) and horizon <= t_max
    return wp.where(ok and F(0.5) * bound * horizon * horizon <= end + gap, 1, 0)


@wp.kernel
def _before(c: Carry, touching: wp.array(dtype=wp.int32), flags: wp.array(dtype=wp.int32)):
    """Before the planned contact: whether any world has seen a contact (``episode``'s skip)."""
    i = wp.tid()
    if c.first[i] >= 0 or touching[i] != 0:
        wp.atomic_max(flags, 0, 1)


@wp.kernel
def _observe(
    r: Rules,
    c: Carry,
    S: wp.array2d(dtype=F),
    touching: wp.array(dtype=wp.int32),
    step: int,
    seen: wp.array(dtype=wp.int32),
    out: wp.array(dtype=wp.int32),
    queue: wp.array(dtype=wp.int32),
):
    """One step's look at world i (``device_observe.observe``); counts the worlds going and
    queues those due a search."""
    i = wp.tid()
    if not (step < r.approach and seen[0] == 0):
        _look(r, c, S, touching[i] != 0, step, i)
    if c.active[i] != 0:
        wp.atomic_add(out, 0, 1)
    if c.search[i] != 0:
        queue[wp.atomic_add(out, 1, 1)] = i


@wp.func
def _look(r: Rules, c: Carry, S: wp.array2d(dtype=F), touch: bool, step: int, i: int):
    """``episode._Stepper.observe`` for world i, its search left flagged."""
    if c.active[i] == 0 or not (touch or c.first[i] >= 0 or step >= r.approach):
        return
    if not _finite(S, i):
        _finish(c, r, i, r.non_finite, step, S, F(0.0), 0)
        return
    elapsed = F(step - c.prev_step[i]) * r.dt
    if _moved(r, c, S, i, 0, elapsed) + _moved(r, c, S, i, 1, elapsed) > 0:
        _finish(c, r, i, r.jumped, step, S, F(0.0), 0)
        return
    for j in range(COLUMNS):
        c.prev[j, i] = S[j, i]
    c.prev_step[i] = step
    pen, apart, off_span, side = _geometry(r, S, i, c.came_from[i])
    c.peak[i] = wp.max(c.peak[i], pen)
    speeds = _hypot(S[2, i], S[3, i]) + _hypot(S[8, i], S[9, i]) + wp.abs(S[12, i])
    speeds = speeds + wp.abs(S[17, i]) + wp.abs(S[10, i]) * r.flag_arm
    if touch and pen < -r.flag_gap and pen < -(r.flag_gap + F(2.0) * r.dt * speeds):
        _finish(c, r, i, r.contact_flag, step, S, side, 1)
    dvx, dvy = S[2, i] - c.v0[0, i], S[3, i] - c.v0[1, i]
    deflected = dvx * dvx + dvy * dvy > c.v0[2, i]
    if touch or (deflected and c.first[i] < 0):
        if c.first[i] < 0:
            c.first[i] = step
        c.last[i] = step
        c.off[i] = wp.where(r.rigid != 0 and off_span > F(0.0), c.off[i] + 1, 0)
        if c.off[i] > r.off_span_steps:
            _finish(c, r, i, r.left, step, S, side, 1)
    if not touch and c.first[i] >= 0:
        if off_span > F(0.0):
            _finish(c, r, i, r.left, step, S, side, 1)
        if c.active[i] != 0 and apart != 0:
            t_max = F(r.max_steps - step) * r.dt
            if r.spatial == 0 and _separates(r, S, i, t_max) != 0:
                _finish(c, r, i, r.separated, step, S, side, 1)
            elif c.check_at[i] <= step:
                c.search[i] = 1
    if not touch and c.first[i] < 0 and step > r.approach + 1:
        _finish(c, r, i, wp.where(side <= F(0.0), r.passed, r.missed), step, S, side, 1)
    c.side_now[i] = side


@wp.kernel
def _gather(S: wp.array2d(dtype=F), idx: wp.array(dtype=wp.int32), rows: wp.array2d(dtype=F)):
    j = wp.tid()
    for col in range(COLUMNS):
        rows[j, col] = S[col, idx[j]]


@wp.kernel
def _resolve(
    r: Rules,
    c: Carry,
    S: wp.array2d(dtype=F),
    step: int,
    idx: wp.array(dtype=wp.int32),
    answers: wp.array2d(dtype=wp.int32),
):
    """The host's search answers (left, ahead, check_at) for world idx[j]."""
    j = wp.tid()
    i = idx[j]
    if answers[j, 0] != 0:
        _finish(c, r, i, r.left, step, S, c.side_now[i], 1)
    if answers[j, 1] == 0:
        _finish(c, r, i, r.separated, step, S, c.side_now[i], 1)
    else:
        c.check_at[i] = answers[j, 2]
    c.search[i] = 0


@wp.kernel
def _budget(r: Rules, c: Carry, S: wp.array2d(dtype=F)):
    """``episode._Stepper.budget_spent`` for world i."""
    i = wp.tid()
    if not _finite(S, i):
        _finish(c, r, i, r.non_finite, r.max_steps, S, F(0.0), 0)
    pen, apart, off_span, side = _geometry(r, S, i, c.came_from[i])
    if c.active[i] != 0:
        c.peak[i] = wp.max(c.peak[i], pen)
    _finish(c, r, i, r.budget, r.max_steps, S, side, 1)


@wp.kernel
def _count(c: Carry, out: wp.array(dtype=wp.int32)):
    if c.active[wp.tid()] != 0:
        wp.atomic_add(out, 0, 1)


def rules(k: EpisodeConstants) -> Rules:
    """The constants as the kernels take them."""
    r = Rules()
    for field, value in (
        ("bat_r", k.bat_radius_m),
        ("s_min", k.s_min_m),
        ("s_max", k.s_max_m),
        ("dt", k.dt_s),
        ("jump_limit", k.jump_limit_m),
        ("flag_gap", k.flag_gap_m),
        ("flag_arm", k.flag_arm_m),
        ("ball_r_end", k.episode_end_m),
        ("reach", k.reach_m),
    ):
        setattr(r, field, float(value))
    for field, value in (
        ("approach", k.approach_steps),
        ("max_steps", k.max_steps),
        ("off_span_steps", k.off_span_steps),
        ("rigid", k.rigid),
        ("spatial", k.spatial),
    ):
        setattr(r, field, int(value))
    names = ("non_finite", "jumped", "passed", "missed", "budget", "left_cylinder")
    for field, name in zip((*names[:5], "left"), names):
        setattr(r, field, k.code(name))
    r.separated, r.contact_flag = k.code("separated"), k.code("contact_flag")
    return r


class WarpEpisode:
    """``adapters.device.DeviceEpisode`` in the kernels above, on ``device``: ``fill(S,
    touching)`` writes the engine's worlds' state columns (20, n, float64) and last step's
    contact flags (n, int32) into the arrays it is given."""

    def __init__(
        self, k: EpisodeConstants, n: int, device: str, fill: Callable[[wp.array, wp.array], None]
    ) -> None:
        self.k, self.n, self.device, self.fill = k, n, device, fill
        self.r = rules(k)
        with wp.ScopedDevice(device):
            self.S = wp.zeros((COLUMNS, n), dtype=F)
            self.touching = wp.zeros(n, dtype=wp.int32)
            self.flags = wp.zeros(2, dtype=wp.int32)
            self.seen = wp.zeros(1, dtype=wp.int32)
            self.queue = wp.zeros(n, dtype=wp.int32)

    def _launch(self, kernel, dim: int, *inputs) -> None:
        wp.launch(kernel, dim=dim, inputs=list(inputs), device=self.device)

    def start(self, starts: np.ndarray, came_from: np.ndarray, ball_v0: np.ndarray) -> None:
        n, cols = self.n, np.ascontiguousarray(starts.T)
        c = Carry()
        with wp.ScopedDevice(self.device):
            for name in ("ended", "off", "prev_step", "check_at", "search"):
                setattr(c, name, wp.zeros(n, dtype=wp.int32))
            c.steps = wp.full(n, self.k.max_steps, dtype=wp.int32)
            c.first, c.last = wp.full(n, -1, dtype=wp.int32), wp.full(n, -1, dtype=wp.int32)
            c.active = wp.ones(n, dtype=wp.int32)
            c.peak = wp.full(n, -np.inf, dtype=F)
            c.side_m = wp.full(n, np.nan, dtype=F)
            c.side_now = wp.zeros(n, dtype=F)
            c.came_from = wp.array(came_from, dtype=F)
            c.v0 = wp.array(np.ascontiguousarray(ball_v0.T), dtype=F)
            c.prev, c.end = wp.array(cols, dtype=F), wp.array(cols, dtype=F)
        self.c = c

    def observe(self, step: int) -> tuple[bool, bool]:
        self.fill(self.S, self.touching)
        self.seen.zero_()
        self.flags.zero_()
        if step < self.k.approach_steps:
            self._launch(_before, self.n, self.c, self.touching, self.seen)
        args = (self.r, self.c, self.S, self.touching, step, self.seen, self.flags, self.queue)
        self._launch(_observe, self.n, *args)
        going, self.searches = self.flags.numpy().tolist()
        return going > 0, self.searches > 0

    def searching(self) -> tuple[np.ndarray, np.ndarray]:
        idx = np.sort(self.queue.numpy()[: self.searches])
        with wp.ScopedDevice(self.device):
            self.idx = wp.array(idx.astype(np.int32), dtype=wp.int32)
            rows = wp.zeros((len(idx), COLUMNS), dtype=F)
        self._launch(_gather, len(idx), self.S, self.idx, rows)
        return idx, rows.numpy()

    def resolve(self, step: int, idx, left, ahead, check_at) -> bool:
        answers = np.stack([left, ahead, check_at], axis=1).astype(np.int32)
        with wp.ScopedDevice(self.device):
            answers = wp.array(answers, dtype=wp.int32)
        self._launch(_resolve, len(idx), self.r, self.c, self.S, step, self.idx, answers)
        self.flags.zero_()
        self._launch(_count, self.n, self.c, self.flags)
        return int(self.flags.numpy()[0]) > 0

    def budget(self) -> None:
        self.fill(self.S, self.touching)
        self._launch(_budget, self.n, self.r, self.c, self.S)

    def result(self) -> dict[str, np.ndarray]:
        c = self.c
        return {
            "ended": c.ended.numpy().astype(np.int64),
            "steps": c.steps.numpy().astype(np.int64),
            "first": c.first.numpy().astype(np.int64),
            "last": c.last.numpy().astype(np.int64),
            "peak_m": c.peak.numpy(),
            "side_m": c.side_m.numpy(),
            "end": c.end.numpy(),
        }
