"""The engines a process holds: one ``Hosted`` per engine and settings, made once and reused
(adapters hold no state between impacts), oldest closed first; a single-world engine's
``Hosted`` makes more of its adapters for a long run, stepped together as one batch, or, where
its record names one (``Capabilities.pool_adapter``), one adapter holding the run's worlds.
"""

from __future__ import annotations

import atexit
import contextlib
import gc
import math
import time
from collections import OrderedDict
from dataclasses import replace

import adapters
from adapters import BatchedEngine, MassProperties, Scene, Settings, clock

from .judge import mass_allowance
from .worlds import EngineWorlds, ManyWorlds, OneWorld

#: Engines kept alive per process (one per engine and settings), oldest closed first.
ENGINE_CACHE = 8


class SceneMismatch(RuntimeError):
    """The engine holds mass properties other than the scene's (an adapter bug, not physics)."""


#: The most single-world engines one ``Hosted`` steps together as one batch (``EngineWorlds``),
#: and the fewest worth it: the batch's numpy work on a step (about 0.3 ms here) must be shared
#: by enough worlds to cost less than a world alone does in Python floats.
POOL_MAX, POOL_MIN = 256, 16
#: The most worlds of a pool adapter (``Capabilities.pool_adapter``: worlds on one model, the
#: harness's work on a step shared by them all) one batch holds, within the record's
#: ``max_worlds``: MuJoCo's judged impact cost 13.3 / 12.0 us at 1e3 / 1e4 in pools of 256,
#: 9.3 / 8.3 in pools of 1000 (7.1 in one of 1e4), and an e = 0 run of 2048 impacts peaked at
#: 0.29 GB in pools of 256, 0.72 GB in pools of 1024 (each world's long contact held; measured).
POOL_ADAPTER_MAX = 1024
#: What an impact costs the harness less when fired in a batch of single-world engines than
#: alone (s): 93-118 us alone against 8-16 us in a batch of 90-250 (MuJoCo, PyBullet, pymunk in
#: a run of 1e3, ``bench_engines``' harness share on a 2-core host). More engines are made only
#: once the impacts fired repay their making.
POOLED_SAVING_S = 1e-4


def batch_cap(record: adapters.EngineRecord) -> int:
    """The most worlds one batch of a single-world engine holds before its ``max_worlds``:
    POOL_MAX engines apart, POOL_ADAPTER_MAX in its pool adapter."""
    return POOL_MAX if record.can.pool_adapter is None else POOL_ADAPTER_MAX


