"""The bat as a free-free beam: its profile, its wood, its bending modes and nodes.

A wood bat is a solid of revolution whose radius varies along its length. Bending it, at the
frequencies a 0.7 ms impact reaches (below about 2 kHz), is Euler-Bernoulli's beam with rotary
inertia; Timoshenko's adds shear, which lowers the higher modes. Both are finite-element models
here, on a mesh that puts a node at every kink of the profile, with every integral exact
(Gauss-Legendre on polynomials), so that the beam's rigid-body mass, COM and inertia equal the
profile's to rounding and ``rigid_bat`` hands the rigid impact theory the very same body.

``R161_PROFILE`` is a piecewise-linear profile (knob, handle, taper, barrel) whose density and
taper are fitted to the R161's mass, balance point and J_cm (``presets.R161``); ``ASH`` is
white ash from the USDA Wood Handbook.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from functools import cached_property

import numpy as np
from scipy import interpolate, linalg, optimize

from . import checks
from .beam_fe import euler_bernoulli, timoshenko
from .model import Bat

#: A free-free beam moving in a plane has two rigid-body modes, translation and rotation.
RIGID_MODES = 2
_GAUSS_X, _GAUSS_W = np.polynomial.legendre.leggauss(5)  # exact to degree 9


@dataclass(frozen=True, kw_only=True)
class Wood:
    """A straight-grained wood along the bat's axis: Young's modulus ``youngs_modulus_pa``
    (Pa), shear modulus ``shear_modulus_pa`` (Pa) and density ``density_kgpm3`` (kg/m^3)."""

    name: str
    youngs_modulus_pa: float
    shear_modulus_pa: float
    density_kgpm3: float

    def __post_init__(self) -> None:
        checks.positive("youngs_modulus_pa", self.youngs_modulus_pa)
        checks.positive("shear_modulus_pa", self.shear_modulus_pa)
        checks.positive("density_kgpm3", self.density_kgpm3)


#: White ash, the R161's wood, at 12% moisture: E_L = 12.0 GPa, specific gravity 0.60 (USDA
#: Forest Products Laboratory, Wood Handbook, FPL-GTR-190 (2010), table 5-3a); G_LR = 0.080 E_L
#: (same handbook, table 5-1, the ratio for ash). The density is the R161 fit's (``R161_PROFILE``).
ASH = Wood(
    name="ash", youngs_modulus_pa=12.0e9, shear_modulus_pa=0.080 * 12.0e9, density_kgpm3=600.0
)


@dataclass(frozen=True, kw_only=True)
class Profile:
    """A bat's radius along its axis: ``radii_m`` (m) at ``stations_m`` (m from the knob end,
    increasing, the first 0 and the last the length), linear in between."""

    stations_m: tuple[float, ...]
    radii_m: tuple[float, ...]

    def __post_init__(self) -> None:
        if len(self.stations_m) != len(self.radii_m) or len(self.stations_m) < 2:
            raise ValueError(
                f"stations_m and radii_m must pair up, at least two: got "
                f"{len(self.stations_m)} and {len(self.radii_m)}"
            )
        checks.array_in_range("radii_m", self.radii_m, 0.0)
        if self.stations_m[0] != 0.0 or np.any(np.diff(self.stations_m) <= 0.0):
            raise ValueError(f"stations_m = {self.stations_m}: must start at 0 and increase")

    @property
    def length_m(self) -> float:
        return self.stations_m[-1]

    def radius_m(self, x_m):
        """Radius (m) at ``x_m`` (m from the knob)."""
        return np.interp(x_m, self.stations_m, self.radii_m)


@dataclass(frozen=True, kw_only=True)
class Beam:
    """A free-free beam of ``profile`` in ``wood``, ``elements`` finite elements (at least;
    the profile's kinks add nodes), Euler-Bernoulli (``shear`` False, Hermite cubics with rotary
    inertia) or Timoshenko (linear elements, reduced shear integration: no locking).
    ``stiffness_scale`` multiplies E and G (1e6: the rigid limit)."""

    profile: Profile
    wood: Wood
    elements: int = 160
    shear: bool = False
    stiffness_scale: float = 1.0

    def __post_init__(self) -> None:
        checks.integer("elements", self.elements, 4, 5000)
        checks.positive("stiffness_scale", self.stiffness_scale)

    @cached_property
    def nodes_m(self) -> np.ndarray:
        """Mesh nodes (m from the knob): equal spacing plus every profile station."""
        even = np.linspace(0.0, self.profile.length_m, self.elements + 1)
        return np.unique(np.concatenate([even, self.profile.stations_m]))

    def _sections(self, x):
        """Area (m^2) and second moment (m^4) of the section at x."""
        r = self.profile.radius_m(x)
        return math.pi * r**2, math.pi * r**4 / 4.0

    def _quadrature(self):
        """Per element: its length, Gauss points (m), weights (m), A and I there."""
        x0, x1 = self.nodes_m[:-1], self.nodes_m[1:]
        h = x1 - x0
        pts = x0[:, None] + h[:, None] * (_GAUSS_X[None, :] + 1.0) / 2.0
        wts = h[:, None] * _GAUSS_W[None, :] / 2.0
        area, second = self._sections(pts)
        return h, pts, wts, area, second

    @cached_property
    def rigid(self) -> dict:
        """Mass (kg), COM from the knob (m) and J about the COM (kg m^2), rotary inertia of
        the sections included: the integrals the rigid modes of the mesh hold."""
        _, pts, wts, area, second = self._quadrature()
        rho = self.wood.density_kgpm3
        mass = float(np.sum(rho * area * wts))
        com = float(np.sum(rho * area * pts * wts)) / mass
        inertia = float(np.sum(rho * (area * (pts - com) ** 2 + second) * wts))
        return {"mass_kg": mass, "com_from_knob_m": com, "inertia_cm_kgm2": inertia}

    def rigid_bat(self, like: Bat) -> Bat:
        """``like`` (its name, length, capsule radius) with this beam's mass properties."""
        return replace(like, **self.rigid)

    @cached_property
    def matrices(self) -> tuple[np.ndarray, np.ndarray]:
        """Global stiffness and mass matrices (free-free, DOFs (w, rotation) per node)."""
        build = timoshenko if self.shear else euler_bernoulli
        wood, scale = self.wood, self.stiffness_scale
        return build(
            self.nodes_m,
            wood.youngs_modulus_pa * scale,
            wood.shear_modulus_pa * scale,
            wood.density_kgpm3,
            *self._quadrature(),
        )

    @cached_property
    def _eigen(self) -> tuple[np.ndarray, np.ndarray]:
        K, M = self.matrices
        lam, vec = linalg.eigh(K, M)
        return np.sqrt(np.clip(lam, 0.0, None)) / (2 * math.pi), vec

    def modes(self, count: int = 6) -> Modes:
        """The first ``count`` bending modes (rigid-body modes left out), mass-normalised."""
        hz, vec = self._eigen
        checks.integer("count", count, 1, len(hz) - RIGID_MODES)
        # the rigid modes are the two lowest: a stiff beam's roundoff lifts their frequencies
        # to eps-sized shares of its highest mode's, which can pass any fixed threshold
        elastic = np.arange(RIGID_MODES, len(hz))[:count]
        if len(elastic) < count:
            raise ValueError(f"count = {count}: the mesh has {len(elastic)} bending modes")
        shapes = vec[0::2, elastic].T
        slopes = vec[1::2, elastic].T
        sign = np.sign(shapes[:, -1])  # each shape positive at the barrel end
        return Modes(
            frequencies_hz=hz[elastic],
            nodes_m=self.nodes_m,
            shapes=shapes * sign[:, None],
            slopes=slopes * sign[:, None],
            hermite=not self.shear,
            length_m=self.profile.length_m,
        )


