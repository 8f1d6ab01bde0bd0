"""Section 3c of the findings: the flexible bat's two sweet spots, from
``experiments.parts.flex_beam`` (the R161 as a Timoshenko beam hit by the realistic ball,
``analytic.ball``)."""

from __future__ import annotations

import pandas as pd

from ..parts import flex_beam as B
from . import flex_models
from .answers import MLB, PAPER
from .ranges import node_spread
from .report import md_table

Section = tuple[str, dict, dict]
SWINGS = {s.key: s for s in B.SWINGS if s.key in (PAPER.key, MLB.key)}


def flex_section() -> Section:
    """Modes, both sweet spots with the modulus's sensitivity, the zone, the efficiency."""
    modes = pd.DataFrame(B.modes_rows())
    spots = pd.DataFrame([B.sweet_spots(sw, k) for sw in SWINGS.values() for k in B.MODULUS_SCALES])
    rows = [B.impact_row(sw, x) for sw in SWINGS.values() for x in B.POINTS_M[::2]]
    fine = [B.impact_row(sw, x) for sw in SWINGS.values() for x in B.ZONE_POINTS_M]
    zones = {key: B.sweet_zone(fine, key) for key in SWINGS}
    models_text, models = flex_models.section(SWINGS)
    node = node_spread()
    text = "\n".join(
        [
            _modes_text(modes, node),
            _spots_text(spots, zones, modes, rows),
            models_text,
            _efficiency_text(rows),
        ]
    )
    stats = {"spots": spots.to_dict("records"), "zones": zones, "models": models, "node": node}
    return text, {}, stats


def _modes_text(modes: pd.DataFrame, node) -> str:
    ti = modes[(modes.theory == "Timoshenko") & (modes.modulus_scale == 1.0)].iloc[0]
    eb = modes[(modes.theory == "Euler-Bernoulli") & (modes.modulus_scale == 1.0)].iloc[0]
    lo = modes[(modes.theory == "Timoshenko") & (modes.modulus_scale == 0.8)].iloc[0]
    hi = modes[(modes.theory == "Timoshenko") & (modes.modulus_scale == 1.2)].iloc[0]
    return f"""## 3c. The flexible bat: two sweet spots

A sports physicist defines the sweet spot two ways: where the batted ball is fastest, and where
the hit leaves the bat least vibration, the node of its first bending mode ([cross1998],
[nathan2000]). `python -m experiments.flex` models the R161 as a free-free beam: a knob, handle,
flared taper and barrel whose radii and wood density are fitted to its mass, balance point and
J_cm (`analytic.beam`), white ash (E = 12.0 GPa, G = 0.08 E [woodhandbook]). Its first modes,
Timoshenko (shear included) beside Euler-Bernoulli: **{ti.f1_hz:.0f} and {ti.f2_hz:.0f} Hz**
({eb.f1_hz:.0f} and {eb.f2_hz:.0f} Hz without shear, which matters from the second mode on:
{100 * (1 - ti.f2_hz / eb.f2_hz):.0f}%, and {100 * (1 - ti.f3_hz / eb.f3_hz):.0f}% at the
third's {ti.f3_hz:.0f} Hz); the first mode's barrel node lies **{100 * ti.node1_from_tip_m:.1f} cm
from the end**, its handle node {100 * ti.node1_handle_from_knob_m:.1f} cm from the knob. Wood
bats measure about 170 Hz with the barrel node 5-7 in (13-18 cm) from the end [russellmodes].
With E 20% lower or higher the first mode moves to {lo.f1_hz:.0f} or {hi.f1_hz:.0f} Hz. A
scale of E and G together cannot move a node (K - w^2 M keeps its mode shapes when K is
scaled), so it is no test of the node; what can move it is the profile, which is assumed (the
R161's is not published). Over the assumed knob radius, handle length, barrel radius and
taper shape (`inputs.INPUTS`; each profile refitted to the R161's mass, balance and J_cm) the
node lies **{node.text()} cm** from the end, moved most by the {node.driver}
(`ranges.node_spread`). Chart of v1 and the energy left in bending along the barrel, the
Hunt-Crossley ball on the beam: [flex.png](flex.png) (`python -m experiments.flex`).
"""


