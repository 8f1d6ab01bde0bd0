"""The whole rigid-body impact episode: the single impulse, and what follows when it is not all.

``predict`` is one instantaneous impulse. That is the rigid-body answer only when the bodies
separate after it and do not meet again. At e = 0 (or e small) the ball stays on the turning
bat: frictionless rigid dynamics keep it in sustained contact, sliding along the barrel, until
the contact force vanishes or the ball leaves the cylinder; and a small bounce can be caught up
with by the turning bat. ``collide`` follows the two rigid bodies (ball: a point mass at the
centre of its sphere; bat: the capsule's cylinder, R = r_bat + r_ball from the axis) through:
- impulses (Newton's law with e at the contact point, frictionless);
- free flight in closed form, the next contact root-found on the gap to float precision;
- sustained contact, integrated with solve_ivp (rtol 1e-12). With d = p_ball - p_com,
  t = (cos th, sin th), n = (-sin th, cos th), s = d.t, the gap g = d.n - R obeys
      g'' = (a - A).n - 2 omega (v - V).t - alpha s - omega^2 d.n,
  and a normal force lambda n on the ball (-lambda n on the bat at the contact point, torque
  -lambda s) keeps g'' = 0 with
      lambda = [2 omega (v - V).t + omega^2 d.n] / (1/m + 1/M + s^2/J),
  until lambda falls to zero or s leaves [s_min, s_max].
The episode ends when the gap has grown past one ball radius (EPISODE_GAP_RADII) with no contact
to come, when the ball is off the cylinder's span, or after ``max_episode_s``. The adapters end
an engine's episode the same way (``free_flight``). Frame: the contact frame at the first contact
(x along the bat toward the barrel, y toward the ball), as in ``predict``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields

import numpy as np
from scipy import integrate, optimize

from . import checks
from .model import ImpactCase, Outcome

EPISODE_GAP_RADII = 1.0  #: the episode is over once the gap exceeds this many ball radii
MAX_EPISODE_S = 1.0  #: longest episode followed (s)
RTOL = 1e-12  #: solve_ivp tolerance in sustained contact
#: After an impulse, a bounce whose gap would peak below this is sustained contact (m): float
#: positions of ~1 m resolve ~1e-16 m.
APEX_M = 1e-12


@dataclass(frozen=True, kw_only=True)
class PlanarState:
    """Both bodies at one instant, in one fixed frame: the ball's centre and velocity, the bat's
    COM, velocity, angle (of its axis, toward the barrel) and angular velocity. The ball's side
    of the bat is the +normal side, normal = (-sin angle, cos angle). Units: m, m/s, rad, rad/s."""

    ball_x_m: float
    ball_y_m: float
    ball_vx_mps: float
    ball_vy_mps: float
    bat_x_m: float
    bat_y_m: float
    bat_vx_mps: float
    bat_vy_mps: float
    bat_angle_rad: float
    bat_omega_radps: float

    def array(self) -> np.ndarray:
        """The state as 10 floats in field order (no ``astuple``: it deep-copies, 20 us)."""
        return np.array([getattr(self, f) for f in _PLANAR_FIELDS], dtype=float)

    @classmethod
    def of(cls, y) -> PlanarState:
        return cls(**dict(zip((f.name for f in fields(cls)), map(float, y))))


#: ``PlanarState``'s field names, in order.
_PLANAR_FIELDS = tuple(f.name for f in fields(PlanarState))


@dataclass(frozen=True, kw_only=True)
class CollisionEpisode(Outcome):
    """The rigid-body outcome of the whole episode (fields of ``Outcome``, at its end) and how it
    went: ``impacts`` impulses, ``sustained_contact_s`` (s) of sliding contact and the largest
    contact force in it, ``peak_sustained_force_n`` (N; 0 without), ``episode_s`` (s) from the
    first contact to the end (to the last separation when ``separates_for_good`` proves it),
    ``ended``: 'separated', 'left_cylinder' or 'time_limit', and
    ``end_state`` (contact frame at the first contact)."""

    impacts: int
    sustained_contact_s: float
    peak_sustained_force_n: float
    episode_s: float
    ended: str
    end_state: PlanarState


# Internally the state is the array of PlanarState's fields, y = [px, py, vx, vy, Px, Py, Vx, Vy,
# theta, omega].


def _geometry(y):
    d = y[0:2] - y[4:6]
    t = np.array([math.cos(y[8]), math.sin(y[8])])
    n = np.array([-t[1], t[0]])
    return d, t, n


def _free(y, dt):
    out = y.copy()
    out[0:2] += y[2:4] * dt
    out[4:6] += y[6:8] * dt
    out[8] += y[9] * dt
    return out


def collide(case: ImpactCase, *, max_episode_s: float = MAX_EPISODE_S) -> CollisionEpisode:
    """The whole rigid impact episode for ``case``, followed for at most ``max_episode_s`` (s)
    (see the module docstring)."""
    checks.instance("case", case, ImpactCase)
    bat, ball = case.bat, case.ball
    m, M, J = ball.mass_kg, bat.mass_kg, bat.inertia_cm_kgm2
    reach = bat.radius_m + ball.radius_m
    y = first_touch(case)
    y0 = y.copy()
    t_now, impacts, sustained, ended, peak = 0.0, 0, 0.0, "time_limit", 0.0
    impulse_total = 0.0
    in_contact = True  # touching at t = 0
    while t_now < max_episode_s:
        d, tt, n = _geometry(y)
        s = float(d @ tt)
        if in_contact:
            v_rel = float((y[2:4] - y[6:8]) @ n) - y[9] * s
            if v_rel < 0.0:  # approaching: an impulse
                P = -(1.0 + case.e) * v_rel / (1 / m + 1 / M + s * s / J)
                y[2:4] += P * n / m
                y[6:8] -= P * n / M
                y[9] -= P * s / J
                impulse_total += P
                impacts += 1
                v_rel = float((y[2:4] - y[6:8]) @ n) - y[9] * s
            if _stays_on(y, v_rel):  # sustained contact
                y, dt, why, force = _slide(
                    y, m, M, J, reach, bat.s_min_m, bat.s_max_m, max_episode_s - t_now
                )
                t_now += dt
                sustained += dt
                peak = max(peak, force)
                if why == "left_cylinder":
                    ended = why
                    break
            in_contact = False
        # free flight to the next contact or the end of the episode
        if separates_for_good(
            PlanarState.of(y),
            reach_m=reach,
            ball_radius_m=ball.radius_m,
            t_max_s=max_episode_s - t_now,
        ):
            ended = "separated"
            break
        dt, why = _next_contact(
            y, reach, ball.radius_m, bat.s_min_m, bat.s_max_m, max_episode_s - t_now
        )
        y = _free(y, dt)
        t_now += dt
        if why == "contact":
            in_contact = True
            continue
        ended = why
        break
    return CollisionEpisode(
        **outcome_fields(case, y0, y),
        impacts=impacts,
        sustained_contact_s=sustained,
        peak_sustained_force_n=peak,
        episode_s=t_now,
        ended=ended,
        end_state=PlanarState.of(y),
    )


def first_touch(case: ImpactCase) -> np.ndarray:
    """Both bodies at the first touch, contact frame, as the array of PlanarState's fields."""
    reach = case.bat.radius_m + case.ball.radius_m
    return np.array(
        [
            case.s_m,
            reach,
            case.v0_mps * math.sin(case.theta_rad),
            -case.v0n_mps,
            0.0,
            0.0,
            case.u0_mps * math.sin(case.phi_rad),
            case.u0n_mps,
            0.0,
            case.omega0_radps,
        ]
    )


