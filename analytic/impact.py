"""Planar rigid-body impact of a ball on a swinging bat: impulse, outcomes, sweet spot, COP.

Assumptions (the paper's 4.1-4.4): planar motion, rigid bodies, an instantaneous frictionless
impulse (no hands, no gravity during the impact) and Newton's restitution law at the contact point.
Every function here is closed form; the vectorized ones broadcast over numpy arrays.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from . import checks
from .model import MAX_OMEGA_RADPS, MAX_SPEED_MPS, Ball, Bat, ImpactCase, Outcome


def _normal_impulse(m: float, M: float, J: float, s, closing, e):
    """P = (1 + e) v_c / (1/m + 1/M + s^2/J): the normal impulse on the ball (N s)."""
    return (1.0 + e) * closing / (1.0 / m + 1.0 / M + s * s / J)


def predict(case: ImpactCase) -> Outcome:
    """Outcome of one impact (planar impulse model, frictionless, oblique allowed).

    With n-components v0n = v0 cos(theta), u0n = u0 cos(phi) and v_c = v0n + u0n + omega0 s:
        P      = (1 + e) v_c / (1/m + 1/M + s^2/J)
        v1     = -v0n + P/m        u1 = u0n - P/M        omega1 = omega0 - P s / J
        q      = (e - m/Meff) / (1 + m/Meff),   1/Meff = 1/M + s^2/J
    so that v1 = q v0n + (1 + q)(u0n + omega0 s). Frictionless: the tangential velocities
    v0 sin(theta) and u0 sin(phi) are unchanged. The hand point at x_h moves along y with
    u + omega (x_h - x_cm), so its change is  dv_h = -P (1/M + s (x_h - x_cm)/J).
    """
    checks.instance("case", case, ImpactCase)
    bat, ball = case.bat, case.ball
    m, M, J, s = ball.mass_kg, bat.mass_kg, bat.inertia_cm_kgm2, case.s_m
    vc = case.closing_speed_mps
    P = _normal_impulse(m, M, J, s, vc, case.e)
    v1 = -case.v0n_mps + P / m
    u1 = case.u0n_mps - P / M
    w1 = case.omega0_radps - P * s / J
    r = m * (1.0 / M + s * s / J)
    q = (case.e - r) / (1.0 + r)
    d_hand = case.hands_from_knob_m - bat.com_from_knob_m
    v_t = case.v0_mps * math.sin(case.theta_rad)
    u_t = case.u0_mps * math.sin(case.phi_rad)
    ke0 = 0.5 * (m * case.v0_mps**2 + M * case.u0_mps**2 + J * case.omega0_radps**2)
    ke1 = 0.5 * (m * (v1**2 + v_t**2) + M * (u1**2 + u_t**2) + J * w1**2)
    return Outcome(
        v1_mps=v1,
        u1_mps=u1,
        omega1_radps=w1,
        impulse_ns=P,
        q=q,
        closing_speed_mps=vc,
        hand_dv_mps=-P * (1.0 / M + s * d_hand / J),
        ke_before_j=ke0,
        ke_after_j=ke1,
        v1_t_mps=v_t,
        u1_t_mps=u_t,
    )


def _speeds(v0_mps: ArrayLike, u0_mps: ArrayLike, omega0_radps: ArrayLike):
    """v0, u0 and omega0 as arrays, each within the range an ImpactCase accepts."""
    return (
        checks.array_in_range("v0_mps", v0_mps, 0.0, MAX_SPEED_MPS),
        checks.array_in_range("u0_mps", u0_mps, -MAX_SPEED_MPS, MAX_SPEED_MPS),
        checks.array_in_range("omega0_radps", omega0_radps, -MAX_OMEGA_RADPS, MAX_OMEGA_RADPS),
    )


def _bodies(bat: Bat, ball: Ball) -> None:
    """Refuse anything but a Bat and a Ball, named, before any arithmetic on them."""
    checks.instance("bat", bat, Bat)
    checks.instance("ball", ball, Ball)


def batted_ball_speed(
    bat: Bat,
    ball: Ball,
    s_m: ArrayLike,
    *,
    v0_mps: ArrayLike,
    u0_mps: ArrayLike = 0.0,
    omega0_radps: ArrayLike = 0.0,
    e: ArrayLike = 0.5,
    theta_rad: ArrayLike = 0.0,
    phi_rad: ArrayLike = 0.0,
) -> np.ndarray:
    """Vectorized v1 (normal component, m/s) over broadcast arrays of impact points and speeds.

    v1 = -v0n + (1 + e) v_c / (1 + m/M + m s^2/J), with v0n, v_c as in ``predict``.
    Raises ValueError if any point is off the bat or any pair does not approach (v_c <= 0).
    """
    return predict_arrays(
        bat,
        ball,
        s_m=s_m,
        v0_mps=v0_mps,
        u0_mps=u0_mps,
        omega0_radps=omega0_radps,
        e=e,
        theta_rad=theta_rad,
        phi_rad=phi_rad,
    )["v1_mps"]


def predict_arrays(
    bat: Bat,
    ball: Ball,
    *,
    s_m: ArrayLike,
    v0_mps: ArrayLike,
    u0_mps: ArrayLike = 0.0,
    omega0_radps: ArrayLike = 0.0,
    e: ArrayLike = 0.5,
    theta_rad: ArrayLike = 0.0,
    phi_rad: ArrayLike = 0.0,
    hands_from_knob_m: ArrayLike = 0.1,
) -> dict[str, np.ndarray]:
    """``predict`` over broadcast arrays of impacts on one bat: the normal-direction fields
    v1_mps, u1_mps, omega1_radps, impulse_ns and hand_dv_mps (same formulas, vectorized), for
    tables of many impacts. Raises ValueError if any point is off the bat, any value out of
    range, or any pair does not approach (closing speed <= 0)."""
    _bodies(bat, ball)
    m, M, J = ball.mass_kg, bat.mass_kg, bat.inertia_cm_kgm2
    s = checks.array_in_range("s_m", s_m, -bat.com_from_knob_m, bat.s_barrel_end_m)
    v0, u0, w0 = _speeds(v0_mps, u0_mps, omega0_radps)
    v0n = v0 * np.cos(checks.array_in_range("theta_rad", theta_rad, -math.pi / 2, math.pi / 2))
    u0n = u0 * np.cos(checks.array_in_range("phi_rad", phi_rad, -math.pi / 2, math.pi / 2))
    hands = checks.array_in_range("hands_from_knob_m", hands_from_knob_m, 0.0, bat.length_m)
    vc = v0n + u0n + w0 * s
    if np.any(vc <= 0.0):
        bad = np.broadcast_to(s, vc.shape)[vc <= 0.0].flat[0]
        raise ValueError(
            f"closing speed <= 0 at s_m={bad!r}: the bodies do not approach; "
            "allowed: v0*cos(theta) + u0*cos(phi) + omega0*s > 0"
        )
    P = _normal_impulse(m, M, J, s, vc, checks.array_in_range("e", e, 0.0, 1.0))
    return {
        "v1_mps": -v0n + P / m,
        "u1_mps": u0n - P / M,
        "omega1_radps": w0 - P * s / J,
        "impulse_ns": P,
        "hand_dv_mps": -P * (1.0 / M + s * (hands - bat.com_from_knob_m) / J),
    }


def collision_efficiency(bat: Bat, ball: Ball, s_m: ArrayLike, e: ArrayLike = 0.5) -> np.ndarray:
    """Vectorized q = (e - m/Meff)/(1 + m/Meff), 1/Meff = 1/M + s^2/J (dimensionless).

    q is the batted-ball speed per unit pitch speed off a bat at rest: v1 = q v0.
    """
    _bodies(bat, ball)
    s = checks.array_in_range("s_m", s_m, -bat.com_from_knob_m, bat.s_barrel_end_m)
    ee = checks.array_in_range("e", e, 0.0, 1.0)
    r = ball.mass_kg * (1.0 / bat.mass_kg + s * s / bat.inertia_cm_kgm2)
    return (ee - r) / (1.0 + r)


def sweet_spot(
    bat: Bat,
    ball: Ball,
    v0_mps: ArrayLike,
    u0_mps: ArrayLike = 0.0,
    omega0_radps: ArrayLike = 0.0,
    *,
    theta_rad: ArrayLike = 0.0,
    phi_rad: ArrayLike = 0.0,
) -> np.ndarray | float:
    """Impact point s* (m from the COM) that maximizes v1; independent of e.

    dv1/ds = 0 gives omega0 s^2 + 2 A s - omega0 J k = 0 with A = v0n + u0n, k = (m + M)/(m M):
        s* = [-A + sqrt(A^2 + omega0^2 J k)] / omega0 = omega0 J k / (A + sqrt(A^2 + omega0^2 J k))
    the root where v1 peaks, for either sign of A and omega0, with a closing speed there of
    A + omega0 s* = sqrt(A^2 + omega0^2 J k) > 0 (a bat turning into a ball at rest has one).
    The second form is used for A > 0, the first for A <= 0: neither cancels, and the second
    gives s* = 0 at omega0 = 0. With omega0 = 0 and A <= 0 nothing approaches: ValueError. s*
    may lie beyond the barrel end; then v1 is largest at the end of the bat.
    """
    _bodies(bat, ball)
    v0, u0, w0 = _speeds(v0_mps, u0_mps, omega0_radps)
    th = checks.array_in_range("theta_rad", theta_rad, -math.pi / 2, math.pi / 2)
    ph = checks.array_in_range("phi_rad", phi_rad, -math.pi / 2, math.pi / 2)
    A, w0 = np.broadcast_arrays(v0 * np.cos(th) + u0 * np.cos(ph), w0)
    if np.any((A <= 0.0) & (w0 == 0.0)):
        bad = A[(A <= 0.0) & (w0 == 0.0)].flat[0]
        raise ValueError(
            f"v0*cos(theta) + u0*cos(phi) = {float(bad)!r} m/s with omega0_radps=0.0: nothing "
            "on the bat approaches the ball; allowed: > 0, or omega0_radps != 0"
        )
    m, M, J = ball.mass_kg, bat.mass_kg, bat.inertia_cm_kgm2
    cJ = J * (m + M) / (m * M)
    root = np.sqrt(A * A + w0 * w0 * cJ)
    with np.errstate(divide="ignore", invalid="ignore"):
        s = np.where(A > 0.0, w0 * cJ / (A + root), (root - A) / np.where(w0 == 0.0, 1.0, w0))
    return float(s) if s.ndim == 0 else s


def hittable_sweet_spot(
    bat: Bat, ball: Ball, v0_mps: float, u0_mps: float = 0.0, omega0_radps: float = 0.0
) -> float:
    """The best impact point the bat offers (m from the COM): the sweet spot, or the nearer end
    of the capsule's cylinder when the sweet spot lies beyond it (v1 is unimodal in s)."""
    s = sweet_spot(bat, ball, v0_mps, u0_mps, omega0_radps)
    return min(max(s, bat.s_min_m), bat.s_max_m)


