"""Fuzz: every engine at its reference profile, over random impacts, lands within the tolerance
each row is judged against (experiments.core.judge) of the rigid-body answer, or, for a compliant
contact, of its own contact law.

The tolerance is derived, not fitted (rounding at the engine's precision, the contact foot's
slide while the turning bat is first seen overlap_m deep); if it were too tight, or an engine
wrong somewhere in this space, a draw would come back `inaccurate` or failed. e runs over
[0, 1]: the answer is the whole rigid episode (analytic.collide), which for small e holds
re-contacts and sustained sliding contact; an engine still touching at the end of its budget
is right only where the rigid episode is too ('time_limit'). Closing speeds
are kept at 20 m/s and above, the bat-ball regime (slow pitches and swings give 30-60): below it
this test found an engine that holds a slow contact on a fast-turning bat for about 25 steps and
misses v1 by 0.73 m/s (v_c 1-5 m/s with omega0 40-48 rad/s; reported, not yet diagnosed);
a 1500-draw run found it once above 20 m/s too (v_c 22 m/s, omega0 44 rad/s, s = 0, an oblique
bat, e = 0.53: 0.39 m/s off after 1526 steps, the other engines within 4e-7). Another draw
found an engine that misses a long plastic slide by more than its float32 allowance, however
small the step (s = 0, v0 = 1, u0 = 31 m/s, omega0 = -31.25 rad/s, e = 0: the ball rides the
bat for 95 ms and slides off its end; 0.16, 0.10, 0.14 m/s off at dt = 3e-5, 1e-5, 3e-6 s
against a 0.094 m/s tolerance at 1e-5, where the other float32 engines converge to 0.003 and
0.018 m/s; reported, not yet diagnosed). The batched engines' volleys, fired once on every
engine, found an engine whose Hunt-Crossley contact leaves its own law at small e on a fast-turning
bat: e <= 0.1 (its dissipation floored at e = 0.1, d = 0.25 s/m), s = 0.058 m, v0 = 41.8,
u0 = 15.5 m/s, omega0 = 48.8 rad/s: 15.47 against the law's 12.66 m/s head-on, 23.05 against
17.84 at theta = 0.83 rad; at e = 0.2 it follows the law to 1e-4 m/s (the bodies part at no
more than 1/d with the overlap open, and the turning bat may catch the ball again: reported,
not yet diagnosed).
"""

from __future__ import annotations

import math

import pytest
from hypothesis import Phase, given, seed, settings
from hypothesis import strategies as st

import adapters
from analytic import ImpactCase, presets
from experiments.core import Job, Runner, tables

from .conftest import sound

pytestmark = pytest.mark.full
ENGINES = adapters.names()
SINGLE = [n for n in ENGINES if not adapters.record(n).batched]
BATCHED = [n for n in ENGINES if adapters.record(n).batched]
MIN_CLOSING_MPS = 20.0


@st.composite
def impacts(draw, e: float | None = None) -> ImpactCase:
    """A random impact; its e drawn last unless given."""
    bat = presets.R161
    s = draw(st.floats(bat.s_min_m, bat.s_max_m))
    theta, phi = draw(st.floats(-1.0, 1.0)), draw(st.floats(-0.5, 0.5))
    v0, u0, w0 = (
        draw(st.floats(1.0, 60.0)),
        draw(st.floats(-5.0, 30.0)),
        draw(st.floats(-50.0, 50.0)),
    )
    closing = v0 * math.cos(theta) + u0 * math.cos(phi) + w0 * s
    if closing < MIN_CLOSING_MPS:  # keep only impacts (assume would discard too many draws)
        u0 += (MIN_CLOSING_MPS - closing) / math.cos(phi) + draw(st.floats(0.0, 20.0))
    return ImpactCase(
        bat=bat,
        ball=presets.BASEBALL,
        s_m=s,
        v0_mps=v0,
        u0_mps=u0,
        omega0_radps=w0,
        e=draw(st.floats(0.0, 1.0)) if e is None else e,
        theta_rad=theta,
        phi_rad=phi,
    )


