"""Fire the ball along a bat in one engine (or all) and compare every impact with theory.

    python -m experiments.sweep --engine NAME[,NAME...]|all
    python -m experiments.sweep --engine all --points 41 --u0 0 --omega0 0
    python -m experiments.sweep --compare results/old.csv results/new.csv

Writes <out>/<name>.csv (one row per impact), <name>.json (provenance and summary) and
<name>.png (v1 along the bat per engine over the analytic curve, and the error), atomically.
"""

from __future__ import annotations

import argparse
import math
import sys
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Callable

import numpy as np
import pandas as pd

import adapters
from analytic import Bat, batted_ball_speed, presets
from analytic.dynamics import HingedSwing

from . import _cli, _grid, _runner
from ._io import ROOT, atomic_write_many, figure_png, json_bytes, provenance

FLOAT_FORMAT = "%.12g"


@dataclass(frozen=True, kw_only=True)
class Sweep:
    """One sweep: engines, profile and time step, and what to fire."""

    engines: tuple[str, ...]
    profile: str
    dt_s: float | None
    firing: _grid.Firing
    name: str


def default_name(engine: str, profile: str, dt_s: float | None, bat: Bat, corked: bool,
                 still: bool, hinged: bool = False) -> str:
    """sweep_<engine|all>_<profile>[-dt<dt>]_<bat>[_corked]_<swing|still|hinged>."""
    prof = profile if dt_s is None else f"{profile}-dt{dt_s:.0e}"
    motion = "hinged" if hinged else "still" if still else "swing"
    return "_".join(["sweep", engine, prof, bat.name.split()[0] + ("_corked" if corked else ""),
                     motion])


def build_parser() -> argparse.ArgumentParser:
    swing, pitch = presets.PAPER_SWING, presets.PAPER_PITCH_MPS
    p = argparse.ArgumentParser(
        prog="python -m experiments.sweep",
        description="Fire a ball along a bat in physics engines and compare with impact theory.",
        epilog=f"engines: {', '.join(adapters.names())}; bats: {', '.join(presets.BATS)}. "
               "Exit code 2 on bad input (results left untouched).",
    )
    _cli.add_engine(p)
    p.add_argument("--profile", choices=adapters.PROFILES, default="reference",
                   help="engine settings: tuned for fidelity, or the engine's own defaults")
    p.add_argument("--dt", type=float, default=None, metavar="S",
                   help="override the profile's time step (s)")
    p.add_argument("--bat", choices=list(presets.BATS), default="r161")
    p.add_argument("--corked", action="store_true", help="drill and fill the barrel end")
    p.add_argument("--hole-radius", type=float, default=0.0127, metavar="M")
    p.add_argument("--hole-depth", type=float, default=0.254, metavar="M")
    p.add_argument("--fill-density", type=float, default=200.0, metavar="KGM3",
                   help="cork 200, rubber 1100, hollow 0")
    p.add_argument("--wood-density", type=float, default=640.0, metavar="KGM3")
    p.add_argument("--points", type=int, default=41, help="impact points over the hittable length")
    p.add_argument("--s-range", type=float, nargs=2, default=None, metavar=("MIN", "MAX"),
                   help="part of the bat to sweep, m from the COM (default: all of it)")
    p.add_argument("--v0", type=float, default=pitch, metavar="MPS", help="pitch speed")
    p.add_argument("--u0", type=float, default=swing.u0_mps, metavar="MPS", help="bat COM speed")
    p.add_argument("--omega0", type=float, default=swing.omega0_radps, metavar="RADPS")
    p.add_argument("--e", type=float, default=presets.E_WOOD, help="coefficient of restitution")
    p.add_argument("--theta", type=float, default=0.0, metavar="RAD",
                   help="ball's angle to the contact normal")
    p.add_argument("--swing", action="store_true",
                   help="swing the bat about the hands in the engine before each impact, with "
                        "the constant torque that reaches --omega0 over --swing-angle; u0 is "
                        "then omega0 times the hands-to-COM distance (--u0 is ignored)")
    p.add_argument("--hands", type=float, default=0.1, metavar="M",
                   help="hands (pivot) from the knob, for --swing and the COP")
    p.add_argument("--swing-angle", type=float, default=math.pi / 2, metavar="RAD")
    _cli.add_runner(p)
    _cli.add_out(p, ROOT / "results")
    p.add_argument("--name", default=None, help="file stem (default from the options)")
    p.add_argument("--no-locate", action="store_true",
                   help="skip locating the sweet spot and COP from engine data")
    p.add_argument("--compare", nargs=2, type=Path, metavar=("OLD", "NEW"),
                   help="print what changed between two sweep tables, then exit")
    return p