@dataclass(frozen=True, kw_only=True)
class SweetRegion:
    """The range of sweet spots s* (m from the COM) over ranges of pitch and swing speeds."""

    s_min_m: float
    s_max_m: float

    @property
    def width_m(self) -> float:
        """Length of the region along the bat (m)."""
        return self.s_max_m - self.s_min_m


def sweet_region(
    bat: Bat,
    ball: Ball,
    *,
    v0_range_mps: tuple[float, float],
    u0_range_mps: tuple[float, float],
    omega0_range_radps: tuple[float, float],
) -> SweetRegion:
    """Where the sweet spot can lie when v0, u0 and omega0 range over the given intervals.

    s*(A, omega0) from ``sweet_spot`` is increasing in omega0 (ds*/domega0 = J k A (A + R) /
    (R (A + R)^2) > 0 with R = sqrt(A^2 + omega0^2 J k)) and monotone in A = v0 + u0 (sign of
    -omega0), so its extremes over the box of speeds lie on the box's corners.
    """
    corners = np.array(np.meshgrid(v0_range_mps, u0_range_mps, omega0_range_radps)).reshape(3, -1)
    s = sweet_spot(bat, ball, corners[0], corners[1], corners[2])
    return SweetRegion(s_min_m=float(np.min(s)), s_max_m=float(np.max(s)))


