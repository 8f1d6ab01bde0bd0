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
The episode ends when the gap has grown past one ball radius (EPISODE_GAP_RADII) or the ball is
off the cylinder's span, or after MAX_EPISODE_S. Frame: the contact frame at the first contact
(x along the bat toward the barrel, y toward the ball), as in ``predict``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy import integrate, optimize

from .model import ImpactCase, Outcome

EPISODE_GAP_RADII = 1.0   #: the episode is over once the gap exceeds this many ball radii
MAX_EPISODE_S = 1.0       #: longest episode followed (s)
RTOL = 1e-12              #: solve_ivp tolerance in sustained contact
#: After an impulse, a separation slower than this fraction of the first closing speed is
#: treated as sustained contact (a Zeno sequence of ever smaller bounces).
ZENO_REL = 1e-9


@dataclass(frozen=True, kw_only=True)
class CollisionEpisode(Outcome):
    """The rigid-body outcome of the whole episode (fields of ``Outcome``, at its end) and how it
    went: ``impacts`` impulses, ``sustained_contact_s`` (s) of sliding contact, ``episode_s``
    (s) from the first contact to the end, ``ended``: 'separated', 'left_cylinder' or
    'time_limit'."""

    impacts: int
    sustained_contact_s: float
    episode_s: float
    ended: str


# The state of both bodies, contact frame at t = 0 (m, m/s, rad, rad/s):
# y = [px, py, vx, vy, Px, Py, Vx, Vy, theta, omega] (ball centre and velocity, bat COM and
# velocity, bat angle and angular velocity).


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


def collide(case: ImpactCase) -> CollisionEpisode:
    """The whole rigid impact episode for ``case`` (see the module docstring)."""
    bat, ball = case.bat, case.ball
    m, M, J = ball.mass_kg, bat.mass_kg, bat.inertia_cm_kgm2
    reach = bat.radius_m + ball.radius_m
    y = np.array([case.s_m, reach,
                  case.v0_mps * math.sin(case.theta_rad), -case.v0n_mps,
                  0.0, 0.0, case.u0_mps * math.sin(case.phi_rad), case.u0n_mps,
                  0.0, case.omega0_radps])
    v_c0 = case.closing_speed_mps
    ke0 = _energy(y, m, M, J)
    t_now, impacts, sustained, ended = 0.0, 0, 0.0, "time_limit"
    impulse_total = 0.0
    in_contact = True  # touching at t = 0
    while t_now < MAX_EPISODE_S:
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
            if v_rel <= ZENO_REL * v_c0:  # stays on the bat: sustained contact
                y, dt, why = _slide(y, m, M, J, reach, bat.s_min_m, bat.s_max_m,
                                    MAX_EPISODE_S - t_now)
                t_now += dt
                sustained += dt
                if why == "left_cylinder":
                    ended = why
                    break
            in_contact = False
        # free flight to the next contact or the end of the episode
        dt, why = _next_contact(y, reach, ball.radius_m, bat.s_min_m, bat.s_max_m,
                                MAX_EPISODE_S - t_now)
        y = _free(y, dt)
        t_now += dt
        if why == "contact":
            in_contact = True
            continue
        ended = why
        break
    V = case.u0n_mps + case.omega0_radps * case.s_m
    v1 = float(y[3])
    hands = case.hands_from_knob_m - bat.com_from_knob_m
    return CollisionEpisode(
        v1_mps=v1, u1_mps=float(y[7]), omega1_radps=float(y[9]),
        impulse_ns=m * (v1 + case.v0n_mps), q=(v1 - V) / (case.v0n_mps + V),
        closing_speed_mps=v_c0,
        hand_dv_mps=float(y[7] - case.u0n_mps) + float(y[9] - case.omega0_radps) * hands,
        ke_before_j=ke0, ke_after_j=_energy(y, m, M, J), v1_t_mps=float(y[2]),
        u1_t_mps=float(y[6]), impacts=impacts, sustained_contact_s=sustained,
        episode_s=t_now, ended=ended)


def _energy(y, m, M, J) -> float:
    return 0.5 * (m * (y[2] ** 2 + y[3] ** 2) + M * (y[6] ** 2 + y[7] ** 2) + J * y[9] ** 2)


def _gap(y, dt, reach):
    z = _free(y, dt)
    d, tt, n = _geometry(z)
    return float(d @ n) - reach, float(d @ tt)


def _next_contact(y, reach, r_ball, s_min, s_max, t_max):
    """Time to the next contact (root of the gap, to float precision) or to the episode's end,
    and which: 'contact', 'separated', 'left_cylinder' or 'time_limit'."""
    w = abs(y[9])
    h = min(1e-4, 0.02 / w) if w > 0 else 1e-4
    t0, g0 = 0.0, _gap(y, 0.0, reach)[0]
    while t0 < t_max:
        t1 = min(t0 + h, t_max)
        g1, s1 = _gap(y, t1, reach)
        if not s_min <= s1 <= s_max:
            return t1, "left_cylinder"
        if g1 > EPISODE_GAP_RADII * r_ball:
            return t1, "separated"
        if g0 > 0.0 and g1 <= 0.0:
            root = optimize.brentq(lambda t: _gap(y, t, reach)[0], t0, t1, xtol=1e-15,
                                   rtol=4 * np.finfo(float).eps)
            return root, "contact"
        t0, g0 = t1, g1
    return t_max, "time_limit"


def _slide(y, m, M, J, reach, s_min, s_max, t_max):
    """Integrate the sustained frictionless contact until the force vanishes or the ball
    leaves the cylinder; returns (state, duration, 'released' or 'left_cylinder')."""
    def force(z):
        d, tt, n = _geometry(z)
        s = float(d @ tt)
        rel = z[2:4] - z[6:8]
        return (2 * z[9] * float(rel @ tt) + z[9] ** 2 * float(d @ n)) \
            / (1 / m + 1 / M + s * s / J), n, s

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
        return y, 0.0, "released"
    scale = np.abs(y).max() + 1.0
    sol = integrate.solve_ivp(rhs, (0.0, t_max), y, method="DOP853", rtol=RTOL,
                              atol=RTOL * scale * 1e-3, events=(released, off_end))
    z = sol.y[:, -1]
    why = "left_cylinder" if len(sol.t_events[1]) else "released"
    return z, float(sol.t[-1]), why
