"""The findings' ranges by construction (experiments.findings.inputs, .ranges, issue 58).

``inputs.spread`` must return a number's value at its central inputs and a low and high that
contain its value at every single-input corner (and, for few inputs, at every corner); the
short answers may quote no number without a range or a declared "no uncertain input"; the
beam's node is held to what can move it (the assumed profile), not to a scale of E and G.
"""

from __future__ import annotations

import math
import re

import pytest

from analytic import ImpactCase, compliant, presets
from analytic.ball import (
    COR_LAW,
    HYSTERETIC_BALL,
    HYSTERETIC_BALL_GAP,
    REALISTIC_BALL,
    WALL,
)
from analytic.compliant import hunt_crossley_dissipation
from analytic.cork import corked_bat
from experiments.findings import answers as A
from experiments.findings import inputs as I
from experiments.findings import ranges as R
from experiments.parts import flex_beam as B

from .test_findings_claims import SHORT_ANSWERS, _referee

#: Closed forms and brentq roots (to 1e-10) agree to a few ulps of a m/s value.
EXACT = 1e-9


def _box(**bounds):
    return {
        k: I.Input(key=k, label=k, unit="1", central=c, low=lo, high=hi, source="test")
        for k, (lo, c, hi) in bounds.items()
    }


def test_spread_of_a_linear_function_spans_its_box_and_names_the_widest_input():
    # f = 2a - 3b + c over a in [0, 1], b in [0, 2], c in [-1, 1]: a linear f takes its
    # extremes at corners, so with three inputs (every corner sampled) low and high are
    # exact: 0 - 6 - 1 = -7 and 2 - 0 + 1 = 3; b's ends move it most (6 against 2 and 2)
    table = _box(a=(0, 0.5, 1), b=(0, 1, 2), c=(-1, 0, 1))
    sp = I.spread(lambda a, b, c: 2 * a - 3 * b + c, ("a", "b", "c"), table)
    assert (sp.central, sp.low, sp.high) == (-2.0, -7.0, 3.0)
    assert sp.driver == "b"
    assert dict((k, (lo, hi)) for k, lo, hi in sp.ends) == {
        "a": (-3.0, -1.0),
        "b": (1.0, -5.0),
        "c": (-3.0, -1.0),
    }


def test_a_sampled_spread_stays_in_its_box_and_holds_every_single_input_end():
    # six inputs: a Sobol sample, not every corner; f = sum of squares (x - 0.3)^2 on [0, 1]^6,
    # central 0.5: every sampled value lies between the true least (0) and most (6 x 0.49),
    # and low/high include each input's own two ends
    keys = tuple("abcdef")
    table = _box(**{k: (0, 0.5, 1) for k in keys})

    def f(**x):
        return sum((v - 0.3) ** 2 for v in x.values())

    sp = I.spread(f, keys, table)
    assert len(I.sample(keys, table)) == 1 + 2 * 6 + I.SAMPLE_POINTS
    assert 0.0 <= sp.low and sp.high <= 6 * 0.49 + 1e-12
    for _, lo, hi in sp.ends:
        assert sp.low <= min(lo, hi) and max(lo, hi) <= sp.high


def test_every_declared_input_has_a_source_and_its_central_value_in_its_range():
    for i in I.INPUTS.values():
        assert i.low <= i.central <= i.high and i.low < i.high, i.key
        assert i.source.strip(), i.key
    with pytest.raises(ValueError, match="source"):
        I.Input(key="x", label="x", unit="1", central=1, low=0, high=2, source=" ")


def test_the_hole_wood_range_is_a_density_not_a_specific_gravity():
    # 82 g (2.9 oz) from a 1 in x 10 in hole [nathancork]: 82 g / (pi 12.7^2 254 mm^3) =
    # 0.64 g/cm^3; ash at 12% moisture, specific gravity 0.60 on oven-dry mass, weighs
    # 0.60 x 1.12 = 0.672 g/cm^3 [woodhandbook]: the declared central and high end
    wood = I.INPUTS["wood_density_kgm3"]
    hole_m3 = math.pi * 0.0127**2 * 0.254
    assert wood.central == pytest.approx(2.9 * 0.028349523125 / hole_m3, rel=0.01)
    assert wood.high == pytest.approx(0.60 * 1.12 * 1000, rel=1e-12)


