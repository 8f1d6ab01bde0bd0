"""PyBullet's worlds side by side: many bat-ball pairs in each physics client, for a long run
(``Capabilities.pool_adapter``: the harness steps its pools on this instead of on one client
per world).

A client costs 21 ms to connect and 27 MB; a pair in a client about 1 ms. The pairs of a client
lie in the same place, each pair's two bodies in a collision group of their own (filter group
= mask = one bit), so no pair touches another; the solver takes each pair's island alone, so
every world ends bit for bit as it does in a client of its own (``tests/test_pool.py``).
Alone means ``minimumSolverIslandSize`` 0 (``getPhysicsEngineParameters`` does not read it
back; a world alone is one island whatever it is): Bullet's island callback holds an
island back until its contacts and constraints exceed that size, so at 1 two one-contact
islands were solved as one, and the solver's early stop on their summed residual
(``solverResidualThreshold``, 1e-7 by the PyBullet Quickstart Guide) stepped them otherwise
than alone: two worlds in contact together parted in a last bit 7 steps in, and 3 of 21
sustained contacts (e = 0) ended off (measured; with the threshold at 0 the joint solve
matched alone).
Stepping PAIRS_PER_CLIENT pairs together costs less per pair than one (1.8-2.5 us a step
against 3.9, 4-16 pairs, measured); 30 cost 3.5: the broadphase pairs every overlapping box.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from ..frames import in_the_plane
from ..interface import STATE_FIELDS, BatchedEngine, Hands, MassProperties, Scene, State
from . import RECORD
from .adapter import (
    acting,
    add_pair,
    configure,
    drive_pair,
    load_pair,
    pair_mass_properties,
    pb,
    read_pair,
    set_friction,
    set_pair,
    set_restitution,
)

#: Pairs in one client (collision groups are bits of an int).
PAIRS_PER_CLIENT = 16


class PybulletWorlds(BatchedEngine):
    """``n`` PyBullet worlds in ceil(n / PAIRS_PER_CLIENT) clients (module docstring)."""

    record = RECORD

    def __init__(self, settings) -> None:
        super().__init__(settings)
        self._clients: list[int] = []
        self._built: list[tuple[int, int, int]] = []  # (client, bat, ball) per world built
        self._pairs: list[tuple[int, int, int]] = []  # the first n: the worlds in use
        self._scene: Scene | None = None

    def build(self, scene: Scene, worlds: int) -> None:
        """``worlds`` pairs holding ``scene``: those built already if the scene is theirs and
        there are enough (a run's last, smaller batch takes the first ones; the others, idle,
        touch nothing of theirs), else every pair built anew."""
        if scene != self._scene or worlds > len(self._built):
            self._build(scene, worlds)
        self._use(worlds)

    def _build(self, scene: Scene, worlds: int) -> None:
        need = math.ceil(worlds / PAIRS_PER_CLIENT)
        while len(self._clients) < need:
            self._clients.append(pb.connect(pb.DIRECT))
        self._built, self._scene = [], None
        for k, c in enumerate(self._clients[:need]):
            pb.resetSimulation(physicsClientId=c)
            configure(c, self.settings)
            pb.setPhysicsEngineParameter(minimumSolverIslandSize=0, physicsClientId=c)
            for bit in range(min(PAIRS_PER_CLIENT, worlds - k * PAIRS_PER_CLIENT)):
                bat, ball = add_pair(c, scene, self.settings)
                for body in (bat, ball):
                    pb.setCollisionFilterGroupMask(body, -1, 1 << bit, 1 << bit, physicsClientId=c)
                self._built.append((c, bat, ball))
        self._body_world = {
            (c, body): i for i, (c, bat, ball) in enumerate(self._built) for body in (bat, ball)
        }
        self._scene = scene
        self._joints: list[int | None] = [None] * worlds

    def _use(self, worlds: int) -> None:
        if any(j is not None for j in self._joints):
            self.set_drive(None)
        self._pairs = self._built[:worlds]
        self._joints = [None] * worlds
        self._loads: list = [None] * worlds
        self._planar = np.ones(worlds, dtype=bool)

    def mass_properties(self) -> MassProperties:
        return pair_mass_properties(*self._pairs[0])

    def set_state(self, states: np.ndarray) -> None:
        for i, ((c, bat, ball), row) in enumerate(zip(self._pairs, np.asarray(states).tolist())):
            state = State(*row)
            self._planar[i] = in_the_plane(state)
            set_pair(c, bat, ball, state)

    def set_drive(self, hands: Sequence[Hands] | None) -> None:
        for i, (c, bat, _) in enumerate(self._pairs):
            if self._joints[i] is not None:
                pb.removeConstraint(self._joints[i], physicsClientId=c)
            self._joints[i], self._loads[i] = drive_pair(
                c, bat, None if hands is None else hands[i]
            )

    def step(self) -> None:
        for (c, bat, _), load in zip(self._pairs, self._loads):
            if load is not None:
                load_pair(c, bat, load)
        for c in self._clients[: math.ceil(len(self._pairs) / PAIRS_PER_CLIENT)]:
            pb.stepSimulation(physicsClientId=c)

    def read(self) -> np.ndarray:
        return np.array(
            [
                read_pair(c, bat, ball, planar)
                for (c, bat, ball), planar in zip(self._pairs, self._planar)
            ],
            dtype=float,
        ).reshape(-1, len(STATE_FIELDS))

    def in_contact(self) -> np.ndarray:
        out = np.zeros(len(self._built), dtype=bool)
        for c in self._clients[: math.ceil(len(self._pairs) / PAIRS_PER_CLIENT)]:
            for pt in pb.getContactPoints(physicsClientId=c):
                if acting(pt):
                    out[self._body_world[c, pt[1]]] = True
        return out[: len(self._pairs)]

    def set_body_restitution(self, *, bat: float, ball: float) -> None:
        self._scene = None  # the pairs no longer hold the scene as built
        for c, bat_id, ball_id in self._built:
            set_restitution(c, (bat_id, ball_id), bat=bat, ball=ball)

    def set_body_friction(self, *, bat: float, ball: float) -> None:
        self._scene = None
        for c, bat_id, ball_id in self._built:
            set_friction(c, (bat_id, ball_id), bat=bat, ball=ball)

    def close(self) -> None:
        for c in self._clients:
            pb.disconnect(physicsClientId=c)
        self._clients, self._built, self._pairs, self._scene = [], [], [], None
