"""What the judge allows on an impact with friction or out of the swing plane, and the columns
such an impact adds to a table.

Two rigid answers apply. Theory is Routh's: one impulse integrated through slip and stick
(``analytic.friction``, energetic restitution); it is the ``*_analytic_*`` columns. A rigid
engine resolves the impact in one step, and as its step shrinks it converges to another law:
Newton's restitution and Coulomb's cone on the total impulse (``one_step_impulse``), or for a
convex solver (MuJoCo's) that law's relaxation, where a slide leaves faster by mu times its
final slip (``ErrorModel.friction_law`` says which; the ``*_law_*`` columns). A law differs
from theory by its own gap (where the collision matrix couples the normal and the tangent and
the slip stops within the impact: 1e-5 to 1e-3 relative on the paper's swing; the relaxation
adds mu |v_t'| to a slide's v1), which no setting removes; so, as a soft contact is judged
against its own contact law, a rigid engine's frictional impact is judged against its law, and
its error against theory is beside it. Both count only where free flight then parts
the bodies for good (``analytic.frictional``); elsewhere, and for a soft contact (no frictional
law here), the row is unjudged. Each output X (v1; the ball's velocity along the bat, vt1, and
out of the swing plane, vz1; its spin about z, spin1, and about x, backspin1) is allowed what
the single impulse's v1 is allowed (``judge``):

    allowed_X = precision_rel scale_X + mapping slip0 [/ r] + GEOM_SAFETY (|dX/ds| slide
                + |d2X/ds2| slide^2 / 2 + leak_X)  (+ a lingering contact's share, velocities)

- scale_X: the impact's speed scale for velocities, that over r_ball for spins; mapping: the
  share of the slip slip0 (the contact points' tangential speed before the impact) the
  engine's friction mapping leaves (``ErrorModel.friction_mapping_error_rel``; times 5/2 for
  spins, I = 2 m r^2 / 5);
- slide: how far the contact foot moves along the axis while the contact is seen late, as for
  v1; |dX/ds| the larger one-sided difference over CURVATURE_STEP_M (a slip that stops makes
  X(s) kinked, not smooth);
- leak_X: the normal seen turned by tilt = |omega0| delta / v_n (the bat's turn while the
  contact is seen late) + delta / R for an undercut (the foot's angle in the plane across the
  axis) turns a share tilt of the impulse P into the tangent plane and back, and Coulomb's
  bound with it: (1 + mu) P tilt / m on a velocity, (5/2)(1 + mu) P tilt / (m r) on a spin.
"""

from __future__ import annotations

import functools
import math
from dataclasses import replace

import numpy as np

import adapters
from analytic import ImpactCase
from analytic.frictional import FrictionEpisode, frictional_episode

from . import judge, terms

#: Column stem -> (index into the analytic ball velocity or spin, the engine outcome's field,
#: 'velocity' or 'spin').
OUTPUTS = {
    "vt1": (0, "v1_t_mps", "velocity"),
    "vz1": (2, "v1_z_mps", "velocity"),
    "spin1": (2, "spin1_radps", "spin"),
    "backspin1": (0, "backspin1_radps", "spin"),
}
UNITS = {"velocity": "mps", "spin": "radps"}
#: The case's own columns in a table with friction (what it was fired with).
CASE_COLUMNS = ("mu", "undercut_m", "spin0_x_radps", "spin0_y_radps", "spin0_z_radps")


def tangential_tolerance(
    case: ImpactCase,
    settings: adapters.Settings,
    errors: adapters.ErrorModel,
    impulse_ns: float,
    mass_kg: float,
) -> float:
    """Allowed error of a tangential velocity after a frictionless impact: rounding, and the
    normal tilted by the bat's turn omega0 delta / v_c when the contact is seen (and by a
    collision routine's own bias, its slide over r1 + r2), which leaks the impulse P/mass
    times that tilt into it."""
    tilt = abs(
        case.omega0_radps
    ) * settings.overlap_m / case.closing_speed_mps + errors.collision_slide_m(
        settings, case.bat
    ) / (case.bat.radius_m + case.ball.radius_m)
    return (
        judge.precision_rel(settings, errors, case) * case.v0_mps
        + terms.GEOM_SAFETY * abs(impulse_ns) / mass_kg * tilt
    )


