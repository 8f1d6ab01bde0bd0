"""The flexible R161: its modes, its two sweet spots and the chain against the beam.

The numbers ``experiments.flex`` tabulates and the findings quote, from ``analytic`` alone:
the beam's modes (Euler-Bernoulli and Timoshenko, the wood's modulus at 80, 100 and 120%),
the exit speed and the energy left in bending along the barrel for each swing, the two sweet
spots (the exit speed's peak; the first mode's barrel node) and the sweet zone where both
hold, and the segmented chain's modes and exit speeds as N grows against the beam's.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from functools import cache

import numpy as np
from scipy import optimize

from analytic import ImpactCase, beam, flexible, presets
from analytic.ball import REALISTIC_BALL
from analytic.chain import Chain
from analytic.chain_impact import ChainImpact, compliant_reference
from analytic.compliant import predict as rigid_predict

#: The wood's Young's modulus relative to the handbook's, for the sensitivity columns.
MODULUS_SCALES = (0.8, 1.0, 1.2)
#: Impact points along the barrel (m from the knob) of the exit-speed curves, and the finer
#: ones around the sweet spots that the sweet zone is read from (1 cm apart).
POINTS_M = tuple(np.round(np.linspace(0.45, 0.80, 15), 4))
ZONE_POINTS_M = tuple(np.round(np.arange(0.60, 0.7251, 0.01), 4))
#: The sweet zone: exit speed within this share of its peak ...
SPEED_SHARE = 0.02
#: ... and the first mode's energy below this share of the collision's kinetic energy in
#: the centre-of-mass frame, 1/2 m_red v_rel^2 (what a hit can give the bat to vibrate).
STING_SHARE = 0.02
#: Segment counts of the chain-against-beam table.
SEGMENTS = (4, 8, 16, 32, 64)


@dataclass(frozen=True, kw_only=True)
class Swing:
    """A pitch ``v0_mps`` and the bat's COM speed ``u0_mps`` and rate ``omega0_radps``."""

    key: str
    v0_mps: float
    u0_mps: float
    omega0_radps: float


#: The paper's swing (section 6.3) and a major-league swing about the knob, as the findings
#: have them (``experiments.findings.answers``), and a bat at rest (Nathan 2000's case).
SWINGS = (
    Swing(
        key="paper",
        v0_mps=presets.PAPER_PITCH_MPS,
        u0_mps=presets.PAPER_SWING.u0_mps,
        omega0_radps=presets.PAPER_SWING.omega0_radps,
    ),
    Swing(key="mlb", v0_mps=40.0, u0_mps=48.0 * presets.R161.com_from_knob_m, omega0_radps=48.0),
    Swing(key="still", v0_mps=40.0, u0_mps=0.0, omega0_radps=0.0),
)


@cache
def r161_beam(modulus_scale: float = 1.0, shear: bool = True) -> beam.Beam:
    """The R161's beam (Timoshenko unless ``shear`` is False), E and G scaled."""
    profile, wood = presets.r161_profile()
    wood = replace(
        wood,
        youngs_modulus_pa=wood.youngs_modulus_pa * modulus_scale,
        shear_modulus_pa=wood.shear_modulus_pa * modulus_scale,
    )
    return beam.Beam(profile=profile, wood=wood, shear=shear)


def modes_rows() -> list[dict]:
    """Per theory and modulus: the first three frequencies and the nodes that matter."""
    rows = []
    for shear in (False, True):
        for scale in MODULUS_SCALES:
            modes = r161_beam(scale, shear).modes(3)
            rows.append(
                {
                    "theory": "Timoshenko" if shear else "Euler-Bernoulli",
                    "modulus_scale": scale,
                    **{f"f{i + 1}_hz": float(f) for i, f in enumerate(modes.frequencies_hz)},
                    "node1_from_tip_m": modes.barrel_node_from_tip_m(0),
                    "node1_handle_from_knob_m": float(modes.node_positions_m(0)[0]),
                    "node2_from_tip_m": modes.barrel_node_from_tip_m(1),
                }
            )
    return rows


def _case(b: beam.Beam, sw: Swing, x_m: float) -> ImpactCase:
    bat = b.rigid_bat(presets.R161)
    return ImpactCase(
        bat=bat,
        ball=presets.BASEBALL,
        s_m=x_m - bat.com_from_knob_m,
        v0_mps=sw.v0_mps,
        u0_mps=sw.u0_mps,
        omega0_radps=sw.omega0_radps,
        e=presets.E_WOOD,
    )