class Hosted:
    """One engine with its settings, and the scene it holds: a batched adapter, or the
    single-world adapters (one, or more for a long run: ``pool_size``) stepped together."""

    def __init__(self, name: str, settings: Settings) -> None:
        self.name, self.settings = name, settings
        self.record = adapters.record(name)
        self.adapter = adapters.create(name, settings)
        # what one more world costs (``pool_size``): declared for a pool whose worlds cost a
        # fixed trifle (``Cost.pool_world_make_s``), else timed on the first build
        self.make_s: float | None = self.record.cost.pool_world_make_s
        self.batched = isinstance(self.adapter, BatchedEngine)
        self.engines, self.scenes = [self.adapter], [None]
        self.scene: Scene | None = None
        self.worlds = 0
        # a single-world engine's pool adapter (``Capabilities.pool_adapter``), once made: its
        # scene and world count as built, and the most worlds it was built with (it keeps
        # what holds them)
        self.pool, self.pool_scene, self.pool_n, self.pool_worlds = None, None, 0, 0
        self.broken = False  # whether its adapters failed (``failed``)

    def failed(self, timed_out: bool = False) -> None:
        """The engine failed a batch (raised, exited, timed out): its adapters, in whatever
        state that left them, are made anew before the next (``renew_if_failed``); a timeout
        counts towards the engine's ``TIMEOUTS`` in a row."""
        self.broken = True
        TIMEOUTS[self.name] = TIMEOUTS.get(self.name, 0) + timed_out

    def succeeded(self) -> None:
        """The engine fired a batch: its timeouts in a row start again from none."""
        TIMEOUTS.pop(self.name, None)

    def renew_if_failed(self) -> None:
        """After a failure: close every adapter (whatever it says, it is not used again) and
        make the first one anew."""
        if not self.broken:
            return
        self.close()
        self.engines, self.scenes, self.scene, self.worlds = [], [], None, 0
        self.adapter = adapters.create(self.name, self.settings)
        self.engines, self.scenes, self.broken = [self.adapter], [None], False

    def held(self) -> int:
        """How many worlds this host holds: its single-world adapters', or its pool's."""
        return max(len(self.engines), self.pool_worlds)

    def pool_size(self, impacts: int, left: int) -> int:
        """How many single-world engines to step the next of a run's ``left`` impacts on (of
        ``impacts`` in all): those made already, or as many as the run repays
        (``POOLED_SAVING_S`` an impact against each engine's making: its first build as timed,
        then, with a pool adapter, a world's share of the pool's first build), if at least
        ``POOL_MIN``, shared out evenly. Every batch of a run asks of the whole run, and the
        cost of making is measured once, so a run fired again finds its engines made: a
        firing makes what it repays itself, in a run's first firing, not a few each time.
        Where the record declares what a pool world costs (``Cost.pool_world_make_s``), nothing
        is timed: a run is pooled from its first batch, the same whatever the machine's load
        (timed, a loaded machine's slow first build left a run of 200 impacts unpooled)."""
        if self.make_s is None:
            return 1
        repaid = int(impacts * POOLED_SAVING_S / self.make_s)
        size = min(batch_cap(self.record), impacts, max(self.held(), repaid))
        if size > self.held() and self.record.can.max_worlds is not None:
            size = min(size, _room(self))
        # the run in batches of even size (no last one of a few impacts, fired alone)
        size = min(left, math.ceil(impacts / math.ceil(impacts / size)))
        return size if size >= POOL_MIN else 1

    def shrink(self) -> None:
        """Close every engine but the first (a pool given back)."""
        for engine in self.engines[1:]:
            _close(engine)
        del self.engines[1:], self.scenes[1:]
        if self.pool is not None:
            _close(self.pool)
            self.pool, self.pool_scene, self.pool_n, self.pool_worlds = None, None, 0, 0

    def batch(self, scene: Scene, n: int):
        """The adapter(s) holding ``scene`` in ``n`` worlds (built when either changed, and
        their mass properties checked), seen as the episode steps them."""
        if self.batched:
            if scene != self.scene or n != self.worlds:
                self.scene = None
                self.adapter.build(scene, n)
                self._check(self.adapter, scene)
                self.scene, self.worlds = scene, n
            return ManyWorlds(self.adapter, n)
        if n > 1 and self.record.can.pool_adapter is not None:
            return self._pooled(scene, n)
        while len(self.engines) < n:
            self.engines.append(adapters.create(self.name, self.settings))
            self.scenes.append(None)
        for i in range(n):
            if self.scenes[i] != scene:
                self.scenes[i] = None
                t0 = time.perf_counter()
                self.engines[i].build(scene)
                if self.make_s is None:
                    self.make_s = time.perf_counter() - t0
                self._check(self.engines[i], scene)
                self.scenes[i] = self.scene = scene
        return OneWorld(self.adapter) if n == 1 else EngineWorlds(self.engines[:n])

    def _pooled(self, scene: Scene, n: int) -> ManyWorlds:
        """The engine's pool adapter holding ``scene`` in ``n`` worlds (built when either
        changed, its mass properties checked)."""
        if self.pool is None:
            self.pool = adapters.pool_class(self.name)(self.settings)
        if scene != self.pool_scene or n != self.pool_n:
            self.pool_scene = None
            t0 = time.perf_counter()
            self.pool.build(scene, n)
            if self.pool_worlds == 0 and self.record.cost.pool_world_make_s is None:
                # what a world costs in the pool, as first built
                self.make_s = (time.perf_counter() - t0) / n
            self._check(self.pool, scene)
            self.pool_scene, self.pool_n = scene, n
            self.pool_worlds = max(self.pool_worlds, n)
        return ManyWorlds(self.pool, n)

    def _check(self, adapter, scene: Scene) -> None:
        check_mass_properties(self.name, adapter.mass_properties(), scene, self.record.eps)

    def close(self) -> None:
        """Close every adapter it holds (``_close``: whatever each does, it is not used again)."""
        self.scene, self.scenes = None, [None] * len(self.engines)
        for engine in self.engines:
            _close(engine)
        if self.pool is not None:
            _close(self.pool)
            self.pool, self.pool_scene, self.pool_n, self.pool_worlds = None, None, 0, 0


