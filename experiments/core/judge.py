"""The tolerance each fired impact is judged against, derived as the conformance suite derives
it: what the engine's float precision, the depth at which it first sees the contact, and (after
a swing in the engine) its integrator's angle error can move v1 by.

    allowed = (ROUND_OPS + SOLVE_SAFETY cond) eps speed + GEOM_SAFETY |dv1/ds| slide  (+ ...)

- eps: the engine's unit roundoff (its record's precision); cond: its contact solve's
  condition number (``ErrorModel.solve_conditioning``); speed = v0 + |u0| + |omega0| L.
- The contact is first seen delta = overlap_m + contact_phase v_c dt deep, delta / v_c after the
  geometric instant; meanwhile the turning bat (and any tangential motion) slides the contact
  foot along the axis by (R |omega0| + |v_t - u_t|) delta / v_c, R = r_bat + r_ball, and v1
  takes the analytic value of a point that far away: |dv1/ds| slide + |d2v1/ds2| slide^2 / 2
  (the second term matters at the sweet spot, where dv1/ds = 0); the normal has turned by
  omega0 delta / v_c meanwhile, so the impulse takes in (1 + e) |v_t - u_t| times that turn.
- Swung in the engine about the hands (first-order integrators): the bat is turned by
  d_theta = omega_r dt / 2 at release (omega_r its analytic release speed), which slides the
  foot by (R + |s|) d_theta, tilts the ball's approach by d_theta ((v0 + |v1|) d_theta^2) and
  comes with the hinge's relative omega error HINGE_K (omega_r dt)^2, which moves v1 by
  (1 + q)(d + |s|) d_omega; twice their sum covers the neglected cross terms.
- When the rigid episode is more than one impulse (``analytic.collide``: e = 0 or small, the
  ball re-met or riding the turning bat), each impulse carries the terms above (a later one
  seen a whole step late), and the sustained contact force F (peak F_max) is quantized by
  the step: the engine applies it for up to
  OFF_SPAN_STEPS + 2 steps more or less than the rigid episode (one where the contact starts, one
  where it ends, and the steps the ball may pass the cylinder's end before the engine's episode
  is over), which moves v1 by at most (OFF_SPAN_STEPS + 2) F_max dt / m; and a velocity-level
  contact lets the sliding ball sink up to a dt T into the bat (a = F_max / m_eff, T the
  sliding time), which weakens the slide's effect on v1 by sink / R.
- A contact that separates slower than the turning bat tilts its normal (e v_c < |v_t - u_t|
  omega0 dt) stays active into the next step(s), where the constraint removes the approach the
  tilt creates: LINGER_STEPS steps of |v_t - u_t| omega0 dt - e v_c.
An impact whose outcome is sound (``endings.Physics``) is ``ok`` only within this tolerance of
the rigid-body answer; otherwise its status is ``inaccurate``. Engines whose contact converges to
another model than the rigid impulse (soft contacts) are judged against that model instead
(``soft_judgement``). Every tolerance of the harness is a named term of ``terms``, with its
reason: the tests import them rather than restate them.
"""

from __future__ import annotations

import functools
import math
from dataclasses import replace
from enum import StrEnum

import numpy as np

import adapters
from analytic import CollisionEpisode, ImpactCase, collide, compliant
from analytic.frictional import frictional_episode
from analytic.gradients import normal_fields

from .endings import Physics


class Status(StrEnum):
    """The verdict on a fired impact: ``ok`` (sound, and v1 matched the answer that applies
    within its tolerance), ``inaccurate`` (sound, but outside it), ``unjudged`` (sound, but no
    answer applies that the harness can judge it against: a soft contact beyond its law's
    single contact, or stepped too coarsely for the law's bound), or the engine's physical
    outcome when it was not sound (``endings.Physics``: the same words). A member is its value
    as a string (``str(Status.OK) == "ok"``, in f-strings and CSV alike): modules outside the
    judge name statuses only through it, never by their words."""

    OK = "ok"
    TUNNELLED = Physics.TUNNELLED.value
    NO_CONTACT = Physics.NO_CONTACT.value
    NON_FINITE = Physics.NON_FINITE.value
    ENERGY_GAINED = Physics.ENERGY_GAINED.value
    PENETRATION = Physics.PENETRATION.value
    NO_SEPARATION = Physics.NO_SEPARATION.value
    UNSUPPORTED = Physics.UNSUPPORTED.value
    ERROR = Physics.ERROR.value
    TIMEOUT = Physics.TIMEOUT.value
    INACCURATE = "inaccurate"
    UNJUDGED = "unjudged"


