"""Throughput against batch size, with the error beside it (a part of ``bench_engines``).

For one engine at its reference profile: the paper's swing over the 41-point grid, tiled to B
impacts, fired as one call (one batch on a batched engine, pools of its adapters on a
single-world one) and every impact judged where the firing ends (``verdicts.judge_columns``):
judged impacts per second, the largest |v1 - rigid theory| and the status counts. Laying the
verdicts out as a pandas table is presentation, timed on its own after
(``table_us_per_impact``: a few hundred us for a table of one row, which a caller judging one
impact never builds). The harness's own cost is the firing's and judging's wall time less the
time spent inside the engine's calls (ENGINE_CALLS), clocked in the same firing (two separate
timings of ~60 us an impact differ by more than the few us sought), the clock's own cost per
call (0.3 us here, measured on a call that does nothing) taken out of both; the same worlds
stepped bare (set the starts, step as many times, nothing read) are timed beside it. Where the
engine's time goes: inside its steps alone (``step_us_per_impact``; on a GPU a step may only
queue work, waited for at the next read) and a read of states already computed
(``read_us_per_impact``: the copy off the device and the conversion). A single-world engine's
long run is stepped bare on its pool adapter, as the harness held it, and beside it its
library's own batched call on the same states and threads (``anchor_us_per_impact``,
``BatchedEngine.anchor_s``; NaN without one): a pool that steps only when read (MuJoCo's,
through ``mujoco.rollout``) shows its steps under the reads. Each size is fired once untimed
first (compiles, caches); the numbers are medians of the repeats (below LOOPED_IMPACTS impacts,
each repeat the mean over that many impacts' worth of firings; the bare run and its anchor
timed up to BARE_TIMINGS times a repeat). Sizes grow while the next one's
firing, priced at this one's cost per impact, fits in the budget. Every adapter made before, of
any engine, is closed first: each engine is measured alone in the process (another engine's
hundreds of adapters left alive slowed the next: PyBullet at 1e3 measured 12-14 us alone, 17
after PhysX).
"""

from __future__ import annotations

import contextlib
import math
import time

import numpy as np
import pandas as pd

import adapters
from adapters import Scene
from analytic import presets

from ..core import firings, inputs, tables, verdicts
from ..core.fire import Jobs, fire_jobs
from ..core.fired import gather
from ..core.hosting import close_engines, hosted
from ..core.judge import Status
from ..core.placement import start_state

GRID = 41
SIZES = (1, 10, 100, 1_000, 10_000, 100_000)
#: A batch smaller than this is fired (and stepped bare) this many impacts' worth of times in
#: each timing, the per-firing mean taken: one firing of one impact lasts a few hundred us, in
#: which the machine's other work and a cold cache moved a single timing by 2-3x (measured:
#: batch 1's bare 42-62 us a timing, 19-26 us at best over 2000).
LOOPED_IMPACTS = 100
#: The bare run (and its library's batched call beside it) is timed up to this many times in
#: each repeat, taking turns, the medians kept, while those timings last at most BARE_BUDGET_S
#: in all: one timing each of 1e3 MuJoCo worlds (7 ms) put the bare pool at 1.20-1.37x
#: ``rollout``'s own over four runs, five each at 1.19-1.20x in isolation (measured).
BARE_TIMINGS = 5
BARE_BUDGET_S = 0.5


def _firing() -> firings.Firing:
    return firings.Firing(
        bat=presets.R161,
        s_m=firings.grid(presets.R161, GRID),
        v0_mps=presets.PAPER_PITCH_MPS,
        u0_mps=presets.PAPER_SWING.u0_mps,
        omega0_radps=presets.PAPER_SWING.omega0_radps,
        e=presets.E_WOOD,
    )


