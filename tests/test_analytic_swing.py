"""Swing-speed models: each obeys the scaling law it names, and maps the reference to itself."""

from __future__ import annotations

import pytest

from analytic import Swing, SwingModel, presets, swing_for

from .conftest import EPS

R161, AL = presets.R161, presets.EASTON31
REF = presets.PAPER_SWING


@pytest.mark.parametrize("model", list(SwingModel))
def test_reference_bat_keeps_its_swing(model):
    # Every model is a ratio of the bat's property to the reference's: 1 for the same bat.
    got = swing_for(R161, model=model, reference_bat=R161, reference=REF)
    assert got.u0_mps == pytest.approx(REF.u0_mps, rel=4 * EPS)
    assert got.omega0_radps == pytest.approx(REF.omega0_radps, rel=4 * EPS)


def test_constant_force_scales_u0_as_inverse_mass():
    # Paper eq. 8.1.5: u0 = sqrt(1 + lambda^2) F / M, so M u0 is the same for every bat.
    got = swing_for(AL, model="constant_force", reference_bat=R161, reference=REF)
    assert AL.mass_kg * got.u0_mps == pytest.approx(R161.mass_kg * REF.u0_mps, rel=4 * EPS)
    assert got.omega0_radps == REF.omega0_radps


def test_constant_torque_gives_equal_kinetic_energy_about_knob():
    # tau * dtheta = I_knob omega^2 / 2: the same work gives the same rotational energy.
    got = swing_for(AL, model=SwingModel.CONSTANT_TORQUE, reference_bat=R161, reference=REF)
    assert AL.inertia_knob_kgm2 * got.omega0_radps**2 == pytest.approx(
        R161.inertia_knob_kgm2 * REF.omega0_radps**2, rel=16 * EPS
    )


def test_measured_model_keeps_omega_times_inertia_power():
    # Cross & Bower: omega = C / I^n, so omega I^n is the batter's constant C.
    n = 0.27
    got = swing_for(AL, model=SwingModel.MEASURED, reference_bat=R161, reference=REF, exponent=n)
    assert got.omega0_radps * AL.inertia_knob_kgm2**n == pytest.approx(
        REF.omega0_radps * R161.inertia_knob_kgm2**n, rel=16 * EPS
    )


def test_instantaneous_centre_stays_fixed_relative_to_knob():
    # u0/omega0 = x_cm - x_ic: the new bat turns about the same point of the batter's swing.
    got = swing_for(AL, model=SwingModel.MEASURED, reference_bat=R161, reference=REF)
    x_ic_ref = R161.com_from_knob_m - REF.u0_mps / REF.omega0_radps
    x_ic = AL.com_from_knob_m - got.u0_mps / got.omega0_radps
    assert x_ic == pytest.approx(x_ic_ref, abs=1e-12)


def test_speed_at_point():
    # v(s) = u0 + omega0 s for a rigid body in plane motion.
    assert Swing(u0_mps=10.0, omega0_radps=20.0).speed_at(0.15) == pytest.approx(13.0)
