"""The tidy table of fired impacts: their columns and their verdicts, laid out.

Shared by the sweep, the studies, the benchmarks and the regression test, so every table is made
one way. It judges nothing: each row's verdict comes from the one judge (``verdicts``), called
where the firing ends; what to fire is ``firings``, locating marks on engine data ``locate``.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Sequence

import numpy as np
import pandas as pd

from . import verdicts
from .fire import Fired
from .fired import Gathered, gather

#: Columns of a sweep table, in order. Units are in the names.
COLUMNS = (
    "engine",
    "profile",
    "bat",
    "s_m",
    "v0_mps",
    "u0_mps",
    "omega0_radps",
    "e",
    "theta_rad",
    "v1_analytic_mps",
    "v1_engine_mps",
    "v1_abs_err_mps",
    "v1_rel_err",
    "v1_tol_mps",
    "v1_impulse_mps",
    "rigid_impacts",
    "rigid_sustained_s",
    "rigid_end",
    "v1_law_mps",
    "v1_law_err_mps",
    "v1_law_tol_mps",
    "u1_analytic_mps",
    "u1_engine_mps",
    "omega1_analytic_radps",
    "omega1_engine_radps",
    "hand_dv_analytic_mps",
    "hand_dv_engine_mps",
    "ke_before_j",
    "ke_after_j",
    "status",
    "physics",
    "episode_end",
    "ball_side_end_m",
    "contact_duration_s",
    "peak_penetration_m",
    "steps",
    "wall_s",
)
TIMING_COLUMNS = ("wall_s",)
#: Extra columns of a sweep whose bat is swung in the engine before each impact.
SWING_COLUMNS = (
    "release_omega_engine_radps",
    "release_omega_analytic_radps",
    "release_angle_err_rad",
)


def table(
    fired: Sequence[Fired],
    profile: str,
    spin_columns: bool = False,
    error_models: verdicts.ErrorModels | None = None,
) -> pd.DataFrame:
    """The tidy table of fired impacts, one row per impact in order: the case, the answers it
    was judged against (``verdicts.judge_columns``: the rigid-body answer, ``analytic.collide``'s
    whole episode followed as long as the engine's budget, the single impulse beside it, the
    engine's own contact law), the engine's outcome, their difference, the tolerance and the
    verdict. With a swing (any NaN-free release), the SWING_COLUMNS too; with friction or out
    of the swing plane (or ``spin_columns``: a flight needs them), ``friction_judge.columns``.
    It lays columns out; it judges nothing itself."""
    g = gather(fired)
    v = verdicts.judge_columns(g, error_models, spin_columns)
    return layout(g, v, profile)


def layout(g: Gathered, v: verdicts.Verdicts, profile: str) -> pd.DataFrame:
    """The table of gathered impacts ``g`` and their verdicts ``v`` (``table``)."""
    c, n, a = g.cols, len(g.cases), v.answers
    inv = a["rows"]
    each = functools.partial(_spread, rows=inv)
    rigid = a["rigid_episodes"]
    cases = [g.cases[i] for i in _firsts(inv, len(rigid))]
    cols = {
        "engine": _texts(g.engines),
        "profile": _spread([profile], np.zeros(n, dtype=np.intp)),
        "bat": each([k.bat.name for k in cases]),
        **{
            f: each([getattr(k, f) for k in cases])
            for f in ("s_m", "v0_mps", "u0_mps", "omega0_radps", "e", "theta_rad")
        },
        "v1_analytic_mps": a["v1_analytic_mps"],
        "v1_engine_mps": c["v1_mps"],
        "v1_abs_err_mps": a["v1_abs_err_mps"],
        "v1_rel_err": _relative(a),
        "v1_tol_mps": a["v1_tol_mps"],
        "v1_impulse_mps": a["v1_impulse_mps"],
        "rigid_impacts": each([r.impacts for r in rigid]),
        "rigid_sustained_s": each([r.sustained_contact_s for r in rigid]),
        "rigid_end": each([r.ended for r in rigid]),
        **{k: a[k] for k in ("v1_law_mps", "v1_law_err_mps", "v1_law_tol_mps")},
        "u1_analytic_mps": a["u1_analytic_mps"],
        "u1_engine_mps": c["u1_mps"],
        "omega1_analytic_radps": a["omega1_analytic_radps"],
        "omega1_engine_radps": c["omega1_radps"],
        "hand_dv_analytic_mps": a["hand_dv_analytic_mps"],
        "hand_dv_engine_mps": c["hand_dv_mps"],
        "ke_before_j": c["ke_before_j"],
        "ke_after_j": c["ke_after_j"],
        "status": _text(v.status),
        "physics": _text(c["physics"]),
        "episode_end": _text(c["ended"]),
        "ball_side_end_m": c["ball_side_m"],
        "contact_duration_s": c["contact_duration_s"],
        "peak_penetration_m": c["peak_penetration_m"],
        "steps": c["steps"],
        "wall_s": c["wall_s"],
    }
    cols.update({k: x for k, x in a.items() if k not in _LAID_OUT})
    if np.isfinite(c["release_omega_analytic_radps"]).any():
        cols["release_omega_engine_radps"] = c["release_omega_radps"]
        cols["release_omega_analytic_radps"] = c["release_omega_analytic_radps"]
        cols["release_angle_err_rad"] = c["release_angle_rad"] - c["release_angle_analytic_rad"]
    return pd.DataFrame(cols, copy=False)  # (columns made here, not shared)


#: The judge's answers laid out above (the rest, friction's, are added as they come).
_LAID_OUT = frozenset(
    (
        "v1_analytic_mps",
        "v1_abs_err_mps",
        "v1_tol_mps",
        "v1_impulse_mps",
        "rigid_episodes",
        "rows",
        "v1_law_mps",
        "v1_law_err_mps",
        "v1_law_tol_mps",
        "u1_analytic_mps",
        "omega1_analytic_radps",
        "hand_dv_analytic_mps",
    )
)


def _relative(a: dict) -> np.ndarray:
    """|v1 engine - v1 rigid| / |v1 rigid| (inf where the rigid v1 is 0)."""
    ref = a["v1_analytic_mps"]
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(ref != 0.0, a["v1_abs_err_mps"] / np.abs(ref), math.inf)


def _firsts(rows: np.ndarray, k: int) -> np.ndarray:
    """The first row of each of the ``k`` distinct impacts ``rows`` index."""
    first = np.full(k, -1, dtype=np.intp)
    first[rows[::-1]] = np.arange(len(rows) - 1, -1, -1)
    return first


def _spread(values: list, rows: np.ndarray):
    """One value per distinct impact (``values``) spread over the rows: an array, or for
    strings a column as pandas stores them (``_text``), taken from the few values made once."""
    if bool(values) and isinstance(values[0], str):
        return _text(values).take(rows)
    return np.array(values)[rows]


def _text(values) -> pd.api.extensions.ExtensionArray:
    """Strings as pandas stores them (its 'str' dtype), made from Python strings: its own
    inference from numpy's fixed-width strings costs ten times as much (about 0.6 against
    0.06 ms a column of 1e4)."""
    return pd.array(np.asarray(values, dtype=object), dtype="str")


def _texts(values: list) -> pd.api.extensions.ExtensionArray:
    """``_text`` of strings that are often all one value (an engine's name on every row)."""
    if values and values.count(values[0]) == len(values):  # (C speed: compared by identity)
        return _spread(values[:1], np.zeros(len(values), dtype=np.intp))
    return _text(values)
