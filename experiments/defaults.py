"""Each engine out of the box, measured: how many impacts it catches, and which knob costs what.

    python -m experiments.defaults [--engine ...] [--phases K]

1. Caught at its own step: the paper's swing (R161, v0 46.9 m/s, u0 17.87 m/s, omega0 32 rad/s,
   e = 0.5) at 9 points over s in [-0.2, 0.2] m, each with the contact instant at K phases of
   the engine's default step ((k + 1/2)/K, what unaligned simulations meet): the fraction that
   comes back ok and their error, against the tunnelling bound's share of phases whose
   first-seen overlap stays below R = r_ball + r_bat, or whose gap a step before is within the
   engine's speculative margin (``judge.caught_in_theory``).
2. Knob by knob: at the reference step (10 us) with the contact mid-step, the default profile
   with one setting at a time put back to its reference value, and the reference profile with one
   setting at a time set to its default value: the max relative error of v1 over the points, so
   each default's cost is measured alone (the record's profiles say which settings differ).
Writes defaults_caught.csv, defaults_knobs.csv and defaults.json into the run directory.
"""

from __future__ import annotations

import argparse
import dataclasses
import math
import sys
import time

import numpy as np
import pandas as pd

import adapters
from analytic import presets

from .core import cli, firings, judge, runs, tables
from .core.cli import Command
from .core.io import json_bytes, provenance

S_M = tuple(np.linspace(-0.2, 0.2, 9))
REF_DT_S = 1e-5
#: Settings that place the impact rather than configure the engine.
PLACEMENT = ("dt_s", "contact_phase", "overlap_m", "approach_steps", "max_contact_s")


def firing() -> firings.Firing:
    return firings.Firing(
        bat=presets.R161,
        s_m=S_M,
        v0_mps=presets.PAPER_PITCH_MPS,
        u0_mps=presets.PAPER_SWING.u0_mps,
        omega0_radps=presets.PAPER_SWING.omega0_radps,
        e=presets.E_WOOD,
    )


def knobs(name: str) -> list[str]:
    """Settings fields whose default-profile value differs from the reference profile's."""
    rec = adapters.record(name)
    ref, default = rec.profiles["reference"], rec.profiles["default"]
    return [
        f.name
        for f in dataclasses.fields(ref)
        if f.name not in PLACEMENT and getattr(ref, f.name) != getattr(default, f.name)
    ]


def plans(name: str, k: int) -> list[tuple[dict, adapters.Settings]]:
    """(row labels, settings) of every configuration measured for one engine."""
    rec = adapters.record(name)
    ref, default = rec.profiles["reference"], rec.profiles["default"]
    out = [
        (
            {"part": "caught", "phase": float(p)},
            dataclasses.replace(default, contact_phase=float(p)),
        )
        for p in (np.arange(k) + 0.5) / k
    ]
    mid = {"dt_s": REF_DT_S, "contact_phase": 0.5}
    out.append(
        ({"part": "knobs", "change": "default profile"}, dataclasses.replace(default, **mid))
    )
    out.append(({"part": "knobs", "change": "reference profile"}, dataclasses.replace(ref, **mid)))
    for knob in knobs(name):
        out.append(
            (
                {"part": "knobs", "change": f"default, {knob} = reference {getattr(ref, knob)!r}"},
                dataclasses.replace(default, **mid, **{knob: getattr(ref, knob)}),
            )
        )
        out.append(
            (
                {
                    "part": "knobs",
                    "change": f"reference, {knob} = default {getattr(default, knob)!r}",
                },
                dataclasses.replace(ref, **mid, **{knob: getattr(default, knob)}),
            )
        )
    return out


def _options(p: argparse.ArgumentParser) -> None:
    p.add_argument(
        "--phases",
        type=cli.integer(2, 1000),
        default=64,
        help="contact phases per point at the default step (default 64)",
    )


def produce(args: argparse.Namespace) -> tuple[dict[str, bytes], str]:
    t0 = time.perf_counter()
    f = firing()
    todo = [(name, labels, st) for name in args.engine for labels, st in plans(name, args.phases)]
    jobs = [j for name, _, st in todo for j in f.jobs(name, st)]
    with runs.Progress(len(jobs), "impacts") as bar, cli.runner(args, bar) as runner:
        table = tables.table(runner.fire(jobs), "defaults")
    n = len(S_M)
    reach = presets.R161.radius_m + presets.BASEBALL.radius_m
    caught, knob_rows = [], []
    for i, (name, labels, st) in enumerate(todo):
        df = table.iloc[i * n : (i + 1) * n]
        ok = df[df.status.isin(judge.MEASURED)]
        row = {
            "engine": name,
            **labels,
            "dt_s": st.dt_s,
            "impacts": n,
            "ok": len(ok),
            "within_tolerance": int((df.status == judge.Status.OK).sum()),
            "max_rel_err": float(ok.v1_rel_err.max()) if len(ok) else math.nan,
            "statuses": ", ".join(f"{k} {v}" for k, v in df.status.value_counts().items()),
        }
        if labels["part"] == "caught":
            vc = df.v0_mps + df.u0_mps + df.omega0_radps * df.s_m
            margin = adapters.record(name).errors.speculative_margin_m(st)
            row["theory_ok"] = int(
                sum(
                    judge.caught_in_theory(v, st.dt_s, labels["phase"], reach, st.overlap_m, margin)
                    for v in vc
                )
            )
            caught.append(row)
        else:
            knob_rows.append(row)
    caught = pd.DataFrame(caught)
    summary = (
        caught.groupby("engine", sort=False)
        .agg(
            dt_s=("dt_s", "first"),
            ok=("ok", "sum"),
            theory_ok=("theory_ok", "sum"),
            impacts=("impacts", "sum"),
            max_rel_err_caught=("max_rel_err", "max"),
        )
        .reset_index()
    )
    summary["fraction_ok"] = summary.ok / summary.impacts
    summary["fraction_theory"] = summary.theory_ok / summary.impacts
    knob_table = pd.DataFrame(knob_rows)
    files = {
        "defaults_caught.csv": summary.to_csv(
            index=False, float_format="%.6g", lineterminator="\n"
        ).encode(),
        "defaults_knobs.csv": knob_table.to_csv(
            index=False, float_format="%.6g", lineterminator="\n"
        ).encode(),
        "defaults.json": json_bytes(
            {
                "phases": args.phases,
                "grid_s_m": list(S_M),
                "elapsed_s": time.perf_counter() - t0,
                "caught_per_phase": caught.to_dict(orient="records"),
                "provenance": provenance(),
            }
        ),
    }
    text = (
        summary.to_string(index=False, float_format=lambda v: f"{v:.3g}")
        + "\n\n"
        + knob_table[["engine", "change", "ok", "max_rel_err", "statuses"]].to_string(
            index=False, float_format=lambda v: f"{v:.3g}"
        )
    )
    return files, text


COMMAND = Command(name="defaults", doc=__doc__, produce=produce, options=_options)
main = COMMAND.main


if __name__ == "__main__":
    sys.exit(main())