#: Statuses whose v1 is a measurement (a sound impact): errors are taken over them. ``ok`` rows
#: matched their answer within tolerance, ``inaccurate`` did not, ``unjudged`` have none.
MEASURED = (Status.OK.value, Status.INACCURATE.value, Status.UNJUDGED.value)

from .terms import (  # noqa: E402 - the tolerance table (``terms``), read by name below
    CURVATURE_STEP_M,
    ENERGY_GAIN_REL,
    ENERGY_GAIN_ULPS,
    FD_STEP_M,
    GEOM_SAFETY,
    HINGE_K,
    LAW_MAX_REL_ERROR,
    LAW_SAFETY,
    LINGER_STEPS,
    MASS_CHECK_REL,
    MASS_CHECK_ULPS,
    OFF_SPAN_STEPS,
    ROUND_OPS,
    SOLVE_SAFETY,
)


def errors_of(o, models=None) -> adapters.ErrorModel:
    """The error model an outcome is judged with: the one ``models`` gives its engine (a study
    asking what another precision or contact law would allow), else its engine's record's."""
    return (models or {}).get(o.engine) or adapters.record(o.engine).errors


def mass_allowance(eps: float) -> float:  # relative, between mass properties set and read back
    return max(MASS_CHECK_REL, MASS_CHECK_ULPS * eps)


def energy_allowance(errors: adapters.ErrorModel, settings: adapters.Settings) -> float:
    """Relative kinetic-energy gain allowed before ``energy_gained``: rounding, 4 times a
    mapping's stated bias (an impulse that much too large, at e = 1) and twice a stiff solve's
    velocity error (SOLVE_SAFETY cond eps; MJX float32: +0.08 to +0.37% measured, 0.95% let)."""
    eps = errors.eps
    return (
        max(ENERGY_GAIN_REL, ENERGY_GAIN_ULPS * eps)
        + 4.0 * errors.mapping_error_rel(settings)
        + 2.0 * SOLVE_SAFETY * errors.solve_conditioning(settings) * eps
    )


#: ``derivatives``' answers by (case, field), as ``rigid``'s: studies fire the same case at
#: many settings. Emptied when it holds CACHED_CASES.
_DERIVED: dict[tuple[ImpactCase, str], tuple[float, float, float]] = {}
CACHED_CASES = 1 << 16