#: How long an adapter's close may take (s) before it is left as it is.
CLOSE_LIMIT_S = 10.0


def _close(adapter) -> None:
    """Close an adapter within CLOSE_LIMIT_S, whatever it does: one that raises, exits or hangs
    there is left to the process's end (its results are in already)."""
    with (
        contextlib.suppress(Exception, SystemExit, clock.TimedOut, clock.ProcessExit),
        clock.limited(CLOSE_LIMIT_S),
        clock.exits_raise(),
    ):
        adapter.close()


def _room(host: Hosted) -> int:
    """How many worlds ``host`` may hold within its engine's ``max_worlds``: the other hosts
    of that engine give back their pools first, and keep a world each."""
    others = [h for h in _HOSTED.values() if h is not host and h.name == host.name]
    for other in others:
        other.shrink()
    return host.record.can.max_worlds - len(others)


def check_mass_properties(name: str, got: MassProperties, scene: Scene, eps: float) -> None:
    """Raise SceneMismatch unless the engine holds the scene's mass properties, to
    ``judge.mass_allowance`` of its precision."""
    bat, ball = scene.bat, scene.ball
    want = MassProperties(
        bat_mass_kg=bat.mass_kg,
        bat_com_from_knob_m=bat.com_from_knob_m,
        bat_inertia_kgm2=bat.inertia_cm_kgm2,
        ball_mass_kg=ball.mass_kg,
        ball_inertia_kgm2=ball.inertia_kgm2,
    )
    rel = mass_allowance(eps)
    for field in MassProperties.__dataclass_fields__:
        a, b = getattr(got, field), getattr(want, field)
        if not math.isclose(a, b, rel_tol=rel, abs_tol=1e-15):
            raise SceneMismatch(
                f"{name}: {field} read back as {a!r}, the scene has {b!r} "
                f"(allowed relative difference {rel:g})"
            )


_HOSTED: OrderedDict[tuple[str, Settings], Hosted] = OrderedDict()
#: Engine name -> its batches that timed out in a row in this process, whatever their
#: settings: a hung engine hangs at any.
TIMEOUTS: dict[str, int] = {}


def engine_settings(name: str, settings: Settings) -> Settings:
    """The settings an engine is made with: a batched engine's worlds may differ in where the
    contact falls in a step (``contact_phase``: placement, the harness's, not the engine's),
    so its adapter is made with contact_phase 0 and serves them all."""
    if adapters.record(name).batched and settings.contact_phase != 0.0:
        return replace(settings, contact_phase=0.0)
    return settings


def hosted(name: str, settings: Settings) -> Hosted:
    """This process's adapter for ``name`` and ``settings`` (made once, reused)."""
    settings = engine_settings(name, settings)
    key = (name, settings)
    if key in _HOSTED:
        _HOSTED.move_to_end(key)
        return _HOSTED[key]
    while len(_HOSTED) >= ENGINE_CACHE:
        _HOSTED.popitem(last=False)[1].close()
    made = _HOSTED[key] = Hosted(name, settings)
    return made


def close_engines() -> None:
    """Close every adapter this process holds, and free what they held (an engine's objects
    in reference cycles, freed at exit after their library, would complain)."""
    while _HOSTED:
        _HOSTED.popitem()[1].close()
    TIMEOUTS.clear()
    gc.collect()


# at exit, while the engines' own modules are still there to free their worlds
atexit.register(close_engines)


def forget_engines() -> None:
    """In a forked worker: drop the copies of the parent's adapters (they are the parent's),
    and free them: an engine's limit on worlds (``Capabilities.max_worlds``) counts them."""
    _HOSTED.clear()
    gc.collect()
