"""The README's engines table, from the files in results/: what each engine gets right at its
reference profile, what it does out of the box, and what an impact costs.

``python -m experiments.baselines`` writes it into README.md between BEGIN and END after the
report; ``tests/test_readme.py`` fails when the README's table is not the one these files give.
"""

from __future__ import annotations

import json
from pathlib import Path

import pandas as pd

import adapters

from ..core.judge import Status
from ..parts import throughput

BEGIN = "<!-- engines table: written by python -m experiments.baselines from results/ -->"
END = "<!-- end of the engines table -->"
REFERENCE = "sweep_all_reference_r161_swing"
DEFAULT = "sweep_all_default_r161_swing"
HEADER = (
    "| engine | install | float | reference profile: impacts ok, max error of v1 | "
    "out of the box (its dt): statuses | CPU cost per impact: batch of 1; best batch | "
    "GPU: judged impacts/s at the best batch (max error) |\n"
    "| --- | --- | --- | --- | --- | --- | --- |"
)


def _install(rec) -> str:
    extra, package = rec.install.extra, rec.install.package
    return f"`[{extra}]` ({package})" if extra else f"core ({package})"


def accuracy(rows: pd.DataFrame, name: str) -> str:
    """ok count and the largest error over the ok rows: against rigid theory, or against the
    engine's own contact law where that is what it converges to."""
    ok = rows[rows.status == Status.OK]
    rec = adapters.record(name)
    law = rec.errors.contact_law(adapters.settings_for(name), 0.5) is not None
    err = (ok.v1_law_err_mps if law else ok.v1_abs_err_mps).max()
    against = "its own contact law" if law else "rigid theory"
    return f"{len(ok)}/{len(rows)} ok, {err:.1e} m/s against {against}"


def out_of_the_box(meta: dict, name: str) -> str:
    counts = meta["engines"][name]["status_counts"]
    dt = meta["engines"][name]["settings"]["dt_s"]
    return f"{', '.join(f'{k} {v}' for k, v in counts.items())} ({dt:.2g} s)"


def _costs(results: Path) -> dict[str, str]:
    """Per engine: the cost per impact through the harness in a batch of one and in its
    cheapest batch (``experiments.parts.throughput``, in bench_batches.csv); where that has no row,
    the median over a grid through the runner (bench_engines.csv) and no batch."""
    bench = pd.read_csv(results / "bench_engines.csv")
    out = {
        name: f"{us:,.0f} us; not measured"
        for name, us in zip(bench.engine, bench.harness_per_collision_us)
    }
    for name, rows in _batches(results, "CPU").groupby("engine"):
        one, best = rows[rows.batch == 1], rows.loc[rows.us_per_impact.idxmin()]
        first = f"{one.us_per_impact.iloc[0]:,.0f} us" if len(one) else "-"
        out[name] = f"{first}; {best.us_per_impact:,.1f} us at {best.batch:,}"
    return out


def _batches(results: Path, kind: str) -> pd.DataFrame:
    """The rows of bench_batches.csv measured on a ``kind`` of device ('CPU' or 'GPU')."""
    path = results / "bench_batches.csv"
    rows = pd.read_csv(path) if path.exists() else pd.DataFrame(columns=["engine", "device"])
    return rows[[throughput.kind(d) == kind for d in rows.device]]


def _gpu(results: Path) -> dict[str, str]:
    """Per engine run on a GPU: its judged impacts/s at its best batch, the error beside it."""
    out = {}
    for name, rows in _batches(results, "GPU").groupby("engine"):
        best = rows.loc[rows.impacts_per_s.idxmax()]
        out[name] = (
            f"{best.impacts_per_s:.2g}/s at {best.batch:,} ({rows.max_abs_err_mps.max():.1e} m/s)"
        ).replace("e+0", "e")
    return out


def engines_table(results: Path) -> str:
    """The table, one row per engine in the reference baseline, from ``results``."""
    ref = pd.read_csv(results / f"{REFERENCE}.csv")
    default = json.loads((results / f"{DEFAULT}.json").read_text())
    costs, gpu = _costs(results), _gpu(results)
    lines = [HEADER]
    for name, rows in ref.groupby("engine", sort=True):
        rec = adapters.record(name)
        cost = costs.get(name, "not benchmarked")
        lines.append(
            f"| {name} | {_install(rec)} | {rec.errors.precision} | "
            f"{accuracy(rows, name)} | {out_of_the_box(default, name)} | {cost} | "
            f"{gpu.get(name, '-')} |"
        )
    for name in sorted(set(adapters.names()) - set(ref.engine)):
        if adapters.record(name).adapter.startswith("adapters."):  # a built-in, not measured
            rec = adapters.record(name)
            lines.append(
                f"| {name} | {_install(rec)} | {rec.errors.precision} | not in "
                "results/ yet | not in results/ yet | not benchmarked | - |"
            )
    return "\n".join(lines)


def with_table(readme: str, table: str) -> str:
    """``readme`` with the text between BEGIN and END replaced by ``table``."""
    head, rest = readme.split(BEGIN, 1)
    _, tail = rest.split(END, 1)
    return f"{head}{BEGIN}\n{table}\n{END}{tail}"
