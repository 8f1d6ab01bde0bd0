"""Firing impacts in this process: jobs in, outcomes out, in order.

    fired = fire_jobs([Job(engine="mujoco", settings=s, case=c) for c in cases])

Each job is placed (``placement``), fired on the process's adapter for its engine and settings
(made once and reused: adapters hold no state between impacts), stepped through its episode
(``episode``) and measured. A single-world engine fires one job at a time; a batched engine
fires each run of consecutive jobs that share a scene as one batch. Where the jobs run is the
runner's business (``experiments.core.runner``).
"""

from __future__ import annotations

import atexit
import math
import threading
import time
from collections import OrderedDict
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import NamedTuple

import adapters
from adapters import BatchedEngine, MassProperties, Scene, Settings, State
from analytic import ImpactCase
from analytic.dynamics import HingedSwing, MotionState

from . import geometry as g
from .episode import ManyWorlds, OneWorld, SimOutcome, classify, step_episodes
from .judge import Status, mass_allowance
from .placement import (
    PARKED_BALL_Y_M,
    SwingPlan,
    check_placement,
    hands_for,
    start_state,
    swing_case,
)

#: Engines kept alive per process (one per engine and settings), oldest closed first.
ENGINE_CACHE = 8
#: Set by the SIGINT handler of ``experiments.core.cli.main_guard``. Python code that an engine
#: calls back (pymunk's velocity functions) swallows the KeyboardInterrupt raised there, so
#: every batch checks this flag once it is done.
INTERRUPTED = threading.Event()


class SceneMismatch(RuntimeError):
    """The engine holds mass properties other than the scene's (an adapter bug, not physics)."""


@dataclass(frozen=True, kw_only=True)
class Job:
    """One impact to fire: which engine, with which settings, and, with ``swing``, the bat swung
    about the hands in the engine first (the case is then re-planned for the engine's step)."""

    engine: str
    settings: Settings
    case: ImpactCase
    swing: HingedSwing | None = None


class Fired(NamedTuple):
    """A fired job: the case as simulated (re-planned under a swing), the engine's outcome, and
    with a swing the analytic omega and angle at release (rad/s, rad; NaN without)."""

    case: ImpactCase
    outcome: SimOutcome
    release_omega_radps: float
    release_angle_rad: float


class Hosted:
    """One adapter of an engine with its settings, and the scene it holds."""

    def __init__(self, name: str, settings: Settings) -> None:
        self.name, self.settings = name, settings
        self.record = adapters.record(name)
        self.adapter = adapters.create(name, settings)
        self.batched = isinstance(self.adapter, BatchedEngine)
        self.scene: Scene | None = None
        self.worlds = 0

    def batch(self, scene: Scene, n: int):
        """The adapter holding ``scene`` in ``n`` worlds (built when either changed, and its mass
        properties checked), seen as the episode steps it."""
        if not self.batched and n != 1:
            raise ValueError(f"{self.name} steps one world at a time; allowed: n=1")
        if scene != self.scene or (self.batched and n != self.worlds):
            self.scene = None
            if self.batched:
                self.adapter.build(scene, n)
            else:
                self.adapter.build(scene)
            check_mass_properties(self.name, self.adapter.mass_properties(), scene,
                                  self.record.eps)
            self.scene, self.worlds = scene, n
        return ManyWorlds(self.adapter, n) if self.batched else OneWorld(self.adapter)

    def close(self) -> None:
        self.scene = None
        self.adapter.close()


def check_mass_properties(name: str, got: MassProperties, scene: Scene, eps: float) -> None:
    """Raise SceneMismatch unless the engine holds the scene's mass properties, to
    ``judge.mass_allowance`` of its precision."""
    bat, ball = scene.bat, scene.ball
    want = MassProperties(bat_mass_kg=bat.mass_kg, bat_com_from_knob_m=bat.com_from_knob_m,
                          bat_inertia_kgm2=bat.inertia_cm_kgm2, ball_mass_kg=ball.mass_kg,
                          ball_inertia_kgm2=ball.inertia_kgm2)
    rel = mass_allowance(eps)
    for field in MassProperties.__dataclass_fields__:
        a, b = getattr(got, field), getattr(want, field)
        if not math.isclose(a, b, rel_tol=rel, abs_tol=1e-15):
            raise SceneMismatch(f"{name}: {field} read back as {a!r}, the scene has {b!r} "
                                f"(allowed relative difference {rel:g})")


_HOSTED: OrderedDict[tuple[str, Settings], Hosted] = OrderedDict()


