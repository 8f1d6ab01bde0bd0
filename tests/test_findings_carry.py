"""The findings in metres (experiments.findings.carry and its section, carry_text).

Each check restates the physics independently of the code under test: without friction the
normal impulse passes through the ball's centre, so a level, square hit launches the ball level
with the pitch's own spin and the planar model's speed; the ball's angular momentum about the
contact point bounds how much of a pitch's spin survives the impact; drag only slows a ball.
"""

from __future__ import annotations

import math
import re

import numpy as np
import pytest

from analytic import batted_ball_speed
from analytic.flight import RPM_RADPS, Launch, carry_range_m, fly, time_to_travel
from experiments.findings import REFS
from experiments.findings import answers as A
from experiments.findings import carry as C
from experiments.findings import carry_text as T
from experiments.findings import ranges as R

#: In the full tier (a minute of flights and frictional impulses; the fast tier checks the
#: numbers the findings quote, test_findings_claims), on one worker: they share the carries the
#: module's functions cache (a worker each would compute most of them again).
pytestmark = [pytest.mark.full, pytest.mark.xdist_group("carry")]
#: Routh's impulse is integrated to RTOL 1e-13 and a flight to rtol 1e-10 (analytic.friction,
#: analytic.flight): 1e-8 relative leaves two orders to spare for both.
TOL_REL = 1e-8


@pytest.fixture(scope="module")
def section():
    """The section's text, charts and numbers (computed once; the functions cache theirs)."""
    return T.carry_section()


@pytest.mark.parametrize("sc", A.SCENARIOS, ids=lambda sc: sc.key)
def test_without_friction_a_level_square_hit_is_the_planar_model_flown_level(sc):
    # mu = 0: the only impulse is along the normal, which passes through the ball's centre. At
    # undercut 0 the normal is horizontal, so the ball leaves level (launch 0), unspun, at the
    # planar model's v1, and flies as a level launch from the same height.
    s = A.best_v1(A.R161, sc)[0]
    hit = C.hit_of(sc, mu=0.0, spin_radps=(0.0, 0.0, 0.0))
    got = C.launch_of(hit, s, 0.0)
    v1 = float(
        batted_ball_speed(
            A.R161,
            A.BALL,
            s,
            v0_mps=sc.v0_mps,
            u0_mps=sc.swing.u0_mps,
            omega0_radps=sc.swing.omega0_radps,
            e=A.E,
        )
    )
    assert got.speed_mps == pytest.approx(v1, rel=TOL_REL)
    assert abs(got.launch_rad) < 1e-12 and abs(got.backspin_radps) < 1e-9
    # both flights integrated to the carry's FLIGHT_RTOL: they agree to a few times it
    level = fly(
        Launch(speed_mps=v1, launch_rad=0.0, height_m=got.height_m), samples=2, rtol=C.FLIGHT_RTOL
    )
    assert C.carry_m(hit, s, 0.0) == pytest.approx(level.carry_m, rel=10 * C.FLIGHT_RTOL)


def test_without_friction_the_pitchs_spin_passes_through():
    # mu = 0: no torque on the ball, so a fastball's backspin (-x) leaves unchanged, which for
    # the batted ball (leaving along +y) is topspin.
    hit = C.hit_of(A.PAPER, mu=0.0)
    got = C.launch_of(hit, A.best_v1(A.R161, A.PAPER)[0], 0.0)
    assert got.backspin_radps == pytest.approx(-C.FASTBALL_SPIN_RPM * RPM_RADPS, rel=TOL_REL)


@pytest.mark.parametrize("sc", A.SCENARIOS, ids=lambda sc: sc.key)
def test_the_distance_sweet_spot_lies_on_the_barrel_and_is_a_maximum(sc):
    ss, grid = C.sweet_spots(sc), C.carry_grid(C.hit_of(sc))
    best = ss.best
    # inside the barrel half (COM to end), not pushed against either end of the grid
    assert grid.s_m[1] < best.s_m < grid.s_m[-2]
    assert grid.undercut_m[1] < best.undercut_m < grid.undercut_m[-2]
    # no grid point, and no nearby point, carries farther (FATOL_M: the search's tolerance)
    assert grid.carry_m.max() <= best.carry_m + C.FATOL_M
    hit = C.hit_of(sc)
    for ds, dd in ((1e-3, 0.0), (-1e-3, 0.0), (0.0, 2e-4), (0.0, -2e-4)):
        assert C.carry_m(hit, best.s_m + ds, best.undercut_m + dd) <= best.carry_m + C.FATOL_M
    # and within one grid step of the grid's own best point
    gs, gd, _ = grid.best()
    assert abs(gs - best.s_m) <= np.diff(grid.s_m)[0]
    assert abs(gd - best.undercut_m) <= np.diff(grid.undercut_m)[0]