def derivatives(cases, field: str = "v1_mps") -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The single impulse's ``field`` at each case's s, its |d/ds| (central difference over
    FD_STEP_M, kept on the cylinder) and |d2/ds2| (over CURVATURE_STEP_M), each case's worked
    out once (``_DERIVED``)."""
    new = [c for c in dict.fromkeys(cases) if (c, field) not in _DERIVED]
    if new:
        if len(_DERIVED) + len(new) > CACHED_CASES:
            _DERIVED.clear()
        _DERIVED.update(zip(((c, field) for c in new), zip(*_derived(new, field))))
    if len(cases) == 1:  # (one impact: no table of one row to build)
        return tuple(np.array([x]) for x in _DERIVED[cases[0], field])
    value, slope, curvature = np.array([_DERIVED[c, field] for c in cases]).reshape(-1, 3).T
    return value, slope, curvature


def _derived(cases, field: str) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``derivatives`` worked out: one vectorized prediction per bat and ball for all rows and
    all five points (``normal_fields``: the formulas without their checks, a third of the cost
    on one impact)."""
    n = len(cases)
    value, slope, curvature = np.empty(n), np.empty(n), np.empty(n)
    groups: dict[tuple, list[int]] = {}
    for i, c in enumerate(cases):
        groups.setdefault((c.bat, c.ball), []).append(i)
    h = CURVATURE_STEP_M
    for (bat, ball), idx in groups.items():
        cs = [cases[i] for i in idx]
        s = np.array([c.s_m for c in cs])
        lo = np.maximum(s - FD_STEP_M, bat.s_min_m)
        hi = np.minimum(s + FD_STEP_M, bat.s_max_m)
        s3 = np.clip(
            np.clip(s[:, None] + np.array([-h, 0.0, h]), bat.s_min_m - h, bat.s_max_m + h),
            -bat.com_from_knob_m,
            bat.s_barrel_end_m,
        )
        points = np.column_stack([lo, hi, s3])  # rows x 5
        # one column per input, broadcast over the five points (rows x 1)
        v0, u0, w0, e, theta, phi = np.array(
            [(c.v0_mps, c.u0_mps, c.omega0_radps, c.e, c.theta_rad, c.phi_rad) for c in cs]
        ).T[:, :, None]
        # the cases' values were checked when they were made, the points are kept on the bat
        v0n, u0n = v0 * np.cos(theta), u0 * np.cos(phi)
        m, M, J = ball.mass_kg, bat.mass_kg, bat.inertia_cm_kgm2
        v = normal_fields(m, M, J, points, v0n, u0n, w0, e)[field]
        value[idx] = v[:, 3]
        slope[idx] = np.abs(v[:, 1] - v[:, 0]) / (hi - lo)
        curvature[idx] = np.abs(v[:, 2] - 2 * v[:, 3] + v[:, 4]) / h**2
    return value, slope, curvature


def precision_rel(
    settings: adapters.Settings, errors: adapters.ErrorModel, case: ImpactCase
) -> float:
    """Relative error of an impact's velocities without a geometric cause: ROUND_OPS eps, a
    stiff solve's rounding (SOLVE_SAFETY eps ``ErrorModel.solve_conditioning``), the bias the
    mapping of e leaves (``ErrorModel.mapping_error_rel``), and the approach lost along a
    normal the collision routine tilts (``ErrorModel.collision_slide_m`` over r1 + r2)^2."""
    tilt = errors.collision_slide_m(settings, case.bat) / (case.bat.radius_m + case.ball.radius_m)
    return (
        (ROUND_OPS + SOLVE_SAFETY * errors.solve_conditioning(settings)) * errors.eps
        + errors.mapping_error_rel(settings)
        + tilt * tilt
    )


def _lingering(case: ImpactCase, dt_s: float, tangential_mps: float) -> float:
    """What a contact kept LINGER_STEPS steps after its impulse adds (m/s): the normal tilts by
    omega0 dt a step, so the tangential speed approaches at tangential omega0 dt; beyond e v_c
    (e small) the engine's constraint takes that out again (module docstring)."""
    per_step = tangential_mps * abs(case.omega0_radps) * dt_s
    return LINGER_STEPS * max(0.0, per_step - case.e * case.closing_speed_mps)


def _tangential(case: ImpactCase) -> float:  # the approach's relative tangential speed (m/s)
    return abs(case.v0_mps * math.sin(case.theta_rad) - case.u0_mps * math.sin(case.phi_rad))


def _speed(case: ImpactCase) -> float:  # the speed scale of rounding: v0 + |u0| + |w0| L
    return case.v0_mps + abs(case.u0_mps) + abs(case.omega0_radps) * case.bat.length_m


@functools.lru_cache(maxsize=1 << 16)
def rigid(case: ImpactCase, max_episode_s: float) -> CollisionEpisode:
    """The rigid-body answer an engine's impact is judged against: the whole episode, followed
    as long as the engine follows its own (its ``max_contact_s``); with friction or out of the
    swing plane, one frictional impulse (``analytic.frictional``, ``friction_judge``). Cached:
    studies fire the same case at many settings."""
    if not case.frictionless_planar:
        return frictional_episode(case, max_episode_s=max_episode_s)
    return collide(case, max_episode_s=max_episode_s)