@dataclass(frozen=True, kw_only=True)
class Modes:
    """Mass-normalised bending modes: ``frequencies_hz`` (Hz), shapes (m/sqrt(kg)) at the mesh
    ``nodes_m`` (m), their slopes (1/sqrt(kg) for Euler-Bernoulli's w'; Timoshenko's section
    rotation), interpolated between nodes by Hermite cubics or, for Timoshenko, cubic splines."""

    frequencies_hz: np.ndarray
    nodes_m: np.ndarray
    shapes: np.ndarray
    slopes: np.ndarray
    hermite: bool
    length_m: float

    @cached_property
    def _splines(self):
        if self.hermite:
            return [
                interpolate.CubicHermiteSpline(self.nodes_m, w, dw)
                for w, dw in zip(self.shapes, self.slopes, strict=True)
            ]
        return [interpolate.CubicSpline(self.nodes_m, w) for w in self.shapes]

    def shape(self, x_m) -> np.ndarray:
        """Each mode's displacement at ``x_m`` (m from the knob): shape (modes, ...)."""
        x_m = checks.array_in_range("x_m", x_m, 0.0, self.length_m)
        return np.array([s(x_m) for s in self._splines])

    def slope(self, x_m) -> np.ndarray:
        """Each mode's dw/dx at ``x_m``."""
        x_m = checks.array_in_range("x_m", x_m, 0.0, self.length_m)
        return np.array([s(x_m, 1) for s in self._splines])

    def node_positions_m(self, mode: int = 0) -> np.ndarray:
        """Where mode ``mode`` (0: the first bending mode) does not move (m from the knob)."""
        checks.integer("mode", mode, 0, len(self.frequencies_hz) - 1)
        grid = self.nodes_m
        w = self.shapes[mode]
        roots = [
            optimize.brentq(self._splines[mode], a, b, xtol=1e-12)
            for a, b, wa, wb in zip(grid[:-1], grid[1:], w[:-1], w[1:], strict=True)
            if wa * wb < 0.0
        ]
        return np.array(roots)

    def barrel_node_from_tip_m(self, mode: int = 0) -> float:
        """The node nearest the barrel end, as its distance from the tip (m)."""
        return float(self.length_m - self.node_positions_m(mode)[-1])


