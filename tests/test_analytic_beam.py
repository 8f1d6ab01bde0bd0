"""The beam, the segmented chain and their impacts against closed forms and published data."""

from __future__ import annotations

import math

import numpy as np
import pytest

from analytic import WOOD_DENSITY_KGM3, beam, presets
from analytic.ball import REALISTIC_BALL
from analytic.chain import Chain
from analytic.chain_impact import ChainImpact, compliant_reference, impulse_reference
from analytic.compliant import BASEBALL_HERTZ, HuntCrossley
from analytic.cork import corked_bat

#: beta_n L of a free-free uniform Euler-Bernoulli beam: roots of cos(bL) cosh(bL) = 1
FREE_FREE_BETA_L = (4.730040744862704, 7.853204624095838, 10.995607838001671)
#: Hermite cubic elements converge as h^4 in frequency (160 elements: under 1e-8 here); the
#: rotary inertia this model keeps and the closed form omits lowers mode n by about
FE_REL = 1e-4  # (beta_n L)^2 (r/L)^2 / 8: 2e-5 for the third mode of a 1 mm by 1 m rod


@pytest.fixture(scope="module")
def r161():
    profile, wood = presets.r161_profile()
    return profile, wood


def test_uniform_free_free_beam_matches_closed_form():
    # omega_n = (beta_n L)^2 sqrt(E I / (rho A L^4)), r = 1 mm, L = 1 m
    r, length = 0.001, 1.0
    wood = beam.Wood(
        name="rod", youngs_modulus_pa=2e11, shear_modulus_pa=8e10, density_kgpm3=7800.0
    )
    rod = beam.Beam(profile=beam.Profile(stations_m=(0.0, length), radii_m=(r, r)), wood=wood)
    area, second = math.pi * r**2, math.pi * r**4 / 4
    want = [
        bl**2 * math.sqrt(2e11 * second / (7800 * area * length**4)) / (2 * math.pi)
        for bl in FREE_FREE_BETA_L
    ]
    np.testing.assert_allclose(rod.modes(3).frequencies_hz, want, rtol=FE_REL)


def test_r161_profile_holds_the_bats_mass_properties(r161):
    # the fitted profile's M, x_cm, J_cm are the R161's (Cross 2009), to the fit's 1e-10
    got = beam.Beam(profile=r161[0], wood=r161[1]).rigid
    assert got["mass_kg"] == pytest.approx(presets.R161.mass_kg, rel=1e-10)
    assert got["com_from_knob_m"] == pytest.approx(presets.R161.com_from_knob_m, rel=1e-10)
    assert got["inertia_cm_kgm2"] == pytest.approx(presets.R161.inertia_cm_kgm2, rel=1e-10)


def test_one_wood_density_for_every_model_of_the_r161(r161):
    # the cork model's default wood is the density at which the beam's profile has the R161's
    # M, x_cm and J_cm (the fit's residual is 1e-10, so the density agrees to about that)
    assert r161[1].density_kgpm3 == pytest.approx(WOOD_DENSITY_KGM3, rel=1e-9)
    drilled = corked_bat(presets.R161)  # 1 x 10 in of cork, 200 kg/m^3
    removed = (WOOD_DENSITY_KGM3 - 200.0) * math.pi * 0.0127**2 * 0.254
    assert presets.R161.mass_kg - drilled.mass_kg == pytest.approx(removed, rel=1e-12)


@pytest.mark.parametrize("shear", [False, True])
def test_r161_modes_fall_in_the_measured_ranges(r161, shear):
    # wood bats: first mode about 170 Hz, barrel node 5-7 in (13-18 cm) from the tip
    # (D. A. Russell, "Vibrational modes of a baseball bat", Kettering/Penn State pages);
    # second mode 550-650 Hz. The bars: 150-200 Hz, node 13-20 cm.
    modes = beam.Beam(profile=r161[0], wood=r161[1], shear=shear).modes(2)
    assert 150.0 <= modes.frequencies_hz[0] <= 200.0
    assert 550.0 <= modes.frequencies_hz[1] <= 650.0
    assert 0.13 <= modes.barrel_node_from_tip_m(0) <= 0.20


