"""Gradients through the impact, judged against the closed form as velocities are.

An engine's dv1/dx, x one of INPUTS (the impact point s, the pitch speed v0, e, the bat's J):
- **finite differences through the harness** (every engine, what users of most engines do):
  v1 fired at x - h, x and x + h, (v1(x+h) - v1(x-h)) / 2h. The step h is the engine's own:
  its velocity tolerance at the impact (``judge.output_tolerance``: rounding in its precision,
  the contact seen late) divided by h, plus the closed form's own truncation error at h, is
  smallest there (``fd_step``); that sum is the row's tolerance.
- **the engine's automatic differentiation** (``BatchedEngine.derivative``): the start
  state's tangent (the placement, differentiated in float64 by a central difference of
  PLACEMENT_STEP of x's scale), through as many steps as the impact's episode took. Its
  tolerance is the judge's for an output (``autodiff_tolerance``), dv1/dx as the output: the
  derivative passes through the same operations as the velocity, in the same precision.

Statuses (``GradStatus``): ``ok`` within the tolerance; ``zero``, the vanishing gradient of
a hard contact (GRAD_ZERO_SHARE); ``exploding`` (GRAD_EXPLODE); ``non_finite``; ``biased``,
any other miss; ``unsupported``, no automatic differentiation, and ``error``, the engine's
derivative raised (the row says why).
"""

from __future__ import annotations

import math
import time
from collections.abc import Sequence
from enum import StrEnum
from types import SimpleNamespace

import numpy as np

import adapters
from adapters import Scene
from analytic.friction_gradients import moved, value_of
from analytic.gradients import derivatives, normal_fields
from analytic.model import ImpactCase

from .endings import Physics
from .fire import Job, fire_jobs
from .hosting import hosted
from .judge import (
    Status,
    law_answer,
    output_tolerance,
    single_impulse_tolerance,
    soft_judgement,
)
from .placement import start_state
from .terms import CURVATURE_STEP_M, GRAD_EXPLODE, GRAD_ZERO_SHARE, PLACEMENT_STEP

#: The inputs differentiated (finite differences), and those the engines' own
#: ``derivative`` reaches (through the start state, and J).
INPUTS = ("s_m", "v0_mps", "e", "bat_inertia_kgm2")
AUTODIFF_INPUTS = ("s_m", "v0_mps", "bat_inertia_kgm2")


class GradStatus(StrEnum):
    """A derivative's verdict: the impact's own words (``Status``) where they mean the same,
    and the three a derivative alone can earn (biased, zero, exploding)."""

    OK = Status.OK.value
    BIASED = "biased"
    ZERO = "zero"
    EXPLODING = "exploding"
    NON_FINITE = Status.NON_FINITE.value
    UNSUPPORTED = Status.UNSUPPORTED.value
    UNJUDGED = Status.UNJUDGED.value  # no answer applies (a soft law's bound does not hold)
    ERROR = Status.ERROR.value  # the engine's derivative raised


def scale_of(case: ImpactCase, name: str) -> float:
    """The size a step in ``name`` is measured against (m, m/s, 1, kg m^2)."""
    return {"s_m": case.bat.length_m, "e": 1.0}.get(name, abs(value_of(case, name)))


def rigid_v1(case: ImpactCase) -> float:
    """The single impulse's v1 (``analytic.gradients.normal_fields``)."""
    b = case.bat
    return float(
        normal_fields(
            case.ball.mass_kg,
            b.mass_kg,
            b.inertia_cm_kgm2,
            case.s_m,
            case.v0n_mps,
            case.u0n_mps,
            case.omega0_radps,
            case.e,
        )["v1_mps"]
    )


def analytic(case: ImpactCase, name: str) -> float:
    """The closed form dv1/d``name`` (``analytic.gradients.derivatives``)."""
    return float(
        derivatives(
            case.bat,
            case.ball,
            s_m=case.s_m,
            v0_mps=case.v0_mps,
            u0_mps=case.u0_mps,
            omega0_radps=case.omega0_radps,
            e=case.e,
            theta_rad=case.theta_rad,
            phi_rad=case.phi_rad,
        )["v1_mps"][name]
    )


def _room(case: ImpactCase, name: str) -> float:
    """How far ``name`` may move either way and stay an impact the harness fires."""
    x = value_of(case, name)
    if name == "s_m":
        return min(x - case.bat.s_min_m, case.bat.s_max_m - x)
    if name == "e":
        return min(x, 1.0 - x) if 0.0 < x < 1.0 else 0.0
    return 0.5 * abs(x)


def contact_law(name: str, settings: adapters.Settings, case: ImpactCase):
    """The continuous law an engine's soft contact converges to at this case's e (its
    velocities are judged against it, and so its gradients), or None: the rigid impulse."""
    return adapters.record(name).errors.contact_law(settings, case.e)


def law_v1(name: str, settings: adapters.Settings, case: ImpactCase) -> float:
    return float(law_answer(case, contact_law(name, settings, case)).v1_mps)


