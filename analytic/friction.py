"""Rigid impact of two bodies with Coulomb friction at one point: Routh's method, in 3D.

Stronge, Impact Mechanics (2000), ch. 5 (3D: sec. 5.2-5.4): the relative velocity of the
contact points v (B's point subtracted from A's) changes with the impulse P on A (-P on B) as
dv = K dP, K = (1/m_A + 1/m_B) 1 - [r_A] I_A^-1 [r_A] - [r_B] I_B^-1 [r_B] ([r] x = r cross x).
The normal impulse p = n.P grows monotonically through the impact and is the independent
variable: dP/dp = n - mu s^ while the points slip (s^ = v_t/|v_t|, the tangential part of v),
and dP/dp = n + T tau while they stick, tau = -(T'KT)^-1 T'K n the friction that keeps v_t = 0
(T: two tangent vectors), possible only if |tau| <= mu; otherwise slip restarts along the
direction s^ in which v_t grows from rest (T'K(n - mu T s^) parallel to +s^). Compression ends
where v_n = n.v reaches 0; the normal force's work W = int v_n dp is then W_c < 0.

Restitution is energetic (Stronge's hypothesis): the impact ends where W = (1 - e^2) W_c, the
normal force giving back e^2 of the work of compression. It is the one of the three hypotheses
that never creates energy with friction; Poisson's (p_end = (1 + e) p_c, ``hypothesis =
"poisson"``) agrees with it unless the slip stops or turns during compression (Stronge sec.
4.4); Newton's kinematic law (v_n' = -e v_n) is the frictionless special case of both.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike
from scipy import integrate, optimize

from . import checks
from .impulse3d import RigidBody3D, _vec3, apply_impulse
from .model import ImpactCase

#: Integration tolerance (relative): the wall limits are met to 1e-12.
RTOL = 1e-13
#: A tangential slip speed below this fraction of the closing speed is rest (stick).
REST = 1e-12
#: Slower than this fraction of the closing speed, a slip is taken to rest in one straight
#: step (an adaptive integrator cannot follow a 3D slip's direction into the origin).
NEAR = 1e-7
#: More changes between slip and stick than this is a contact that chatters: an error.
MAX_PHASES = 20
HYPOTHESES = ("energetic", "poisson")


@dataclass(frozen=True, kw_only=True, eq=False)
class FrictionalImpulse:
    """Result of ``frictional_impulse``: the impulse on A (3-vector, N s; -P on B), both bodies
    after, the normal impulse at the end of compression (N s), and the phases in order, each
    ('slip' or 'stick', the normal impulse where it ended, N s)."""

    impulse_ns: np.ndarray
    a: RigidBody3D
    b: RigidBody3D
    compression_ns: float
    phases: tuple[tuple[str, float], ...]


def collision_matrix(
    a: RigidBody3D, b: RigidBody3D, r_a: np.ndarray, r_b: np.ndarray
) -> np.ndarray:
    """K: the change of the contact points' relative velocity per unit impulse on A (1/kg)."""

    def term(body: RigidBody3D, r: np.ndarray) -> np.ndarray:
        x = np.array([[0.0, -r[2], r[1]], [r[2], 0.0, -r[0]], [-r[1], r[0], 0.0]])
        return -x @ np.linalg.solve(body.inertia_kgm2, x)

    return (1.0 / a.mass_kg + 1.0 / b.mass_kg) * np.eye(3) + term(a, r_a) + term(b, r_b)


def _tangents(n: np.ndarray) -> np.ndarray:
    """Two unit vectors perpendicular to n and to each other, as the columns of a 3x2 matrix."""
    helper = np.eye(3)[int(np.argmin(np.abs(n)))]
    t1 = np.cross(n, helper)
    t1 /= np.linalg.norm(t1)
    return np.column_stack([t1, np.cross(n, t1)])