def _analytic(ep, stem: str, case: ImpactCase) -> float:
    """The rigid answer's value of an OUTPUTS stem: the frictional impulse's, or a frictionless
    planar episode's (the ball leaves in the plane, its spin as it came)."""
    index, _, kind = OUTPUTS[stem]
    if not hasattr(ep, "friction"):
        return (
            (ep.v1_t_mps, ep.v1_mps, 0.0)[index] if kind == "velocity" else case.spin_radps[index]
        )
    vector = ep.ball_velocity_mps if kind == "velocity" else ep.ball_spin_radps
    return float(vector[index])


def _late(
    case: ImpactCase, st: adapters.Settings, errors: adapters.ErrorModel
) -> tuple[float, float]:
    """(slide along the axis, m; tilt of the normal, rad) of a contact seen late."""
    v_n = case.closing_speed_mps * math.cos(case.tilt_rad)
    reach = case.bat.radius_m + case.ball.radius_m
    early = min(errors.speculative_margin_m(st), v_n * st.dt_s)
    bias = errors.collision_slide_m(st, case.bat)
    delta = st.overlap_m + max(st.contact_phase * v_n * st.dt_s, early)
    slide = (reach * abs(case.omega0_radps) + judge._tangential(case)) * delta / v_n + bias
    tilt = (
        abs(case.omega0_radps) * delta / v_n
        + bias / reach
        + (delta / reach if case.undercut_m else 0.0)
    )
    return slide, tilt


@functools.lru_cache(maxsize=1 << 16)
def law(case: ImpactCase, max_episode_s: float, which: str) -> FrictionEpisode:
    """The episode of the one-step law ``which`` (``ErrorModel.friction_law``) for ``case``
    (module docstring). Cached as ``judge.rigid``."""
    return frictional_episode(case, max_episode_s=max_episode_s, law=which)


def _neighbours(case: ImpactCase, st: adapters.Settings, which: str) -> tuple[list, float]:
    """The law's episodes at s - h, s, s + h (h = CURVATURE_STEP_M, kept on the cylinder)."""
    bat, h = case.bat, terms.CURVATURE_STEP_M
    lo, hi = max(case.s_m - h, bat.s_min_m), min(case.s_m + h, bat.s_max_m)
    eps = [law(replace(case, s_m=s), st.max_contact_s, which) for s in (lo, case.s_m, hi)]
    return eps, min(case.s_m - lo, hi - case.s_m) or h


def tolerances(
    case: ImpactCase, settings: adapters.Settings, errors: adapters.ErrorModel
) -> dict[str, float]:
    """Allowed |engine - one-step law| of v1 and of every OUTPUTS stem (module docstring); NaN
    for each where no frictional answer applies."""
    nan = dict.fromkeys(("v1", *OUTPUTS), math.nan)
    if errors.contact_reference(settings) is not adapters.ContactReference.RIGID_IMPULSE:
        return nan
    episodes, h = _neighbours(case, settings, errors.friction_law(settings))
    if (
        any(ep.ended == "meets_again" for ep in episodes)
        or judge.rigid(case, settings.max_contact_s).ended == "meets_again"
    ):
        return nan
    ball = case.ball
    slide, tilt = _late(case, settings, errors)
    impulse = float(np.linalg.norm(episodes[1].friction.impulse_ns))
    leak = (1.0 + case.mu) * impulse * tilt / ball.mass_kg
    rounding = judge.precision_rel(settings, errors, case) * judge._speed(case)
    mapping = errors.friction_mapping_error_rel(settings) * episodes[1].friction.slip0_mps
    lingering = judge._lingering(case, settings.dt_s, judge._tangential(case))
    out = {}
    for stem in ("v1", *OUTPUTS):
        spin = stem != "v1" and OUTPUTS[stem][2] == "spin"
        x = [ep.v1_mps if stem == "v1" else _analytic(ep, stem, case) for ep in episodes]
        slope = max(abs(x[2] - x[1]), abs(x[1] - x[0])) / h
        curvature = abs(x[2] - 2.0 * x[1] + x[0]) / h**2
        geometric = slope * slide + 0.5 * curvature * slide**2
        if spin:
            out[stem] = (rounding + 2.5 * mapping) / ball.radius_m + terms.GEOM_SAFETY * (
                geometric + 2.5 * leak / ball.radius_m
            )
        else:
            out[stem] = rounding + mapping + terms.GEOM_SAFETY * (geometric + leak) + lingering
    return out


