"""The real-ball fit (``experiments.realball``, ``experiments.parts.realball_fit``): a fit
recovers known parameters from synthetic targets, by finite differences and by a Jacobian;
through the harness a constant-e engine recovers the e of a flat law; a held-out check fails
when the fitted knobs are perturbed (a constant e's, a soft model's); every declared ball
model's speed dependence is measured; each engine's best model is its lowest-cost one."""

from __future__ import annotations

import json
from collections.abc import Sequence
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

import adapters
from adapters import RESTITUTION_KNOB, BallContact, ContactKnob
from analytic.ball import SPEED_REF_MPS, CorLaw, cor_range
from analytic.compliant import hunt_crossley_restitution
from experiments import realball
from experiments.parts import realball_fit as rf

#: The synthetic ball: COR = a (v / v_ref)^-p, contact time t (s), as three knobs.
SYNTHETIC_KNOBS = (
    ContactKnob(setting="a", lo=0.3, hi=0.9, unit="1"),
    ContactKnob(setting="p", lo=0.0, hi=0.5, unit="1"),
    ContactKnob(setting="t", lo=1e-4, hi=1e-2, unit="s", log=True),
)
TRUE_X = (0.56, 0.18, 8e-4)
TARGET = CorLaw(cor_ref=TRUE_X[0], speed_ref_mps=SPEED_REF_MPS, exponent=TRUE_X[1])
#: A smooth closed-form model meets its target exactly at TRUE_X: the fit stops at
#: least_squares' default xtol (1e-8 relative in unit coordinates), which a 2-point
#: difference of step FD_STEP on a power law leaves near 1e-6; 1e-5 relative bounds it.
RECOVER_REL = 1e-5


class Synthetic:
    """A closed-form probe: COR = a (v/v_ref)^-p, contact t, its Jacobian exact."""

    knobs = SYNTHETIC_KNOBS

    def __init__(self, exact_jacobian: bool) -> None:
        self.impacts, self.exact = 0, exact_jacobian

    def measure(self, x: np.ndarray, speeds: Sequence[float]) -> rf.Measured:
        a, p, t = x
        v = np.asarray(speeds) / SPEED_REF_MPS
        self.impacts += len(speeds)
        return rf.Measured(cor=a * v**-p, contact_s=np.full(len(v), t), sound=np.ones(len(v), bool))

    def derivative(self, x: np.ndarray, speeds: Sequence[float]) -> np.ndarray | None:
        # d/da a v^-p = v^-p; d/dp = -a v^-p ln v; the COR does not depend on t
        a, p, _ = x
        v = np.asarray(speeds) / SPEED_REF_MPS
        self.impacts += len(speeds)
        return np.stack([v**-p, -a * v**-p * np.log(v), 0.0 * v], axis=1)


def _synthetic_fit(gradient: bool):
    """The fit of the synthetic probe to TARGET and TRUE_X's contact time, from one start."""
    return rf.fit(
        Synthetic(exact_jacobian=gradient),
        rf.FIT_SPEEDS_MPS,
        (0.45, 0.05, 3e-4),
        lasts=True,
        law=TARGET,
        contact_s=TRUE_X[2],
        gradient=gradient,
    )


@pytest.mark.parametrize("gradient", [False, True], ids=["finite_differences", "gradient"])
def test_fit_recovers_known_parameters_from_synthetic_targets(gradient):
    got = _synthetic_fit(gradient)
    np.testing.assert_allclose(got.x, TRUE_X, rtol=RECOVER_REL)
    assert got.cost < 1e-12, got


def test_gradient_fit_agrees_with_fd_and_fires_fewer_impacts():
    # the same optimum (within RECOVER_REL of each other) and, with the COR rows' Jacobian
    # from the derivative, fewer impacts: each iteration fires every speed once and the
    # contact time's row at one speed per knob, not every speed per knob
    fd, grad = (_synthetic_fit(g) for g in (False, True))
    np.testing.assert_allclose(grad.x, fd.x, rtol=2 * RECOVER_REL)
    assert grad.impacts < fd.impacts, (grad, fd)


