"""A ball's impact on a segmented bat (``analytic.chain``), solved exactly for the linear chain.

The ball moves along y (the bat's transverse direction), hitting the axis point ``x_m``; the
bat starts straight, moving as a rigid body with its COM at ``u0_mps`` toward the ball and
turning at ``omega0_radps`` (small angles: the chain is linear). Between contacts the chain
moves freely, z' = A z with z = (q, q'), A = [[0, I], [-M^-1 K, -M^-1 C]], stepped exactly by
exp(A h). Two contacts, one per kind of engine:

- ``impulse_reference``: Newton's restitution at each touch, P = -(1 + e) v_rel / w with
  w = 1/m + b M^-1 b^T, b the contact point's row; the springs pass no impulse, so a touch
  sees the chain with its joints free. A chain bounces back into the ball: every contact
  until none can come is followed;
- ``compliant_reference``: a continuous force law (``analytic.compliant``), m_eff = 1/w,
  integrated with DOP853 until it releases; then free flight, and again if the bodies meet.

An episode ends when no contact can come: the gap of the rigid part, less the most the
vibration can bend the contact point (sqrt(2 E_vib b K+ b^T), E_vib the energy in the
bending modes, which springs and dampers cannot raise), is open and opening.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np
from scipy import integrate, linalg, optimize

from . import checks
from .chain import Chain
from .compliant import ContactLaw, Hysteretic, ImpactLaw, law_for_impact
from .model import Ball

#: The free-flight search samples the gap this many times per period of the chain's highest
#: mode: a re-contact shorter than a sixteenth of a period could slip between samples.
SAMPLES_PER_PERIOD = 16
#: Contacts after which an episode is called 'zeno' (ever shorter bounces, no end in sight).
MAX_CONTACTS = 500
#: solve_ivp tolerance of the compliant contact (as ``analytic.compliant``).
RTOL = 1e-11


@dataclass(frozen=True, kw_only=True)
class ChainImpact:
    """A ball of ``ball`` at ``v0_mps`` (m/s) toward the chain's axis point ``x_m`` (m from
    the knob), the chain's COM at ``u0_mps`` (m/s) toward the ball, spinning at
    ``omega0_radps`` (rad/s; positive: the barrel end toward the ball); restitution ``e``
    (used by ``impulse_reference`` only)."""

    chain: Chain
    ball: Ball
    x_m: float
    v0_mps: float
    e: float
    u0_mps: float = 0.0
    omega0_radps: float = 0.0

    def __post_init__(self) -> None:
        bat = self.chain.bat
        checks.in_range("x_m", self.x_m, bat.radius_m, bat.length_m - bat.radius_m)
        checks.positive("v0_mps", self.v0_mps)
        checks.in_range("e", self.e, 0.0, 1.0, lo_open=True)
        checks.finite("u0_mps", self.u0_mps)
        checks.finite("omega0_radps", self.omega0_radps)

    @property
    def s_m(self) -> float:
        """The impact point from the COM (m), as the rigid theory has it."""
        return self.x_m - self.chain.bat.com_from_knob_m

    def initial_velocities(self) -> np.ndarray:
        """q' of the straight bat moving rigidly: y0' = u0 - omega0 x_cm, theta_i' = omega0."""
        qd = np.full(self.chain.segments + 1, self.omega0_radps)
        qd[0] = self.u0_mps - self.omega0_radps * self.chain.bat.com_from_knob_m
        return qd


@dataclass(frozen=True, kw_only=True)
class ChainOutcome:
    """After the episode: the ball's ``v1_mps`` (m/s, away from the bat), the bat's rigid
    motion ``u1_mps`` (COM, m/s) and ``omega1_radps`` (rad/s), ``vibration_j`` (J, the energy
    left in the bending modes), ``ke_before_j``/``energy_after_j`` (J, everything: kinetic,
    springs), ``contacts`` (separate touches), ``contact_s`` (s, first touch to last release),
    ``ended`` ('separated', 'zeno' or 'time_limit') and ``peak_overlap_m`` (m, the deepest
    overlap of a compliant contact; 0 for impulses) and ``peak_turn_rad`` (rad, how far the
    struck segment turned during it: the linear chain's geometric error grows with it)."""

    v1_mps: float
    u1_mps: float
    omega1_radps: float
    vibration_j: float
    ke_before_j: float
    energy_after_j: float
    contacts: int
    contact_s: float
    ended: str
    peak_overlap_m: float = 0.0
    peak_turn_rad: float = 0.0


