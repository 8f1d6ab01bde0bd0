"""Fire the ball along a bat in one engine (or all) and compare every impact with theory.

    python -m experiments.sweep --engine NAME[,NAME...]|all
    python -m experiments.sweep --engine all --points 41 --u0 0 --omega0 0
    python -m experiments.sweep --compare runs/A/sweep.csv runs/B/sweep.csv

Writes runs/<name>/sweep.csv (one row per impact), sweep.json (provenance, configuration and
summary) and sweep.png (v1 along the bat per engine over the analytic curve, and the error),
all at once (see experiments._cli for names and --out/--name/--force).
"""

from __future__ import annotations

import argparse
import math
import sys
import time
from collections.abc import Callable, Mapping
from dataclasses import dataclass, replace
from pathlib import Path

import pandas as pd

import adapters
from analytic import Bat, compliant, flight, predict, presets
from analytic.ball import LAWS
from analytic.cork import corked_bat
from analytic.dynamics import HingedSwing
from analytic.model import WOOD_DENSITY_KGM3

from .compare import check_table, compare_tables
from .core import boundary, carry, cli, estimate, firings, judge, runs, tables
from .core import locate as locating
from .core.estimate import duration
from .core.fire import Job
from .core.io import json_bytes, provenance
from .core.placement import min_dt_s
from .core.runner import Runner
from .parts import sweep_chart
from .parts.sweep_options import DEFAULT_E, build_parser, in_options

FLOAT_FORMAT = "%.12g"
#: Runs estimated to take longer say so before they start.
LONG_RUN_S = 60.0


@dataclass(frozen=True, kw_only=True)
class Sweep:
    """One sweep: engines, profile and time step, and what to fire."""

    engines: tuple[str, ...]
    profile: str
    dt_s: float | None
    firing: firings.Firing
    name: str
    #: Each engine's settings: the profile's, with the time step overridden if one is given.
    settings: Mapping[str, adapters.Settings]
    #: A compliant law (analytic.ball.LAWS) whose prediction goes beside the rigid one.
    law: str | None = None
    #: Add each batted ball's flight (``core.carry``).
    flight: bool = False

    def jobs(self) -> list[Job]:
        """Every impact of the sweep: each engine over the grid."""
        return [j for n in self.engines for j in self.firing.jobs(n, self.settings[n])]


def default_name(
    engine: str,
    profile: str,
    dt_s: float | None,
    bat: Bat,
    corked: bool,
    still: bool,
    hinged: bool = False,
    e: float = DEFAULT_E,
) -> str:
    """sweep_<engine|all>_<profile>[-dt<dt>]_<bat>[_corked]_<swing|still|hinged>[_e<e>]."""
    prof = profile if dt_s is None else f"{profile}-dt{dt_s:.0e}"
    motion = "hinged" if hinged else "still" if still else "swing"
    return "_".join(
        ["sweep", engine, prof, bat.name.split()[0] + ("_corked" if corked else ""), motion]
        + ([] if e == DEFAULT_E else [f"e{e:g}"])
    )


HOLE = {
    "hole_radius": ("hole_radius_m", 0.0127),
    "hole_depth": ("hole_depth_m", 0.254),
    "fill_density": ("fill_density_kgm3", 200.0),
    "wood_density": ("wood_density_kgm3", WOOD_DENSITY_KGM3),
}


def sweep_from_args(args: argparse.Namespace) -> Sweep:
    """Validate every option together (ValueError names the problem) and build the sweep."""
    bat = _bat(args)
    if args.law is not None and args.reference != "compliant":
        raise ValueError(
            f"--law {args.law} without --reference compliant does nothing; "
            "allowed: add --reference compliant, or leave --law out"
        )
    law = (args.law or "ball") if args.reference == "compliant" else None
    s = firings.grid(bat, args.points, *(args.s_range or (None, None)))
    swing, u0 = _swing(args, bat)
    # the pitch's backspin lifts it: about -x for a ball coming along -y (impact frame)
    firing = firings.Firing(
        bat=bat,
        s_m=s,
        v0_mps=args.v0,
        u0_mps=u0,
        omega0_radps=args.omega0,
        e=args.e,
        theta_rad=args.theta,
        hands_from_knob_m=args.hands,
        swing=swing,
        mu=args.friction,
        undercut_m=args.undercut,
        spin_radps=(-args.spin, 0.0, 0.0),
    )
    cases = firing.cases()  # every impact validated before anything runs
    dt = {} if args.dt is None else {"dt_s": args.dt}
    settings = {n: adapters.settings_for(n, args.profile, **dt) for n in args.engine}
    if swing is not None:
        _check_swing_steps(swing, bat, settings, args)
    if args.flight:
        _check_flight(cases)
    locating.analytic_marks(firing, budget_s(settings))  # the marks too (cached for the run)
    need = max(min_dt_s(c, st) for c in cases for st in settings.values())
    if not all(st.dt_s > need for st in settings.values()):
        step = (
            f"--dt {args.dt:g} s"
            if args.dt is not None
            else f"the {args.profile} profile's step ({min(st.dt_s for st in settings.values()):g}"
            " s)"
        )
        slowest = min(c.closing_speed_mps for c in cases)
        raise ValueError(
            f"{step} is too small to place these impacts: at a closing speed of "
            f"{slowest:.3g} m/s the contact, first seen overlap_m deep after "
            "approach_steps steps, would start inside the bat; allowed: --dt > "
            f"{need:.3g} s, or a faster impact (--v0, --u0, --omega0)"
        )
    name = default_name(
        runs.engine_label(args.engine),
        args.profile,
        args.dt,
        presets.BATS[args.bat],
        args.corked,
        args.u0 == 0 and args.omega0 == 0,
        args.swing,
        args.e,
    ) + (f"_{law}" if law else "")
    name += "".join(
        f"_{k}{v:g}"
        for k, v in (("mu", args.friction), ("undercut", args.undercut), ("spin", args.spin))
        if v
    )
    return Sweep(
        engines=args.engine,
        profile=args.profile,
        dt_s=args.dt,
        firing=firing,
        name=name,
        law=law,
        settings=settings,
        flight=args.flight,
    )


