"""The scene records: a bat, a ball and one impact between them.

Conventions (see DESIGN.md): the bat axis is x, from the knob (x = 0) to the barrel end (x = L);
the swing plane is x-y and y points from the bat toward the ball. ``s`` is the impact point's
distance from the bat's centre of mass (COM) along the axis, positive toward the barrel. The ball
approaches with speed ``v0``; the bat's COM moves toward the ball with ``u0`` and spins with
``omega0`` about z (positive: the barrel end moves toward the ball).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from . import checks

#: The bat's wood (kg/m^3), one value for every model of the R161: the density at which its
#: fitted profile (``presets.r161_profile``: knob, handle, flared taper, 2.5 in barrel) has the
#: R161's mass, balance point and J_cm. Inside white ash's specific gravity, 0.55-0.67 (USDA
#: Wood Handbook, FPL-GTR-190, 2010, ch. 5). The cork model drills its hole
#: in this wood; tests re-derive it from the fit.
WOOD_DENSITY_KGM3 = 584.4235903446794

#: The largest coefficient of friction accepted: beyond a few, every impact grips.
MAX_MU = 10.0
#: The largest speed (m/s) of a ball or a bat's COM, and spin (rad/s) of a bat, accepted: three
#: times the speed of sound, near twenty times the hardest-hit balls (MLB Statcast: about 122
#: mph, 55 m/s); the rigid impact means nothing there, and energies stay far from overflowing.
MAX_SPEED_MPS = 1_000.0
MAX_OMEGA_RADPS = 1_000.0
#: A ball's spin (rad/s): its surface then moves at up to 10 times MAX_SPEED_MPS; pitches spin
#: at up to about 3,500 rpm, 370 rad/s (MLB Statcast).
MAX_SPIN_RADPS = 10_000.0


@dataclass(frozen=True, kw_only=True)
class Bat:
    """A bat as the impact model sees it: a rigid body with a capsule for a surface.

    Units: lengths in m, mass in kg, moments of inertia in kg m^2. ``inertia_cm_kgm2`` is the
    transverse moment (about an axis through the COM perpendicular to the bat); the capsule
    (``length_m`` overall, ``radius_m``) only gives the engines a surface to hit, the mass
    properties are set, not derived from it, because a real bat is not a uniform capsule.
    """

    name: str
    length_m: float
    radius_m: float
    mass_kg: float
    com_from_knob_m: float
    inertia_cm_kgm2: float
    #: Moment about the long axis; only 3D engines need it and the planar impact never excites it.
    #: ``None`` means that of a solid cylinder of the capsule's radius, M r^2 / 2.
    inertia_axial_kgm2: float | None = None

    def __post_init__(self) -> None:
        checks.positive("length_m", self.length_m)
        checks.in_range("radius_m", self.radius_m, 0.0, self.length_m / 2, lo_open=True)
        checks.positive("mass_kg", self.mass_kg)
        checks.in_range("com_from_knob_m", self.com_from_knob_m, 0.0, self.length_m)
        checks.positive("inertia_cm_kgm2", self.inertia_cm_kgm2)
        if self.inertia_axial_kgm2 is not None:
            checks.positive("inertia_axial_kgm2", self.inertia_axial_kgm2)
        # a bat's mass spans its capsule: its J is no less than that of a disk of the capsule's
        # radius at the COM, M r^2 / 4 (a heavy 'wall' bat, J >> M L^2, stays allowed)
        checks.in_range(
            "inertia_cm_kgm2", self.inertia_cm_kgm2, self.mass_kg * self.radius_m**2 / 4
        )

    @property
    def axial_inertia_kgm2(self) -> float:
        """Moment about the long axis (kg m^2), with the solid-cylinder default filled in."""
        if self.inertia_axial_kgm2 is not None:
            return self.inertia_axial_kgm2
        return 0.5 * self.mass_kg * self.radius_m**2

    @property
    def s_min_m(self) -> float:
        """Lowest hittable s (m): where the capsule's cylinder starts at the knob end."""
        return self.radius_m - self.com_from_knob_m

    @property
    def s_max_m(self) -> float:
        """Highest hittable s (m): where the capsule's cylinder ends at the barrel end."""
        return self.length_m - self.radius_m - self.com_from_knob_m

    @property
    def s_barrel_end_m(self) -> float:
        """s of the barrel end itself (m)."""
        return self.length_m - self.com_from_knob_m

    def inertia_about(self, pivot_from_knob_m: float) -> float:
        """Transverse moment of inertia (kg m^2) about a pivot on the axis (parallel axes):
        I_p = J_cm + M (x_cm - x_p)^2."""
        x_p = checks.in_range("pivot_from_knob_m", pivot_from_knob_m, 0.0, self.length_m)
        return self.inertia_cm_kgm2 + self.mass_kg * (self.com_from_knob_m - x_p) ** 2

    @property
    def inertia_knob_kgm2(self) -> float:
        """Transverse moment of inertia about the knob end (kg m^2), the 'swing weight'."""
        return self.inertia_about(0.0)

    def check_s(self, s_m: float, name: str = "s_m") -> float:
        """Return ``s_m`` if it lies on the bat (between knob and barrel end), else raise."""
        return checks.in_range(name, s_m, -self.com_from_knob_m, self.s_barrel_end_m)


