"""The friction options of the sweep and the friction study: bad input named before any work,
the columns friction and flight add, and the study's files."""

from __future__ import annotations

import json
import math
import subprocess
import sys

import pandas as pd
import pytest

import adapters
from analytic import flight
from experiments import friction, sweep
from experiments.core import Status, runs
from experiments.core.io import ROOT

#: A single-world engine whose rigid contact has friction and no declared defect, taken from
#: the registry (no engine named here).
EXACT = next(
    n
    for n in adapters.names()
    if adapters.record(n).can.friction_rule is not None
    and not adapters.record(n).errors.friction_defect
    and not adapters.record(n).batched
    and adapters.contact_reference(n) is adapters.ContactReference.RIGID_IMPULSE
)


@pytest.mark.parametrize(
    "args,piece",
    [
        (["--friction", "-0.1"], "--friction"),
        (["--friction", "0.5", "--undercut", "0.2"], "--undercut=0.2 is out of range"),
        (["--spin", "nan"], "--spin"),
    ],
)
def test_bad_contact_options_exit_2_naming_them(args, piece, tmp_path):
    res = subprocess.run(
        [sys.executable, "-m", "experiments.sweep", *args, "--out", str(tmp_path)],
        cwd=ROOT,
        capture_output=True,
        text=True,
        timeout=120,
        check=False,
    )
    assert res.returncode == 2
    assert piece in res.stderr and len(res.stderr.strip().splitlines()) == 1
    assert not any(tmp_path.iterdir())


def test_friction_and_flight_columns(tmp_path):
    # An oblique hit with friction: every row judged on its tangential velocity and spin too,
    # and flown: a ball leaving toward the outfield lands short of its flight in a vacuum
    # (drag only takes energy; Magnus lift does no work but tilts the path, and at these
    # launch angles it cannot carry the ball past the vacuum range: checked by the flight's
    # own tests), after a positive hang time.
    assert (
        sweep.main(
            [
                "--engine",
                EXACT,
                "--points",
                "3",
                "--friction",
                "0.5",
                "--theta",
                "0.3",
                "--flight",
                "--no-locate",
                "--out",
                str(tmp_path),
                "--name",
                "f",
            ]
        )
        == 0
    )
    t = pd.read_csv(tmp_path / "f" / "sweep.csv")
    for col in (
        "vt1_analytic_mps",
        "vt1_law_mps",
        "vt1_tol_mps",
        "spin1_engine_radps",
        "backspin1_abs_err_radps",
        "carry_engine_m",
        "hang_analytic_s",
        "friction_law",
    ):
        assert col in t.columns
    assert (t.status == Status.OK).all(), list(t.episode_end)
    out = t[t.v1_analytic_mps > 0]
    assert (out.hang_analytic_s > 0).all()
    for r in out.itertuples():
        launch = flight.batted_ball_launch(
            [r.vt1_analytic_mps, r.v1_analytic_mps, 0.0], [0.0, 0.0, r.spin1_analytic_radps]
        )
        assert r.carry_analytic_m < flight.vacuum_carry_m(launch)[0] or launch.launch_rad <= 0.0


def test_friction_study_files_and_summary(tmp_path):
    # The study over one exact-Coulomb engine: its files, and every row of its reference
    # profile within 1% of its own law's spin (SPIN_COST_REL), where the summary lists no
    # costly cell (its other friction families may cost more: that is what they show).
    assert friction.main(["--engine", EXACT, "--quick", "--out", str(tmp_path), "--name", "s"]) == 0
    names = {p.name for p in (tmp_path / "s").iterdir()}
    assert names == {"friction.csv", "friction.json", "friction.png", runs.MANIFEST}
    summary = json.loads((tmp_path / "s" / "friction.json").read_text())["summary"]
    assert summary[0]["engine"] == EXACT and summary[0]["spin_cost_cells"] == []
    t = pd.read_csv(tmp_path / "s" / "friction.csv")
    assert t[t.family == "reference"].spin_rel_err_law.max() <= friction.SPIN_COST_REL
    assert math.isfinite(t.law_spin_rel_gap.max())