@pytest.mark.parametrize("sc", A.SCENARIOS, ids=lambda sc: sc.key)
def test_carry_rises_with_the_undercut_to_its_best_then_falls(sc):
    # Under the ball's centre the launch angle and the backspin both grow with the undercut:
    # the carry rises to a single peak, then falls as the ball pops up.
    grid, best = C.carry_grid(C.hit_of(sc)), C.sweet_spots(sc).best
    column = grid.carry_m[:, int(np.argmin(abs(grid.s_m - best.s_m)))]
    k = int(np.argmax(column))
    assert np.all(np.diff(column[: k + 1]) > 0) and np.all(np.diff(column[k:]) < 0)
    assert abs(grid.undercut_m[k] - best.undercut_m) <= np.diff(grid.undercut_m)[0]
    # the launch angle grows with the undercut at the best point's s
    rows = C.sweet_spots(sc).rows
    assert np.all(np.diff([r.launch.launch_rad for r in rows]) > 0)


@pytest.mark.parametrize("sc", A.SCENARIOS, ids=lambda sc: sc.key)
def test_a_curveball_leaves_with_more_backspin_than_a_fastball(sc):
    # Hubbard's argument: the curveball's topspin already turns the way the batted ball's
    # backspin does. Bounds: the ball's angular momentum about the contact point is conserved;
    # ending in rolling on an immovable surface keeps I / (I + m r^2) = 2/7 of a difference in
    # incoming spin, and a bat that gives way tangentially keeps more, at most all of it.
    po = C.pitch_optima(sc)
    incoming = C.CURVEBALL_SPIN_RPM + C.FASTBALL_SPIN_RPM
    kept = (po.curveball_spin_at_fastballs_rpm - po.fastball_spin_rpm) / incoming
    assert 2 / 7 < kept < 1
    # at the curveball's own best point too
    c = po.curveball
    fast = C.launch_of(C.hit_of(sc), c.s_m, c.undercut_m)
    assert c.launch.backspin_radps > fast.backspin_radps


@pytest.mark.parametrize("sc", A.SCENARIOS, ids=lambda sc: sc.key)
def test_friction_hardly_matters_once_the_slip_stops(sc):
    # Sawicki et al.: post-impact conditions independent of mu. Once the slip stops within the
    # impact only its sliding start depends on mu, and that start shrinks as 1/mu.
    scan = C.mu_scan(sc)
    grip = scan[scan["slip stops"]]
    assert len(grip) >= 4
    far = abs(grip["carry (m)"] - grip["carry (m)"].iloc[-1]).to_numpy()[:-1]
    assert np.all(np.diff(far) < 0)
    assert far.max() < 1e-4 * grip["carry (m)"].iloc[-1]  # a centimetre in 100 m


@pytest.mark.parametrize("sc", A.SCENARIOS, ids=lambda sc: sc.key)
def test_bat_table_ranges_are_the_flight_models(sc):
    # The solid R161 row is the distance sweet spot; its range is flight.carry_range_m's, and
    # every change keeps its sign at each corner of the drag/lift spread.
    t = C.bat_table(sc)
    best = C.sweet_spots(sc).best
    assert t.iloc[0]["carry (m)"] == best.carry_m and t.iloc[0]["change (m)"] == 0.0
    lo, hi = carry_range_m(best.launch)
    assert t.iloc[0]["carry range (m)"] == f"{lo:.1f}-{hi:.1f}"
    assert C.corner_carries(best.launch).min() == pytest.approx(lo, rel=TOL_REL)
    for _, r in t.iloc[1:].iterrows():
        a, b = (float(x) for x in r["change over spread (m)"].split(" to "))
        if abs(r["change (m)"]) > 0.1:
            assert np.sign(a) == np.sign(b) == np.sign(r["change (m)"])