class _Impact:
    """The impact's state as a function of the normal impulse p: y = (P (3), W)."""

    def __init__(self, K: np.ndarray, n: np.ndarray, v0: np.ndarray, mu: float) -> None:
        self.K, self.n, self.v0, self.mu = K, n, v0, mu
        self.T = _tangents(n)
        self.rest = REST * float(np.linalg.norm(v0))
        self.near = NEAR * float(np.linalg.norm(v0))
        tt = self.T.T @ K @ self.T
        self.tau = -np.linalg.solve(tt, self.T.T @ K @ n)
        self.hint = np.zeros(2)  # slip direction (tangent coordinates) while |v_t| is ~0

    def velocity(self, y: np.ndarray) -> np.ndarray:
        return self.v0 + self.K @ y[:3]

    def slip_rhs(self, p: float, y: np.ndarray) -> np.ndarray:
        v = self.velocity(y)
        vt = self.T.T @ v
        speed = math.hypot(*vt)
        s = vt / speed if speed > self.rest else self.hint
        return np.concatenate([self.n - self.mu * (self.T @ s), [self.n @ v]])

    def slip_speed(self, y: np.ndarray) -> float:
        return math.hypot(*(self.T.T @ self.velocity(y)))

    def _slowing_rate(self, y: np.ndarray) -> tuple[float, float, np.ndarray]:
        """The slip's speed, how fast it falls per unit normal impulse, and dP/dp."""
        vt = self.T.T @ self.velocity(y)
        speed = math.hypot(*vt)
        s = vt / speed if speed > self.rest else self.hint
        dP = self.n - self.mu * (self.T @ s)
        return speed, -float(s @ (self.T.T @ self.K @ dP)), dP

    def slowing(self, y: np.ndarray) -> bool:
        return self._slowing_rate(y)[1] > 0.0

    def to_rest(self, p: float, y: np.ndarray) -> tuple[float, np.ndarray]:
        """From a slip slower than ``near`` to rest in one straight step along its direction
        (exact where the slip keeps its direction, as in a plane; the error elsewhere is of
        order near): the normal impulse and state at rest."""
        speed, rate, dP = self._slowing_rate(y)
        if speed <= self.rest:
            return p, y
        dp = speed / rate
        vn0 = float(self.n @ self.velocity(y))
        out = np.concatenate([y[:3] + dP * dp, [y[3]]])
        out[3] += 0.5 * dp * (vn0 + float(self.n @ self.velocity(out)))
        return p + dp, out

    def stick_rhs(self, p: float, y: np.ndarray) -> np.ndarray:
        return np.concatenate([self.n + self.T @ self.tau, [self.n @ self.velocity(y)]])

    def can_stick(self) -> bool:
        return float(np.hypot(*self.tau)) <= self.mu

    def slip_from_rest(self) -> np.ndarray:
        """The direction (tangent coordinates) in which v_t grows from rest under slip:
        T'K(n - mu T s) = lambda s with lambda > 0 (Stronge sec. 5.3)."""
        A, c = self.T.T @ self.K @ self.T, self.T.T @ self.K @ self.n

        def parts(phi: float) -> tuple[float, float]:
            s = np.array([math.cos(phi), math.sin(phi)])
            h = c - self.mu * (A @ s)
            return float(h[0] * s[1] - h[1] * s[0]), float(h @ s)

        grid = np.linspace(-math.pi, math.pi, 721)
        cross = [parts(phi)[0] for phi in grid]
        for lo, hi, f_lo, f_hi in zip(grid, grid[1:], cross, cross[1:]):
            if f_lo == 0.0 or f_lo * f_hi < 0.0:
                phi = (
                    lo
                    if f_lo == 0.0
                    else optimize.brentq(lambda x: parts(x)[0], lo, hi, xtol=1e-15)
                )
                if parts(phi)[1] > 0.0:
                    return np.array([math.cos(phi), math.sin(phi)])
        raise ArithmeticError(
            "no direction of slip from rest: the contact jams (|tau| > mu "
            "and no slip direction grows)"
        )


def frictional_impulse(
    a: RigidBody3D,
    b: RigidBody3D,
    *,
    r_a_m: ArrayLike,
    r_b_m: ArrayLike,
    normal: ArrayLike,
    e: float,
    mu: float,
    hypothesis: str = "energetic",
    rtol: float = RTOL,
) -> FrictionalImpulse:
    """The impulse between bodies A and B touching at one point with Coulomb friction mu and
    restitution e (module docstring). n is the contact normal from B to A; r_A, r_B go from
    each COM to the contact point; ``rtol`` the integration's relative tolerance (RTOL: to
    rounding; a coarser one for many impacts). Raises ValueError unless the points approach
    (n.v < 0)."""
    r_a, r_b, n = _vec3("r_a_m", r_a_m), _vec3("r_b_m", r_b_m), _vec3("normal", normal)
    if not np.linalg.norm(n) > 0.0:
        raise ValueError("normal is the zero vector; allowed: a non-zero 3-vector")
    n = n / np.linalg.norm(n)
    checks.in_range("e", e, 0.0, 1.0)
    checks.in_range("mu", mu, 0.0, 1e6)
    if hypothesis not in HYPOTHESES:
        raise ValueError(f"hypothesis={hypothesis!r} is unknown; allowed: {HYPOTHESES}")
    v0 = a.point_velocity(r_a) - b.point_velocity(r_b)
    if not n @ v0 < 0.0:
        raise ValueError(
            f"relative normal velocity v_rel={float(n @ v0)!r} m/s: the bodies "
            "do not approach; allowed: v_rel < 0"
        )
    K = collision_matrix(a, b, r_a, r_b)
    rtol = checks.in_range("rtol", rtol, RTOL, 1e-6)
    P, p_c, phases = _integrate(_Impact(K, n, v0, mu), e, hypothesis, rtol)
    a1, b1 = apply_impulse(a, b, r_a, r_b, P)
    return FrictionalImpulse(impulse_ns=P, a=a1, b=b1, compression_ns=p_c, phases=phases)


