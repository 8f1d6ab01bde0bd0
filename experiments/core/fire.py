"""Firing impacts in this process: jobs in, outcomes out, in order.

    fired = fire_jobs([Job(engine="mujoco", settings=s, case=c) for c in cases])

Each job is placed (``placement``), fired on the process's engine for its settings
(``hosting``), stepped through its episode (``episode``) and measured. A batched engine fires
each run of consecutive jobs that share a scene as one batch; a single-world engine fires them
one at a time, or, in a long run, on several of its adapters stepped together. Where the jobs
run is the runner's business (``experiments.core.runner``).
"""

from __future__ import annotations

import contextlib
import math
import time
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass
from itertools import compress, pairwise
from operator import attrgetter, ne
from types import SimpleNamespace

import numpy as np

import adapters
from adapters import ContactReference, Scene, Settings, clock
from analytic import ImpactCase
from analytic.dynamics import HingedSwing

from . import geometry as g
from . import watchdog
from .boundary import STOP
from .device_episode import observed_episodes
from .drive import swing_into_place
from .endings import LABELS, Physics, classify
from .fired import (
    Fired,
    FiredBlock,
    FiredSeq,
    NotFired,
    analytic_release,
    nan_release,
    outcome,
    unmeasured,
)
from .hosting import TIMEOUTS, Hosted, SceneMismatch, engine_settings, hosted
from .judge import energy_allowance
from .placement import (
    SwingPlan,
    case_columns,
    check_placements,
    distinct_cases,
    start_states,
    swing_case,
    take_rows,
)
from .worlds import OneWorld


@dataclass(frozen=True, kw_only=True)
class Job:
    """One impact to fire: which engine, with which settings, and, with ``swing``, the bat swung
    about the hands in the engine first (the case is then re-planned for the engine's step)."""

    engine: str
    settings: Settings
    case: ImpactCase
    swing: HingedSwing | None = None


class Jobs(Sequence):
    """Jobs that share engine, settings and swing, one per case (a grid, or a grid tiled over
    many worlds), held as their cases: ``runs`` knows them for one engine's run without a look
    at each job, and no ``Job`` is made per impact until one is asked for. ``distinct``: the
    distinct cases (``placement.distinct_cases``), where known."""

    def __init__(
        self,
        *,
        engine: str,
        settings: Settings,
        cases: Sequence[ImpactCase],
        swing: HingedSwing | None = None,
        distinct: tuple[np.ndarray, np.ndarray] | None = None,
    ) -> None:
        self.engine, self.settings, self.cases, self.swing = engine, settings, cases, swing
        self.distinct = distinct

    def __len__(self) -> int:
        return len(self.cases)

    def __getitem__(self, i):
        if isinstance(i, slice):
            return Jobs(
                engine=self.engine, settings=self.settings, cases=self.cases[i], swing=self.swing
            )
        return Job(engine=self.engine, settings=self.settings, case=self.cases[i], swing=self.swing)

    def known(self) -> Jobs:
        """These jobs with their distinct cases known (worked out once for a firing)."""
        return (
            self
            if self.distinct is not None
            else Jobs(
                engine=self.engine,
                settings=self.settings,
                cases=self.cases,
                swing=self.swing,
                distinct=distinct_cases(self.cases),
            )
        )

    def one_scene(self) -> bool:
        """Whether every case shares the scene (bat, ball, e, mu): a look at each distinct
        case object once, however often the grid is tiled."""
        first = (self.distinct or distinct_cases(self.cases))[0]
        return len({scene_key(self.cases[i]) for i in first}) == 1

    def __add__(self, other: Sequence[Job]) -> list[Job]:
        return [*self, *other]

    def __radd__(self, other: Sequence[Job]) -> list[Job]:
        return [*other, *self]


def fire_jobs(jobs: Sequence[Job], tick: Callable[[int], None] | None = None) -> FiredSeq:
    """Fire jobs in this process, in order: each run of consecutive jobs sharing engine,
    settings, scene and swing as one batch on a batched engine, and on a single-world one in
    batches of as many engines as the run repays (``Hosted.pool_size``).
    An engine that fails (raises, exits, hangs, holds another scene) fails its batch's rows,
    not the run (``guarded``)."""
    parts: list[Sequence[Fired]] = []
    for run in runs(jobs):
        for group, fired in _fired_batches(run):
            if isinstance(fired, FiredBlock) or not parts or isinstance(parts[-1], FiredBlock):
                parts.append(fired)
            else:
                parts[-1] += fired
            STOP.check()  # a signal an engine's callback swallowed
            if tick is not None:
                tick(len(group))
    return FiredSeq(parts)


