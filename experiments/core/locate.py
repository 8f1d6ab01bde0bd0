"""Locating the sweet spot and the centre of percussion on an engine's own data: a study of
its own, firing more impacts where the grid brackets a mark (a bounded search on a
single-world engine, grids fired at once on a batched one), and the analytic marks each is
compared with, those of the answer the rows are judged against (``analytic.marks``)."""

from __future__ import annotations

import functools
import math
from collections.abc import Iterable

import numpy as np
from scipy import optimize

import adapters
from analytic import (
    EpisodeMark,
    center_of_percussion,
    episode_cop_mark,
    episode_sweet_spot_mark,
    presets,
    sweet_spot,
)
from analytic.collide import MAX_EPISODE_S
from analytic.marks import SINGLE_IMPULSE

from .fire import Job, fire_jobs
from .firings import Firing


def _engine_values(
    name: str, settings: adapters.Settings, firing: Firing, s_m, field: str
) -> np.ndarray:
    """``field`` of the engine's outcome at each s, fired together (one batch on a batched
    engine); NaN where the impact is not sound (simulate's verdict)."""
    jobs = [
        Job(engine=name, settings=settings, case=firing.case(float(s)), swing=firing.swing)
        for s in s_m
    ]
    return np.array(
        [getattr(f.outcome, field) if f.outcome.sound else math.nan for f in fire_jobs(jobs)]
    )


def _engine_value(
    name: str, settings: adapters.Settings, firing: Firing, s: float, field: str
) -> float:
    return float(_engine_values(name, settings, firing, [s], field)[0])


#: Points per round of a batched engine's search: each round is one batch, and narrows the
#: bracket to two (a maximum) or one (a root) of its REFINE_POINTS - 1 intervals.
REFINE_POINTS = 17


def _refine(
    name: str,
    settings: adapters.Settings,
    firing: Firing,
    bracket,
    field: str,
    tol_m: float,
    kind: str,
) -> float:
    """The engine's argmax (kind 'max') or root ('root') of ``field`` in ``bracket`` by grids of
    REFINE_POINTS fired at once, to ``tol_m``: a batched engine's search (a step of one world
    costs it about as much as a step of all of them). NaN if an impact fails."""
    lo, hi = bracket
    while hi - lo > tol_m:
        s = np.linspace(lo, hi, REFINE_POINTS)
        v = _engine_values(name, settings, firing, s, field)
        if not np.isfinite(v).all():
            return math.nan
        if kind == "max":
            i = int(np.argmax(v))
            lo, hi = s[max(i - 1, 0)], s[min(i + 1, REFINE_POINTS - 1)]
            continue
        change = np.nonzero(np.sign(v[:-1]) * np.sign(v[1:]) <= 0)[0]
        if not len(change):
            return math.nan
        lo, hi = s[change[0]], s[change[0] + 1]
    return float(0.5 * (lo + hi))


def locate_sweet_spot(
    name: str,
    settings: adapters.Settings,
    firing: Firing,
    bracket: tuple[float, float],
    xatol_m: float = 1e-7,
) -> float:
    """argmax of the engine's v1(s) inside ``bracket`` (bounded Brent search on simulations;
    grids fired at once on a batched engine, ``_refine``).

    Returns NaN if any simulation in the search fails.
    """
    if adapters.record(name).batched:
        return _refine(name, settings, firing, bracket, "v1_mps", xatol_m, "max")
    failed = []  # a NaN steers the bounded search anywhere: any one voids the result

    def minus_v1(s: float) -> float:
        v = _engine_value(name, settings, firing, s, "v1_mps")
        failed.extend([s] if not math.isfinite(v) else [])
        return -v

    res = optimize.minimize_scalar(
        minus_v1, bounds=bracket, method="bounded", options={"xatol": xatol_m}
    )
    return float(res.x) if math.isfinite(res.fun) and not failed else math.nan