@dataclass(frozen=True, kw_only=True)
class Ball:
    """A ball: a uniform sphere. Units: mass in kg, radius in m."""

    name: str
    mass_kg: float
    radius_m: float

    def __post_init__(self) -> None:
        checks.positive("mass_kg", self.mass_kg)
        checks.positive("radius_m", self.radius_m)

    @property
    def inertia_kgm2(self) -> float:
        """Moment of inertia of a uniform sphere, 2 m r^2 / 5 (kg m^2)."""
        return 0.4 * self.mass_kg * self.radius_m**2


@dataclass(frozen=True, kw_only=True)
class ImpactCase:
    """One impact: bat, ball, where they meet and how they move just before.

    Units: ``s_m`` in m from the COM (barrel side positive); ``v0_mps`` the ball's speed (m/s);
    ``u0_mps`` the speed of the bat's COM (m/s); ``omega0_radps`` the bat's angular speed (rad/s);
    ``theta_rad`` the angle of the ball's velocity to the contact normal and ``phi_rad`` that of
    the bat's COM velocity (rad; both tilt toward +x, the barrel, in the swing plane);
    ``hands_from_knob_m`` the hand point whose velocity change is reported (m from the knob).
    Friction and the third dimension (``analytic.friction``): ``mu`` the Coulomb coefficient
    between ball and bat (0: frictionless); ``undercut_m`` the ball centre's offset from the
    bat's axis along z, out of the swing plane, at contact (m; the contact normal tilts by
    asin(undercut / (r_bat + r_ball))); ``spin_radps`` the ball's spin before the impact
    (rad/s about x, y, z: +x with the ball leaving along +y is backspin).
    """

    bat: Bat
    ball: Ball
    s_m: float
    v0_mps: float
    u0_mps: float = 0.0
    omega0_radps: float = 0.0
    e: float = 0.5
    theta_rad: float = 0.0
    phi_rad: float = 0.0
    hands_from_knob_m: float = 0.1
    mu: float = 0.0
    undercut_m: float = 0.0
    spin_radps: tuple[float, float, float] = (0.0, 0.0, 0.0)

    def __post_init__(self) -> None:
        checks.instance("bat", self.bat, Bat)
        checks.instance("ball", self.ball, Ball)
        self.bat.check_s(self.s_m)
        checks.in_range("v0_mps", self.v0_mps, 0.0, MAX_SPEED_MPS)
        checks.in_range("u0_mps", self.u0_mps, -MAX_SPEED_MPS, MAX_SPEED_MPS)
        checks.in_range("omega0_radps", self.omega0_radps, -MAX_OMEGA_RADPS, MAX_OMEGA_RADPS)
        checks.in_range("e", self.e, 0.0, 1.0)
        checks.in_range(
            "theta_rad", self.theta_rad, -math.pi / 2, math.pi / 2, lo_open=True, hi_open=True
        )
        checks.in_range("phi_rad", self.phi_rad, -math.pi / 2, math.pi / 2)
        checks.in_range("hands_from_knob_m", self.hands_from_knob_m, 0.0, self.bat.length_m)
        checks.in_range("mu", self.mu, 0.0, MAX_MU)
        reach = self.bat.radius_m + self.ball.radius_m
        checks.in_range("undercut_m", self.undercut_m, -reach, reach, lo_open=True, hi_open=True)
        spin = tuple(
            checks.in_range(f"spin_radps[{i}]", w, -MAX_SPIN_RADPS, MAX_SPIN_RADPS)
            for i, w in enumerate(self.spin_radps)
        )
        if len(spin) != 3:
            raise ValueError(
                f"spin_radps={self.spin_radps!r} has {len(spin)} components; "
                "allowed: 3 (about x, y, z)"
            )
        object.__setattr__(self, "spin_radps", spin)
        vc = self.closing_speed_mps
        if not vc > 0.0:
            raise ValueError(
                f"closing speed v0*cos(theta) + u0*cos(phi) + omega0*s = {vc!r} m/s at s_m="
                f"{self.s_m!r}: the bodies do not approach; allowed: closing speed > 0"
            )

    @property
    def v0n_mps(self) -> float:
        """Normal component of the ball's approach speed, v0 cos(theta) (m/s)."""
        return self.v0_mps * math.cos(self.theta_rad)

    @property
    def u0n_mps(self) -> float:
        """Normal component of the bat COM's approach speed, u0 cos(phi) (m/s)."""
        return self.u0_mps * math.cos(self.phi_rad)

    @property
    def closing_speed_mps(self) -> float:
        """Closing speed of the contact points in the swing plane, v0n + u0n + omega0 s (m/s);
        along an undercut's tilted normal it is cos(tilt) times this."""
        return self.v0n_mps + self.u0n_mps + self.omega0_radps * self.s_m

    @property
    def tilt_rad(self) -> float:
        """The contact normal's tilt out of the swing plane, asin(undercut / (r_bat + r_ball))."""
        return math.asin(self.undercut_m / (self.bat.radius_m + self.ball.radius_m))

    @property
    def out_of_plane(self) -> bool:
        """Whether the impact leaves the swing plane: an undercut, or a spin about x or y."""
        return self.undercut_m != 0.0 or self.spin_radps[:2] != (0.0, 0.0)

    @property
    def frictionless_planar(self) -> bool:
        """Whether the planar frictionless model (``predict``, ``collide``) is the whole answer:
        no friction and nothing out of the swing plane (a spin about z alone changes nothing
        without friction)."""
        return self.mu == 0.0 and not self.out_of_plane