def _fired_batches(run: Sequence[Job]):
    """Each batch of a run with what it gave (``guarded``); every job's row an error where
    the engine's adapter cannot even be made."""
    try:
        host = hosted(run[0].engine, run[0].settings)
    except (Exception, SystemExit) as err:  # noqa: BLE001 - any failure of the engine's
        yield run, _unmeasured(run, NotFired(Physics.ERROR, _why(err)), 0.0)
        return
    for group, placed in _groups(host, run):
        yield group, guarded(host, group, placed)


#: After this many timeouts in a row (in this process, ``hosting.TIMEOUTS``), an engine's
#: further batches are not fired: each would wait out its whole limit.
TIMEOUTS_IN_A_ROW = 2


def guarded(host: Hosted, jobs: Sequence[Job], placed: Placed | None = None) -> Sequence[Fired]:
    """``fire_group`` within the engine's wall-clock limit (``watchdog``), whatever the engine
    does: past the limit its batch's rows are 'timeout'; where it raised, called sys.exit or
    holds mass properties other than the scene's, 'error' (``ended`` says which), and its
    adapters are made anew for the next batch; where it cannot fire them, 'unsupported'."""
    t0 = time.perf_counter()
    limit = watchdog.limit_s(
        host.record, host.settings, len(jobs), _swing_steps(host, jobs), batched=host.batched
    )
    try:
        if (timeouts := TIMEOUTS.get(host.name, 0)) >= TIMEOUTS_IN_A_ROW:
            raise NotFired(
                Physics.TIMEOUT, f"not fired: {host.name} timed out {timeouts} times in a row"
            )
        with clock.limited(limit), clock.exits_raise():
            host.renew_if_failed()
            fired = fire_group(host, jobs, placed)
        host.succeeded()
        return fired
    except NotFired as err:
        failure = err
    except CaseError:
        raise
    except clock.TimedOut:
        host.failed(timed_out=True)
        failure = NotFired(Physics.TIMEOUT, f"timeout: no result within {limit:.3g} s")
    except KeyboardInterrupt as err:  # the user's Ctrl-C stops the run; the engine's own is
        if not STOP.active or STOP.signum is not None:  # its failure
            raise
        host.failed()
        failure = NotFired(Physics.ERROR, _why(err))
    except (Exception, SystemExit, clock.ProcessExit) as err:  # noqa: BLE001 - any failure
        host.failed()
        failure = NotFired(Physics.ERROR, _why(err))
    return _unmeasured(jobs, failure, time.perf_counter() - t0)


def _why(err: BaseException) -> str:
    """What an engine's failure was, for its rows' ``ended``."""
    if isinstance(err, SystemExit | clock.ProcessExit):
        call = "sys.exit" if isinstance(err, SystemExit) else "os._exit"
        return f"error: the engine called {call}({err.code!r})"
    if isinstance(err, KeyboardInterrupt):
        return "error: the engine raised KeyboardInterrupt (no Ctrl-C was pressed)"
    if isinstance(err, SceneMismatch):
        return f"error: scene mismatch: {err}"[:200]
    return f"error: {err!r}"[:200]


def _swing_steps(host: Hosted, jobs: Sequence[Job]) -> int:
    swing = jobs[0].swing
    return (
        0 if swing is None else math.ceil(swing.duration_s(jobs[0].case.bat) / host.settings.dt_s)
    )


def _unmeasured(jobs: Sequence[Job], failure: NotFired, wall_s: float) -> list[Fired]:
    """The rows of a batch that ``failure`` stopped (its re-planned cases, where it has them)."""
    cases, each, _ = _cases(jobs)
    return unmeasured(
        jobs[0].engine,
        failure.cases or cases,
        each,
        failure.plans,
        failure.physics,
        failure.why,
        wall_s / len(cases),
    )


def _groups(host: Hosted, run: Sequence[Job]):
    """The batches a run is fired in, each with its rows of the run's ``Placed`` (or None):
    one on a batched engine; on a single-world one, as many engines at a time as the rest of
    the run repays, the run placed once for all its batches of several worlds (but under a
    swing, which re-plans each case: its batches place theirs). A run's swings last alike
    (one swing, bat and step), each world's about hands of its own."""
    if host.batched:
        yield run, None
        return
    at, placed = 0, None
    while at < len(run):
        size = host.pool_size(len(run), len(run) - at)
        if size > 1 and placed is None and run[0].swing is None:
            placed = Placed.of(host, run)
        yield run[at : at + size], placed and placed.rows(at, size)
        at += size


