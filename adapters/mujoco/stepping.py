"""How MuJoCo's worlds pool (``worlds``) steps its worlds: many at once in one call of MuJoCo's
``mujoco.rollout`` (``roll``, with the worlds whose call met a warning found in its output,
``warned``), or one alone on data of its own, one ``mj_step`` at a time (``OwnWorld``). The
pool decides which worlds go where and from which step; this module only steps (and says
what a call gave, ``Chunk``, and what a drive is stepped under, ``driven``).

``rollout`` takes physics rows (time, qpos, qvel: ``rows``) and a warm start in, and gives the
state and sensor data of every step out; the contact flag of a step is the model's contact
sensor (``model.CONTACT_SENSOR``: the contacts at the step's start, which ``ncon`` is after
``mj_step``), the first sensor datum.
"""

from __future__ import annotations

import contextlib
import importlib
from dataclasses import dataclass

import numpy as np

from ..loading import import_engine
from . import RECORD
from .adapter import BLOW_UPS
from .rows import QVEL, TIME, WIDTH

mujoco = import_engine(RECORD)
#: MuJoCo's batched call, where the release has it with its contact sensor (else every world
#: is stepped on its own, as alone).
ROLLOUT = None
with contextlib.suppress(ImportError):
    ROLLOUT = getattr(importlib.import_module("mujoco.rollout"), "Rollout", None)
if not hasattr(mujoco.mjtSensor, "mjSENS_CONTACT"):
    ROLLOUT = None

FULL = int(mujoco.mjtState.mjSTATE_FULLPHYSICS)
#: What a chunk's controls set at every step: the motors and the hands' constraint.
CONTROL = int(mujoco.mjtState.mjSTATE_CTRL) | int(mujoco.mjtState.mjSTATE_EQ_ACTIVE)


@dataclass(frozen=True, kw_only=True)
class Chunk:
    """One call's steps, as the pool keeps them (``worlds``): its worlds, the step before each
    one's first (its rest point), the states (worlds, steps, 27) and contact flags (worlds,
    steps) it gave, the rows it started from and the models and control rows it ran under (and
    a carried world's warm start then)."""

    worlds: np.ndarray
    base_step: np.ndarray
    rows: np.ndarray
    touching: np.ndarray
    start_rows: np.ndarray
    models: list
    control: np.ndarray  # (worlds, nc)
    start_warm: np.ndarray | None = None  # (worlds, nv)
    #: (worlds,) the rows dropped before the first kept (a drive's call keeps one)
    dropped: np.ndarray | None = None


def roll(
    pool, models: list, datas: list, start: np.ndarray, control: np.ndarray, steps: int, warm=None
) -> tuple[np.ndarray, np.ndarray]:
    """One ``rollout`` call on ``pool`` (a ``Rollout``) with its threads' ``datas``: the
    worlds whose physics rows are ``start`` (k, 27) on their ``models`` (k, of one
    structure), ``steps`` steps under their control rows ``control`` (k, nc; or one row for
    all), from the warm start ``warm`` (k, nv; None: zero). The states (k, steps, 27) and the
    contact flags (k, steps) of every step."""
    k = len(start)
    rows = np.empty((k, steps, WIDTH))
    sensors = np.empty((k, steps, models[0].nsensordata))
    controls = np.empty((k, steps, control.shape[-1]))
    controls[:] = control if control.ndim == 1 else control[:, None, :]
    pool.rollout(
        models,
        datas,
        start,
        controls,
        control_spec=CONTROL,
        skip_checks=True,
        nstep=steps,
        initial_warmstart=warm,
        state=rows,
        sensordata=sensors,
    )
    return rows, sensors[:, :, 0] > 0.0


def warned(start: np.ndarray, rows: np.ndarray, dt_s: float) -> np.ndarray:
    """Per world of a ``roll``, whether its call met a warning: ``rollout`` stops stepping it
    there (the later steps repeat the last state, its time too), where MuJoCo had reset the
    state (time 0, at rest) and gone on, as a world alone would."""
    k, steps = rows.shape[:2]
    clock = np.cumsum(np.hstack([start[:, TIME : TIME + 1], np.full((k, steps), dt_s)]), axis=1)
    return np.any(rows[:, :, TIME] != clock[:, 1:], axis=1) | (
        (start[:, TIME] == 0.0) & np.all(rows[:, 0, QVEL] == 0.0, axis=1)
    )


def clear_warnings(data, which=None) -> None:
    """Zero ``data``'s warning counters (``which``: their indices; None: every one)."""
    for w in range(len(data.warning)) if which is None else which:
        data.warning[w].number = 0


def any_warning(data, which=None) -> bool:
    """Whether ``data`` counts a warning (``which``: among these indices; None: any)."""
    return any(
        data.warning[w].number for w in (range(len(data.warning)) if which is None else which)
    )


def control_row(engine) -> np.ndarray:
    """The control row (``CONTROL``) ``engine`` (a ``MujocoEngine``) steps under."""
    out = np.empty(mujoco.mj_stateSize(engine.model, CONTROL))
    mujoco.mj_getState(engine.model, engine.data, out, CONTROL)
    return out


def driven(engine, hands) -> tuple[list, np.ndarray]:
    """Per world, a model driven by its ``hands`` (a copy of ``engine``'s holding their pivot
    and load site, one for equal hands: ``MujocoEngine.driven_twin``) and its control row."""
    twins = {}
    for h in hands:
        if h not in twins:
            twins[h] = engine.driven_twin(h)
    return [twins[h].model for h in hands], np.stack([control_row(twins[h]) for h in hands])


class OwnWorld:
    """A world stepped on data of its own, one ``mj_step`` at a time, as alone: from the
    physics row ``row`` at ``step``, on ``model`` under the control row ``control``, from the
    warm start ``warm`` (None: zero; any at a rest point)."""

    def __init__(
        self, data, model, row: np.ndarray, step: int, control: np.ndarray, warm=None
    ) -> None:
        self.data, self.model, self.step = data, model, step
        mujoco.mj_setState(model, data, row, FULL)
        data.qacc_warmstart[:] = 0.0 if warm is None else warm
        clear_warnings(data, BLOW_UPS)
        self.set_control(model, control)

    def set_control(self, model, control: np.ndarray) -> None:
        """Step on under ``control`` on ``model`` (a drive changed)."""
        self.model = model
        mujoco.mj_setState(model, self.data, control, CONTROL)

    def advance(self, to_step: int) -> None:
        for _ in range(to_step - self.step):
            mujoco.mj_step(self.model, self.data)
        self.step = max(self.step, to_step)

    def row(self, out: np.ndarray) -> None:
        mujoco.mj_getState(self.model, self.data, out, FULL)

    def touching(self) -> bool:
        return self.data.ncon > 0

    def failed(self) -> bool:
        return any_warning(self.data, BLOW_UPS)
