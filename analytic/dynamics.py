"""Forces and torques on a bat, free or hinged at the hands: closed form and reference integration.

The seed lecture's rigid body in 2D: a force f applied at a body point at angle q to the body's
axis, held fixed in the body frame (a 'thruster'), plus a torque tau. With the force at r from the
COM along the axis, the torque about the COM is tau + r f sin(q), constant in time, so
    omega(t) = omega_0 + (tau + r f sin q) t / J,   theta(t) = theta_0 + ... t^2/2,
and the COM is pushed by f (cos(theta + q), sin(theta + q)) / M, which turns with the body; that
has a closed form only when theta is constant (no net torque), otherwise ``motion`` integrates it
with scipy's solve_ivp at rtol 1e-12. A bat hinged at a pivot x_p turns about it with
    I_p alpha = tau + (x_f - x_p) f sin q,   I_p = J + M (x_cm - x_p)^2,
closed form for any constant load. The bat starts at rest; angles are of the axis to world x.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy import integrate

from . import checks
from .model import Bat

#: solve_ivp tolerances for the reference: relative, and absolute (the state is of order 1).
REFERENCE_RTOL = 1e-12
REFERENCE_ATOL = 1e-14


@dataclass(frozen=True, kw_only=True)
class Drive:
    """Loads on the bat, constant in the bat's own frame, and an optional hinge.

    Units: ``force_n`` N, applied at ``force_at_from_knob_m`` on the axis (None: the COM) at
    ``force_angle_rad`` to the axis (counter-clockwise from the knob-to-barrel direction);
    ``torque_nm`` N m about z; ``pivot_from_knob_m`` the hinge point, fixed in the world (None:
    a free bat).
    """

    force_n: float = 0.0
    force_angle_rad: float = 0.0
    force_at_from_knob_m: float | None = None
    torque_nm: float = 0.0
    pivot_from_knob_m: float | None = None

    def __post_init__(self) -> None:
        checks.finite("force_n", self.force_n)
        checks.finite("force_angle_rad", self.force_angle_rad)
        checks.finite("torque_nm", self.torque_nm)
        if self.force_at_from_knob_m is not None:
            checks.finite("force_at_from_knob_m", self.force_at_from_knob_m)
        if self.pivot_from_knob_m is not None:
            checks.finite("pivot_from_knob_m", self.pivot_from_knob_m)

    def check(self, bat: Bat) -> None:
        """Raise ValueError unless the load point and the pivot lie on the bat."""
        for name in ("force_at_from_knob_m", "pivot_from_knob_m"):
            x = getattr(self, name)
            if x is not None:
                checks.in_range(name, x, 0.0, bat.length_m)
        if self.pivot_from_knob_m is not None and self.pivot_from_knob_m == bat.com_from_knob_m:
            raise ValueError(
                f"pivot_from_knob_m={self.pivot_from_knob_m!r} is the COM: a hinge "
                "there carries no load; allowed: any other point of the bat"
            )

    def force_arm_m(self, bat: Bat) -> float:
        """Signed distance of the load point from the COM along the axis (m)."""
        x = bat.com_from_knob_m if self.force_at_from_knob_m is None else self.force_at_from_knob_m
        return x - bat.com_from_knob_m

    def torque_about_com_nm(self, bat: Bat) -> float:
        """tau + r f sin(q): constant, because the force turns with the bat (N m)."""
        arm_m = self.force_arm_m(bat)
        return self.torque_nm + arm_m * self.force_n * math.sin(self.force_angle_rad)


@dataclass(frozen=True, kw_only=True)
class MotionState:
    """The bat's COM and orientation at time ``t_s``. Units: s, m, rad, m/s, rad/s (world)."""

    t_s: float
    x_m: float
    y_m: float
    angle_rad: float
    vx_mps: float
    vy_mps: float
    omega_radps: float


