"""Firing an engine over a grid of impact points: rows of a tidy table, serial or in processes.

Shared by the sweep, the benchmarks and the regression test, so every table is made one way.
"""

from __future__ import annotations

import math
from concurrent.futures import ProcessPoolExecutor
from dataclasses import dataclass, replace
from typing import Iterable

import numpy as np
from scipy import optimize
from tqdm import tqdm

import adapters
from adapters.base import swing_case
from analytic import Bat, ImpactCase, center_of_percussion, predict, presets, sweet_spot
from analytic.dynamics import HingedSwing

#: Columns of a sweep table, in order. Units are in the names.
COLUMNS = (
    "engine", "profile", "bat", "s_m", "v0_mps", "u0_mps", "omega0_radps", "e", "theta_rad",
    "v1_analytic_mps", "v1_engine_mps", "v1_abs_err_mps", "v1_rel_err",
    "u1_analytic_mps", "u1_engine_mps", "omega1_analytic_radps", "omega1_engine_radps",
    "hand_dv_analytic_mps", "hand_dv_engine_mps", "ke_before_j", "ke_after_j", "status",
    "contact_duration_s", "peak_penetration_m", "steps", "wall_s",
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

    def case(self, s_m: float) -> ImpactCase:
        """The impact at one grid point (validates every field)."""
        return ImpactCase(bat=self.bat, ball=presets.BASEBALL, s_m=s_m, v0_mps=self.v0_mps,
                          u0_mps=self.u0_mps, omega0_radps=self.omega0_radps, e=self.e,
                          theta_rad=self.theta_rad, hands_from_knob_m=self.hands_from_knob_m)

    def cases(self) -> list[ImpactCase]:
        return [self.case(s) for s in self.s_m]


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


def row(case: ImpactCase, out: adapters.SimOutcome, profile: str) -> dict:
    """One table row: analytic vs engine for one impact."""
    ref = predict(case)
    err = out.v1_mps - ref.v1_mps
    return {
        "engine": out.engine, "profile": profile, "bat": case.bat.name, "s_m": case.s_m,
        "v0_mps": case.v0_mps, "u0_mps": case.u0_mps, "omega0_radps": case.omega0_radps,
        "e": case.e, "theta_rad": case.theta_rad,
        "v1_analytic_mps": ref.v1_mps, "v1_engine_mps": out.v1_mps, "v1_abs_err_mps": abs(err),
        "v1_rel_err": abs(err) / abs(ref.v1_mps) if ref.v1_mps != 0 else math.inf,
        "u1_analytic_mps": ref.u1_mps, "u1_engine_mps": out.u1_mps,
        "omega1_analytic_radps": ref.omega1_radps, "omega1_engine_radps": out.omega1_radps,
        "hand_dv_analytic_mps": ref.hand_dv_mps, "hand_dv_engine_mps": out.hand_dv_mps,
        "ke_before_j": out.ke_before_j, "ke_after_j": out.ke_after_j,
        "status": out.status.value, "contact_duration_s": out.contact_duration_s,
        "peak_penetration_m": out.peak_penetration_m, "steps": out.steps, "wall_s": out.wall_s,
    }


def fire_one(engine: adapters.Engine, case: ImpactCase, profile: str,
             swing: HingedSwing | None = None) -> dict:
    """One row; with a swing, the case is re-planned for the engine's step and swung into."""
    if swing is None:
        return row(case, engine.simulate(case), profile)
    case, plan = swing_case(case.bat, case.ball, s_m=case.s_m, v0_mps=case.v0_mps, e=case.e,
                            swing=swing, settings=engine.settings)
    out = engine.simulate(case, swing=plan)
    return {**row(case, out, profile), "release_omega_engine_radps": out.release_omega_radps,
            "release_omega_analytic_radps": plan.omega_release_radps,
            "release_angle_err_rad": out.release_angle_rad - plan.angle_release_rad}


_WORKER_ENGINE: adapters.Engine | None = None


def _init_worker(name: str, settings: adapters.Settings) -> None:
    global _WORKER_ENGINE
    _WORKER_ENGINE = adapters.engine_class(name)(settings)


def _fire_chunk(args: tuple[list[ImpactCase], str, HingedSwing | None]) -> list[dict]:
    cases, profile, swing = args
    return [fire_one(_WORKER_ENGINE, c, profile, swing) for c in cases]


def fire(name: str, settings: adapters.Settings, profile: str, cases: list[ImpactCase], *,
         workers: int = 1, progress: tqdm | None = None,
         swing: HingedSwing | None = None) -> list[dict]:
    """Rows for every case on one engine, in the order given; ``workers`` > 1 uses processes."""
    if workers <= 1:
        engine = adapters.engine_class(name)(settings)
        rows = []
        try:
            for c in cases:
                rows.append(fire_one(engine, c, profile, swing))
                if progress is not None:
                    progress.update(1)
        finally:
            engine.close()
        return rows
    chunks = [list(chunk) for chunk in np.array_split(np.array(cases, dtype=object), workers * 4)
              if len(chunk)]
    rows = []
    with ProcessPoolExecutor(workers, initializer=_init_worker,
                             initargs=(name, settings)) as pool:
        for part in pool.map(_fire_chunk, [(c, profile, swing) for c in chunks]):
            rows.extend(part)
            if progress is not None:
                progress.update(len(part))
    return rows


def locate_sweet_spot(engine: adapters.Engine, firing: Firing, bracket: tuple[float, float],
                      xatol_m: float = 1e-7) -> float:
    """argmax of the engine's v1(s) inside ``bracket`` (bounded Brent search on simulations).

    Returns NaN if any simulation in the search fails.
    """
    def minus_v1(s: float) -> float:
        r = fire_one(engine, firing.case(float(s)), "", firing.swing)
        return -r["v1_engine_mps"] if r["status"] == "ok" else math.nan

    res = optimize.minimize_scalar(minus_v1, bounds=bracket, method="bounded",
                                   options={"xatol": xatol_m})
    return float(res.x) if math.isfinite(res.fun) else math.nan


def locate_cop(engine: adapters.Engine, firing: Firing, bracket: tuple[float, float],
               xtol_m: float = 1e-9) -> float:
    """The s where the engine's hand-point velocity change crosses zero (Brent's root finder).

    Returns NaN if the bracket holds no sign change or a simulation fails.
    """
    def hand(s: float) -> float:
        r = fire_one(engine, firing.case(float(s)), "", firing.swing)
        return r["hand_dv_engine_mps"] if r["status"] == "ok" else math.nan

    a, b = hand(bracket[0]), hand(bracket[1])
    if not (math.isfinite(a) and math.isfinite(b)) or a * b > 0:
        return math.nan
    try:
        return float(optimize.brentq(hand, *bracket, xtol=xtol_m))
    except (ValueError, RuntimeError):
        return math.nan


def analytic_marks(firing: Firing) -> dict[str, float]:
    """The analytic sweet spot and COP (s in m from the COM) for a firing."""
    bat = firing.bat
    return {
        "sweet_spot_m": sweet_spot(bat, presets.BASEBALL, firing.v0_mps, firing.u0_mps,
                                   firing.omega0_radps, theta_rad=firing.theta_rad),
        "cop_m": center_of_percussion(bat, firing.hands_from_knob_m),
    }


def bracket_around(s: Iterable[float], values: Iterable[float], kind: str) -> tuple[float, float] | None:
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


def with_dt(settings: adapters.Settings, dt_s: float | None) -> adapters.Settings:
    """Settings with the time step overridden when one is given."""
    return settings if dt_s is None else replace(settings, dt_s=dt_s)
