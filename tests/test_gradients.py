"""Gradients through the impact (``experiments.core.gradients``): each engine's dv1/dx, by
central differences through the harness and by its own automatic differentiation, against the
closed form of ``analytic.gradients``:

    dv1/ds  = (1 + e) [omega0 D - v_c 2 s / J] / (m D^2)
    dv1/dv0 = (1 + e) / (m D) - 1          (head-on)
    dv1/dJ  = (1 + e) v_c s^2 / (m D^2 J^2)
    D = 1/m + 1/M + s^2/J,  v_c = v0 + u0 + omega0 s.

Each row's tolerance is derived from its engine's error model (the module docstring): a
central difference's is the velocity tolerance over the step plus the closed form's own
truncation at that step; autodiff's is the judge's tolerance with dv1/dx as the output."""

from __future__ import annotations

import math

import numpy as np
import pytest

import adapters
from analytic import impact, presets
from experiments import gradients as command
from experiments.core import gradients as grad
from experiments.core.gradients import GradStatus, judge_gradient
from experiments.core.terms import GRAD_EXPLODE, GRAD_ZERO_SHARE
from experiments.parts import gradient_studies as studies

SINGLE = [n for n in adapters.available() if not adapters.record(n).batched]
BATCHED = [n for n in adapters.available() if adapters.record(n).batched]
DIFFERENTIABLE = [n for n in adapters.available() if adapters.record(n).can.autodiff]
EXACT = [n for n in DIFFERENTIABLE if not adapters.record(n).errors.gradient_defect]
DEFECTIVE = [n for n in DIFFERENTIABLE if adapters.record(n).errors.gradient_defect]
#: The cheapest engine with its own derivative and none declared wrong.
FAST_AD = min(EXACT, key=lambda n: adapters.record(n).cost.step_cost_s)
POINTS_M = (-0.2, 0.2)  # one either side of the sweet spot, dv1/ds of either sign


def _cases(points=POINTS_M):
    return [grad.moved(command.base_case(), "s_m", s) for s in points]


def test_a_gradient_is_judged_by_its_distance_from_the_closed_form():
    # truth 10, tolerance 1: within it ok; 0 (a hard contact's) zero; beyond GRAD_EXPLODE
    # times (truth + tolerance) exploding; NaN non_finite; any other miss biased
    assert judge_gradient(10.9, 10.0, 1.0) is GradStatus.OK
    assert judge_gradient(GRAD_ZERO_SHARE * 10.0, 10.0, 1.0) is GradStatus.ZERO
    assert judge_gradient(GRAD_EXPLODE * 11.0 * 1.01, 10.0, 1.0) is GradStatus.EXPLODING
    assert judge_gradient(-GRAD_EXPLODE * 11.0 * 1.01, 10.0, 1.0) is GradStatus.EXPLODING
    assert judge_gradient(math.nan, 10.0, 1.0) is GradStatus.NON_FINITE
    assert judge_gradient(math.inf, 10.0, 1.0) is GradStatus.NON_FINITE
    assert judge_gradient(-10.0, 10.0, 1.0) is GradStatus.BIASED


def test_a_float64_engine_difference_tolerance_is_tight():
    # the tolerance is a bound, not a blanket: for the cheapest float64 single-world engine
    # (velocities to ~1e-8 m/s), tol_v / h + truncation at the best h stays below 1e-5 of the
    # slope (55 (m/s)/m at s = 0.2 m), and the step below 1 mm
    name = min(
        (n for n in SINGLE if adapters.record(n).errors.precision == "float64"),
        key=lambda n: adapters.record(n).cost.step_cost_s,
    )
    case = _cases()[1]
    h, tol = grad.fd_step(case, adapters.settings_for(name), name, "s_m")
    assert h < 1e-3 and tol < 1e-5 * abs(grad.analytic(case, "s_m")), (h, tol)


@pytest.mark.parametrize("name", SINGLE)
@pytest.mark.parametrize("wrt", ["s_m", "v0_mps", "e", "bat_inertia_kgm2"])
def test_finite_differences_through_the_engine_meet_the_closed_form(name, wrt):
    # every single-world engine (the batched ones in the full tier): at a point either side of
    # the sweet spot, each input's central difference through the harness is ok
    rows = grad.finite_differences(name, adapters.settings_for(name), _cases(), wrt)
    for r in rows:
        assert r["status"] == GradStatus.OK, r
    # and an engine without automatic differentiation says so in one row
    (ad,) = [
        r
        for r in grad.gradient_rows(name, adapters.settings_for(name), _cases()[:1], wrt)
        if r["method"] == "autodiff"
    ] or [None]
    if wrt in grad.AUTODIFF_INPUTS:
        assert ad["status"] == GradStatus.UNSUPPORTED and ad["why"], ad


@pytest.mark.parametrize("name", BATCHED)
def test_finite_differences_through_a_batched_engine_meet_the_closed_form(name):
    rows = grad.finite_differences(name, adapters.settings_for(name), _cases(), "s_m")
    assert [r["status"] for r in rows] == [GradStatus.OK] * len(rows), rows


@pytest.mark.parametrize("name", EXACT)
def test_every_engine_derivative_not_declared_wrong_meets_the_closed_form(name):
    _meets_the_closed_form(name)


