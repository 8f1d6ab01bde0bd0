"""A plug-in engine written from ``adapters.interface`` alone: planar rigid bodies in numpy,
many worlds per call (the batched form). It lives outside the harness's packages; a test
installs it as a distribution with an entry point and runs every experiment over it.

Each step, for every world: positions move with the velocities (then the bat's angle with its
spin), contacts are found on the new positions, loads change the velocities, and a ball
overlapping the bat and approaching it gets Newton's impulse j = -(1 + e) v_n / (1/m + 1/M +
(r x n)^2 / J) along n, from the closest point of the bat's axis to the ball's centre. A hinged
bat turns about its pivot: alpha = tau_P / (J + M d^2), the COM kept on the pivot's circle.
"""

from __future__ import annotations

import dataclasses
import math
import os
import time
from dataclasses import dataclass

import numpy as np

from adapters import (
    BatchedEngine,
    Capabilities,
    Cost,
    Hands,
    Install,
    Integrator,
    MassProperties,
    Presentation,
    Scene,
    Studies,
)
from adapters.records import EngineRecord, KnobFamily, RestitutionRule, Settings

BX, BY, BVX, BVY, BW, CX, CY, CA, CVX, CVY, CW = range(11)


@dataclass(frozen=True, kw_only=True)
class ToySettings(Settings):
    """No knobs of its own: the time step and the harness's placement."""


RECORD = EngineRecord(
    name="toyengine",
    adapter="toy_engine:ToyEngine",
    install=Install(
        package="numpy",
        import_name="numpy",
    ),
    profiles={
        "reference": ToySettings(dt_s=1e-5),
        "default": ToySettings(dt_s=1 / 60, contact_phase=0.5),
    },
    can=Capabilities(
        integrators=(Integrator(label="semi-implicit Euler, positions first"),),
        restitution_rule=RestitutionRule.MAPPED,
    ),
    cost=Cost(
        step_cost_s=2e-5,
    ),
    look=Presentation(
        marker="*",
    ),
    studies=Studies(
        speed_accuracy=(KnobFamily(label="impulse, positions first", quick=True),),
    ),
)


class ToyEngine(BatchedEngine):
    """Impulses on sphere and capsule, in numpy, over many worlds."""

    record = RECORD

    def build(self, scene: Scene, worlds: int) -> None:
        self.scene, self.n = scene, worlds
        bat, ball = scene.bat, scene.ball
        self.mass = np.array([ball.mass_kg, bat.mass_kg])
        self.inertia = np.array([ball.inertia_kgm2, bat.inertia_cm_kgm2])
        self.s = np.zeros((worlds, 11))
        self.touching = np.zeros(worlds, dtype=bool)
        self.hands: list[Hands] | None = None

    def mass_properties(self) -> MassProperties:
        bat = self.scene.bat
        return MassProperties(
            bat_mass_kg=float(self.mass[1]),
            bat_com_from_knob_m=bat.com_from_knob_m,
            bat_inertia_kgm2=float(self.inertia[1]),
            ball_mass_kg=float(self.mass[0]),
            ball_inertia_kgm2=float(self.inertia[0]),
        )

    def set_state(self, states: np.ndarray) -> None:
        self.s = np.array(states, dtype=float)
        self.touching[:] = False

    def read(self) -> np.ndarray:
        return self.s.copy()

    def in_contact(self) -> np.ndarray:
        return self.touching.copy()

    def set_drive(self, hands) -> None:
        self.hands = None if hands is None else list(hands)

    def step(self) -> None:
        s, dt = self.s, self.settings.dt_s
        s[:, [BX, BY]] += dt * s[:, [BVX, BVY]]
        if self.hands is None:
            s[:, [CX, CY]] += dt * s[:, [CVX, CVY]]
            s[:, CA] += dt * s[:, CW]
        else:
            self._drive(dt)
        self._collide()

    def _drive(self, dt: float) -> None:
        """Positions first, then the loads' velocities; a hinged bat about its pivot."""
        s, bat = self.s, self.scene.bat
        M, J = bat.mass_kg, bat.inertia_cm_kgm2
        for i, h in enumerate(self.hands):
            angle = s[i, CA] + dt * s[i, CW]
            if h.pivot_from_com_m is None:
                s[i, [CX, CY]] += dt * s[i, [CVX, CVY]]
                s[i, CA] = angle
                q = angle + h.angle_rad
                s[i, CVX] += dt * h.force_n * math.cos(q) / M
                s[i, CVY] += dt * h.force_n * math.sin(q) / M
                s[i, CW] += dt * h.torque_about_com_nm / J
                continue
            p = h.pivot_from_com_m
            tau = h.torque_nm + (h.arm_m - p) * h.force_n * math.sin(h.angle_rad)
            omega = s[i, CW] + dt * tau / (J + M * p * p)
            c, sn = math.cos(angle), math.sin(angle)
            s[i, [CX, CY, CA]] = (h.pivot_xy_m[0] - p * c, h.pivot_xy_m[1] - p * sn, angle)
            s[i, [CVX, CVY, CW]] = (omega * p * sn, -omega * p * c, omega)

    def _collide(self) -> None:
        """Newton's impulse where the ball overlaps the bat and approaches it."""
        s, bat, ball = self.s, self.scene.bat, self.scene.ball
        c, sn = np.cos(s[:, CA]), np.sin(s[:, CA])
        dx, dy = s[:, BX] - s[:, CX], s[:, BY] - s[:, CY]
        t = np.clip(dx * c + dy * sn, bat.s_min_m, bat.s_max_m)
        nx, ny = dx - t * c, dy - t * sn
        dist = np.hypot(nx, ny)
        self.touching = (dist < bat.radius_m + ball.radius_m) & (dist > 0.0)
        nx, ny = nx / np.where(dist > 0.0, dist, 1.0), ny / np.where(dist > 0.0, dist, 1.0)
        arm = t * (c * ny - sn * nx)  # (r x n) of the bat's contact point about its COM
        vn = (s[:, BVX] - s[:, CVX] + s[:, CW] * t * sn) * nx + (
            s[:, BVY] - s[:, CVY] - s[:, CW] * t * c
        ) * ny
        hit = self.touching & (vn < 0.0)
        j = np.where(
            hit,
            -(1.0 + self.scene.e)
            * vn
            / (1 / ball.mass_kg + 1 / bat.mass_kg + arm**2 / bat.inertia_cm_kgm2),
            0.0,
        )
        s[:, BVX] += j * nx / ball.mass_kg
        s[:, BVY] += j * ny / ball.mass_kg
        s[:, CVX] -= j * nx / bat.mass_kg
        s[:, CVY] -= j * ny / bat.mass_kg
        s[:, CW] -= j * arm / bat.inertia_cm_kgm2


