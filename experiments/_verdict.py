"""The tolerance each fired impact is judged against, derived as the conformance suite derives
it: what the engine's float precision, the depth at which it first sees the contact, and (after
a swing in the engine) its integrator's angle error can move v1 by.

    allowed = ROUND_OPS eps speed + GEOM_SAFETY |dv1/ds| slide  (+ the swing's terms)

- eps: the engine's unit roundoff (its record's precision); speed = v0 + |u0| + |omega0| L.
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
  seen as late as a whole step, contact_phase 1), and the sustained
  contact force F (peak F_max) is quantized by the step: the engine applies it for up to
  OFF_SPAN_STEPS + 2 steps more or less than the rigid episode (one where the contact starts, one
  where it ends, and the steps the ball may pass the cylinder's end before the engine's episode
  is over), which moves v1 by at most (OFF_SPAN_STEPS + 2) F_max dt / m; and a velocity-level
  contact lets the sliding ball sink up to a dt T into the bat (a = F_max / m_eff, T the
  sliding time), which weakens the slide's effect on v1 by sink / R.
- A contact that separates slower than the turning bat tilts its normal (e v_c < |v_t - u_t|
  omega0 dt) stays active into the next step(s), where the constraint removes the approach the
  tilt creates: LINGER_STEPS steps of |v_t - u_t| omega0 dt - e v_c.
An impact the engine reports sound (status ok) is kept ok only within this tolerance of the
rigid-body answer; otherwise its status is ``inaccurate``. Engines whose contact converges to
another model than the rigid impulse (soft contacts) are not judged here (NaN tolerance).
"""

from __future__ import annotations

import functools
import math
from dataclasses import replace

import numpy as np

import adapters
from adapters.base import OFF_SPAN_STEPS
from analytic import CollisionEpisode, ImpactCase, collide, compliant, predict_arrays

ROUND_OPS = 1e4      #: float operations of an impact, each within eps
GEOM_SAFETY = 10.0   #: covers the factors of order 1 the slide estimate neglects
HINGE_K = 4.0        #: empirical bound on the hinges' (omega dt)^2 constant (0.05-3.7 measured)
FD_STEP_M = 1e-6     #: finite-difference step for dv1/ds (m)
CURVATURE_STEP_M = 1e-3  #: step for d2v1/ds2 (m): v1(s) is a smooth rational function
#: Steps a contact may stay active after its impulse (PyBullet measured 1.16 at e = 0)
LINGER_STEPS = 2


def _derivatives(cases) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Single-impulse v1 at each case's s, |dv1/ds| (central difference over FD_STEP_M, kept on
    the cylinder) and |d2v1/ds2| (over CURVATURE_STEP_M): one vectorized prediction per bat and
    ball for all rows and all five points."""
    n = len(cases)
    v1, slope, curvature = np.empty(n), np.empty(n), np.empty(n)
    groups: dict[tuple, list[int]] = {}
    for i, c in enumerate(cases):
        groups.setdefault((c.bat, c.ball), []).append(i)
    h = CURVATURE_STEP_M
    for (bat, ball), idx in groups.items():
        cs = [cases[i] for i in idx]
        s = np.array([c.s_m for c in cs])
        lo = np.maximum(s - FD_STEP_M, bat.s_min_m)
        hi = np.minimum(s + FD_STEP_M, bat.s_max_m)
        s3 = np.clip(np.clip(s[:, None] + np.array([-h, 0.0, h]), bat.s_min_m - h,
                             bat.s_max_m + h), -bat.com_from_knob_m, bat.s_barrel_end_m)
        points = np.column_stack([lo, hi, s3])  # rows x 5
        kw = {f: np.repeat([getattr(c, f) for c in cs], 5).reshape(-1, 5) for f in (
            "v0_mps", "u0_mps", "omega0_radps", "e", "theta_rad", "phi_rad")}
        v = predict_arrays(bat, ball, s_m=points, **kw)["v1_mps"]
        v1[idx] = v[:, 3]
        slope[idx] = np.abs(v[:, 1] - v[:, 0]) / (hi - lo)
        curvature[idx] = np.abs(v[:, 2] - 2 * v[:, 3] + v[:, 4]) / h**2
    return v1, slope, curvature


def _lingering(case: ImpactCase, dt_s: float, tangential_mps: float) -> float:
    """What a contact kept for LINGER_STEPS steps after its impulse can add (m/s): the ball
    leaves at e v_c, while the turning bat tilts the normal by omega0 dt per step, against
    which the relative tangential speed approaches at tangential omega0 dt; where that exceeds
    e v_c (e = 0 or small), the engine's constraint takes it out again at the next step."""
    per_step = tangential_mps * abs(case.omega0_radps) * dt_s
    return LINGER_STEPS * max(0.0, per_step - case.e * case.closing_speed_mps)


@functools.lru_cache(maxsize=1 << 16)
def rigid(case: ImpactCase, max_episode_s: float) -> CollisionEpisode:
    """The rigid-body answer an engine's impact is judged against: the whole episode, followed
    as long as the engine follows its own (its ``max_contact_s``). Cached: studies fire the same
    case at many settings."""
    return collide(case, max_episode_s=max_episode_s)


