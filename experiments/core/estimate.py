"""What a run will cost, before it starts: steps per impact times each engine's step cost.

An impact takes ``approach_steps`` steps to reach the contact, the contact's own steps (one for
a rigid impulse; the rigid episode's sliding time, or a compliant law's contact time, over dt)
and a few more until free flight proves the bodies apart; a hinged swing adds its own steps.
The step cost is the engine record's ``step_cost_s`` (measured by ``experiments.bench_engines``),
a step with the bodies apart its ``Cost.coast_s`` (a contact solver's step can cost ten of them);
each step adds the harness's own ``STEP_OVERHEAD_S`` (``COAST_OVERHEAD_S`` with the bodies
apart), each step it reads (the contact's and those after it) ``OBSERVED_STEP_S``, shared by the
impacts of a single-world engine's pool (read together), and each impact its ``OVERHEAD_S``. A
batched engine steps each run of jobs that share a scene together, for as many steps as the
longest of them takes, each step costing ``step_cost_s`` plus ``world_step_cost_s`` per world, and
each new batch size its ``start_s`` (compiling). An impact the engine cannot fire (a swing on an
engine that cannot drive the bat) costs the harness's overhead only. The estimate is for warning
a user before hours of work, not a benchmark: it is good to a factor of a few.
"""

from __future__ import annotations

import math
from collections import defaultdict
from collections.abc import Sequence

import adapters
from analytic import ImpactCase

from . import hosting, judge
from .fire import Job, runs

#: The harness's own cost per impact (s): placement, classification, the table's row.
OVERHEAD_S = 1e-4
#: What a step costs beyond the engine's own step (s): the adapter's Python wrapper, reading
#: the state, watching the contact (measured: 6-30 us; the baseline sweeps' wall times).
STEP_OVERHEAD_S = 1e-5
#: What a step with the bodies apart costs beyond the engine's own (s): the loop's call alone, no
#: reading (measured: 0.09 us, ``episode.run_episode`` of a ``Coast`` on a step that does nothing).
COAST_OVERHEAD_S = 1e-7
#: What reading one step costs the harness (s): the state read back, the contact's geometry,
#: the end of the episode tested (measured: about 40 us a step of one world on a 2-core host,
#: in a profile of MuJoCo's reference sweep; a MuJoCo default-profile sweep, 147 read steps an
#: impact, took 190 us a step in all).
OBSERVED_STEP_S = 5e-5
#: Steps after the contact until free flight proves the bodies apart.
AFTER_CONTACT_STEPS = 3
#: Impacts per engine whose episodes are integrated to estimate the contact's length.
SAMPLES = 5
#: Simulations one search for a mark (the sweet spot, the COP) fires one after another: a
#: bounded Brent search's, or a batched engine's grid refinements (``core.tables``).
SEARCH_SIMULATIONS = 25


def contact_s(case: ImpactCase, settings: adapters.Settings, errors: adapters.ErrorModel) -> float:
    """How long the contact lasts in the model the engine converges to (s): its law's contact
    time for a compliant contact, the rigid episode's for a rigid one (0 for one impulse); an
    untuned contact's own time where the engine knows it."""
    untuned = errors.untuned_contact_s(settings)
    if untuned is not None:
        return untuned
    law = errors.contact_law(settings, case.e)
    if law is not None:
        return judge.law_answer(case, law).contact_duration_s
    episode = judge.rigid(case, settings.max_contact_s)
    return episode.sustained_contact_s if episode.impacts == 1 else episode.episode_s


def coast_steps(job: Job) -> float:
    """The steps of an impact with the bodies apart: the approach and a hinged swing's."""
    st = job.settings
    swing = 0.0 if job.swing is None else job.swing.duration_s(job.case.bat) / st.dt_s
    return st.approach_steps + swing


def observed_steps(job: Job, contact_time_s: float) -> float:
    """The steps of an impact the harness reads: the contact's and those after it."""
    st = job.settings
    return min(
        max(1.0, contact_time_s / st.dt_s) + AFTER_CONTACT_STEPS,
        math.ceil(st.max_contact_s / st.dt_s) + 2,
    )


def run_s(jobs: Sequence[Job]) -> dict[str, float]:
    """Estimated wall time (s) of firing ``jobs``, per engine, from a sample of each engine's
    impacts (their mean contact time stands for all of them)."""
    by_engine: dict[str, list[Job]] = defaultdict(list)
    for job in jobs:
        by_engine[job.engine].append(job)
    out = {}
    for name, mine in by_engine.items():
        sample = mine[:: max(1, len(mine) // SAMPLES)][:SAMPLES]
        rec = adapters.record(name)
        contact = sum(contact_s(j.case, j.settings, rec.errors) for j in sample) / len(sample)
        cost = rec.cost.step_cost_s + STEP_OVERHEAD_S
        coast = rec.cost.coast_s + COAST_OVERHEAD_S
        if not rec.drives_bat and mine[0].swing is not None:  # unsupported: nothing stepped
            out[name] = len(mine) * OVERHEAD_S
        elif rec.cost.world_step_cost_s is None:
            out[name] = sum(
                coast_steps(j) * coast + observed_steps(j, contact) * cost + OVERHEAD_S
                for j in mine
            ) + sum(
                max(observed_steps(j, contact) for j in batch) * OBSERVED_STEP_S
                for batch in _pooled(rec, mine)
            )
        else:
            batches = runs(mine)
            world = rec.cost.world_step_cost_s
            out[name] = rec.cost.start_s * len(
                {(run[0].settings, len(run)) for run in batches}
            ) + sum(
                max(map(coast_steps, run)) * (coast + len(run) * world)
                + max(observed_steps(j, contact) for j in run)
                * (cost + len(run) * world + OBSERVED_STEP_S)
                + len(run) * OVERHEAD_S
                for run in batches
            )
    return out


def _pooled(rec: adapters.EngineRecord, jobs: Sequence[Job]) -> list[Sequence[Job]]:
    """The batches a single-world engine's jobs are read in: each run of POOL_MIN impacts or
    more in batches of up to POOL_MAX (a pool adapter's POOL_ADAPTER_MAX, within the record's
    ``max_worlds``), read together a step at a time (``hosting.pool_size``); a shorter run's
    impacts one by one."""
    most = hosting.batch_cap(rec)
    most = min(most, rec.can.max_worlds or most)
    out: list[Sequence[Job]] = []
    for run in runs(jobs):
        size = most if len(run) >= hosting.POOL_MIN else 1
        out += [run[i : i + size] for i in range(0, len(run), size)]
    return out


def search_s(jobs: Sequence[Job]) -> dict[str, float]:
    """Estimated wall time (s) of searching for a mark (the sweet spot, the COP) near each of
    ``jobs``, on its engine's own data: SEARCH_SIMULATIONS simulations like the job each (a
    batched engine compiles for them once), per engine."""
    out: dict[str, float] = defaultdict(float)
    for job in jobs:
        rec = adapters.record(job.engine)
        start = rec.cost.start_s if rec.batched else 0.0
        if job.engine not in out:
            out[job.engine] = start
        out[job.engine] += SEARCH_SIMULATIONS * (run_s([job])[job.engine] - start)
    return dict(out)


def duration(seconds: float) -> str:
    """A duration as a person reads it: 42 s, 6.1 min, 3.2 h, 4.5 days."""
    for unit, size in (("days", 86400), ("h", 3600), ("min", 60)):
        if seconds >= size:
            return f"{seconds / size:.3g} {unit}"
    return f"{seconds:.3g} s"
