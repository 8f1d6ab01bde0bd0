"""Each engine's contact semantics, pinned by tiny tests driven by its record: how two bodies'
restitution values combine, the restitution threshold, and a soft contact's calibration (the
reference profile's e is one of ``check_engine``'s checks)."""

from __future__ import annotations

import numpy as np
import pytest
from scipy import integrate

import adapters
from adapters import Scene
from analytic import ImpactCase, compliant, predict, presets
from analytic.compliant import damping_ratio_for, restitution_of_damping_ratio
from experiments.core import Job, fire_jobs, terms
from experiments.core.hosting import Hosted
from experiments.core.placement import start_state

R161, BALL = presets.R161, presets.BASEBALL
ENGINES = adapters.names()
COMBINING = [
    n
    for n in ENGINES
    if adapters.record(n).can.restitution_rule is not adapters.RestitutionRule.MAPPED
]
THRESHOLDS = [n for n in ENGINES if adapters.record(n).can.threshold_setting is not None]
SOFT = [n for n in ENGINES if adapters.record(n).can.soft_contact is not None]


def _central_e(name: str, settings, v0=40.0, e=0.5, bat=R161) -> float:
    """Measured e of a central impact (s = 0: no rotation): separation / approach speed."""
    return _central_es(name, settings, (v0,), e, bat)[0]


def _central_es(name: str, settings, speeds, e=0.5, bat=R161) -> list[float]:
    """``_central_e`` at each approach speed, fired together (one batch on a batched engine)."""
    jobs = [
        Job(
            engine=name,
            settings=settings,
            case=ImpactCase(bat=bat, ball=BALL, s_m=0.0, v0_mps=v, e=e),
        )
        for v in speeds
    ]
    return [(f.outcome.v1_mps - f.outcome.u1_mps) / f.case.v0_mps for f in fire_jobs(jobs)]


def _tol(name: str) -> float:
    """Rounding of the impact's float operations at the engine's precision."""
    return terms.ROUND_OPS * adapters.record(name).eps


@pytest.mark.parametrize("name", COMBINING)
def test_body_restitutions_combine_as_the_record_says(name):
    # Set by hand on a fresh adapter, bat 0.6 and ball 0.5 make a central impact separate at
    # 0.3 (product), 0.6 (max), 0.55 (mean) or 0.5 (min).
    st = adapters.settings_for(name)
    host = Hosted(name, st)
    try:
        host.batch(Scene(bat=R161, ball=BALL, e=0.5), 1)
        eng = host.adapter
        eng.set_body_restitution(bat=0.6, ball=0.5)
        eng.set_state(start_state(ImpactCase(bat=R161, ball=BALL, s_m=0.0, v0_mps=40.0), st)[0])
        for _ in range(st.approach_steps + 2):
            eng.step()
        r = eng.read()
    finally:
        host.close()
    want = adapters.record(name).can.restitution_rule.combine(0.6, 0.5)
    assert (r.ball_vy_mps - r.bat_vy_mps) / 40.0 == pytest.approx(want, abs=_tol(name))


@pytest.mark.parametrize("name", THRESHOLDS)
def test_restitution_threshold_drops_e(name):
    # Below the restitution velocity threshold the engine makes the contact plastic: a 40 m/s
    # impact under a 50 m/s threshold separates at 0.
    st = adapters.settings_for(name, **{adapters.record(name).can.threshold_setting: 50.0})
    assert _central_e(name, st) == pytest.approx(0.0, abs=_tol(name))


def test_spring_damper_restitution_formula_against_ode():
    # Integrate x'' = -2 zeta x' - x from x = 0, x' = -1 until the force x + 2 zeta x' returns to
    # zero; e = final speed. rtol 1e-12 in solve_ivp bounds the comparison at ~1e-10.
    for zeta in (0.05, 0.2553, 0.5, 0.9, 1.0, 1.5, 4.0):  # under-, critically and overdamped

        def rhs(t, y, z=zeta):
            return [y[1], -2 * z * y[1] - y[0]]

        def released(t, y, z=zeta):
            return y[0] + 2 * z * y[1] if t > 1e-9 else -1.0

        released.terminal, released.direction = True, 1
        sol = integrate.solve_ivp(
            rhs, (0, 10), [0.0, -1.0], events=released, rtol=1e-12, atol=1e-14
        )
        e_ode = sol.y_events[0][0][1]
        assert restitution_of_damping_ratio(zeta) == pytest.approx(e_ode, rel=1e-9)
    assert damping_ratio_for(0.5) == pytest.approx(0.2553, abs=1e-4)  # measured in the engine