def outcome_fields(case: ImpactCase, y0: np.ndarray, y: np.ndarray) -> dict:
    """The fields of ``Outcome`` for an impact that took the bodies from ``y0`` to ``y``."""
    bat, ball = case.bat, case.ball
    m, M, J = ball.mass_kg, bat.mass_kg, bat.inertia_cm_kgm2
    V = case.u0n_mps + case.omega0_radps * case.s_m
    v1 = float(y[3])
    hands = case.hands_from_knob_m - bat.com_from_knob_m
    return dict(
        v1_mps=v1,
        u1_mps=float(y[7]),
        omega1_radps=float(y[9]),
        impulse_ns=m * (v1 + case.v0n_mps),
        q=(v1 - V) / (case.v0n_mps + V),
        closing_speed_mps=case.closing_speed_mps,
        hand_dv_mps=float(y[7] - case.u0n_mps) + float(y[9] - case.omega0_radps) * hands,
        ke_before_j=_energy(y0, m, M, J),
        ke_after_j=_energy(y, m, M, J),
        v1_t_mps=float(y[2]),
        u1_t_mps=float(y[6]),
    )


def free_flight(
    state: PlanarState,
    *,
    reach_m: float,
    ball_radius_m: float,
    s_min_m: float,
    s_max_m: float,
    t_max_s: float,
) -> tuple[float, str]:
    """Where free flight from ``state`` leads: (time, why), why 'contact' (the gap closes again
    at that time, to float precision), 'separated' (the gap has grown past EPISODE_GAP_RADII
    ball radii first), 'left_cylinder' (the ball is off the span [s_min, s_max] first) or
    'time_limit' (``t_max_s``). ``reach_m`` = r_bat + r_ball. How both ``collide`` and the
    engines decide that an episode is over."""
    return _next_contact(state.array(), reach_m, ball_radius_m, s_min_m, s_max_m, t_max_s)


