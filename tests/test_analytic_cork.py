"""Corked-bat algebra against an independent numerical integration, and the paper's variant.

The integration represents the original bat by two point masses M/2 at x_cm +- sqrt(J/M) (same
mass, COM and J_cm: any body with these reproduces the transverse mechanics) and adds the hole as
a continuum of density rho_fill - rho_wood integrated by scipy's tplquad in cylindrical
coordinates. Quadrature is asked for ~1e-13 relative accuracy; QUAD_REL leaves room for it.
"""

from __future__ import annotations

import math
from dataclasses import replace

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
        val, _ = integrate.tplquad(
            lambda phi, rho, x: drho * rho * f(x, rho * math.cos(phi)),
            L - h,
            L,
            0.0,
            r,
            0.0,
            2 * math.pi,
            **opts,
        )
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
    got = corked_bat(
        R161, hole_radius_m=r, hole_depth_m=h, fill_density_kgm3=fill, wood_density_kgm3=640.0
    )
    mass, com, inertia = _integrate_corked(R161, r, h, fill, 640.0)
    assert got.mass_kg == pytest.approx(mass, rel=QUAD_REL)
    assert got.com_from_knob_m == pytest.approx(com, rel=QUAD_REL)
    assert got.inertia_cm_kgm2 == pytest.approx(inertia, rel=QUAD_REL)


@given(st.floats(0.002, 0.02), st.floats(0.01, 0.3), st.floats(0.0, 2000.0), st.floats(300, 900))
def test_paper_variant_differs_by_documented_amount(r, h, fill, wood):
    # J_paper - J_exact = 2 (M + dM) R^2 - dM r^2/4; mass and COM agree (both exact there).
    exact = corked_bat(
        R161, hole_radius_m=r, hole_depth_m=h, fill_density_kgm3=fill, wood_density_kgm3=wood
    )
    paper = corked_bat_paper(
        R161, hole_radius_m=r, hole_depth_m=h, fill_density_kgm3=fill, wood_density_kgm3=wood
    )
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
    corked = corked_bat(R161, hole_radius_m=0.0127, hole_depth_m=0.254, fill_density_kgm3=0.0)
    assert corked.mass_kg < R161.mass_kg
    assert corked.com_from_knob_m < R161.com_from_knob_m
    assert corked.inertia_cm_kgm2 < R161.inertia_cm_kgm2
    assert corked.inertia_knob_kgm2 < R161.inertia_knob_kgm2


# -- a hole must leave the bat a wall and a bottom ----------------------------------------------


def _wall(bat, depth_m: float) -> float:
    """The least radius (m) over the drilled span [L - h, L], read off the bat's profile at a
    fine grid (independent of Hole.wall_radius_m's stations), and its capsule's radius."""
    from analytic.presets import r161_profile

    x = np.linspace(bat.length_m - depth_m, bat.length_m, 20_001)
    return min(bat.radius_m, float(r161_profile()[0].radius_m(x).min()))


@pytest.mark.parametrize("depth_m", [0.254, 0.5, 0.7, 0.83])
def test_a_hole_as_wide_as_the_bat_where_it_is_drilled_is_refused(depth_m):
    # A hole of radius r >= the bat's radius where it is drilled leaves no wood around it: the
    # R161's profile (knob 21.5 mm, handle 14.4 mm, barrel 31.75 mm; its capsule 30 mm) bounds
    # r over the span [L - h, L] (a 10 in hole stays in the barrel: 30 mm; 0.5 m reaches the
    # taper, 0.7 m and more the handle). Just under the wall is a bat; at the wall it is not.
    wall = _wall(R161, depth_m)
    corked_bat(R161, hole_radius_m=wall * (1 - 1e-9), hole_depth_m=depth_m)
    for r in (wall, 1.5 * wall):
        with pytest.raises(
            ValueError,
            match=r"hole_radius_m=.* leaves no wall.*allowed: 0 < "
            r"hole_radius_m <",
        ) as err:
            corked_bat(R161, hole_radius_m=r, hole_depth_m=depth_m)
        assert "\n" not in str(err.value) and f"hole_depth_m={depth_m:g}" in str(err.value)
        with pytest.raises(ValueError, match="leaves no wall"):
            corked_bat_paper(R161, hole_radius_m=r, hole_depth_m=depth_m)


def test_a_hole_through_the_bat_is_refused():
    # depth >= L drills out the knob: no bottom, so no corked bat (it was allowed at L).
    for depth in (R161.length_m, R161.length_m + 0.1):
        with pytest.raises(ValueError, match=r"hole_depth_m=.*allowed: 0 < hole_depth_m < 0.84"):
            corked_bat(R161, hole_radius_m=0.005, hole_depth_m=depth)


def test_a_bat_without_a_profile_is_bounded_by_its_capsule():
    # Only the capsule's radius is known of a bat built by hand: it is the wall.
    bat = replace(R161, name="plain")
    corked_bat(bat, hole_radius_m=0.02, hole_depth_m=0.7)  # the R161's handle would refuse
    with pytest.raises(ValueError, match="leaves no wall, 'plain' being 0.03 m in radius"):
        corked_bat(bat, hole_radius_m=0.03, hole_depth_m=0.254)


def test_a_hollow_metal_bat_is_not_corked():
    with pytest.raises(ValueError, match=r"bat 'easton31' is a hollow metal shell.*allowed"):
        corked_bat(presets.EASTON31)


@pytest.mark.parametrize(
    "field,kw",
    [
        ("hole_radius_m", {"radius_m": 0.0}),
        ("hole_depth_m", {"depth_m": -0.1}),
        ("fill_density_kgm3", {"fill_density_kgm3": math.nan}),
        ("wood_density_kgm3", {"wood_density_kgm3": 50.0}),
    ],
)
def test_a_hole_made_directly_is_checked(field, kw):
    from analytic import Hole

    good = dict(radius_m=0.0127, depth_m=0.254, fill_density_kgm3=200.0, wood_density_kgm3=600.0)
    with pytest.raises(ValueError, match=rf"{field}=.*allowed"):
        Hole(**{**good, **kw})