def test_shear_lowers_the_higher_modes_more(r161):
    # Timoshenko's correction grows with the mode's wavenumber: (f_EB - f_T)/f_EB rises
    eb = beam.Beam(profile=r161[0], wood=r161[1]).modes(4).frequencies_hz
    ti = beam.Beam(profile=r161[0], wood=r161[1], shear=True).modes(4).frequencies_hz
    drop = 1.0 - ti / eb
    assert np.all(drop > 0.0) and np.all(np.diff(drop) > 0.0)


def test_chain_converges_to_the_beam(r161):
    # lumped springs k = 1 / int dx/EI: the chain's modes tend to Euler-Bernoulli's as N grows
    b = beam.Beam(profile=r161[0], wood=r161[1])
    want = b.modes(2).frequencies_hz
    errs = [
        np.abs(Chain.from_beam(b, n, like=presets.R161).frequencies_hz[:2] / want - 1).max()
        for n in (8, 16, 32, 64)
    ]
    assert np.all(np.diff(errs) < 0.0) and errs[-1] < 2e-3
    chain = Chain.from_beam(b, 8, like=presets.R161)
    assert sum(chain.masses_kg) == pytest.approx(presets.R161.mass_kg, rel=1e-12)


def test_chain_rejects_bad_input(r161):
    b = beam.Beam(profile=r161[0], wood=r161[1])
    with pytest.raises(ValueError, match="segments"):
        Chain.from_beam(b, 1, like=presets.R161)


@pytest.fixture(scope="module")
def chain8(r161):
    return Chain.from_beam(beam.Beam(profile=r161[0], wood=r161[1]), 8, like=presets.R161)


@pytest.mark.parametrize("x_m", [0.45, 0.66, 0.75])
def test_chain_impulses_conserve_momentum_and_elastic_energy(chain8, x_m):
    # e = 1: sum of kinetic and spring energy after = before; m v1 + sum m_i v_i = -m v0
    impact = ChainImpact(chain=chain8, ball=presets.BASEBALL, x_m=x_m, v0_mps=40.0, e=1.0)
    out = impulse_reference(impact)
    assert out.ended == "separated"
    assert out.energy_after_j == pytest.approx(out.ke_before_j, rel=1e-9)
    p_bat = presets.R161.mass_kg * out.u1_mps
    assert presets.BASEBALL.mass_kg * out.v1_mps + p_bat == pytest.approx(
        -presets.BASEBALL.mass_kg * 40.0, abs=1e-9
    )


def test_chain_under_an_elastic_contact_conserves_energy(chain8):
    # Hertz without dissipation: kinetic plus spring energy after = before (solver's 1e-11)
    law = HuntCrossley(stiffness=REALISTIC_BALL.stiffness, exponent=1.5, dissipation_spm=0.0)
    impact = ChainImpact(chain=chain8, ball=presets.BASEBALL, x_m=0.66, v0_mps=40.0, e=0.5)
    out = compliant_reference(impact, law)
    assert out.ended == "separated"
    assert out.energy_after_j == pytest.approx(out.ke_before_j, rel=1e-8)


def test_flexible_bat_conserves_energy_under_an_elastic_contact(r161):
    # Hertz without dissipation: kinetic + bending energy after = before, to the solver's 1e-11
    from analytic import ImpactCase, flexible

    b = beam.Beam(profile=r161[0], wood=r161[1], shear=True)
    law = HuntCrossley(stiffness=REALISTIC_BALL.stiffness, exponent=1.5, dissipation_spm=0.0)
    case = ImpactCase(
        bat=b.rigid_bat(presets.R161),
        ball=presets.BASEBALL,
        s_m=0.0,
        v0_mps=46.9,
        u0_mps=17.87,
        omega0_radps=32.0,
        e=0.5,
    )
    out = flexible.predict(case, b, law, modes=8)
    assert out.energy_after_j == pytest.approx(out.ke_before_j, rel=1e-9)
    assert out.vibration_j > 0.05 * out.ke_before_j  # and the bat does take some of it