def sweep_from_args(args: argparse.Namespace) -> Sweep:
    """Validate every option (ValueError names the problem) and build the sweep."""
    bat = presets.BATS[args.bat]
    if args.corked:
        bat = bat.corked(hole_radius_m=args.hole_radius, hole_depth_m=args.hole_depth,
                         fill_density_kgm3=args.fill_density, wood_density_kgm3=args.wood_density)
    if args.dt is not None and not (math.isfinite(args.dt) and args.dt > 0):
        raise ValueError(f"--dt={args.dt!r} is not allowed; allowed: a time step > 0 s")
    s = _grid.grid(bat, args.points, *(args.s_range or (None, None)))
    swing, u0 = None, args.u0
    if args.swing:
        if args.theta != 0.0:
            raise ValueError("--swing with --theta is not supported; allowed: --theta 0")
        swing = HingedSwing.for_omega(bat, args.omega0, hands_from_knob_m=args.hands,
                                      angle_rad=args.swing_angle)
        u0 = args.omega0 * swing.arm_m(bat)
    firing = _grid.Firing(bat=bat, s_m=s, v0_mps=args.v0, u0_mps=u0, omega0_radps=args.omega0,
                          e=args.e, theta_rad=args.theta, hands_from_knob_m=args.hands,
                          swing=swing)
    firing.cases()  # every impact validated before anything runs
    engines = args.engine
    for name in engines:
        adapters.settings_for(name, args.profile, **({} if args.dt is None else {"dt_s": args.dt}))
    name = args.name or default_name(_cli.engine_label(engines), args.profile, args.dt, presets.BATS[args.bat],
                                     args.corked, args.u0 == 0 and args.omega0 == 0, args.swing)
    return Sweep(engines=engines, profile=args.profile, dt_s=args.dt, firing=firing, name=name)


def run(sweep: Sweep, runner: _runner.Runner | None = None, *, locate: bool = True,
        chart: bool = False) -> tuple[pd.DataFrame, dict]:
    """Fire every engine over the grid; return the table and a per-engine summary. With
    ``chart`` the summary's "png" holds the chart, drawn while the workers locate the marks."""
    runner = runner or _runner.Runner()
    settings = {n: _grid.with_dt(adapters.settings_for(n, sweep.profile), sweep.dt_s)
                for n in sweep.engines}
    jobs = [j for n in sweep.engines for j in sweep.firing.jobs(n, settings[n])]
    t0 = time.perf_counter()
    table = _grid.table(runner.fire(jobs), sweep.profile)
    elapsed = time.perf_counter() - t0
    marks = _grid.analytic_marks(sweep.firing)
    summary = {n: _summarize(table[table.engine == n]) for n in sweep.engines}
    located = _locate(runner, sweep.firing, settings, table, marks) if locate else lambda: {}
    meta = {"analytic": marks, "engines": summary, "fire_s": elapsed}
    if chart:
        meta["png"] = render(table, sweep, marks)
    for (name, key), value in located().items():
        summary[name][key] = value
    for n in sweep.engines:
        summary[n].update(settings=settings[n].as_dict(),
                          engine_version=adapters.record(n).version())
    return table, meta


def _summarize(df: pd.DataFrame) -> dict:
    ok = df[df.status == "ok"]
    return {
        "impacts": len(df),
        "status_counts": {k: int(v) for k, v in df.status.value_counts().sort_index().items()},
        "v1_abs_err_max_mps": float(ok.v1_abs_err_mps.max()) if len(ok) else math.nan,
        "v1_abs_err_median_mps": float(ok.v1_abs_err_mps.median()) if len(ok) else math.nan,
        "v1_rel_err_max": float(ok.v1_rel_err.max()) if len(ok) else math.nan,
        "v1_rel_err_median": float(ok.v1_rel_err.median()) if len(ok) else math.nan,
        "wall_per_impact_median_s": float(df.wall_s.median()),
        "sweet_spot_engine_m": math.nan,
        "cop_engine_m": math.nan,
    }


