"""The episode kept where a batched engine's worlds live: what the harness asks of an adapter
that offers it (``BatchedEngine.device_episode``); imports no engine.

On a GPU the harness's per-step look at every world (its state read off the device, observed in
numpy) costs as much as the engine's step. An adapter may instead hand the harness its worlds'
state on the device, in one of two forms:

- ``ArrayDevice``: an array library with a compiler (JAX: ``jax.numpy`` and ``jax.jit``) and a
  function giving the worlds' state columns and contact flags as that library's arrays. The
  harness runs its own observation, written once against an array namespace, through it
  (``experiments.core.device_episode``).
- a ``DeviceEpisode``: the adapter's own kernels (Warp) doing the same observation on the
  engine's own arrays, from the numbers in ``EpisodeConstants``.

Either way only the end of each world's episode leaves the device: its ending code, steps,
first and last contact steps, peak penetration, side and end state (``DeviceEpisode.result``),
and, each step, two flags (any world still going; any world due a free-flight search, whose
few rows the harness searches on the host, ``searching`` and ``resolve``).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, Protocol

import numpy as np

#: The endings a device episode writes, in ``EpisodeConstants.codes`` order (the harness's
#: ``experiments.core.endings.Ending`` names them; their integer codes come with the constants).
ENDINGS = (
    "non_finite",
    "jumped",
    "passed",
    "missed",
    "budget",
    "left_cylinder",
    "separated",
    "contact_flag",
)


@dataclass(frozen=True, kw_only=True)
class EpisodeConstants:
    """The numbers of one batch's episode observation (``experiments.core.episode``'s rules),
    handed to the device. Units: m, s; ``deflected`` a fraction of the ball's incoming speed."""

    bat_radius_m: float
    ball_radius_m: float
    s_min_m: float  #: the bat's axis span from its COM (m)
    s_max_m: float
    dt_s: float
    approach_steps: int
    max_steps: int
    jump_limit_m: float  #: what a state may move beyond twice its speeds (``terms.JUMP_REACHES``)
    flag_gap_m: float  #: the gap past which a contact flag is doubted (``terms.FLAG_REACHES``)
    deflected: float  #: ``terms.DEFLECTED``
    off_span_steps: int  #: ``terms.OFF_SPAN_STEPS``
    episode_end_m: float  #: ``analytic.collide``'s gap that ends an episode (its search)
    rigid: bool  #: the contact converges to a rigid impulse (slides off the span only then)
    spatial: bool  #: measured in 3D (out of the swing plane)
    codes: tuple[int, ...]  #: the ending codes, in ``ENDINGS`` order

    def code(self, name: str) -> int:
        """The integer code of an ending named in ``ENDINGS``."""
        return self.codes[ENDINGS.index(name)]

    @property
    def reach_m(self) -> float:
        return self.bat_radius_m + self.ball_radius_m

    @property
    def flag_arm_m(self) -> float:
        """The farthest a bat surface point lies from the COM (m): its spin's reach."""
        return max(abs(self.s_min_m), abs(self.s_max_m)) + self.bat_radius_m


@dataclass(frozen=True, kw_only=True)
class ArrayDevice:
    """A batched engine's worlds as an array library holds them on their device (JAX).

    ``xp``: the library's numpy-like module; ``jit``: its compiler (a function of arrays in, a
    compiled one out); ``columns()``: the worlds' state now, as (20, rows) columns in
    ``STATE_FIELDS`` order, and the last step's contact flags (rows,), both on the device, the
    engine's own numbers (``read`` gives the same values, as float64); ``rows``: the worlds it
    holds (padding worlds past ``n`` included); ``call(fn, *args)`` runs a compiled function
    as the engine's calls run (its precision's mode)."""

    xp: Any
    jit: Callable
    columns: Callable[[], tuple[Any, Any]]
    rows: int
    call: Callable[..., Any]


class DeviceEpisode(Protocol):
    """The adapter's own kernels observing every world's episode after each step
    (``adapters.device``'s docstring). The harness sets the worlds' states, asks for it
    (``device_episode``: it lasts until the next ``set_state``), steps the engine and calls
    these in this order: ``start`` once; ``observe`` after each step (``approach_steps`` and
    the skip of free flight included: the rules of ``experiments.core.episode``);
    ``searching`` and ``resolve`` when ``observe`` says a search is due; ``budget`` if the
    steps run out; ``result`` at the end."""

    def start(self, starts: np.ndarray, came_from: np.ndarray, ball_v0: np.ndarray) -> None:
        """Begin: the start states (n, 20), the side each ball came from (+-1), and each
        ball's incoming (vx, vy, DEFLECTED^2 |v|^2) (n, 3), all float64 from the host."""

    def observe(self, step: int) -> tuple[bool, bool]:
        """One step's look at every world; (any world still going, any due a search)."""

    def searching(self) -> tuple[np.ndarray, np.ndarray]:
        """The worlds due a free-flight search: their indices (sorted) and state rows (k, 20)."""

    def resolve(
        self, step: int, idx: np.ndarray, left: np.ndarray, ahead: np.ndarray, check_at
    ) -> bool:
        """The searches' answers for worlds ``idx``: off the span first, contact ahead, and the
        step to look at it again (the harness's reckoning). Returns whether any world is still
        going."""

    def budget(self) -> None:
        """The steps ran out: end every world still going with the last reading."""

    def result(self) -> dict[str, np.ndarray]:
        """Per world (n): ``ended`` (codes), ``steps``, ``first``, ``last``, ``peak_m``,
        ``side_m`` and ``end`` (20, n), float64 columns of the end state."""