#: Impacts per volley: they share one e, so a batched engine fires them as one batch (a world
#: alone costs it 1-3 ms a step on a CPU, and an impact takes 10 to 10^4 steps).
PER_E = 10


@st.composite
def volleys(draw) -> list[ImpactCase]:
    """PER_E random impacts sharing one random e."""
    return draw(st.lists(impacts(draw(st.floats(0.0, 1.0))), min_size=PER_E, max_size=PER_E))


def check(cases: list[ImpactCase], engines: list[str]) -> None:
    """Every engine at its reference profile within its row's tolerance on every case."""
    jobs = [
        Job(engine=n, settings=adapters.settings_for(n), case=c) for n in engines for c in cases
    ]
    table = tables.table(Runner().fire(jobs), "reference")
    bad = table[~sound(table)]
    assert bad.empty, bad[
        [
            "engine",
            "status",
            "s_m",
            "v0_mps",
            "u0_mps",
            "omega0_radps",
            "e",
            "theta_rad",
            "v1_abs_err_mps",
            "v1_tol_mps",
            "rigid_impacts",
            "rigid_sustained_s",
            "rigid_end",
        ]
    ].to_string()


#: CI draws the same impacts every run (40 one by one for the single-world engines, 2 volleys of
#: PER_E for the batched ones: a volley steps as long as its longest impact, up to 10^4 steps of
#: 1-10 ms each on a CPU, and 6 volleys took 20 minutes), so a rare engine defect found by a
#: long exploration (1500 draws by hand) cannot make CI flaky; what such runs find is pinned
#: below as explicit cases, or reported (the defects in the module docstring). The seed is the
#: one derandomize took from this test's source as it stood when the draws were first made:
#: fixed here, so that editing the test does not change which impacts CI fires.
FUZZ_SEED = int(
    "2854912894427551916355026813104932745314755663703456825604648569410385391"
    "9911088644224227363740352016727941935740046"
)


# No shrinking and no explain phase: each re-fires every engine (the explain phase under a
# line tracer), which on a failure ran for hours; the first failing draw is reported as is.
@seed(FUZZ_SEED)
@settings(
    max_examples=40,
    deadline=None,
    database=None,
    phases=(Phase.explicit, Phase.reuse, Phase.generate),
)
@given(case=impacts())
def test_every_engine_is_within_its_tolerance(case):
    check([case], SINGLE)


@seed(FUZZ_SEED)
@settings(
    max_examples=2,
    deadline=None,
    database=None,
    phases=(Phase.explicit, Phase.reuse, Phase.generate),
)
@given(cases=volleys())
def test_every_batched_engine_is_within_its_tolerance(cases):
    check(cases, BATCHED)


@pytest.mark.parametrize("name", ENGINES)  # one engine a test: xdist spreads them
def test_plastic_cases_end_where_rigid_theory_does(name):
    # Two draws with e = 0, fired together (one scene: one batch on a batched engine).
    # Head-on at the COM with no spin: after the impulse ball and bat move together, nothing
    # separates them; every engine and the rigid episode are still in contact when the budget
    # ends (the rigid end once said 'separated' for a 1e-15 m/s float-noise opening).
    # On a bat turning away: the ball rides the barrel for 98 ms and slides off its end. The
    # engines' episode ended a foot-slide bound past the end, which, where the ball drifts
    # slowly along the axis, was many steps: 1.09x the tolerance in all three founding engines
    # alike. It now ends after OFF_SPAN_STEPS steps past the end, as the tolerance's
    # sustained-force term assumes.
    head_on = ImpactCase(
        bat=presets.R161,
        ball=presets.BASEBALL,
        s_m=0.0,
        v0_mps=35.17854551140874,
        u0_mps=15.0,
        e=0.0,
    )
    slide_off = ImpactCase(
        bat=presets.R161,
        ball=presets.BASEBALL,
        s_m=0.1171875,
        v0_mps=9.0,
        u0_mps=21.0,
        omega0_radps=-38.0,
        e=0.0,
        phi_rad=0.140625,
    )
    check([head_on, slide_off], [name])