def fd_step(
    case: ImpactCase, settings: adapters.Settings, name: str, wrt: str
) -> tuple[float, float]:
    """(h, tolerance): the central-difference step for dv1/d``wrt`` from engine ``name``'s
    error model (module docstring), and the slope error it allows ((m/s) per unit of x). A
    soft contact's velocity tolerance is its law's (``judge.soft_judgement``); the closed
    form's truncation stands for its law's (the same shape of v1 against each input)."""
    if contact_law(name, settings, case) is None:
        tol_v = output_tolerance(case, settings, adapters.record(name).errors, "v1_mps")
    else:
        tol_v = soft_judgement(case, SimpleNamespace(engine=name, settings=settings))[1]
    x, d = value_of(case, wrt), analytic(case, wrt)
    hs = scale_of(case, wrt) * np.logspace(-7, -1, 49)
    hs = hs[hs <= _room(case, wrt)]
    if not len(hs) or not math.isfinite(tol_v):
        return (float(hs[-1]) if len(hs) else math.nan), math.nan
    trunc = np.array(
        [
            abs(
                (rigid_v1(moved(case, wrt, x + h)) - rigid_v1(moved(case, wrt, x - h))) / (2 * h)
                - d
            )
            for h in hs
        ]
    )
    total = tol_v / hs + trunc
    k = int(np.argmin(total))
    return float(hs[k]), float(total[k])


def autodiff_tolerance(
    case: ImpactCase, settings: adapters.Settings, errors: adapters.ErrorModel, name: str
) -> float:
    """The judge's tolerance of an output (``judge.single_impulse_tolerance``) with dv1/d``name``
    as that output: its rounding on the largest |dv1/d``name``| along the bat, and the contact
    seen late moving it by its own slope and curvature in s."""
    bat, s, k = case.bat, case.s_m, CURVATURE_STEP_M

    def g(x: float) -> float:
        return analytic(moved(case, "s_m", min(max(x, bat.s_min_m), bat.s_max_m)), name)

    slope = abs(g(s + k) - g(s - k)) / (2 * k)
    curvature = abs(g(s + k) - 2 * g(s) + g(s - k)) / k**2
    return single_impulse_tolerance(
        case, settings, errors, slope, curvature, _terms_scale(case, name)
    )


def _terms_scale(case: ImpactCase, name: str) -> float:
    """The size of dv1/d``name``'s two terms, the impulse's (dP/dx / m) and the pitch's own
    (-d v0n/dx), added as magnitudes and maxed along the bat: rounding and a biased impulse
    scale with them, not with their sum (dv1/dv0 = -1 + 1.2 = 0.2 on the sweet spot)."""
    s = np.linspace(case.bat.s_min_m, case.bat.s_max_m, 41)
    d = derivatives(
        case.bat,
        case.ball,
        s_m=s,
        v0_mps=case.v0_mps,
        u0_mps=case.u0_mps,
        omega0_radps=case.omega0_radps,
        e=case.e,
        theta_rad=case.theta_rad,
        phi_rad=case.phi_rad,
    )
    impulse = d["impulse_ns"][name] / case.ball.mass_kg
    return float(np.max(np.abs(impulse) + np.abs(d["v1_mps"][name] - impulse)))


def judge_gradient(value: float, truth: float, tol: float) -> GradStatus:
    """A gradient's status against the closed form (module docstring)."""
    if not math.isfinite(value):
        return GradStatus.NON_FINITE
    if abs(value - truth) <= tol:
        return GradStatus.OK
    if abs(value) <= GRAD_ZERO_SHARE * abs(truth):
        return GradStatus.ZERO
    if abs(value) > GRAD_EXPLODE * (abs(truth) + tol):
        return GradStatus.EXPLODING
    return GradStatus.BIASED


def _row(
    name,
    settings,
    method,
    case,
    wrt,
    value,
    truth,
    tol,
    h,
    v1_physics,
    why,
    cost_s,
    failed: GradStatus | None = None,
) -> dict:
    law = contact_law(name, settings, case)
    if failed is not None:  # no gradient to judge: why the engine gave none
        status, tol = failed, math.nan
    elif not math.isfinite(tol):
        status = GradStatus.UNJUDGED
    else:
        status = judge_gradient(value, truth, tol)
    return {
        "engine": name,
        "precision": adapters.record(name).errors.precision,
        "method": method,
        "input": wrt,
        "s_m": case.s_m,
        "v0_mps": case.v0_mps,
        "e": case.e,
        "dt_s": settings.dt_s,
        "value": value,
        "analytic": truth,
        "reference": "rigid impulse" if law is None else type(law).__name__,
        "abs_err": abs(value - truth),
        "tolerance": tol,
        "step": h,
        "v1_physics": v1_physics,
        "status": status.value,
        "why": why,
        "cost_s": cost_s,
    }


