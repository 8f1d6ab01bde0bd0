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

from .core import inputs
from .core.cli import Command
from .core.io import ROOT, figure_png, json_bytes, provenance
from .errors import BadInput
from .parts import throughput

RUNS = ROOT / "results" / "gpu_runs"
RESULTS = ROOT / "results"
#: The bars: every engine's judged impacts/s at its best batch (the slowest's), the fastest
#: engine's, and the harness's largest share of the wall time.
BARS = {"slowest_impacts_per_s": 1e5, "fastest_impacts_per_s": 1e6, "harness_share": 0.25}


RUNS_ALLOWED = "a folder of the runs a GPU machine made (default results/gpu_runs)"
STABILITY_JSON = "a stability run's stability.json (its devices, quick, elapsed_s, provenance)"


def _runs(root: Path) -> list[Path]:
    """The run directories under ``root``, oldest first (their run.json's date), each checked
    (``check_run``): BadInput naming the first file that is not what it must be."""
    inputs.directory(root, RUNS_ALLOWED)
    dated = sorted((inputs.run_date(p), p.parent) for p in root.glob("*/run.json"))
    for _, d in dated:
        check_run(d)
    return [d for _, d in dated]


def check_run(d: Path) -> None:
    """BadInput unless every file of the run directory ``d`` that this command reads is what
    it must be: its tables (header's width on every row, the columns read, numbers where
    numbers belong) and a stability run's meta and both its tables."""
    if (d / "bench_batches.csv").exists():
        inputs.table(d / "bench_batches.csv", inputs.THROUGHPUT)
    if (d / "twins.csv").exists():
        inputs.table(d / "twins.csv", inputs.TWINS_ON_DEVICE)
    if (d / "stability.json").exists():
        path = d / "stability.json"
        meta = inputs.json_object(
            path,
            STABILITY_JSON,
            {"devices": dict, "quick": bool, "elapsed_s": (int, float), "provenance": dict},
        )
        if not meta["devices"] or not all(isinstance(v, str) for v in meta["devices"].values()):
            raise inputs.bad(
                path,
                f"has devices = {meta['devices']!r}",
                f"an engine -> device name object in {STABILITY_JSON}",
            )
        if "machine" not in meta["provenance"]:
            raise inputs.bad(path, "has no provenance.machine", STABILITY_JSON)
        inputs.table(d / "stability.csv", inputs.STABILITY)
        inputs.table(d / "stability_cells.csv", inputs.STABILITY_CELLS)


def _gpu(table: pd.DataFrame) -> pd.DataFrame:
    return table[[throughput.kind(d) == "GPU" for d in table.device]]


def batches(runs: list[Path], committed: pd.DataFrame | None) -> pd.DataFrame:
    """The committed CPU rows and every run's GPU rows (the latest per engine and batch), in
    the table's order (``throughput.merged``)."""
    parts = [
        _gpu(pd.read_csv(d / "bench_batches.csv"))
        for d in runs
        if (d / "bench_batches.csv").is_file()
    ]
    gpu = pd.concat(parts, ignore_index=True).drop_duplicates(["engine", "batch"], keep="last")
    first = {name: i for i, name in enumerate(dict.fromkeys(gpu.engine))}
    gpu = (
        gpu.assign(first=gpu.engine.map(first))
        .sort_values(["first", "batch"], kind="stable")
        .drop(columns="first")
    )
    cpu = (
        None
        if committed is None
        else committed[[throughput.kind(d) == "CPU" for d in committed.device]]
    )
    return throughput.merged(cpu, gpu) if cpu is not None else gpu.reset_index(drop=True)


#: The columns of a twin step on each device (twins.csv): the GPU's, then the CPU's beside it.
TWIN_COLUMNS = ["engine", "step", "max_abs_diff_mps", "median_abs_diff_mps", "statuses"]


def twins(runs: list[Path], cpu: pd.DataFrame) -> pd.DataFrame:
    """Each twin step on the GPU beside the same step on the CPU (none if no run has twins)."""
    keep = [
        "engine",
        "device",
        "step",
        "max_abs_diff_mps_gpu",
        "max_abs_diff_mps_cpu",
        "ratio",
        "median_abs_diff_mps_gpu",
        "median_abs_diff_mps_cpu",
        "statuses_gpu",
        "statuses_cpu",
    ]
    parts = [_gpu(pd.read_csv(d / "twins.csv")) for d in runs if (d / "twins.csv").is_file()]
    if not parts:
        return pd.DataFrame(columns=keep)
    gpu = pd.concat(parts, ignore_index=True)[["device", *TWIN_COLUMNS]]
    both = gpu.merge(cpu[TWIN_COLUMNS], on=["engine", "step"], suffixes=("_gpu", "_cpu"))
    both["ratio"] = both.max_abs_diff_mps_gpu / both.max_abs_diff_mps_cpu
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
            row |= {
                f"{kind.lower()}_s": meta["elapsed_s"],
                f"{kind.lower()}_machine": meta["provenance"]["machine"],
                "impacts": len(pd.read_csv(d / "stability.csv")),
            }
        if {"CPU", "GPU"} <= set(by_kind):
            row |= _cells_agree(*(by_kind[k][0] / "stability_cells.csv" for k in ("GPU", "CPU")))
        out.append(row)
    return out