def test_impact_at_the_node_leaves_the_first_mode_still(r161):
    # a force at a node of mode 1 does no work on it: its energy there is a small fraction of
    # what a hit 16 cm away leaves (the contact point slides by millimetres meanwhile)
    from analytic import ImpactCase, flexible

    b = beam.Beam(profile=r161[0], wood=r161[1], shear=True)
    node = b.modes(1).node_positions_m(0)[-1] - presets.R161.com_from_knob_m

    def mode1(s):
        case = ImpactCase(
            bat=b.rigid_bat(presets.R161),
            ball=presets.BASEBALL,
            s_m=s,
            v0_mps=40.0,
            u0_mps=0.0,
            omega0_radps=0.0,
            e=0.5,
        )
        return flexible.predict(case, b, REALISTIC_BALL, modes=8).mode_energy_j[0]

    assert mode1(node) < 1e-2 * mode1(node - 0.16)


def test_fine_chain_and_beam_agree_on_the_exit_speed(r161):
    # two independent solutions of one bat: the linear chain of 32 segments (springs from EI)
    # and the Euler-Bernoulli beam's modes, both under the realistic ball on a still bat.
    # The chain's error falls as 1/N^2 (0.15 m/s at N = 8, 0.054 at 16, 0.008 at 32 measured)
    from analytic import ImpactCase, flexible

    eb = beam.Beam(profile=r161[0], wood=r161[1])
    chain = Chain.from_beam(eb, 32, like=presets.R161)
    impact = ChainImpact(chain=chain, ball=presets.BASEBALL, x_m=0.66, v0_mps=40.0, e=0.5)
    case = ImpactCase(
        bat=eb.rigid_bat(presets.R161),
        ball=presets.BASEBALL,
        s_m=impact.s_m,
        v0_mps=40.0,
        u0_mps=0.0,
        omega0_radps=0.0,
        e=0.5,
    )
    want = flexible.predict(case, eb, REALISTIC_BALL).v1_mps
    assert compliant_reference(impact, REALISTIC_BALL).v1_mps == pytest.approx(want, abs=0.05)


def test_beam_tends_to_the_rigid_bat_as_1_over_its_stiffness(r161):
    # E and G x S: the bending compliance in series with the ball's falls as 1/S, and so does
    # v1's gap from analytic.compliant's rigid bat (measured 1.1e-3, 1.1e-4, 9.9e-6 at
    # S = 1e3, 1e4, 1e5: under 1e-4 at 1e4, a tenth of it at ten times the stiffness). The
    # older one-d Hertz law, whose measured 9.9e-7 at E x 1e6 the bar was set on (the
    # realistic ball, less dissipative at this 65 m/s closing speed, gives 1.1e-6).
    from analytic import ImpactCase, flexible
    from analytic.compliant import predict as rigid_predict

    def gap(scale):
        b = beam.Beam(profile=r161[0], wood=r161[1], shear=True, stiffness_scale=scale)
        case = ImpactCase(
            bat=b.rigid_bat(presets.R161),
            ball=presets.BASEBALL,
            s_m=0.0,
            v0_mps=46.9,
            u0_mps=17.87,
            omega0_radps=32.0,
            e=0.5,
        )
        rigid = rigid_predict(case, BASEBALL_HERTZ).v1_mps
        return abs(flexible.predict(case, b, BASEBALL_HERTZ, modes=1).v1_mps / rigid - 1)

    coarse, fine = gap(1e3), gap(1e4)
    assert fine < 2e-4
    assert 8.0 < coarse / fine < 12.0
    assert gap(1e6) < 1e-6  # the bar: the rigid limit at E x 1e6 (measured 9.9e-7)