def single_impulse_tolerance(
    case: ImpactCase,
    settings: adapters.Settings,
    errors: adapters.ErrorModel,
    slope: float,
    curvature: float,
    scale_mps: float | None = None,
) -> float:
    """Allowed |engine - single impulse| of an output whose |d/ds| and |d2/ds2| are given:
    ROUND_OPS eps times ``scale_mps`` (default the impact's speed scale) for rounding, the
    slide of a contact seen late (a speculative one up to a step early), and what a lingering
    contact adds."""
    st = settings
    v_c = case.closing_speed_mps
    reach = case.bat.radius_m + case.ball.radius_m
    tangential = _tangential(case)
    # a speculative contact is solved from the geometry at the start of the step that closes
    # it: as far off as the gap it had then (up to the margin, or a whole step)
    early = min(errors.speculative_margin_m(st), v_c * st.dt_s)
    delta = st.overlap_m + max(st.contact_phase * v_c * st.dt_s, early)
    slide = (reach * abs(case.omega0_radps) + tangential) * delta / v_c + errors.collision_slide_m(
        st, case.bat
    )
    # the same delay turns the normal by omega0 delta / v_c, so the impulse, (1 + e) times the
    # approach along it, takes in that share of the tangential speed
    leak = (1.0 + case.e) * tangential * abs(case.omega0_radps) * delta / v_c
    # (and a collision routine's own bias moves it too: ``ErrorModel.collision_slide_m``)
    seen_late = GEOM_SAFETY * (slope * slide + 0.5 * curvature * slide**2 + leak)
    scale = _speed(case) if scale_mps is None else scale_mps
    return (
        precision_rel(st, errors, case) * scale + seen_late + _lingering(case, st.dt_s, tangential)
    )


def tolerances(
    cases,
    outcomes,
    errors_each,
    release_omega_radps,
    rigid_episodes,
    derivatives: tuple | None = None,
) -> np.ndarray:
    """Allowed |v1 engine - v1 rigid| per impact (m/s; NaN where not judged), each outcome
    judged with its error model (``errors_each``); ``derivatives``: the cases' single-impulse
    v1 and its derivatives (``derivatives``), if already worked out."""
    out = np.full(len(cases), math.nan)
    v1, slopes, curvatures = derivatives or derivatives(cases)
    for i, (case, o, errors, w_r, ep) in enumerate(
        zip(cases, outcomes, errors_each, release_omega_radps, rigid_episodes)
    ):
        st = o.settings
        if (
            errors.contact_reference(st) is not adapters.ContactReference.RIGID_IMPULSE
            or not case.frictionless_planar
        ):  # (friction: ``friction_judge``)
            continue
        if ep.impacts > 1 or ep.sustained_contact_s > 0.0:
            out[i] = _episode_tolerance(
                case, ep, st, errors, w_r, _speed(case) * precision_rel(st, errors, case), v1[i]
            )
            continue
        tol = single_impulse_tolerance(case, st, errors, slopes[i], curvatures[i])
        if math.isfinite(w_r):
            tol += _swing_terms(case, st.dt_s, w_r, v1[i], slopes[i], curvatures[i])
        out[i] = tol
    return out


def _swing_terms(
    case: ImpactCase, dt_s: float, w_r: float, v1: float, slope: float, curvature: float
) -> float:
    """After a swing in the engine (first-order integrators): the release angle's slide and
    tilt and the hinge's omega error, twice their sum (module docstring)."""
    bat, ball = case.bat, case.ball
    reach = bat.radius_m + ball.radius_m
    d_theta = 0.5 * abs(w_r) * dt_s
    d_omega = HINGE_K * (w_r * dt_s) ** 2 * abs(w_r)
    r = ball.mass_kg * (1 / bat.mass_kg + case.s_m**2 / bat.inertia_cm_kgm2)
    q = (case.e - r) / (1 + r)
    arm = bat.com_from_knob_m - case.hands_from_knob_m
    swing_slide = (reach + abs(case.s_m)) * d_theta
    return 2 * (
        slope * swing_slide
        + 0.5 * curvature * swing_slide**2
        + (case.v0_mps + abs(v1)) * d_theta**2
        + (1 + q) * (abs(arm) + abs(case.s_m)) * d_omega
    )


