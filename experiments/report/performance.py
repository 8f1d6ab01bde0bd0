"""What a collision costs in each engine, and what the runners gain (the benchmarks)."""

from __future__ import annotations

import math
import re

import pandas as pd

from ..core.runner import CHUNK_S, MIN_PARALLEL_S
from . import gpu
from .base import (
    Results,
    engines_text,
    label,
    lead,
    md_table,
    names,
    num,
    sci,
    secs,
    span,
    times,
    whole,
)
from .data import need


def section(res: Results) -> str:
    bench = res.csv("bench_engines.csv")
    meta = res.json("bench_engines.json")
    machine = meta["provenance"]["machine"]
    points = int(bench.impacts.iloc[0] / meta["repeats"])
    table = pd.DataFrame(
        {
            "engine": bench.engine.map(label),
            "steps per collision": bench.steps_median.map(lambda v: f"{v:g}"),
            "simulate() us": bench.simulate_per_collision_us.map(lambda v: whole(v, 3)),
            "bare engine us, same steps (per step)": [
                f"{whole(a, 3)} ({whole(b, 2)})"
                for a, b in zip(bench.bare_steps_us, bench.bare_per_step_us)
            ],
            "simulate overhead us": bench.simulate_overhead_us.map(lambda v: whole(v, 3)),
            "runner + table us per impact": bench.harness_per_collision_us.map(
                lambda v: whole(v, 3)
            ),
            "harness / bare": bench.ratio.map(lambda v: num(v, 3)),
        }
    )
    intro = (
        f"{res.chart('bench_engines.png', 'cost of one collision')}\n\n"
        f"One run on a {machine['cpus']}-core machine (`{machine['platform']}`), reference "
        f"profile, R161, the paper's swing, {points} points x {meta['repeats']} repeats "
        "(medians; `results/bench_engines.csv`):"
    )
    (swing,) = need(res, "swing")
    rigid = bench[bench.engine.isin(swing.rigid)]
    return "\n\n".join(
        part
        for part in [
            intro,
            md_table(table),
            steps(res, bench),
            overhead(rigid),
            batches(res),
            twins(res),
            gpu.section(res),
            runners(res, meta),
            analytic(res, meta),
        ]
        if part
    )


def batches(res: Results) -> str:
    """Throughput at each engine's best batch (``bench_batches.csv``): judged impacts/s, the
    harness's share of it against the engine's own, the largest error beside it."""
    t = res.csv("bench_batches.csv")
    best = t.loc[t.groupby("engine", sort=False).impacts_per_s.idxmax()]
    each = [
        f"{label(r.engine)} {sci(r.impacts_per_s)}/s at {r.batch:,} "
        f"(harness {num(r.harness_us_per_impact, 2)} us, bare engine "
        f"{num(r.bare_us_per_impact, 2)} us an impact{_anchor(r)}; "
        f"error {num(r.max_abs_err_mps)} m/s)"
        for r in best.sort_values("impacts_per_s", ascending=False).itertuples()
    ]
    return "\n\n".join(
        [
            res.chart("bench_batches.png", "impacts per second against batch size"),
            lead(
                "**Batches.** Fired in batches of growing size and every impact judged, each "
                "engine's best (`results/bench_batches.csv`; its cost alone: its "
                "[page](engines.md)):",
                each,
            ),
            "A batched engine fires its worlds in one call; a single-world engine fires on as many "
            "of its adapters as the run repays, stepped in turn and judged together. The harness's "
            "share is the wall time less the time inside the engine's calls, reads included.",
        ]
    )


def _anchor(r) -> str:
    """A pool adapter's bare cost beside its library's own batched call on the same states
    (``anchor_us_per_impact``), where measured."""
    a = getattr(r, "anchor_us_per_impact", math.nan)
    if math.isnan(a):  # (no such call)
        return ""
    return f", its library's own batched call {num(a, 2)} ({r.bare_us_per_impact / a:.2f}x)"


def twins(res: Results) -> str:
    """The twins' largest differences (``twins.csv``): a port against its original, at their
    reference profiles and over the set-ups that match them."""
    each = []
    for (engine, twin), g in res.csv("twins.csv").groupby(["engine", "twin"], sort=False):
        ref = g[g.step.str.startswith("each at its reference")].max_abs_diff_mps
        rest = g.max_abs_diff_mps.drop(ref.index)
        each.append(
            f"{label(engine)} against {label(twin)}: {num(ref.max())} m/s at their "
            f"reference profiles, {num(rest.min())}-{num(rest.max())} m/s over "
            f"{len(rest)} matched set-ups"
        )
    return lead(
        "**Twins.** The ports of one engine fired on the same grid, the largest "
        "difference of v1 between them (`results/twins.csv`, `python -m "
        "experiments.twins`):",
        each,
    )