def start_state(bat: Bat, drive: Drive, angle_rad: float = 0.0) -> MotionState:
    """At rest at ``angle_rad``; free: COM at the origin; hinged: the pivot at the origin."""
    if drive.pivot_from_knob_m is None:
        return MotionState(
            t_s=0.0, x_m=0.0, y_m=0.0, angle_rad=angle_rad, vx_mps=0.0, vy_mps=0.0, omega_radps=0.0
        )
    d = bat.com_from_knob_m - drive.pivot_from_knob_m
    return MotionState(
        t_s=0.0,
        x_m=d * math.cos(angle_rad),
        y_m=d * math.sin(angle_rad),
        angle_rad=angle_rad,
        vx_mps=0.0,
        vy_mps=0.0,
        omega_radps=0.0,
    )


def has_closed_form(bat: Bat, drive: Drive) -> bool:
    """Hinged bats always; free bats when the force does not turn (no torque about the COM)."""
    return (
        drive.pivot_from_knob_m is not None
        or drive.force_n == 0.0
        or drive.torque_about_com_nm(bat) == 0.0
    )


def motion(bat: Bat, drive: Drive, t_s: float, angle_rad: float = 0.0) -> MotionState:
    """The state at ``t_s`` from rest at ``angle_rad``: closed form where one exists, else the
    reference integration (``motion_integrated``)."""
    drive.check(bat)
    checks.non_negative("t_s", t_s)
    if not has_closed_form(bat, drive):
        return motion_integrated(bat, drive, t_s, angle_rad)
    if drive.pivot_from_knob_m is not None:
        x_p = drive.pivot_from_knob_m
        d = bat.com_from_knob_m - x_p
        torque = drive.torque_nm + (drive.force_arm_m(bat) + d) * drive.force_n * math.sin(
            drive.force_angle_rad
        )
        alpha = torque / bat.inertia_about(x_p)
        th, w = angle_rad + 0.5 * alpha * t_s**2, alpha * t_s
        c, s = math.cos(th), math.sin(th)
        return MotionState(
            t_s=t_s,
            x_m=d * c,
            y_m=d * s,
            angle_rad=th,
            vx_mps=-w * d * s,
            vy_mps=w * d * c,
            omega_radps=w,
        )
    alpha = drive.torque_about_com_nm(bat) / bat.inertia_cm_kgm2
    a = drive.force_n / bat.mass_kg
    direction = angle_rad + drive.force_angle_rad  # the body does not turn when a is non-zero
    ax, ay = a * math.cos(direction), a * math.sin(direction)
    return MotionState(
        t_s=t_s,
        x_m=0.5 * ax * t_s**2,
        y_m=0.5 * ay * t_s**2,
        angle_rad=angle_rad + 0.5 * alpha * t_s**2,
        vx_mps=ax * t_s,
        vy_mps=ay * t_s,
        omega_radps=alpha * t_s,
    )


def motion_integrated(bat: Bat, drive: Drive, t_s: float, angle_rad: float = 0.0) -> MotionState:
    """The same motion by numerical integration (solve_ivp, DOP853, rtol REFERENCE_RTOL).

    Free bat: x'' = f cos(theta + q)/M, y'' = f sin(theta + q)/M, theta'' = (tau + r f sin q)/J.
    Hinged bat: theta'' = torque about the pivot / I_p, the COM on its circle.
    """
    drive.check(bat)
    s0 = start_state(bat, drive, angle_rad)
    if t_s == 0.0:
        return s0
    M, f, q = bat.mass_kg, drive.force_n, drive.force_angle_rad
    if drive.pivot_from_knob_m is not None:
        x_p = drive.pivot_from_knob_m
        d = bat.com_from_knob_m - x_p
        torque = drive.torque_nm + (drive.force_arm_m(bat) + d) * f * math.sin(q)
        inertia = bat.inertia_about(x_p)

        def rhs(t, y):
            return [y[1], torque / inertia]

        sol = integrate.solve_ivp(
            rhs,
            (0.0, t_s),
            [angle_rad, 0.0],
            method="DOP853",
            rtol=REFERENCE_RTOL,
            atol=REFERENCE_ATOL,
        )
        th, w = sol.y[:, -1]
        return MotionState(
            t_s=t_s,
            x_m=d * math.cos(th),
            y_m=d * math.sin(th),
            angle_rad=th,
            vx_mps=-w * d * math.sin(th),
            vy_mps=w * d * math.cos(th),
            omega_radps=w,
        )
    alpha = drive.torque_about_com_nm(bat) / bat.inertia_cm_kgm2

    def rhs(t, y):
        return [y[3], y[4], y[5], f * math.cos(y[2] + q) / M, f * math.sin(y[2] + q) / M, alpha]

    sol = integrate.solve_ivp(
        rhs,
        (0.0, t_s),
        [s0.x_m, s0.y_m, angle_rad, 0.0, 0.0, 0.0],
        method="DOP853",
        rtol=REFERENCE_RTOL,
        atol=REFERENCE_ATOL,
    )
    x, y, th, vx, vy, w = sol.y[:, -1]
    return MotionState(t_s=t_s, x_m=x, y_m=y, angle_rad=th, vx_mps=vx, vy_mps=vy, omega_radps=w)