def bare_s(
    name: str, settings, cases, steps: int, reads: list | None = None, anchors: list | None = None
) -> float:
    """Seconds to set the batch's starts and step it ``steps`` times, nothing read; a batched
    engine's states read once at the end, and, with ``reads``, read again (the states already
    computed: the copy off the device and the conversion alone), that second read's seconds
    appended to it. A single-world engine's run held in its pool adapter is stepped there, in
    batches of the worlds the pool holds, with the states read once at the end of each; with
    ``anchors``, the seconds its library's own batched call takes on the same states
    (``BatchedEngine.anchor_s``) are appended, None without one."""
    host = hosted(name, settings)
    c = cases[0]
    if not host.batched and host.pool is not None and host.pool_worlds > 1:
        size, bare, anchor = host.pool_worlds, 0.0, 0.0
        for first in range(0, len(cases), size):
            part = cases[first : first + size]
            batch = host.batch(Scene(bat=c.bat, ball=c.ball, e=c.e), len(part))
            starts = batch.xp.stack([start_state(k, settings)[0] for k in part])
            t0 = time.perf_counter()
            batch.set_state(starts)
            for _ in range(steps):
                batch.step()
            batch.read()
            bare += time.perf_counter() - t0
            one = host.pool.anchor_s(starts, steps) if anchors is not None else None
            anchor = None if one is None or anchor is None else anchor + one
        if anchors is not None:
            anchors.append(anchor)
        return bare
    if host.batched:
        batch = host.batch(Scene(bat=c.bat, ball=c.ball, e=c.e), len(cases))
        starts = batch.xp.stack([start_state(k, settings)[0] for k in cases])
        t0 = time.perf_counter()
        batch.set_state(starts)
        for _ in range(steps):
            batch.step()
        batch.read()
        bare = time.perf_counter() - t0
        if reads is not None:
            t0 = time.perf_counter()
            batch.read()
            reads.append(time.perf_counter() - t0)
        return bare
    batch = host.batch(Scene(bat=c.bat, ball=c.ball, e=c.e), 1)
    t0 = time.perf_counter()
    for k in cases:
        batch.set_state(start_state(k, settings)[0])
        for _ in range(steps):
            batch.step()
    return time.perf_counter() - t0


#: The adapter calls that are the engine's own work: the time inside them is the engine's.
ENGINE_CALLS = ("set_state", "step", "read", "in_contact", "failed", "set_drive")


#: Whether a clocked call is under way (``_clocked``).
_INSIDE = [False]


@contextlib.contextmanager
def _clocked(cls: type, spent: list[float]):
    """While open, the time inside the ENGINE_CALLS of every adapter of class ``cls`` (those
    made meanwhile too) adds up in ``spent[0]`` (s), the calls are counted in ``spent[1]``, and
    the time inside ``step`` alone adds up in ``spent[2]`` (s)."""

    def clock(call):
        stepping = call.__name__ == "step"

        def timed(*args):
            if _INSIDE[0]:  # a pool's call into its worlds' adapters: counted once, outside
                return call(*args)
            _INSIDE[0] = True
            t0 = time.perf_counter()
            try:
                return call(*args)
            finally:
                dt = time.perf_counter() - t0
                _INSIDE[0] = False
                spent[0] += dt
                spent[1] += 1
                if stepping:
                    spent[2] += dt

        return timed

    calls = {name: cls.__dict__.get(name) for name in ENGINE_CALLS if hasattr(cls, name)}
    for name in calls:
        setattr(cls, name, clock(getattr(cls, name)))
    try:
        yield
    finally:
        for name, own in calls.items():
            if own is None:
                delattr(cls, name)
            else:
                setattr(cls, name, own)


class _Noop:
    def step(self) -> None:
        pass


def clock_cost_s(calls: int = 20_000) -> tuple[float, float]:
    """What the clock adds to one call (s): the part it counts as the engine's (its own
    readings) and the part outside its readings, that would count as the harness's; both
    measured on a call that does nothing, medians of 5."""
    noop = _Noop()
    inside, outside = [], []
    for _ in range(5):
        t0 = time.perf_counter()
        for _ in range(calls):
            noop.step()
        plain = time.perf_counter() - t0
        spent = [0.0, 0, 0.0]
        with _clocked(_Noop, spent):
            t0 = time.perf_counter()
            for _ in range(calls):
                noop.step()
            wall = time.perf_counter() - t0
        inside.append(spent[0] / calls)
        outside.append((wall - plain - spent[0]) / calls)
    return float(np.median(inside)), float(np.median(outside))


