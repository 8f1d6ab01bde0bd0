"""How long an engine's work may take on the wall clock before it is a ``timeout``: a batch's
limit (``limit_s``), for ``adapters.clock.limited`` to hold it to (``fire.guarded``), and a
worker's chunk's (``runner``), for a hang in compiled code that only stopping the worker ends.
"""

from __future__ import annotations

import math

import adapters

#: A batch of impacts may take this many times its worst-case cost (every episode stepped to
#: ``max_contact_s``, at the record's step cost) before it is a timeout: the record's costs are
#: measured on one 2-core host and a loaded one may be ten times slower; a hang is not slow.
SLACK = 50.0
#: No batch is a timeout before this (s): starting an engine (a JAX compile, a Warp module's
#: load) is part of its first batch, whatever its record says.
FLOOR_S = 60.0


def limit_s(
    record: adapters.EngineRecord,
    settings: adapters.Settings,
    worlds: int,
    swing_steps: int = 0,
    floor_s: float = FLOOR_S,
    batched: bool | None = None,
) -> float:
    """How long a batch of ``worlds`` impacts on this engine may take (s): the record's own
    ``Cost.impact_limit_s`` per impact where it sets one (a batched engine's worlds stepping
    together, once for them all), else SLACK times the worst case (at least ``floor_s``),
    plus the engine's start-up. ``batched``: its adapter's form (default: its record's)."""
    cost = record.cost
    per_world = 1 if (record.batched if batched is None else batched) else worlds
    if cost.impact_limit_s is not None:
        return cost.start_s + cost.impact_limit_s * per_world
    steps = (
        settings.approach_steps
        + math.ceil(settings.max_contact_s / settings.dt_s)
        + 2
        + swing_steps
    )
    step = cost.step_cost_s * per_world + (cost.world_step_cost_s or 0.0) * worlds
    return cost.start_s + max(floor_s, SLACK * steps * step)