@dataclass(frozen=True, kw_only=True)
class HingedSwing:
    """A swing from rest about the hands under a constant torque, up to the impact.

    Units: ``torque_nm`` N m; ``hands_from_knob_m`` the pivot (m from the knob); ``angle_rad``
    the angle swept before impact. Work-energy: tau theta = I_p omega^2 / 2, so at impact
    omega0 = sqrt(2 tau theta / I_p) after t = sqrt(2 theta I_p / tau), and the COM moves at
    u0 = omega0 d, d = x_cm - x_hands: u0 and omega0 come from one swing.
    """

    torque_nm: float
    hands_from_knob_m: float = 0.1
    angle_rad: float = math.pi / 2

    def __post_init__(self) -> None:
        checks.positive("torque_nm", self.torque_nm)
        checks.in_range("angle_rad", self.angle_rad, 0.0, 2 * math.pi, lo_open=True)
        checks.non_negative("hands_from_knob_m", self.hands_from_knob_m)

    def drive(self) -> Drive:
        """The swing as a Drive: the torque, hinged at the hands."""
        return Drive(torque_nm=self.torque_nm, pivot_from_knob_m=self.hands_from_knob_m)

    def arm_m(self, bat: Bat) -> float:
        """d = x_cm - x_hands (m)."""
        checks.in_range(
            "hands_from_knob_m", self.hands_from_knob_m, 0.0, bat.com_from_knob_m, hi_open=True
        )
        return bat.com_from_knob_m - self.hands_from_knob_m

    def duration_s(self, bat: Bat) -> float:
        """t = sqrt(2 theta I_p / tau) (s)."""
        return math.sqrt(
            2 * self.angle_rad * bat.inertia_about(self.hands_from_knob_m) / self.torque_nm
        )

    def omega_at(self, bat: Bat, t_s: float) -> float:
        """omega = tau t / I_p (rad/s)."""
        return self.torque_nm * t_s / bat.inertia_about(self.hands_from_knob_m)

    def angle_swept(self, bat: Bat, t_s: float) -> float:
        """tau t^2 / (2 I_p) (rad)."""
        return 0.5 * self.torque_nm * t_s**2 / bat.inertia_about(self.hands_from_knob_m)

    @classmethod
    def for_omega(
        cls,
        bat: Bat,
        omega0_radps: float,
        *,
        hands_from_knob_m: float = 0.1,
        angle_rad: float = math.pi / 2,
    ) -> HingedSwing:
        """The torque that brings ``bat`` to omega0 over ``angle_rad``: I_p omega0^2/(2 theta)."""
        checks.positive("omega0_radps", omega0_radps)
        torque = bat.inertia_about(hands_from_knob_m) * omega0_radps**2 / (2 * angle_rad)
        return cls(torque_nm=torque, hands_from_knob_m=hands_from_knob_m, angle_rad=angle_rad)


def state_array(s: MotionState) -> np.ndarray:
    """(x, y, angle, vx, vy, omega) as an array, for comparisons."""
    return np.array([s.x_m, s.y_m, s.angle_rad, s.vx_mps, s.vy_mps, s.omega_radps])
