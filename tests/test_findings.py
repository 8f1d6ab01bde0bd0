"""The findings report and the computations it rests on (experiments.findings.answers, .metal).

Each check restates the physics independently of the code under test: q = (e - r)/(1 + r) with
r = m (1/M + s^2/J); a sweet zone's edges are where v1 = 0.99 max v1; a corked bat breaks even
where the swing-speed gain makes up for the lost mass, and gains more the faster a lighter bat
is swung; the realistic ball's COR falls with speed inside the measured band; a metal
bat at BBCOR's drop -3 weighs its length less 3 oz.
"""

from __future__ import annotations

import re

import numpy as np
import pytest

import adapters
from analytic import SwingModel, batted_ball_speed, presets
from experiments import findings
from experiments.core import Runner, Status
from experiments.findings import answers as A
from experiments.findings import ball as FB
from experiments.findings import metal as M

from .conftest import FINDINGS_ENGINES

#: brentq roots are asked to 1e-10 in the exponent and closed forms are exact to a few ulps
ROOT_TOL = 1e-8


@pytest.mark.xdist_group("findings")
def test_report_is_complete(findings_run):
    text = (findings_run / "findings.md").read_text()
    for heading in (
        "## 1. Where is the sweet spot?",
        "## 2. Does corking help?",
        "## 3. Why are metal bats restricted?",
        "## 3b. How far does the ball go?",
        "## 3c. The flexible bat: two sweet spots",
        "## 4. The ball as it really is",
        "## 5. Audit of the paper",
        "## 6. The engines",
        "## Referee",
        "## References",
    ):
        assert heading in text
    images = re.findall(r"!\[[^\]]*\]\(([^)]+)\)", text)
    assert len(images) == 5
    for name in images:
        assert (findings_run / name).stat().st_size > 0
    for key in findings.REFS:  # every reference is cited somewhere in the text
        assert f"[{key}]" in text.split("## References")[0]
    for name in FINDINGS_ENGINES:  # every engine of the run confirms the headline impacts
        assert f"| {name} |" in text.split("## 6. The engines")[1]


def test_cork_verdict_depends_on_the_swing_exponent():
    # Same swing: less mass behind the ball, slower. Faster swings of the lighter bat make up
    # for it: the gain grows with n and vanishes at the break-even exponent.
    cork = A.CORK_1x10
    for sc in A.SCENARIOS:
        n0 = A.break_even_exponent(cork, sc)
        assert abs(A.cork_gain(cork, sc, n0)) < ROOT_TOL
        gains = A.v1_gain_curve(cork, sc, np.linspace(0.0, 1.0, 11))
        assert np.all(np.diff(gains) > 0)
        assert A.cork_gain(cork, sc, 0.27) < 0 < A.cork_gain(cork, sc, 1.0)
        assert A.best_v1(cork, sc)[1] < A.best_v1(presets.R161, sc)[1]
    # the paper's u0 ~ 1/M swing makes corking pay; the measured n = 0.27 does not
    wood = A.best_v1(presets.R161, A.PAPER)[1]
    for model, sign in ((SwingModel.CONSTANT_FORCE, 1), (SwingModel.MEASURED, -1)):
        corked = A.best_v1(cork, A.PAPER, A.carried_swing(cork, A.PAPER, model))[1]
        assert sign * (corked - wood) > 0


def test_a_corked_barrel_is_less_lively_in_a_cannon_test():
    # Nathan's check, 6 in from each bat's barrel end, a still bat: the corked bat is lighter
    # with less inertia, so 1/M_eff = 1/M + s^2/J grows, r = m/M_eff grows and
    # q = (e - r)/(1 + r) falls (q's formula itself: test_analytic_impact)
    q = A.nathan_q_check()
    r = {
        name: presets.BASEBALL.mass_kg
        * (1 / bat.mass_kg + (bat.s_barrel_end_m - 0.1524) ** 2 / bat.inertia_cm_kgm2)
        for name, bat in (("solid", presets.R161), ("corked", A.CORK_1x10))
    }
    assert r["corked"] > r["solid"]
    assert q["corked"] < q["solid"] < 0.5


def test_sweet_zone_edges_are_one_percent_below_the_best():
    bat, ball = presets.R161, presets.BASEBALL
    for sc in A.SCENARIOS:
        s_best, v_best = A.best_v1(bat, sc)
        lo, hi = A.zone(bat, sc)
        assert lo < s_best < hi
        for s in (lo, hi):
            if bat.s_min_m < s < bat.s_max_m:
                v = float(
                    batted_ball_speed(
                        bat,
                        ball,
                        s,
                        v0_mps=sc.v0_mps,
                        u0_mps=sc.swing.u0_mps,
                        omega0_radps=sc.swing.omega0_radps,
                        e=0.5,
                    )
                )
                assert v == pytest.approx(0.99 * v_best, rel=1e-9)