def tolerances(cases, outcomes, release_omega_radps, rigid_episodes) -> np.ndarray:
    """Allowed |v1 engine - v1 rigid| per impact (m/s; NaN where not judged)."""
    out = np.full(len(cases), math.nan)
    v1, slopes, curvatures = _derivatives(cases)
    for i, (case, o, w_r, ep) in enumerate(zip(cases, outcomes, release_omega_radps,
                                               rigid_episodes)):
        rec = adapters.record(o.engine)
        cls = adapters.engine_class(o.engine)
        if cls.converges_to(o.settings) is not adapters.ContactReference.RIGID_IMPULSE:
            continue
        bat, ball, st = case.bat, case.ball, o.settings
        slope, curvature = slopes[i], curvatures[i]
        v_c = case.closing_speed_mps
        reach = bat.radius_m + ball.radius_m
        tangential = abs(case.v0_mps * math.sin(case.theta_rad)
                         - case.u0_mps * math.sin(case.phi_rad))
        speed = case.v0_mps + abs(case.u0_mps) + abs(case.omega0_radps) * bat.length_m

        def seen_late(phase: float) -> float:
            # a speculative contact is solved from the geometry at the start of the step that
            # closes it: as far off as the gap it had then (up to the margin, or a whole step)
            early = min(cls.speculative_margin_m(st), v_c * st.dt_s)
            delta = st.overlap_m + max(phase * v_c * st.dt_s, early)
            slide = (reach * abs(case.omega0_radps) + tangential) * delta / v_c
            # the same delay turns the normal by omega0 delta / v_c, so the impulse, (1 + e)
            # times the approach along it, takes in that share of the tangential speed
            leak = (1.0 + case.e) * tangential * abs(case.omega0_radps) * delta / v_c
            return GEOM_SAFETY * (slope * slide + 0.5 * curvature * slide**2 + leak)

        if ep.impacts > 1 or ep.sustained_contact_s > 0.0:
            out[i] = _episode_tolerance(case, ep, o, w_r, speed * ROUND_OPS * rec.eps, v1[i])
            continue
        tol = ROUND_OPS * rec.eps * speed + seen_late(st.contact_phase) \
            + _lingering(case, st.dt_s, tangential)
        if math.isfinite(w_r):
            d_theta = 0.5 * abs(w_r) * st.dt_s
            d_omega = HINGE_K * (w_r * st.dt_s) ** 2 * abs(w_r)
            r = ball.mass_kg * (1 / bat.mass_kg + case.s_m**2 / bat.inertia_cm_kgm2)
            q = (case.e - r) / (1 + r)
            arm = bat.com_from_knob_m - case.hands_from_knob_m
            swing_slide = (reach + abs(case.s_m)) * d_theta
            tol += 2 * (slope * swing_slide + 0.5 * curvature * swing_slide**2
                        + (case.v0_mps + abs(v1[i])) * d_theta**2
                        + (1 + q) * (abs(arm) + abs(case.s_m)) * d_omega)
        out[i] = tol
    return out


def _episode_tolerance(case: ImpactCase, ep: CollisionEpisode, o, w_r: float,
                       rounding: float, v1_impulse: float) -> float:
    """The tolerance of an episode of more than one impulse. The same sources as for one, but
    the rigid answer's sensitivity is taken from ``collide`` itself (a long slide along the
    turning bat amplifies a shift of the contact point or of the bat's speed far more than the
    single impulse does): v1 of the episode with s moved by the slides, and, after a swing in
    the engine, with omega0 (and u0 with it) and the approach tilted by the swing's errors."""
    bat, ball, st = case.bat, case.ball, o.settings
    reach = bat.radius_m + ball.radius_m
    v_c = case.closing_speed_mps
    tangential = abs(case.v0_mps * math.sin(case.theta_rad)
                     - case.u0_mps * math.sin(case.phi_rad))

    def delay(phase: float) -> float:
        return (st.overlap_m + phase * v_c * st.dt_s) / v_c

    # the first contact seen at its phase, each later one as late as a whole step
    late = delay(st.contact_phase) + (ep.impacts - 1) * delay(1.0)
    slide = (reach * abs(case.omega0_radps) + tangential) * late
    leak = (1.0 + case.e) * tangential * abs(case.omega0_radps) * late
    moved = []
    if math.isfinite(w_r):
        d_theta = 0.5 * abs(w_r) * st.dt_s
        d_omega = HINGE_K * (w_r * st.dt_s) ** 2 * abs(w_r)
        slide += (reach + abs(case.s_m)) * d_theta
        arm = bat.com_from_knob_m - case.hands_from_knob_m
        moved += [dict(omega0_radps=case.omega0_radps + sign * d_omega,
                       u0_mps=case.u0_mps + sign * d_omega * arm) for sign in (-1, 1)]
        # the bat turned by d_theta tilts each approach against the contact normal
        moved += [{angle: max(min(getattr(case, angle) + sign * d_theta, 1.5), -1.5)}
                  for angle in ("theta_rad", "phi_rad") for sign in (-1, 1)]
    span = [dict(s_m=min(max(case.s_m + sign * slide, bat.s_min_m), bat.s_max_m))
            for sign in (-1, 1)]
    dv_s = max(abs(rigid(replace(case, **kw), st.max_contact_s).v1_mps - ep.v1_mps)
               for kw in span)
    dv_swing = max((abs(rigid(replace(case, **kw), st.max_contact_s).v1_mps - ep.v1_mps)
                    for kw in moved), default=0.0)
    # a velocity-level contact lets the ball sink into the bat as it slides, up to
    # a dt T (a = F_max / m_eff, T the sliding time); at R - sink the turning bat's pull on the
    # ball, omega^2 d.n, is that fraction weaker, and so is what the slide did to v1
    m_eff = 1.0 / (1 / ball.mass_kg + 1 / bat.mass_kg + case.s_m**2 / bat.inertia_cm_kgm2)
    sink = ep.peak_sustained_force_n / m_eff * st.dt_s * ep.sustained_contact_s
    slid = abs(ep.v1_mps - v1_impulse)
    return (rounding * ep.impacts + GEOM_SAFETY * (dv_s + leak) + 2 * dv_swing
            + sink / reach * slid
            + ep.impacts * _lingering(case, st.dt_s, tangential)
            + (OFF_SPAN_STEPS + 2) * ep.peak_sustained_force_n * st.dt_s / ball.mass_kg)


