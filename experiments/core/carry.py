"""Where each batted ball lands (``--flight``): its flight from the contact point, analytic and
engine, through ``analytic.flight`` (gravity, Nathan's drag and lift).

The ball leaves the bat with the velocity and spin a table's row holds, in the impact frame (x
along the bat, y toward the outfield, z = x cross y up: the swing plane level), from the
contact point ``height_m`` above the ground; the spin about y (along the ball's path, no lift)
is not in the table and is taken as 0.
"""

from __future__ import annotations

import math

import numpy as np
import pandas as pd

from analytic import flight
from analytic.model import MAX_SPIN_RADPS

#: The columns ``with_flight`` adds, per side (analytic, engine): launch angle (deg), carry
#: (m) and hang time (s); and |carry engine - carry analytic| (m).
FLIGHT_COLUMNS = (
    "launch_analytic_deg",
    "launch_engine_deg",
    "carry_analytic_m",
    "carry_engine_m",
    "carry_abs_err_m",
    "hang_analytic_s",
    "hang_engine_s",
)


def _fly(v, w, height_m: float) -> tuple[float, float, float]:
    """(launch angle deg, carry m, hang s) of a ball leaving with v and w (impact frame); NaN
    for a ball that does not fly out (non-finite, or not moving toward the outfield) or that
    the flight model does not hold (faster than ``flight.MAX_SPEED_MPS``, spinning faster than
    ``MAX_SPIN_RADPS``: an engine's blow-up)."""
    if (
        not (np.isfinite(v).all() and np.isfinite(w).all())
        or not v[1] > 0.0
        or np.linalg.norm(v) > flight.MAX_SPEED_MPS
        or np.abs(w).max() > MAX_SPIN_RADPS
    ):
        return math.nan, math.nan, math.nan
    launch = flight.batted_ball_launch(v, w, height_m=height_m)
    if launch.launch_rad <= 0.0 and height_m <= 0.0:
        return math.degrees(launch.launch_rad), 0.0, 0.0
    out = flight.fly_vectors(
        [0.0, 0.0, height_m], flight.impact_to_field(v), flight.impact_to_field(w), samples=2
    )
    return math.degrees(launch.launch_rad), out.carry_m, out.hang_s


def with_flight(table: pd.DataFrame, height_m: float = 0.9) -> pd.DataFrame:
    """``table`` (with ``friction_judge``'s columns) with FLIGHT_COLUMNS."""
    out = table.copy()
    for side in ("analytic", "engine"):
        v = table[[f"vt1_{side}_mps", f"v1_{side}_mps", f"vz1_{side}_mps"]].to_numpy(float)
        w = np.column_stack(
            [table[f"backspin1_{side}_radps"], np.zeros(len(table)), table[f"spin1_{side}_radps"]]
        )
        got = np.array([_fly(v[i], w[i], height_m) for i in range(len(table))]).reshape(-1, 3)
        out[f"launch_{side}_deg"], out[f"carry_{side}_m"] = got[:, 0], got[:, 1]
        out[f"hang_{side}_s"] = got[:, 2]
    out["carry_abs_err_m"] = (out.carry_engine_m - out.carry_analytic_m).abs()
    return out[[*table.columns, *FLIGHT_COLUMNS]]
