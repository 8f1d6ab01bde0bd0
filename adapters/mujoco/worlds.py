"""MuJoCo's worlds on one model, stepped by MuJoCo's own batched call, ``mujoco.rollout`` (C,
a persistent pool of ``adapters.engine_threads()`` threads, the same ``mj_step``), for a long
run (``Capabilities.pool_adapter``): every world ends bit for bit as it does alone
(``tests/test_pool.py``).

How a world is stepped (a ``rollout`` call, or alone on data of its own) is ``stepping``'s;
which worlds, from where and how far, is this module's. The harness observes every step, so
the pool steps in chunks: ``step`` only counts; a read (``in_contact``, ``read``, ``failed``)
steps, in one call for all worlds, up to the step asked and on to the chunk's end, whose
later steps the next reads take. The first chunk of an episode ends ``approach_steps`` + 2
steps in, where most impacts are over (the paper's swing: 4 steps); each further chunk is
twice as long, up to WINDOW_MAX steps (a long contact costs a few calls, at most twice its
steps). A drive (the
hands) is stepped without looking ahead. A world whose episode is over (``retire``) is in no
further call: a long contact elsewhere (e = 0: hundreds of steps) no longer steps them all.

What ``rollout`` does not give back is the warm start (the last step's accelerations, which
seed the solver's next one): a world goes on from a step whose state is exact with any warm
start, its *rest point*: the start (warm start 0, as ``set_state`` sets it), or the state
before a step without constraints (no contact, hands off), whose solver does not run. A chunk
starts at each world's rest point (the steps since are stepped again, the same bits). Kept
apart, stepped one ``mj_step`` at a time on data of their own as alone (``OwnWorld``): worlds
under RK4 (whose ``ncon`` after a step is its last stage's contacts, not its start's), worlds whose
chunk met a warning (``rollout`` stops there; MuJoCo reset the state and goes on), worlds too
long without a rest point for a call's memory, and worlds left mid-episode by a drive change.
"""

from __future__ import annotations

import os
import time
import weakref
from collections.abc import Sequence

import numpy as np

from ..interface import BatchedEngine, Hands, MassProperties, Scene
from ..loading import engine_threads
from . import RECORD
from .adapter import MujocoEngine
from .rows import WIDTH, physics_rows, state_rows
from .stepping import (
    ROLLOUT,
    Chunk,
    OwnWorld,
    any_warning,
    clear_warnings,
    control_row,
    driven,
    mujoco,
    roll,
    warned,
)

#: The most numbers one ``rollout`` call writes (states and sensor data: 8e6, 64 MB); more
#: worlds go in further calls, and a world that alone needs more is stepped on its own.
CALL_NUMBERS = 8_000_000
#: Steps a world may go without a rest point, stepped from it once already, before it is
#: stepped on data of its own, its warm start carried from call to call (a long contact: each
#: chunk would step it again from its rest point; a drive's first call, a swing's thousands of
#: steps, goes with the others on every thread).
CARRY_AFTER = 64
#: The longest a further chunk grows (steps): a world's chunk is held until it is read past, so
#: a pool's memory is its worlds times this (e = 0 over 2048 impacts, pools of 1024: 1.18 GB
#: peak and 40 s unbounded, 0.72 GB and 33 s at 256; measured).
WINDOW_MAX = 256


#: The pools whose ``Rollout`` threads run in this process, and, in a forked child, the copies
#: of its parent's ``Rollout`` objects, kept and never freed: their threads stayed in the
#: parent, and freeing one joins threads the child does not have (a worker forked from a
#: process holding a pool hung or died of SIGSEGV when it dropped its parent's engines).
_THREADED: weakref.WeakSet = weakref.WeakSet()
_INHERITED: list = []


def _after_fork_in_child() -> None:
    for worlds in list(_THREADED):
        _INHERITED.extend(r for r in (worlds._pool, worlds._alone) if r is not None)
        worlds._pool = worlds._alone = None
        worlds._scene = None  # (made anew, with a pool of this process's, if used again)
    _THREADED.clear()


os.register_at_fork(after_in_child=_after_fork_in_child)


