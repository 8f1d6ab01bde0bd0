"""The impact episode: step a batch of worlds from their start states until each impact is over,
then classify how it ended. One path for every engine: single-world engines are a batch of one
(``OneWorld``, in Python floats) or of several engines stepped in turn (``EngineWorlds``).

Every episode the harness steps, of any kind of world, runs through one loop,
``run_episode``; what it is for (when it is over, what it measures) is its task's: the
impact's (``_Stepper``), the segmented bat's (``chain``), a swing's or a drive's (``Coast``).

The worlds it steps are the engine seen as a batch (``worlds``).

An impact's episode ends as ``analytic.collide`` ends the rigid one: the bodies apart with no
contact to come in free flight (``analytic.collide.free_flight``), the ball off the cylinder's
span, or ``max_contact_s`` of episode spent (the budget). How it ended (``ended``) decides the
status: 'non_finite' (NaN or inf, a failure the engine reported) and 'jumped' (a state that
moved more than its speeds allow: a silent reset) are ``non_finite``; 'passed' (no contact seen
when due, the ball's centre beyond the bat's axis) is ``tunnelled``; 'missed' (no contact seen
when due, the ball still on its side, its velocity as it was) is ``no_contact``; a ball
deflected between two readings had its contact then (``terms.DEFLECTED``); 'budget' is
``no_separation`` (or ``tunnelled`` without a contact); 'contact_flag' (the adapter said the
bodies touch while its own state has them a contact reach apart: ``terms.FLAG_REACHES``) is
``error``; after 'separated' or 'left_cylinder' the
final state is checked: beyond the bat's axis ``tunnelled``, deeper than r_ball + r_bat at any
step ``penetration``, more kinetic energy than before ``energy_gained``, else ``ok`` (the judge
may still find it inaccurate).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Protocol

from adapters import Settings
from analytic import Ball, Bat, Outcome

from . import geometry as g
from .endings import Ending, Physics
from .terms import DEFLECTED, FLAG_REACHES, JUMP_REACHES, OFF_SPAN_STEPS


@dataclass(frozen=True, kw_only=True)
class SimOutcome(Outcome):
    """An engine's outcome: the fields of ``analytic.Outcome`` measured from the engine, plus how
    the episode went. Units: s, m, and as in ``Outcome``; NaN where not measurable.

    ``q`` is measured as (v1 - V)/(v0n + V), V = u0n + omega0 s, the inverse of
    v1 = q v0n + (1 + q) V; ``impulse_ns`` is the ball's momentum change m (v1 + v0n).
    ``ended``: how stepping ended (module docstring); ``ball_side_m``: the ball centre's
    distance from the bat's axis line at the end, positive on the side it came from.
    """

    engine: str
    physics: Physics
    contact_duration_s: float
    peak_penetration_m: float
    steps: int
    wall_s: float
    settings: Settings
    ended: str
    ball_side_m: float
    #: With a swing before the impact: the engine's bat at release (rad/s, rad); NaN without.
    release_omega_radps: float = math.nan
    release_angle_rad: float = math.nan
    #: The ball after the impact, out of the swing plane: its velocity along z (m/s), its spin
    #: about z (the swing plane's: in-plane friction's) and about x (backspin: +x lifts a ball
    #: leaving along +y) (rad/s).
    v1_z_mps: float = math.nan
    spin1_radps: float = math.nan
    backspin1_radps: float = math.nan

    @property
    def sound(self) -> bool:
        """True when the outcome is physically sound: v1 is a measurement the judge can hold."""
        return self.physics is Physics.SOUND


@dataclass
class Episodes:
    """The end of each world's episode, in the batch's namespace (an array of n values, or one
    value for one world): how it ended (``Ending``), the steps it took, the state then (its
    ``columns``), the first and last step that saw the contact (-1: none), the deepest
    penetration (m), and the ball centre's side of the bat's axis then (m, positive on the
    side it came from)."""

    ended: object
    steps: object
    end: object
    first: object
    last: object
    peak_m: object
    side_m: object


class Task(Protocol):
    """What an episode is for (dm_control's split: the loop steps, the task judges): after
    each step it looks at the world as it needs and says whether the episode is over; if the
    steps run out first, it is told so."""

    def over(self, step: int, world) -> bool: ...

    def budget_spent(self, world) -> None: ...


class Coast:
    """A task that only steps: a swing into place, a drive for a set time."""

    def over(self, step: int, world) -> bool:
        return False

    def budget_spent(self, world) -> None:
        pass


class Recorder(Coast):
    """A task that reads the world after every step (``record(world)``), to the end."""

    def __init__(self, record) -> None:
        self.record = record

    def over(self, step: int, world) -> bool:
        self.record(world)
        return False


def run_episode(world, task: Task, max_steps: int) -> int:
    """The harness's one stepping loop, for every kind of world (one engine, a batch of them,
    a batched engine, a segmented bat): step ``world`` until ``task`` says the episode is over
    or ``max_steps`` have run (then ``task.budget_spent``). Returns the steps taken."""
    for step in range(1, max_steps + 1):
        world.step()
        if task.over(step, world):
            return step
    task.budget_spent(world)
    return max_steps


class _Stepper:
    """Steps one batch through its episodes; what it has learnt of each world so far, in the
    batch's namespace (``geometry.ARRAYS`` or ``geometry.SCALARS``): no loop over worlds but
    for the rare free-flight search."""

    def __init__(
        self, batch, bat: Bat, ball: Ball, settings: Settings, spatial: bool, rigid: bool
    ) -> None:
        self.batch, self.xp, self.bat, self.ball, self.st = batch, batch.xp, bat, ball, settings
        # out of the swing plane: the 3D measures (geometry module docstring)
        self.spatial = spatial
        self.geometry = g.contact_geometry_3d if spatial else g.contact_geometry
        self.jumped = g.jumped_3d if spatial else g.jumped
        xp, n = self.xp, batch.n
        self.max_steps = (
            settings.approach_steps + math.ceil(settings.max_contact_s / settings.dt_s) + 2
        )
        # a rigid contact slides off the cylinder's end only in sustained contact, as in
        # collide; a soft one may be milliseconds long and slide past it within one impact
        self.rigid = rigid
        self.limit_m = JUMP_REACHES * (bat.radius_m + ball.radius_m)
        self.flag_gap_m = FLAG_REACHES * (bat.radius_m + ball.radius_m)
        self.first, self.last = xp.full(n, -1), xp.full(n, -1)
        self.peak, self.off_steps = xp.full(n, -math.inf), xp.full(n, 0)
        self.active, self.prev_step = xp.full(n, True), xp.full(n, 0)
        self.check_at, self.ends = xp.full(n, 0), []  # ends: (mask, reading) per finish
        self.ended_now = False  # whether a world's episode ended at this step's reading

    def run(self, starts) -> Episodes:
        """Step from ``starts`` until every world's episode is over (module docstring)."""
        batch, xp, n = self.batch, self.xp, self.batch.n
        self.prev = cols = xp.columns(starts)
        self.out = Episodes(
            ended=xp.full(n, Ending.NONE),
            steps=xp.full(n, self.max_steps),
            end=cols,
            first=None,
            last=None,
            peak_m=None,
            side_m=xp.full(n, math.nan),
        )
        self.came_from = xp.where(g.side_of_axis(xp, cols) < 0.0, -1.0, 1.0)
        vx0, vy0 = cols[g.BALL_VX], cols[g.BALL_VY]
        self.ball_v0 = (vx0, vy0, DEFLECTED**2 * (vx0 * vx0 + vy0 * vy0))
        batch.set_state(starts)
        run_episode(batch, self, self.max_steps)
        o = self.out
        o.ended = xp.where(batch.failed(), Ending.NON_FINITE, o.ended)
        o.first, o.last, o.peak_m = self.first, self.last, self.peak
        o.end = xp.ended_at(o.end, self.ends)
        return o

    def over(self, step: int, batch) -> bool:
        """One step's look (``run_episode``): whether every world's episode is over. Free
        flight before the planned contact step cannot go wrong but by a blow-up, which the
        final reading still catches: the state is read from that step on."""
        xp = self.xp
        if (
            step < self.st.approach_steps
            and not xp.any(self.first >= 0)
            and not batch.any_contact()
        ):
            return False
        self.observe(step, batch.in_contact(), self.xp.columns(batch.read()))
        if self.ended_now:  # stepped no further (``BatchedEngine.retire``): read as they end
            batch.retire(xp.not_(self.active))
            self.ended_now = False
        return not xp.any(self.active)

    def budget_spent(self, batch) -> None:
        """The budget ran out: the last reading ends every episode still going."""
        xp = self.xp
        if not xp.any(self.active):
            return
        S = xp.columns(batch.read())
        finite = xp.finite(S)
        self.finish(xp.not_(finite), Ending.NON_FINITE, self.max_steps, S)
        if not xp.any(self.active):
            return
        pen, _, _, side = self.geometry(xp, self.bat, self.ball, S, self.came_from)
        self.peak = xp.where(self.active, xp.maximum(self.peak, pen), self.peak)
        self.finish(self.active, Ending.BUDGET, self.max_steps, S, side)

    def finish(self, mask, why: Ending, step: int, S, side=None) -> None:
        """End the episodes of the worlds in ``mask`` (still active) with this reading
        (``S``: its columns)."""
        xp, o = self.xp, self.out
        m = mask & self.active
        if not xp.any(m):
            return
        o.ended, o.steps = xp.where(m, why, o.ended), xp.where(m, step, o.steps)
        if self.ends and self.ends[-1][1] is S:  # (one reading's ends as one: fewer copies)
            self.ends[-1] = (self.ends[-1][0] | m, S)
        else:
            self.ends.append((m, S))
        if side is not None:
            o.side_m = xp.where(m, side, o.side_m)
        self.active = self.active & xp.not_(m)
        self.ended_now = True
        if why in (Ending.NON_FINITE, Ending.JUMPED):
            self.peak = xp.where(m, math.nan, self.peak)

    def observe(self, step: int, touching, S) -> None:
        """One step's reading (``S``: its columns): failures, the contact's first and last
        steps, how it ends."""
        xp, st, no = self.xp, self.st, self.xp.not_
        look = self.active & (touching | (self.first >= 0) | (step >= st.approach_steps))
        finite = xp.finite(S)
        self.finish(look & no(finite), Ending.NON_FINITE, step, S)
        jumped = self.jumped(xp, self.prev, S, (step - self.prev_step) * st.dt_s, self.limit_m)
        self.finish(look & finite & jumped, Ending.JUMPED, step, S)
        ok = look & finite & no(jumped)
        if not xp.any(ok):
            return
        self.prev = xp.pick(ok, S, self.prev)
        self.prev_step = xp.where(ok, step, self.prev_step)
        pen, apart, off_span, side = self.geometry(xp, self.bat, self.ball, S, self.came_from)
        self.peak = xp.where(ok, xp.maximum(self.peak, pen), self.peak)
        self.flag_check(ok & touching & (pen < -self.flag_gap_m), step, S, pen, side)
        # a contact that began and ended between two readings shows in the ball's velocity
        vx0, vy0, limit2 = self.ball_v0
        dvx, dvy = S[g.BALL_VX] - vx0, S[g.BALL_VY] - vy0
        deflected = dvx * dvx + dvy * dvy > limit2  # |v - v0| > DEFLECTED |v0|, squared
        t = ok & (touching | (deflected & (self.first < 0)))
        self.first = xp.where(t & (self.first < 0), step, self.first)
        self.last = xp.where(t, step, self.last)
        self.off_steps = xp.where(
            t, xp.where(self.rigid & (off_span > 0.0), self.off_steps + 1, 0), self.off_steps
        )
        self.finish(t & (self.off_steps > OFF_SPAN_STEPS), Ending.LEFT_CYLINDER, step, S, side)
        self.flight_end(ok & no(touching) & (self.first >= 0), step, S, apart, off_span, side)
        due = ok & no(touching) & (self.first < 0) & (step > st.approach_steps + 1)
        self.finish(due & (side <= 0.0), Ending.PASSED, step, S, side)
        self.finish(due & (side > 0.0), Ending.MISSED, step, S, side)

    def flag_check(self, far, step: int, S, pen, side) -> None:
        """The passive check of the adapter's contact flag: a contact it reports (``far``)
        while its own state has the surfaces a contact reach apart (``terms.FLAG_REACHES``) and
        more than twice as far as they can move apart in a step (its flag may be the step's
        start's, its state the end's) ends the episode as 'contact_flag'."""
        xp = self.xp
        if not xp.any(far):
            return
        arm = max(abs(self.bat.s_min_m), abs(self.bat.s_max_m)) + self.bat.radius_m
        speeds = (
            xp.hypot(S[g.BALL_VX], S[g.BALL_VY])
            + xp.hypot(S[g.BAT_VX], S[g.BAT_VY])
            + abs(S[g.BALL_VZ])
            + abs(S[g.BAT_VZ])
            + abs(S[g.BAT_W]) * arm
        )
        moved = 2.0 * self.st.dt_s * speeds
        self.finish(far & (pen < -(self.flag_gap_m + moved)), Ending.CONTACT_FLAG, step, S, side)

    def flight_end(self, after, step: int, S, apart, off_span, side) -> None:
        """After contact, the worlds whose bodies do not touch: the episode ends as
        ``analytic.collide`` would end it from this state, off the cylinder's span or apart for
        good (``separates_for_good``, a few float operations), else, where a free-flight search
        is due, when ``free_flight`` says (it predicted a contact: searched again near it)."""
        xp, bat, ball, no = self.xp, self.bat, self.ball, self.xp.not_
        if not xp.any(after):  # (the contact goes on everywhere: nothing to look for)
            return
        self.finish(after & (off_span > 0.0), Ending.LEFT_CYLINDER, step, S, side)
        after = after & self.active & apart
        t_left, dt = (self.max_steps - step) * self.st.dt_s, self.st.dt_s
        # out of the plane there is no cheap bound: the 3D search decides (``analytic.spatial``)
        gone = after & (
            False
            if self.spatial
            else xp.separates(
                S, reach_m=bat.radius_m + ball.radius_m, ball_radius_m=ball.radius_m, t_max_s=t_left
            )
        )
        self.finish(gone, Ending.SEPARATED, step, S, side)
        search = after & no(gone) & (self.check_at <= step)
        if not xp.any(search):
            return
        kw = dict(
            reach_m=bat.radius_m + ball.radius_m,
            ball_radius_m=ball.radius_m,
            s_min_m=bat.s_min_m,
            s_max_m=bat.s_max_m,
            t_max_s=t_left,
        )
        t, ahead, left = (
            g.free_flights_3d(xp, S, search, **kw)
            if self.spatial
            else xp.free_flights(S, search, **kw)
        )
        self.finish(search & left, Ending.LEFT_CYLINDER, step, S, side)
        self.finish(search & no(ahead), Ending.SEPARATED, step, S, side)
        self.check_at = xp.where(
            search & ahead, step + xp.maximum(1, xp.floor(t / dt) - 1), self.check_at
        )


def step_episodes(
    batch,
    bat: Bat,
    ball: Ball,
    settings: Settings,
    starts,
    spatial: bool = False,
    rigid: bool = True,
) -> Episodes:
    """Step every world of ``batch`` (a ``OneWorld`` or ``ManyWorlds``) from its start until
    its episode is over (module docstring); ``spatial``: measured in 3D (out of the plane);
    ``rigid``: the contact converges to a rigid impulse (``ErrorModel.contact_reference``)."""
    return _Stepper(batch, bat, ball, settings, spatial, rigid).run(starts)