def _bat(args: argparse.Namespace) -> Bat:
    """The bat the options ask for (corked if asked, with the hole options)."""
    bat = presets.BATS[args.bat]
    given = [k for k in HOLE if getattr(args, k) is not None]
    if given and not args.corked:
        flag = "--" + given[0].replace("_", "-")
        raise ValueError(
            f"{flag} {getattr(args, given[0])!r} without --corked does nothing; "
            "allowed: add --corked, or leave the hole options out"
        )
    if args.corked and bat in presets.HOLLOW:
        raise ValueError(
            f"--corked with --bat {args.bat}: a hollow metal shell has no wood in "
            "its barrel to drill and fill; allowed: --corked with a wood bat ("
            + ", ".join(n for n, b in presets.BATS.items() if b not in presets.HOLLOW)
            + ")"
        )
    if args.corked:
        bat = corked_bat(
            bat,
            **{
                field: default if getattr(args, k) is None else getattr(args, k)
                for k, (field, default) in HOLE.items()
            },
        )
    return bat


def _swing(args: argparse.Namespace, bat: Bat) -> tuple[HingedSwing | None, float]:
    """The hinged swing (None without --swing) and the bat's nominal u0 (m/s)."""
    hands_max = bat.com_from_knob_m if args.swing else bat.length_m
    if not args.hands < hands_max:
        raise ValueError(
            f"--hands {args.hands!r} m is not allowed for '{bat.name}'; allowed: 0 "
            f"<= --hands < {hands_max:g} m from the knob ("
            + (
                "the hands must be on the knob side of the COM to swing it)"
                if args.swing
                else "on the bat)"
            )
        )
    if args.hands == bat.com_from_knob_m:  # the hand point's change is -P/M wherever it hits
        raise ValueError(
            f"--hands {args.hands!r} m is the COM of '{bat.name}', which has no "
            f"centre of percussion; allowed: 0 <= --hands < {hands_max:g} m from "
            f"the knob, != {bat.com_from_knob_m:g} m"
        )
    if not args.swing:
        return None, args.u0
    if args.u0 != presets.PAPER_SWING.u0_mps:
        raise ValueError(
            f"--u0 {args.u0!r} with --swing does nothing (the swing sets u0 = "
            "omega0 x the hands-to-COM distance); allowed: leave --u0 out"
        )
    if args.theta != 0.0:
        raise ValueError(
            f"--swing with --theta {args.theta!r}: not supported; allowed: --theta 0 with --swing"
        )
    swing = HingedSwing.for_omega(
        bat, args.omega0, hands_from_knob_m=args.hands, angle_rad=args.swing_angle
    )
    return swing, args.omega0 * swing.arm_m(bat)


def _check_swing_steps(
    swing: HingedSwing,
    bat: Bat,
    settings: Mapping[str, adapters.Settings],
    args: argparse.Namespace,
) -> None:
    """Refuse a swing shorter than a time step: t = 2 theta / omega0 under dt is stepped as
    one whole step (``placement.swing_case``), which releases the bat at tau dt / I_p, not at
    --omega0 (at 1e-6 rad and 32 rad/s, 160 times faster: an impact no case allows)."""
    dt = max(st.dt_s for st in settings.values())
    lasts = swing.duration_s(bat)
    if lasts < dt:
        raise ValueError(
            f"--swing-angle {args.swing_angle:g} rad: the swing to --omega0 "
            f"{args.omega0:g} rad/s lasts {lasts:.3g} s, under one time step "
            f"({dt:g} s), so it cannot be stepped; allowed: --swing-angle >= "
            f"{args.omega0 * dt / 2:.3g} rad (2 theta / omega0 >= dt), or a "
            "smaller --dt"
        )


