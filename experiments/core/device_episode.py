"""A batched engine's episodes observed where its worlds live (``adapters.device``): each step's
look at every world (failures, contact geometry, endings) computed on the engine's device, in
the harness's observation compiled there (``device_observe``, JAX) or in the adapter's own
kernels (Warp); only two flags a step, the rows due a free-flight search, and at the end each
world's ending, counts and end state come back to the host.

Where it runs (``BATSIM_DEVICE_EPISODE``): ``auto`` (the default) where the engine's worlds are
not on a CPU, ``1`` wherever the adapter offers it (the tests run it on the CPU against the
numpy path), ``0`` never. On a CPU the numpy path (``episode``) stays the default: it is the
reference this one is tested against, and it gains nothing there. Measured on a loaded 2-core
CPU (the 41-point grid tiled to 1e4 worlds at the reference profile, 4 steps an impact;
``fire_jobs`` timed whole, median of 3, each path warmed first), us a fired impact, numpy
against the device path: mjwarp 46.2 / 46.1, newton 7.0 / 7.3, mjx 97.7 / 85.4, mjx64
109.7 / 112.9 (the engines' steps dominate; the differences are within this machine's noise).
What it saves, the state's copy off a GPU and numpy's pass over it every step, needs a GPU.

The end state, endings and first and last contact steps equal the numpy path's for a world
whose observation decides as numpy's does; its state's columns are the engine's own numbers
(cast to float64 as ``read`` casts them), so v1 then has the same bits. The geometry is
computed in the device's arithmetic (the engine's precision under JAX, float64 in Warp's
kernels, with fused multiply-adds): the peak penetration differs by that rounding.
"""

from __future__ import annotations

import functools
import math
import os
from functools import partial

import numpy as np

from adapters import Settings
from adapters.device import ENDINGS, ArrayDevice, EpisodeConstants
from analytic import Ball, Bat
from analytic.collide import EPISODE_GAP_RADII

from . import device_observe as obs
from . import geometry as g
from .endings import Ending
from .episode import Episodes, run_episode, step_episodes
from .terms import DEFLECTED, FLAG_REACHES, JUMP_REACHES, OFF_SPAN_STEPS
from .worlds import ManyWorlds

#: The environment variable that chooses the path (module docstring) and its values.
ENV = "BATSIM_DEVICE_EPISODE"
CHOICES = ("auto", "1", "0")


def wanted(engine) -> bool:
    """Whether this batched engine's episodes run on its device (``ENV``)."""
    choice = os.environ.get(ENV, "auto") or "auto"
    if choice not in CHOICES:
        raise ValueError(f"{ENV}={choice!r}; allowed: {', '.join(CHOICES)}")
    if choice == "auto":
        return not engine.device().startswith("cpu")
    return choice == "1"


def constants(
    bat: Bat, ball: Ball, settings: Settings, spatial: bool, rigid: bool
) -> EpisodeConstants:
    """The numbers of ``episode``'s rules for this batch, as the device takes them."""
    reach = bat.radius_m + ball.radius_m
    return EpisodeConstants(
        bat_radius_m=bat.radius_m,
        ball_radius_m=ball.radius_m,
        s_min_m=bat.s_min_m,
        s_max_m=bat.s_max_m,
        dt_s=settings.dt_s,
        approach_steps=settings.approach_steps,
        max_steps=settings.approach_steps + math.ceil(settings.max_contact_s / settings.dt_s) + 2,
        jump_limit_m=JUMP_REACHES * reach,
        flag_gap_m=FLAG_REACHES * reach,
        deflected=DEFLECTED,
        off_span_steps=OFF_SPAN_STEPS,
        episode_end_m=EPISODE_GAP_RADII * ball.radius_m,
        rigid=rigid,
        spatial=spatial,
        codes=tuple(int(Ending[name.upper()]) for name in ENDINGS),
    )


def observed_episodes(
    batch, bat: Bat, ball: Ball, settings: Settings, starts, spatial: bool, rigid: bool
) -> Episodes:
    """``episode.step_episodes``, on the engine's device where it offers that and it is
    wanted there (``wanted``), else in numpy (or Python floats) on the host."""
    if isinstance(batch, ManyWorlds) and wanted(batch.engine):
        k = constants(bat, ball, settings, spatial, rigid)
        batch.set_state(starts)  # (asked after it: a device episode lasts until the next)
        device = batch.engine.device_episode(k)
        if isinstance(device, ArrayDevice):
            device = ArrayEpisode(device, k, batch.n)
        if device is not None:
            return on_device(batch, device, k, starts)
    return step_episodes(batch, bat, ball, settings, starts, spatial, rigid)


def on_device(batch, device, k: EpisodeConstants, starts: np.ndarray) -> Episodes:
    """Step ``batch``, set to ``starts`` (n, 20), through its episodes, each step observed by
    ``device`` (an ``adapters.device.DeviceEpisode``)."""
    cols = np.ascontiguousarray(starts.T)
    came_from = np.where(g.side_of_axis(g.ARRAYS, cols) < 0.0, -1.0, 1.0)
    vx0, vy0 = cols[g.BALL_VX], cols[g.BALL_VY]
    ball_v0 = np.stack([vx0, vy0, k.deflected**2 * (vx0 * vx0 + vy0 * vy0)], axis=1)
    device.start(starts, came_from, ball_v0)
    run_episode(batch, _Watch(device, k), k.max_steps)
    r = device.result()
    return Episodes(
        ended=np.where(batch.failed(), Ending.NON_FINITE, r["ended"]),
        steps=r["steps"],
        end=r["end"],
        first=r["first"],
        last=r["last"],
        peak_m=r["peak_m"],
        side_m=r["side_m"],
    )


