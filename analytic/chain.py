"""A segmented bat: N rigid segments joined by torsional springs, and its exact linear impact.

What an engine can build of a flexible bat: ``Chain.from_beam`` cuts the beam into N equal
segments (each with the mass, COM and J_cm of its slice of the profile) and joins neighbours at
their common end by a torsional spring of stiffness k_j = 1 / int dx / (E I) over the length
l = L/N centred on the joint, the bending compliance that joint stands for. As N grows, the
chain's low modes tend to the Euler-Bernoulli beam's.

The chain's small transverse motion is linear. Its coordinates are the knob end's displacement
y0 and each segment's angle theta_i; a point x on segment i moves by
y(x) = y0 + sum_{j<i} l theta_j + (x - a_i) theta_i, its row of the Jacobian ``point_row``.
M = sum_i m_i b(c_i) b(c_i)^T + J_i e_i e_i^T and K = sum_j k_j (e_j+1 - e_j)(e_j+1 - e_j)^T
(e_i the unit vector of theta_i). ``analytic.chain_impact`` solves a ball's impact on it
exactly: in modal coordinates between contacts, with Newton's restitution at each contact of
a rigid engine or under the compliant law of a soft one. This is the reference an engine's
chain is judged against: exact for the chain, not for the beam.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property

import numpy as np
from scipy import linalg

from . import checks
from .beam import RIGID_MODES, Beam
from .model import Bat

#: Segment counts a chain may have.
SEGMENTS_RANGE = (2, 256)


@dataclass(frozen=True, kw_only=True)
class Chain:
    """N rigid segments along x from the knob (x = 0) to the barrel end: segment i spans
    [i l, (i+1) l], l = length / N. Per segment ``masses_kg`` (kg), ``coms_m`` (m from the
    knob) and ``inertias_kgm2`` (about its own COM, kg m^2); per joint (N - 1, joint j between
    segments j and j+1) ``stiffnesses_nmprad`` (N m/rad) and ``dampings_nmsprad`` (N m s/rad).
    ``bat`` is the whole as a rigid bat (its name, capsule radius and mass properties)."""

    bat: Bat
    masses_kg: tuple[float, ...]
    coms_m: tuple[float, ...]
    inertias_kgm2: tuple[float, ...]
    stiffnesses_nmprad: tuple[float, ...]
    dampings_nmsprad: tuple[float, ...]

    def __post_init__(self) -> None:
        n = len(self.masses_kg)
        checks.integer("segments", n, *SEGMENTS_RANGE)
        for name in ("coms_m", "inertias_kgm2"):
            if len(getattr(self, name)) != n:
                raise ValueError(f"{name}: {len(getattr(self, name))} values for {n} segments")
        for name in ("stiffnesses_nmprad", "dampings_nmsprad"):
            if len(getattr(self, name)) != n - 1:
                raise ValueError(f"{name}: {len(getattr(self, name))} values for {n - 1} joints")
        checks.array_in_range("masses_kg", self.masses_kg, 0.0)
        checks.array_in_range("inertias_kgm2", self.inertias_kgm2, 0.0)
        checks.array_in_range("stiffnesses_nmprad", self.stiffnesses_nmprad, 0.0)
        checks.array_in_range("dampings_nmsprad", self.dampings_nmsprad, 0.0)

    @classmethod
    def from_beam(
        cls, beam: Beam, segments: int, *, like: Bat, damping_nmsprad: float = 0.0
    ) -> Chain:
        """``segments`` equal slices of ``beam``; ``like`` gives the name and capsule radius."""
        checks.integer("segments", segments, *SEGMENTS_RANGE)
        checks.non_negative("damping_nmsprad", damping_nmsprad)
        length = beam.profile.length_m
        cuts = np.linspace(0.0, length, segments + 1)
        masses, coms, inertias = [], [], []
        for a, b in zip(cuts[:-1], cuts[1:], strict=True):
            piece = _slice(beam, a, b)
            masses.append(piece["mass_kg"])
            coms.append(piece["com_from_knob_m"])
            inertias.append(piece["inertia_cm_kgm2"])
        half = length / segments / 2.0
        springs = tuple(1.0 / _bending_compliance(beam, x - half, x + half) for x in cuts[1:-1])
        return cls(
            bat=beam.rigid_bat(like),
            masses_kg=tuple(masses),
            coms_m=tuple(coms),
            inertias_kgm2=tuple(inertias),
            stiffnesses_nmprad=springs,
            dampings_nmsprad=(damping_nmsprad,) * (segments - 1),
        )

    @property
    def segments(self) -> int:
        return len(self.masses_kg)

    @property
    def segment_length_m(self) -> float:
        return self.bat.length_m / self.segments

    def segment_of(self, x_m: float) -> int:
        """The segment holding the axis point ``x_m`` (m from the knob)."""
        checks.in_range("x_m", x_m, 0.0, self.bat.length_m)
        return min(int(x_m / self.segment_length_m), self.segments - 1)

    def point_row(self, x_m: float) -> np.ndarray:
        """dy(x)/dq: the transverse displacement of axis point ``x_m`` per coordinate."""
        i, ell = self.segment_of(x_m), self.segment_length_m
        row = np.zeros(self.segments + 1)
        row[0] = 1.0
        row[1 : i + 1] = ell
        row[i + 1] = x_m - i * ell
        return row

    @cached_property
    def matrices(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Mass, stiffness and damping matrices in (y0, theta_1 .. theta_N)."""
        n = self.segments
        M, K, C = (np.zeros((n + 1, n + 1)) for _ in range(3))
        for i, (m, c, J) in enumerate(
            zip(self.masses_kg, self.coms_m, self.inertias_kgm2, strict=True)
        ):
            b = self.point_row(min(c, self.bat.length_m))
            b[i + 2 :] = 0.0
            b[i + 1] = c - i * self.segment_length_m
            M += m * np.outer(b, b)
            M[i + 1, i + 1] += J
        for j, (k, d) in enumerate(
            zip(self.stiffnesses_nmprad, self.dampings_nmsprad, strict=True)
        ):
            diff = np.zeros(n + 1)
            diff[j + 1], diff[j + 2] = -1.0, 1.0
            K += k * np.outer(diff, diff)
            C += d * np.outer(diff, diff)
        return M, K, C

    @cached_property
    def modes(self) -> tuple[np.ndarray, np.ndarray]:
        """(angular frequencies (rad/s), mass-normalised mode vectors as columns), rigid-body
        modes first (their frequency set to exactly 0)."""
        M, K, _ = self.matrices
        lam, vec = linalg.eigh(K, M)
        omega = np.sqrt(np.clip(lam, 0.0, None))
        omega[:RIGID_MODES] = 0.0  # translation and rotation (roundoff lifts them off zero)
        return omega, vec

    @property
    def frequencies_hz(self) -> np.ndarray:
        """The bending modes' frequencies (Hz), lowest first."""
        omega, _ = self.modes
        return omega[omega > 0.0] / (2 * math.pi)


