"""Bad input is a ValueError that names the field, the value and the allowed range."""

from __future__ import annotations

import math
from dataclasses import replace

import pytest

from analytic import (
    Ball,
    Bat,
    ImpactCase,
    batted_ball_speed,
    center_of_percussion,
    corked_bat_paper,
    presets,
    sweet_spot,
)
from analytic.cork import corked_bat

R161, BALL = presets.R161, presets.BASEBALL
GOOD = dict(bat=R161, ball=BALL, s_m=0.1, v0_mps=46.9, u0_mps=17.87, omega0_radps=32.0, e=0.5)
BAT = dict(
    name="b",
    length_m=0.84,
    radius_m=0.033,
    mass_kg=0.871,
    com_from_knob_m=0.56,
    inertia_cm_kgm2=0.039,
)


def _raises(field: str, value, fn, *args, **kwargs):
    with pytest.raises(ValueError) as err:
        fn(*args, **kwargs)
    msg = str(err.value)
    assert field in msg and "allowed" in msg, msg
    if not (isinstance(value, float) and math.isnan(value)):
        # a long value (a Bat where a Ball belongs) is shown by its beginning
        assert repr(value)[:30] in msg or f"{value!r}".rstrip("0") in msg, msg


@pytest.mark.parametrize(
    "field", ["length_m", "radius_m", "mass_kg", "com_from_knob_m", "inertia_cm_kgm2"]
)
@pytest.mark.parametrize("value", [math.nan, math.inf, -math.inf])
def test_bat_rejects_non_finite(field, value):
    _raises(field, value, Bat, **{**BAT, field: value})


@pytest.mark.parametrize("field", ["length_m", "radius_m", "mass_kg", "inertia_cm_kgm2"])
@pytest.mark.parametrize("value", [0.0, -0.1])
def test_bat_rejects_non_positive(field, value):
    _raises(field, value, Bat, **{**BAT, field: value})


@pytest.mark.parametrize("value", [-0.01, 0.85])
def test_bat_rejects_com_off_the_bat(value):
    _raises("com_from_knob_m", value, Bat, **{**BAT, "com_from_knob_m": value})


@pytest.mark.parametrize(
    "field,value", [("mass_kg", 0.0), ("radius_m", -1.0), ("mass_kg", math.nan)]
)
def test_ball_rejects_bad_values(field, value):
    _raises(field, value, Ball, **{"name": "x", "mass_kg": 0.145, "radius_m": 0.0366, field: value})


@pytest.mark.parametrize(
    "field,value",
    [
        ("s_m", -0.57),
        ("s_m", 0.29),
        ("s_m", math.nan),
        ("e", -0.1),
        ("e", 1.01),
        ("e", math.inf),
        ("v0_mps", -1.0),
        ("u0_mps", math.nan),
        ("omega0_radps", math.inf),
        ("theta_rad", math.pi / 2),
        ("phi_rad", -2.0),
        ("hands_from_knob_m", 0.9),
    ],
)
def test_impact_case_rejects(field, value):
    _raises(field, value, ImpactCase, **{**GOOD, field: value})


def test_impact_case_rejects_separating_bodies():
    with pytest.raises(ValueError, match="closing speed"):
        ImpactCase(**{**GOOD, "v0_mps": 0.0, "u0_mps": -1.0, "omega0_radps": 0.0})


def test_vectorized_names_the_offending_point():
    _raises("s_m", 0.3, batted_ball_speed, R161, BALL, [0.0, 0.3], v0_mps=40.0)
    _raises("e", 2.0, batted_ball_speed, R161, BALL, [0.0], v0_mps=40.0, e=2.0)
    _raises("v0_mps", -3.0, sweet_spot, R161, BALL, -3.0)


@pytest.mark.parametrize("value", [-0.1, 0.85, math.nan])
def test_pivot_off_the_bat(value):
    _raises("pivot_from_knob_m", value, center_of_percussion, R161, value)
    _raises("pivot_from_knob_m", value, R161.inertia_about, value)


def test_pivot_at_com_has_no_cop():
    _raises("pivot_from_knob_m", 0.56, center_of_percussion, R161, 0.56)


@pytest.mark.parametrize(
    "field,value",
    [
        ("hole_depth_m", 0.9),
        ("hole_depth_m", 0.0),
        ("hole_radius_m", 0.04),
        ("hole_radius_m", -0.01),
        ("fill_density_kgm3", -1.0),
        ("wood_density_kgm3", -640.0),
        ("fill_density_kgm3", math.nan),
        ("fill_density_kgm3", 30000.0),
        ("fill_density_kgm3", 1e9),
        ("wood_density_kgm3", 0.0),
        ("wood_density_kgm3", 5000.0),
    ],
)
def test_cork_rejects(field, value):
    _raises(field, value, corked_bat, R161, **{field: value})
    _raises(field, value, corked_bat_paper, R161, **{field: value})


