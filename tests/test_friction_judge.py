"""What the judge allows with friction or out of the swing plane
(``experiments.core.friction_judge``):

- at mu = 0 every frictional answer (Routh's, the one-step law, its relaxation) is the
  frictionless impulse: v1 = -v0n + P/m, P = (1 + e) v_c / (1/m + 1/M + s^2/J), and the
  ball's tangential velocity v0 sin(theta) unchanged;
- ``columns`` adds the documented columns (the case's, then per output its analytic, law and
  engine values, both errors and the tolerance, the phases, slip, cone and law), with
  abs_err = |engine - analytic|;
- an output within its tolerance of the law is ``within``; one off by twice it is not; a
  frictionless planar impact is not judged here (``within`` whatever it did);
- a tangential velocity's frictionless tolerance is rounding plus a leak linear in the impulse
  P: allowed = precision_rel v0 + GEOM_SAFETY P/m tilt.
"""

from __future__ import annotations

import dataclasses
import math

import pytest

import adapters
from analytic import ImpactCase, predict, presets
from analytic.friction import LAWS
from experiments.core import Job, fire_jobs, friction_judge
from experiments.core.judge import rigid

from .conftest import EPS

#: The cheapest single-world engine with friction (records only: no engine named).
ENGINE = min(
    (
        n
        for n in adapters.available()
        if not adapters.record(n).batched and adapters.record(n).can.friction_rule is not None
    ),
    key=lambda n: adapters.record(n).cost.step_cost_s,
)
SETTINGS = adapters.settings_for(ENGINE)
ERRORS = adapters.record(ENGINE).errors
#: A frictionless answer recomputed another way agrees to a few dozen float64 roundings of
#: the impact's speed scale (an impulse integrated in a few steps, then projected).
ANSWER_REL = 64 * EPS


def _case(mu: float, theta_rad: float = 0.3, s_m: float = 0.1) -> ImpactCase:
    """The paper's swing, the pitch arriving theta off the normal, in the swing plane."""
    return ImpactCase(
        bat=presets.R161,
        ball=presets.BASEBALL,
        s_m=s_m,
        v0_mps=presets.PAPER_PITCH_MPS,
        u0_mps=presets.PAPER_SWING.u0_mps,
        omega0_radps=presets.PAPER_SWING.omega0_radps,
        e=presets.E_WOOD,
        theta_rad=theta_rad,
        mu=mu,
    )


@pytest.fixture(scope="module")
def fired():
    """A frictional impact (mu = 0.3, oblique in the plane) fired once."""
    (f,) = fire_jobs([Job(engine=ENGINE, settings=SETTINGS, case=_case(0.3))])
    return f


def _columns(case: ImpactCase, outcome):
    ep = rigid(case, outcome.settings.max_contact_s)
    return friction_judge.columns([case], [outcome], [ERRORS], [ep])


@pytest.mark.parametrize("which", LAWS)
def test_at_mu_zero_every_frictional_answer_is_the_frictionless_impulse(which):
    # mu = 0: no tangential impulse, so the normal impulse is the planar one and the ball
    # keeps its tangential velocity v0 sin(theta)
    case = _case(0.0)
    want = predict(case)
    ep = friction_judge.law(case, SETTINGS.max_contact_s, which)
    scale = case.v0_mps + abs(case.u0_mps) + abs(case.omega0_radps) * case.bat.length_m
    assert abs(ep.v1_mps - want.v1_mps) <= ANSWER_REL * scale, (ep.v1_mps, want.v1_mps)
    vt1 = ep.ball_velocity_mps[friction_judge.OUTPUTS["vt1"][0]]
    assert abs(vt1 - case.v0_mps * math.sin(case.theta_rad)) <= ANSWER_REL * scale