def _stays_on(y, v_rel: float) -> bool:
    """After an impulse: does the ball stay on the bat? Only if the gap's free-flight
    curvature g'' pulls it back (g'' < 0) and the bounce would peak below APEX_M,
    v_rel^2 / (2 |g''|): the end of a Zeno sequence of ever smaller bounces, which float
    positions cannot resolve any more (e = 0 gives a zero bounce)."""
    curving = _curving(y)
    return curving < 0.0 and max(v_rel, 0.0) ** 2 / (-2.0 * curving) < APEX_M


def _curving(y) -> float:
    """g'' of the gap in free flight: -2 omega (v - V).t - omega^2 d.n."""
    d, tt, n = _geometry(y)
    return -2 * y[9] * float((y[2:4] - y[6:8]) @ tt) - y[9] ** 2 * float(d @ n)


def _energy(y, m, M, J) -> float:
    return 0.5 * (m * (y[2] ** 2 + y[3] ** 2) + M * (y[6] ** 2 + y[7] ** 2) + J * y[9] ** 2)


def _gap(y, t, reach):
    """Gap and axial coordinate of the ball after free flight for time(s) ``t``."""
    dx = y[0] - y[4] + (y[2] - y[6]) * t
    dy = y[1] - y[5] + (y[3] - y[7]) * t
    c, s = np.cos(y[8] + y[9] * t), np.sin(y[8] + y[9] * t)
    return dy * c - dx * s - reach, dx * c + dy * s


#: Samples of the gap evaluated at once while looking for the end of a free flight.
_CHUNK = 32
#: The shortest sample, as a fraction of the longest: a gap that opens at g' ~ 0 (a sample on
#: its minimum) asks for h ~ g'/|g''| ~ 0, which t + h no longer moves (a search that never
#: ended); a bounce that closes again within 1e-13 s opens the gap by less than a femtometre.
MIN_SAMPLE_FRACTION = 1e-9


def _sample_step(y, h_max: float) -> float:
    d, tt, n = _geometry(y)
    opening = float((y[2:4] - y[6:8]) @ n) - y[9] * float(d @ tt)
    curving = _curving(y)
    if opening > 0.0 and -curving * h_max > 0.5 * opening:  # (no overflow for tiny g'')
        return max(0.5 * opening / -curving, MIN_SAMPLE_FRACTION * h_max)
    return h_max


def separates_for_good(
    state: PlanarState, *, reach_m: float, ball_radius_m: float, t_max_s: float
) -> bool:
    """A sufficient condition, in a few float operations, for free flight from ``state`` to
    reach the episode's end gap (EPISODE_GAP_RADII ball radii) with no contact before it. In
    free flight g'' = -2 omega (v - V).t - omega^2 d.n, so |g''| <= C = 2 |omega| |v - V|
    + omega^2 (|d| + |v - V| T) up to time T, and g(t) >= g0 + g' t - C t^2 / 2; with
    T = 2 g_end / g' that bound is past g_end at T (and positive before) when g0 >= 0 and
    C T^2 / 2 <= g_end + g0, and it gets there within ``t_max_s`` if T <= t_max_s (a ball
    leaving at 1e-15 m/s is still on the bat at the end of the episode). Used by ``collide``
    and by the engines' episodes alike."""
    w = state.bat_omega_radps
    c, s = math.cos(state.bat_angle_rad), math.sin(state.bat_angle_rad)
    dx, dy = state.ball_x_m - state.bat_x_m, state.ball_y_m - state.bat_y_m
    rvx, rvy = state.ball_vx_mps - state.bat_vx_mps, state.ball_vy_mps - state.bat_vy_mps
    opening = rvy * c - rvx * s - w * (dx * c + dy * s)
    gap = dy * c - dx * s - reach_m
    if opening <= 0.0 or gap < 0.0:
        return False
    end = EPISODE_GAP_RADII * ball_radius_m
    horizon = 2.0 * end / opening
    if horizon > t_max_s:
        return False
    v_rel = math.hypot(rvx, rvy)
    bound = 2.0 * abs(w) * v_rel + w * w * (math.hypot(dx, dy) + v_rel * horizon)
    return 0.5 * bound * horizon * horizon <= end + gap


