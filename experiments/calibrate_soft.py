"""Soft contacts: does the spring-damper calibration hit the target e, at any speed and mass?

    python -m experiments.calibrate_soft [--engine NAME[,NAME...]|all] [--quick]

For every chosen engine whose record declares a soft contact: central impacts (s = 0, so the bat
does not turn) of the baseball on bats of 0.3, 0.871 and 3 kg at 5 to 80 m/s, for several target
e and time steps, at a natural frequency w = 3000 rad/s. Measured e = (v1 - u1)/v0. Writes
soft_calibration.csv into the run directory and prints the residual per engine, step and target.
"""

from __future__ import annotations

import argparse
import sys
from dataclasses import replace

import pandas as pd

import adapters
from analytic import ImpactCase, presets

from .core import cli, runs
from .core.cli import Command
from .core.fire import Job

TARGETS = (0.3, 0.5, 0.8, 1.0)
SPEEDS_MPS = (5.0, 20.0, 40.0, 80.0)
MASSES_KG = (0.3, 0.871, 3.0)
STEPS_S = (1e-5, 1e-6, 1e-7)
QUICK_STEPS_S = STEPS_S[:1]
OMEGA_RADPS = 3000.0


def jobs(engine: str, steps_s: tuple[float, ...] = STEPS_S) -> list[Job]:
    """Every (step, bat mass, target e, speed) for one engine's soft contact."""
    rec = adapters.record(engine)
    out = []
    for dt in steps_s:
        settings = adapters.settings_for(
            engine, dt_s=dt, **rec.can.soft_contact, **{rec.can.stiffness_setting: OMEGA_RADPS}
        )
        # placed no deeper than half the slowest approach's step (MJX's reference 1 um is
        # more than a 5 m/s ball travels in two steps of 1e-7 s; a soft force starts at zero)
        settings = replace(settings, overlap_m=min(settings.overlap_m, 0.5 * min(SPEEDS_MPS) * dt))
        for mass in MASSES_KG:
            bat = replace(presets.R161, name=f"r161@{mass}kg", mass_kg=mass)
            out += [
                Job(
                    engine=engine,
                    settings=settings,
                    case=ImpactCase(bat=bat, ball=presets.BASEBALL, s_m=0.0, v0_mps=v0, e=e),
                )
                for e in TARGETS
                for v0 in SPEEDS_MPS
            ]
    return out


def _check(p: argparse.ArgumentParser, args: argparse.Namespace) -> None:
    hard = [n for n in args.engine if n not in soft_engines(args.engine)]
    if not soft_engines(args.engine) or (hard and args.engine != adapters.available()):
        # every engine (the default): those with a soft contact; a list names only such
        p.error(
            f"--engine: {', '.join(hard)} {'has' if len(hard) == 1 else 'have'} no soft "
            "contact; allowed: " + ", ".join(soft_engines(adapters.names()))
        )


def soft_engines(engines: tuple[str, ...]) -> list[str]:
    """The engines among these whose record declares a soft contact."""
    return [n for n in engines if adapters.record(n).can.soft_contact is not None]


def produce(args: argparse.Namespace) -> tuple[dict[str, bytes], str]:
    """Every calibration impact of the chosen soft engines: the table and its summary."""
    steps = QUICK_STEPS_S if args.quick else STEPS_S
    todo = [j for n in soft_engines(args.engine) for j in jobs(n, steps)]
    with runs.Progress(len(todo), "impacts") as bar, cli.runner(args, bar) as runner:
        fired = runner.fire(todo)
    rows = []
    for job, (case, out, _, _) in zip(todo, fired):
        e_meas = (out.v1_mps - out.u1_mps) / case.v0_mps
        rows.append(
            {
                "engine": job.engine,
                "dt_s": job.settings.dt_s,
                "w_dt": OMEGA_RADPS * job.settings.dt_s,
                "bat_mass_kg": case.bat.mass_kg,
                "e_target": case.e,
                "v0_mps": case.v0_mps,
                "e_measured": e_meas,
                "residual": e_meas - case.e,
                "physics": out.physics.value,
                "contact_duration_s": out.contact_duration_s,
            }
        )
    table = pd.DataFrame(rows)
    summary = table.groupby(["engine", "dt_s", "e_target"]).agg(
        residual_min=("residual", "min"),
        residual_max=("residual", "max"),
        spread_over_speed_and_mass=("residual", lambda r: r.max() - r.min()),
    )
    text = (
        f"w = {OMEGA_RADPS:g} rad/s; residual = e_measured - e_target over "
        f"{len(SPEEDS_MPS)} speeds x {len(MASSES_KG)} bat masses\n"
        + summary.to_string(float_format=lambda v: f"{v:.3e}")
    )
    return {
        "soft_calibration.csv": table.to_csv(
            index=False, float_format="%.10g", lineterminator="\n"
        ).encode()
    }, text


COMMAND = Command(
    name="calibrate_soft",
    doc=__doc__,
    produce=produce,
    check=_check,
    quick=f"one time step ({QUICK_STEPS_S[0]:g} s), not {len(STEPS_S)}",
)
main = COMMAND.main


if __name__ == "__main__":
    sys.exit(main())
