"""The general two-body collision impulse in 3D (seed 002, EQ 141), for any inertia tensors.

The planar formulas of ``analytic.impact`` are its special case (tests check they agree).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike

from . import checks


def _vec3(name: str, x: ArrayLike) -> np.ndarray:
    a = checks.array_in_range(name, x)
    if a.shape != (3,):
        raise ValueError(f"{name} has shape {a.shape}; allowed: a 3-vector")
    return a


@dataclass(frozen=True, kw_only=True, eq=False)
class RigidBody3D:
    """A rigid body's mass properties and velocity at one instant, in the world frame.

    Units: ``mass_kg`` kg; ``inertia_kgm2`` the 3x3 inertia tensor about the COM (kg m^2);
    ``velocity_mps`` the COM velocity (m/s); ``omega_radps`` the angular velocity (rad/s).
    """

    mass_kg: float
    inertia_kgm2: np.ndarray
    velocity_mps: np.ndarray = field(default_factory=lambda: np.zeros(3))
    omega_radps: np.ndarray = field(default_factory=lambda: np.zeros(3))

    def __post_init__(self) -> None:
        checks.positive("mass_kg", self.mass_kg)
        inertia = checks.array_in_range("inertia_kgm2", self.inertia_kgm2)
        if inertia.shape != (3, 3):
            raise ValueError(f"inertia_kgm2 has shape {inertia.shape}; allowed: 3x3")
        scale = np.max(np.abs(inertia))
        if not np.allclose(inertia, inertia.T, rtol=0.0, atol=1e-12 * scale):
            raise ValueError("inertia_kgm2 is not symmetric; allowed: a symmetric 3x3 tensor")
        if np.min(np.linalg.eigvalsh(inertia)) <= 0.0:
            raise ValueError("inertia_kgm2 is not positive definite; allowed: eigenvalues > 0")
        object.__setattr__(self, "inertia_kgm2", inertia)
        object.__setattr__(self, "velocity_mps", _vec3("velocity_mps", self.velocity_mps))
        object.__setattr__(self, "omega_radps", _vec3("omega_radps", self.omega_radps))

    def point_velocity(self, r_m: np.ndarray) -> np.ndarray:
        """Velocity of the body point at r from the COM: v + omega x r (m/s)."""
        return self.velocity_mps + np.cross(self.omega_radps, r_m)

    def kinetic_energy_j(self) -> float:
        """(m v.v + omega.I omega) / 2 (J)."""
        return 0.5 * (
            self.mass_kg * self.velocity_mps @ self.velocity_mps
            + self.omega_radps @ self.inertia_kgm2 @ self.omega_radps
        )


@dataclass(frozen=True, kw_only=True, eq=False)
class Impulse3D:
    """Result of ``impulse_3d``: the impulse magnitude j (N s, along n on A), both bodies after."""

    j_ns: float
    a: RigidBody3D
    b: RigidBody3D


def impulse_3d(
    a: RigidBody3D,
    b: RigidBody3D,
    *,
    r_a_m: ArrayLike,
    r_b_m: ArrayLike,
    normal: ArrayLike,
    e: float,
) -> Impulse3D:
    """Frictionless impulse between bodies A and B touching at one point (EQ 141).

    n is the contact normal pointing from B to A; r_A, r_B go from each COM to the contact point.
        v_rel = n . (pdot_A - pdot_B),   pdot = v + omega x r
        j = -(1 + e) v_rel / (1/M_A + 1/M_B + n.((I_A^-1 (r_A x n)) x r_A)
                                           + n.((I_B^-1 (r_B x n)) x r_B))
        v_A += j n / M_A,  omega_A += I_A^-1 (r_A x j n);  B gets -j n.
    Raises ValueError unless the contact points approach (v_rel < 0).
    """
    r_a, r_b = _vec3("r_a_m", r_a_m), _vec3("r_b_m", r_b_m)
    n = _vec3("normal", normal)
    norm = np.linalg.norm(n)
    if norm == 0.0:
        raise ValueError("normal is the zero vector; allowed: a non-zero 3-vector")
    n = n / norm
    checks.in_range("e", e, 0.0, 1.0)
    v_rel = float(n @ (a.point_velocity(r_a) - b.point_velocity(r_b)))
    if not v_rel < 0.0:
        raise ValueError(
            f"relative normal velocity v_rel={v_rel!r} m/s: the bodies do not "
            "approach; allowed: v_rel < 0"
        )
    inv_a = np.linalg.inv(a.inertia_kgm2)
    inv_b = np.linalg.inv(b.inertia_kgm2)
    denom = (
        1.0 / a.mass_kg
        + 1.0 / b.mass_kg
        + n @ np.cross(inv_a @ np.cross(r_a, n), r_a)
        + n @ np.cross(inv_b @ np.cross(r_b, n), r_b)
    )
    j = -(1.0 + e) * v_rel / denom
    a1, b1 = apply_impulse(a, b, r_a, r_b, j * n)
    return Impulse3D(j_ns=float(j), a=a1, b=b1)


def apply_impulse(
    a: RigidBody3D, b: RigidBody3D, r_a: np.ndarray, r_b: np.ndarray, impulse: np.ndarray
) -> tuple[RigidBody3D, RigidBody3D]:
    """Both bodies after the impulse P on A at r_A (and -P on B at r_B): v += P/M,
    omega += I^-1 (r x P)."""

    def kicked(body: RigidBody3D, r: np.ndarray, P: np.ndarray) -> RigidBody3D:
        return RigidBody3D(
            mass_kg=body.mass_kg,
            inertia_kgm2=body.inertia_kgm2,
            velocity_mps=body.velocity_mps + P / body.mass_kg,
            omega_radps=body.omega_radps + np.linalg.inv(body.inertia_kgm2) @ np.cross(r, P),
        )

    return kicked(a, r_a, impulse), kicked(b, r_b, -impulse)