#: Soft contacts: a factor 2 over the first-order term below (measured for MuJoCo at
#: w = 3000 rad/s, paper's swing, s = 0.1 m, dt = 1e-5..1e-7: 0.86 of the term for Euler,
#: 0.22 for RK4).
LAW_SAFETY = 2.0


@functools.lru_cache(maxsize=1 << 12)
def law_answer(case: ImpactCase, law) -> compliant.CompliantOutcome:
    """The answer of the continuous contact law a soft engine declares (``Engine.contact_law``).
    Cached: the studies fire one case and law at many steps and phases."""
    return compliant.predict(case, law)


#: The leading-order bound below holds while the step's restitution error is small: where the
#: engine's own estimate (``Engine.law_restitution_error``) exceeds this, the step is too coarse
#: for it (an implicit step of 8% of a contact was 2.6 m/s off and "within" a 13 m/s bound), and
#: the row is left unjudged.
LAW_MAX_REL_ERROR = 0.05


def soft_judgement(case: ImpactCase, o) -> tuple[float, float]:
    """(v1 of the engine's own contact law, allowed |v1 engine - v1 law|) for an engine whose
    contact converges to a continuous law; (NaN, NaN) for a rigid contact; (v1 law, NaN),
    unjudged, where the law's answer or the bound does not apply. The tolerance is the leading
    error of the engine's step through a contact of duration t_c: its restitution comes out off
    by e times ``Engine.law_restitution_error`` (semi-implicit Euler: (pi/3) dt/t_c), e the
    law's own restitution at this impact (it moves with speed for Hunt-Crossley), which moves
    v1 by v_c / (1 + r) per unit e, r = m (1/M + s^2/J); LAW_SAFETY times that, plus rounding.
    ``analytic.compliant.predict`` follows one contact of an infinite cylinder: where the
    rigid episode at the law's e holds more (re-contacts, a sustained slide), or the ball slides
    past the cylinder's end during the contact, its answer is not the engine's, and the row is
    unjudged; so is a step whose estimated restitution error exceeds LAW_MAX_REL_ERROR."""
    law = adapters.engine_class(o.engine).contact_law(o.settings, case.e)
    if law is None:
        return math.nan, math.nan
    ref = law_answer(case, law)
    bat, ball = case.bat, case.ball
    v_c, t_c = case.closing_speed_mps, ref.contact_duration_s
    rel_err = adapters.engine_class(o.engine).law_restitution_error(o.settings,
                                                                    o.settings.dt_s / t_c)
    e_law = (ref.v1_mps - ref.u1_mps - ref.omega1_radps * case.s_m) / v_c
    reach = bat.radius_m + ball.radius_m
    tangential = abs(case.v0_mps * math.sin(case.theta_rad) - case.u0_mps * math.sin(case.phi_rad))
    slide = (tangential + reach * abs(case.omega0_radps)) * t_c
    episode = rigid(replace(case, e=min(max(e_law, 0.0), 1.0)), o.settings.max_contact_s)
    if (rel_err > LAW_MAX_REL_ERROR or episode.impacts > 1
            or episode.sustained_contact_s > 0.0
            or not bat.s_min_m + slide <= case.s_m <= bat.s_max_m - slide):
        return ref.v1_mps, math.nan
    r = ball.mass_kg * (1 / bat.mass_kg + case.s_m**2 / bat.inertia_cm_kgm2)
    de = max(case.e, e_law) * rel_err
    speed = case.v0_mps + abs(case.u0_mps) + abs(case.omega0_radps) * bat.length_m
    rounding = ROUND_OPS * adapters.record(o.engine).eps * speed
    return ref.v1_mps, LAW_SAFETY * v_c / (1 + r) * de + rounding