def output_tolerance(
    case: ImpactCase, settings: adapters.Settings, errors: adapters.ErrorModel, field: str
) -> float:
    """``single_impulse_tolerance`` of one output of ``analytic.predict`` (v1_mps, u1_mps or
    omega1_radps: its rounding scaled to rad/s by 1/L) for a case fired once."""
    _, slope, curvature = derivatives([case], field)
    scale = _speed(case) / case.bat.length_m if field == "omega1_radps" else None
    return single_impulse_tolerance(case, settings, errors, slope[0], curvature[0], scale)


def _episode_tolerance(
    case: ImpactCase,
    ep: CollisionEpisode,
    st: adapters.Settings,
    errors: adapters.ErrorModel,
    w_r: float,
    rounding: float,
    v1_impulse: float,
) -> float:
    """The tolerance of an episode of more than one impulse. The same sources as for one, but
    the rigid answer's sensitivity is taken from ``collide`` itself (a long slide along the
    turning bat amplifies a shift of the contact point or of the bat's speed far more than the
    single impulse does): v1 of the episode with s moved by the slides, and, after a swing in
    the engine, with omega0 (and u0 with it) and the approach tilted by the swing's errors."""
    bat, ball = case.bat, case.ball
    reach = bat.radius_m + ball.radius_m
    v_c = case.closing_speed_mps
    tangential = _tangential(case)

    def delay(phase: float) -> float:
        return (st.overlap_m + phase * v_c * st.dt_s) / v_c

    # the first contact seen at its phase, each later one as late as a whole step
    late = delay(st.contact_phase) + (ep.impacts - 1) * delay(1.0)
    slide = (reach * abs(case.omega0_radps) + tangential) * late + errors.collision_slide_m(st, bat)
    leak = (1.0 + case.e) * tangential * abs(case.omega0_radps) * late
    moved = []
    if math.isfinite(w_r):
        d_theta = 0.5 * abs(w_r) * st.dt_s
        d_omega = HINGE_K * (w_r * st.dt_s) ** 2 * abs(w_r)
        slide += (reach + abs(case.s_m)) * d_theta
        arm = bat.com_from_knob_m - case.hands_from_knob_m
        moved += [
            dict(
                omega0_radps=case.omega0_radps + sign * d_omega,
                u0_mps=case.u0_mps + sign * d_omega * arm,
            )
            for sign in (-1, 1)
        ]
        # the bat turned by d_theta tilts each approach against the contact normal
        moved += [
            {angle: max(min(getattr(case, angle) + sign * d_theta, 1.5), -1.5)}
            for angle in ("theta_rad", "phi_rad")
            for sign in (-1, 1)
        ]
    span = [
        dict(s_m=min(max(case.s_m + sign * slide, bat.s_min_m), bat.s_max_m)) for sign in (-1, 1)
    ]
    dv_s = max(abs(rigid(replace(case, **kw), st.max_contact_s).v1_mps - ep.v1_mps) for kw in span)
    dv_swing = max(
        (abs(rigid(replace(case, **kw), st.max_contact_s).v1_mps - ep.v1_mps) for kw in moved),
        default=0.0,
    )
    # a velocity-level contact lets the ball sink into the bat as it slides, up to
    # a dt T (a = F_max / m_eff, T the sliding time); at R - sink the turning bat's pull on the
    # ball, omega^2 d.n, is that fraction weaker, and so is what the slide did to v1
    m_eff = 1.0 / (1 / ball.mass_kg + 1 / bat.mass_kg + case.s_m**2 / bat.inertia_cm_kgm2)
    sink = ep.peak_sustained_force_n / m_eff * st.dt_s * ep.sustained_contact_s
    slid = abs(ep.v1_mps - v1_impulse)
    return (
        rounding * ep.impacts
        + GEOM_SAFETY * (dv_s + leak)
        + 2 * dv_swing
        + sink / reach * slid
        + ep.impacts * _lingering(case, st.dt_s, tangential)
        + (OFF_SPAN_STEPS + 2) * ep.peak_sustained_force_n * st.dt_s / ball.mass_kg
    )