def _next_contact(y, reach, r_ball, s_min, s_max, t_max):
    """Time to the next contact (root of the gap, to float precision) or to the episode's end,
    and which: 'contact', 'separated', 'left_cylinder' or 'time_limit'. The gap is sampled
    every h, a contact is a sign change: h lets the bat turn 0.02 rad at most, is at most
    0.1 ms, and (chosen afresh every _CHUNK samples) is a quarter of the time 2 g'/|g''| in
    which the gap, opening at g' against its curvature g'' = -2 omega (v - V).t
    - omega^2 d.n, closes again (a slow bounce off the turning bat is caught up within a
    fraction of a millisecond)."""
    w = abs(y[9])
    h_max = 0.02 / w if w * 1e-4 > 0.02 else 1e-4
    t0, g0 = 0.0, float(_gap(y, 0.0, reach)[0])
    while t0 < t_max:
        h = _sample_step(_free(y, t0), h_max)
        t = np.minimum(t0 + h * np.arange(1, _CHUNK + 1), t_max)
        g, ax = _gap(y, t, reach)
        prev = np.concatenate(([g0], g[:-1]))
        off = ~((s_min <= ax) & (ax <= s_max))
        sep = g > EPISODE_GAP_RADII * r_ball
        hit = (prev > 0.0) & (g <= 0.0)
        sunk = (prev <= 0.0) & (g < -APEX_M)  # closed from a gap lost in float noise
        end = off | sep | hit | sunk | (t >= t_max)
        if end.any():
            k = int(np.argmax(end))
            if off[k]:
                return float(t[k]), "left_cylinder"
            if sep[k]:
                return float(t[k]), "separated"
            lo = t0 if k == 0 else float(t[k - 1])
            if sunk[k]:
                return lo, "contact"
            if hit[k]:
                root = optimize.brentq(
                    lambda x: float(_gap(y, x, reach)[0]),
                    lo,
                    float(t[k]),
                    xtol=1e-15,
                    rtol=4 * np.finfo(float).eps,
                )
                return root, "contact"
            return t_max, "time_limit"
        t0, g0 = float(t[-1]), float(g[-1])
    return t_max, "time_limit"


def _slide(y, m, M, J, reach, s_min, s_max, t_max):
    """Integrate the sustained frictionless contact until the force vanishes or the ball
    leaves the cylinder; returns (state, duration, 'released' or 'left_cylinder', the largest
    force at the solver's steps)."""

    def force(z):
        d, tt, n = _geometry(z)
        s = float(d @ tt)
        rel = z[2:4] - z[6:8]
        return (
            (2 * z[9] * float(rel @ tt) + z[9] ** 2 * float(d @ n)) / (1 / m + 1 / M + s * s / J),
            n,
            s,
        )

    def rhs(t, z):
        lam, n, s = force(z)
        a = lam * n / m
        A = -lam * n / M
        return [z[2], z[3], a[0], a[1], z[6], z[7], A[0], A[1], z[9], -lam * s / J]

    def released(t, z):
        return force(z)[0]

    def off_end(t, z):
        s = force(z)[2]
        return min(s - s_min, s_max - s)

    released.terminal, released.direction = True, -1
    off_end.terminal, off_end.direction = True, -1
    if force(y)[0] <= 0.0:  # nothing holds the ball on: it leaves at once
        return y, 0.0, "released", 0.0
    scale = np.abs(y).max() + 1.0
    sol = integrate.solve_ivp(
        rhs,
        (0.0, t_max),
        y,
        method="DOP853",
        rtol=RTOL,
        atol=RTOL * scale * 1e-3,
        events=(released, off_end),
    )
    z = sol.y[:, -1]
    why = "left_cylinder" if len(sol.t_events[1]) else "released"
    peak = max(force(sol.y[:, i])[0] for i in range(sol.y.shape[1]))
    return z, float(sol.t[-1]), why, max(peak, 0.0)
