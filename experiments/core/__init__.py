"""The harness core: engine-independent, public, and what the commands and the tests use.

    from experiments.core import Firing, Runner, table, check_engine
    firing = Firing(bat=presets.R161, s_m=grid(presets.R161, 41), v0_mps=46.9, u0_mps=17.87,
                    omega0_radps=32.0, e=0.5)
    with Runner(workers=2) as runner:
        rows = table(runner.fire(firing.jobs("mujoco", adapters.settings_for("mujoco"))),
                     "reference")
    print(check_engine("mujoco"))          # every conformance check of the suite, one report

From the theory (``analytic``) and the engine interface (``adapters``) up:
- ``placement``: where an impact starts so that the engine meets the contact as planned;
  a hinged swing into the impact;
- ``geometry``: sphere against capsule on batches of states;
- ``episode``: stepping a batch of worlds until each impact is over, and the status it earns;
- ``judge``: every tolerance, each with its reason, and the verdict against the answer that
  applies (rigid theory, or the engine's own contact law);
- ``verdicts``: the one judge over columns, called where a firing ends: every impact's
  verdict, the answer it was held to, its error and tolerance, as arrays (one impact: the
  same function on columns of length one);
- ``fire``: jobs fired in this process (adapters made once, scenes built and checked);
- ``runner``: the same jobs serially, over local processes or on a Dask cluster;
- ``firings``: what to fire (a bat and ball, a motion, a grid of impact points);
- ``tables``: the tidy table of fired impacts and their verdicts, laid out;
- ``locate``: the sweet spot and centre of percussion located on an engine's own data;
- ``check``: ``check_engine``, the conformance suite a plug-in author runs;
- ``estimate``: what a run will cost, before it starts;
- ``cli``, ``io``: the command-line convention, run directories, atomic files, provenance.
"""

from .check import check_engine
from .check_report import CheckReport
from .endings import Physics
from .episode import SimOutcome
from .fire import Fired, Job, fire_jobs
from .firings import Firing, grid
from .hosting import SceneMismatch
from .judge import MEASURED, Status
from .placement import SwingPlan, start_state, swing_case
from .runner import Runner
from .tables import COLUMNS, table

__all__ = [
    "COLUMNS",
    "CheckReport",
    "Fired",
    "Firing",
    "Job",
    "MEASURED",
    "Physics",
    "Runner",
    "SceneMismatch",
    "SimOutcome",
    "Status",
    "SwingPlan",
    "check_engine",
    "fire_jobs",
    "grid",
    "start_state",
    "swing_case",
    "table",
]
