"""A grid of impact points, the tidy table of fired impacts, and locating marks on engine data.

Shared by the sweep, the studies, the benchmarks and the regression test, so every table is made
one way: each row judged (``judge``) against the answer that applies. The impacts themselves run
through ``experiments.core.runner``.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Iterable, Sequence
from dataclasses import dataclass

import numpy as np
import pandas as pd
from scipy import optimize

import adapters
from analytic import (
    Bat,
    EpisodeMark,
    ImpactCase,
    center_of_percussion,
    episode_cop_mark,
    episode_sweet_spot_mark,
    presets,
    sweet_spot,
)
from analytic.collide import MAX_EPISODE_S
from analytic.dynamics import HingedSwing
from analytic.marks import SINGLE_IMPULSE

from . import verdicts
from .fire import Fired, Job, Jobs, fire_jobs
from .fired import Gathered, gather

#: Columns of a sweep table, in order. Units are in the names.
COLUMNS = (
    "engine", "profile", "bat", "s_m", "v0_mps", "u0_mps", "omega0_radps", "e", "theta_rad",
    "v1_analytic_mps", "v1_engine_mps", "v1_abs_err_mps", "v1_rel_err", "v1_tol_mps",
    "v1_impulse_mps", "rigid_impacts", "rigid_sustained_s", "rigid_end", "v1_law_mps",
    "v1_law_err_mps", "v1_law_tol_mps",
    "u1_analytic_mps", "u1_engine_mps", "omega1_analytic_radps", "omega1_engine_radps",
    "hand_dv_analytic_mps", "hand_dv_engine_mps", "ke_before_j", "ke_after_j", "status",
    "episode_end", "ball_side_end_m", "contact_duration_s", "peak_penetration_m", "steps",
    "wall_s",
)
TIMING_COLUMNS = ("wall_s",)
#: Extra columns of a sweep whose bat is swung in the engine before each impact.
SWING_COLUMNS = ("release_omega_engine_radps", "release_omega_analytic_radps",
                 "release_angle_err_rad")


@dataclass(frozen=True, kw_only=True)
class Firing:
    """What to fire: one bat and ball, one motion, a grid of s. Units: m, m/s, rad/s, rad."""

    bat: Bat
    s_m: tuple[float, ...]
    v0_mps: float
    u0_mps: float
    omega0_radps: float
    e: float
    theta_rad: float = 0.0
    hands_from_knob_m: float = 0.1
    #: Swing the bat about the hands in the engine before each impact (u0, omega0 then come from
    #: the swing; ``u0_mps`` and ``omega0_radps`` are its nominal values).
    swing: HingedSwing | None = None
    #: Friction and the third dimension, as ``ImpactCase`` takes them (0: frictionless, planar).
    mu: float = 0.0
    undercut_m: float = 0.0
    spin_radps: tuple[float, float, float] = (0.0, 0.0, 0.0)

    def case(self, s_m: float) -> ImpactCase:
        """The impact at one grid point (validates every field)."""
        return ImpactCase(bat=self.bat, ball=presets.BASEBALL, s_m=s_m, v0_mps=self.v0_mps,
                          u0_mps=self.u0_mps, omega0_radps=self.omega0_radps, e=self.e,
                          theta_rad=self.theta_rad, hands_from_knob_m=self.hands_from_knob_m,
                          mu=self.mu, undercut_m=self.undercut_m, spin_radps=self.spin_radps)

    def cases(self) -> list[ImpactCase]:
        return [self.case(s) for s in self.s_m]

    def jobs(self, engine: str, settings: adapters.Settings) -> Jobs:
        """One job per grid point for an engine."""
        return Jobs(engine=engine, settings=settings, cases=self.cases(), swing=self.swing)


def grid(bat: Bat, points: int, s_min_m: float | None = None,
         s_max_m: float | None = None) -> tuple[float, ...]:
    """``points`` evenly spaced impact points over the bat's hittable length (or a part of it)."""
    lo = bat.s_min_m if s_min_m is None else s_min_m
    hi = bat.s_max_m if s_max_m is None else s_max_m
    if points < 2:
        raise ValueError(f"points={points} is too few; allowed: points >= 2")
    for name, value in (("s_min", lo), ("s_max", hi)):
        if not bat.s_min_m - 1e-12 <= value <= bat.s_max_m + 1e-12:
            raise ValueError(f"{name}={value:g} m is off the bat '{bat.name}'; allowed: "
                             f"{bat.s_min_m:.4f} <= s <= {bat.s_max_m:.4f} m (the capsule's "
                             "cylinder, from the COM)")
    if not lo < hi:
        raise ValueError(f"s_min={lo:g} >= s_max={hi:g}; allowed: s_min < s_max")
    return tuple(float(x) for x in np.linspace(lo, hi, points))


