"""``python -m experiments.flex --quick``: the whole study runs and its numbers hold together."""

from __future__ import annotations

import json

import pandas as pd

import adapters
from experiments import flex
from experiments.core.judge import Status


def test_quick_flex_study_writes_consistent_tables(tmp_path):
    engine = next(n for n in adapters.available() if adapters.record(n).chain_adapter)
    assert flex.main(["--quick", "--engine", engine, "--out", str(tmp_path), "--name", "f"]) == 0
    out = tmp_path / "f"
    for name in ("flex.csv", "flex_modes.csv", "flex_sweet.csv", "flex_chain.csv",
                 "flex_engines.csv", "flex.json", "flex.png", "flex_engines.png"):
        assert (out / name).stat().st_size > 0
    rows = pd.read_csv(out / "flex.csv")
    # energy: what the bat keeps bending can be no more than the collision's kinetic energy in
    # the centre-of-mass frame, 1/2 m_red v_rel^2, of which the first mode's share is a part
    assert ((rows.sting_share >= 0) & (rows.sting_share < 1)).all()
    assert (rows.vibration_j >= rows.mode1_j).all()
    spots = pd.read_csv(out / "flex_sweet.csv")
    # the speed peak lies on the barrel, within the search's bounds (0.50-0.80 m from the knob)
    assert spots.speed_peak_from_tip_m.between(0.04, 0.34).all()
    statuses = set(pd.read_csv(out / "flex_engines.csv").status)
    assert statuses <= {s.value for s in Status}
    assert json.loads((out / "flex.json").read_text())["engines"][engine]["statuses"]