def test_both_contact_time_definitions_give_the_hysteretic_ball_0_7_ms():
    # by the force's duration, HYSTERETIC_BALL lasts 0.7 ms on a wall at 40 m/s; by the time
    # until the gap closes, HYSTERETIC_BALL_GAP: its force lets go at x_r = (1 - e^2) x_max,
    # which then closes at the rebound speed e v, t = t_force + x_r / (e v). Roundoff of the
    # stiffness's two passes: 1e-6 relative.
    case = ImpactCase(bat=WALL, ball=presets.BASEBALL, s_m=0.0, v0_mps=40.0, e=0.5)
    e = COR_LAW.cor(40.0)
    force = compliant.predict(case, HYSTERETIC_BALL)
    assert force.contact_duration_s == pytest.approx(0.7e-3, rel=1e-6)
    gap = compliant.predict(case, HYSTERETIC_BALL_GAP)
    t_gap = gap.contact_duration_s + (1 - e * e) * gap.peak_penetration_m / (e * 40.0)
    assert t_gap == pytest.approx(0.7e-3, rel=1e-6)
    assert HYSTERETIC_BALL_GAP.stiffness > 3 * HYSTERETIC_BALL.stiffness
    # Hunt-Crossley lets go where its gap closes: F = k x^n (1 + d x') stays positive down to
    # x = 0 when 1 - d e v > 0 at the rebound rate -e v
    d = hunt_crossley_dissipation(e, 40.0)
    assert 1 - d * e * 40.0 > 0
    assert compliant.predict(case, REALISTIC_BALL).contact_duration_s == pytest.approx(
        0.7e-3, rel=1e-6
    )


def test_the_node_moves_with_the_profile_not_with_a_scale_of_e():
    # K - w^2 M: scaling K (E and G together) scales w^2 and keeps every mode shape, so the
    # node cannot move (to the eigen-solver's roundoff): no test of the node. The profile can
    # move it: over the assumed knob, handle, barrel and taper the node spans more than 1 mm,
    # and stays inside Russell's measured 13-18 cm [russellmodes]
    nodes = [B.r161_beam(k).modes(1).barrel_node_from_tip_m(0) for k in (0.8, 1.2)]
    assert nodes[0] == pytest.approx(nodes[1], abs=1e-9)
    sp = R.node_spread()
    assert sp.high - sp.low > 0.1
    assert 13.0 <= sp.low < sp.central < sp.high <= 18.0
    # its central profile is the flex command's, on 60 elements instead of 160 (0.02 mm apart)
    assert sp.central == pytest.approx(
        100 * B.r161_beam(1.0).modes(1).barrel_node_from_tip_m(0), abs=5e-3
    )


@pytest.mark.parametrize("sc", A.SCENARIOS, ids=lambda sc: sc.key)
def test_cork_and_metal_ranges_hold_their_single_input_corners(sc):
    # the cork's loss at n = 0.27 in wood of the declared range's ends, recomputed: each end
    # lies in the range, the denser wood losing more (dM grows with rho_wood)
    wood = I.INPUTS["wood_density_kgm3"]
    sp = R.cork_spreads(sc)["n027"]
    ends = [
        A.cork_gain(corked_bat(presets.R161, wood_density_kgm3=rho), sc, 0.27)
        for rho in (wood.low, wood.high)
    ]
    assert ends[1] < ends[0] < 0
    for v in ends:
        assert sp.low - EXACT <= v <= sp.high + EXACT
    # every cork and metal spread holds each input's two ends
    for spread in [*R.cork_spreads(sc).values(), *R.metal_spreads(sc).values()]:
        for _, lo, hi in spread.ends:
            assert spread.low <= min(lo, hi) and max(lo, hi) <= spread.high


@pytest.mark.xdist_group("findings")
def test_every_short_answer_number_carries_a_range_or_rests_on_no_input(findings_run):
    # strike every claim's value from the short answers: no digit may remain (names with
    # digits, R161 and v1, aside); and each claim they quote is an input, a range (central
    # (low-high), or a span), or says it rests on no uncertain input
    text = (findings_run / "findings.md").read_text()
    short = SHORT_ANSWERS.search(text).group(0)
    table = text.split("## Referee", 1)[1].split("\n## ", 1)[0]
    rows = {
        m.group(2): (m.group(1).strip(), m.group(3))
        for m in re.finditer(
            r"^\| [^|]+ \| ([^|]+) \| `([^`]+)` \| [^|]+ \| ([^|]+) \|", table, re.M
        )
    }
    assert rows.keys() == _referee(text).keys()
    # names with digits (R161, v1), cross-references, a unit's power (kg/m^3)
    left = re.sub(r"\b[A-Za-z_]+\d\w*|section \w+|\^\d", " ", short)
    quoted = []
    for key, (value, depends) in sorted(rows.items(), key=lambda kv: -len(kv[1][0])):
        if value in left:
            quoted.append(key)
            left = left.replace(value, " ")
            ranged = "(" in value or "what-if" in depends or "no uncertain input" in depends
            assert key.startswith("input.") or ranged, (key, value, depends)
    assert not re.search(r"\d", left), [ln for ln in left.splitlines() if re.search(r"\d", ln)]
    assert len(quoted) > 30
