"""The episode observed where a batched engine's worlds live (``experiments.core.device_episode``:
JAX's compiled observation, Warp's kernels) against the numpy path, its reference, on this CPU:
the same firing through both gives the same endings, physics, statuses, steps and contact
steps, and v1 with the same bits (both read the engine's own number at the same step, cast to
float64 alike). The contact geometry is computed in the device's arithmetic, so the peak
penetration and the ball's side differ by its rounding (``ROUNDING_M``).
"""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

import adapters
from experiments.core import tables
from experiments.core.device_episode import ENV, wanted
from experiments.core.fire import Jobs, fire_jobs
from experiments.parts import throughput

from .conftest import cheapest

BATCHED = [n for n in adapters.available() if adapters.record(n).batched]
GRID = throughput.GRID
#: The columns that must agree exactly, and those within the device's rounding.
EXACT = (
    "episode_end",
    "physics",
    "status",
    "steps",
    "contact_duration_s",
    "v1_engine_mps",
    "u1_engine_mps",
    "omega1_engine_radps",
    "ke_after_j",
)
ROUNDED = ("peak_penetration_m", "ball_side_end_m")


def rounding_m(name: str) -> float:
    """The geometry's rounding on the device: positions of order 1 m through some tens of
    operations in the engine's precision (JAX computes in it; Warp's kernels in float64,
    within it): 64 ulps of 1 m. Measured: 8.9e-9 m (mjx, float32), 1.4e-17 m elsewhere."""
    return 64 * float(np.finfo(adapters.record(name).errors.precision).eps)


def _fired(monkeypatch, name: str, profile: str, size: int, where: str) -> pd.DataFrame:
    monkeypatch.setenv(ENV, where)
    base = throughput._firing().cases()
    cases = [base[i % GRID] for i in range(size)]
    settings = adapters.record(name).profiles[profile]
    return tables.table(fire_jobs(Jobs(engine=name, settings=settings, cases=cases)), "device")


def _same(monkeypatch, name: str, profile: str, size: int) -> None:
    ref = _fired(monkeypatch, name, profile, size, "0")
    dev = _fired(monkeypatch, name, profile, size, "1")
    for col in EXACT:
        assert ref[col].tolist() == dev[col].tolist(), col
    for col in ROUNDED:
        np.testing.assert_allclose(dev[col], ref[col], rtol=0, atol=rounding_m(name), err_msg=col)


@pytest.mark.parametrize("profile", ["reference", "default"])
@pytest.mark.parametrize("name", BATCHED)
def test_the_device_episode_ends_every_world_as_numpy_does(monkeypatch, name, profile):
    # the reference profile's impacts end separated (and search free flight); the default
    # profile's tunnel (passed): both sets of rules, on the 41-point grid
    _same(monkeypatch, name, profile, GRID)


@pytest.mark.essential
@pytest.mark.parametrize("name", [cheapest(batched=True)])
def test_the_cheapest_batched_engine_ends_the_grid_on_its_device_as_numpy_does(monkeypatch, name):
    # the fast tier's check (seconds: Warp's kernels are cached once compiled)
    _same(monkeypatch, name, "reference", GRID)


@pytest.mark.full
@pytest.mark.parametrize("name", BATCHED)
def test_the_device_episode_ends_1e4_worlds_as_numpy_does(monkeypatch, name):
    _same(monkeypatch, name, "reference", 10_000)


class _Engine:
    def __init__(self, where: str) -> None:
        self.where = where

    def device(self) -> str:
        return self.where


def test_the_device_path_is_the_default_off_a_cpu_only(monkeypatch):
    monkeypatch.delenv(ENV, raising=False)
    assert [wanted(_Engine(d)) for d in ("cpu", "cpu: cpu", "cuda:0: NVIDIA H200")] == [
        False,
        False,
        True,
    ]
    monkeypatch.setenv(ENV, "1")
    assert wanted(_Engine("cpu"))
    monkeypatch.setenv(ENV, "0")
    assert not wanted(_Engine("gpu: NVIDIA H200"))
    monkeypatch.setenv(ENV, "yes")
    with pytest.raises(ValueError, match="allowed: auto, 1, 0"):
        wanted(_Engine("cpu"))