def impact_row(
    sw: Swing, x_m: float, modulus_scale: float = 1.0, law=REALISTIC_BALL, **beam_kw
) -> dict:
    """The rigid bat and the beam at one impact point (``law``, the realistic ball by default,
    on both; ``beam_kw`` to ``flexible.predict``: modes, loss_factor, patch_m)."""
    b = r161_beam(modulus_scale)
    case = _case(b, sw, x_m)
    rigid = rigid_predict(case, law)
    flex = flexible.predict(case, b, law, **beam_kw)
    m, M, J, s = case.ball.mass_kg, case.bat.mass_kg, case.bat.inertia_cm_kgm2, case.s_m
    m_red = 1.0 / (1 / m + 1 / M + s * s / J)
    available = 0.5 * m_red * case.closing_speed_mps**2
    return {
        "swing": sw.key,
        "modulus_scale": modulus_scale,
        "x_m": x_m,
        "s_m": s,
        "v1_rigid_mps": rigid.v1_mps,
        "v1_beam_mps": flex.v1_mps,
        "q_rigid": rigid.q,
        "q_beam": flex.q,
        "vibration_j": flex.vibration_j,
        "mode1_j": flex.mode_energy_j[0],
        "mode2_j": flex.mode_energy_j[1],
        "sting_share": flex.mode_energy_j[0] / available,
        "contact_beam_s": flex.contact_duration_s,
        "contact_rigid_s": rigid.contact_duration_s,
        "touches": flex.touches,
    }


def speed_peak_m(sw: Swing, modulus_scale: float = 1.0, law=REALISTIC_BALL) -> tuple[float, float]:
    """(x of the beam's exit-speed peak (m from the knob), v1 there) under ``law``: bounded
    Brent search over the barrel to 0.5 mm."""
    res = optimize.minimize_scalar(
        lambda x: -impact_row(sw, x, modulus_scale, law)["v1_beam_mps"],
        bounds=(0.50, 0.80),
        method="bounded",
        options={"xatol": 5e-4},
    )
    return float(res.x), float(-res.fun)


def sweet_spots(sw: Swing, modulus_scale: float = 1.0, law=REALISTIC_BALL) -> dict:
    """Both sweet spots (m from the barrel end) and the rigid bat's speed peak beside them,
    the ball ``law`` on both."""
    b = r161_beam(modulus_scale)
    x_peak, v_peak = speed_peak_m(sw, modulus_scale, law)
    rigid = optimize.minimize_scalar(
        lambda x: -rigid_predict(_case(b, sw, x), law).v1_mps,
        bounds=(0.50, 0.80),
        method="bounded",
        options={"xatol": 5e-4},
    )
    length = presets.R161.length_m
    return {
        "swing": sw.key,
        "modulus_scale": modulus_scale,
        "speed_peak_from_tip_m": length - x_peak,
        "v1_peak_mps": v_peak,
        "node1_from_tip_m": b.modes(1).barrel_node_from_tip_m(0),
        "rigid_peak_from_tip_m": length - float(rigid.x),
        "v1_rigid_peak_mps": -rigid.fun,
    }


def sweet_zone(rows: list[dict], sw_key: str) -> tuple[float, float] | None:
    """The span of impact points (m from the barrel end, nearest first) where the beam's exit
    speed is within SPEED_SHARE of the grid's best and the first mode takes under STING_SHARE
    of the available energy; None if no grid point does both."""
    mine = [r for r in rows if r["swing"] == sw_key and r["modulus_scale"] == 1.0]
    best = max(r["v1_beam_mps"] for r in mine)
    good = [
        presets.R161.length_m - r["x_m"]
        for r in mine
        if r["v1_beam_mps"] >= (1 - SPEED_SHARE) * best and r["sting_share"] <= STING_SHARE
    ]
    return (float(min(good)), float(max(good))) if good else None


def chain_rows(points_m=(0.50, 0.66, 0.75)) -> list[dict]:
    """The chain against the Euler-Bernoulli beam as N grows: frequencies, and the exit speed
    of a still bat under the realistic ball at a few points."""
    eb = r161_beam(1.0, shear=False)
    want = eb.modes(3).frequencies_hz
    still = SWINGS[2]
    beam_v1 = {
        x: flexible.predict(_case(eb, still, x), eb, REALISTIC_BALL).v1_mps for x in points_m
    }
    rows = []
    for n in SEGMENTS:
        chain = Chain.from_beam(eb, n, like=presets.R161)
        row = {
            "segments": n,
            **{
                f"f{i + 1}_rel_err": float(f / w - 1)
                for i, (f, w) in enumerate(zip(chain.frequencies_hz[:3], want, strict=True))
            },
        }
        for x in points_m:
            impact = ChainImpact(
                chain=chain, ball=presets.BASEBALL, x_m=x, v0_mps=still.v0_mps, e=presets.E_WOOD
            )
            row[f"v1_chain_{x:g}_mps"] = compliant_reference(impact, REALISTIC_BALL).v1_mps
            row[f"v1_beam_{x:g}_mps"] = beam_v1[x]
        rows.append(row)
    return rows