def fit_profile(
    bat: Bat,
    *,
    knob_radius_m: float,
    knob_length_m: float,
    handle_end_m: float,
    barrel_radius_m: float,
    taper_exponent: float,
    wood: Wood,
) -> tuple[Profile, Wood]:
    """A knob-handle-taper-barrel profile with ``bat``'s mass, COM and J_cm. Given: the knob,
    where the handle ends, the barrel's radius and the taper's shape (r grows as the
    ``taper_exponent`` power of the distance along it: 1 a cone, 2 a flare). Solved for (three
    unknowns for the three conditions): the handle's radius, where the barrel starts and the
    wood's density."""

    def build(p):
        x2, r_h, rho = p
        u = np.linspace(0.0, 1.0, 13)
        taper = handle_end_m + (x2 - handle_end_m) * u
        radii = r_h + (barrel_radius_m - r_h) * u**taper_exponent
        prof = Profile(
            stations_m=(0.0, knob_length_m, knob_length_m + 1e-3, *taper, bat.length_m),
            radii_m=(knob_radius_m, knob_radius_m, r_h, *radii, barrel_radius_m),
        )
        return prof, replace(wood, density_kgpm3=rho)

    def residual(p):
        if not handle_end_m + 0.01 < p[0] < bat.length_m - 0.01 and 0.0 < p[1]:
            return [1e3, 1e3, 1e3]
        got = Beam(profile=build(p)[0], wood=build(p)[1], elements=8).rigid
        return [
            got["mass_kg"] / bat.mass_kg - 1.0,
            (got["com_from_knob_m"] - bat.com_from_knob_m) / bat.length_m,
            got["inertia_cm_kgm2"] / bat.inertia_cm_kgm2 - 1.0,
        ]

    guess = [0.7 * bat.length_m, 0.5 * barrel_radius_m, wood.density_kgpm3]
    sol = optimize.least_squares(
        residual, guess, x_scale=[0.1, 1e-3, 100.0], xtol=1e-15, ftol=1e-15, gtol=1e-15
    )
    if np.max(np.abs(sol.fun)) > 1e-10:
        raise ValueError(
            f"no profile of this shape has {bat.name}'s mass properties "
            f"(residual {np.max(np.abs(sol.fun)):.1e})"
        )
    return build(sol.x)
