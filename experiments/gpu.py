"""The batched engines on a GPU: the runs made on a GPU machine, gathered into results' tables.

    python -m experiments.gpu [--runs DIR]

A GPU machine is lent here for minutes, not kept, so the commands are run there as they are run
anywhere (engines on Warp with BATSIM_WARP_DEVICE=cuda:0, on JAX on its default device):

    python -m experiments.bench_engines --quick --batches-only --engine E --batches 1000,...
    python -m experiments.twins --engine E,...
    python -m experiments.stability --quick --engine E,...

and their run directories (csv and json) are committed as they came back, under --runs
(default results/gpu_runs/, with ``session.json`` saying what ran out of time), beside the
same stability map run on this machine's CPU. This command derives, on any machine:
- bench_batches.csv and .png: every run's GPU rows (a later run's row for the same engine
  and batch wins) beside the committed CPU rows;
- twins_gpu.csv: each twin step's largest and median difference on the GPU beside the CPU's
  (results/twins.csv), and their ratio;
- gpu.json: where the GPU run's time goes at each engine's best batch (the bare engine, a read
  of states already computed, which is the copy off the device, and the harness), the
  stability map's wall time on each device and how many of its cells agree, and the bars.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

import pandas as pd

from .core.cli import Command
from .core.io import ROOT, figure_png, json_bytes, provenance
from .parts import throughput

RUNS = ROOT / "results" / "gpu_runs"
RESULTS = ROOT / "results"
#: The bars: every engine's judged impacts/s at its best batch (the slowest's), the fastest
#: engine's, and the harness's largest share of the wall time.
BARS = {"slowest_impacts_per_s": 1e5, "fastest_impacts_per_s": 1e6, "harness_share": 0.25}


def _runs(root: Path) -> list[Path]:
    """The run directories under ``root``, oldest first (their run.json's date)."""
    dirs = [p.parent for p in root.glob("*/run.json")]
    return sorted(dirs, key=lambda d: json.loads((d / "run.json").read_text())["date_utc"])


def _gpu(table: pd.DataFrame) -> pd.DataFrame:
    return table[[throughput.kind(d) == "GPU" for d in table.device]]


def batches(runs: list[Path], committed: pd.DataFrame | None) -> pd.DataFrame:
    """The committed CPU rows, then every run's GPU rows (the latest per engine and batch)."""
    parts = [_gpu(pd.read_csv(d / "bench_batches.csv")) for d in runs
             if (d / "bench_batches.csv").is_file()]
    gpu = pd.concat(parts, ignore_index=True).drop_duplicates(["engine", "batch"], keep="last")
    first = {name: i for i, name in enumerate(dict.fromkeys(gpu.engine))}
    gpu = gpu.assign(first=gpu.engine.map(first)).sort_values(
        ["first", "batch"], kind="stable").drop(columns="first")
    cpu = None if committed is None else committed[
        [throughput.kind(d) == "CPU" for d in committed.device]]
    return throughput.merged(cpu, gpu) if cpu is not None else gpu.reset_index(drop=True)


def twins(runs: list[Path], cpu: pd.DataFrame) -> pd.DataFrame:
    """Each twin step on the GPU beside the same step on the CPU."""
    gpu = pd.concat([_gpu(pd.read_csv(d / "twins.csv")) for d in runs
                     if (d / "twins.csv").is_file()], ignore_index=True)
    both = gpu.merge(cpu.drop(columns=["device"], errors="ignore"), on=["engine", "step"],
                     suffixes=("_gpu", "_cpu"))
    both["ratio"] = both.max_abs_diff_mps_gpu / both.max_abs_diff_mps_cpu
    keep = ["engine", "device", "step", "max_abs_diff_mps_gpu", "max_abs_diff_mps_cpu",
            "ratio", "median_abs_diff_mps_gpu", "median_abs_diff_mps_cpu", "statuses_gpu",
            "statuses_cpu"]
    return both[keep]


def stability(runs: list[Path]) -> list[dict]:
    """Each stability map (its engines and size): its wall time on each kind of device it ran
    on, and, where it ran on both, how many of its cells agree (failure and fraction ok)."""
    maps = {}
    for d in runs:
        if (d / "stability.json").is_file():
            meta = json.loads((d / "stability.json").read_text())
            kinds = {throughput.kind(v) for v in meta["devices"].values()}
            key = (tuple(sorted(meta["devices"])), meta["quick"])
            maps.setdefault(key, {})[kinds.pop() if len(kinds) == 1 else "mixed"] = (d, meta)
    out = []
    for (engines, quick), by_kind in maps.items():
        row = {"engines": list(engines), "quick": quick}
        for kind, (d, meta) in sorted(by_kind.items()):
            row |= {f"{kind.lower()}_s": meta["elapsed_s"],
                    f"{kind.lower()}_machine": meta["provenance"]["machine"],
                    "impacts": len(pd.read_csv(d / "stability.csv"))}
        if {"CPU", "GPU"} <= set(by_kind):
            cells = [pd.read_csv(by_kind[k][0] / "stability_cells.csv") for k in ("GPU", "CPU")]
            same = (cells[0].failure.fillna("") == cells[1].failure.fillna("")) & (
                cells[0].fraction_ok == cells[1].fraction_ok)
            row |= {"cells": len(same), "cells_agree": int(same.sum())}
        out.append(row)
    return out


def profile(table: pd.DataFrame) -> list[dict]:
    """At each engine's best GPU batch: the wall time per impact and its parts (us)."""
    out = []
    for name, rows in _gpu(table).groupby("engine", sort=False):
        r = rows.loc[rows.impacts_per_s.idxmax()]
        out.append({"engine": name, "device": r.device, "batch": int(r.batch),
                    "impacts_per_s": float(r.impacts_per_s), "us_per_impact": r.us_per_impact,
                    "bare_engine_us": r.bare_us_per_impact, "read_us": r.read_us_per_impact,
                    "harness_us": r.harness_us_per_impact,
                    "harness_share": r.harness_us_per_impact / r.us_per_impact,
                    "bare_impacts_per_s": 1e6 / r.bare_us_per_impact,
                    "max_abs_err_mps": float(rows.max_abs_err_mps.max())})
    return out


def bars(prof: list[dict]) -> dict:
    """Each bar, what was measured and whether it is met."""
    slowest = min(prof, key=lambda p: p["impacts_per_s"])
    fastest = max(prof, key=lambda p: p["impacts_per_s"])
    worst = max(prof, key=lambda p: p["harness_share"])
    got = {"slowest_impacts_per_s": slowest["impacts_per_s"],
           "fastest_impacts_per_s": fastest["impacts_per_s"],
           "harness_share": worst["harness_share"]}
    met = {"slowest_impacts_per_s": got["slowest_impacts_per_s"] >= BARS["slowest_impacts_per_s"],
           "fastest_impacts_per_s": got["fastest_impacts_per_s"] >= BARS["fastest_impacts_per_s"],
           "harness_share": got["harness_share"] <= BARS["harness_share"]}
    return {k: {"bar": BARS[k], "measured": got[k], "met": bool(met[k])} for k in BARS} | {
        "slowest": slowest["engine"], "fastest": fastest["engine"],
        "largest_harness_share": worst["engine"]}


def _options(p: argparse.ArgumentParser) -> None:
    p.add_argument("--runs", type=Path, default=RUNS, metavar="DIR",
                   help="the GPU machine's run directories (default results/gpu_runs)")


def _check(p: argparse.ArgumentParser, args: argparse.Namespace) -> None:
    if not _runs(args.runs):
        p.error(f"--runs {args.runs}: no run directory (one with a run.json) in it; allowed: "
                "a folder of the runs a GPU machine made")


def produce(args: argparse.Namespace) -> tuple[dict[str, bytes], str]:
    import matplotlib.pyplot as plt

    runs = _runs(args.runs)
    committed = RESULTS / "bench_batches.csv"
    table = batches(runs, pd.read_csv(committed) if committed.is_file() else None)
    pairs = twins(runs, pd.read_csv(RESULTS / "twins.csv"))
    prof, maps = profile(table), stability(runs)
    session = args.runs / "session.json"
    fig = throughput.chart(table)
    files = {"bench_batches.csv": table.to_csv(index=False, float_format="%.4g",
                                               lineterminator="\n").encode(),
             "bench_batches.png": figure_png(fig),
             "twins_gpu.csv": pairs.to_csv(index=False, float_format="%.6g",
                                           lineterminator="\n").encode(),
             "gpu.json": json_bytes({
                 "profile": prof, "stability": maps, "bars": bars(prof),
                 "session": json.loads(session.read_text()) if session.is_file() else None,
                 "runs": [d.name for d in runs], "provenance": provenance()})}
    plt.close(fig)
    lines = [f"{p['engine']}: {p['impacts_per_s']:.3g} judged impacts/s at {p['batch']:,} "
             f"({p['us_per_impact']:.2f} us: bare engine {p['bare_engine_us']:.2f}, harness "
             f"{p['harness_us']:.2f}, {p['harness_share']:.0%})" for p in prof]
    return files, "\n".join(lines)


COMMAND = Command(name="gpu", doc=__doc__, produce=produce, options=_options, check=_check,
                  engines=False, runner=False)
main = COMMAND.main


if __name__ == "__main__":
    sys.exit(main())
