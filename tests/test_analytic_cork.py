"""Corked-bat algebra against an independent numerical integration, and the paper's variant.

The integration represents the original bat by two point masses M/2 at x_cm +- sqrt(J/M) (same
mass, COM and J_cm: any body with these reproduces the transverse mechanics) and adds the hole as
a continuum of density rho_fill - rho_wood integrated by scipy's tplquad in cylindrical
coordinates. Quadrature is asked for ~1e-13 relative accuracy; QUAD_REL leaves room for it.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from scipy import integrate

from analytic import corked_bat, corked_bat_paper, presets

from .conftest import EPS

QUAD_REL = 1e-10
R161 = presets.R161


def _integrate_corked(bat, r, h, rho_fill, rho_wood):
    """Mass, COM and J about the new COM by summation over point masses + quadrature."""
    drho = rho_fill - rho_wood
    L = bat.length_m
    opts = dict(epsabs=0.0, epsrel=1e-13)

    def hole_integral(f):
        # int over x in [L-h, L], rho in [0, r], phi in [0, 2 pi] of f(x, y) * drho * rho
        val, _ = integrate.tplquad(lambda phi, rho, x: drho * rho * f(x, rho * math.cos(phi)),
                                   L - h, L, 0.0, r, 0.0, 2 * math.pi, **opts)
        return val

    a = math.sqrt(bat.inertia_cm_kgm2 / bat.mass_kg)
    xs = np.array([bat.com_from_knob_m - a, bat.com_from_knob_m + a])
    ms = np.array([bat.mass_kg / 2, bat.mass_kg / 2])
    mass = ms.sum() + hole_integral(lambda x, y: 1.0)
    com = (ms @ xs + hole_integral(lambda x, y: x)) / mass
    inertia = ms @ (xs - com) ** 2 + hole_integral(lambda x, y: (x - com) ** 2 + y**2)
    return mass, com, inertia


@pytest.mark.parametrize("depth_in", [6, 8, 10])
@pytest.mark.parametrize("fill", [0.0, 200.0, 1100.0])
def test_corked_equals_numerical_integration(depth_in, fill):
    # M' = M + dM, x'_cm = (M x_cm + dM x_c)/M', J' = J + M(x_cm-x')^2 + dM(r^2/4+h^2/12+(x_c-x')^2)
    r, h = 0.0127, depth_in * 0.0254
    got = corked_bat(R161, hole_radius_m=r, hole_depth_m=h, fill_density_kgm3=fill,
                     wood_density_kgm3=640.0)
    mass, com, inertia = _integrate_corked(R161, r, h, fill, 640.0)
    assert got.mass_kg == pytest.approx(mass, rel=QUAD_REL)
    assert got.com_from_knob_m == pytest.approx(com, rel=QUAD_REL)
    assert got.inertia_cm_kgm2 == pytest.approx(inertia, rel=QUAD_REL)


@given(st.floats(0.002, 0.02), st.floats(0.01, 0.3), st.floats(0.0, 2000.0), st.floats(300, 900))
def test_paper_variant_differs_by_documented_amount(r, h, fill, wood):
    # J_paper - J_exact = 2 (M + dM) R^2 - dM r^2/4; mass and COM agree (both exact there).
    exact = corked_bat(R161, hole_radius_m=r, hole_depth_m=h, fill_density_kgm3=fill,
                       wood_density_kgm3=wood)
    paper = corked_bat_paper(R161, hole_radius_m=r, hole_depth_m=h, fill_density_kgm3=fill,
                             wood_density_kgm3=wood)
    dM = (fill - wood) * math.pi * r**2 * h
    R = exact.com_from_knob_m - R161.com_from_knob_m
    scale = R161.inertia_cm_kgm2 + R161.mass_kg * R161.length_m**2
    assert paper.mass_kg == pytest.approx(exact.mass_kg, rel=8 * EPS)
    assert paper.com_from_knob_m == pytest.approx(exact.com_from_knob_m, abs=1e3 * EPS)
    diff = paper.inertia_cm_kgm2 - exact.inertia_cm_kgm2
    assert diff == pytest.approx(2 * exact.mass_kg * R**2 - dM * r**2 / 4, abs=1e3 * EPS * scale)


def test_lighter_fill_moves_com_to_the_knob_and_lowers_inertia():
    # Removing mass at the barrel end: dM < 0 at x_c > x_cm gives R = dM (x_c - x_cm)/M' < 0,
    # and less mass far from the COM means a smaller J_cm and a much smaller I_knob.
    corked = R161.corked(hole_radius_m=0.0127, hole_depth_m=0.254, fill_density_kgm3=0.0)
    assert corked.mass_kg < R161.mass_kg
    assert corked.com_from_knob_m < R161.com_from_knob_m
    assert corked.inertia_cm_kgm2 < R161.inertia_cm_kgm2
    assert corked.inertia_knob_kgm2 < R161.inertia_knob_kgm2
