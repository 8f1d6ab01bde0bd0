"""An engine's own derivative of an impact by its settings' contact knobs
(``BatchedEngine.knob_derivative``), against central differences of the same engine rebuilt
with each knob moved, on a baseball fired centrally at a rigid wall (``analytic.ball.WALL``,
s = 0): the rebound v1 = ball_vy at the end, COR = v1 / v0 (the wall stays still).

A central difference of step h meets the derivative within

    truncation + rounding = h^2 |f'''| / 6 + delta / h,

delta the engine's own noise on v1 (measured here: the spread of v1 under relative knob
moves of 1e-13, whose true effect is far below it) and h^2 f''' / 6 estimated by Richardson,
|D(2h) - D(h)| / 3. The noise is not eps |v1|: a float64 MJX step solves its contact with a
Newton search and line search whose last bits jump (1.5e-9 m/s at 20 m/s, 7e-9 at 50,
measured); at h = 1e-3 of the knob the two terms are of one size for solref[0]
(truncation ~ 5e-2 (m/s)/s against ~ 6e-3 of rounding, at 20 m/s), and the sum stays below 1e-4 of
each derivative.

The mapping from settings to the model's arrays (``mujoco.model.contact_tangents``) is
checked apart, against differences of the model MuJoCo compiles (no engine stepped)."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

import adapters
from adapters.interface import Scene
from adapters.mujoco import RegularisedSettings
from adapters.mujoco.model import CONTACT_ARRAYS, CONTACT_KNOBS, contact_tangents, port_model
from analytic import presets
from analytic.ball import WALL

BALL = presets.BASEBALL
SPEEDS_MPS = np.array([20.0, 50.0])
#: A soft contact resolved by dt = 1e-5 s: about 30 steps of contact (w ~ 1/(tau zeta)),
#: 2-5 mm deep, across the impedance's width, so that d(r) and the COR depend on speed.
SOLREF = (2e-4, 0.5)
SOLIMP = (0.5, 0.95, 0.005, 0.5, 2.0)
#: The wall's 1e12 kg puts trace(M) at 4e12: MuJoCo's solver divides its improvement and
#: gradient by it, and at the default tolerance (1e-8) stops before its first iteration,
#: leaving the ball's velocity stepwise constant through the contact. tolerance 0 runs
#: each step's Newton solve to its iteration limit (4: 8 gives the same bits).
SOLVER = {"tolerance": 0.0, "iterations": 4}
STEPS = 48  # the contact is over by step 40 at both speeds (measured)
KNOBS = CONTACT_KNOBS["native"]
#: The knob's relative step of the central differences (the module docstring).
REL_STEP = 1e-3
#: The relative knob moves whose v1 spread measures the engine's noise (the true change,
#: |dv1/dx| x 1e-13, is below 1e-12 m/s).
NOISE_REL = 1e-13
#: The most noise a float64 engine may show on v1 (measured 7e-9 m/s: 15x that): a bound,
#: so that a tolerance built on the measured noise cannot grow without notice.
NOISE_MAX_MPS = 1e-7
#: The share of each rebound's change Richardson's estimate may miss (its O(h^4) term, a
#: rounding in D(2h)): the tolerance is this many times the estimate.
SAFETY = 3.0

#: Float64 engines whose adapters differentiate by their settings' knobs, with MuJoCo's
#: solref and solimp among those settings.
ENGINES = [
    n
    for n in adapters.available()
    if adapters.record(n).can.knob_autodiff
    and adapters.record(n).errors.precision == "float64"
    and {"solref", "solimp"} <= {f.name for f in dataclasses.fields(adapters.settings_for(n))}
]


def _settings(name: str, **overrides):
    kw = {"dt_s": 1e-5, "contact_model": "native", "solref": SOLREF, "solimp": SOLIMP}
    return adapters.settings_for(name, **{**kw, **SOLVER, **overrides})


def _starts() -> np.ndarray:
    # the ball touching the wall at its COM (s = 0), approaching along -y at v0
    s = np.zeros((len(SPEEDS_MPS), 20))
    s[:, 1] = WALL.radius_m + BALL.radius_m
    s[:, 3] = -SPEEDS_MPS
    return s


def _engine(name: str, **overrides):
    eng = adapters.create(name, _settings(name, **overrides))
    eng.build(Scene(bat=WALL, ball=BALL, e=0.5), len(SPEEDS_MPS))
    return eng


def _v1(name: str, **overrides) -> np.ndarray:
    eng = _engine(name, **overrides)
    eng.set_state(_starts())
    for _ in range(STEPS):
        eng.step()
    v1 = eng.read()[:, 3]
    eng.close()
    return v1


def _moved(knob: tuple, dx: float) -> dict:
    field, i = knob
    value = list(dict(solref=SOLREF, solimp=SOLIMP)[field])
    value[i] += dx
    return {field: tuple(value)}


def _base(knob: tuple) -> float:
    field, i = knob
    return dict(solref=SOLREF, solimp=SOLIMP)[field][i]


def _difference(name: str, knob: tuple, h: float) -> np.ndarray:
    return (_v1(name, **_moved(knob, h)) - _v1(name, **_moved(knob, -h))) / (2 * h)


def _arrays(scene: Scene, st, knob: tuple, dx: float) -> dict[str, np.ndarray]:
    """port_model's contact arrays with the knob moved by dx."""
    import mujoco  # here: collecting the tests imports no engine (test_adapters_registry)

    field, i = knob
    if i is None:
        moved = dataclasses.replace(st, **{field: getattr(st, field) + dx})
    else:
        value = list(getattr(st, field))
        value[i] += dx
        moved = dataclasses.replace(st, **{field: tuple(value)})
    m = port_model(mujoco, scene, moved)
    return {f: np.array(getattr(m, f), dtype=float) for f in CONTACT_ARRAYS}