def _locate(runner, firing, settings, table, marks) -> Callable[[], dict]:
    """Start locating the sweet spot and COP on each all-ok engine's own data, the searches
    side by side; returns a function that waits for {(engine, summary key): value}."""
    calls, keys = [], []
    for name, df in table.groupby("engine", sort=False):
        if not (df.status == "ok").all():
            continue
        bracket = _grid.bracket_around(df.s_m, df.v1_engine_mps, "max")
        if bracket is not None and bracket[0] < marks["sweet_spot_m"] < bracket[1]:
            calls.append((_grid.locate_sweet_spot, (name, settings[name], firing, bracket)))
            keys.append((name, "sweet_spot_engine_m"))
        bracket = _grid.bracket_around(df.s_m, df.hand_dv_engine_mps, "root")
        if bracket is not None:
            calls.append((_grid.locate_cop, (name, settings[name], firing, bracket)))
            keys.append((name, "cop_engine_m"))
    # a bounded Brent search takes ~10-25 simulations of about the grid's median cost
    estimate = 25 * len(calls) * float(table.wall_s.median())
    pending = runner.submit_all(calls, estimate)
    return lambda: dict(zip(keys, pending()))


def render(table: pd.DataFrame, sweep: Sweep, marks: dict) -> bytes:
    """The chart as PNG bytes."""
    import matplotlib.pyplot as plt

    fig = plot(table, sweep, marks)
    png = figure_png(fig)
    plt.close(fig)
    return png