def _spots_text(spots: pd.DataFrame, zones: dict, modes: pd.DataFrame, rows: list) -> str:
    base = spots[spots.modulus_scale == 1.0]
    ti = modes[(modes.theory == "Timoshenko") & (modes.modulus_scale == 1.0)].iloc[0]
    shift = 100 * (base.rigid_peak_from_tip_m - base.speed_peak_from_tip_m)
    apart = 100 * (base.speed_peak_from_tip_m - base.node1_from_tip_m).abs()
    contact = pd.DataFrame(rows).contact_beam_s * 1e3
    table = pd.DataFrame(
        {
            "swing": base.swing,
            "speed peak, beam (cm from end)": 100 * base.speed_peak_from_tip_m,
            "first-mode node (cm)": 100 * base.node1_from_tip_m,
            "speed peak - node (cm)": 100 * (base.speed_peak_from_tip_m - base.node1_from_tip_m)
            + 0.0,
            "speed peak, rigid bat (cm)": 100 * base.rigid_peak_from_tip_m,
            "v1 peak beam / rigid (m/s)": [
                f"{a:.1f} / {b:.1f}"
                for a, b in zip(base.v1_peak_mps, base.v1_rigid_peak_mps, strict=True)
            ],
        }
    )
    sens = {key: spots[spots.swing == key].speed_peak_from_tip_m for key in SWINGS}
    zone_text = "; ".join(
        f"{key}: {100 * z[0]:.1f}-{100 * z[1]:.1f} cm from the end" if z else f"{key}: none"
        for key, z in zones.items()
    )
    return f"""The realistic ball (section 4) hits the beam (`analytic.flexible`: the beam's first
24 modes driven through the contact, the bat moving and turning as a rigid body beneath them,
integrated until the ball leaves), for the paper's swing and the MLB-like one:

{md_table(table, floatfmt="{:.1f}")}

**Under this ball the two sweet spots lie {apart.min():.1f}-{apart.max():.1f} cm apart** (under
a hysteretic ball farther, below), while the rigid bat under the same ball peaks
{shift.min():.1f}-{shift.max():.1f} cm farther from the end. Where the
first mode is not excited, nothing is lost to it, and the second and third modes
({ti.f2_hz:.0f} Hz and {ti.f3_hz:.0f} Hz, periods comparable to the
{contact.min():.2f}-{contact.max():.2f} ms contact) give back part of what they take while the
ball is still on the bat: near the node this beam returns the ball faster than the rigid bat.
That excess rests on the ball's law (section 4's realistic ball): its damping grows with the
compression rate (Hunt-Crossley), so a bat that gives locally slows the compression and the
ball loses less (measured wood bats test just under the ball's own COR [ncaa]). With the
wood's modulus 20% lower or higher the speed peak moves by at most
{100 * max(s.max() - s.min() for s in sens.values()):.1f} cm. The sweet zone, where v1 is
within {100 * B.SPEED_SHARE:.0f}% of the best on a 1 cm grid and the first mode takes under
{100 * B.STING_SHARE:.0f}% of the collision's available energy: {zone_text}.
"""


def _efficiency_text(rows: list[dict]) -> str:
    t = pd.DataFrame(rows)
    t = t[t.swing == PAPER.key]
    table = pd.DataFrame(
        {
            "cm from end": 100 * (0.84 - t.x_m),
            "q rigid": t.q_rigid,
            "q beam": t.q_beam,
            "vibration (J)": t.vibration_j,
            "first mode (J)": t.mode1_j,
        }
    )
    return f"""Collision efficiency q = (v1 - V)/(v0 + V) along the barrel (the paper's swing): the
rigid bat's falls smoothly from the sweet spot, the beam's falls off within a few centimetres
of the node as the energy left in bending grows. This is the shape Nathan's flexible-bat
model finds ([nathan2000]: the exit speed matches the rigid bat's only near the node); its
numbers are not compared here. The hollow metal barrel's trampoline effect (its hoop modes,
a shell's, not a beam's) is out of scope: a beam has no section that deforms, so the metal bat
of section 3 keeps its e as an input.

{md_table(table, floatfmt="{:.3g}")}
"""
