"""Smoke tests of the speed-accuracy and stability experiments in --quick mode.

They check the outputs' shape and one physical fact each: the tunnelling bound. A contact first
seen phase * v * dt deep is handled iff that is below R = r_ball + r_bat (past it the ball's
centre is beyond the bat's axis), so with the reference solver the fraction of contact phases
that come back ok must equal the count of phases (k + 1/2)/K with phase * v * dt < R, exactly.
"""

from __future__ import annotations

import pandas as pd
import pytest

import adapters
from experiments import pareto, stability
from experiments.core import Status

#: The stability map's tests share one worker (its map over every engine takes two minutes).
STABILITY = pytest.mark.xdist_group("stability")


@pytest.fixture(scope="module")
def stability_out(tmp_path_factory):
    out = tmp_path_factory.mktemp("stability")
    assert stability.main(["--quick", "--out", str(out), "--name", "s"]) == 0
    return out / "s"


@pytest.mark.full
@STABILITY
def test_stability_outputs(stability_out):
    names = {p.name for p in stability_out.iterdir()}
    soft = {
        f"stability_{n}_soft.png"
        for n in adapters.names()
        if adapters.record(n).can.soft_contact is not None
    }
    assert {
        "stability.csv",
        "stability.png",
        "stability_energy.png",
        "stability_cells.csv",
        "stability.json",
        *soft,
    } <= names
    rows = pd.read_csv(stability_out / "stability.csv")
    q = stability.QUICK
    per_map = len(q["steps"]) * len(q["speeds"]) * q["phases"]
    soft = [n for n in adapters.names() if adapters.record(n).can.soft_contact is not None]
    hunt_crossley = [n for n in adapters.names() if stability.hunt_crossley_law(n) is not None]
    assert (
        len(rows)
        == (2 * len(adapters.names()) + len(hunt_crossley)) * per_map
        + len(soft) * len(q["omegas"]) * len(q["steps"]) * q["phases"]
    )
    assert set(rows.status) <= {s.value for s in Status}


@pytest.mark.full
@STABILITY
def test_tunnelling_bound_is_where_theory_puts_it(stability_out):
    # The bound is a rigid contact's, first seen at one depth and resolved in that step; a
    # compliant one takes many steps, and a coarse step may miss it between readings.
    cells = pd.read_csv(stability_out / "stability_cells.csv")
    rigid = [
        n
        for n in adapters.names()
        if adapters.contact_reference(n) is adapters.ContactReference.RIGID_IMPULSE
    ]
    ref = cells[cells["map"].isin([f"{n} reference" for n in rigid])]
    assert len(ref) == len(rigid) * len(stability.QUICK["steps"]) * len(stability.QUICK["speeds"])
    # caught: the engine resolved the contact soundly (ok, inaccurate or unjudged); whether it
    # did so accurately is the map's colour, not the tunnelling bound
    pd.testing.assert_series_equal(
        ref.fraction_caught, ref.theory_fraction_caught, check_names=False
    )
    # and the map is not trivially all-ok or all-failed: both sides of the bound are sampled
    assert ref.fraction_ok.min() < 0.5 < ref.fraction_ok.max()


@pytest.mark.full
@STABILITY
def test_hunt_crossley_map_is_judged_against_its_law(stability_out):
    # A Hunt-Crossley contact's map (dt x closing speed) is judged against its own law: with
    # several readings per contact (dt below a tenth of t_c, ~1.2 ms here) every phase is ok.
    rows = pd.read_csv(stability_out / "stability.csv")
    for name in adapters.names():
        if stability.hunt_crossley_law(name) is None:
            continue
        fine = rows[(rows["map"] == stability.hc_label(name)) & (rows.dt_s <= 1e-4)]
        assert len(fine) and (fine.status == Status.OK).all(), fine.status.value_counts()


@pytest.mark.full
@STABILITY
def test_soft_contact_sinks_through_below_v_over_r(stability_out):
    # An undamped-ish spring lets the ball sink v/w deep: through the bat when w < v/R.
    rows = pd.read_csv(stability_out / "stability.csv")
    soft = rows[rows.soft_omega_radps.notna()]
    weak = soft[soft.soft_omega_radps < stability.SOFT_SPEED_MPS / stability.REACH_M / 1.5]
    assert len(weak) and (weak.status == Status.TUNNELLED).all()


@pytest.mark.full
def test_pareto_outputs(tmp_path):
    assert pareto.main(["--quick", "--out", str(tmp_path), "--name", "p"]) == 0
    tmp_path = tmp_path / "p"
    table = pd.read_csv(tmp_path / "pareto.csv")
    configs = pareto.configs(True, adapters.names())
    assert len(table) == len(configs) + len(adapters.names())
    assert {"median_rel_err", "max_rel_err", "wall_per_collision_s", "n_ok", "n_tunnelled"} <= set(
        table.columns
    )
    assert (tmp_path / "pareto.png").stat().st_size > 0
    conv = pd.read_csv(tmp_path / "convergence.csv")
    assert set(conv.engine) == set(adapters.names())


@pytest.mark.full
@pytest.mark.parametrize("name", adapters.names())  # one engine a test: xdist spreads them
def test_out_of_the_box_catches_no_more_than_the_tunnelling_bound(name, tmp_path):
    # At each engine's own step, a contact first seen deeper than R = r_ball + r_bat has the
    # ball's centre past the bat's axis: no engine can return it ok. So ok <= theory_ok, per
    # engine, and every knob row names a setting that differs between the two profiles.
    from experiments import defaults

    assert (
        defaults.main(["--engine", name, "--phases", "4", "--out", str(tmp_path), "--name", "d"])
        == 0
    )
    caught = pd.read_csv(tmp_path / "d" / "defaults_caught.csv")
    assert set(caught.engine) == {name}
    assert (caught.ok <= caught.theory_ok).all(), caught
    knobs = pd.read_csv(tmp_path / "d" / "defaults_knobs.csv")
    changed = knobs[(knobs.engine == name) & knobs.change.str.contains(" = ")]
    assert len(changed) == 2 * len(defaults.knobs(name))


def test_cheapest_setting_reaches_its_target_and_nothing_sound_is_cheaper():
    table = pd.DataFrame(
        {
            "engine": ["a", "a", "b", "b"],
            "family": ["f"] * 4,
            "dt_s": [1e-3, 1e-4, 1e-3, 1e-4],
            "max_rel_err": [2e-3, 2e-5, 5e-4, 5e-6],
            "wall_per_collision_s": [1e-5, 1e-4, 3e-5, 3e-4],
            "all_ok": [True, True, False, True],
        }
    )
    best = pareto.cheapest(table, targets=(1e-2, 1e-3, 1e-6)).set_index(["target", "engine"])
    # b at 1e-3 s is cheap and accurate enough but not sound: never chosen
    assert best.loc[(1e-2, "any"), "setting"] == "f, dt = 0.001 s"
    assert best.loc[(1e-2, "any"), "winner"] == "a"
    assert best.loc[(1e-3, "any"), "winner"] == "a" and best.loc[(1e-3, "b"), "max_rel_err"] == 5e-6
    assert best.loc[(1e-6, "any"), "setting"] == "none reaches it"