def test_unit_coordinates_round_trip_and_bounds():
    # u = 1 + (x - lo)/(hi - lo), or 1 + ln(x/lo)/ln(hi/lo): x -> u -> x to float precision
    x = np.array(TRUE_X)
    np.testing.assert_allclose(rf.from_unit(SYNTHETIC_KNOBS, rf.to_unit(SYNTHETIC_KNOBS, x)), x)
    np.testing.assert_allclose(rf.to_unit(SYNTHETIC_KNOBS, [k.lo for k in SYNTHETIC_KNOBS]), 1.0)
    np.testing.assert_allclose(rf.to_unit(SYNTHETIC_KNOBS, [k.hi for k in SYNTHETIC_KNOBS]), 2.0)


def _models() -> list[tuple[str, BallContact]]:
    """Every installed engine's every declared ball model (records only)."""
    return [(n, b) for n in adapters.available() for b in adapters.record(n).balls]


def _cheapest(models: list[tuple[str, BallContact]]) -> tuple[str, BallContact]:
    return min(models, key=lambda m: adapters.record(m[0]).cost.step_cost_s)


def _constant_e_model() -> tuple[str, BallContact]:
    """The cheapest installed engine's rigid e: one restitution knob, the same at every speed."""
    rigid = [
        (n, b)
        for n, b in _models()
        if not b.speed_dependent and [k.setting for k in b.knobs] == [RESTITUTION_KNOB]
    ]
    return _cheapest(rigid)


#: A rigid impulse delivers e to roundoff: 1e-6 covers float32 engines (unit roundoff 6e-8
#: times the few operations of an impulse) and the optimiser's xtol.
E_TOL = 1e-6


def test_a_constant_e_engine_recovers_a_flat_laws_e_through_the_harness():
    # a flat law (exponent 0) is one e at every speed: COR = (v1 - u1)/v0 = e on a wall
    engine, ball = _constant_e_model()
    flat = CorLaw(cor_ref=0.6, speed_ref_mps=SPEED_REF_MPS, exponent=0.0)
    got = rf.fit(rf.EngineProbe(engine, ball), (10.0, 40.0), (0.5,), lasts=False, law=flat)
    assert abs(got.x[0] - 0.6) < E_TOL, got


def test_a_held_out_check_fails_when_the_knobs_are_perturbed():
    # fitted to COR_LAW, e lies within COR_LAWS' range at every held-out speed; 0.1 higher
    # it leaves the range at 85 ft/s, whose half width is MLB's 0.032
    engine, ball = _constant_e_model()
    best = rf.fit(rf.EngineProbe(engine, ball), (10.0, 40.0, 60.0), (0.5,), lasts=False)
    held = realball.speed_rows(engine, ball, best.x, (), rf.HELD_OUT_SPEEDS_MPS)
    assert all(r["in_range"] for r in held), held
    moved = realball.speed_rows(engine, ball, (best.x[0] + 0.1,), (), rf.HELD_OUT_SPEEDS_MPS)
    out = [r["speed_mps"] for r in moved if not r["in_range"]]
    assert SPEED_REF_MPS in out, moved
    lo, hi = cor_range(SPEED_REF_MPS)
    assert hi - lo == pytest.approx(0.064)


#: A soft model's knob is walked in steps of this share of its range until the COR at
#: CONTACT_SPEED_MPS (a fit speed) has moved by PERTURB_BANDS of its half band.
PERTURB_STEP_UNIT, PERTURB_BANDS = 0.05, 3.0