class _Watch:
    """The episode's task (``episode.Task``) with the looking done on the device; the
    free-flight searches the device flags are run here, on their rows alone."""

    def __init__(self, device, k: EpisodeConstants) -> None:
        self.device, self.k = device, k

    def over(self, step: int, batch) -> bool:
        going, search = self.device.observe(step)
        if search:
            idx, rows = self.device.searching()
            t, ahead, left = _search(self.k, step, rows)
            going = self.device.resolve(step, idx, left, ahead, check_at(self.k, step, t))
        return not going

    def budget_spent(self, batch) -> None:
        self.device.budget()


def _search(k: EpisodeConstants, step: int, rows: np.ndarray) -> tuple:
    """``episode._Stepper.flight_end``'s search from these rows (k, 20), on the host."""
    S = np.ascontiguousarray(rows.T)
    kw = dict(
        reach_m=k.reach_m,
        ball_radius_m=k.ball_radius_m,
        s_min_m=k.s_min_m,
        s_max_m=k.s_max_m,
        t_max_s=(k.max_steps - step) * k.dt_s,
    )
    every = np.ones(len(rows), dtype=bool)
    if k.spatial:
        return g.free_flights_3d(g.ARRAYS, S, every, **kw)
    return g.ARRAYS.free_flights(S, every, **kw)


def check_at(k: EpisodeConstants, step: int, t_s: np.ndarray) -> np.ndarray:
    """The step a world with a contact ahead in ``t_s`` is looked at again (as the numpy
    path reckons it, in float64)."""
    return (step + np.maximum(1, np.floor(t_s / k.dt_s) - 1)).astype(np.int64)


@functools.lru_cache(maxsize=16)
def _compiled(jit, mod, k: EpisodeConstants):
    """The observation's functions compiled by ``jit`` for these constants (kept: a new
    batch of the same kind compiles nothing)."""
    xp = obs.namespace(mod)
    return (
        jit(partial(obs.observe, xp, k)),
        jit(partial(obs.resolve, xp, k)),
        jit(partial(obs.budget, xp, k)),
    )


class ArrayEpisode:
    """``adapters.device.DeviceEpisode`` for an ``ArrayDevice``: the harness's observation
    (``device_observe``) compiled by the device's array library, on the worlds' columns
    there."""

    def __init__(self, device: ArrayDevice, k: EpisodeConstants, n: int) -> None:
        self.dev, self.k, self.n = device, k, n
        self.fns = _compiled(device.jit, device.xp, k)

    def start(self, starts: np.ndarray, came_from: np.ndarray, ball_v0: np.ndarray) -> None:
        pad = self.dev.rows - self.n
        starts, came_from, ball_v0 = (
            np.concatenate([a, np.repeat(a[:1], pad, axis=0)]) for a in (starts, came_from, ball_v0)
        )
        carry = obs.start(self.k, starts, came_from, ball_v0, self.n)
        self.c = self.dev.call(lambda: {key: self.dev.xp.asarray(v) for key, v in carry.items()})

    def observe(self, step: int) -> tuple[bool, bool]:
        S, touching = self.dev.columns()
        self.c, flags = self.dev.call(self.fns[0], self.c, step, touching, S)
        going, search = np.asarray(flags).tolist()
        return going, search

    def searching(self) -> tuple[np.ndarray, np.ndarray]:
        idx = np.flatnonzero(np.asarray(self.c["search"]))
        S, _ = self.dev.columns()
        # gathered in a bucket's worth of rows (a power of two): few shapes to compile
        at = np.resize(idx, 1 << max(0, len(idx) - 1).bit_length())
        return idx, np.asarray(S[:, at], dtype=float).T[: len(idx)]

    def resolve(self, step: int, idx, left, ahead, check_at) -> bool:
        S, _ = self.dev.columns()
        rows = self.dev.rows
        full = [np.zeros(rows, dtype=bool), np.zeros(rows, dtype=bool), np.zeros(rows, np.int32)]
        for a, values in zip(full, (left, ahead, check_at)):
            a[idx] = values
        self.c, going = self.dev.call(self.fns[1], self.c, step, S, *full)
        return bool(going)

    def budget(self) -> None:
        S, _ = self.dev.columns()
        self.c = self.dev.call(self.fns[2], self.c, S)

    def result(self) -> dict[str, np.ndarray]:
        c, n = self.c, self.n
        return {
            "ended": np.asarray(c["ended"])[:n].astype(np.int64),
            "steps": np.asarray(c["steps"])[:n].astype(np.int64),
            "first": np.asarray(c["first"])[:n].astype(np.int64),
            "last": np.asarray(c["last"])[:n].astype(np.int64),
            "peak_m": np.asarray(c["peak"], dtype=float)[:n],
            "side_m": np.asarray(c["side_m"], dtype=float)[:n],
            "end": np.ascontiguousarray(np.asarray(c["end"], dtype=float)[:, :n]),
        }