@pytest.mark.full
@pytest.mark.parametrize("name", SOFT)
@pytest.mark.parametrize("w,dt", [(3000.0, 1e-5), (3000.0, 1e-6)])
def test_soft_calibration_is_independent_of_speed_and_mass(name, w, dt):
    # Soft contact: x'' = -b x' - k x in the contact's normal coordinate, whatever the masses, so
    # the measured e is the target up to the discretization error, first order in w*dt
    # (measured coefficient ~1/6; we allow w*dt/2), and does not change with speed or mass
    # beyond two stated causes: the contact starts overlap_m deep (x(0) = x0 adds at most w x0
    # to the release speed: w x0 / v relative, largest at the slowest v), and each of the
    # contact's pi / (w dt) steps rounds the velocities once (at worst adding up: steps * eps).
    rec = adapters.record(name)
    st = adapters.settings_for(
        name, dt_s=dt, **rec.can.soft_contact, **{rec.can.stiffness_setting: w}
    )
    heavy = R161.__class__(**{**R161.__dict__, "name": "heavy", "mass_kg": 3.0})
    speeds = (5.0, 40.0, 80.0)
    measured = [e for bat in (R161, heavy) for e in _central_es(name, st, speeds, bat=bat)]
    assert np.all(np.abs(np.array(measured) - 0.5) <= w * dt / 2)
    start = w * st.overlap_m / min(speeds)
    rounding = np.pi / (w * dt) * rec.eps
    assert np.ptp(measured) <= 1e-9 + w * dt * 1e-3 + start + rounding


def _soft_engines():
    """(engine, integrator label, its overrides, the fine step pair) for every engine with a
    soft contact mode: a single-world engine's reference integrator (the first) at dt = 1e-6 and
    1e-7 s, the others a decade coarser. 1e-7 s is 10^4 steps a contact, 1-3 minutes on a
    batched engine's CPU step: a batched engine, whose model is a single-world engine's (its
    ``twin_of``, which the fine pair checks, and ``experiments.twins`` pins row by row), is
    checked at the coarser pair only."""
    import adapters

    out = []
    for name in adapters.names():
        rec = adapters.record(name)
        if rec.can.soft_contact is None:
            continue
        for k, integ in enumerate(rec.can.integrators or (None,)):
            out.append(
                (
                    name,
                    getattr(integ, "label", "default"),
                    dict(integ.overrides) if integ else {},
                    k == 0 and not rec.batched,
                )
            )
    return out


@pytest.mark.full
@pytest.mark.parametrize(
    "engine,label,overrides,fine",
    _soft_engines(),
    ids=[f"{n}-{lab}" for n, lab, _, _ in _soft_engines()],
)
def test_soft_contact_converges_to_its_own_law(engine, label, overrides, fine):
    # An engine's soft contact, at w = 3000 rad/s and e = 0.5 on the paper's swing (s = 0.1 m,
    # where the bat turns 35 mrad during the ~1 ms contact), against the law its adapter
    # declares (ErrorModel.contact_law) integrated by compliant.predict: the difference is the
    # engine's discretization and falls at least first order in dt (measured for MuJoCo:
    # 10.0x per decade for Euler, implicitfast and RK4 alike, 0.28 -> 0.028 -> 0.0028 m/s
    # for Euler from dt = 1e-5 to 1e-7 s; RK4 is first order here too, its constraint
    # solve is per step). At 1e-7 s the engine is closer to its law than the law is to rigid
    # theory (the model error of a 1 ms contact on a turning bat).
    rec = adapters.record(engine)
    case = ImpactCase(
        bat=R161, ball=BALL, s_m=0.1, v0_mps=46.9, u0_mps=17.87, omega0_radps=32.0, e=0.5
    )
    steps = (1e-6, 1e-7) if fine else (1e-5, 1e-6)
    errors = []
    for dt in steps:
        settings = adapters.settings_for(
            engine,
            dt_s=dt,
            **rec.can.soft_contact,
            **overrides,
            **{rec.can.stiffness_setting: 3000.0},
        )
        law = rec.errors.contact_law(settings, case.e)
        assert law is not None, f"{engine}: a soft contact must declare its law"
        out = fire_jobs([Job(engine=engine, settings=settings, case=case)])[0].outcome
        assert out.sound, out.physics
        errors.append(abs(out.v1_mps - compliant.predict(case, law).v1_mps))
    assert errors[0] / errors[1] >= 8.0  # at least first order (10x per decade)
    assert errors[1] < 5e-3 * steps[1] / 1e-7  # 2.8e-3 m/s measured at 1e-7 s for Euler
    if not fine:
        return
    assert abs(compliant.predict(case, law).v1_mps - predict(case).v1_mps) > errors[1]