def plot(table: pd.DataFrame, sweep: Sweep, marks: dict):
    """v1 along the bat: analytic curve, each engine's points, sweet spot and COP; error panel."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    f = sweep.firing
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(8, 7), sharex=True,
                                      gridspec_kw={"height_ratios": [3, 2]})
    s = np.linspace(f.bat.s_min_m, f.bat.s_max_m, 400)
    top.plot(s, batted_ball_speed(f.bat, presets.BASEBALL, s, v0_mps=f.v0_mps, u0_mps=f.u0_mps,
                                  omega0_radps=f.omega0_radps, e=f.e, theta_rad=f.theta_rad),
             color="black", lw=1.5, label="analytic")
    style = {n: adapters.record(n) for n in table.engine.unique()}
    floor = 1e-16
    any_ok = False
    for i, (name, df) in enumerate(table.groupby("engine", sort=False)):
        ok = df.status == "ok"
        any_ok |= bool(ok.any())
        mark, color = style[name].marker, style[name].color
        top.plot(df.s_m[ok], df.v1_engine_mps[ok], mark, ms=5, mfc="none",
                 color=color, label=f"{name} ({ok.sum()}/{len(df)} ok)")
        if (~ok).any():
            # Failed impacts carry no trustworthy v1: a rug along the bottom, one row per engine.
            statuses = ", ".join(f"{k} {v}" for k, v in df.status[~ok].value_counts().items())
            top.plot(df.s_m[~ok], np.full((~ok).sum(), 0.03 + 0.05 * i), "x", ms=6,
                     color=color, transform=top.get_xaxis_transform(),
                     label=f"{name} failed: {statuses}")
        bottom.semilogy(df.s_m[ok], np.maximum(df.v1_abs_err_mps[ok], floor), mark,
                        ms=5, mfc="none", color=color, label=name)
    for ax in (top, bottom):
        ax.axvline(marks["sweet_spot_m"], color="tab:red", ls="--", lw=1)
        ax.axvline(marks["cop_m"], color="tab:purple", ls=":", lw=1.2)
    top.annotate(f"sweet spot {marks['sweet_spot_m'] * 1e3:.1f} mm", (marks["sweet_spot_m"], 0.3),
                 xycoords=("data", "axes fraction"), rotation=90, color="tab:red", fontsize=8,
                 ha="right")
    top.annotate(f"COP (hands {f.hands_from_knob_m} m) {marks['cop_m'] * 1e3:.1f} mm",
                 (marks["cop_m"], 0.3), xycoords=("data", "axes fraction"), rotation=90,
                 color="tab:purple", fontsize=8, ha="left")
    top.set_ylabel("batted-ball speed v1 (m/s)")
    top.set_title(f"{f.bat.name}: v0 = {f.v0_mps:g} m/s, u0 = {f.u0_mps:.4g} m/s, "
                  f"omega0 = {f.omega0_radps:g} rad/s, e = {f.e:g}; profile {sweep.profile}"
                  + (f", dt = {sweep.dt_s:g} s" if sweep.dt_s else "")
                  + (f"\nswung in the engine about the hands ({f.hands_from_knob_m:g} m from the "
                     f"knob) by {f.swing.torque_nm:.1f} N m over {f.swing.angle_rad:.3g} rad"
                     if f.swing else ""), fontsize=10)
    top.legend(fontsize=8, loc="lower center")
    top.grid(alpha=0.3)
    bottom.set_ylabel("|v1 engine - v1 analytic| (m/s)")
    bottom.set_xlabel("impact point s from the COM toward the barrel (m)")
    bottom.grid(alpha=0.3, which="both")
    if any_ok:
        bottom.legend(fontsize=8)
    else:
        bottom.text(0.5, 0.5, "no ok impacts", transform=bottom.transAxes, ha="center")
    fig.tight_layout()
    return fig


def print_summary(meta: dict) -> None:
    """Per engine: errors, statuses, sweet spot and COP from engine data vs analytic (mm)."""
    marks = meta["analytic"]
    print(f"{'engine':9} {'ok':>7} {'max |dv1| m/s':>14} {'median':>10} {'max rel':>9} "
          f"{'sweet spot mm':>18} {'COP mm':>18} {'us/impact':>9}")
    for name, s in meta["engines"].items():
        ok = s["status_counts"].get("ok", 0)

        def mm(x, ref):
            return "n/a" if not math.isfinite(x) else f"{x * 1e3:.4f} ({(x - ref) * 1e3:+.1e})"

        print(f"{name:9} {ok:>3}/{s['impacts']:<3} {s['v1_abs_err_max_mps']:>14.3e} "
              f"{s['v1_abs_err_median_mps']:>10.2e} {s['v1_rel_err_max']:>9.2e} "
              f"{mm(s['sweet_spot_engine_m'], marks['sweet_spot_m']):>18} "
              f"{mm(s['cop_engine_m'], marks['cop_m']):>18} "
              f"{s['wall_per_impact_median_s'] * 1e6:>9.1f}")
    print(f"analytic: sweet spot {marks['sweet_spot_m'] * 1e3:.4f} mm, "
          f"COP {marks['cop_m'] * 1e3:.4f} mm from the COM")


def write(table: pd.DataFrame, meta: dict, sweep: Sweep, out_dir: Path) -> list[Path]:
    """CSV, JSON sidecar and PNG: all rendered first, then renamed into place together."""
    stem = out_dir / sweep.name
    csv = table.to_csv(index=False, float_format=FLOAT_FORMAT, lineterminator="\n")
    png = meta.get("png") or render(table, sweep, meta["analytic"])
    sidecar = {k: v for k, v in meta.items() if k != "png"}
    return atomic_write_many({
        stem.with_suffix(".csv"): csv.encode("utf-8"),
        stem.with_suffix(".json"): json_bytes({**sidecar, "provenance": provenance()}),
        stem.with_suffix(".png"): png,
    })


def main(argv: list[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    if args.compare:
        from .compare import compare_tables

        return compare_tables(*args.compare)
    try:
        sweep = sweep_from_args(args)
    except ValueError as err:
        parser.error(str(err))
    t0 = time.perf_counter()
    try:
        with _cli.Progress(len(sweep.firing.s_m) * len(sweep.engines), "impacts") as bar, \
                _cli.runner(args, bar) as runner:
            table, meta = run(sweep, runner, locate=not args.no_locate, chart=True)
        paths = write(table, meta, sweep, args.out)
    except KeyboardInterrupt:
        print("interrupted: previous results left intact", file=sys.stderr)
        return 130
    print_summary(meta)
    print(f"{len(table)} impacts in {time.perf_counter() - t0:.2f} s -> "
          + ", ".join(str(p.relative_to(ROOT) if p.is_relative_to(ROOT) else p) for p in paths))
    return 0


if __name__ == "__main__":
    sys.exit(main())