def _integrate(imp: _Impact, e: float, hypothesis: str, rtol: float = RTOL):
    """Integrate dP/dp through slip and stick until restitution ends: (P, p_c, phases). y[3]
    is the normal force's work in the stage (compression, then restitution from 0: a target
    e^2 W_c stays resolved however small e is)."""
    n, v0 = imp.n, imp.v0
    scale = -(1.0 + e) * float(n @ v0) / float(n @ imp.K @ n)  # the frictionless impulse
    tiny = 1e-3 * rtol * scale
    atol = np.array([tiny] * 3 + [tiny * float(np.linalg.norm(v0))])
    p, y, phases = 0.0, np.zeros(4), []
    mode, p_c, w_c, stopping, resumed = "slip", None, None, False, False
    for _ in range(MAX_PHASES):
        speed = imp.slip_speed(y)
        resumed = resumed and speed <= imp.near  # a slip restarted from rest, still slow
        if (
            mode == "slip"
            and not resumed
            and (speed <= imp.rest or ((stopping or speed <= imp.near) and imp.slowing(y)))
        ):
            p, y = imp.to_rest(p, y)  # at rest, or about to stop: stopped
            if p > 0.0:
                phases.append(("slip", p))
            mode = _from_rest(imp)
            resumed = mode == "slip"
        if p_c is None and float(n @ imp.velocity(y)) >= 0.0:  # compression ended here
            p_c, w_c, y = p, y[3], np.concatenate([y[:3], [0.0]])
            if e == 0.0:
                phases.append((mode, p))
                return y[:3], p_c, tuple(phases)
        events = [_stage_end(imp, e, hypothesis, p_c, w_c)]
        if mode == "slip":
            events.append(_event(lambda p, y: imp.slip_speed(y) - imp.near, -1.0))
        rhs = imp.slip_rhs if mode == "slip" else imp.stick_rhs
        sol = integrate.solve_ivp(
            rhs, (p, p + 100.0 * scale), y, method="DOP853", rtol=rtol, atol=atol, events=events
        )
        if sol.status != 1:
            raise ArithmeticError("the impact did not end within 100 frictionless impulses")
        p, y = float(sol.t[-1]), sol.y[:, -1]
        stopping = len(sol.t_events) > 1 and len(sol.t_events[1]) > 0
        if len(sol.t_events[0]):  # compression or restitution over
            if p_c is None:
                p_c, w_c = p, y[3]
                y = np.concatenate([y[:3], [0.0]])  # W counts restitution's work from 0
                if e > 0.0:
                    continue
            phases.append((mode, p))
            return y[:3], p_c, tuple(phases)
    raise ArithmeticError(f"the contact changed between slip and stick {MAX_PHASES} times")


def _event(f, direction: float):
    f.terminal, f.direction = True, direction
    return f


def _stage_end(imp: _Impact, e: float, hypothesis: str, p_c: float | None, w_c: float | None):
    """The event that ends the stage: compression (v_n = 0), else restitution (its work, W
    counted from 0 at p_c, reaching -e^2 W_c, energetic; p = (1 + e) p_c, Poisson's)."""
    if p_c is None:
        return _event(lambda p, y: float(imp.n @ imp.velocity(y)), 1.0)
    if hypothesis == "energetic":
        return _event(lambda p, y: y[3] + e * e * w_c, 1.0)
    return _event(lambda p, y: p - (1.0 + e) * p_c, 1.0)


def _from_rest(imp: _Impact) -> str:
    """How the points go on from relative rest: stick if friction can hold them, else slip
    (the direction it restarts in is kept for the integrator)."""
    if imp.can_stick():
        return "stick"
    imp.hint = imp.slip_from_rest()
    return "slip"


