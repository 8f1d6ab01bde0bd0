"""An engine's worlds as the episode steps them: one batch, whatever the engine.

A single-world engine (``adapters.Engine``) is a batch of one in Python floats (``OneWorld``)
or of several of its adapters stepped in turn (``EngineWorlds``); a batched engine
(``adapters.BatchedEngine``) is its ``n`` worlds (``ManyWorlds``). The last two read in numpy
arrays, every world's state a row of ``adapters.STATE_FIELDS``, and their read is checked for
its shape: an adapter that breaks the interface says so in one line, not deep in the episode.
"""

from __future__ import annotations

from collections.abc import Sequence
from itertools import chain

import numpy as np

from adapters import PLANAR_FIELDS, STATE_FIELDS, Hands, State

from . import geometry as g

#: The widths of a batch's state rows an adapter may read: planar or every field.
WIDTHS = (len(PLANAR_FIELDS), len(STATE_FIELDS))


class OneWorld:
    """A single-world engine (``adapters.Engine``) as a batch of one, in Python floats."""

    xp = g.SCALARS
    n = 1

    def __init__(self, engine) -> None:
        self.engine, self.checked = engine, False

    def set_state(self, state: State) -> None:
        self.engine.set_state(state)

    def step(self) -> None:
        self.engine.step()

    def any_contact(self) -> bool:
        return self.engine.in_contact()

    def in_contact(self) -> bool:
        return self.engine.in_contact()

    def read(self) -> State:
        state = self.engine.read()
        if not self.checked:  # its first read: what every later one will be
            check_state(state)
            self.checked = True
        return state

    def failed(self) -> bool:
        return self.engine.failed()

    def retire(self, done) -> None:
        pass  # (its episode is over: nothing steps it)

    def set_drive(self, hands: Sequence[Hands] | None) -> None:
        self.engine.set_drive(None if hands is None else hands[0])


class EngineWorlds:
    """Several single-world engines (``adapters.Engine``), one world each, stepped in turn and
    seen as one batch in numpy arrays: the harness's work on a step is done once for them all."""

    xp = g.ARRAYS

    def __init__(self, engines: Sequence) -> None:
        self.engines, self.n, self.checked = engines, len(engines), False
        self.live = engines  # those stepped: the worlds whose episode goes on (``retire``)

    def set_state(self, states: np.ndarray) -> None:
        for engine, row in zip(self.engines, states.tolist()):
            engine.set_state(State(*row))
        self.live = self.engines

    def step(self) -> None:
        for engine in self.live:
            engine.step()

    def any_contact(self) -> bool:
        return any(engine.in_contact() for engine in self.engines)

    def in_contact(self) -> np.ndarray:
        return np.fromiter((engine.in_contact() for engine in self.engines), bool, self.n)

    def read(self) -> np.ndarray:
        states = [engine.read() for engine in self.engines]
        if not self.checked:  # the first read: what every later one will be
            check_state(states[0])
            self.checked = True
        flat = np.fromiter(chain.from_iterable(states), float, self.n * len(states[0]))
        return g.padded(flat.reshape(self.n, -1))

    def failed(self) -> np.ndarray:
        return np.array([engine.failed() for engine in self.engines], dtype=bool)

    def retire(self, done: np.ndarray) -> None:
        """Stop stepping the worlds ``done`` (their episode is over; what they read stays as
        it was then, their failure with it)."""
        self.live = [e for e, over in zip(self.engines, done.tolist()) if not over]

    def set_drive(self, hands: Sequence[Hands] | None) -> None:
        for i, engine in enumerate(self.engines):
            engine.set_drive(None if hands is None else hands[i])


class ManyWorlds:
    """A batched engine (``adapters.BatchedEngine``) over ``n`` worlds, in numpy arrays."""

    xp = g.ARRAYS

    def __init__(self, engine, n: int) -> None:
        self.engine, self.n = engine, n

    def set_state(self, states: np.ndarray) -> None:
        self.engine.set_state(states)

    def step(self) -> None:
        self.engine.step()

    def any_contact(self) -> bool:
        return bool(np.any(self.engine.in_contact()))

    def in_contact(self) -> np.ndarray:
        return np.asarray(self.engine.in_contact(), dtype=bool)

    def read(self) -> np.ndarray:
        states = np.asarray(self.engine.read())
        if (
            states.ndim != 2
            or states.shape[0] != self.n
            or states.shape[1] not in WIDTHS
            or states.dtype.kind != "f"
        ):
            raise ValueError(
                f"read() gave an array of {states.dtype} of shape {states.shape}; "
                f"allowed: floats, ({self.n}, {' or '.join(map(str, WIDTHS))}): a "
                "row of adapters.STATE_FIELDS (or PLANAR_FIELDS) per world"
            )
        return g.padded(states.astype(float, copy=False))

    def failed(self) -> np.ndarray:
        got = self.engine.failed()
        return np.zeros(self.n, dtype=bool) if got is None else np.asarray(got, dtype=bool)

    def retire(self, done: np.ndarray) -> None:
        self.engine.retire(done)

    def set_drive(self, hands: Sequence[Hands] | None) -> None:
        self.engine.set_drive(hands)


def check_state(state) -> None:
    """ValueError unless ``state`` is what a single-world engine's read gives: an
    ``adapters.State`` of floats."""
    if not isinstance(state, State) or not all(isinstance(v, float) for v in state):
        kinds = sorted({type(v).__name__ for v in state}) if isinstance(state, tuple) else []
        raise ValueError(
            f"read() gave a {type(state).__name__} of {', '.join(kinds) or '?'}; "
            "allowed: an adapters.State of floats"
        )