class OffByOnePercent(ToyEngine):
    """The same engine with its batted ball 1% too fast: ``check_engine`` must fail it."""

    def read(self) -> np.ndarray:
        out = super().read()
        out[:, BVY] = np.where(out[:, BVY] > 0.0, 1.01 * out[:, BVY], out[:, BVY])
        return out


#: The faulty twin, registered by a test under its own name.
FAULTY = dataclasses.replace(RECORD, name="toyengine_faulty", adapter="toy_engine:OffByOnePercent")


class Diverges(ToyEngine):
    """The same engine whose solver gives up once the ball touches the bat."""

    def step(self) -> None:
        super().step()
        if self.touching.any():
            raise RuntimeError("solver diverged")


#: A twin whose every impact raises mid-episode: a row each, never a crash.
BROKEN = dataclasses.replace(RECORD, name="toyengine_broken", adapter="toy_engine:Diverges")


# -- adapters that break the interface, each a twin under its own name (a test registers it):
# every one of them must become rows that say what it did, never the end of a run


class Exits(ToyEngine):
    """Calls sys.exit(0) once the ball touches the bat."""

    def step(self) -> None:
        super().step()
        if self.touching.any():
            raise SystemExit(0)


class Hangs(ToyEngine):
    """Never returns once the ball touches the bat."""

    def step(self) -> None:
        super().step()
        if self.touching.any():
            time.sleep(3600)


class StuckFlag(ToyEngine):
    """Says the bodies touch at every step, whatever its state."""

    def in_contact(self) -> np.ndarray:
        return np.ones(self.n, dtype=bool)


class WrongShape(ToyEngine):
    """Reads back five columns a world."""

    def read(self) -> np.ndarray:
        return self.s[:, :5].copy()


class ExitsHard(ToyEngine):
    """Ends its process with os._exit(3) once the ball touches the bat."""

    def step(self) -> None:
        super().step()
        if self.touching.any():
            os._exit(3)


class Interrupts(ToyEngine):
    """Raises KeyboardInterrupt once the ball touches the bat (no Ctrl-C was pressed)."""

    def step(self) -> None:
        super().step()
        if self.touching.any():
            raise KeyboardInterrupt


class Strings(ToyEngine):
    """Reads back its state as text."""

    def read(self) -> np.ndarray:
        return self.s.astype(str)


class Integers(ToyEngine):
    """Reads back its state rounded to integers."""

    def read(self) -> np.ndarray:
        return self.s.astype(np.int64)


class CloseHangs(ToyEngine):
    """Never returns from close."""

    def close(self) -> None:
        time.sleep(3600)


class HeavyBall(ToyEngine):
    """Holds a ball 10% heavier than the scene's."""

    def mass_properties(self) -> MassProperties:
        return dataclasses.replace(
            super().mass_properties(), ball_mass_kg=1.1 * float(self.mass[0])
        )


MISBEHAVING = {
    name: dataclasses.replace(
        RECORD,
        name=f"toyengine_{name}",
        adapter=f"toy_engine:{cls}",
        cost=Cost(step_cost_s=2e-5, impact_limit_s=limit),
    )
    for name, cls, limit in (
        ("exits", "Exits", None),
        ("hangs", "Hangs", 1.0),
        ("stuckflag", "StuckFlag", None),
        ("wrongshape", "WrongShape", None),
        ("heavyball", "HeavyBall", None),
        ("exitshard", "ExitsHard", None),
        ("interrupts", "Interrupts", None),
        ("strings", "Strings", None),
        ("integers", "Integers", None),
        ("closehangs", "CloseHangs", None),
    )
}
#: The twins one by one, for entry points ("toy_engine:MISBEHAVING_HANGS").
globals().update({f"MISBEHAVING_{k.upper()}": rec for k, rec in MISBEHAVING.items()})
