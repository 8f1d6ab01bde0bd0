"""One short page per engine, as its users read it, and their index (``engines.md``).

Each page says, from the files in results/ and the engine's record: how to install it, what it
computes in, what its library offers to step many worlds at once (and whether the harness uses
it), how close its reference profile comes to theory, what its out-of-the-box settings
do, the cheapest setting within PAGE_TARGET of rigid theory (``pareto_cheapest.csv``), the
defects its record declares (measured failures no setting removes), what an impact costs
through the harness, alone and in its best batch, on each device ``bench_batches.csv`` has, and
the releases ``history.csv`` judged.
The long report (``report.md``) keeps the studies; a page repeats none of its tables.
"""

from __future__ import annotations

import json
from pathlib import Path

import pandas as pd

import adapters
from analytic import presets

from . import readme

#: The accuracy a page names the cheapest setting for: the max relative error of v1 against
#: rigid theory over the Pareto grid (one of ``pareto_cheapest.csv``'s targets).
PAGE_TARGET = 0.01


def page_name(name: str) -> str:
    """The file an engine's page is written to."""
    return f"engine_{name}.md"


def _install(rec: adapters.EngineRecord) -> str:
    extra, package = rec.install.extra, rec.install.package
    return (
        f"`pip install 'batsim[{extra}]'` (the `{package}` package)"
        if extra
        else f"a core dependency (`{package}`): `pip install -e .`"
    )


def _cheapest(results: Path, name: str) -> str:
    table = pd.read_csv(results / "pareto_cheapest.csv")
    rows = table[(table.engine == name) & (table.target == PAGE_TARGET)]
    if not len(rows) or pd.isna(rows.winner.iloc[0]):
        return f"no setting of its families reaches {PAGE_TARGET:.0%} (`pareto.csv`)"
    r = rows.iloc[0]
    return (
        f"{r.setting}: max relative error {r.max_rel_err:.1e}, "
        f"{r.wall_per_collision_s * 1e6:,.0f} us a collision (`pareto_cheapest.csv`)"
    )


def _defects(name: str) -> list[str]:
    """What the record declares it gets wrong whatever the settings."""
    rec, st = adapters.record(name), adapters.settings_for(name)
    out = [f"friction: {rec.errors.friction_defect}"] if rec.errors.friction_defect else []
    if rec.errors.chain_defect:  # (its text names the segmented bat)
        out.append(rec.errors.chain_defect)
    slide = rec.errors.collision_slide_m(st, presets.R161)
    if slide > 0.0:
        out.append(
            f"its collision routine slides the contact point up to {slide * 1e6:.2f} um "
            "along the R161's axis (in its tolerance)"
        )
    if rec.errors.host_rounding:
        out.append(
            "its kernels round as the host CPU's instruction set orders them: rows "
            "differ by rounding between hosts"
        )
    return out or ["none declared"]


def _costs(results: Path, name: str) -> list[str]:
    path = results / "bench_batches.csv"
    rows = pd.read_csv(path) if path.exists() else pd.DataFrame(columns=["engine"])
    rows = rows[rows.engine == name]
    if not len(rows):
        return ["not benchmarked (`python -m experiments.bench_engines`)"]
    out = []
    kind = rows.device.map(lambda d: "CPU" if "cpu" in d.lower() else f"GPU ({d})")
    for device, on in rows.groupby(kind, sort=True):
        one, best = on[on.batch == 1], on.loc[on.us_per_impact.idxmin()]
        alone = f"{one.us_per_impact.iloc[0]:,.0f} us alone" if len(one) else "alone not measured"
        out.append(
            f"{device}: {alone}; {best.us_per_impact:,.1f} us in a batch of "
            f"{best.batch:,} (the harness's share {best.harness_us_per_impact:,.1f} us)"
            + _anchored(on)
        )
    return out