def _quadrature(beam: Beam, a: float, b: float):
    """Gauss points and weights over [a, b], split at the profile's kinks (exact there)."""
    stations = np.asarray(beam.profile.stations_m)
    nodes = np.unique(np.concatenate([[a, b], stations[(stations > a) & (stations < b)]]))
    x0, x1 = nodes[:-1], nodes[1:]
    gx, gw = np.polynomial.legendre.leggauss(8)
    pts = x0[:, None] + (x1 - x0)[:, None] * (gx + 1) / 2
    return pts, (x1 - x0)[:, None] * gw / 2


def _slice(beam: Beam, a: float, b: float) -> dict:
    """Mass, COM and J of the beam between a and b."""
    pts, wts = _quadrature(beam, a, b)
    area, second = beam._sections(pts)
    rho = beam.wood.density_kgpm3
    mass = float(np.sum(rho * area * wts))
    com = float(np.sum(rho * area * pts * wts)) / mass
    inertia = float(np.sum(rho * (area * (pts - com) ** 2 + second) * wts))
    return {"mass_kg": mass, "com_from_knob_m": com, "inertia_cm_kgm2": inertia}


def _bending_compliance(beam: Beam, a: float, b: float) -> float:
    """int_a^b dx / (E I(x)) (rad per N m), clipped to the bat (1/r^4 is smooth between
    kinks: 8 Gauss points per piece leave under 1e-9 of it)."""
    pts, wts = _quadrature(beam, max(a, 0.0), min(b, beam.profile.length_m))
    _, second = beam._sections(pts)
    E = beam.wood.youngs_modulus_pa * beam.stiffness_scale
    return float(np.sum(wts / (E * second)))