def columns(cases, outcomes, errors, episodes) -> tuple[dict, np.ndarray, np.ndarray]:
    """The columns an impact with friction or out of the plane adds: the case's own, then per
    OUTPUTS stem Routh's value (analytic), the one-step law's (law), the engine's, |engine -
    analytic|, |engine - law| and the tolerance on the latter; the impulse's phases under
    Routh and the engine's friction cone. Also v1's law and tolerance (columns of 2), and
    whether every added output is within its tolerance (True where none is judged).
    ``errors``: each outcome's error model."""
    n = len(cases)
    cols: dict[str, list] = {k: [] for k in CASE_COLUMNS}
    for c in cases:
        cols["mu"].append(c.mu)
        cols["undercut_m"].append(c.undercut_m)
        for axis, w in zip("xyz", c.spin_radps):
            cols[f"spin0_{axis}_radps"].append(w)
    plain = [c.frictionless_planar for c in cases]
    laws = [
        ep if p else law(c, o.settings.max_contact_s, err.friction_law(o.settings))
        for c, o, err, ep, p in zip(cases, outcomes, errors, episodes, plain)
    ]
    tols = [
        dict.fromkeys(("v1", *OUTPUTS), math.nan) if p else tolerances(c, o.settings, err)
        for c, o, err, p in zip(cases, outcomes, errors, plain)
    ]
    within = np.ones(n, dtype=bool)
    for stem, (_, field, kind) in OUTPUTS.items():
        unit = UNITS[kind]
        want = np.array([_analytic(ep, stem, c) for ep, c in zip(episodes, cases)])
        at_law = np.array([_analytic(ep, stem, c) for ep, c in zip(laws, cases)])
        got = np.array([getattr(o, field) for o in outcomes])
        tol = np.array([t[stem] for t in tols])
        within &= ~(np.abs(got - at_law) > tol)
        cols[f"{stem}_analytic_{unit}"], cols[f"{stem}_law_{unit}"] = want, at_law
        cols[f"{stem}_engine_{unit}"] = got
        cols[f"{stem}_abs_err_{unit}"] = np.abs(got - want)
        cols[f"{stem}_law_err_{unit}"], cols[f"{stem}_tol_{unit}"] = np.abs(got - at_law), tol
    cols["friction_phases"] = [
        ",".join(p for p, _ in ep.friction.phases) if hasattr(ep, "friction") else ""
        for ep in episodes
    ]
    cols["slip0_mps"] = [
        ep.friction.slip0_mps if hasattr(ep, "friction") else math.nan for ep in episodes
    ]
    cols["friction_cone"] = [err.friction_cone(o.settings) for o, err in zip(outcomes, errors)]
    cols["friction_law"] = [err.friction_law(o.settings) for o, err in zip(outcomes, errors)]
    v1_law = np.column_stack([[ep.v1_mps for ep in laws], [t["v1"] for t in tols]])
    return cols, v1_law, within
