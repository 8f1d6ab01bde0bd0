"""MuJoCo soft contact: does the solref calibration hit the target e, at any speed and mass?

    python -m experiments.calibrate_soft

Central impacts (s = 0, so the bat does not turn) of the baseball on bats of 0.3, 0.871 and 3 kg
at 5 to 80 m/s, for several target e and time steps, with w = 3000 rad/s. Measured e =
(v1 - u1)/v0. Writes results/mujoco_soft_calibration.csv and prints the residual per time step.
"""

from __future__ import annotations

import sys
from dataclasses import replace

import pandas as pd

import adapters
from analytic import ImpactCase, presets

from ._io import ROOT, atomic_write_many

TARGETS = (0.3, 0.5, 0.8, 1.0)
SPEEDS_MPS = (5.0, 20.0, 40.0, 80.0)
MASSES_KG = (0.3, 0.871, 3.0)
STEPS_S = (1e-5, 1e-6, 1e-7)
OMEGA_RADPS = 3000.0


def main() -> int:
    rows = []
    for dt in STEPS_S:
        engine = adapters.load("mujoco", contact_model="soft", soft_omega_radps=OMEGA_RADPS,
                               dt_s=dt)
        for mass in MASSES_KG:
            bat = replace(presets.R161, name=f"r161@{mass}kg", mass_kg=mass)
            for e in TARGETS:
                for v0 in SPEEDS_MPS:
                    out = engine.simulate(ImpactCase(bat=bat, ball=presets.BASEBALL, s_m=0.0,
                                                     v0_mps=v0, e=e))
                    e_meas = (out.v1_mps - out.u1_mps) / v0
                    rows.append({"dt_s": dt, "w_dt": OMEGA_RADPS * dt, "bat_mass_kg": mass,
                                 "e_target": e, "v0_mps": v0, "e_measured": e_meas,
                                 "residual": e_meas - e, "status": out.status.value,
                                 "contact_duration_s": out.contact_duration_s})
    table = pd.DataFrame(rows)
    atomic_write_many({ROOT / "results" / "mujoco_soft_calibration.csv": table.to_csv(
        index=False, float_format="%.10g", lineterminator="\n").encode()})
    summary = table.groupby(["dt_s", "e_target"]).agg(
        residual_min=("residual", "min"), residual_max=("residual", "max"),
        spread_over_speed_and_mass=("residual", lambda r: r.max() - r.min()))
    print(f"w = {OMEGA_RADPS:g} rad/s; residual = e_measured - e_target over "
          f"{len(SPEEDS_MPS)} speeds x {len(MASSES_KG)} bat masses")
    print(summary.to_string(float_format=lambda v: f"{v:.3e}"))
    return 0


if __name__ == "__main__":
    sys.exit(main())
