"""CI guard: each engine's agreement with theory must not regress past the committed baseline.

results/thresholds.json (written by ``python -m experiments.baselines``) holds, per baseline grid
and engine, the largest |v1 engine - v1 analytic| allowed and the rule behind it. Here we re-run
every 5th point of those 41-point grids (9 impacts) and compare.
"""

from __future__ import annotations

import json

import pandas as pd
import pytest

import adapters
from experiments import _grid, _runner, sweep
from experiments._io import ROOT

THRESHOLDS = json.loads((ROOT / "results" / "thresholds.json").read_text())
CASES = [(base, engine) for base, spec in THRESHOLDS["baselines"].items()
         for engine in spec["engines"]]


@pytest.mark.parametrize("baseline,engine", CASES, ids=[f"{b}-{e}" for b, e in CASES])
def test_agreement_does_not_regress(baseline, engine):
    spec = THRESHOLDS["baselines"][baseline]
    args = sweep.build_parser().parse_args(spec["options"])
    plan = sweep.sweep_from_args(args)
    settings = _grid.with_dt(adapters.settings_for(engine, plan.profile), plan.dt_s)
    with _runner.Runner() as runner:
        rows = _grid.table(runner.fire(plan.firing.jobs(engine, settings)[::5]), plan.profile)
    assert (rows.status == "ok").all(), rows.status.value_counts().to_dict()
    allowed = spec["engines"][engine]["max_abs_err_mps"]
    worst = rows.v1_abs_err_mps.max()
    assert worst <= allowed, f"{engine}: max |dv1| {worst:.3e} m/s > allowed {allowed:.3e} m/s"


def test_baseline_tables_match_thresholds():
    # The committed tables and thresholds come from one run: the same worst errors.
    for name, spec in THRESHOLDS["baselines"].items():
        table = pd.read_csv(ROOT / "results" / f"{name}.csv")
        for engine, limits in spec["engines"].items():
            worst = table[table.engine == engine].v1_abs_err_mps.max()
            assert worst == pytest.approx(limits["baseline_max_abs_err_mps"], rel=1e-9)