@dataclass(frozen=True, kw_only=True)
class Outcome:
    """The state just after an impact, and what the impact did.

    Velocities are in the contact frame: ``*_n`` along the normal y (positive: away from the bat
    for the ball, toward the ball for the bat), ``*_t`` along the bat axis x (positive toward the
    barrel). Units: m/s, rad/s, N s, J. ``v1_mps`` is the ball's normal velocity, the batted-ball
    speed of the planar model; for an oblique impact ``ball_speed_mps`` adds the tangential part.
    """

    v1_mps: float
    u1_mps: float
    omega1_radps: float
    impulse_ns: float
    q: float
    closing_speed_mps: float
    hand_dv_mps: float
    ke_before_j: float
    ke_after_j: float
    v1_t_mps: float = 0.0
    u1_t_mps: float = 0.0

    @property
    def energy_lost_j(self) -> float:
        """Kinetic energy dissipated by the impact (J)."""
        return self.ke_before_j - self.ke_after_j

    @property
    def ball_speed_mps(self) -> float:
        """The ball's speed after the impact, normal and tangential parts together (m/s)."""
        return math.hypot(self.v1_mps, self.v1_t_mps)

    @property
    def theta1_rad(self) -> float:
        """Angle of the ball's outgoing velocity to the contact normal (rad)."""
        return math.atan2(self.v1_t_mps, self.v1_mps)