@pytest.mark.full
def test_a_held_out_check_fails_when_a_soft_models_knobs_are_perturbed():
    # fitted to COR_LAW at the fit speeds, the cheapest speed-dependent model bounces within
    # COR_LAWS' range at 85 ft/s, held out. The knob that moves the COR at 40 m/s most,
    # walked until that fit speed's COR has moved by 3 of its half bands, carries the held-out
    # 85 ft/s COR out of MLB's +-0.032 too: its row says out of range. The walk reads 40 m/s
    # only, so the verdict at 85 ft/s is a prediction the check could miss.
    engine, ball = _cheapest([(n, b) for n, b in _models() if b.speed_dependent])
    probe = rf.EngineProbe(engine, ball)
    best = rf.fit(probe, rf.FIT_SPEEDS_MPS, ball.start, lasts=ball.lasts)
    held = realball.speed_rows(engine, ball, best.x, (), (SPEED_REF_MPS,))
    assert held[0]["in_range"], held
    u0, v = rf.to_unit(ball.knobs, best.x), rf.CONTACT_SPEED_MPS

    def cor_at(u):
        return probe.measure(rf.from_unit(ball.knobs, u), (v,)).cor[0]

    c0 = cor_at(u0)
    moves = [
        u0 + sign * PERTURB_STEP_UNIT * np.eye(len(u0))[j]
        for j in range(len(u0))
        for sign in (1, -1)
    ]
    moves = [np.clip(m, 1.0, 2.0) for m in moves]
    step = max(moves, key=lambda m: abs(cor_at(m) - c0)) - u0
    u = u0.copy()
    while abs(cor_at(u) - c0) < PERTURB_BANDS * rf.half_band(v):
        assert np.all((u + step >= 1.0) & (u + step <= 2.0)), (u, step)
        u = u + step
    moved = realball.speed_rows(engine, ball, rf.from_unit(ball.knobs, u), (), (SPEED_REF_MPS,))
    assert not moved[0]["in_range"], (engine, ball.label, moved)


#: The declared speed dependence, measured: a speed-dependent contact's COR at its start
#: moves by more than SPEED_DEPENDENT_MIN between 10 and 60 m/s; a constant one by less than
#: CONSTANT_MAX (float32 roundoff and a solver's tolerance on a rigid e, 1e-6 measured).
SPEED_DEPENDENT_MIN, CONSTANT_MAX = 5e-3, 1e-4


def _models_slow_ones_full():
    out = []
    for n, b in _models():
        rec = adapters.record(n)
        slow = rec.batched or rec.cost.step_cost_s > 1e-4
        mark = [pytest.mark.full] if slow else []
        out.append(pytest.param(n, b, marks=mark, id=f"{n}-{b.label.replace(' ', '_')}"))
    return out


@pytest.mark.parametrize(("engine", "ball"), _models_slow_ones_full())
def test_declared_speed_dependence_is_measured(engine, ball):
    m = rf.EngineProbe(engine, ball).measure(np.array(ball.start), (10.0, 60.0))
    assert m.sound.all(), m
    moved = abs(m.cor[1] - m.cor[0])
    if ball.speed_dependent:
        assert moved > SPEED_DEPENDENT_MIN, (engine, m.cor)
    else:
        assert moved < CONSTANT_MAX, (engine, m.cor)


def test_sweet_spot_is_the_parabolas_vertex():
    # v1 = -(s - 0.07)^2 sampled on a grid: the vertex is 0.07 exactly (a parabola)
    s = np.linspace(-0.2, 0.3, 11)
    assert realball.sweet_spot_m(s, -((s - 0.07) ** 2)) == pytest.approx(0.07, abs=1e-12)


def _differentiating():
    return [
        pytest.param(n, b, id=f"{n}-{b.label.replace(' ', '_')}")
        for n, b in _models()
        if rf.EngineProbe(n, b).has_derivative()
    ]


@pytest.mark.full
@pytest.mark.parametrize(("engine", "ball"), _differentiating())
def test_the_probes_cor_derivative_is_the_finite_difference_of_its_cor(engine, ball):
    # dCOR/dx = (d ball_vy - d bat_vy)/v0 from the adapter's knob_derivative against a
    # central difference of the fired COR at +-1e-3 of each knob: truncation h^2 COR'''/6
    # and the engine's noise (solver bits, ~1e-8 m/s over v0 / h ~ 1e-6) are under 1e-4 of
    # the derivatives here (``test_knob_derivative``); 1e-3 relative, or 1e-3 of the largest
    # where one is near zero, with margin.
    probe = rf.EngineProbe(engine, ball)
    x, speeds = np.array(ball.start), (20.0, 50.0)
    probe.measure(x, speeds)  # (the episode's steps, which the derivative follows)
    d = probe.derivative(x, speeds)
    for j, knob in enumerate(probe.knobs):
        h = 1e-3 * x[j]
        up, down = x.copy(), x.copy()
        up[j], down[j] = x[j] + h, x[j] - h
        fd = (probe.measure(up, speeds).cor - probe.measure(down, speeds).cor) / (2 * h)
        scale = np.abs(d).max(axis=1)
        assert np.all(np.abs(d[:, j] - fd) <= 1e-3 * np.maximum(np.abs(fd), scale)), (knob, d, fd)