@pytest.mark.parametrize("sc", A.SCENARIOS, ids=lambda sc: sc.key)
def test_drag_only_lengthens_the_reaction_times(sc):
    t = C.reaction_times(sc)
    assert (t["t, drag (s)"] > t["t, no drag (s)"]).all()
    assert (
        t["below, no drag"] == (A.PITCHER_AFTER_FOLLOW_THROUGH_M / t["v1 (m/s)"] < A.REACTION_S)
    ).all()
    assert not (t["below, drag"] & ~t["below, no drag"]).any()
    # the pitch arrives at the scenario's speed from its release speed (brentq to 1e-9 m/s)
    pt = C.pitch_time(sc)
    arrive = time_to_travel(pt["release_mps"], backspin_radps=C.FASTBALL_SPIN_RPM * RPM_RADPS)
    assert arrive.arrival_speed_mps == pytest.approx(sc.v0_mps, abs=1e-8)
    assert arrive.time_s == pt["t_drag_s"]


def test_section_quotes_the_computed_numbers(section):
    text, figs, _ = section
    assert text.startswith("## 3b. How far does the ball go?")
    assert list(figs) == [T.CHART] and f"]({T.CHART})" in text
    for sc in A.SCENARIOS:
        b = C.sweet_spots(sc).best
        # the longest carry over the joint range of its inputs (e, the spin handed on and its
        # boost, drag, lift: ``ranges.carry_spread``): central at the central model's best ball
        # (every input central is that model), and wider than drag and lift's corners alone
        # (a joint range holds every single-input corner)
        spread = R.carry_spread(sc)
        low, high = carry_range_m(b.launch)
        assert spread.central == b.carry_m and spread.low <= low and high <= spread.high
        assert f"**{spread.text()} m**" in text
        assert f"{abs(b.s_m - C.sweet_spots(sc).speed_s_m) * 1e3:.1f} mm" in text
    p, m = C.pitch_optima(A.PAPER), C.pitch_optima(A.MLB)
    assert (
        f"**{p.curveball.undercut_m * 100:.2f} cm against {p.fastball.undercut_m * 100:.2f} cm**"
    ) in text
    assert (
        f"{m.curveball.undercut_m * 100:.2f} against {m.fastball.undercut_m * 100:.2f} cm"
    ) in text
    gain = p.curveball.carry_m - p.fastball.carry_m
    assert f"{gain:+.1f} m ({C.feet(gain):+.0f} ft)" in text
    # the gain over the joint range of the spin handed on, its boost, drag and lift
    # (``ranges.curve_spread``): central at rigid rolling (the whole spin handed on, no boost),
    # and holding none (no spin handed on: the two pitches leave alike and carry the same)
    spreads = [R.curve_spread(sc) for sc in (A.PAPER, A.MLB)]
    for po, cs in zip((p, m), spreads):
        assert cs.central == pytest.approx(po.curveball.carry_m - po.fastball.carry_m, abs=1e-9)
        assert cs.low <= 0.0 <= cs.high
    assert (
        f"**the curveball's gain is {spreads[0].text('+')} m (paper's swing) and "
        f"{spreads[1].text('+')} m (MLB-like)**"
    ) in " ".join(text.split())
    cork = C.bat_table(A.PAPER)
    row = cork[(cork["swing model"] == "measured") & (cork.bat == "R161, 1 x 10 in cork")]
    change = row["change (m)"].iloc[0]
    assert f"{change:+.1f} m ({C.feet(change):+.0f} ft)" in text
    r = C.reaction_summary(A.PAPER)
    assert f"**{r['al_below_drag']} of {r['al_below_no_drag']} (paper's swing)" in text
    assert f"{C.pitch_time(A.MLB)['t_drag_s']:.3f} s" in text
    # every reference the section cites exists, and the new ones are cited
    cited = set(re.findall(r"\[([a-z0-9]+)\]", text))
    assert cited <= set(REFS)
    assert {
        "sawicki2003",
        "statcast",
        "kensrud2017",
        "nathan2012",
        "crossnathan2006",
        "popmech2009",
        "nathancalc",
        "adair",
        "mlbrelease",
    } <= cited


def test_feet_are_metres_over_0_3048():
    assert C.feet(0.3048) == pytest.approx(1.0, rel=1e-15)
    assert math.isclose(C.feet(100.0), 328.084, rel_tol=1e-6)