def test_columns_adds_the_documented_columns(fired):
    cols, v1_law, within = _columns(fired.case, fired.outcome)
    stems = {"vt1": "mps", "vz1": "mps", "spin1": "radps", "backspin1": "radps"}
    kinds = ("analytic", "law", "engine", "abs_err", "law_err", "tol")
    want = {
        "mu",
        "undercut_m",
        "spin0_x_radps",
        "spin0_y_radps",
        "spin0_z_radps",
        *(f"{stem}_{kind}_{unit}" for stem, unit in stems.items() for kind in kinds),
        "friction_phases",
        "slip0_mps",
        "friction_cone",
        "friction_law",
    }
    assert set(cols) == want
    assert cols["mu"] == [0.3] and cols["friction_law"] == [ERRORS.friction_law(SETTINGS)]
    assert v1_law.shape == (1, 2) and math.isfinite(v1_law[0, 1]) and v1_law[0, 1] > 0.0
    for stem, unit in stems.items():  # abs_err = |engine - analytic|, law_err = |engine - law|
        got = cols[f"{stem}_engine_{unit}"][0]
        assert cols[f"{stem}_abs_err_{unit}"][0] == abs(got - cols[f"{stem}_analytic_{unit}"][0])
        assert cols[f"{stem}_law_err_{unit}"][0] == abs(got - cols[f"{stem}_law_{unit}"][0])
    # the engine's tangential speed is the outcome's, and within its tolerance of its law
    assert cols["vt1_engine_mps"][0] == fired.outcome.v1_t_mps and within[0]


@pytest.mark.parametrize("share,inside", [(0.5, True), (2.0, False)])
def test_a_tangential_output_off_by_a_share_of_its_tolerance(fired, share, inside):
    # every output at its law's value, then vt1 moved by share x its tolerance: within at
    # half of it, not within at twice it
    cols, _, _ = _columns(fired.case, fired.outcome)
    at_law = {
        field: cols[f"{stem}_law_{friction_judge.UNITS[kind]}"][0]
        for stem, (_, field, kind) in friction_judge.OUTPUTS.items()
    }
    tol = cols["vt1_tol_mps"][0]
    assert math.isfinite(tol) and tol > 0.0
    at_law["v1_t_mps"] += share * tol
    moved = dataclasses.replace(fired.outcome, **at_law)
    _, _, within = _columns(fired.case, moved)
    assert bool(within[0]) is inside


def test_a_frictionless_planar_impact_is_not_judged_here(fired):
    # mu = 0, in the plane: the frictionless judge's business (tolerances NaN here), so even
    # an absurd tangential speed leaves it `within`
    case = _case(0.0, theta_rad=0.0)
    absurd = dataclasses.replace(fired.outcome, v1_t_mps=1e3)
    cols, v1_law, within = _columns(case, absurd)
    assert math.isnan(cols["vt1_tol_mps"][0]) and math.isnan(v1_law[0, 1]) and within[0]


def test_the_frictionless_tangential_tolerance_leaks_linearly_in_the_impulse():
    # allowed = rounding + GEOM_SAFETY P/m tilt: equal steps in P give equal steps in the
    # tolerance (to float rounding of the largest), and none of it is negative
    case, m = _case(0.0), presets.BASEBALL.mass_kg
    tols = [
        friction_judge.tangential_tolerance(case, SETTINGS, ERRORS, p, m)
        for p in (0.0, 1.0, 2.0, 3.0)
    ]
    assert tols[0] > 0.0  # rounding alone, at no impulse
    steps = [b - a for a, b in zip(tols, tols[1:])]
    assert case.omega0_radps != 0.0 and all(s > 0.0 for s in steps)  # the bat turns: a leak
    assert steps[2] - steps[1] == pytest.approx(0.0, abs=8 * EPS * tols[-1])
    assert steps[1] - steps[0] == pytest.approx(0.0, abs=8 * EPS * tols[-1])
    # the sign of the impulse does not matter: |P|
    assert friction_judge.tangential_tolerance(case, SETTINGS, ERRORS, -2.0, m) == tols[2]
