"""Every engine's segmented bat: N = 8 at its reference profile over the barrel, and a
stability map over N x dt.

Each row is ``experiments.core.chain.fire_chain``'s: the engine's exit speed beside the
linear chain's (Newton's restitution at every touch for a rigid contact, the engine's own
compliant law for a soft one), its tolerance and its status. References depend on the impact
and the contact law only, so each is solved once and shared by every engine and step.
"""

from __future__ import annotations

from functools import cache

import numpy as np

import adapters
from analytic import presets
from analytic.chain import Chain
from analytic.chain_impact import ChainImpact

from ..core import chain as core_chain
from ..core.judge import Status
from .flex_beam import r161_beam

#: The chain of the accuracy table, and its 11 impact points (m from the knob).
SEGMENTS = 8
POINTS_M = tuple(np.round(np.linspace(0.30, 0.80, 11), 3))
#: The stability map: segment counts, time steps (s) and its impact point (m from the knob:
#: the first mode's barrel node, the speed sweet spot's neighbourhood).
MAP_SEGMENTS = (4, 8, 16, 32, 64)
MAP_STEPS_S = (1e-4, 1e-5, 1e-6)
MAP_POINT_M = 0.66
#: The ball: a 40 m/s pitch on a bat at rest (the chain is linear: no swing's turn), e 0.5.
V0_MPS = 40.0
#: A map cell whose estimated cost exceeds this is not fired (s): 'unsupported'. The estimate:
#: the engine's wall time per step and body on its N = 8 rows, times N + 1 bodies, times the
#: episode's steps (a contact's few milliseconds and the quiet period after it).
MAP_BUDGET_S = 60.0


def chain_engines(names) -> list[str]:
    """The engines among ``names`` that build a segmented bat."""
    return [n for n in names if adapters.record(n).can.chain_adapter]


@cache
def r161_chain(segments: int) -> Chain:
    """The R161 (Euler-Bernoulli beam: the chain's springs are bending's alone) in pieces."""
    return Chain.from_beam(r161_beam(1.0, shear=False), segments, like=presets.R161)


def impact(segments: int, x_m: float) -> ChainImpact:
    return ChainImpact(
        chain=r161_chain(segments), ball=presets.BASEBALL, x_m=x_m, v0_mps=V0_MPS, e=presets.E_WOOD
    )


@cache
def _reference(segments: int, x_m: float, law_key: str, law):
    return core_chain.reference_for_law(impact(segments, x_m), law)


def fire(name: str, settings, segments: int, x_m: float) -> dict:
    """One row, its reference shared through the cache."""
    law = adapters.record(name).errors.contact_law(settings, presets.E_WOOD)
    ref = _reference(segments, x_m, repr(law), law)
    return core_chain.fire_chain(name, settings, impact(segments, x_m), known=ref)


def accuracy_rows(names, tick=lambda n: None) -> list[dict]:
    """N = SEGMENTS at every engine's reference profile, POINTS_M; ``tick(1)`` after each."""
    rows = []
    for n in chain_engines(names):
        for x in POINTS_M:
            rows.append(fire(n, adapters.settings_for(n), SEGMENTS, x) | {"profile": "reference"})
            tick(1)
    return rows


def stability_rows(
    names, step_body_s: dict, steps_s=MAP_STEPS_S, segments=MAP_SEGMENTS, tick=lambda n: None
) -> list[dict]:
    """MAP_POINT_M at every N and dt, the reference profile otherwise (cells over the budget
    are rows too, 'unsupported'); ``step_body_s``: per engine, its wall time per step and
    body (s); ``tick(1)`` after each cell."""
    rows = []
    for n in chain_engines(names):
        for k in segments:
            for dt in steps_s:
                rows.append(_map_cell(n, k, dt, step_body_s[n]) | {"profile": "reference"})
                tick(1)
    return rows


def step_body_cost_s(rows: list[dict]) -> float:
    """Median wall time per step and body over an engine's fired rows (s)."""
    costs = [r["wall_s"] / r["steps"] / (r["segments"] + 1) for r in rows if r.get("steps")]
    return float(np.median(costs)) if costs else 0.0


def _map_cell(name: str, segments: int, dt_s: float, step_body_s: float) -> dict:
    chain = r161_chain(segments)
    lowest = float(chain.modes[0][chain.modes[0] > 0].min())
    episode_s = 2e-3 + 2 * np.pi / lowest
    cost = step_body_s * (segments + 1) * episode_s / dt_s
    if cost > MAP_BUDGET_S:
        return {
            "engine": name,
            "segments": segments,
            "dt_s": dt_s,
            "x_m": MAP_POINT_M,
            "status": Status.UNSUPPORTED.value,
            "why": f"over the map's budget ({cost:.0f} s est.)",
        }
    return fire(name, adapters.settings_for(name, dt_s=dt_s), segments, MAP_POINT_M)