def hosted(name: str, settings: Settings) -> Hosted:
    """This process's adapter for ``name`` and ``settings`` (made once, reused)."""
    key = (name, settings)
    if key in _HOSTED:
        _HOSTED.move_to_end(key)
        return _HOSTED[key]
    while len(_HOSTED) >= ENGINE_CACHE:
        _HOSTED.popitem(last=False)[1].close()
    made = _HOSTED[key] = Hosted(name, settings)
    return made


def close_engines() -> None:
    """Close every adapter this process holds."""
    while _HOSTED:
        _HOSTED.popitem()[1].close()


# at exit, while the engines' own modules are still there to free their worlds
atexit.register(close_engines)


def forget_engines() -> None:
    """In a forked worker: drop the copies of the parent's adapters (they are the parent's)."""
    _HOSTED.clear()


def fire_jobs(jobs: Sequence[Job], tick: Callable[[int], None] | None = None) -> list[Fired]:
    """Fire jobs in this process, in order: one at a time on a single-world engine, each run of
    consecutive jobs sharing engine, settings, scene and swing as one batch on a batched one."""
    out: list[Fired] = []
    for run in runs(jobs):
        host = hosted(run[0].engine, run[0].settings)
        for group in [run] if host.batched else [[job] for job in run]:
            out += fire_group(host, group)
            if INTERRUPTED.is_set():
                raise KeyboardInterrupt
            if tick is not None:
                tick(len(group))
    return out


def same_batch(a: Job, b: Job) -> bool:
    return (a.engine == b.engine and a.settings == b.settings and a.swing == b.swing
            and (a.case.bat, a.case.ball, a.case.e) == (b.case.bat, b.case.ball, b.case.e))


def runs(jobs: Sequence[Job]) -> list[Sequence[Job]]:
    """Consecutive jobs that share engine, settings, scene and swing: a batched engine's batches."""
    out, start = [], 0
    for i in range(1, len(jobs) + 1):
        if i == len(jobs) or not same_batch(jobs[start], jobs[i]):
            out.append(jobs[start:i])
            start = i
    return out


def fire_group(host: Hosted, jobs: Sequence[Job]) -> list[Fired]:
    """Fire jobs that share engine, settings, scene and swing as one batch (module docstring)."""
    t0 = time.perf_counter()
    st = host.settings
    plans: list[SwingPlan] | None = None
    cases = [j.case for j in jobs]
    if jobs[0].swing is not None:
        planned = [swing_case(c.bat, c.ball, s_m=c.s_m, v0_mps=c.v0_mps, e=c.e,
                              swing=jobs[0].swing, settings=st) for c in cases]
        cases, plans = [p[0] for p in planned], [p[1] for p in planned]
    for c in cases:
        check_placement(c, st)
    bat, ball = cases[0].bat, cases[0].ball
    batch = host.batch(Scene(bat=bat, ball=ball, e=cases[0].e), len(cases))
    xp = batch.xp
    starts = xp.stack([start_state(c, st)[0] for c in cases])
    release = [(math.nan, math.nan)] * len(cases)
    try:
        if plans is not None:
            starts, release = _swing_into_place(batch, plans, starts, bat)
        episodes = step_episodes(batch, bat, ball, st, starts)
    except NotImplementedError:  # an engine that cannot drive the bat
        return _failed(host, cases, plans, Status.UNSUPPORTED, "no set_drive", t0)
    except (KeyboardInterrupt, SceneMismatch):
        raise
    except Exception as err:  # the engine raised while stepping: a failure, not a crash
        return _failed(host, cases, plans, Status.ERROR, f"error: {err!r}"[:200], t0)
    wall = (time.perf_counter() - t0) / len(cases)
    return [_fired(host, case, xp.row(starts, i), episodes, i, release[i], plan, wall)
            for i, (case, plan) in enumerate(zip(cases, plans or [None] * len(cases)))]


def _swing_into_place(batch, plans: list[SwingPlan], starts, bat):
    """Swing every world's bat from rest about the hands and release it (the ball parked far
    away); returns the start states with the engine's bats, and each release's omega and
    angle (rad/s, rad)."""
    if len({p.steps for p in plans}) != 1:
        raise ValueError("swings of one batch must last the same number of steps")
    xp = batch.xp
    batch.set_state(xp.stack([p.bat_start for p in plans]))
    batch.set_drive([p.hands(bat) for p in plans])
    for _ in range(plans[0].steps):
        batch.step()
    batch.set_drive(None)
    swung = batch.read()
    release = [(float(xp.row(swung, i)[g.BAT_W]), float(xp.row(swung, i)[g.BAT_ANGLE]))
               for i in range(len(plans))]
    return xp.with_bat(starts, swung), release