@dataclass(frozen=True, kw_only=True)
class Placed:
    """Jobs' case columns (``case_columns``, with each job's ``contact_phase``) and start
    states, worked out once for a run and taken by rows for each of its batches."""

    cc: SimpleNamespace
    starts: np.ndarray

    @classmethod
    def of(cls, host: Hosted, jobs: Sequence[Job]) -> Placed:
        cases, each, distinct = _cases(jobs)
        cc = case_columns(g.ARRAYS, cases, distinct)
        cc.contact_phase = _contact_phase(each)
        return cls(
            cc=cc, starts=start_states(g.ARRAYS, cases[0].bat, cases[0].ball, cc, host.settings)[0]
        )

    def rows(self, at: int, n: int) -> Placed:
        return Placed(cc=take_rows(self.cc, slice(at, at + n)), starts=self.starts[at : at + n])


def _cases(jobs: Sequence[Job]) -> tuple[list, list, tuple | None]:
    """The jobs' cases, settings, and distinct cases where known."""
    if isinstance(jobs, Jobs):
        return list(jobs.cases), [jobs.settings] * len(jobs), jobs.distinct
    return [j.case for j in jobs], [j.settings for j in jobs], None


def _contact_phase(each: list[Settings]):
    return (
        each[0].contact_phase
        if each.count(each[0]) == len(each)
        else np.array([k.contact_phase for k in each])
    )


#: What the jobs of one batch share: engine, settings, swing, bat, ball, e and mu (equal tuples
#: compare their shared objects by identity first, so a grid's jobs compare fast).
batch_key = attrgetter("engine", "settings", "swing", "case.bat", "case.ball", "case.e", "case.mu")
#: What the cases of one batch share.
scene_key = attrgetter("bat", "ball", "e", "mu")


def runs(jobs: Sequence[Job]) -> list[Sequence[Job]]:
    """A batched engine's batches: consecutive jobs that share engine, settings, scene and
    swing, those of one engine differing only in ``contact_phase`` joined into one."""
    if not jobs:
        return []
    if isinstance(jobs, Jobs) and (jobs := jobs.known()).one_scene():
        return [jobs]
    keys = list(map(batch_key, jobs))
    cuts = [0, *compress(range(1, len(keys)), map(ne, keys[1:], keys)), len(keys)]
    spans: list[list[int]] = []  # [first, end) of each batch: joined runs are consecutive
    last = None
    for a, b in pairwise(cuts):
        j = jobs[a]
        key = (j.engine, engine_settings(j.engine, j.settings), *keys[a][2:])
        if key == last and adapters.record(j.engine).batched:
            spans[-1][1] = b
        else:
            spans.append([a, b])
        last = key
    return [jobs[a:b] for a, b in spans]


def fire_group(host: Hosted, jobs: Sequence[Job], placed: Placed | None = None) -> Sequence[Fired]:
    """Fire jobs that share engine, settings, scene and swing as one batch (module docstring):
    a ``FiredBlock`` on a batched engine, a list of one ``Fired`` on a single-world one.
    ``placed``: the jobs' ``Placed``, where their run worked it out."""
    t0 = time.perf_counter()
    st = host.settings
    plans: list[SwingPlan] | None = None
    cases, each, distinct = _cases(jobs)
    if jobs[0].swing is not None:
        with _harness():
            planned = [
                swing_case(
                    c.bat,
                    c.ball,
                    s_m=c.s_m,
                    v0_mps=c.v0_mps,
                    e=c.e,
                    swing=jobs[0].swing,
                    settings=k,
                    mu=c.mu,
                    undercut_m=c.undercut_m,
                    spin_radps=c.spin_radps,
                )
                for c, k in zip(cases, each)
            ]
        cases, plans = [p[0] for p in planned], [p[1] for p in planned]
    bat, ball = cases[0].bat, cases[0].ball
    xp = g.ARRAYS if host.batched or len(cases) > 1 else g.SCALARS
    # a swing re-plans every case: the jobs' distinct cases are not the fired ones
    distinct = distinct if plans is None else None
    if placed is None or xp is not g.ARRAYS:  # (placed here: one world, or a batched engine)
        cc, placed = case_columns(xp, cases, distinct), None
        cc.contact_phase = _contact_phase(each)
    else:
        cc = placed.cc
    t = cc.turned  # ImpactCase.out_of_plane, over the columns
    spatial = t is not None and bool(
        np.any((t.undercut_m != 0.0) | (t.spin_x != 0.0) | (t.spin_y != 0.0))
    )
    lacking = _lacking(host.record, cases[0].mu, spatial)
    if lacking:
        raise NotFired(Physics.UNSUPPORTED, lacking, cases, plans)
    try:
        batch = host.batch(Scene(bat=bat, ball=ball, e=cases[0].e, mu=cases[0].mu), len(cases))
    except adapters.MissingFeature as err:  # an older release of the engine (history)
        raise NotFired(Physics.UNSUPPORTED, str(err)[:200], cases, plans) from None
    with _harness():
        check_placements(xp, cases, cc, each)
        starts = start_states(xp, bat, ball, cc, st)[0] if placed is None else placed.starts
    release = xp.full(len(cases), math.nan), xp.full(len(cases), math.nan)
    try:
        if plans is not None:
            starts, release = swing_into_place(batch, plans, starts, bat)
        rigid = host.record.errors.contact_reference(st) is ContactReference.RIGID_IMPULSE
        episodes = observed_episodes(batch, bat, ball, st, starts, spatial, rigid)
    except NotImplementedError:  # an engine that cannot drive the bat
        raise NotFired(Physics.UNSUPPORTED, "no set_drive", cases, plans) from None
    except Exception as err:  # the engine raised while stepping: a failure, not a crash
        raise NotFired(Physics.ERROR, f"error: {err!r}"[:200], cases, plans) from err
    cols = _measure(xp, host, cc, starts, episodes, bat, ball, spatial)
    cols["release_omega_radps"], cols["release_angle_rad"] = release
    cols["steps"] = cols["steps"] + (plans[0].steps if plans else 0)
    wall = (time.perf_counter() - t0) / len(cases)
    if isinstance(batch, OneWorld):
        return [
            Fired(
                cases[0],
                outcome(cols, None, engine=host.name, settings=st, wall_s=wall),
                *analytic_release(plans[0] if plans else None),
            )
        ]
    cols.update(
        nan_release(len(cases))
        if plans is None
        else {
            "release_omega_analytic_radps": np.array([p.omega_release_radps for p in plans]),
            "release_angle_analytic_rad": np.array([p.angle_release_rad for p in plans]),
        }
    )
    return FiredBlock(cases, cols, engine=host.name, settings=each, wall_s=wall, distinct=distinct)