class _Free:
    """The chain's exact free motion and the bounds the episode's end is judged by."""

    def __init__(self, impact: ChainImpact) -> None:
        chain = impact.chain
        M, K, C = chain.matrices
        n = chain.segments + 1
        self.M, self.K, self.n = M, K, n
        self.minv = linalg.inv(M)
        self.A = np.block([[np.zeros((n, n)), np.eye(n)], [-self.minv @ K, -self.minv @ C]])
        omega, vec = chain.modes
        self.rigid, self.bending, self.omega = vec[:, omega == 0], vec[:, omega > 0], omega
        self.modal, self.undamped = vec, not np.any(C)
        self.h = 2 * np.pi / omega.max() / SAMPLES_PER_PERIOD
        self.step = linalg.expm(self.A * self.h)
        self.row = chain.point_row(impact.x_m)
        flex = self.bending / omega[omega > 0]
        self.reach_gain = float(np.sqrt(np.sum((self.row @ flex) ** 2)))

    def advance(self, z: np.ndarray, t: float) -> np.ndarray:
        """The state after a free flight of ``t``: modal closed form without dampers."""
        if self.undamped:
            eta = self.modal.T @ self.M @ z[: self.n]
            etad = self.modal.T @ self.M @ z[self.n :]
            w = self.omega
            safe = np.where(w > 0.0, w, 1.0)
            cos, sin = np.cos(w * t), np.sin(w * t)
            pos = np.where(w > 0.0, eta * cos + etad / safe * sin, eta + etad * t)
            vel = np.where(w > 0.0, etad * cos - eta * w * sin, etad)
            return np.concatenate([self.modal @ pos, self.modal @ vel])
        return linalg.expm(self.A * t) @ z

    def vibration_j(self, z: np.ndarray) -> float:
        """Energy in the bending modes: the M-projection off the rigid modes."""
        q, qd = z[: self.n], z[self.n :]
        qd_b = self.bending @ (self.bending.T @ self.M @ qd)
        return float(0.5 * qd_b @ self.M @ qd_b + 0.5 * q @ self.K @ q)

    def rigid_part(self, z: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        P = self.rigid @ self.rigid.T @ self.M
        return P @ z[: self.n], P @ z[self.n :]


def _gap(free: _Free, z, ball, reach):
    return ball[0] - free.row @ z[: free.n] - reach


def _next_contact(free: _Free, z, ball, reach, t_left):
    """Time to the next touch (float), or the reason none comes ('separated', 'time_limit').
    Between touches the rigid part moves uniformly and the bending energy cannot grow."""
    q_r, qd_r = free.rigid_part(z)
    bound = free.reach_gain * np.sqrt(2.0 * free.vibration_j(z))
    opening = ball[1] - free.row @ qd_r
    t, zz = 0.0, z.copy()
    g_prev = _gap(free, zz, ball, reach)
    while t < t_left:
        rigid_gap = ball[0] + ball[1] * t - free.row @ (q_r + qd_r * t) - reach
        if rigid_gap > bound and opening >= 0.0:
            return "separated"
        z_next = free.step @ zz
        g = ball[0] + ball[1] * (t + free.h) - free.row @ z_next[: free.n] - reach
        if g < 0.0:

            def gap_at(tau, z0=zz, t0=t):
                zt = free.advance(z0, tau)
                return ball[0] + ball[1] * (t0 + tau) - free.row @ zt[: free.n] - reach

            lo = 0.0
            if g_prev <= 0.0:  # just after a touch: start where the gap has opened
                taus = free.h * np.arange(1, 64) / 64
                opened = [tau for tau in taus if gap_at(tau) > 0.0]
                if not opened:
                    return t + free.h / 64
                lo = opened[0]
            return t + optimize.brentq(gap_at, lo, free.h, xtol=1e-15)
        t, zz, g_prev = t + free.h, z_next, g
    return "time_limit"


def _episode(impact: ChainImpact, touch, max_s: float) -> ChainOutcome:
    """Free flights between touches; ``touch(z, ball)`` resolves one (returns z, ball and
    how long it lasted)."""
    chain, m = impact.chain, impact.ball.mass_kg
    free = _Free(impact)
    reach = chain.bat.radius_m + impact.ball.radius_m
    z = np.concatenate([np.zeros(free.n), impact.initial_velocities()])
    ball = np.array([reach, -impact.v0_mps])

    def energy(z, b):
        return float(
            0.5 * m * b[1] ** 2
            + 0.5 * z[free.n :] @ free.M @ z[free.n :]
            + 0.5 * z[: free.n] @ free.K @ z[: free.n]
        )

    before = energy(z, ball)
    t, contacts, last_release, ended = 0.0, 0, 0.0, "time_limit"
    while t < max_s:
        z, ball, lasted = touch(free, z, ball)
        contacts += lasted is not None
        t += lasted or 0.0
        last_release = t
        if contacts >= MAX_CONTACTS:
            ended = "zeno"
            break
        nxt = _next_contact(free, z, ball, reach, max_s - t)
        if isinstance(nxt, str):
            ended = nxt
            break
        z, ball, t = free.advance(z, nxt), ball + np.array([ball[1] * nxt, 0.0]), t + nxt
    q_r, qd_r = free.rigid_part(z)
    x_cm = chain.bat.com_from_knob_m
    omega1 = float(qd_r[1])
    return ChainOutcome(
        v1_mps=float(ball[1]),
        u1_mps=float(qd_r[0] + omega1 * x_cm),
        omega1_radps=omega1,
        vibration_j=free.vibration_j(z),
        ke_before_j=before,
        energy_after_j=energy(z, ball),
        contacts=contacts,
        contact_s=last_release,
        ended=ended,
    )


def impulse_reference(impact: ChainImpact, *, max_s: float = 0.02) -> ChainOutcome:
    """The episode under Newton's restitution at every touch (rigid-contact engines)."""
    m = impact.ball.mass_kg

    def touch(free, z, ball):
        v_rel = ball[1] - free.row @ z[free.n :]
        if v_rel >= 0.0:
            return z, ball, None
        w = 1.0 / m + free.row @ free.minv @ free.row
        p = -(1.0 + impact.e) * v_rel / w
        z = z.copy()
        z[free.n :] -= free.minv @ free.row * p
        return z, ball + np.array([0.0, p / m]), 0.0

    return _episode(impact, touch, max_s)


def compliant_reference(
    impact: ChainImpact, law: ContactLaw | ImpactLaw, *, max_s: float = 0.02
) -> ChainOutcome:
    """The episode under a continuous force ``law`` (``analytic.compliant``: soft engines; an
    ``ImpactLaw`` resolved at the first touch's closing speed v0 + b q', kept for re-touches)."""
    m = impact.ball.mass_kg
    row = impact.chain.point_row(impact.x_m)
    law = law_for_impact(law, impact.v0_mps + float(row @ impact.initial_velocities()))
    if isinstance(law, Hysteretic):
        raise ValueError(
            "law: a hysteretic law needs its deepest overlap carried, which the "
            "chain's integration does not; allowed: a rate-dependent law"
        )
    reach = impact.chain.bat.radius_m + impact.ball.radius_m
    peaks: list[float] = []
    turns: list[float] = []
    hit = impact.chain.segment_of(impact.x_m) + 1  # the struck segment's angle in q

    def touch(free, z, ball):
        n = free.n
        m_eff = 1.0 / (1.0 / m + free.row @ free.minv @ free.row)

        def contact(y):
            x = reach - (y[-2] - free.row @ y[:n])
            rate = -(y[-1] - free.row @ y[n : 2 * n])
            return x, rate

        def rhs(t, y):
            x, rate = contact(y)
            f = max(law.force_n(x, rate, m_eff), 0.0) if x > 0.0 or t == 0.0 else 0.0
            dz = free.A @ y[: 2 * n]
            dz[n:] -= free.minv @ free.row * f
            return np.concatenate([dz, [y[-1], f / m]])

        def released(t, y):
            return 1.0 if t == 0.0 else law.release_value(*contact(y), m_eff)

        released.terminal, released.direction = True, -1
        y0 = np.concatenate([z, ball])
        sol = integrate.solve_ivp(
            rhs,
            (0.0, 1.0),
            y0,
            method="DOP853",
            rtol=RTOL,
            atol=RTOL * 1e-3 * (np.abs(y0).max() + 1.0),
            events=released,
        )
        y = sol.y[:, -1]
        peaks.append(max(contact(sol.y[:, i])[0] for i in range(sol.y.shape[1])))
        turn = sol.y[hit, :] - sol.y[hit, 0]
        turns.append(float(np.abs(turn).max()))
        return y[: 2 * n], y[2 * n :], float(sol.t[-1])

    return replace(
        _episode(impact, touch, max_s),
        peak_overlap_m=max(peaks, default=0.0),
        peak_turn_rad=max(turns, default=0.0),
    )