def finite_differences(
    name: str, settings: adapters.Settings, cases: Sequence[ImpactCase], wrt: str
) -> list[dict]:
    """One row per case: dv1/d``wrt`` by central differences through the harness, against the
    closed form (a soft contact: its law's v1 differenced over the same step), and the episode
    steps the middle impact took (for the autodiff rows), in ``row['steps']``."""
    steps = [fd_step(c, settings, name, wrt) for c in cases]
    jobs = []
    for c, (h, _) in zip(cases, steps):
        x = value_of(c, wrt)
        jobs += [
            Job(engine=name, settings=settings, case=moved(c, wrt, x + k * h)) for k in (-1, 0, 1)
        ]
    t0 = time.perf_counter()
    fired = fire_jobs(jobs)
    cost = (time.perf_counter() - t0) / len(cases)
    rows = []
    for i, (c, (h, tol)) in enumerate(zip(cases, steps)):
        lo, mid, hi = (fired[3 * i + k] for k in range(3))
        value = (hi.outcome.v1_mps - lo.outcome.v1_mps) / (2 * h)
        truth = (
            analytic(c, wrt)
            if contact_law(name, settings, c) is None
            else (law_v1(name, settings, hi.case) - law_v1(name, settings, lo.case)) / (2 * h)
        )
        outcomes = {f.outcome.physics for f in (lo, mid, hi)}
        why = "" if outcomes == {Physics.SOUND} else "impacts: " + ", ".join(sorted(outcomes))
        row = _row(
            name,
            settings,
            "finite_difference",
            c,
            wrt,
            value,
            truth,
            tol,
            h,
            mid.outcome.physics.value,
            why,
            cost,
        )
        rows.append(row | {"steps": int(max(f.outcome.steps for f in (lo, mid, hi)))})
    return rows


def tangents(cases: Sequence[ImpactCase], settings: adapters.Settings, wrt: str) -> np.ndarray:
    """d(start state)/d``wrt`` of each case (the harness's placement, float64 differences)."""
    out = []
    for c in cases:
        if wrt == "bat_inertia_kgm2":  # the placement does not read J
            out.append(np.zeros(20))
            continue
        x, d = value_of(c, wrt), PLACEMENT_STEP * scale_of(c, wrt)
        hi, lo = (np.array(start_state(moved(c, wrt, x + k * d), settings)[0]) for k in (1, -1))
        out.append((hi - lo) / (2 * d))
    return np.array(out)


def autodiff(
    name: str, settings: adapters.Settings, cases: Sequence[ImpactCase], wrt: str, steps: int
) -> tuple[np.ndarray, np.ndarray, GradStatus | None, str]:
    """(v1, dv1/d``wrt``, failed, why) by the engine's own ``derivative`` over ``steps``
    steps, for cases that share bat, ball and e; where it has none (``failed`` UNSUPPORTED)
    or it raised (ERROR), NaN and the reason."""
    host = hosted(name, settings)
    nan = np.full(len(cases), math.nan)
    if not host.batched:
        return (
            nan,
            nan,
            GradStatus.UNSUPPORTED,
            f"{name} is a single-world engine with no automatic differentiation",
        )
    c = cases[0]
    scene = Scene(bat=c.bat, ball=c.ball, e=c.e)
    # the scene built (its world count kept: the derivative takes its own), not rebuilt
    host.batch(scene, host.worlds if host.scene == scene else len(cases))
    starts = np.array([start_state(k, settings)[0] for k in cases], dtype=float)
    try:
        ends, d_ends = host.adapter.derivative(
            starts, tangents(cases, settings, wrt), steps, float(wrt == "bat_inertia_kgm2")
        )
    except NotImplementedError as why:
        return nan, nan, GradStatus.UNSUPPORTED, str(why)
    except Exception as err:  # the engine failed: a row that says so, not a crash
        return nan, nan, GradStatus.ERROR, repr(err)[:200]
    return ends[:, 3], d_ends[:, 3], None, ""


def gradient_rows(
    name: str, settings: adapters.Settings, cases: Sequence[ImpactCase], wrt: str
) -> list[dict]:
    """Finite-difference rows, then autodiff rows, for cases sharing bat, ball and e."""
    fd = finite_differences(name, settings, cases, wrt)
    if wrt not in AUTODIFF_INPUTS:
        return fd
    t0 = time.perf_counter()
    _, values, failed, why = autodiff(name, settings, cases, wrt, max(r["steps"] for r in fd))
    cost = (time.perf_counter() - t0) / len(cases)
    errors = adapters.record(name).errors
    ad = [
        _row(
            name,
            settings,
            "autodiff",
            c,
            wrt,
            float(v),
            analytic(c, wrt),
            autodiff_tolerance(c, settings, errors, wrt),
            math.nan,
            r["v1_physics"],
            why,
            cost,
            failed,
        )
        for c, v, r in zip(cases, values, fd)
    ]
    return fd + (ad[:1] if why else ad)  # an engine without: one row says why