def locate_cop(
    name: str,
    settings: adapters.Settings,
    firing: Firing,
    bracket: tuple[float, float],
    xtol_m: float = 1e-9,
) -> float:
    """The s where the engine's hand-point velocity change crosses zero (Brent's root finder;
    grids fired at once on a batched engine, ``_refine``).

    Returns NaN if the bracket holds no sign change or a simulation fails.
    """

    def hand(s: float) -> float:
        return _engine_value(name, settings, firing, s, "hand_dv_mps")

    a, b = hand(bracket[0]), hand(bracket[1])
    if not (math.isfinite(a) and math.isfinite(b)) or a * b > 0:
        return math.nan
    if adapters.record(name).batched:
        return _refine(name, settings, firing, bracket, "hand_dv_mps", xtol_m, "root")
    try:
        return float(optimize.brentq(hand, *bracket, xtol=xtol_m))
    except (ValueError, RuntimeError):
        return math.nan


def analytic_marks(firing: Firing, max_episode_s: float = MAX_EPISODE_S) -> dict:
    """The analytic sweet spot and COP (s in m from the COM) for a firing, each that of the
    answer its rows are judged against (``analytic.marks``): for a frictionless planar firing
    the whole rigid episode's (``judge.rigid``, followed for ``max_episode_s``, the engines'
    ``max_contact_s``; at e = 0 a sustained contact moves both), located on ``collide`` as an
    engine's are on its own outcomes, or the single impulse's closed form where the episode at
    it is that impulse; else the single impulse's closed form. ``*_reference`` says which:
    'single impulse', 'whole episode', or 'none' (the mark NaN, ``*_why`` saying why: the
    episode there is still in contact at the budget, say; with friction, what the frictionless
    closed form leaves out), and ``*_single_impulse_m`` gives the closed form beside it. A
    sweet spot beyond the cylinder's ends is flagged by the best point the bat offers,
    ``sweet_spot_hittable_m``, the nearer end; ``cylinder_s_min_m`` and ``cylinder_s_max_m``
    are the cylinder's ends (s, m). Cached: the sweep asks twice."""
    return dict(_marks(firing, float(max_episode_s)))


@functools.lru_cache(maxsize=16)
def _marks(firing: Firing, max_episode_s: float) -> tuple:
    bat = firing.bat
    single = {
        "sweet_spot": sweet_spot(
            bat,
            presets.BASEBALL,
            firing.v0_mps,
            firing.u0_mps,
            firing.omega0_radps,
            theta_rad=firing.theta_rad,
        ),
        "cop": center_of_percussion(bat, firing.hands_from_knob_m),
    }
    case = firing.case(firing.s_m[0])  # its speeds: the marks' searches set their own s
    # with friction or out of the swing plane the rows' answer is a frictional impulse
    # (judge.rigid), on which nothing is located: the frictionless closed forms, said so
    left_out = "frictionless and in the swing plane: the firing's friction or tilt is not in it"
    found = {
        k: EpisodeMark(s_m=v, reference=SINGLE_IMPULSE, why=left_out) for k, v in single.items()
    }
    if case.frictionless_planar:
        found = {
            "sweet_spot": episode_sweet_spot_mark(case, max_episode_s=max_episode_s),
            "cop": episode_cop_mark(case, max_episode_s=max_episode_s),
        }
    out: dict = {}
    for k, mark in found.items():
        out.update(
            {
                f"{k}_m": mark.s_m,
                f"{k}_reference": mark.reference,
                f"{k}_single_impulse_m": single[k],
            }
        )
        if mark.why:
            out[f"{k}_why"] = mark.why
    s_star = out["sweet_spot_m"]
    out["sweet_spot_hittable_m"] = (
        min(max(s_star, bat.s_min_m), bat.s_max_m) if math.isfinite(s_star) else math.nan
    )
    out.update(cylinder_s_min_m=bat.s_min_m, cylinder_s_max_m=bat.s_max_m)
    return tuple(out.items())


def bracket_around(
    s: Iterable[float], values: Iterable[float], kind: str
) -> tuple[float, float] | None:
    """A bracket from grid data: around the max (kind='max') or a sign change (kind='root')."""
    s, v = np.asarray(list(s)), np.asarray(list(values), dtype=float)
    ok = np.isfinite(v)
    s, v = s[ok], v[ok]
    if len(s) < 3:
        return None
    if kind == "max":
        i = int(np.argmax(v))
        return float(s[max(i - 1, 0)]), float(s[min(i + 1, len(s) - 1)])
    change = np.nonzero(np.sign(v[:-1]) * np.sign(v[1:]) <= 0)[0]
    return (float(s[change[0]]), float(s[change[0] + 1])) if len(change) else None
