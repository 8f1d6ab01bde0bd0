"""The gradient study's three questions beyond the table (a part of ``experiments.gradients``):
where an engine's own gradient puts the sweet spot, how a soft contact's smoothing biases its
gradient (against stiffness and step), and a bat's J recovered by gradient descent through
a differentiable engine against the closed-form least-squares fit.
"""

from __future__ import annotations

import math
import time

import numpy as np
from scipy import optimize

import adapters
from analytic import impact
from analytic.model import ImpactCase

from ..core.gradients import (
    GradStatus,
    analytic,
    autodiff,
    autodiff_tolerance,
    contact_law,
    fd_step,
    finite_differences,
    law_v1,
    moved,
    rigid_v1,
)

#: The sweet spot is sought within this distance of the closed form's (m).
SEARCH_M = 0.06
#: The soft contact's stiffness (natural frequency, rad/s) and its resolution omega dt.
STIFFNESSES_RADPS = (1e3, 3e3, 1e4, 3e4, 1e5)
RESOLUTIONS = (0.1, 0.03, 0.01)
#: The J fit: impact points (m from the COM), the measurement noise (m/s: an assumption, a
#: radar gun's quoted +-0.1 mph is 0.045 m/s; twice that here), its seed, the first guess
#: (a share of the true J) and the descent's stop (a share of the fit's standard error).
FIT_POINTS_M = tuple(np.linspace(-0.10, 0.22, 20))
FIT_NOISE_MPS = 0.1
FIT_SEED = 0
FIT_START = 0.8
FIT_STOP = 1e-3
FIT_MAX_ITERATIONS = 30


def sweet_spot(
    name: str, settings: adapters.Settings, base: ImpactCase, method: str, steps: int
) -> dict:
    """The root of the engine's dv1/ds (by ``method``) near the closed form's sweet spot,
    with the distance its gradient tolerance allows: tol(dv1/ds) / |d2v1/ds2|."""
    bat = base.bat
    want = float(impact.sweet_spot(bat, base.ball, base.v0_mps, base.u0_mps, base.omega0_radps))
    law = contact_law(name, settings, base)
    if law is not None:  # its law's own sweet spot
        want = _law_sweet_spot(name, settings, base, want)
    calls = [0]

    def slope(s: float) -> float:
        calls[0] += 1
        c = moved(base, "s_m", s)
        if method == "autodiff":
            return float(autodiff(name, settings, [c], "s_m", steps)[1][0])
        return float(finite_differences(name, settings, [c], "s_m")[0]["value"])

    at, errors = moved(base, "s_m", want), adapters.record(name).errors
    tol = (
        autodiff_tolerance(at, settings, errors, "s_m")
        if method == "autodiff"
        else fd_step(at, settings, name, "s_m")[1]
    )
    k = 1e-4
    curvature = abs(
        analytic(moved(at, "s_m", want + k), "s_m") - analytic(moved(at, "s_m", want - k), "s_m")
    ) / (2 * k)
    row = {
        "engine": name,
        "method": method,
        "reference_m": want,
        "reference": "rigid impulse" if law is None else type(law).__name__,
        "tolerance_m": tol / curvature,
        "found_m": math.nan,
        "evaluations": 0,
        "status": GradStatus.UNSUPPORTED.value,
        "why": "",
    }
    lo, hi = max(want - SEARCH_M, bat.s_min_m + 1e-3), min(want + SEARCH_M, bat.s_max_m - 1e-3)
    t0 = time.perf_counter()
    g_lo, g_hi = slope(lo), slope(hi)
    if not (math.isfinite(g_lo) and math.isfinite(g_hi)):
        row["why"] = "no autodiff" if method == "autodiff" else "non-finite gradient"
        return row
    if g_lo * g_hi > 0:
        return row | {
            "status": GradStatus.BIASED.value,
            "why": f"dv1/ds keeps its sign over [{lo:.3f}, {hi:.3f}] m",
        }
    try:
        found = optimize.brentq(slope, lo, hi, xtol=1e-7)
    except (ValueError, RuntimeError) as err:  # a NaN met on the way, or no convergence
        return row | {"status": GradStatus.NON_FINITE.value, "why": f"root search: {err}"}
    ok = abs(found - want) <= row["tolerance_m"]
    return row | {
        "found_m": found,
        "evaluations": calls[0],
        "cost_s": time.perf_counter() - t0,
        "status": (GradStatus.OK if ok else GradStatus.BIASED).value,
    }


