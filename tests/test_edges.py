"""Verdicts at the edges: every engine at time steps from 1e-12 to 1 s, reference and default
profiles. No row may be ``tunnelled`` unless the ball really went through the bat, nor ``ok``
unless it came back off it matching the answer, judged here against the engine's own
trajectory (read after every step, apart from the harness's episode): a reset of the state
(MuJoCo puts a blown-up world back at its model's pose) is never mistaken for either. A step
too small to place the impact is refused before any work (the sweep names the smallest that
works). The bodies' centres may move at most twice their larger speed over a step plus 1 cm
(a position correction, never a reset). Each impact may hold its contact CONTACT_STEPS steps
(at most the profile's ``max_contact_s``): some engines hold a contact until that limit at
tiny steps (PyBullet's default slop), which would take hours at 1e-10 s."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

import adapters
from analytic import ImpactCase, presets
from experiments.core import Job, Status, judge, tables, terms
from experiments.core.fire import guarded
from experiments.core.hosting import Hosted
from experiments.core.placement import min_dt_s

pytestmark = pytest.mark.full
STEPS_S = tuple(float(x) for x in np.geomspace(1e-12, 1.0, 13))
CONTACT_STEPS = 5000
CASES = [
    ImpactCase(
        bat=presets.R161,
        ball=presets.BASEBALL,
        s_m=s,
        v0_mps=46.9,
        u0_mps=17.87,
        omega0_radps=32.0,
        e=0.5,
    )
    for s in (-0.2, 0.1)
]
REACH_M = presets.R161.radius_m + presets.BASEBALL.radius_m
SLACK_M = 0.01


class Recorder:
    """A single-world adapter that also watches its state after every step: the side the ball
    is on at the start and at the end, and whether any step jumped (``_continuous``)."""

    def __init__(self, engine) -> None:
        self.engine = engine

    def __getattr__(self, name):
        return getattr(self.engine, name)

    def set_state(self, state) -> None:
        self.engine.set_state(state)
        self.first = self.last = np.array(state, dtype=float)
        self.continuous = True

    def step(self) -> None:
        self.engine.step()
        now = np.array(self.engine.read(), dtype=float)
        self.continuous &= _continuous(self.last, now, self.settings.dt_s)
        self.last = now

    def side_m(self) -> tuple[float, float]:
        """The ball centre's distance from the bat's axis line at the start and at the end, +
        on the side it came from (the line turns with the bat: its normal is the bat's)."""
        start, end = (
            float((s[1] - s[6]) * np.cos(s[7]) - (s[0] - s[5]) * np.sin(s[7]))
            for s in (self.first, self.last)
        )
        return abs(start), end * math.copysign(1.0, start)


def _continuous(before: np.ndarray, after: np.ndarray, dt_s: float) -> bool:
    """No body's centre moved farther in a step than twice its larger speed allows + SLACK_M."""
    for x, v in ((slice(0, 2), slice(2, 4)), (slice(5, 7), slice(8, 10))):
        moved = math.hypot(*(after[x] - before[x]))
        speed = max(math.hypot(*before[v]), math.hypot(*after[v]))
        if moved > 2 * speed * dt_s + SLACK_M:
            return False
    return True


#: Steps at which every engine's reference profile is built to be accurate (its working range):
#: every impact there comes back ok.
WORKING_S = (1e-6, 1e-3)
#: What a contact first seen deeper than REACH_M can end as (the ball's centre is past the bat's
#: axis: nothing sound can push it back out the way it came).
PAST_THE_AXIS = {
    Status.TUNNELLED,
    Status.NO_CONTACT,
    Status.PENETRATION,
    Status.NON_FINITE,
    Status.ENERGY_GAINED,
}


@pytest.mark.parametrize("profile", adapters.PROFILES)
@pytest.mark.parametrize("name", [n for n in adapters.names() if not adapters.record(n).batched])
def test_no_false_tunnelled_or_ok_from_1e12_to_1_s(name, profile):
    for dt in STEPS_S:
        st = adapters.settings_for(name, profile, dt_s=dt)
        st = replace(st, max_contact_s=min(st.max_contact_s, CONTACT_STEPS * dt))
        # placed approach_steps steps before a contact first seen overlap_m deep: below that
        # the bodies would start inside each other, and the sweep refuses the step
        unplaceable = any(
            c.closing_speed_mps * dt * (st.approach_steps - st.contact_phase) <= st.overlap_m
            for c in CASES
        )
        assert unplaceable == (dt <= max(min_dt_s(c, st) for c in CASES)), dt
        if unplaceable:
            continue
        host = Hosted(name, st)
        host.adapter = Recorder(host.adapter)
        try:
            for case in CASES:
                row = tables.table(
                    guarded(host, [Job(engine=name, settings=st, case=case)]), profile
                ).iloc[0]
                _judge_row(row, host.adapter, dt)
                # first seen deeper than r_ball + r_bat: the tunnelling bound
                if st.overlap_m + st.contact_phase * case.closing_speed_mps * dt > REACH_M:
                    assert row.status in PAST_THE_AXIS, (name, dt, row.status)
                elif profile == "reference" and WORKING_S[0] <= dt <= WORKING_S[1]:
                    assert row.status == Status.OK, (name, dt, case.s_m, row.status)
        finally:
            host.close()
    assert STEPS_S[0] <= max(min_dt_s(c, st) for c in CASES)  # 1e-12 s cannot be placed


def _judge_row(row, rec: Recorder, dt_s: float) -> None:
    start, end = rec.side_m()
    where = f"{row.engine} dt={dt_s:g} s={row.s_m}: {row.status} ({row.episode_end})"
    if row.status == Status.TUNNELLED:
        assert rec.continuous, f"{where}: the state jumped"
        assert end < 0.0, f"{where}: the ball did not pass through ({start:.3g} -> {end:.3g} m)"
    if row.status == Status.OK:
        assert rec.continuous, f"{where}: the state jumped"
        assert end > 0.0, f"{where}: the ball ended beyond the bat"
        err, tol = (
            (row.v1_abs_err_mps, row.v1_tol_mps)
            if math.isfinite(row.v1_tol_mps)
            else (row.v1_law_err_mps, row.v1_law_tol_mps)
        )
        assert err <= tol, f"{where}: v1 off by {err:.3g} > {tol:.3g}"
    if row.status == Status.NO_CONTACT:
        assert end > 0.0, f"{where}: the ball passed through ({start:.3g} -> {end:.3g} m)"
        dv = math.hypot(*(rec.last[2:4] - rec.first[2:4]))
        # no_contact: the judge's own line between a ball flying past and one it deflected
        assert dv <= terms.DEFLECTED * math.hypot(*rec.first[2:4]), (
            f"{where}: the ball was deflected by {dv:.3g} m/s"
        )


@pytest.mark.parametrize("name", [n for n in adapters.names() if not adapters.record(n).batched])
def test_a_contact_between_two_readings_is_judged_not_missed(name):
    """A slow ball (5 m/s) on a still bat at steps of 1.5-7.4 ms, the contact instant anywhere
    in the step: a contact shorter than a step (a compliant one) may begin and end between two
    readings; the ball's changed velocity says it happened."""
    case = ImpactCase(bat=presets.R161, ball=presets.BASEBALL, s_m=0.1, v0_mps=5.0, e=0.5)
    for dt in (1.46685e-3, 3.298e-3, 7.414e-3):
        for phase in judge.phases(16):
            st = adapters.settings_for(name, dt_s=dt, contact_phase=float(phase))
            host = Hosted(name, st)
            host.adapter = Recorder(host.adapter)
            try:
                row = tables.table(
                    guarded(host, [Job(engine=name, settings=st, case=case)]), "reference"
                ).iloc[0]
                _judge_row(row, host.adapter, dt)
                # seen at most phase v dt + overlap_m = 37 mm deep, inside the 66.6 mm reach:
                # caught, and judged ok within its tolerance (_judge_row)
                assert phase * case.v0_mps * dt + st.overlap_m < REACH_M
                assert row.status == Status.OK, (name, dt, phase, row.status, row.episode_end)
            finally:
                host.close()