def sweet_zone(
    bat: Bat,
    ball: Ball,
    *,
    v0_mps: float,
    u0_mps: float = 0.0,
    omega0_radps: float = 0.0,
    e: float = 0.5,
    fraction: float = 0.99,
) -> SweetRegion:
    """The stretch of bat (s in m from the COM) where v1 >= fraction * max v1 for one swing.

    With c = (1 + e)/m, T = v_target + v0 and k = 1/m + 1/M, v1(s) = v_target reads
    (T/J) s^2 - c omega0 s + (T k - c A) = 0; its two roots bound the zone. Not clipped to the bat.
    """
    checks.in_range("fraction", fraction, 0.0, 1.0, lo_open=True)
    s_best = hittable_sweet_spot(bat, ball, v0_mps, u0_mps, omega0_radps)
    v_max = float(
        batted_ball_speed(
            bat, ball, s_best, v0_mps=v0_mps, u0_mps=u0_mps, omega0_radps=omega0_radps, e=e
        )
    )
    if not v_max > 0.0:
        raise ValueError(f"max v1 = {v_max!r} m/s; a sweet zone needs a positive batted speed")
    m, M, J = ball.mass_kg, bat.mass_kg, bat.inertia_cm_kgm2
    T = fraction * v_max + v0_mps
    c = (1.0 + e) / m
    a2, a1, a0 = T / J, -c * omega0_radps, T * (1.0 / m + 1.0 / M) - c * (v0_mps + u0_mps)
    disc = max(a1 * a1 - 4.0 * a2 * a0, 0.0)
    root = math.sqrt(disc)
    return SweetRegion(s_min_m=(-a1 - root) / (2 * a2), s_max_m=(-a1 + root) / (2 * a2))