def _check_flight(cases) -> None:
    """Refuse a --flight whose batted balls (the single impulse's) would leave faster than the
    flight model holds (``analytic.flight.MAX_SPEED_MPS``): their carry is no answer."""
    fastest = max(cases, key=lambda c: abs(predict(c).v1_mps))
    v1 = abs(predict(fastest).v1_mps)
    if v1 > flight.MAX_SPEED_MPS:
        raise ValueError(
            f"--flight: the ball would leave at {v1:.4g} m/s (s = {fastest.s_m:.3g} "
            f"m), over the {flight.MAX_SPEED_MPS:g} m/s the flight model's drag and "
            "lift hold to; allowed: slower --v0, --u0, --omega0, or no --flight"
        )


def budget_s(settings: Mapping[str, adapters.Settings]) -> float:
    """How long the rigid episode behind the analytic marks is followed (s): as long as the
    engines follow theirs (``max_contact_s``; the shortest, should they differ), as their rows'
    answers are (``judge.rigid``)."""
    return min(st.max_contact_s for st in settings.values())


def check_cost(sweep: Sweep, budget_h: float, locate: bool = True) -> float:
    """The run's estimated wall time (s, ``core.estimate``: the impacts, then with ``locate``
    the searches for each engine's sweet spot and COP); ValueError if over ``budget_h``."""
    per_engine = estimate.run_s(sweep.jobs())
    if locate:  # a search near each analytic mark on the bat, per engine
        marks = locating.analytic_marks(sweep.firing, budget_s(sweep.settings))
        at = [
            s
            for s in (marks["sweet_spot_m"], marks["cop_m"])
            if math.isfinite(s) and sweep.firing.bat.s_min_m <= s <= sweep.firing.bat.s_max_m
        ]
        near = [
            Job(
                engine=n,
                settings=sweep.settings[n],
                case=sweep.firing.case(s),
                swing=sweep.firing.swing,
            )
            for n in sweep.engines
            for s in at
        ]
        for name, search_s in estimate.search_s(near).items():
            per_engine[name] += search_s
    total = sum(per_engine.values())
    if total > budget_h * 3600.0:
        worst = max(per_engine, key=per_engine.get)
        each = per_engine[worst] / len(sweep.firing.s_m)
        raise ValueError(
            f"this sweep would take about {duration(total)} ({worst}: {duration(each)} an "
            f"impact), over --budget-h {budget_h:g}; allowed: a run within the budget (a "
            "coarser --dt, fewer --points or engines), or a larger --budget-h"
        )
    return total


def run(
    sweep: Sweep, runner: Runner | None = None, *, locate: bool = True, chart: bool = False
) -> tuple[pd.DataFrame, dict]:
    """Fire every engine over the grid; return the table and a per-engine summary. With
    ``chart`` the summary's "png" holds the chart, drawn while the workers locate the marks."""
    runner = runner or Runner()
    settings = sweep.settings
    t0 = time.perf_counter()
    table = tables.table(runner.fire(sweep.jobs()), sweep.profile, spin_columns=sweep.flight)
    if sweep.flight:
        table = carry.with_flight(table)
    if sweep.law:
        table = with_compliant(table, sweep.firing, sweep.law)
    elapsed = time.perf_counter() - t0
    marks = locating.analytic_marks(sweep.firing, budget_s(settings))
    summary = {n: _summarize(table[table.engine == n]) for n in sweep.engines}
    located = _locate(runner, sweep.firing, settings, table, marks) if locate else lambda: {}
    meta = {"analytic": marks, "engines": summary, "fire_s": elapsed}
    if chart:
        meta["png"] = sweep_chart.render(table, sweep, marks)
    for (name, key), value in located().items():
        summary[name][key] = value
    for n in sweep.engines:
        summary[n].update(
            settings=settings[n].as_dict(), engine_version=adapters.record(n).version()
        )
    return table, meta


