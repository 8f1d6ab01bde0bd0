"""MuJoCo's worlds on one model: an ``MjData`` a world, all on the model compiled for the scene
(``Capabilities.pool_adapter``: the harness steps a long run's pool on this instead of on one
adapter, model and data a world).

A world of its own costs a model copy and an ``MjData`` (1.5 ms with the first compile, 0.5 ms
after, measured); a world here costs its ``MjData`` alone (0.34-0.5 ms), so a run of 1e3
impacts repays a pool of about 200. Each world is a ``MujocoEngine`` sharing the model, stepped
and read as alone: it ends bit for bit as it does alone (``tests/test_pool.py``). The model's
drive settings (the hands' anchor, the load's site) are shared: every world takes the same
hands, as the swing's batches (of one world) do.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from ..interface import STATE_FIELDS, BatchedEngine, Hands, MassProperties, Scene, State
from . import RECORD
from .adapter import MujocoEngine


class MujocoWorlds(BatchedEngine):
    """``n`` MuJoCo worlds on one model (module docstring)."""

    record = RECORD

    def __init__(self, settings) -> None:
        super().__init__(settings)
        self._built: list[MujocoEngine] = []  # every world made, on the scene's model
        self._worlds: list[MujocoEngine] = []  # the first n: the worlds in use
        self._scene: Scene | None = None

    def build(self, scene: Scene, worlds: int) -> None:
        """``worlds`` worlds holding ``scene``: those made already if the scene is theirs (a
        run's last, smaller batch takes the first ones), more made on the same model."""
        if scene != self._scene:
            first = MujocoEngine(self.settings)
            first.build(scene)
            self._built, self._scene = [first], scene
        while len(self._built) < worlds:
            self._built.append(self._built[0].sibling())
        self._worlds = self._built[:worlds]

    def mass_properties(self) -> MassProperties:
        return self._built[0].mass_properties()

    def set_state(self, states: np.ndarray) -> None:
        for world, row in zip(self._worlds, np.asarray(states).tolist()):
            world.set_state(State(*row))

    def step(self) -> None:
        for world in self._worlds:
            world.step()

    def read(self) -> np.ndarray:
        return np.array([world.read() for world in self._worlds], dtype=float).reshape(
            -1, len(STATE_FIELDS)
        )

    def in_contact(self) -> np.ndarray:
        return np.array([world.in_contact() for world in self._worlds], dtype=bool)

    def failed(self) -> np.ndarray:
        return np.array([world.failed() for world in self._worlds], dtype=bool)

    def set_drive(self, hands: Sequence[Hands] | None) -> None:
        if hands is not None and any(h != hands[0] for h in hands):
            raise ValueError(
                "hands: one model holds one drive; allowed: the same hands in every world"
            )
        for world in self._worlds:
            world.set_drive(None if hands is None else hands[0])

    def set_body_friction(self, *, bat: float, ball: float) -> None:
        self._built[0].set_body_friction(bat=bat, ball=ball)  # the model's: every world's

    def close(self) -> None:
        self._built, self._worlds, self._scene = [], [], None