def _anchored(rows: pd.DataFrame) -> str:
    """Where a pool adapter was timed beside its library's own batched call on the same
    states (``anchor_us_per_impact``): the bare pool against it at each batch of 1,000 and
    more."""
    if "anchor_us_per_impact" not in rows:
        return ""
    on = rows[(rows.batch >= 1000) & rows.anchor_us_per_impact.notna()]
    each = [
        f"{r.bare_us_per_impact:.1f} against {r.anchor_us_per_impact:.1f} us at {r.batch:,} "
        f"({r.bare_us_per_impact / r.anchor_us_per_impact:.2f}x)"
        for r in on.itertuples()
    ]
    return (
        "; bare, its pool against its library's own batched call: " + ", ".join(each)
        if each
        else ""
    )


def _releases(results: Path, name: str) -> str:
    """The releases ``experiments.history`` judged, and the first whose reference swing is ok."""
    path = results / "history.csv"
    table = pd.read_csv(path) if path.exists() else pd.DataFrame(columns=["engine"])
    rows = table[table.engine == name]
    if not len(rows):
        return "not judged (`python -m experiments.history`)"
    listed = list(dict.fromkeys(rows.release.astype(str)))
    ok = rows[(rows.grid == "swing") & (rows.ok == rows.impacts)].release.astype(str)
    since = f"; its reference swing all ok from {ok.iloc[0]}" if len(ok) else ""
    return (
        f"{len(listed)} releases, {listed[0]} to {listed[-1]}, in [history.md]"
        f"(history.md#{name}){since}"
    )


def _batching(rec) -> str:
    """What the engine's library offers to step many worlds at once (``EngineRecord.batching``),
    and whether the harness steps through it."""
    said = rec.batching
    if said is None:
        return "not stated by its record"
    if not said.call:
        return said.why
    kind = "many worlds a call" if said.worlds else "one world's step on threads"
    use = "used" if said.used else "not used"
    return f"`{said.call.replace(':', '.')}` ({kind}; {use}): {said.why}"


def page(results: Path, name: str) -> str:
    """The engine's page (module docstring)."""
    rec = adapters.record(name)
    ref = pd.read_csv(results / f"{readme.REFERENCE}.csv")
    default = json.loads((results / f"{readme.DEFAULT}.json").read_text())
    rows = ref[ref.engine == name]
    kind = ("many worlds a call" if rec.batched else "one world at a time") + (
        ", in the swing plane only" if rec.can.planar else ""
    )
    lines = [
        f"# {rec.look.label or name} (`{name}`)",
        "",
        f"- **Install**: {_install(rec)}.",
        f"- **Computes** in {rec.errors.precision}, {kind}.",
        f"- **Many worlds at once** (its library's own call): {_batching(rec)}.",
        f"- **Reference profile** (the paper's swing, R161, 41 points): "
        f"{readme.accuracy(rows, name) if len(rows) else 'not in results/ yet'}.",
        f"- **Out of the box** (its own dt): "
        f"{readme.out_of_the_box(default, name) if name in default['engines'] else '-'}.",
        f"- **Cheapest within {PAGE_TARGET:.0%}** of rigid theory: {_cheapest(results, name)}.",
        "- **Declared defects**: " + "; ".join(_defects(name)) + ".",
        "- **Cost per impact** through the harness (`bench_batches.csv`): "
        + "; ".join(_costs(results, name))
        + ".",
        f"- **Releases**: {_releases(results, name)}.",
        "",
    ]
    return "\n".join(lines)


def index(results: Path) -> str:
    """The pages' index: one line per engine."""
    ref = pd.read_csv(results / f"{readme.REFERENCE}.csv")
    lines = [
        "# Engines",
        "",
        "One page per engine, from the files in `results/` (written by "
        "`python -m experiments.report`); the studies are in [report.md](report.md), "
        "each engine's releases side by side in [history.md](history.md).",
        "",
    ]
    for name in sorted(set(ref.engine)):
        rec = adapters.record(name)
        lines.append(
            f"- [{rec.look.label or name}]({page_name(name)}): {rec.errors.precision}, "
            f"{'batched' if rec.batched else 'single-world'}"
        )
    return "\n".join(lines) + "\n"


def pages(results: Path) -> dict[str, bytes]:
    """The index and every engine's page of the reference baseline, as files."""
    ref = pd.read_csv(results / f"{readme.REFERENCE}.csv")
    files = {"engines.md": index(results).encode()}
    for name in sorted(set(ref.engine)):
        files[page_name(name)] = page(results, name).encode()
    return files