def _law_sweet_spot(
    name: str, settings: adapters.Settings, base: ImpactCase, near_m: float
) -> float:
    """The root of a soft contact law's dv1/ds (central differences of its v1 over the
    engine's step) near the rigid sweet spot."""

    def slope(s: float) -> float:
        c = moved(base, "s_m", s)
        h = fd_step(c, settings, name, "s_m")[0]
        return (
            law_v1(name, settings, moved(c, "s_m", s + h))
            - law_v1(name, settings, moved(c, "s_m", s - h))
        ) / (2 * h)

    return float(optimize.brentq(slope, near_m - SEARCH_M / 2, near_m + SEARCH_M / 2, xtol=1e-7))


def soft_bias(name: str, base: ImpactCase, steps_for, quick: bool = False) -> list[dict]:
    """The engine's own dv1/ds through its soft contact at each stiffness and resolution,
    against the rigid closed form: the smoothing's bias, and where it converges.
    ``steps_for(settings)``: the episode's steps at those settings."""
    rec = adapters.record(name)
    rows = []
    for w in STIFFNESSES_RADPS[2:3] if quick else STIFFNESSES_RADPS:
        for k in RESOLUTIONS[1:2] if quick else RESOLUTIONS:
            st = adapters.settings_for(
                name, **dict(rec.can.soft_contact), **{rec.can.stiffness_setting: w, "dt_s": k / w}
            )
            v1, g, _, why = autodiff(name, st, [base], "s_m", steps_for(st))
            truth = analytic(base, "s_m")
            rows.append(
                {
                    "engine": name,
                    "stiffness_radps": w,
                    "omega_dt": k,
                    "dt_s": k / w,
                    "v1_mps": float(v1[0]),
                    "v1_rigid_mps": rigid_v1(base),
                    "value": float(g[0]),
                    "analytic": truth,
                    "bias": float(g[0]) - truth,
                    "why": why,
                }
            )
    return rows


def fit_data(base: ImpactCase) -> tuple[np.ndarray, np.ndarray]:
    """(s, v1 measured): the closed form's v1 at FIT_POINTS_M plus seeded Gaussian noise."""
    s = np.array(FIT_POINTS_M)
    truth = np.array([rigid_v1(moved(base, "s_m", x)) for x in s])
    return s, truth + np.random.default_rng(FIT_SEED).normal(0.0, FIT_NOISE_MPS, len(s))


def least_squares_j(base: ImpactCase, s: np.ndarray, v1: np.ndarray) -> dict:
    """J fitted to the measurements through the closed form (scipy's least_squares), its
    standard error sigma / sqrt(sum (dv1/dJ)^2)."""
    t0 = time.perf_counter()

    def residual(j):
        return [
            rigid_v1(moved(moved(base, "s_m", x), "bat_inertia_kgm2", j[0])) - y
            for x, y in zip(s, v1)
        ]

    fit = optimize.least_squares(residual, [FIT_START * base.bat.inertia_cm_kgm2])
    j = float(fit.x[0])
    slopes = [
        analytic(moved(moved(base, "s_m", x), "bat_inertia_kgm2", j), "bat_inertia_kgm2") for x in s
    ]
    return {
        "j_kgm2": j,
        "sigma_kgm2": FIT_NOISE_MPS / math.sqrt(np.sum(np.square(slopes))),
        "evaluations": int(fit.nfev),
        "cost_s": time.perf_counter() - t0,
    }


def descend_j(
    name: str,
    settings: adapters.Settings,
    base: ImpactCase,
    s: np.ndarray,
    v1: np.ndarray,
    sigma_kgm2: float,
    steps: int,
) -> dict:
    """J by gradient descent through the engine's own derivative: each iteration builds the
    bat with the current J, takes v1 and dv1/dJ at every point in one call, and steps by
    -sum(r g) / sum(g^2) (the Gauss-Newton step length) until the step is below FIT_STOP of
    the fit's standard error, or the loss no longer falls (the engine's rounding: the J
    before that step is kept)."""
    j, path = FIT_START * base.bat.inertia_cm_kgm2, []
    t0 = time.perf_counter()
    for _ in range(FIT_MAX_ITERATIONS):
        cases = [moved(moved(base, "s_m", x), "bat_inertia_kgm2", j) for x in s]
        got, g, _, why = autodiff(name, settings, cases, "bat_inertia_kgm2", steps)
        if why:
            return {"engine": name, "why": why}
        r = got - v1
        loss = float(np.mean(r * r))
        if path and loss >= path[-1]["loss_m2ps2"]:  # the engine's rounding: no lower loss
            j = path[-1]["j_kgm2"]
            break
        step = -float(np.sum(r * g) / np.sum(g * g))
        path.append({"j_kgm2": j, "loss_m2ps2": loss})
        j += step
        if abs(step) < FIT_STOP * sigma_kgm2:
            break
    return {
        "engine": name,
        "j_kgm2": j,
        "iterations": len(path),
        "cost_s": time.perf_counter() - t0,
        "path": path,
        "why": "",
    }