def test_no_hunt_crossley_dissipation_keeps_a_ball_in_range_at_five_speeds():
    # Hunt-Crossley (Drake's point contact, any exponent): a - ln(1 + a) = -e a - ln(1 - e a)
    # with a = d v (``compliant.hunt_crossley_restitution``), so e falls with d v alone,
    # faster than COR_LAWS' steepest (v^-1/4): over every d that keeps 85 ft/s within
    # MLB's band, at most 4 of the study's 9 speeds from 15 to 55 m/s lie within the range,
    # under the bar's 5. Why Drake's fit cannot reach it.
    speeds = (15.0, 20.0, SPEED_REF_MPS, 30.0, 35.0, 40.0, 45.0, 50.0, 55.0)
    best = 0
    for d in np.geomspace(1e-4, 1.0, 2000):
        e = [hunt_crossley_restitution(d, v) for v in speeds]
        if abs(e[2] - 0.546) > 0.032:
            continue
        best = max(best, sum(lo <= c <= hi for c, (lo, hi) in zip(e, map(cor_range, speeds))))
    assert best == 4


def test_best_models_picks_each_engines_lowest_finite_difference_cost():
    # an engine's best model is the argmin of its models' finite-difference fit costs; a
    # gradient fit's cost (another optimiser's stop) does not choose
    table = pd.DataFrame(
        {
            "engine": ["a", "a", "a", "b"],
            "model": ["x", "y", "x", "z"],
            "method": [rf.METHODS[0], rf.METHODS[0], rf.METHODS[1], rf.METHODS[0]],
            "cost": [0.8, 0.02, 0.001, 4.0],
        }
    )
    assert realball.best_models(table) == {"a": "y", "b": "z"}


def test_the_committed_best_model_is_each_engines_lowest_cost_one():
    # in every committed table, each engine has one model marked best: the one whose
    # finite-difference fit (realball_fits.csv) has the lowest cost
    results = Path(__file__).resolve().parents[1] / "results"
    fits = pd.read_csv(results / "realball_fits.csv")
    fd = fits[fits.method == rf.METHODS[0]]
    want = {e: t.model[t.cost.idxmin()] for e, t in fd.groupby("engine")}
    for name in ("realball_fits.csv", "realball.csv", "realball_sweet.csv"):
        rows = pd.read_csv(results / name)
        got = {e: sorted(set(t.model[t.best])) for e, t in rows.groupby("engine")}
        assert got == {e: [m] for e, m in want.items()}, name


def test_the_readmes_baseball_numbers_are_the_committed_results():
    # every number the README's "A baseball in your engine" quotes, read from the table the
    # command wrote (results/realball_fits.csv), rounded as quoted
    root = Path(__file__).resolve().parents[1]
    text = (root / "README.md").read_text()
    section = text[text.index("## A baseball in your engine") : text.index("## What the findings")]
    fits = pd.read_csv(root / "results" / "realball_fits.csv")
    best = fits[fits.best]
    fd = best[best.method == rf.METHODS[0]].set_index("engine")
    grad = best[best.method == rf.METHODS[1]].set_index("engine")
    soft = fd[fd.speed_dependent & fd.in_mlb_band]
    flat = fd[~fd.speed_dependent]
    assert f"{soft.speeds_in_range.min()}/{soft.speeds_checked.max()} speeds" in section
    assert f"sweet spot {100 * soft.sweet_spot_m.mean():.1f} cm" in section
    assert f"the ball's {100 * soft.sweet_spot_ball_m.mean():.1f}" in section
    (engine,) = grad.index
    assert f"in {grad.impacts[engine]} impacts, not {fd.impacts[engine]}" in section
    assert f"constant e ({json.loads(flat.knobs.iloc[0])['e']:.3f})" in section
    # an engine with several models: its best one's e and speeds, its others' speeds
    every = fits[fits.method == rf.METHODS[0]]
    several = every[every.groupby("engine").model.transform("nunique") > 1]
    for r in several.itertuples():
        n = f"{r.speeds_in_range}/{r.speeds_checked}"
        if r.best:
            e = json.loads(r.knobs)["e"]
            assert f"best, its {r.model} (e {e:.3f}, {n} speeds)" in section, r
        else:
            assert f"{r.model} falls too fast ({n})" in section, r