def test_a_larger_metal_inertia_moves_its_sweet_spot_toward_the_end():
    # s* = omega0 J k / (A + sqrt(A^2 + omega0^2 J k)) grows with J; with the swing carried over
    # (omega0 ~ I_knob^-0.27) the slower swing pulls it back, but less than J pushes it out
    for sc in A.SCENARIOS:
        scan = M.metal_inertia_scan(sc)
        assert np.all(np.diff(scan["sweet spot (cm from end)"]) < 0)
        wood = A.from_end_cm(presets.R161, A.best_v1(presets.R161, sc)[0])
        for model in SwingModel:
            f = M.fraction_matching_wood_sweet_spot(sc, model)
            al = M.aluminium_with(f)
            s = A.best_v1(al, sc, A.carried_swing(al, sc, model))[0]
            assert A.from_end_cm(al, s) == pytest.approx(wood, abs=1e-6)


def test_bbcor_metal_bats_are_drop_minus_three_with_the_papers_proportions():
    # weight (oz) = length (in) - 3; the 31 in one is the paper's Easton (31 in, 28 oz)
    for length in M.BBCOR_LENGTHS_IN:
        bat = M.bbcor_bat(length)
        assert bat.mass_kg == pytest.approx((length - 3) * 0.028349523125, rel=1e-12)
        assert M.uniform_rod_fraction(bat) == pytest.approx(M.uniform_rod_fraction(A.AL))
    easton = M.bbcor_bat(31)
    assert (easton.mass_kg, easton.length_m) == pytest.approx((A.AL.mass_kg, A.AL.length_m))
    assert easton.inertia_cm_kgm2 == pytest.approx(A.AL.inertia_cm_kgm2, rel=1e-12)


def test_same_swing_is_the_zero_exponent_limit():
    # n = 0: the bat turns about the same axis at the same rate, so the cork bat's COM, dx
    # nearer the knob, moves at u0 + omega0 dx (dx < 0), not at the R161's u0
    for sc in A.SCENARIOS:
        sw = A.same_swing(A.CORK_1x10, sc)
        dx = A.CORK_1x10.com_from_knob_m - presets.R161.com_from_knob_m
        assert sw.omega0_radps == sc.swing.omega0_radps
        assert sw.u0_mps == pytest.approx(sc.swing.u0_mps + sc.swing.omega0_radps * dx, rel=1e-12)


def test_realistic_ball_cor_falls_with_speed_and_contact_lasts_about_a_millisecond():
    cor = FB.ball_cor_curve()
    assert np.all(np.diff(cor["COR"]) < 0)
    # the MLB band at 25.9 m/s [mlbcor]; about 0.5 at 40-60 m/s and 0.6-1 ms [nathan2000]
    at = cor.set_index("impact speed (m/s)")
    assert 0.514 <= at.loc[25.9, "COR"] <= 0.578
    assert abs(at.loc[60.0, "COR"] - 0.5) < 0.05
    assert at.loc[20.0:60.0, "contact time (ms)"].between(0.6, 1.0).all()


def test_audit_numbers_restated():
    n = A.audit_numbers()
    r161, sw = presets.R161, presets.PAPER_SWING
    # the paper's swing turns the bat about the point u0/omega0 from the COM
    pivot_m = r161.com_from_knob_m - sw.u0_mps / sw.omega0_radps
    assert n["pivot_from_knob_m"] == pytest.approx(pivot_m)
    # had the paper subtracted (M + dM) R^2, only the hole cylinder's dM r^2/4 would be missing
    cork = A.CORK_1x10
    dm = cork.mass_kg - r161.mass_kg
    assert n["cork_J_if_subtracted_pct"] == pytest.approx(
        -dm * 0.0127**2 / 4 / cork.inertia_cm_kgm2 * 100, rel=1e-12
    )


@pytest.mark.full
def test_every_engine_confirms_the_headline_impacts():
    with Runner() as runner:
        checks = A.engine_checks(runner, adapters.names())
    assert set(checks.engine) == set(adapters.names())
    assert (checks.status == Status.OK).all(), checks[checks.status != Status.OK][
        ["engine", "bat", "swing model", "v1_abs_err_mps", "v1_tol_mps", "status"]
    ]