def test_the_knobs_move_the_model_arrays_as_the_compiled_model_does():
    # contact_tangents against central differences of port_model's arrays (MuJoCo C's
    # compile of the MJCF, no engine stepped): solref and solimp are at most quadratic in
    # every knob (w^2), so a central difference is exact but for rounding (1e-9 relative
    # at a relative step of 1e-4); soft with friction also moves the bat-ball pair's solref
    base = RegularisedSettings(dt_s=1e-5)
    cases = [
        (dataclasses.replace(base, contact_model="native", solref=SOLREF, solimp=SOLIMP), 0.0),
        (dataclasses.replace(base, contact_model="soft", invweight_scale=1e-3), 0.0),
        (dataclasses.replace(base, contact_model="soft", invweight_scale=0.5), 0.2),
        (dataclasses.replace(base, contact_model="impulse", invweight_scale=0.5), 0.0),
    ]
    for st, mu in cases:
        scene = Scene(bat=WALL, ball=BALL, e=0.5, mu=mu)
        for knob in CONTACT_KNOBS[st.contact_model]:
            field, i = knob
            x = getattr(st, field) if i is None else getattr(st, field)[i]
            h = 1e-4 * abs(x)

            up, down = _arrays(scene, st, knob, h), _arrays(scene, st, knob, -h)
            got = contact_tangents(st, scene.e, knob)
            for f in CONTACT_ARRAYS:
                fd = (up[f] - down[f]) / (2 * h)
                want = np.broadcast_to(got[f], fd.shape)
                scale = np.abs(up[f]).max(initial=0.0) / h
                np.testing.assert_allclose(
                    want,
                    fd,
                    rtol=0,
                    atol=1e-9 * max(scale, 1.0),
                    err_msg=f"{st.contact_model} {knob} {f}",
                )
    # a knob the contact model ignores, or one no model has, is refused, naming the others
    with pytest.raises(ValueError, match="does not act on the soft contact; supported:"):
        contact_tangents(cases[1][0], 0.5, ("solref", 0))
    with pytest.raises(ValueError, match=r"\('solimp', 4\)"):
        contact_tangents(cases[0][0], 0.5, ("solimp", 5))


@pytest.mark.full
@pytest.mark.parametrize("name", ENGINES)
def test_the_knob_derivative_meets_central_differences_of_the_engine(name):
    eng = _engine(name)
    with pytest.raises(ValueError, match="supported"):  # refused before any work
        eng.knob_derivative(_starts(), STEPS, [("solref", 0), ("soft_omega_radps", None)])
    ends, d = eng.knob_derivative(_starts(), STEPS, KNOBS)
    assert ends.shape[0] == len(SPEEDS_MPS) and d.shape == (*ends.shape, len(KNOBS)), d.shape
    v1 = _v1(name)
    # the derivative's own end state is the plain firing's, bit for bit near (float64)
    np.testing.assert_allclose(ends[:, 3], v1, rtol=0, atol=1e-12)
    # the engine's noise on v1: its spread under knob moves of 1e-13 (module docstring)
    noise = np.zeros(len(SPEEDS_MPS))
    for knob in KNOBS[:2]:
        for j in (1, 2):
            shift = _v1(name, **_moved(knob, j * NOISE_REL * _base(knob)))
            noise = np.maximum(noise, np.abs(shift - v1))
    assert np.all(noise < NOISE_MAX_MPS), noise
    delta = np.maximum(noise, 4 * np.finfo(float).eps * np.abs(v1))
    for k, knob in enumerate(KNOBS):
        h = REL_STEP * abs(_base(knob))
        d1, d2 = _difference(name, knob, h), _difference(name, knob, 2 * h)
        # truncation of D(h) by Richardson, |D(2h) - D(h)| / 3, plus rounding delta / h
        tol = SAFETY * (np.abs(d2 - d1) / 3 + delta / h)
        got = d[:, 3, k]
        assert np.all(np.abs(got - d1) <= tol), (knob, got, d1, d2, tol)
        assert np.all(tol <= 1e-3 * np.abs(got)), (knob, tol, got)  # a bound, not a blanket
    # physics: more damping ratio, less bounce (solref[1] lowers the stiffness at fixed b)
    assert np.all(d[:, 3, KNOBS.index(("solref", 1))] / SPEEDS_MPS < 0), d[:, 3, :]


@pytest.mark.full
@pytest.mark.parametrize("name", ENGINES)
def test_the_cor_depends_on_speed_only_through_the_impedance_width(name):
    # with solimp's d(r) rising across its width the deeper, faster impact is stiffer and
    # bounces more; a constant impedance (d0 = dwidth) leaves a linear contact (x'' = -d (b
    # x' + k x)), whose trajectory from touching scales with v0: the same COR at both speeds
    # to within the engine's noise over v0 (delta < NOISE_MAX_MPS)
    cor = _v1(name) / SPEEDS_MPS
    assert cor[1] - cor[0] > 0.01, cor
    flat = _v1(name, solimp=(0.9, 0.9, *SOLIMP[2:])) / SPEEDS_MPS
    assert abs(flat[1] - flat[0]) <= NOISE_MAX_MPS / SPEEDS_MPS[0], flat
