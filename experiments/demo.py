"""A short analytic demo: v1 along the R161 for the paper's swing, the sweet spot and the COP.

    python -m experiments.demo
"""

from __future__ import annotations

import numpy as np

from analytic import batted_ball_speed, center_of_percussion, presets, sweet_spot


def main() -> None:
    bat, ball, swing = presets.R161, presets.BASEBALL, presets.PAPER_SWING
    v0 = presets.PAPER_PITCH_MPS
    s = np.linspace(bat.s_min_m, bat.s_max_m, 11)
    v1 = batted_ball_speed(bat, ball, s, v0_mps=v0, u0_mps=swing.u0_mps,
                           omega0_radps=swing.omega0_radps, e=presets.E_WOOD)
    print(f"{bat.name}: v0 = {v0} m/s, u0 = {swing.u0_mps} m/s, omega0 = {swing.omega0_radps} "
          f"rad/s, e = {presets.E_WOOD}")
    print("   s (m)   v1 (m/s)")
    for x, v in zip(s, v1):
        print(f"{x:8.3f}  {v:9.3f}")
    s_star = sweet_spot(bat, ball, v0, swing.u0_mps, swing.omega0_radps)
    s_cop = center_of_percussion(bat, 0.1)
    print(f"sweet spot s* = {s_star:.4f} m from the COM ({bat.s_barrel_end_m - s_star:.3f} m "
          f"from the barrel end); COP for hands 0.1 m from the knob: {s_cop:.4f} m")


if __name__ == "__main__":
    main()
