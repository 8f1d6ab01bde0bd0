"""Every engine default the harness quotes (its record's ``engine_defaults``) is pinned here:
read back from a fresh engine where the engine reports it, else measured."""

from __future__ import annotations

import dataclasses

import pytest

import adapters
from analytic import ImpactCase, presets
from experiments.core import Job, fire_jobs

CASES = [
    (name, field, value)
    for name in adapters.names()
    for field, value in adapters.record(name).engine_defaults.items()
]
IDS = [f"{name}-{field}" for name, field, _ in CASES]
#: Some engines keep these constants in single precision (pymunk's collision_slop reads back
#: as 0.10000000149): a few float32 ulps.
READ_BACK_REL = 1e-6


def _impacts(name: str, **overrides) -> list[tuple[float, float]]:
    """v1 and omega1 of the paper's swing at three points, contact on a step boundary seen
    1e-9 m deep and mid-step, at 10 us: knobs that feed position error back show in one."""
    jobs = []
    for phase in (0.0, 0.5):
        settings = adapters.settings_for(
            name, "default", dt_s=1e-5, contact_phase=phase, **overrides
        )
        jobs += [
            Job(
                engine=name,
                settings=settings,
                case=ImpactCase(
                    bat=presets.R161,
                    ball=presets.BASEBALL,
                    s_m=s,
                    v0_mps=46.9,
                    u0_mps=17.87,
                    omega0_radps=32.0,
                    e=0.5,
                ),
            )
            for s in (-0.2, 0.05, 0.2)
        ]
    return [(f.outcome.v1_mps, f.outcome.omega1_radps) for f in fire_jobs(jobs)]


@pytest.mark.parametrize("name,field,value", CASES, ids=IDS)
def test_engine_default_is_what_the_record_says(name, field, value):
    read = adapters.engine_class(name).read_back_defaults()
    if field in read:
        # Read back from a fresh engine: equal to a few float32 ulps.
        got, want = read[field], value
        if isinstance(want, tuple):
            assert got == pytest.approx(want, rel=READ_BACK_REL)
        elif isinstance(want, (int, float)) and not isinstance(want, bool):
            assert got == pytest.approx(want, rel=READ_BACK_REL)
        else:
            assert got == want
        return
    # Not reported by the engine: measured. Leaving the knob to the engine and setting it to
    # the quoted value give the same impacts bit for bit, and the knob does matter here
    # (another value changes them), so the equality is not vacuous.
    default_profile = adapters.record(name).profiles["default"]
    assert getattr(default_profile, field) is None, "the default profile leaves it to the engine"
    assert _impacts(name, **{field: value}) == _impacts(name)
    assert _impacts(name, **{field: 2 * value}) != _impacts(name)


def test_every_default_the_default_profile_leaves_to_the_engine_is_known_or_irrelevant():
    # A default profile's None means "the engine's own value": the knobs the harness quotes
    # must be among them or set explicitly to the engine's value in that profile.
    for name in adapters.names():
        rec = adapters.record(name)
        profile = rec.profiles["default"]
        fields = {f.name for f in dataclasses.fields(profile)}
        for field, value in rec.engine_defaults.items():
            assert field in fields, (name, field)
            set_to = getattr(profile, field)
            same = (
                set_to == value
                if isinstance(value, str)
                else set_to == pytest.approx(value, rel=READ_BACK_REL)
            )
            assert set_to is None or same, (name, field, set_to, value)