def table(fired: Sequence[Fired], profile: str, spin_columns: bool = False,
          error_models: verdicts.ErrorModels | None = None) -> pd.DataFrame:
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
        "engine": _texts(g.engines), "profile": _spread([profile], np.zeros(n, dtype=np.intp)),
        "bat": each([k.bat.name for k in cases]),
        **{f: each([getattr(k, f) for k in cases])
           for f in ("s_m", "v0_mps", "u0_mps", "omega0_radps", "e", "theta_rad")},
        "v1_analytic_mps": a["v1_analytic_mps"], "v1_engine_mps": c["v1_mps"],
        "v1_abs_err_mps": a["v1_abs_err_mps"], "v1_rel_err": _relative(a),
        "v1_tol_mps": a["v1_tol_mps"], "v1_impulse_mps": a["v1_impulse_mps"],
        "rigid_impacts": each([r.impacts for r in rigid]),
        "rigid_sustained_s": each([r.sustained_contact_s for r in rigid]),
        "rigid_end": each([r.ended for r in rigid]),
        **{k: a[k] for k in ("v1_law_mps", "v1_law_err_mps", "v1_law_tol_mps")},
        "u1_analytic_mps": a["u1_analytic_mps"], "u1_engine_mps": c["u1_mps"],
        "omega1_analytic_radps": a["omega1_analytic_radps"],
        "omega1_engine_radps": c["omega1_radps"],
        "hand_dv_analytic_mps": a["hand_dv_analytic_mps"], "hand_dv_engine_mps": c["hand_dv_mps"],
        "ke_before_j": c["ke_before_j"], "ke_after_j": c["ke_after_j"],
        "status": _text(v.status), "episode_end": _text(c["ended"]),
        "ball_side_end_m": c["ball_side_m"], "contact_duration_s": c["contact_duration_s"],
        "peak_penetration_m": c["peak_penetration_m"], "steps": c["steps"],
        "wall_s": c["wall_s"],
    }
    cols.update({k: x for k, x in a.items() if k not in _LAID_OUT})
    if np.isfinite(c["release_omega_analytic_radps"]).any():
        cols["release_omega_engine_radps"] = c["release_omega_radps"]
        cols["release_omega_analytic_radps"] = c["release_omega_analytic_radps"]
        cols["release_angle_err_rad"] = c["release_angle_rad"] - c["release_angle_analytic_rad"]
    return pd.DataFrame(cols, copy=False)  # (columns made here, not shared)


#: The judge's answers laid out above (the rest, friction's, are added as they come).
_LAID_OUT = frozenset(("v1_analytic_mps", "v1_abs_err_mps", "v1_tol_mps", "v1_impulse_mps",
                       "rigid_episodes", "rows", "v1_law_mps", "v1_law_err_mps",
                       "v1_law_tol_mps", "u1_analytic_mps", "omega1_analytic_radps",
                       "hand_dv_analytic_mps"))


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


def _engine_values(name: str, settings: adapters.Settings, firing: Firing, s_m,
                   field: str) -> np.ndarray:
    """``field`` of the engine's outcome at each s, fired together (one batch on a batched
    engine); NaN where the impact is not sound (simulate's verdict)."""
    jobs = [Job(engine=name, settings=settings, case=firing.case(float(s)), swing=firing.swing)
            for s in s_m]
    return np.array([getattr(f.outcome, field) if f.outcome.ok else math.nan
                     for f in fire_jobs(jobs)])


def _engine_value(name: str, settings: adapters.Settings, firing: Firing, s: float,
                  field: str) -> float:
    return float(_engine_values(name, settings, firing, [s], field)[0])


#: Points per round of a batched engine's search: each round is one batch, and narrows the
#: bracket to two (a maximum) or one (a root) of its REFINE_POINTS - 1 intervals.
REFINE_POINTS = 17


def _refine(name: str, settings: adapters.Settings, firing: Firing, bracket, field: str,
            tol_m: float, kind: str) -> float:
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


def locate_sweet_spot(name: str, settings: adapters.Settings, firing: Firing,
                      bracket: tuple[float, float], xatol_m: float = 1e-7) -> float:
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

    res = optimize.minimize_scalar(minus_v1, bounds=bracket, method="bounded",
                                   options={"xatol": xatol_m})
    return float(res.x) if math.isfinite(res.fun) and not failed else math.nan


def locate_cop(name: str, settings: adapters.Settings, firing: Firing,
               bracket: tuple[float, float], xtol_m: float = 1e-9) -> float:
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
    single = {"sweet_spot": sweet_spot(bat, presets.BASEBALL, firing.v0_mps, firing.u0_mps,
                                       firing.omega0_radps, theta_rad=firing.theta_rad),
              "cop": center_of_percussion(bat, firing.hands_from_knob_m)}
    case = firing.case(firing.s_m[0])  # its speeds: the marks' searches set their own s
    # with friction or out of the swing plane the rows' answer is a frictional impulse
    # (judge.rigid), on which nothing is located: the frictionless closed forms, said so
    left_out = "frictionless and in the swing plane: the firing's friction or tilt is not in it"
    found = {k: EpisodeMark(s_m=v, reference=SINGLE_IMPULSE, why=left_out)
             for k, v in single.items()}
    if case.frictionless_planar:
        found = {"sweet_spot": episode_sweet_spot_mark(case, max_episode_s=max_episode_s),
                 "cop": episode_cop_mark(case, max_episode_s=max_episode_s)}
    out: dict = {}
    for k, mark in found.items():
        out.update({f"{k}_m": mark.s_m, f"{k}_reference": mark.reference,
                    f"{k}_single_impulse_m": single[k]})
        if mark.why:
            out[f"{k}_why"] = mark.why
    s_star = out["sweet_spot_m"]
    out["sweet_spot_hittable_m"] = (min(max(s_star, bat.s_min_m), bat.s_max_m)
                                    if math.isfinite(s_star) else math.nan)
    out.update(cylinder_s_min_m=bat.s_min_m, cylinder_s_max_m=bat.s_max_m)
    return tuple(out.items())


def bracket_around(s: Iterable[float], values: Iterable[float],
                   kind: str) -> tuple[float, float] | None:
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