class CaseError(ValueError):
    """An impact the harness cannot plan or place: the caller's input, not the engine's doing
    (raised, never made a row)."""


@contextlib.contextmanager
def _harness() -> Iterator[None]:
    """The harness's own part of a batch (planning a swing, placing the worlds): a ValueError
    there is a ``CaseError``."""
    try:
        yield
    except CaseError:
        raise
    except ValueError as err:
        raise CaseError(str(err)) from err


def _measure(xp, host: Hosted, cc, start, ep, bat, ball, spatial: bool) -> dict:
    """Every world's outcome, measured from its start and end states, as columns named as
    ``SimOutcome``'s fields (``q`` is (v1 - V)/(v0n + V), V = u0n + omega0 s)."""
    S0, S1 = xp.cols(start), ep.end
    energy = g.kinetic_energy_3d if spatial else g.kinetic_energy_j
    ke0, ke1 = energy(bat, ball, S0), energy(bat, ball, S1)
    v1, u1, w1 = S1[g.BALL_VY], S1[g.BAT_VY], S1[g.BAT_W]
    V = cc.u0n_mps + cc.omega0_radps * cc.s_m
    allowance = energy_allowance(host.record.errors, host.settings)
    return {
        "v1_mps": v1,
        "u1_mps": u1,
        "omega1_radps": w1,
        "impulse_ns": ball.mass_kg * (v1 + cc.v0n_mps),
        "q": (v1 - V) / (cc.v0n_mps + V),
        "closing_speed_mps": cc.closing_speed_mps,
        "hand_dv_mps": (u1 - S0[g.BAT_VY])
        + (w1 - S0[g.BAT_W]) * (cc.hands_from_knob_m - bat.com_from_knob_m),
        "ke_before_j": ke0,
        "ke_after_j": ke1,
        "v1_t_mps": S1[g.BALL_VX],
        "u1_t_mps": S1[g.BAT_VX],
        "physics": classify(
            xp,
            ep.ended,
            ep.first,
            ep.peak_m,
            ep.side_m,
            bat.radius_m + ball.radius_m,
            ke0,
            ke1,
            allowance,
        ),
        "contact_duration_s": xp.where(
            ep.first >= 0, (ep.last - ep.first + 1) * host.settings.dt_s, 0.0
        ),
        "peak_penetration_m": ep.peak_m,
        "steps": ep.steps,
        "ended": LABELS[ep.ended],
        "ball_side_m": ep.side_m,
        "v1_z_mps": S1[g.BALL_VZ],
        "spin1_radps": S1[g.BALL_W],
        "backspin1_radps": S1[g.BALL_WX],
    }


def _lacking(record: adapters.EngineRecord, mu: float, spatial: bool) -> str:
    """What the engine lacks for these impacts ('' for nothing): friction, or a third
    dimension for an impact out of the swing plane."""
    if spatial and record.can.planar:
        return "planar engine: the impact leaves the swing plane"
    if mu > 0.0 and record.can.friction_rule is None:
        return "no friction in the adapter"
    return ""