def test_cork_that_removes_the_whole_bat_is_rejected():
    # The densest wood in a hole nearly the bat's size makes dM < -M: negative mass. (The
    # R161's own profile refuses such a hole first, by its 14.4 mm handle: a bat known only by
    # its 33 mm capsule gets this far.)
    with pytest.raises(ValueError, match="corked mass"):
        corked_bat(
            Bat(**BAT),
            hole_radius_m=0.0329,
            hole_depth_m=0.8,
            fill_density_kgm3=0.0,
            wood_density_kgm3=1400.0,
        )


@pytest.mark.parametrize(
    "field,value,depth",
    [
        ("hole_radius_m", 0.03, 0.254),  # the capsule's radius: no wall left in the barrel
        ("hole_radius_m", 0.02, 0.7),  # narrower than the barrel, wider than the handle
        ("hole_depth_m", 0.84, 0.84),  # the bat's length: no bottom left
    ],
)
def test_cork_that_leaves_no_wall_or_bottom_is_rejected(field, value, depth):
    kw = {"hole_radius_m": 0.0127, "hole_depth_m": depth, field: value}
    _raises(field, value, corked_bat, R161, **kw)
    _raises(field, value, corked_bat_paper, R161, **kw)


def test_a_sweet_spot_needs_something_to_approach():
    # omega0 = 0 and v0 cos(theta) + u0 cos(phi) <= 0: no point of the bat approaches the ball
    _raises("omega0_radps", 0.0, sweet_spot, R161, BALL, 0.0, 0.0, 0.0)
    _raises("omega0_radps", 0.0, sweet_spot, R161, BALL, 0.0, -2.0, 0.0)


def test_episode_marks_refuse_bad_input():
    from analytic import EpisodeMark, ImpactCase, episode_cop_mark, episode_sweet_spot_mark

    case = ImpactCase(**GOOD)
    for fn in (episode_cop_mark, episode_sweet_spot_mark):
        _raises("max_episode_s", -1.0, fn, case, max_episode_s=-1.0)
        _raises("points", 2, fn, replace(case, e=0.0), points=2)
        _raises("case", R161, fn, R161)
    _raises("reference", "closed form", EpisodeMark, s_m=0.1, reference="closed form")


def test_replace_revalidates():
    # dataclasses.replace runs __post_init__ again, so a derived bad bat cannot slip through.
    _raises("mass_kg", -1.0, replace, R161, mass_kg=-1.0)


# -- the API's other doors: every one refuses with the same one line ---------------------------


@pytest.fixture(scope="module")
def modes():
    from analytic import beam

    profile, wood = presets.r161_profile()
    return beam.Beam(profile=profile, wood=wood, elements=40).modes(3)


def _case(**change):
    return ImpactCase(**{**GOOD, **change})


@pytest.mark.parametrize(
    "field,value,call",
    [
        ("ball", R161, lambda: _case(ball=R161)),
        ("bat", None, lambda: _case(bat=None)),
        ("v0_mps", 1e300, lambda: _case(v0_mps=1e300)),
        ("u0_mps", -2e3, lambda: _case(u0_mps=-2e3)),
        ("omega0_radps", 1e9, lambda: _case(omega0_radps=1e9)),
        ("spin_radps[0]", 1e9, lambda: _case(mu=0.3, spin_radps=(1e9, 0.0, 0.0))),
        ("inertia_cm_kgm2", 1e-12, lambda: Bat(**{**BAT, "inertia_cm_kgm2": 1e-12})),
        ("omega0_radps", 1e9, lambda: sweet_spot(R161, BALL, 46.9, 17.87, 1e9)),
        ("bat", None, lambda: sweet_spot(None, BALL, 46.9)),
        ("case", "junk", lambda: __import__("analytic").predict("junk")),
        ("case", "junk", lambda: __import__("analytic").predict_friction("junk")),
        ("case", "junk", lambda: __import__("analytic").collide("junk")),
        ("law", "junk", lambda: __import__("analytic").predict_friction(_case(mu=0.3), law="junk")),
    ],
)
def test_api_refuses_bad_input(field, value, call):
    # a wrong type or an out-of-range value is one ValueError naming the field, never an
    # AttributeError or OverflowError from deep inside
    _raises(field, value, call)


def test_flight_refuses_bad_input():
    from analytic import flight

    _raises(
        "backspin_radps", 1e9, flight.Launch, speed_mps=45.0, launch_rad=0.5, backspin_radps=1e9
    )
    _raises("launch", "x", flight.fly, "x")


def test_beam_refuses_bad_input(modes):
    from analytic import beam

    _raises(
        "count",
        -1,
        beam.Beam(profile=presets.r161_profile()[0], wood=beam.ASH, elements=8).modes,
        -1,
    )
    _raises("x_m", 5.0, modes.shape, 5.0)  # past the 0.84 m beam
    _raises("x_m", math.nan, modes.slope, math.nan)
    _raises("mode", 99, modes.barrel_node_from_tip_m, 99)
    _raises("wood", "ash", presets.r161_profile, "ash")