def _fired(host: Hosted, case: ImpactCase, start, episodes, i: int,
           release: tuple[float, float], plan: SwingPlan | None, wall_s: float) -> Fired:
    """One world's outcome, measured from its start and end states."""
    bat, ball = case.bat, case.ball
    end = [float(v) for v in episodes.end[i]]
    start = [float(v) for v in start]
    ke0, ke1 = g.kinetic_energy_j(bat, ball, start), g.kinetic_energy_j(bat, ball, end)
    first, last = episodes.first[i], episodes.last[i]
    status = classify(case, episodes.ended[i], first, episodes.peak_m[i], episodes.side_m[i],
                      ke0, ke1, host.record.eps,
                      host.settings)
    v1 = end[g.BALL_VY]
    du, dw = end[g.BAT_VY] - start[g.BAT_VY], end[g.BAT_W] - start[g.BAT_W]
    V = case.u0n_mps + case.omega0_radps * case.s_m
    out = SimOutcome(
        v1_mps=v1, u1_mps=end[g.BAT_VY], omega1_radps=end[g.BAT_W],
        impulse_ns=ball.mass_kg * (v1 + case.v0n_mps), q=(v1 - V) / (case.v0n_mps + V),
        closing_speed_mps=case.closing_speed_mps,
        hand_dv_mps=du + dw * (case.hands_from_knob_m - bat.com_from_knob_m),
        ke_before_j=ke0, ke_after_j=ke1, v1_t_mps=end[g.BALL_VX], u1_t_mps=end[g.BAT_VX],
        engine=host.name, status=status,
        contact_duration_s=(last - first + 1) * host.settings.dt_s if first >= 0 else 0.0,
        peak_penetration_m=episodes.peak_m[i],
        steps=episodes.steps[i] + (plan.steps if plan else 0), wall_s=wall_s,
        settings=host.settings, ended=episodes.ended[i], ball_side_m=episodes.side_m[i],
        release_omega_radps=release[0], release_angle_rad=release[1])
    return Fired(case, out, *_analytic_release(plan))


def _analytic_release(plan: SwingPlan | None) -> tuple[float, float]:
    return (math.nan, math.nan) if plan is None else (plan.omega_release_radps,
                                                      plan.angle_release_rad)


def _failed(host: Hosted, cases, plans, status: Status, why: str, t0: float) -> list[Fired]:
    """Every job of a batch with no measurement: ``status``, NaN numbers, ``ended`` = why."""
    wall = (time.perf_counter() - t0) / len(cases)
    nan = math.nan
    out = []
    for case, plan in zip(cases, plans or [None] * len(cases)):
        o = SimOutcome(v1_mps=nan, u1_mps=nan, omega1_radps=nan, impulse_ns=nan, q=nan,
                       closing_speed_mps=case.closing_speed_mps, hand_dv_mps=nan,
                       ke_before_j=nan, ke_after_j=nan, v1_t_mps=nan, u1_t_mps=nan,
                       engine=host.name, status=status, contact_duration_s=0.0,
                       peak_penetration_m=nan, steps=0, wall_s=wall, settings=host.settings,
                       ended=why, ball_side_m=nan)
        out.append(Fired(case, o, *_analytic_release(plan)))
    return out


def run_motion(name: str, settings: Settings, bat, drive, t_s: float,
               angle_rad: float = 0.0) -> MotionState:
    """Drive the bat alone (the ball parked far away) from rest at ``angle_rad`` for
    round(t/dt) steps under ``drive`` (an ``analytic.dynamics.Drive``), hinged at the world's
    origin if the drive has a pivot; the bat's state at the end, as ``analytic.dynamics``
    gives it."""
    from analytic import presets
    from analytic.dynamics import start_state as motion_start

    host = hosted(name, settings)
    batch = host.batch(Scene(bat=bat, ball=presets.BASEBALL, e=presets.E_WOOD), 1)
    s0 = motion_start(bat, drive, angle_rad)
    rest = State(ball_x_m=0.0, ball_y_m=PARKED_BALL_Y_M, ball_vx_mps=0.0, ball_vy_mps=0.0,
                 ball_omega_radps=0.0, bat_x_m=s0.x_m, bat_y_m=s0.y_m, bat_angle_rad=angle_rad,
                 bat_vx_mps=0.0, bat_vy_mps=0.0, bat_omega_radps=0.0)
    batch.set_state(batch.xp.stack([rest]))
    steps = round(t_s / settings.dt_s)
    batch.set_drive([hands_for(drive, bat)])
    for _ in range(steps):
        batch.step()
    batch.set_drive(None)
    r = [float(v) for v in batch.xp.row(batch.read(), 0)]
    return MotionState(t_s=steps * settings.dt_s, x_m=r[g.BAT_X], y_m=r[g.BAT_Y],
                       angle_rad=r[g.BAT_ANGLE], vx_mps=r[g.BAT_VX], vy_mps=r[g.BAT_VY],
                       omega_radps=r[g.BAT_W])