def one_step_impulse(
    a: RigidBody3D,
    b: RigidBody3D,
    *,
    r_a_m: ArrayLike,
    r_b_m: ArrayLike,
    normal: ArrayLike,
    e: float,
    mu: float,
    relaxed: bool = False,
) -> FrictionalImpulse:
    """The impulse an impulse-based engine solves in one step: Newton's restitution on the
    total normal impulse (v_n' = -e v_n) and Coulomb's cone on the total impulse, sticking
    (v_t' = 0) where the cone allows it, else sliding against the final slip,
    P = p (n - mu T d) with T'(v + K P) = lambda d, lambda >= 0 (Stewart & Trinkle's time
    step). ``relaxed``: Anitescu's convex relaxation of it, which a convex contact solver
    (MuJoCo's) solves: a sliding contact leaves faster along the normal by mu times its final
    slip, v_n' = -e v_n + mu |v_t'| (the optimality condition of min 1/2 P'K P + P'(v - v*)
    over the cone). Not Routh's integration: the laws differ where K couples the normal and
    tangential directions and the slip stops or turns within the impact
    (``frictional_impulse``); ``phases`` is (('stick' or 'slip', p),)."""
    r_a, r_b, n = _vec3("r_a_m", r_a_m), _vec3("r_b_m", r_b_m), _vec3("normal", normal)
    n = n / np.linalg.norm(n)
    checks.in_range("e", e, 0.0, 1.0)
    checks.in_range("mu", mu, 0.0, 1e6)
    v0 = a.point_velocity(r_a) - b.point_velocity(r_b)
    vn = float(n @ v0)
    if not vn < 0.0:
        raise ValueError(
            f"relative normal velocity v_rel={vn!r} m/s: the bodies do not "
            "approach; allowed: v_rel < 0"
        )
    K, T = collision_matrix(a, b, r_a, r_b), _tangents(n)
    if mu == 0.0:  # no friction: EQ 141's impulse along n, the slip left to itself
        P = -(1.0 + e) * vn / float(n @ K @ n) * n
        mode = "slip" if math.hypot(*(T.T @ (v0 + K @ P))) > 0.0 else "stick"
        a1, b1 = apply_impulse(a, b, r_a, r_b, P)
        return FrictionalImpulse(
            impulse_ns=P, a=a1, b=b1, compression_ns=math.nan, phases=((mode, float(n @ P)),)
        )
    P = np.linalg.solve(K, -(1.0 + e) * vn * n - T @ (T.T @ v0))  # sticking
    mode = "stick"
    if math.hypot(*(T.T @ P)) > mu * float(n @ P):
        mode, P = "slip", _one_step_slide(K, T, n, v0, vn, e, mu, relaxed)
    a1, b1 = apply_impulse(a, b, r_a, r_b, P)
    return FrictionalImpulse(
        impulse_ns=P, a=a1, b=b1, compression_ns=math.nan, phases=((mode, float(n @ P)),)
    )


