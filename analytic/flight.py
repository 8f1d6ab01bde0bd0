"""Flight of a baseball through air, after the bat (carry) or from the pitcher's hand (a pitch).

    m dv/dt = m g - 1/2 rho A C_D |v| v + 1/2 rho A C_L |v| (w^ x v),   A = pi r^2,

the drag against the velocity and the Magnus lift along w^ x v (w the spin, w^ = w/|w|): a ball
moving along +x with spin along -y (backspin) is lifted toward +z. The coefficients follow Alan
Nathan's trajectory calculator (``Aerodynamics``, ``NATHAN_2008``): C_D grows linearly with the
spin rate, C_L = cl2 S / (cl0 + cl1 S) with the spin factor S = r |w| / |v|, and the spin decays
as exp(-t / tau) about a fixed axis. The force keeps Nathan's form: C_L is taken at the whole
spin |w|, and the cross product w^ x v carries the angle between spin and velocity.

Field frame (right-handed, m): x from the contact point toward centre field, y to the left as
seen from home plate, z up. The ground is z = 0; the wind is calm. Conversions: 1 mph =
0.44704 m/s, 1 ft = 0.3048 m, 1 rpm = 2 pi / 60 rad/s.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike
from scipy import integrate

from . import checks, presets
from .impulse3d import _vec3
from .model import MAX_SPIN_RADPS, Ball

RPM_RADPS = 2.0 * math.pi / 60.0
MPH_MPS = 0.44704
FT_M = 0.3048
#: The fastest launch the flight model takes (m/s): its drag and lift are measured on balls
#: up to about 50 m/s (Nathan, AJP 76, 119 (2008)); beyond a few times that, past any bat's,
#: a carry would be the model's extrapolation, not an answer.
MAX_SPEED_MPS = 200.0
#: Standard gravity (m/s^2; CGPM 1901).
G_MPS2 = 9.80665
#: Distance from the front of the pitching rubber to the point of home plate: 60 ft 6 in
#: (Official Baseball Rules, rule 2.01 and its diagram; MLB's Statcast glossary, "Extension").
RUBBER_TO_PLATE_M = 60.5 * FT_M
#: A typical pitcher releases the ball 6.4 ft in front of the rubber (MLB.com, "The secret
#: weapon McClanahan and Strider have in common", 3 June 2023; league averages 6.1-6.3 ft in
#: 2015-2021, purplerow.com 2 Feb 2022): release to the point of the plate, 54.1 ft = 16.5 m.
RELEASE_TO_PLATE_M = RUBBER_TO_PLATE_M - 6.4 * FT_M
#: Ball-to-ball and model spread of the drag coefficient, +-10% (R. K. Adair, The Physics of
#: Baseball, 3rd ed. (2002), ch. 2: "an uncertainty of 10% in the drag coefficients ... the
#: uncertainty in the maximum distance ... about 3%, or about 12 feet for a 400 foot home run").
DRAG_SPREAD = 0.10
#: Spread of the lift coefficient, +-20%: ASSUMED, the visible scatter of the measured C_L about
#: the fitted curve at fixed S in Nathan, Am. J. Phys. 76, 119 (2008) (not read off numerically).
LIFT_SPREAD = 0.20


@dataclass(frozen=True, kw_only=True)
class Aerodynamics:
    """Drag and lift coefficients of a spinning baseball (dimensionless unless named):
    C_D = cd0 + cd_spin_per_radps |w| and C_L = cl2 S / (cl0 + cl1 S), S = r |w| / |v|; the spin
    decays as exp(-t / spin_decay_s) (math.inf: no decay)."""

    cd0: float
    cd_spin_per_radps: float
    cl0: float
    cl1: float
    cl2: float
    spin_decay_s: float = 30.0

    def __post_init__(self) -> None:
        for name in ("cd0", "cd_spin_per_radps", "cl1", "cl2"):
            checks.non_negative(name, getattr(self, name))
        checks.positive("cl0", self.cl0)
        if self.spin_decay_s != math.inf:
            checks.positive("spin_decay_s", self.spin_decay_s)

    def drag_coefficient(self, spin_radps: float) -> float:
        """C_D at the spin rate |w| (rad/s)."""
        return self.cd0 + self.cd_spin_per_radps * abs(spin_radps)

    def lift_coefficient(self, spin_factor: float) -> float:
        """C_L at the spin factor S = r |w| / |v| (>= 0)."""
        return self.cl2 * spin_factor / (self.cl0 + self.cl1 * spin_factor)

    def scaled(self, *, drag: float = 1.0, lift: float = 1.0) -> Aerodynamics:
        """These coefficients with C_D times ``drag`` and C_L times ``lift`` (both >= 0): the
        ends of a spread (``DRAG_SPREAD``, ``LIFT_SPREAD``) give a range of carries."""
        checks.non_negative("drag", drag)
        checks.non_negative("lift", lift)
        return Aerodynamics(
            cd0=self.cd0 * drag,
            cd_spin_per_radps=self.cd_spin_per_radps * drag,
            cl0=self.cl0,
            cl1=self.cl1,
            cl2=self.cl2 * lift,
            spin_decay_s=self.spin_decay_s,
        )


NATHAN_2008 = Aerodynamics(
    cd0=0.3008,
    cd_spin_per_radps=0.0292 / (1000.0 * RPM_RADPS),
    cl0=0.583,
    cl1=2.333,
    cl2=1.120,
    spin_decay_s=30.0,
)
"""The coefficients of A. M. Nathan's trajectory calculator (TrajectoryCalculator-new-3D.xlsx,
baseball.physics.illinois.edu, 2016 onward, fitted to 2015 Statcast fly balls), as re-implemented
in pybaseball (analysis/trajectories/batted_balls/parameters.py) and in an R transcription of
the 3D calculator on GitHub ("Alan Nathan's 3D Trajectory Function"): cd0 = 0.3008, cdspin =
0.0292 per 1000 rpm, cl0 = 0.583, cl1 = 2.333, cl2 = 1.120; that transcription reproduces the
calculator's published Fly_ball trajectory (R package mosaicCalc) to the digits given.
The lift curve is a fit to measured C_L(S) such as Nathan, "The effect of spin on the flight of
a baseball", Am. J. Phys. 76, 119 (2008) (S = 0.09-0.6 at 50-110 mph), whose data scatter about
it (``LIFT_SPREAD``); baseballaero.com ("UMBA 1.0", 2020) traces the form to R. Cross, Physics of
Baseball & Softball (2011). C_D of a baseball is quoted from about 0.3 to 0.5 (Adair; Sawicki,
Hubbard & Stronge, Am. J. Phys. 71, 1152 (2003), with a drag crisis): ``DRAG_SPREAD``.
Spin decay: the 3D calculator uses tau = 30 s scaled by (100 mph)/|v| (30-45 s over a fly ball's
speeds); pybaseball's 2D version, 10000 s (none). Here a plain tau = 30 s: from 25 s to none at
all the carry of a 45 m/s, 30 deg, 2000 rpm ball moves by 0.3 m (tests). C_D takes the whole
spin |w|, the 3D calculator its backspin part (the same for a ball without sidespin)."""


@dataclass(frozen=True, kw_only=True)
class Air:
    """Still air of density ``density_kgm3`` (kg/m^3; >= 0, 0 is a vacuum). The default, 1.194,
    is what Nathan's calculator's density formula gives at 70 F, sea level, 29.92 inHg and 50%
    relative humidity (1.2929 (273/T)(p - 0.3783 RH p_sv)/760 kg/m^3, p in mmHg)."""

    density_kgm3: float = 1.194

    def __post_init__(self) -> None:
        checks.in_range("density_kgm3", self.density_kgm3, 0.0, 10.0)


@dataclass(frozen=True, kw_only=True)
class Launch:
    """A ball leaving the bat: speed (m/s), angle above the horizontal (rad), spray angle
    (rad, from +x toward +y), height of the contact point above the ground (m), backspin (rad/s,
    about the horizontal axis v^ x z^ normal to the velocity; > 0 lifts, < 0 is topspin) and
    sidespin (rad/s, about the axis normal to the velocity in its vertical plane, vertical for a
    level ball; > 0 curves the ball to its left, toward +y when hit toward +x). Default height
    0.9 m: Nathan's calculator starts the ball 3 ft (0.91 m) up, 2 ft in front of home plate
    (its default, and pybaseball's)."""

    speed_mps: float
    launch_rad: float
    backspin_radps: float = 0.0
    sidespin_radps: float = 0.0
    height_m: float = 0.9
    direction_rad: float = 0.0

    def __post_init__(self) -> None:
        checks.in_range("speed_mps", self.speed_mps, 0.0, MAX_SPEED_MPS, lo_open=True)
        checks.in_range(
            "launch_rad", self.launch_rad, -math.pi / 2, math.pi / 2, lo_open=True, hi_open=True
        )
        checks.in_range("backspin_radps", self.backspin_radps, -MAX_SPIN_RADPS, MAX_SPIN_RADPS)
        checks.in_range("sidespin_radps", self.sidespin_radps, -MAX_SPIN_RADPS, MAX_SPIN_RADPS)
        checks.in_range("height_m", self.height_m, 0.0, 100.0)
        checks.in_range("direction_rad", self.direction_rad, -math.pi, math.pi)
        if self.height_m == 0.0 and self.launch_rad <= 0.0:
            raise ValueError(
                f"launch_rad={self.launch_rad!r} with height_m=0.0: the ball starts "
                "on the ground moving down; allowed: launch_rad > 0 or height_m > 0"
            )

    def velocity_mps(self) -> np.ndarray:
        """The velocity in the field frame (m/s)."""
        c = math.cos(self.launch_rad)
        return self.speed_mps * np.array(
            [
                c * math.cos(self.direction_rad),
                c * math.sin(self.direction_rad),
                math.sin(self.launch_rad),
            ]
        )

    def spin_radps(self) -> np.ndarray:
        """The spin vector in the field frame (rad/s): backspin along v^ x z^, sidespin along
        (v^ x z^) x v^ (both unit vectors)."""
        a, d = self.launch_rad, self.direction_rad
        back = np.array([math.sin(d), -math.cos(d), 0.0])
        side = np.array([-math.sin(a) * math.cos(d), -math.sin(a) * math.sin(d), math.cos(a)])
        return self.backspin_radps * back + self.sidespin_radps * side


@dataclass(frozen=True, kw_only=True, eq=False)
class Flight:
    """A flight from the contact point to the ground: the horizontal distance to the landing
    point (m), the time in the air (s), the greatest height (m), the speed (m/s) and the angle
    below the horizontal (rad) at landing, the landing point's offset normal to the launch's
    horizontal direction (m, + to its left), and the trajectory sampled evenly in time for
    charts (``t_s``, shape (n,); ``xyz_m``, shape (n, 3), field frame)."""

    carry_m: float
    hang_s: float
    apex_m: float
    landing_speed_mps: float
    landing_angle_rad: float
    lateral_m: float
    t_s: np.ndarray
    xyz_m: np.ndarray


@dataclass(frozen=True, kw_only=True)
class Travel:
    """A pitch over a horizontal distance: the time taken (s), the speed on arrival (m/s) and
    how far it fell below its release height (m, + down)."""

    time_s: float
    arrival_speed_mps: float
    drop_m: float


def _acceleration(ball: Ball, aero: Aerodynamics, air: Air, g_mps2: float, spin0: np.ndarray):
    """The right-hand side d(r, v)/dt of the equation of motion (module docstring)."""
    k = air.density_kgm3 * math.pi * ball.radius_m**2 / (2.0 * ball.mass_kg)
    w0 = float(np.linalg.norm(spin0))
    axis = spin0 / w0 if w0 > 0.0 else np.zeros(3)
    decay = 0.0 if aero.spin_decay_s == math.inf else 1.0 / aero.spin_decay_s

    def rhs(t: float, y: np.ndarray) -> np.ndarray:
        v = y[3:]
        speed = math.sqrt(v @ v)
        w = w0 * math.exp(-t * decay)
        acc = -k * aero.drag_coefficient(w) * speed * v
        if w > 0.0 and speed > 0.0:
            cl = aero.lift_coefficient(ball.radius_m * w / speed)
            acc = acc + k * cl * speed * np.cross(axis, v)
        acc[2] -= g_mps2
        return np.concatenate([v, acc])

    return rhs


def _event(f, *, terminal: bool, direction: float):
    f.terminal, f.direction = terminal, direction
    return f


def _solve(rhs, y0: np.ndarray, t_max: float, events: list, rtol: float):
    """Integrate from t = 0 until a terminal event (DOP853, tolerances ``rtol`` relative and
    rtol times the launch's length and speed scales absolute); raise if none comes by t_max."""
    speed = max(float(np.linalg.norm(y0[3:])), 1.0)
    length = max(speed * t_max / 10.0, abs(float(y0[2])), 1.0)
    atol = rtol * np.array([length] * 3 + [speed] * 3)
    sol = integrate.solve_ivp(
        rhs,
        (0.0, t_max),
        y0,
        method="DOP853",
        rtol=rtol,
        atol=atol,
        events=events,
        dense_output=True,
    )
    if sol.status != 1:
        raise ArithmeticError(f"the flight did not end within {t_max:g} s")
    return sol


def fly_vectors(
    position_m: ArrayLike,
    velocity_mps: ArrayLike,
    spin_radps: ArrayLike,
    *,
    ball: Ball = presets.BASEBALL,
    aero: Aerodynamics = NATHAN_2008,
    air: Air = Air(),
    g_mps2: float = G_MPS2,
    rtol: float = 1e-10,
    samples: int = 101,
) -> Flight:
    """The flight of a ball from ``position_m`` (z >= 0) with ``velocity_mps`` and
    ``spin_radps`` (3-vectors, field frame) down to the ground z = 0; ``samples`` points of it
    are kept. ``lateral_m`` is measured normal to the horizontal part of the velocity."""
    r0, v0 = _vec3("position_m", position_m), _vec3("velocity_mps", velocity_mps)
    w0 = checks.array_in_range(
        "spin_radps", _vec3("spin_radps", spin_radps), -MAX_SPIN_RADPS, MAX_SPIN_RADPS
    )
    checks.instance("ball", ball, Ball)
    checks.in_range("position_m[2]", r0[2], 0.0, 1e3)
    checks.positive("g_mps2", g_mps2)
    checks.in_range("rtol", rtol, 1e-13, 1e-3)
    samples = checks.integer("samples", samples, 2, 100_000)
    if not (r0[2] > 0.0 or v0[2] > 0.0):
        raise ValueError(
            f"velocity_mps[2]={v0[2]!r} at height 0: the ball starts on the "
            "ground moving down; allowed: velocity_mps[2] > 0 or position_m[2] > 0"
        )
    up = max(v0[2], 0.0)
    t_vacuum = (up + math.sqrt(up * up + 2.0 * g_mps2 * r0[2])) / g_mps2
    ground = _event(lambda t, y: y[2], terminal=True, direction=-1.0)
    apex = _event(lambda t, y: y[5], terminal=False, direction=-1.0)
    sol = _solve(
        _acceleration(ball, aero, air, g_mps2, w0),
        np.concatenate([r0, v0]),
        10.0 * t_vacuum + 10.0,
        [ground, apex],
        rtol,
    )
    hang = float(sol.t_events[0][0])
    end = sol.y_events[0][0]
    t = np.linspace(0.0, hang, samples)
    xyz = sol.sol(t)[:3].T
    xyz[-1] = end[:3]
    xyz[-1, 2] = 0.0
    heights = [r0[2]] + [float(y[2]) for y in sol.y_events[1]]
    dx, dy = end[0] - r0[0], end[1] - r0[1]
    h = math.hypot(v0[0], v0[1])
    lateral = (v0[0] * dy - v0[1] * dx) / h if h > 0.0 else 0.0
    return Flight(
        carry_m=math.hypot(dx, dy),
        hang_s=hang,
        apex_m=max(heights),
        landing_speed_mps=float(np.linalg.norm(end[3:])),
        landing_angle_rad=math.atan2(-end[5], math.hypot(end[3], end[4])),
        lateral_m=lateral,
        t_s=t,
        xyz_m=xyz,
    )


def fly(
    launch: Launch,
    *,
    ball: Ball = presets.BASEBALL,
    aero: Aerodynamics = NATHAN_2008,
    air: Air = Air(),
    g_mps2: float = G_MPS2,
    rtol: float = 1e-10,
    samples: int = 101,
) -> Flight:
    """The flight of a batted ball from its contact point (at x = y = 0) to the ground."""
    checks.instance("launch", launch, Launch)
    return fly_vectors(
        [0.0, 0.0, launch.height_m],
        launch.velocity_mps(),
        launch.spin_radps(),
        ball=ball,
        aero=aero,
        air=air,
        g_mps2=g_mps2,
        rtol=rtol,
        samples=samples,
    )


def carry_range_m(
    launch: Launch,
    *,
    drag_spread: float = DRAG_SPREAD,
    lift_spread: float = LIFT_SPREAD,
    ball: Ball = presets.BASEBALL,
    aero: Aerodynamics = NATHAN_2008,
    air: Air = Air(),
    g_mps2: float = G_MPS2,
) -> tuple[float, float]:
    """The least and greatest carry (m) over the four corners C_D (1 +- drag_spread),
    C_L (1 +- lift_spread) of ``aero``: the carry to report as a range."""
    checks.in_range("drag_spread", drag_spread, 0.0, 1.0)
    checks.in_range("lift_spread", lift_spread, 0.0, 1.0)
    carries = [
        fly(
            launch,
            ball=ball,
            aero=aero.scaled(drag=1.0 + i * drag_spread, lift=1.0 + j * lift_spread),
            air=air,
            g_mps2=g_mps2,
            samples=2,
        ).carry_m
        for i in (-1, 1)
        for j in (-1, 1)
    ]
    return min(carries), max(carries)


def vacuum_carry_m(launch: Launch, g_mps2: float = G_MPS2) -> tuple[float, float]:
    """Carry (m) and hang time (s) without air: t = (v sin a + sqrt(v^2 sin^2 a + 2 g h)) / g,
    x = v cos(a) t."""
    checks.positive("g_mps2", g_mps2)
    v, a, h = launch.speed_mps, launch.launch_rad, launch.height_m
    up = v * math.sin(a)
    t = (up + math.sqrt(up * up + 2.0 * g_mps2 * h)) / g_mps2
    return v * math.cos(a) * t, t


def time_to_travel(
    speed_mps: float,
    distance_m: float = RELEASE_TO_PLATE_M,
    *,
    backspin_radps: float = 0.0,
    ball: Ball = presets.BASEBALL,
    aero: Aerodynamics = NATHAN_2008,
    air: Air = Air(),
    g_mps2: float = G_MPS2,
    rtol: float = 1e-10,
) -> Travel:
    """A pitch released horizontally along +x at ``speed_mps`` with ``backspin_radps`` (> 0
    lifts): the time until it has covered ``distance_m`` horizontally, its speed then, and its
    drop. Gravity acts (g_mps2 = 0 turns it off); the ground does not stop it. Default distance:
    release to the point of home plate (``RELEASE_TO_PLATE_M``)."""
    checks.in_range("speed_mps", speed_mps, 0.0, MAX_SPEED_MPS, lo_open=True)
    checks.in_range("distance_m", distance_m, 0.0, 1e3, lo_open=True)
    checks.finite("backspin_radps", backspin_radps)
    checks.non_negative("g_mps2", g_mps2)
    checks.in_range("rtol", rtol, 1e-13, 1e-3)
    rhs = _acceleration(ball, aero, air, g_mps2, np.array([0.0, -backspin_radps, 0.0]))
    arrive = _event(lambda t, y: y[0] - distance_m, terminal=True, direction=1.0)
    sol = _solve(
        rhs,
        np.array([0.0, 0.0, 0.0, speed_mps, 0.0, 0.0]),
        100.0 * distance_m / speed_mps + 10.0,
        [arrive],
        rtol,
    )
    end = sol.y_events[0][0]
    return Travel(
        time_s=float(sol.t_events[0][0]),
        arrival_speed_mps=float(np.linalg.norm(end[3:])),
        drop_m=-float(end[2]),
    )


def impact_to_field(vector: ArrayLike) -> np.ndarray:
    """A vector (velocity or spin) from the impact frame (x along the bat's axis toward the
    barrel, y from the bat toward the outfield, horizontal, z = x cross y up) to the field frame
    with x along the impact frame's y: (x, y, z) -> (y, -x, z), a rotation about z."""
    v = _vec3("vector", vector)
    return np.array([v[1], -v[0], v[2]])


def batted_ball_launch(
    velocity_mps: ArrayLike, spin_radps: ArrayLike, *, height_m: float = 0.9
) -> Launch:
    """The ``Launch`` of a ball leaving the bat with ``velocity_mps`` and ``spin_radps``
    (impact frame, ``impact_to_field``): speed |v|, launch angle atan2(v_z, hypot(v_x, v_y)),
    spray angle atan2(-v_x, v_y) (toward -x, the knob's side, is +), backspin and sidespin the
    spin's components along ``Launch.spin_radps``'s axes. A ball leaving along +y with w_x > 0
    has backspin. The spin along the velocity (gyrospin, no Magnus force at launch) is dropped:
    ``fly_vectors(r, impact_to_field(v), impact_to_field(w))`` keeps it."""
    v, w = impact_to_field(velocity_mps), impact_to_field(spin_radps)
    horizontal = math.hypot(v[0], v[1])
    if not horizontal > 0.0:
        raise ValueError(
            f"velocity_mps={tuple(map(float, velocity_mps))!r} has no horizontal "
            "part: no backspin axis; allowed: hypot(v_x, v_y) > 0"
        )
    speed = float(np.linalg.norm(v))
    vhat = v / speed
    back = np.cross(vhat, [0.0, 0.0, 1.0]) * (speed / horizontal)  # unit: |v^ x z^| = h / |v|
    side = np.cross(back, vhat)
    return Launch(
        speed_mps=speed,
        launch_rad=math.atan2(v[2], horizontal),
        direction_rad=math.atan2(v[1], v[0]),
        height_m=height_m,
        backspin_radps=float(w @ back),
        sidespin_radps=float(w @ side),
    )