def _cells_agree(gpu: Path, cpu: Path) -> dict:
    """How many cells the GPU's map has, and in how many the CPU's same cell (map, dt, v0 or
    a soft contact's stiffness) agrees: the same failure and fraction ok."""
    key = ["map", "dt_s", "v0_mps", "soft_omega_radps"]
    a, b = (pd.read_csv(p)[[*key, "failure", "fraction_ok"]] for p in (gpu, cpu))
    both = a.merge(b, on=key, suffixes=("_gpu", "_cpu"))
    same = (both.failure_gpu.fillna("") == both.failure_cpu.fillna("")) & (
        both.fraction_ok_gpu == both.fraction_ok_cpu
    )
    return {"cells": len(a), "cells_agree": int(same.sum())}


def profile(table: pd.DataFrame) -> list[dict]:
    """At each engine's best GPU batch: the wall time per impact and its parts (us)."""
    out = []
    for name, rows in _gpu(table).groupby("engine", sort=False):
        r = rows.loc[rows.impacts_per_s.idxmax()]
        out.append(
            {
                "engine": name,
                "device": r.device,
                "batch": int(r.batch),
                "impacts_per_s": float(r.impacts_per_s),
                "us_per_impact": r.us_per_impact,
                "bare_engine_us": r.bare_us_per_impact,
                "read_us": r.read_us_per_impact,
                "harness_us": r.harness_us_per_impact,
                "harness_share": r.harness_us_per_impact / r.us_per_impact,
                "bare_impacts_per_s": 1e6 / r.bare_us_per_impact,
                "max_abs_err_mps": float(rows.max_abs_err_mps.max()),
            }
        )
    return out


def bars(prof: list[dict]) -> dict:
    """Each bar, what was measured and whether it is met."""
    slowest = min(prof, key=lambda p: p["impacts_per_s"])
    fastest = max(prof, key=lambda p: p["impacts_per_s"])
    worst = max(prof, key=lambda p: p["harness_share"])
    got = {
        "slowest_impacts_per_s": slowest["impacts_per_s"],
        "fastest_impacts_per_s": fastest["impacts_per_s"],
        "harness_share": worst["harness_share"],
    }
    met = {
        "slowest_impacts_per_s": got["slowest_impacts_per_s"] >= BARS["slowest_impacts_per_s"],
        "fastest_impacts_per_s": got["fastest_impacts_per_s"] >= BARS["fastest_impacts_per_s"],
        "harness_share": got["harness_share"] <= BARS["harness_share"],
    }
    return {k: {"bar": BARS[k], "measured": got[k], "met": bool(met[k])} for k in BARS} | {
        "slowest": slowest["engine"],
        "fastest": fastest["engine"],
        "largest_harness_share": worst["engine"],
    }


def _options(p: argparse.ArgumentParser) -> None:
    p.add_argument(
        "--runs",
        type=Path,
        default=RUNS,
        metavar="DIR",
        help="the GPU machine's run directories (default results/gpu_runs)",
    )


def _check(p: argparse.ArgumentParser, args: argparse.Namespace) -> None:
    """Every run under --runs, and the committed tables read beside them, checked before any
    work; at least one run with GPU rows."""
    try:
        runs = _runs(args.runs)
        gpu_rows = any(
            throughput.kind(d) == "GPU"
            for r in runs
            if (r / "bench_batches.csv").is_file()
            for d in pd.read_csv(r / "bench_batches.csv").device
        )
        if (RESULTS / "bench_batches.csv").exists():
            inputs.table(RESULTS / "bench_batches.csv", inputs.THROUGHPUT)
        inputs.table(RESULTS / "twins.csv", inputs.TWINS)
        if (args.runs / "session.json").exists():
            inputs.json_object(
                args.runs / "session.json",
                "the session's session.json (a JSON object saying what ran)",
                {},
            )
    except BadInput as err:
        p.error(f"--runs: {err}")
    if not gpu_rows:
        p.error(
            f"--runs {args.runs}: no run directory (one with a run.json) holding a "
            "bench_batches.csv with GPU rows in it; allowed: " + RUNS_ALLOWED
        )


def produce(args: argparse.Namespace) -> tuple[dict[str, bytes], str]:
    import matplotlib.pyplot as plt

    runs = _runs(args.runs)
    committed = RESULTS / "bench_batches.csv"
    table = batches(runs, pd.read_csv(committed) if committed.is_file() else None)
    pairs = twins(runs, pd.read_csv(RESULTS / "twins.csv"))
    prof, maps = profile(table), stability(runs)
    session = args.runs / "session.json"
    fig = throughput.chart(table)
    files = {
        "bench_batches.csv": table.to_csv(
            index=False, float_format="%.4g", lineterminator="\n"
        ).encode(),
        "bench_batches.png": figure_png(fig),
        "twins_gpu.csv": pairs.to_csv(
            index=False, float_format="%.6g", lineterminator="\n"
        ).encode(),
        "gpu.json": json_bytes(
            {
                "profile": prof,
                "stability": maps,
                "bars": bars(prof),
                "session": json.loads(session.read_text()) if session.is_file() else None,
                "runs": [d.name for d in runs],
                "provenance": provenance(),
            }
        ),
    }
    plt.close(fig)
    lines = [
        f"{p['engine']}: {p['impacts_per_s']:.3g} judged impacts/s at {p['batch']:,} "
        f"({p['us_per_impact']:.2f} us: bare engine {p['bare_engine_us']:.2f}, harness "
        f"{p['harness_us']:.2f}, {p['harness_share']:.0%})"
        for p in prof
    ]
    return files, "\n".join(lines)


COMMAND = Command(
    name="gpu",
    doc=__doc__,
    produce=produce,
    options=_options,
    check=_check,
    engines=False,
    runner=False,
)
main = COMMAND.main


if __name__ == "__main__":
    sys.exit(main())
