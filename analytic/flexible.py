"""A ball's impact on the flexible bat: the beam's modes driven through a compliant contact.

The bat moves as a rigid body (planar, turning, as ``analytic.compliant`` has it) and bends
in its free-free modes (``analytic.beam``) about that motion, the floating frame in which the
modes, being mass-orthogonal to the rigid ones, carry neither momentum nor angular momentum
(the mean-axis frame). Along its normal n the bat's surface at the contact is displaced by
w(x) = sum_k phi_k(x) q_k, so the overlap is the rigid one plus w, and the contact force f
(a normal force law: the ball's Hertz law) pushes the ball along n, the rigid bat along -n
and each mode with -f phi_k(x): q_k'' + omega_k^2 q_k = -f phi_k(x) (mass-normalised modes,
no damping: wood's loss is slow against a millisecond). Integrated with DOP853 through the
contact, then through free flight for one period of the lowest mode, where the vibrating
barrel may meet the ball again (then once more through the contact). A. M. Nathan, "Dynamics
of the baseball-bat collision", Am. J. Phys. 68, 979 (2000), solved the same problem with a
finite-element bat at rest; the rigid motion and the turn of the bat are added here.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy import integrate, interpolate, optimize

from . import checks
from .beam import Beam
from .collide import _geometry, first_touch, outcome_fields
from .compliant import (
    CompliantOutcome,
    ContactLaw,
    ImpactLaw,
    force_of,
    law_for_impact,
    peak_rate,
    release_of,
)
from .model import ImpactCase

#: Bending modes kept by default: 24 reach 15 kHz on the R161 (Timoshenko). The local
#: compliance under the ball converges slowly in the mode count (a Timoshenko beam's high
#: modes rise linearly in k): 24 against 48 modes moves v1 by about 0.05 m/s (tests).
MODES = 24
#: solve_ivp tolerance (as ``analytic.compliant``).
RTOL = 1e-11
#: Free-flight search for a second touch: this many periods of the lowest mode.
RECONTACT_PERIODS = 1.0
#: Touches followed at most (a vibrating barrel may meet the ball once or twice more).
MAX_TOUCHES = 5


@dataclass(frozen=True, kw_only=True)
class FlexOutcome(CompliantOutcome):
    """A compliant outcome (its rigid-motion fields) plus the bat's bending: ``mode_energy_j``
    (J, per mode, at the end), ``vibration_j`` (J, their sum), ``energy_after_j`` (J, all
    kinetic plus bending; equals ``ke_before_j`` less what the law dissipated) and
    ``touches`` (separate contacts)."""

    mode_energy_j: tuple[float, ...]
    vibration_j: float
    energy_after_j: float
    touches: int


def predict(
    case: ImpactCase,
    beam: Beam,
    law: ContactLaw | ImpactLaw,
    *,
    modes: int = MODES,
    loss_factor: float = 0.0,
    patch_m: float = 0.0,
) -> FlexOutcome:
    """The impact of ``case`` on ``beam``'s flexible bat under the normal force ``law`` (an
    ``ImpactLaw`` resolved at the first touch's closing speed, kept through re-touches; a
    hysteretic law's memory starts afresh at each touch). The case's bat must hold the beam's
    mass properties (``beam.rigid_bat``); its capsule radius is the contact surface's, as in
    the rigid theory. ``loss_factor`` eta (1) damps each mode as a viscous ratio eta/2 at its
    own frequency (the wood's loss, 0 by default); ``patch_m`` a (m) spreads the force evenly
    over s - a..s + a along the axis (a point, 0 by default), so the modes see each shape's
    mean over the patch. Frame and fields as ``analytic.compliant.predict``."""
    checks.in_range("loss_factor", loss_factor, 0.0, 1.0)
    checks.in_range("patch_m", patch_m, 0.0, 0.1 * beam.profile.length_m)
    rigid = beam.rigid
    for key, value in rigid.items():
        if not math.isclose(getattr(case.bat, key), value, rel_tol=1e-12):
            raise ValueError(
                f"bat.{key} = {getattr(case.bat, key)!r}: must be the beam's "
                f"{value!r} (use beam.rigid_bat)"
            )
    shapes = beam.modes(modes)
    problem = _Problem(case, law, shapes, patch_m=patch_m)
    problem.damping = loss_factor * np.sqrt(problem.w2)  # 2 zeta omega, zeta = eta / 2
    y = np.concatenate([first_touch(case), np.zeros(2 * modes + 1)])
    problem.law = law_for_impact(law, problem.state(y)[1])  # the overlap's rate: v_c
    y0, t, touches, peaks = y.copy(), 0.0, 0, []
    while touches < MAX_TOUCHES:
        sol = problem.contact(y)
        touches += 1
        peaks.append(problem.peaks(sol.y))
        t += float(sol.t[-1])
        y = sol.y[:, -1]
        again = problem.flight(y)
        if again is None:
            break
        t += again[0]
        y = again[1]
        y[-1] = 0.0  # the ball has recovered between touches
    modal = problem.mode_energies(y)
    return FlexOutcome(
        **outcome_fields(case, y0[:10], y[:10]),
        contact_duration_s=t,
        peak_force_n=max(p[0] for p in peaks),
        peak_penetration_m=max(p[1] for p in peaks),
        bat_turn_rad=float(y[8]),
        mode_energy_j=tuple(modal),
        vibration_j=float(sum(modal)),
        energy_after_j=problem.energy(y),
        touches=touches,
    )


class _Problem:
    """The equations of motion and the contact's geometry."""

    def __init__(
        self, case: ImpactCase, law: ContactLaw | ImpactLaw, shapes, *, patch_m: float = 0.0
    ) -> None:
        bat, ball = case.bat, case.ball
        self.m, self.M, self.J = ball.mass_kg, bat.mass_kg, bat.inertia_cm_kgm2
        self.reach = bat.radius_m + ball.radius_m
        self.x_cm = bat.com_from_knob_m
        self.law = law
        self.w2 = (2 * math.pi * shapes.frequencies_hz) ** 2
        self.k = len(self.w2)
        nodes = shapes.nodes_m
        point = (
            interpolate.CubicHermiteSpline(nodes, shapes.shapes.T, shapes.slopes.T)
            if shapes.hermite
            else interpolate.CubicSpline(nodes, shapes.shapes.T)
        )
        self.phi = point if patch_m == 0.0 else _patch_mean(point, patch_m)
        self.dphi = self.phi.derivative()
        self.damping = np.zeros(len(self.w2))
        self.phi_max = np.abs(shapes.shapes).max(axis=1)
        self.period = 2 * math.pi / math.sqrt(self.w2[0])
        #: DOP853 oscillates stably to h omega ~ 1 (measured: 1/omega_max blew up a stiff bat)
        self.max_step = 0.5 / math.sqrt(self.w2[-1])

    def state(self, z):
        """Overlap x = reach - d.n + w(s), its rate, the mode shapes there, the slope w'(s),
        s and the frame; w(s) = sum_k phi_k q_k, s = d.t the contact point's arm."""
        d, tt, n = _geometry(z)
        s, h = float(d @ tt), float(d @ n)
        x_knob = s + self.x_cm
        phi = self.phi(x_knob)
        q, qd = z[10 : 10 + self.k], z[10 + self.k : 10 + 2 * self.k]
        slope = float(self.dphi(x_knob) @ q)
        rel = z[2:4] - z[6:8]
        x = self.reach - h + float(phi @ q)
        # x' = dx/dz . z': the same gradient the forces are made of (energy conservation)
        rate = -float(rel @ n) + z[9] * s + slope * (float(rel @ tt) + z[9] * h) + float(phi @ qd)
        m_eff = 1.0 / (1 / self.m + 1 / self.M + s * s / self.J)
        return x, rate, m_eff, phi, (s, h, slope), (tt, n)

    def force(self, z, t=1.0):
        x, rate, m_eff, phi, arms, frame = self.state(z)
        touching = x > 0.0 or t == 0.0
        f = max(force_of(self.law, max(x, 0.0), rate, m_eff, z[-1]), 0.0) if touching else 0.0
        return f, x, phi, arms, frame, rate

    def rhs(self, t, z, free: bool = False):
        """The force is -f grad x: on the ball f (n - w' t), on the bat the opposite with the
        torque -f (s + w' h), on mode k -f phi_k."""
        f, x, phi, (s, h, slope), (tt, n), rate = self.force(z, t)
        f = 0.0 if free else f
        k = self.k
        q, qd = z[10 : 10 + k], z[10 + k : 10 + 2 * k]
        push = f * (n - slope * tt)
        return np.concatenate(
            [
                z[2:4],
                push / self.m,
                z[6:8],
                -push / self.M,
                [z[9], -f * (s + slope * h) / self.J],
                qd,
                -self.w2 * q - self.damping * qd - f * phi,
                [peak_rate(x, rate, z[-1])],
            ]
        )

    def atol(self, y) -> np.ndarray:
        """Absolute tolerances: the rigid coordinates' as ``analytic.compliant``'s; a mode's
        such that phi_k q_k, the surface's displacement, is held to the same (a stiff mode's
        coordinate is tiny, and a tolerance in its own units would ask for steps far below
        its period)."""
        base = RTOL * 1e-3 * (np.abs(y[:10]).max() + 1.0)
        per_mode = base / self.phi_max
        return np.concatenate([np.full(10, base), per_mode, per_mode * np.sqrt(self.w2), [base]])

    def contact(self, y):
        def released(t, z):
            if t == 0.0:
                return 1.0
            x, rate, m_eff, *_ = self.state(z)
            return release_of(self.law, x, rate, m_eff, z[-1])

        released.terminal, released.direction = True, -1
        return integrate.solve_ivp(
            self.rhs,
            (0.0, 1.0),
            y,
            method="DOP853",
            rtol=RTOL,
            atol=self.atol(y),
            events=released,
            max_step=self.max_step,
        )

    def free(self, y, t):
        """The states at times ``t`` (array) of free motion from ``y``: uniform rigid motion,
        harmonic modes. Shape (len(t), size)."""
        t = np.asarray(t, dtype=float)[:, None]
        k, w = self.k, np.sqrt(self.w2)
        q, qd = y[10 : 10 + k], y[10 + k : 10 + 2 * k]
        z = np.repeat(y[None, :], len(t), axis=0)
        z[:, 0:2] += y[2:4] * t
        z[:, 4:6] += y[6:8] * t
        z[:, 8] += y[9] * t[:, 0]
        cos, sin = np.cos(w * t), np.sin(w * t)
        z[:, 10 : 10 + k] = q * cos + qd / w * sin
        z[:, 10 + k : 10 + 2 * k] = qd * cos - q * w * sin
        return z

    def gaps(self, zs) -> np.ndarray:
        """The overlap x of each state (rows of ``zs``), vectorised."""
        d = zs[:, 0:2] - zs[:, 4:6]
        tt = np.column_stack([np.cos(zs[:, 8]), np.sin(zs[:, 8])])
        n = np.column_stack([-tt[:, 1], tt[:, 0]])
        s = np.sum(d * tt, axis=1)
        phi = self.phi(s + self.x_cm)
        return self.reach - np.sum(d * n, axis=1) + np.sum(phi * zs[:, 10 : 10 + self.k], axis=1)

    def flight(self, y):
        """(time, state) of the next touch within RECONTACT_PERIODS of the lowest mode, or
        None: the overlap sampled 16 times per period of the highest mode, its first rise
        through 0 (after the contact has opened) refined by brentq."""
        h = self.max_step * 2 * math.pi / 16
        times = np.arange(1, int(RECONTACT_PERIODS * self.period / h) + 2) * h
        x = self.gaps(self.free(y, times))
        opened = np.flatnonzero(x < 0.0)
        if not len(opened):
            return None
        rises = np.flatnonzero((x[:-1] < 0.0) & (x[1:] >= 0.0))
        rises = rises[rises >= opened[0]]
        if not len(rises):
            return None
        i = rises[0]
        t = optimize.brentq(
            lambda t: float(self.gaps(self.free(y, [t]))[0]), times[i], times[i + 1], xtol=1e-15
        )
        return t, self.free(y, [t])[0]

    def peaks(self, ys) -> tuple[float, float]:
        pairs = [self.force(ys[:, i])[:2] for i in range(ys.shape[1])]
        return max(f for f, _ in pairs), max(x for _, x in pairs)

    def mode_energies(self, z) -> np.ndarray:
        q, qd = z[10 : 10 + self.k], z[10 + self.k : 10 + 2 * self.k]
        return 0.5 * (qd * qd + self.w2 * q * q)

    def energy(self, z) -> float:
        """Kinetic energy of both bodies plus the bending's."""
        ke = (
            0.5 * self.m * float(z[2:4] @ z[2:4])
            + 0.5 * self.M * float(z[6:8] @ z[6:8])
            + 0.5 * self.J * z[9] ** 2
        )
        return ke + float(self.mode_energies(z).sum())


def _patch_mean(shape: interpolate.PPoly, half_m: float) -> interpolate.PPoly:
    """The mean of each shape over x - a..x + a (a = ``half_m``), as a spline in x: from the
    shapes' antiderivative, sampled on a grid fine against a (8 points per a) and clamped to
    the bat at its ends."""
    whole = shape.antiderivative()
    lo, hi = float(shape.x[0]), float(shape.x[-1])
    x = np.linspace(lo, hi, int(math.ceil(8 * (hi - lo) / half_m)) + 1)
    a, b = np.clip(x - half_m, lo, hi), np.clip(x + half_m, lo, hi)
    return interpolate.CubicSpline(x, ((whole(b) - whole(a)).T / (b - a)).T)
