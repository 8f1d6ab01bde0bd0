"""The engine interface of a segmented bat (``analytic.chain``): optional, for engines that join
bodies.

An engine that can build a chain of rigid segments joined by torsional springs names a class
of this form in its record (``chain_adapter = "module:Class"``); the harness
(``experiments.core.chain``) fires a ball at the chain and judges the ball's exit speed and the
energy left in the chain's bending against ``analytic.chain_impact``.

The chain lies along x, its knob end at x = -x_cm (the whole bat's COM at the origin); the
ball comes along -y. Segment i is a capsule of the bat's capsule radius whose cylinder spans
[i l, (i+1) l] from the knob, l = L/N; it holds exactly ``chain.masses_kg[i]`` at its COM
``chain.coms_m[i]`` (from the knob) and ``chain.inertias_kgm2[i]`` about z there (axial
inertia: a solid cylinder's, m r^2 / 2, capped at 2 J where a short thin segment would break
the triangle inequality; the planar impact does not excite it). Neighbours are
joined at their common end by the engine's own revolute joint about z, with a torsional spring
``chain.stiffnesses_nmprad[j]`` (N m/rad, zero torque when straight) and damper
``chain.dampings_nmsprad[j]``; segments do not collide with each other. The ball-segment
contact bounces with restitution ``e`` as the engine's single-bat adapter maps it, at the
engine's settings (the same ``Settings`` class). No gravity.

Planar state, world frame, SI: the ball as (x, y, vx, vy) (m, m/s); segment i as
(x, y, angle, vx, vy, omega) of its COM (m, rad, m/s, rad/s), angle the rotation about z.
"""

from __future__ import annotations

import abc
from dataclasses import dataclass
from typing import TYPE_CHECKING, ClassVar

if TYPE_CHECKING:
    import numpy as np

    from analytic import Ball
    from analytic.chain import Chain

    from .records import EngineRecord, Settings

#: Columns of one segment's row: COM position, angle, COM velocity, angular velocity.
SEGMENT_FIELDS = ("x_m", "y_m", "angle_rad", "vx_mps", "vy_mps", "omega_radps")
#: Columns of the ball's row.
BALL_FIELDS = ("x_m", "y_m", "vx_mps", "vy_mps")


@dataclass(frozen=True, kw_only=True)
class ChainScene:
    """What an engine builds: ``chain`` (segments, joints, springs), ``ball`` and the
    ball-bat restitution ``e``."""

    chain: Chain
    ball: Ball
    e: float


class ChainEngine(abc.ABC):
    """An engine that builds a segmented bat and a ball, one world at a time."""

    #: The engine's record (``adapters.EngineRecord``), the same as its bat adapter's.
    record: ClassVar[EngineRecord]

    def __init__(self, settings: Settings) -> None:
        self.settings = settings

    @abc.abstractmethod
    def build(self, scene: ChainScene) -> None:
        """Create the world holding ``scene`` (see the module docstring)."""

    @abc.abstractmethod
    def mass_properties(self) -> np.ndarray:
        """Read back, per segment, (mass kg, COM from the knob m, inertia about z kg m^2) as
        the engine holds them: shape (N, 3), knob segment first."""

    @abc.abstractmethod
    def set_state(self, ball: np.ndarray, segments: np.ndarray) -> None:
        """Put the ball (4,) and every segment (N, 6) in these states (their joints must
        agree: the harness only passes a straight chain moving rigidly), springs at rest,
        and forget every contact remembered."""

    @abc.abstractmethod
    def step(self) -> None:
        """Advance the world by ``settings.dt_s``."""

    @abc.abstractmethod
    def read(self) -> tuple[np.ndarray, np.ndarray]:
        """The ball (4,) and every segment (N, 6) now."""

    @abc.abstractmethod
    def in_contact(self) -> bool:
        """True if a ball-segment contact acted in the last step."""

    def failed(self) -> bool:
        """True if the engine met a numerical failure since the last ``set_state``."""
        return False

    def close(self) -> None:
        """Release engine resources."""
