"""The batched engines on a GPU (``gpu.json`` and ``twins_gpu.csv``, ``python -m experiments.gpu``):
what a judged impact costs there and where the time goes, the twins by device, the stability
map's time, and the bars."""

from __future__ import annotations

from .base import Results, label, lead, num, sci, span


def section(res: Results) -> str:
    """The GPU paragraphs, or nothing where no GPU run is in results/."""
    if not (res.root / "gpu.json").is_file():
        return ""
    meta = res.json("gpu.json")
    return "\n\n".join(part for part in (_cost(meta), _twins(res), _stability(meta)) if part)


def _cost(meta: dict) -> str:
    each = [
        f"{label(p['engine'])}: {sci(p['impacts_per_s'])} judged impacts/s at "
        f"{p['batch']:,} worlds, error {num(p['max_abs_err_mps'])} m/s; of its "
        f"{num(p['us_per_impact'], 3)} us an impact the bare engine takes "
        f"{num(p['bare_engine_us'], 3)} (the read off the device {num(p['read_us'], 2)}), "
        f"the harness {num(p['harness_us'], 3)} ({p['harness_share']:.0%}); bare, the "
        f"engine would fire {sci(p['bare_impacts_per_s'])}/s"
        for p in meta["profile"]
    ]
    bars = meta["bars"]
    met = [
        f"the slowest, {label(bars['slowest'])}, "
        f"{sci(bars['slowest_impacts_per_s']['measured'])}/s (bar for every engine "
        f"{sci(bars['slowest_impacts_per_s']['bar'])}: "
        f"{'met' if bars['slowest_impacts_per_s']['met'] else 'not met'})",
        f"the fastest, {label(bars['fastest'])}, "
        f"{sci(bars['fastest_impacts_per_s']['measured'])}/s (bar "
        f"{sci(bars['fastest_impacts_per_s']['bar'])}: "
        f"{'met' if bars['fastest_impacts_per_s']['met'] else 'not met'})",
        f"the harness's largest share {bars['harness_share']['measured']:.0%} "
        f"({label(bars['largest_harness_share'])}; bar "
        f"{bars['harness_share']['bar']:.0%}: "
        f"{'met' if bars['harness_share']['met'] else 'not met'})",
    ]
    device = meta["profile"][0]["device"].split(": ")[-1]
    bare = [p["bare_engine_us"] for p in meta["profile"]]
    ratio = [p["harness_us"] / p["bare_engine_us"] for p in meta["profile"]]
    return "\n\n".join(
        [
            lead(
                f"**On a GPU** ({device}; `results/gpu_runs/`, gathered by `python -m "
                "experiments.gpu`). Each engine at its best batch, one firing of the tiled "
                "41-point grid, every impact judged; the parts from the engine's calls clocked "
                "in that firing and a bare run of the same worlds:",
                each,
            ),
            lead(
                f"On the GPU the bare engines take {span(min(bare), max(bare))} us an impact; "
                f"the harness, on the host, {span(min(ratio), max(ratio))} times that, and sets "
                "the rate:",
                met,
            ),
        ]
    )


def _twins(res: Results) -> str:
    pairs = res.csv("twins_gpu.csv")
    each = []
    for engine, g in pairs.groupby("engine", sort=False):
        ref = g[g.step.str.startswith("each at its reference")].iloc[0]
        each.append(
            f"{label(engine)}: {num(ref.max_abs_diff_mps_gpu)} m/s on the GPU against "
            f"{num(ref.max_abs_diff_mps_cpu)} on the CPU at the reference profiles "
            f"(median {num(ref.median_abs_diff_mps_gpu)} against "
            f"{num(ref.median_abs_diff_mps_cpu)}); over its {len(g)} steps the GPU's "
            f"largest difference is {span(g.ratio.min(), g.ratio.max())} times the "
            "CPU's, the statuses "
            f"{'the same' if (g.statuses_gpu == g.statuses_cpu).all() else 'differ'}"
        )
    ratio = pairs.groupby("engine", sort=False).ratio
    held = [label(e) for e, r in ratio if r.between(0.5, 2.0).all()]
    grew = [label(e) for e, r in ratio if not r.between(0.5, 2.0).all()]
    verdict = (
        f"the causes found on the CPU hold for {', '.join(held) or 'none'} (every step "
        "within 2x of the CPU's)"
        + (
            f"; {', '.join(grew)} "
            f"{'differs' if len(grew) == 1 else 'differ'} more on the GPU, a cause the CPU "
            "runs did not show"
            if grew
            else ""
        )
    )
    return lead(
        f"**Twins on the GPU**, each against the engine it implements, run on the "
        f"CPU (`results/twins_gpu.csv`): {verdict}:",
        each,
    )


def _stability(meta: dict) -> str:
    each = []
    for m in meta["stability"]:
        names = ", ".join(label(e) for e in m["engines"])
        if "gpu_s" in m and "cpu_s" in m:
            each.append(
                f"{names} ({'quick map' if m['quick'] else 'map'}, {m['impacts']} "
                f"impacts): {num(m['gpu_s'], 3)} s on the GPU, {num(m['cpu_s'], 3)} s "
                f"on a {m['cpu_machine']['cpus']}-core CPU; {m['cells_agree']} of "
                f"{m['cells']} cells alike"
            )
        elif "cpu_s" in m:
            each.append(
                f"{names} ({'quick map' if m['quick'] else 'map'}): "
                f"{num(m['cpu_s'], 3)} s on a {m['cpu_machine']['cpus']}-core CPU; "
                "not finished on the GPU in its time (`session.json`)"
            )
    return lead(
        "**The stability map** (dt x closing speed) fired in one call: the engines set "
        "dt once per model, so each time step is a batch of its own (a few dozen "
        "worlds), too small to fill a GPU:",
        each,
    )