#: Steps an impact is followed through: the reference profiles' episodes take 3-5 (the engines
#: pad them: MJX to 8), and free flight after the contact leaves v1 as it is.
STEPS = 8


def _meets_the_closed_form(name: str) -> None:
    # dv1/ds, dv1/dv0 and dv1/dJ by the engine's own derivative, within autodiff_tolerance
    st, errors = adapters.settings_for(name), adapters.record(name).errors
    for wrt in grad.AUTODIFF_INPUTS:
        _, values, failed, why = grad.autodiff(name, st, _cases(), wrt, STEPS)
        assert failed is None, why
        for case, value in zip(_cases(), values):
            tol = grad.autodiff_tolerance(case, st, errors, wrt)
            assert grad.judge_gradient(value, grad.analytic(case, wrt), tol) == GradStatus.OK, (
                wrt,
                case.s_m,
                value,
                grad.analytic(case, wrt),
                tol,
            )


@pytest.mark.parametrize("name", DEFECTIVE)
def test_a_declared_gradient_defect_still_misses_the_closed_form(name):
    # its record's gradient_defect: at least one autodiff row is out of its tolerance
    rows = [
        r
        for r in grad.gradient_rows(name, adapters.settings_for(name), _cases(), "s_m")
        if r["method"] == "autodiff"
    ]
    assert any(r["status"] != GradStatus.OK for r in rows), rows


@pytest.mark.parametrize("name", [n for n in BATCHED if n not in DIFFERENTIABLE])
def test_a_batched_engine_without_a_derivative_says_why(name):
    (row,) = [
        r
        for r in grad.gradient_rows(name, adapters.settings_for(name), _cases(), "s_m")
        if r["method"] == "autodiff"
    ]
    assert row["status"] == GradStatus.UNSUPPORTED and len(row["why"]) > len("unsupported: ")


@pytest.mark.full
@pytest.mark.parametrize("name", EXACT)
def test_the_engine_own_gradient_finds_the_sweet_spot_within_a_millimetre(name):
    # the root of the engine's dv1/ds against s* = omega0 J k / (A + sqrt(A^2 + omega0^2 J k))
    # (analytic.impact.sweet_spot): within the distance its gradient tolerance allows,
    # tol / |d2v1/ds2|, and (the bar) within 1 mm
    base = command.base_case()
    row = studies.sweet_spot(name, adapters.settings_for(name), base, "autodiff", 8)
    assert row["status"] == GradStatus.OK, row
    want = impact.sweet_spot(base.bat, base.ball, base.v0_mps, base.u0_mps, base.omega0_radps)
    assert abs(row["found_m"] - want) <= min(row["tolerance_m"], 1e-3), row


@pytest.mark.full
@pytest.mark.parametrize("name", EXACT)
def test_descent_through_the_engine_recovers_the_least_squares_j(name):
    # J from 20 noisy exit speeds: descent through the engine's own dv1/dJ lands on the
    # closed-form least-squares J to within the shift the engine's velocity tolerance allows,
    # sum |g_i| tol_i / sum g_i^2 (g = dv1/dJ), and within 3 standard errors of the true J
    base = command.base_case()
    s, v1 = studies.fit_data(base)
    ls = studies.least_squares_j(base, s, v1)
    got = studies.descend_j(name, adapters.settings_for(name), base, s, v1, ls["sigma_kgm2"], 8)
    st, errors = adapters.settings_for(name), adapters.record(name).errors
    cases = [grad.moved(base, "s_m", x) for x in s]
    g = np.array([grad.analytic(c, "bat_inertia_kgm2") for c in cases])
    tol = np.array([grad.output_tolerance(c, st, errors, "v1_mps") for c in cases])
    assert abs(got["j_kgm2"] - ls["j_kgm2"]) <= np.sum(np.abs(g) * tol) / np.sum(g * g), got
    assert abs(got["j_kgm2"] - base.bat.inertia_cm_kgm2) <= 3 * ls["sigma_kgm2"], (got, ls)


def test_the_least_squares_j_is_within_three_standard_errors_of_the_truth():
    # the closed-form fit of J to the noisy speeds: sigma_J = sigma / sqrt(sum (dv1/dJ)^2)
    base = command.base_case()
    ls = studies.least_squares_j(base, *studies.fit_data(base))
    assert abs(ls["j_kgm2"] - presets.R161.inertia_cm_kgm2) <= 3 * ls["sigma_kgm2"], ls
    assert 0.0 < ls["sigma_kgm2"] < 0.05 * presets.R161.inertia_cm_kgm2, ls


@pytest.mark.parametrize("name", [FAST_AD])
def test_an_engine_whose_derivative_raises_gives_an_error_row(name, monkeypatch):
    # a failure inside the engine's own differentiation is a row with status 'error' and the
    # exception's text, not a crash; the finite-difference rows beside it are untouched
    cls = type(grad.hosted(name, adapters.settings_for(name)).adapter)

    def broken(self, *args, **kwargs):
        raise FloatingPointError("the solver diverged")

    monkeypatch.setattr(cls, "derivative", broken)
    rows = grad.gradient_rows(name, adapters.settings_for(name), _cases()[:1], "s_m")
    fd, ad = rows
    assert fd["status"] == GradStatus.OK, fd
    assert ad["status"] == GradStatus.ERROR and "diverged" in ad["why"], ad