@functools.lru_cache(maxsize=1 << 12)
def law_answer(case: ImpactCase, law) -> compliant.CompliantOutcome:
    """The answer of the continuous contact law a soft engine declares (``ErrorModel.contact_law``).
    Cached: the studies fire one case and law at many steps and phases."""
    return compliant.predict(case, law)


def soft_judgement(
    case: ImpactCase, o, errors: adapters.ErrorModel | None = None
) -> tuple[float, float]:
    """(v1 of the engine's own contact law, allowed |v1 engine - v1 law|) for an engine whose
    contact converges to a continuous law; (NaN, NaN) for a rigid contact; (v1 law, NaN),
    unjudged, where the law's answer or the bound does not apply. The tolerance is the leading
    error of the engine's step through a contact of duration t_c: its restitution comes out off
    by e times ``ErrorModel.law_restitution_error`` (semi-implicit Euler: (pi/3) dt/t_c), e the
    law's own restitution at this impact (it moves with speed for Hunt-Crossley), which moves
    v1 by v_c / (1 + r) per unit e, r = m (1/M + s^2/J); LAW_SAFETY times that, plus rounding.
    ``analytic.compliant.predict`` follows one contact of an infinite cylinder: where the
    rigid episode at the law's e holds more (re-contacts, a sustained slide), or the ball slides
    past the cylinder's end during the contact, its answer is not the engine's, and the row is
    unjudged; so is a step whose estimated restitution error exceeds LAW_MAX_REL_ERROR.
    ``errors``: the error model to judge with (default its engine's record's)."""
    errors = errors or errors_of(o)
    law = errors.contact_law(o.settings, case.e)
    if law is None or not case.frictionless_planar:  # the laws are frictionless, planar
        return math.nan, math.nan
    ref = law_answer(case, law)
    bat, ball = case.bat, case.ball
    v_c, t_c = case.closing_speed_mps, ref.contact_duration_s
    rel_err = errors.law_restitution_error(o.settings, o.settings.dt_s / t_c)
    e_law = (ref.v1_mps - ref.u1_mps - ref.omega1_radps * case.s_m) / v_c
    reach = bat.radius_m + ball.radius_m
    slide = (_tangential(case) + reach * abs(case.omega0_radps)) * t_c
    episode = rigid(replace(case, e=min(max(e_law, 0.0), 1.0)), o.settings.max_contact_s)
    if (
        rel_err > LAW_MAX_REL_ERROR
        or episode.impacts > 1
        or episode.sustained_contact_s > 0.0
        or not bat.s_min_m + slide <= case.s_m <= bat.s_max_m - slide
    ):
        return ref.v1_mps, math.nan
    r = ball.mass_kg * (1 / bat.mass_kg + case.s_m**2 / bat.inertia_cm_kgm2)
    de = max(case.e, e_law) * rel_err
    rounding = precision_rel(o.settings, errors, case) * _speed(case)
    return ref.v1_mps, LAW_SAFETY * v_c / (1 + r) * de + rounding


def phases(k: int) -> np.ndarray:
    """Contact phases (k + 1/2)/K, k = 0..K-1: an even sample of where in a step contact falls."""
    return (np.arange(k) + 0.5) / k


def caught_in_theory(
    v_mps: float,
    dt_s: float,
    phase: np.ndarray | float,
    reach_m: float,
    overlap_m: float = 1e-9,
    speculative_m: float = 0.0,
) -> np.ndarray:
    """The tunnelling bound: whether a rigid contact at this closing speed, step and phase is
    caught. It is first seen ``phase v dt + overlap`` deep, and handled iff that stays below
    the reach r_ball + r_bat (past it the ball's centre is beyond the bat's axis); or its gap
    at the start of the contact's step, ``(1 - phase) v dt - overlap``, is within the engine's
    speculative margin (it is then solved in that step)."""
    p = np.asarray(phase, dtype=float)
    return (p * v_mps * dt_s + overlap_m < reach_m) | (
        (1 - p) * v_mps * dt_s - overlap_m < speculative_m
    )