def steps(res: Results, bench: pd.DataFrame) -> str:
    (swing,) = need(res, "swing")
    pareto = res.csv("pareto.csv")
    pareto["per_step_us"] = pareto.wall_per_collision_s / pareto.steps_median * 1e6
    text = []
    for e in swing.compliant:
        b = bench[bench.engine == e].iloc[0]
        disc = pareto[
            (pareto.engine == e)
            & pareto.family.str.match(r"discrete .*point")
            & (pareto.dt_s == pareto.dt_s.min())
        ]
        text.append(
            f"{label(e)}'s reference is its {swing.setting(e, 'solver')} mode (read every "
            f"{secs(swing.setting(e, 'dt_s'))}: {b.steps_median:g} readings cover a contact of "
            f"{secs(swing.rows(e).contact_duration_s.median())}), "
            f"{secs(b.simulate_per_collision_us * 1e-6)} a collision"
            + (
                f"; its discrete point-contact solvers cost "
                f"{span(disc.per_step_us.min(), disc.per_step_us.max())} us a step "
                f"(`pareto.csv`, at dt = {secs(pareto.dt_s.min())})"
                if len(disc)
                else ""
            )
            + "."
        )
    rigid = bench[bench.engine.isin(swing.rigid)].sort_values("bare_per_step_us")
    for e in rigid.engine:
        ref = pareto[
            (pareto.engine == e)
            & (pareto.family == "reference solver")
            & (pareto.dt_s == swing.setting(e, "dt_s"))
        ]
        here = float(rigid[rigid.engine == e].bare_per_step_us.iloc[0])
        if len(ref) and here > 1.5 * ref.per_step_us.iloc[0]:
            text.append(
                f"{label(e)}'s step costs {num(ref.per_step_us.iloc[0])} us in the "
                f"speed-accuracy run and {num(here)} us in this one: it runs a worker "
                "thread of its own, which competes with the benchmark's processes."
            )
    text.append(
        "Per bare step the rigid-contact engines rank "
        + names(f"{label(r.engine)} ({num(r.bare_per_step_us)} us)" for r in rigid.itertuples())
        + "."
    )
    return "\n\n".join(text)


def overhead(bench: pd.DataFrame) -> str:
    low = bench.loc[bench.simulate_overhead_us.idxmin()]
    top = bench.loc[bench.simulate_overhead_us.idxmax()]
    return "\n\n".join(
        [
            lead(
                "The overhead of `simulate()` over the bare steps:",
                [
                    "placing the bodies, reading them back on the steps around the contact, the "
                    "geometry of each reading",
                    "classifying and building the outcome record",
                    "deciding that the episode is over (the bound of "
                    "`analytic.collide.separates_for_good` on the state after separation)",
                    "it varies with how fast the engine's own Python API sets and reads a state: "
                    "from "
                    f"{num(low.simulate_overhead_us)} us in {label(low.engine)} to "
                    f"{num(top.simulate_overhead_us)} us in {label(top.engine)} among the "
                    "rigid-contact "
                    "engines",
                ],
            ),
            "Firing through the runner and building the table add the rest, much of it the judge: "
            "each row's rigid episode (`collide`, cached across settings) and its tolerance (one "
            "vectorized prediction per bat for every row).",
            "The machine's speed drifts between runs, so read the columns as ratios within one "
            "run.",
        ]
    )


def _points(run: dict) -> int:
    """The sweep's points, as its label spells them ('..., 41 points, ...')."""
    return int(re.search(r"(\d+) points", run["label"]).group(1))


def _engines(run: dict) -> list[str]:
    return re.search(r"--engine (\S+)", run["args"]).group(1).split(",")


def _sweep_label(run: dict) -> str:
    n = len(_engines(run))
    who = f"all {n} engines" if n > 2 else engines_text(_engines(run))
    swing = ", `--swing` (each impact swings the bat first)" if "--swing" in run["args"] else ""
    return f"{who}, {_points(run)} points{swing}"


def runners(res: Results, meta: dict) -> str:
    rows = []
    for r in meta["runners"]:
        n, pts = len(_engines(r)), _points(r)

        def cell(t: float, rng: list) -> str:
            return f"{t:.2f} s ({span(*rng, lambda v: f'{v:.2f}')})"

        rows.append(
            {
                "sweep": f"{_sweep_label(r)}: {n * pts} impacts, {r['repeats']} repeats",
                "serial": cell(r["serial_s"], r["serial_range_s"]),
                "2 processes": f"{cell(r['workers2_s'], r['workers2_range_s'])}: "
                f"{times(r['speedup_workers2'])}",
                "Dask LocalCluster of 2": f"{cell(r['dask_local2_s'], r['dask_local2_range_s'])}: "
                f"{times(r['dask_over_processes'])} the processes",
            }
        )
    cheap = meta["runners"][0]
    return "\n\n".join(
        [
            "The runners, each warmed (workers started, engines imported) and taking turns so that "
            "the machine's drift hits all alike, on one sweep (fire, locate, chart, write); "
            "medians, "
            "with the range over the repeats:",
            md_table(pd.DataFrame(rows)),
            lead(
                "The first impact of a run is fired in the calling process and times the rest:",
                [
                    f"below {MIN_PARALLEL_S:g} s of work nothing is shipped: a sweep whose first "
                    "impact "
                    "is cheap stays serial whatever `--workers` says "
                    f"({times(cheap['speedup_workers2'])}"
                    " here)",
                    f"above it the impacts go out in chunks of about {secs(CHUNK_S)}",
                    "the sweet-spot and COP searches run side by side while this process draws the "
                    "chart",
                ],
            ),
            "The Dask workers share the GIL with their event loop and heartbeats. In the same run "
            f"two processes ran a pure-Python loop {times(meta['two_process_ceiling'])} as fast as "
            "one, which bounds every parallel figure above.",
        ]
    )


def analytic(res: Results, meta: dict) -> str:
    a = res.json("bench_analytic.json")
    return (
        f"`python -m experiments.sweep --engine all` on 41 points takes "
        f"{meta['sweep_41_s']:.1f} s including start-up (every engine imported).\n\n"
        f"`python -m experiments.bench_analytic`: the vectorized analytic v1 runs "
        f"{sci(a['points'], 1)} points in {secs(a['median_s'], 3)} (median of {a['repeats']}; "
        f"{sci(a['impacts_per_s'])} impacts/s)"
        + (
            f"; one impact judged against it (`verdicts.judge`, its outcome the theory's own "
            f"answer, no engine) takes {a['judge_one_impact_us']:.0f} us (median of "
            f"{a['judge_calls']} calls)."
            if "judge_one_impact_us" in a
            else "."
        )
    )
