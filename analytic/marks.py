"""The sweet spot and the centre of percussion of the answer that applies: the whole rigid episode.

The closed forms (``impact.sweet_spot``, ``impact.center_of_percussion``) are those of one
instantaneous impulse. Where the whole episode (``collide``) at the mark is that impulse alone,
they are its marks, exact. Where it is not (e near 0: a sustained contact while the bat turns,
or a second impact), the episode's outcomes differ and so do its marks: the sweet spot is where
the episode's v1 peaks, the COP where its hand-point velocity change crosses zero, each found on
``collide``'s outcomes as an engine's are found on its own (a grid over the bat's cylinder, then
a bounded search or a root). A mark whose episode is still in contact at the budget
(``max_episode_s``, the engines' ``max_contact_s``) has no reference: the episode there is cut,
not over, and an engine's impact there is not sound either.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass, replace

import numpy as np
from scipy import optimize

from . import checks
from .collide import MAX_EPISODE_S, CollisionEpisode, collide
from .impact import center_of_percussion, sweet_spot
from .model import ImpactCase

#: What a mark is located on.
SINGLE_IMPULSE, WHOLE_EPISODE, NO_REFERENCE = "single impulse", "whole episode", "none"
#: A root whose two sides differ by more than this many times the change one step further out
#: is a jump between kinds of episode (one impact and two, say), not a crossing.
JUMP_RATIO = 10.0
#: Steps (m) either side of a root for that test: far above the root's tolerance (1e-12 m), and
#: a change (about 1e-5 m/s at the R161's slope) far above the episode's ODE noise (~1e-11 m/s).
JUMP_STEP_M = 1e-7


@dataclass(frozen=True, kw_only=True)
class EpisodeMark:
    """A mark on the bat (``s_m``, m from the COM; NaN with ``reference`` 'none') and what it
    was located on: 'single impulse' (the closed form, exact where the episode there is that
    impulse), 'whole episode' (``collide``'s outcomes) or 'none'; ``why``: why none, or what a
    closed form kept where it is not the whole answer leaves out."""

    s_m: float
    reference: str
    why: str = ""

    def __post_init__(self) -> None:
        checks.choice("reference", self.reference, (SINGLE_IMPULSE, WHOLE_EPISODE, NO_REFERENCE))


def _none(why: str) -> EpisodeMark:
    return EpisodeMark(s_m=math.nan, reference=NO_REFERENCE, why=why)


@functools.lru_cache(maxsize=64)
def _episode(case: ImpactCase, s_m: float, max_episode_s: float) -> CollisionEpisode | None:
    """The whole episode at ``s_m`` (None where the bodies do not approach there)."""
    try:
        return collide(replace(case, s_m=float(s_m)), max_episode_s=max_episode_s)
    except ValueError:  # the closing speed is <= 0 there: no impact
        return None


def _is_single(ep: CollisionEpisode | None) -> bool:
    return ep is not None and ep.impacts == 1 and ep.sustained_contact_s == 0.0


def _grid(case: ImpactCase, points: int) -> np.ndarray:
    bat = case.bat
    return np.linspace(bat.s_min_m, bat.s_max_m, points)


def _cut(case: ImpactCase, s_m: float, max_episode_s: float, mark: str) -> EpisodeMark:
    """The whole episode's ``mark`` at ``s_m``, or none where that episode is cut at the
    budget."""
    ep = _episode(case, s_m, max_episode_s)
    if ep is None or ep.ended == "time_limit":
        return _none(
            f"the rigid episode at the {mark} ({s_m:.4f} m) is still in contact at "
            f"the {max_episode_s:g} s budget"
        )
    return EpisodeMark(s_m=float(s_m), reference=WHOLE_EPISODE)


def episode_sweet_spot_mark(
    case: ImpactCase, *, max_episode_s: float = MAX_EPISODE_S, points: int = 41
) -> EpisodeMark:
    """Where the whole episode's v1 peaks on the bat's cylinder, at ``case``'s speeds. The
    closed form s* (``sweet_spot``) where the episode there is one impulse and none of
    ``points`` grid points hits harder; else the grid's best, refined to 1 um by a bounded
    search between its neighbours."""
    checks.instance("case", case, ImpactCase)
    checks.positive("max_episode_s", max_episode_s)
    checks.integer("points", points, 3, 10_000)
    bat = case.bat
    s_star = float(
        sweet_spot(
            bat,
            case.ball,
            case.v0_mps,
            case.u0_mps,
            case.omega0_radps,
            theta_rad=case.theta_rad,
            phi_rad=case.phi_rad,
        )
    )
    at = min(max(s_star, bat.s_min_m), bat.s_max_m)

    def v1(s: float) -> float:
        ep = _episode(case, s, max_episode_s)
        return -math.inf if ep is None else ep.v1_mps

    grid = _grid(case, points)
    best = max(grid, key=v1)
    if _is_single(_episode(case, at, max_episode_s)) and v1(best) <= v1(at):
        return EpisodeMark(s_m=s_star, reference=SINGLE_IMPULSE)
    i = int(np.searchsorted(grid, best))
    lo, hi = grid[max(i - 1, 0)], grid[min(i + 1, len(grid) - 1)]
    found = optimize.minimize_scalar(
        lambda s: -v1(s), bounds=(lo, hi), method="bounded", options={"xatol": 1e-6}
    )
    return _cut(case, float(found.x), max_episode_s, "sweet spot")


def episode_cop_mark(
    case: ImpactCase, *, max_episode_s: float = MAX_EPISODE_S, points: int = 41
) -> EpisodeMark:
    """Where the whole episode's hand-point velocity change (``hand_dv_mps``, the hands at
    ``case.hands_from_knob_m``) crosses zero on the bat's cylinder. The closed form
    J / (M d) (``center_of_percussion``) where the episode there (at the cylinder's nearer end
    if it lies beyond) is one impulse; else the crossing of ``points`` grid points nearest it,
    refined by Brent's method to 1e-12 m; none where there is no crossing, or where the
    crossing is a jump between kinds of episode (JUMP_RATIO)."""
    checks.instance("case", case, ImpactCase)
    checks.positive("max_episode_s", max_episode_s)
    checks.integer("points", points, 3, 10_000)
    bat = case.bat
    s_cop = center_of_percussion(bat, case.hands_from_knob_m)
    at = min(max(s_cop, bat.s_min_m), bat.s_max_m)
    if _is_single(_episode(case, at, max_episode_s)):
        return EpisodeMark(s_m=s_cop, reference=SINGLE_IMPULSE)

    def hand(s: float) -> float:
        ep = _episode(case, s, max_episode_s)
        return math.nan if ep is None else ep.hand_dv_mps

    grid = _grid(case, points)
    dv = np.array([hand(s) for s in grid])
    signs = np.sign(dv)
    change = np.flatnonzero(
        np.isfinite(dv[:-1]) & np.isfinite(dv[1:]) & (signs[:-1] * signs[1:] <= 0)
    )
    if not len(change):
        return _none(
            "the rigid episode's hand-point velocity change does not cross zero on the bat"
        )
    k = min(change, key=lambda j: abs(0.5 * (grid[j] + grid[j + 1]) - s_cop))
    root = optimize.brentq(hand, grid[k], grid[k + 1], xtol=1e-12)
    h = JUMP_STEP_M
    near, far = (
        hand(root + h) - hand(root - h),
        max(abs(hand(root + 2 * h) - hand(root + h)), abs(hand(root - h) - hand(root - 2 * h))),
    )
    if not abs(near) <= JUMP_RATIO * far:
        return _none(
            f"the rigid episode's hand-point velocity change jumps across zero at "
            f"{root:.4f} m (a change of episode), it does not cross it"
        )
    return _cut(case, root, max_episode_s, "COP")


def episode_sweet_spot(
    case: ImpactCase, *, points: int = 41, max_episode_s: float | None = None
) -> float:
    """The sweet spot of the whole rigid episode (``collide``, followed for ``max_episode_s``,
    default its own) at ``case``'s speeds: where its batted-ball speed peaks on the bat's
    cylinder (m from the COM). Where the episode is one impulse at the closed-form s* and no
    grid point hits harder, that is s* (``sweet_spot``, exact); where it is not (e near 0: a
    sustained contact or a second impact changes v1), the episode's own peak: the best of
    ``points`` grid points, refined to 1 um by a bounded search between its neighbours; NaN
    where the episode there is still in contact at the budget (``marks.episode_sweet_spot_mark``
    says which)."""
    budget = {} if max_episode_s is None else {"max_episode_s": max_episode_s}
    return episode_sweet_spot_mark(case, points=points, **budget).s_m
