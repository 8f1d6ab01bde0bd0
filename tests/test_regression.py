"""CI guard: each engine's agreement with theory must not regress past the committed baseline.

results/thresholds.json (written by ``python -m experiments.baselines``) holds, per baseline grid
and engine, the largest |v1 engine - v1 analytic| allowed and the rule behind it. Here we re-run
every 5th point of those 41-point grids (9 impacts; a batched engine fires the whole grid, as
one batch, and 9 of its rows are compared) and compare.
"""

from __future__ import annotations

import json

import numpy as np
import pandas as pd
import pytest

import adapters
from experiments import sweep
from experiments.core import Runner, Status, tables
from experiments.core.fire import fire_jobs
from experiments.core.io import ROOT

from .conftest import sound

pytestmark = pytest.mark.full
THRESHOLDS = json.loads((ROOT / "results" / "thresholds.json").read_text())
CASES = [
    (base, engine) for base, spec in THRESHOLDS["baselines"].items() for engine in spec["engines"]
]


@pytest.mark.parametrize("baseline,engine", CASES, ids=[f"{b}-{e}" for b, e in CASES])
def test_agreement_does_not_regress_and_the_baseline_is_what_the_code_produces(baseline, engine):
    spec = THRESHOLDS["baselines"][baseline]
    plan = sweep.sweep_from_args(sweep.build_parser().parse_args(spec["options"]))
    settings = plan.settings[engine]
    jobs = plan.firing.jobs(engine, settings)
    if adapters.record(engine).batched:
        # the whole grid as one batch, as the baseline fired it: a batched engine pays per
        # step, not per world, and a world's bits may depend on its batch (MJX swings every
        # world about the first one's hands)
        rows = tables.table(fire_jobs(jobs), plan.profile).iloc[::5].reset_index(drop=True)
    else:
        with Runner() as runner:  # fired once for both checks
            rows = tables.table(runner.fire(jobs[::5]), plan.profile)
    # Engines are deterministic, so re-firing every 5th point of a committed baseline must give
    # its rows again: v1 to the 12 significant digits the CSV keeps (relative 1e-11 allows the
    # last printed digit), and the status. A table left from older code, or edited, fails here.
    # An engine compiled for the host's CPU (``host_rounding``) rounds in another order on
    # another host: each host's rows then scatter about theory by the engine's own error, whose
    # committed worst is the baseline's, so two hosts' rows differ by at most twice it.
    committed = pd.read_csv(ROOT / "results" / f"{baseline}.csv")
    committed = committed[committed.engine == engine].iloc[::5].reset_index(drop=True)
    assert list(rows.status) == list(committed.status)
    if adapters.record(engine).errors.host_rounding:
        rtol, atol = 0.0, 2 * spec["engines"][engine]["baseline_max_abs_err_mps"]
    else:
        rtol, atol = 1e-11, 1e-12
    np.testing.assert_allclose(rows.v1_engine_mps, committed.v1_engine_mps, rtol=rtol, atol=atol)
    assert sound(rows).all(), rows.status.value_counts().to_dict()
    rows = rows[rows.status == Status.OK]
    allowed = spec["engines"][engine]["max_abs_err_mps"]
    worst = rows[spec["engines"][engine].get("error_column", "v1_abs_err_mps")].max()
    assert worst <= allowed, f"{engine}: max |dv1| {worst:.3e} m/s > allowed {allowed:.3e} m/s"