class MujocoWorlds(BatchedEngine):
    """``n`` MuJoCo worlds on one model, stepped through ``mujoco.rollout`` (module docstring).
    The hands' pivot and load site are the model's: worlds driven by hands of their own (a
    swing's batch: each swing's pivot is its own) each step on a copy of it."""

    record = RECORD

    def __init__(self, settings) -> None:
        super().__init__(settings)
        self._engine: MujocoEngine | None = None  # the scene's model, drive, mass properties
        self._scene: Scene | None = None
        self._pool = None  # the persistent rollout.Rollout
        self._scratch: list = []  # its threads' data
        self._datas: list = []  # data for the worlds stepped on their own, kept for reuse
        self._models: list = []  # each world's model (the scene's, or a copy driven its way)
        self._n = 0

    def build(self, scene: Scene, worlds: int) -> None:
        """``worlds`` worlds holding ``scene`` on one model (made anew if the scene changed)."""
        if scene != self._scene:
            engine = MujocoEngine(self.settings)
            engine.build(scene, contact_sensor=ROLLOUT is not None)
            self._engine, self._scene, self._datas = engine, scene, []
            self._batched = ROLLOUT is not None and self.settings.integrator != "RK4"
            if self._batched and self._pool is None:
                threads = engine_threads()
                self._pool = ROLLOUT(nthread=threads if threads > 1 else 0)
                self._alone = ROLLOUT(nthread=0)  # a carried world's calls (``_carry``)
                self._threads = threads
                _THREADED.add(self)
            if self._batched:
                self._scratch = [mujoco.MjData(engine.model) for _ in range(self._threads)]
            self._models = []
            self._undriven = control_row(engine)  # the hands off
        self._n = worlds
        self.set_state(np.zeros((worlds, 20)))

    def mass_properties(self) -> MassProperties:
        return self._engine.mass_properties()

    def set_state(self, states: np.ndarray) -> None:
        rows, self._planar = physics_rows(states)
        n = self._n = len(rows)
        if len(self._models) != n:  # (a drive of hands per world holds for as many worlds)
            self._models = [self._engine.model] * n
            self._control = np.tile(self._undriven, (n, 1))  # each world's control row
        self._t, self._at = 0, 0
        self._rest_rows, self._rest_step = rows, np.zeros(n, dtype=int)
        self._now, self._touching = rows.copy(), np.zeros(n, dtype=bool)
        self._failed = np.zeros(n, dtype=bool)
        self._chunks: list[Chunk | None] = []
        self._members: list[np.ndarray] | None = None
        self._slot, self._pos = np.full(n, -1), np.zeros(n, dtype=int)
        self._end = np.zeros(n, dtype=int)  # the last step each world's chunk reaches
        self._stale = np.zeros(n, dtype=bool)  # its chunk was under a drive since changed
        self._switched = 0  # the step the drive last changed at
        self._window = self.settings.approach_steps + 2  # the first chunk's end (docstring)
        self._first = True
        self._own: dict[int, OwnWorld] = {}
        self._is_own = np.zeros(n, dtype=bool)
        self._carried = np.zeros(n, dtype=bool)  # its warm start in its own data (``_carry``)
        self._retired = np.zeros(n, dtype=bool)  # its episode over: stepped no further
        self._again = np.zeros(n, dtype=bool)  # stepped from its rest point once already
        if not self._batched:
            for w in range(n):
                self._make_own(w, rows[w], 0, self._control[w])

    def _data(self, w: int):
        """World ``w``'s data of its own (made once, kept for the next episodes)."""
        while len(self._datas) <= w:
            self._datas.append(mujoco.MjData(self._engine.model))
        return self._datas[w]

    def _make_own(
        self, w: int, row: np.ndarray, step: int, control: np.ndarray, warm=None, model=None
    ):
        """World ``w`` stepped on its own (``OwnWorld``) from ``row`` at ``step``, on ``model``
        (None: its own now)."""
        model = self._models[w] if model is None else model
        own = self._own[w] = OwnWorld(self._data(w), model, row, step, control, warm)
        self._members = None
        self._slot[w], self._is_own[w], self._stale[w] = -1, True, False
        return own

    def step(self) -> None:
        self._t += 1  # stepped when read (module docstring)

    def read(self) -> np.ndarray:
        self._sync()
        if not self._retired.any():
            return state_rows(self._now, self._planar)
        if self._unread.any():  # (converted once, at the first read after they ended)
            fresh = self._unread
            self._ended_rows[fresh] = state_rows(self._now[fresh], self._planar[fresh])
            self._unread = np.zeros(self._n, dtype=bool)
        out = self._ended_rows.copy(order="F")
        live = ~self._retired
        out[live] = state_rows(self._now[live], self._planar[live])
        return out

    def in_contact(self) -> np.ndarray:
        self._sync()
        return self._touching.copy()

    def failed(self) -> np.ndarray:
        self._sync()
        return self._failed.copy()

    def retire(self, worlds: np.ndarray) -> None:
        """Step the worlds ``worlds`` no further: their row, contact flag and failure stay as
        at the step read last (``BatchedEngine.retire``), their chunk's memory freed once no
        world reads it."""
        self._sync()
        done = np.asarray(worlds, dtype=bool) & ~self._retired
        if not done.any():
            return
        if not self._retired.any():
            self._ended_rows = np.zeros((self._n, 20), order="F")  # (their rows as they ended)
            self._unread = np.zeros(self._n, dtype=bool)
        self._unread |= done
        self._retired |= done
        self._slot[done] = -1
        self._members = None
        for w in np.flatnonzero(done & self._is_own).tolist():
            del self._own[w]

    def _sync(self) -> None:
        """Every world's row, contact flag and failure at the step asked (``_t``)."""
        t = self._t
        if self._at == t:
            return
        due = np.flatnonzero((self._end < t) & ~self._is_own & ~self._retired)
        if due.size:
            self._refill(due, t)
            self._members = None
        if self._members is None:  # which worlds each chunk serves (since the last refill)
            order = np.argsort(self._slot, kind="stable")
            cuts = np.searchsorted(self._slot[order], np.arange(len(self._chunks) + 1))
            self._members = [order[cuts[i] : cuts[i + 1]] for i in range(len(self._chunks))]
            for i, mine in enumerate(self._members):
                if not mine.size:  # every world of it stepped on since: its memory freed
                    self._chunks[i] = None
        for chunk, mine in zip(self._chunks, self._members):
            if mine.size:
                pos = self._pos[mine]
                k = t - chunk.base_step[pos] - 1
                if chunk.dropped is not None:
                    k = k - chunk.dropped[pos]
                self._now[mine] = chunk.rows[pos, k]
                self._touching[mine] = chunk.touching[pos, k]
        for w, own in self._own.items():
            own.advance(t)
            own.row(self._now[w])
            self._touching[w], self._failed[w] = own.touching(), own.failed()
        self._at = t

    def _refill(self, due: np.ndarray, t: int) -> None:
        """Step the worlds ``due`` from their rest points to step ``t`` and on to the chunk's
        end, in calls of at most CALL_NUMBERS numbers (module docstring)."""
        m = self._engine.model
        for w in due[self._stale[due]]:  # under a drive since changed: on their own from here
            chunk, i = self._chunks[self._slot[w]], self._pos[w]
            own = self._make_own(
                w,
                chunk.start_rows[i],
                int(chunk.base_step[i]),
                chunk.control[i],
                None if chunk.start_warm is None else chunk.start_warm[i],
                chunk.models[i],
            )
            own.advance(self._switched)
            own.set_control(self._models[w], self._control[w])
        due = due[~self._is_own[due]]
        # the hands hold a bat: no step of its is free of constraints
        bound = bool(self._control[:, -1].any())
        if bound:
            end = t
        elif self._first:
            end = max(t, self._window)
        else:
            end = t + self._window
            self._window = min(2 * self._window, WINDOW_MAX)
        self._first = False
        per_step = WIDTH + m.nsensordata
        long = self._again[due] & (t - self._rest_step[due] > CARRY_AFTER)
        carried = self._carried[due] | long
        if carried.any():
            self._carry(due[carried], end)
        due = due[~carried]
        if not due.size:
            return
        steps = end - int(self._rest_step[due].min())
        if steps * per_step > CALL_NUMBERS:  # too long for one call's memory: on their own
            for w in due:
                self._make_own(w, self._rest_rows[w], int(self._rest_step[w]), self._control[w])
            return
        group = max(1, CALL_NUMBERS // (steps * per_step))
        for first in range(0, due.size, group):
            ws = due[first : first + group]
            self._call(ws, end - int(self._rest_step[ws].min()), end, bound)

    def _call(self, ws: np.ndarray, steps: int, end: int, bound: bool) -> None:
        """One ``rollout`` call: worlds ``ws`` from their rest points, ``steps`` steps each,
        reaching ``end`` at least. Bound (a drive's: no reads come before ``end``, and its rest
        points stay), each world's row at ``end`` alone is kept: a swing's 1e4 steps of 256
        worlds held to the next ``set_state`` were 560 MB."""
        start, base, control = self._rest_rows[ws], self._rest_step[ws].copy(), self._control[ws]
        models = [self._models[w] for w in ws.tolist()]
        rows, touching = roll(self._pool, models, self._scratch, start, control, steps)
        bad = warned(start, rows, self._engine.model.opt.timestep)  # such worlds go on their own
        for i in np.flatnonzero(bad):
            self._make_own(int(ws[i]), start[i], int(base[i]), control[i])
        ok = np.flatnonzero(~bad)
        self._again[ws[ok]] = True
        reach, dropped = base + steps, None
        if bound:
            dropped = end - base - 1
            keep = np.arange(ws.size), dropped
            rows, touching = rows[keep][:, None], touching[keep][:, None]
            reach = np.full(ws.size, end)
        self._chunks.append(
            Chunk(
                worlds=ws,
                base_step=base,
                rows=rows,
                touching=touching,
                start_rows=start,
                models=models,
                control=control,
                dropped=dropped,
            )
        )
        w = ws[ok]
        self._slot[w], self._pos[w], self._end[w] = len(self._chunks) - 1, ok, reach[ok]
        if bound:
            return
        # each world's rest point moves to the state before its chunk's last free step
        free = ~touching[ok]
        last = steps - 1 - np.argmax(free[:, ::-1], axis=1)
        moves = free.any(axis=1) & (last >= 1)
        idx = ok[moves]
        self._rest_step[ws[idx]] = base[idx] + last[moves]
        self._rest_rows[ws[idx]] = rows[idx, last[moves] - 1]
        self._again[ws[idx]] = False

    def _carry(self, ws: np.ndarray, end: int) -> None:
        """Worlds ``ws`` stepped to ``end``, each in a call of its own on its own data, which
        keeps the last step's warm start for the next (from its rest point the first time);
        their states in one chunk."""
        m, k = self._engine.model, ws.size
        start, base, control = self._rest_rows[ws], self._rest_step[ws].copy(), self._control[ws]
        models = [self._models[w] for w in ws.tolist()]
        most = end - int(base.min())
        if most * (WIDTH + m.nsensordata) > CALL_NUMBERS:  # too long for a call's memory
            for i, w in enumerate(ws.tolist()):
                self._make_own(w, start[i], int(base[i]), control[i])
            return
        rows = np.empty((k, most, WIDTH))
        touching = np.zeros((k, most), dtype=bool)
        warm = np.zeros((k, m.nv))
        kept = []
        for i, w in enumerate(ws.tolist()):
            d, steps = self._data(w), end - int(base[i])
            if self._carried[w]:
                warm[i] = d.qacc_warmstart
            self._carried[w] = True
            clear_warnings(d)
            got, hit = roll(
                self._alone,
                models[i : i + 1],
                [d],
                start[i : i + 1],
                control[i],
                steps,
                warm[i : i + 1],
            )
            rows[i, :steps], touching[i, :steps] = got[0], hit[0]
            if any_warning(d):  # (module docstring)
                self._make_own(w, start[i], int(base[i]), control[i], warm[i])
            else:
                kept.append(i)
        self._chunks.append(
            Chunk(
                worlds=ws,
                base_step=base,
                rows=rows,
                touching=touching,
                start_rows=start,
                models=models,
                control=control,
                start_warm=warm,
            )
        )
        ok = np.array(kept, dtype=int)
        w = ws[ok]
        self._slot[w], self._pos[w], self._end[w] = len(self._chunks) - 1, ok, end
        self._rest_step[w], self._rest_rows[w] = end, rows[ok, end - base[ok] - 1]

    def set_drive(self, hands: Sequence[Hands] | None) -> None:
        """Each world driven by its ``hands`` on a copy of the model holding their pivot and
        load site (one copy for equal hands); None: the hands let go, each world on the model
        it was driven on, as a world alone keeps its last hands' (the drive off, they act on
        nothing)."""
        self._sync()  # the steps asked so far, under the drive they were asked under
        if hands is None:
            models, control = self._models, np.tile(self._undriven, (self._n, 1))
        else:
            models, control = driven(self._engine, hands)
        if np.array_equal(control, self._control) and all(
            a is b for a, b in zip(models, self._models, strict=True)
        ):
            return
        self._models, self._control = models, control
        for w, own in self._own.items():
            own.set_control(models[w], control[w])
        if self._t > 0:  # the chunks' later steps, and rest points, are the old drive's
            shared = ~self._is_own
            self._stale |= shared
            self._end[shared] = np.minimum(self._end[shared], self._t)
            self._switched = self._t

    def set_body_friction(self, *, bat: float, ball: float) -> None:
        self._engine.set_body_friction(bat=bat, ball=ball)  # the model's: every world's

    def anchor_s(self, states: np.ndarray, steps: int) -> float | None:
        """``rollout`` alone, on these states' physics rows, with this pool's threads."""
        if not self._batched:
            return None
        start, _ = physics_rows(states)
        t0 = time.perf_counter()
        models = [self._engine.model] * len(start)
        roll(self._pool, models, self._scratch, start, self._undriven, steps)
        return time.perf_counter() - t0

    def close(self) -> None:
        if self._pool is not None:
            self._pool.close()
            self._alone.close()
        self._pool, self._engine, self._scene, self._scratch, self._datas = None, None, None, [], []