def _timed(name: str, settings, jobs: Jobs, clock: tuple[float, float], loops: int = 1):
    """Fire ``jobs`` and judge every impact, ``loops`` times over: the last table, and per
    firing the wall time and the time inside the engine's calls and inside its steps alone
    (s), the clock's own cost (``clock_cost_s``) taken out of each, and the table's layout
    time after (s)."""
    spent = [0.0, 0, 0.0]
    pool = adapters.pool_class(name)  # a single-world engine's long runs step on it
    wall = layout_s = 0.0
    with (
        _clocked(type(hosted(name, settings).adapter), spent),
        _clocked(pool, spent) if pool is not None else contextlib.nullcontext(),
    ):
        for _ in range(loops):
            t0 = time.perf_counter()
            fired = gather(fire_jobs(jobs))
            judged = verdicts.judge_columns(fired)
            t1 = time.perf_counter()
            table = tables.layout(fired, judged, "throughput")
            wall, layout_s = wall + t1 - t0, layout_s + time.perf_counter() - t1
    inside_s, outside_s = clock
    return (
        table,
        (wall - spent[1] * (inside_s + outside_s)) / loops,
        (spent[0] - spent[1] * inside_s) / loops,
        spent[2] / loops,
        layout_s / loops,
    )


def measure(name: str, sizes=SIZES, budget_s: float = 30.0, repeats: int = 3) -> list[dict]:
    """One row per batch size (module docstring): medians of ``repeats`` firings and as many
    bare runs, taking turns."""
    close_engines()  # measured alone in the process (module docstring)
    settings = adapters.settings_for(name)
    base = _firing().cases()
    clock = clock_cost_s()
    rows = []
    for size in sizes:
        cases = [base[i % GRID] for i in range(size)]
        jobs = Jobs(engine=name, settings=settings, cases=cases)
        fired = fire_jobs(jobs)  # compile and warm at this size (and the judge's answers)
        tables.table(fired, "throughput")
        steps = int(np.median([f.outcome.steps for f in fired[:GRID]]))
        walls, inside, stepping, bares, reads, anchors = [], [], [], [], [], []
        layouts, loops = [], max(1, LOOPED_IMPACTS // size)
        for _ in range(repeats):
            table, wall, engine, step, layout = _timed(name, settings, jobs, clock, loops)
            walls.append(wall)
            layouts.append(layout)
            inside.append(wall - engine)
            stepping.append(step)
            for _ in range(
                max(1, min(BARE_TIMINGS, int(BARE_BUDGET_S / max(engine * loops, 1e-6))))
            ):
                bare = [bare_s(name, settings, cases, steps, reads, anchors) for _ in range(loops)]
                bares.append(sum(bare) / loops)
        anchored = [a for a in anchors if a is not None]
        wall, bare = float(np.median(walls)), float(np.median(bares))
        rows.append(
            {
                "engine": name,
                "precision": adapters.record(name).errors.precision,
                "batched": hosted(name, settings).batched,
                "device": device(name, settings),
                "batch": size,
                "impacts_per_s": size / wall,
                "wall_s": wall,
                "us_per_impact": wall / size * 1e6,
                "bare_us_per_impact": bare / size * 1e6,
                "anchor_us_per_impact": (
                    float(np.median(anchored)) / size * 1e6 if anchored else math.nan
                ),
                "harness_us_per_impact": float(np.median(inside)) / size * 1e6,
                "step_us_per_impact": float(np.median(stepping)) / size * 1e6,
                "read_us_per_impact": float(np.median(reads)) / size * 1e6 if reads else math.nan,
                "table_us_per_impact": float(np.median(layouts)) / size * 1e6,
                "steps_median": steps,
                "repeats": repeats,
                "max_abs_err_mps": float(table.v1_abs_err_mps.max()),
                "ok": int((table.status == Status.OK).sum()),
                "judged": len(table),
            }
        )
        later = [n for n in sizes if n > size]
        if later and wall / size * min(later) > budget_s:
            break
    return rows


def device(name: str, settings) -> str:
    """Where the engine computes ('cpu' unless its adapter says otherwise)."""
    adapter = hosted(name, settings).adapter
    return adapter.device() if hasattr(adapter, "device") else "cpu"


def kind(device: str) -> str:
    """'GPU' or 'CPU': the kind of device a row's ``device`` names (``inputs.device_kind``;
    an accelerator it does not know of is a GPU here)."""
    return inputs.device_kind(device) or "GPU"


#: What a throughput row measures: a row kept from another table (``merged``) gives way only
#: to one this run measured for the same engine, kind of device and batch size.
ROW_KEY = ("engine", "kind", "batch")


def merged(measured: pd.DataFrame | None, kept: pd.DataFrame | None) -> pd.DataFrame:
    """``measured`` and every row of ``kept`` that it did not measure again (``ROW_KEY``): one
    engine's CPU rows measured anew keep every other engine's rows, its own rows on the other
    kind of device (the CPU rows of one machine beside the GPU rows of another) and at the batch
    sizes this run did not ask for. In the table's order: by engine, batch, CPU before GPU."""
    parts = [t for t in (measured, kept) if t is not None and not t.empty]
    if not parts:
        return measured if measured is not None else kept
    keyed = [t.assign(kind=[kind(d) for d in t.device]) for t in parts]
    both = pd.concat(keyed, ignore_index=True).drop_duplicates(list(ROW_KEY), keep="first")
    return (
        both.sort_values(["engine", "batch", "kind"], kind="stable")
        .drop(columns="kind")
        .reset_index(drop=True)
    )


def chart(table: pd.DataFrame):
    """Impacts per second against the largest error, one marker per engine and precision,
    sized by batch; CPU and GPU in two panels."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    kinds = sorted({kind(d) for d in table.device})
    table = table.assign(device=table.device.replace({"cpu: cpu": "cpu"}))
    fig, axes = plt.subplots(
        1, len(kinds), figsize=(6.5 * len(kinds) + 3, 5), squeeze=False, layout="constrained"
    )
    for ax, panel in zip(axes[0], kinds):
        part = table[[kind(d) == panel for d in table.device]]
        shift = _side_by_side(part)
        for name, rows in part.groupby("engine", sort=False):
            rec = adapters.record(name)
            best = rows.loc[rows.impacts_per_s.idxmax()]
            err = rows.max_abs_err_mps.clip(lower=1e-16) * shift[name]
            ax.plot(err, rows.impacts_per_s, "-", color=rec.look.color, alpha=0.4)
            ax.scatter(
                err,
                rows.impacts_per_s,
                s=12 + 10 * np.log10(rows.batch),
                marker=rec.look.marker,
                color=rec.look.color,
                label=f"{name} ({rec.errors.precision}; best at batch {best.batch:,})",
            )
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("largest |v1 - rigid theory| over the judged impacts (m/s, log)")
        ax.set_ylabel("judged impacts per second (log)")
        ax.set_title(
            f"{panel}: {', '.join(sorted(set(part.device)))}\nmarker size: batch "
            f"1 .. {part.batch.max():.0e} (line joins one engine's sizes)"
            + (
                "\nengines of equal error set side by side (x times 1.3^k)"
                if any(v != 1.0 for v in shift.values())
                else ""
            ),
            fontsize=9,
        )
        ax.grid(alpha=0.3, which="both")
        ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0))  # off the marks
    return fig


def _side_by_side(part: pd.DataFrame) -> dict[str, float]:
    """Each engine's factor on its errors in the chart: engines whose largest errors are equal
    (to 2 digits, every batch size alike) are set side by side, 1.3 times apart, so that no
    marker hides another; 1 for the rest."""
    groups: dict[tuple, list[str]] = {}
    for name, rows in part.groupby("engine", sort=False):
        key = tuple(sorted({float(f"{x:.2g}") for x in rows.max_abs_err_mps}))
        groups.setdefault(key, []).append(name)
    return {
        name: 1.3 ** (k - (len(names) - 1) / 2)
        for names in groups.values()
        for k, name in enumerate(names)
    }


def summary(table: pd.DataFrame) -> pd.DataFrame:
    """Per engine: cost per impact at batch 1 and at its best batch, and the error."""
    out = []
    for name, rows in table.groupby("engine", sort=False):
        one = rows[rows.batch == 1]
        best = rows.loc[rows.impacts_per_s.idxmax()]
        out.append(
            {
                "engine": name,
                "precision": best.precision,
                "device": best.device,
                "us_per_impact_batch1": float(one.us_per_impact.iloc[0]) if len(one) else math.nan,
                "best_batch": int(best.batch),
                "us_per_impact_best": float(best.us_per_impact),
                "impacts_per_s_best": float(best.impacts_per_s),
                "max_abs_err_mps": float(rows.max_abs_err_mps.max()),
            }
        )
    return pd.DataFrame(out)