def with_compliant(table: pd.DataFrame, firing: firings.Firing, law: str) -> pd.DataFrame:
    """The table with the compliant prediction of every impact beside the rigid one:
    v1_compliant_mps, v1_rigid_minus_compliant_mps (m/s), compliant_contact_s (s),
    compliant_peak_force_n (N), compliant_bat_turn_rad (rad): one integration per grid point.
    The law's own e at each closing speed (``compliant_e``) and impulse theory at that e
    (``v1_impulse_law_e_mps``) split the difference into the ball's COR and the contact's
    finite time."""
    contact_law = LAWS[law]
    got = {s: compliant.predict(firing.case(s), contact_law) for s in firing.s_m}
    e_law = {s: contact_law.restitution(firing.case(s).closing_speed_mps) for s in firing.s_m}
    out = table.copy()
    per_row = [got[s] for s in out.s_m]
    out["compliant_e"] = [e_law[s] for s in out.s_m]
    out["v1_impulse_law_e_mps"] = [
        predict(replace(firing.case(s), e=e_law[s])).v1_mps for s in out.s_m
    ]
    out["v1_compliant_mps"] = [g.v1_mps for g in per_row]
    out["v1_rigid_minus_compliant_mps"] = out.v1_analytic_mps - out.v1_compliant_mps
    out["compliant_contact_s"] = [g.contact_duration_s for g in per_row]
    out["compliant_peak_force_n"] = [g.peak_force_n for g in per_row]
    out["compliant_bat_turn_rad"] = [g.bat_turn_rad for g in per_row]
    return out


def _summarize(df: pd.DataFrame) -> dict:
    ok = df[df.status.isin(judge.MEASURED)]
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
    calls, keys = [], []  # keys[i][0]: the engine calls[i] fires
    for name, df in table.groupby("engine", sort=False):
        if not df.status.isin(judge.MEASURED).all():
            continue
        bracket = locating.bracket_around(df.s_m, df.v1_engine_mps, "max")
        if bracket is not None and bracket[0] < marks["sweet_spot_m"] < bracket[1]:
            calls.append((locating.locate_sweet_spot, (name, settings[name], firing, bracket)))
            keys.append((name, "sweet_spot_engine_m"))
        bracket = locating.bracket_around(df.s_m, df.hand_dv_engine_mps, "root")
        if bracket is not None:
            calls.append((locating.locate_cop, (name, settings[name], firing, bracket)))
            keys.append((name, "cop_engine_m"))
    cost = estimate.SEARCH_SIMULATIONS * len(calls) * float(table.wall_s.median())
    if not calls:
        return lambda: {}
    searches = runs.Progress(len(calls), "sweet spot and COP searches", unit="searches")
    pending = runner.submit_all(calls, cost, engines=[k[0] for k in keys], progress=searches)

    def wait() -> dict:
        with searches:
            return dict(zip(keys, pending()))

    return wait


def files(table: pd.DataFrame, meta: dict, sweep: Sweep, stem: str = "sweep") -> dict[str, bytes]:
    """The sweep's CSV, JSON sidecar (summary, configuration, provenance) and PNG, by name."""
    png = meta.get("png") or sweep_chart.render(table, sweep, meta["analytic"])
    sidecar = {k: v for k, v in meta.items() if k != "png"}
    return {
        f"{stem}.csv": table.to_csv(
            index=False, float_format=FLOAT_FORMAT, lineterminator="\n"
        ).encode("utf-8"),
        f"{stem}.json": json_bytes({**sidecar, "provenance": provenance()}),
        f"{stem}.png": png,
    }


@boundary.entry
def main(argv: list[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    if args.compare:
        others = [
            t
            for t in (sys.argv[1:] if argv is None else argv)
            if t.startswith("--") and t.split("=", 1)[0] != "--compare"
        ]
        if others:
            parser.error(
                f"--compare with {others[0]}: a comparison runs nothing; allowed: "
                "--compare OLD NEW alone"
            )

        for path in args.compare:
            try:
                check_table(path)
            except ValueError as err:
                parser.error(f"--compare: {err}")
        return compare_tables(*args.compare)
    try:
        sweep = sweep_from_args(args)
        cost = check_cost(sweep, args.budget_h, locate=not args.no_locate)
    except ValueError as err:
        parser.error(in_options(str(err)))
    target = runs.run_dir(parser, args, "sweep")
    if cost > LONG_RUN_S:
        print(f"estimated: about {duration(cost)}", file=sys.stderr)
    return cli.main_guard(lambda: _run_and_publish(sweep, args, parser, target))


def _run_and_publish(sweep: Sweep, args, parser, target: Path) -> int:
    t0 = time.perf_counter()
    with (
        runs.Progress(len(sweep.firing.s_m) * len(sweep.engines), "impacts") as bar,
        cli.runner(args, bar) as runner,
    ):
        table, meta = run(sweep, runner, locate=not args.no_locate, chart=True)
    meta["configuration"] = runs.configuration(parser, args)
    runs.publish(target, files(table, meta, sweep))
    sweep_chart.print_summary(meta, table)
    if sweep.law:
        sweep_chart.print_compliant(table, sweep.law)
    print(f"{len(table)} impacts in {time.perf_counter() - t0:.2f} s -> {runs.shown(target)}/")
    print(
        "compare two runs: python -m experiments.compare "
        f"{runs.shown(target)}/sweep.csv OTHER_RUN/sweep.csv"
    )
    return 0


if __name__ == "__main__":
    sys.exit(main())