def _one_step_slide(K, T, n, v0, vn: float, e: float, mu: float, relaxed: bool) -> np.ndarray:
    """The sliding impulse of ``one_step_impulse``: P = p (n - mu d) with the final relative
    velocity v* + c (d + mu n) (relaxed) or v* + c d (plain), v* = -e v_n n the target, c >= 0
    the final slip's speed: p K (n - mu d) - c (d [+ mu n]) = v* - v, linear in (p, c) for a
    given d, solvable where det[K (n - mu d), d [+ mu n], v* - v] = 0 (a root in d's angle
    in the tangent plane), with p, c >= 0."""
    b = -e * vn * n - v0

    def columns(phi: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        d = T @ np.array([math.cos(phi), math.sin(phi)])
        return d, K @ (n - mu * d), d + (mu * n if relaxed else 0.0)

    def det(phi: float) -> float:
        _, a1, a2 = columns(phi)
        return float(np.linalg.det(np.column_stack([a1, a2, b])))

    grid = np.linspace(-math.pi, math.pi, 721)
    dets = [det(phi) for phi in grid]
    for lo, hi, f_lo, f_hi in zip(grid, grid[1:], dets, dets[1:]):
        if f_lo == 0.0 or f_lo * f_hi < 0.0:
            phi = lo if f_lo == 0.0 else optimize.brentq(det, lo, hi, xtol=1e-15)
            d, a1, a2 = columns(phi)
            (p, c), *_ = np.linalg.lstsq(np.column_stack([a1, -a2]), b, rcond=None)
            if p >= 0.0 and c >= 0.0:
                return p * (n - mu * d)
    raise ArithmeticError("no sliding direction satisfies the one-step law")


@dataclass(frozen=True, kw_only=True)
class FrictionOutcome:
    """Ball and bat just after a frictional impact, in the impact frame: x along the bat's axis
    (toward the barrel), y the swing's normal (toward the incoming ball), z = x cross y (the
    side of the swing plane an undercut ball's centre is on). Velocities m/s, spins rad/s,
    impulse N s (on the ball), energies J; ``phases`` as ``FrictionalImpulse.phases``;
    ``slip0_mps`` the contact points' tangential speed before the impact."""

    ball_velocity_mps: tuple[float, float, float]
    ball_spin_radps: tuple[float, float, float]
    bat_velocity_mps: tuple[float, float, float]
    bat_omega_radps: tuple[float, float, float]
    impulse_ns: tuple[float, float, float]
    phases: tuple[tuple[str, float], ...]
    ke_before_j: float
    ke_after_j: float
    slip0_mps: float = 0.0

    @property
    def v1_mps(self) -> float:
        """The ball's velocity along y, away from the bat: the planar model's v1 (m/s)."""
        return self.ball_velocity_mps[1]

    @property
    def vt1_mps(self) -> float:
        """The ball's velocity along the bat's axis (m/s)."""
        return self.ball_velocity_mps[0]

    @property
    def launch_rad(self) -> float:
        """The ball's exit angle out of the swing plane, atan2(v_z, v_y) (rad)."""
        return math.atan2(self.ball_velocity_mps[2], self.ball_velocity_mps[1])

    @property
    def backspin_radps(self) -> float:
        """The ball's spin about x: positive lifts a ball leaving along +y (rad/s)."""
        return self.ball_spin_radps[0]


#: The laws ``predict_friction`` computes: Routh's integration, and the two one-step laws.
LAWS = ("routh", "one_step", "relaxed")


def predict_friction(
    case, *, hypothesis: str = "energetic", law: str = "routh", rtol: float = RTOL
) -> FrictionOutcome:
    """The impact of ``case`` (an ``ImpactCase``) with its Coulomb friction ``case.mu``, the
    ball's centre ``case.undercut_m`` off the swing plane (+z) and spinning at
    ``case.spin_radps`` (impact frame). The bat turns about z at omega0 with its inertia tensor
    diag(I_axial, J, J) about the COM; the contact normal tilts by ``case.tilt_rad`` out of the
    plane. ``law`` one of LAWS: Routh's integration (``frictional_impulse``), or the law an
    impulse engine solves in one step (``one_step_impulse``), relaxed or not; ``rtol``
    Routh's integration tolerance."""
    checks.instance("case", case, ImpactCase)
    checks.choice("law", law, LAWS)
    bat, ball = case.bat, case.ball
    tilt = case.tilt_rad
    n = np.array([0.0, math.cos(tilt), math.sin(tilt)])
    m, J = ball.mass_kg, bat.inertia_cm_kgm2
    a = RigidBody3D(
        mass_kg=m,
        inertia_kgm2=ball.inertia_kgm2 * np.eye(3),
        velocity_mps=np.array([case.v0_mps * math.sin(case.theta_rad), -case.v0n_mps, 0.0]),
        omega_radps=np.array(case.spin_radps),
    )
    b = RigidBody3D(
        mass_kg=bat.mass_kg,
        inertia_kgm2=np.diag([bat.axial_inertia_kgm2, J, J]),
        velocity_mps=np.array([case.u0_mps * math.sin(case.phi_rad), case.u0n_mps, 0.0]),
        omega_radps=np.array([0.0, 0.0, case.omega0_radps]),
    )
    contact = dict(
        r_a_m=-ball.radius_m * n,
        r_b_m=np.array([case.s_m, 0.0, 0.0]) + bat.radius_m * n,
        normal=n,
        e=case.e,
        mu=case.mu,
    )
    out = (
        frictional_impulse(a, b, hypothesis=hypothesis, rtol=rtol, **contact)
        if law == "routh"
        else one_step_impulse(a, b, relaxed=law == "relaxed", **contact)
    )
    v0 = a.point_velocity(contact["r_a_m"]) - b.point_velocity(contact["r_b_m"])
    return FrictionOutcome(
        slip0_mps=float(np.linalg.norm(v0 - (v0 @ n) * n)),
        ball_velocity_mps=tuple(map(float, out.a.velocity_mps)),
        ball_spin_radps=tuple(map(float, out.a.omega_radps)),
        bat_velocity_mps=tuple(map(float, out.b.velocity_mps)),
        bat_omega_radps=tuple(map(float, out.b.omega_radps)),
        impulse_ns=tuple(map(float, out.impulse_ns)),
        phases=out.phases,
        ke_before_j=a.kinetic_energy_j() + b.kinetic_energy_j(),
        ke_after_j=out.a.kinetic_energy_j() + out.b.kinetic_energy_j(),
    )
