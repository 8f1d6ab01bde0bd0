"""Each engine's contact semantics, pinned by tiny tests driven by its record: what plays the
role of e, how two bodies' restitution values combine, and the restitution threshold."""

from __future__ import annotations

import numpy as np
import pytest
from scipy import integrate

import adapters
from analytic import ImpactCase, presets
from analytic.compliant import damping_ratio_for, restitution_of_damping_ratio

R161, BALL = presets.R161, presets.BASEBALL
ENGINES = adapters.names()
COMBINING = [n for n in ENGINES
             if adapters.record(n).restitution_rule is not adapters.RestitutionRule.MAPPED]
THRESHOLDS = [n for n in ENGINES if adapters.record(n).threshold_setting is not None]
SOFT = [n for n in ENGINES if adapters.record(n).soft_contact is not None]


def _central_e(engine, v0=40.0, e=0.5, bat=R161) -> float:
    """Measured e of a central impact (s = 0: no rotation): separation / approach speed."""
    out = engine.simulate(ImpactCase(bat=bat, ball=BALL, s_m=0.0, v0_mps=v0, e=e))
    return (out.v1_mps - out.u1_mps) / v0


def _tol(engine) -> float:
    """Rounding of a few thousand operations at the engine's float precision."""
    return 1e4 * engine.record.eps


#: Engines whose reference contact has a coefficient of restitution (a compliant contact's e
#: follows its law and the impact speed: tests/test_adapters_conformance.py::test_law_conformance)
RIGID = [n for n in ENGINES if adapters.engine_class(n).converges_to(adapters.settings_for(n))
         is adapters.ContactReference.RIGID_IMPULSE]


@pytest.mark.parametrize("name", RIGID)
def test_reference_profile_gives_the_target_e(name):
    # Whatever the engine's own parameter, the adapter maps e so that a central impact
    # separates at e times its approach speed.
    eng = adapters.load(name)
    for e in (0.0, 0.3, 0.5, 1.0):
        assert _central_e(eng, e=e) == pytest.approx(e, abs=_tol(eng))
    eng.close()


@pytest.mark.parametrize("name", COMBINING)
def test_body_restitutions_combine_as_the_record_says(name):
    # Set by hand, bat 0.6 and ball 0.5 make a central impact separate at 0.3 (product), 0.6
    # (max), 0.55 (mean) or 0.5 (min); the next simulate(e = 0.5) maps e again (nothing leaks).
    eng = adapters.load(name)
    case = ImpactCase(bat=R161, ball=BALL, s_m=0.0, v0_mps=40.0, e=0.5)
    eng.simulate(case)
    eng.set_body_restitution(bat=0.6, ball=0.5)
    eng.set_state(adapters.start_reading(case, eng.settings)[0])
    for _ in range(eng.settings.approach_steps + 2):
        eng.step()
    r = eng.read()
    want = eng.record.restitution_rule.combine(0.6, 0.5)
    assert (r.ball_vy - r.bat_vy) / 40.0 == pytest.approx(want, abs=_tol(eng))
    assert _central_e(eng, e=0.5) == pytest.approx(0.5, abs=_tol(eng))
    eng.close()


@pytest.mark.parametrize("name", THRESHOLDS)
def test_restitution_threshold_drops_e(name):
    # Below the restitution velocity threshold the engine makes the contact plastic: a 40 m/s
    # impact under a 50 m/s threshold separates at 0.
    eng = adapters.load(name, **{adapters.record(name).threshold_setting: 50.0})
    assert _central_e(eng) == pytest.approx(0.0, abs=_tol(eng))
    eng.close()


def test_spring_damper_restitution_formula_against_ode():
    # Integrate x'' = -2 zeta x' - x from x = 0, x' = -1 until the force x + 2 zeta x' returns to
    # zero; e = final speed. rtol 1e-12 in solve_ivp bounds the comparison at ~1e-10.
    for zeta in (0.05, 0.2553, 0.5, 0.9, 1.0, 1.5, 4.0):  # under-, critically and overdamped
        def rhs(t, y, z=zeta):
            return [y[1], -2 * z * y[1] - y[0]]

        def released(t, y, z=zeta):
            return y[0] + 2 * z * y[1] if t > 1e-9 else -1.0

        released.terminal, released.direction = True, 1
        sol = integrate.solve_ivp(rhs, (0, 10), [0.0, -1.0], events=released, rtol=1e-12,
                                  atol=1e-14)
        e_ode = sol.y_events[0][0][1]
        assert restitution_of_damping_ratio(zeta) == pytest.approx(e_ode, rel=1e-9)
    assert damping_ratio_for(0.5) == pytest.approx(0.2553, abs=1e-4)  # measured in the engine


@pytest.mark.parametrize("name", SOFT)
@pytest.mark.parametrize("w,dt", [(3000.0, 1e-5), (3000.0, 1e-6)])
def test_soft_calibration_is_independent_of_speed_and_mass(name, w, dt):
    # Soft contact: x'' = -b x' - k x in the contact's normal coordinate, whatever the masses, so
    # the measured e is the target up to the discretization error, first order in w*dt
    # (measured coefficient ~1/6; we allow w*dt/2), and does not change with speed or mass.
    rec = adapters.record(name)
    eng = adapters.load(name, dt_s=dt, **rec.soft_contact, **{rec.stiffness_setting: w})
    heavy = R161.__class__(**{**R161.__dict__, "name": "heavy", "mass_kg": 3.0})
    measured = [_central_e(eng, v0=v, bat=bat) for v in (5.0, 40.0, 80.0) for bat in (R161, heavy)]
    assert np.all(np.abs(np.array(measured) - 0.5) <= w * dt / 2)
    assert np.ptp(measured) <= 1e-9 + w * dt * 1e-3  # independent of speed and effective mass
    eng.close()