def center_of_percussion(bat: Bat, pivot_from_knob_m: float = 0.1) -> float:
    """Centre of percussion for a pivot on the axis, as s (m from the COM): s_cop = J / (M d).

    d = x_cm - x_pivot is the pivot's distance from the COM (knob side positive). For a free bat
    it is the impact point that leaves the pivot point's velocity unchanged: dv_h = 0 in
    ``predict``. A pivot at the COM has no COP.
    """
    x_p = checks.in_range("pivot_from_knob_m", pivot_from_knob_m, 0.0, bat.length_m)
    d = bat.com_from_knob_m - x_p
    if d == 0.0:
        raise ValueError(
            f"pivot_from_knob_m={x_p!r} is at the COM, which has no centre of percussion; "
            f"allowed: 0 <= pivot_from_knob_m <= {bat.length_m:g}, != {bat.com_from_knob_m:g}"
        )
    return bat.inertia_cm_kgm2 / (bat.mass_kg * d)


@dataclass(frozen=True, kw_only=True)
class PaperOblique:
    """The paper's oblique-impact result: ball speed v1 (m/s), assumed to leave at angle theta1."""

    v1_mps: float
    theta1_rad: float


def predict_oblique_paper(
    case: ImpactCase, *, arm_m: float | None = None, small_angle: bool = False
) -> PaperOblique:
    """The paper's oblique impact (its eqs. 6.4.1-6.4.3), kept for the audit; it is wrong.

    The paper assumes the ball leaves along its incoming line (angle theta kept), so the ball's
    whole momentum change m(v0 + v1) acts along that line, with a tangential part whose moment arm
    is r (ball centre to bat axis). Solving its momentum, angular momentum and restitution
    equations gives
        v1 = -v0 + J M (1 + e)(u0 cos(phi) + v0 cos(theta) + omega0 s)
                   / [(J m + J M + m M s^2) cos(theta) + m M r s sin(theta)]
    and the 'minor angle' version drops the r s sin(theta) term. Frictionless contact can give
    no tangential impulse, so both the kept angle and the r term contradict its own premise;
    ``predict`` is the correct model.
    """
    bat, ball = case.bat, case.ball
    m, M, J, s = ball.mass_kg, bat.mass_kg, bat.inertia_cm_kgm2, case.s_m
    r = bat.radius_m + ball.radius_m if arm_m is None else checks.positive("arm_m", arm_m)
    th = case.theta_rad
    num = J * M * (1.0 + case.e) * (case.u0n_mps + case.v0n_mps + case.omega0_radps * s)
    den = (J * m + J * M + m * M * s * s) * math.cos(th)
    if not small_angle:
        den += m * M * r * s * math.sin(th)
    return PaperOblique(v1_mps=-case.v0_mps + num / den, theta1_rad=th)
