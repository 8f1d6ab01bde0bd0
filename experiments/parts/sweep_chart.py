"""The sweep's chart: v1 along the bat per engine over the analytic curve, failed impacts in a
strip of their own, each row's error under its tolerance, the sweet spot and the COP; and the
summary it prints."""

from __future__ import annotations

import math

import numpy as np
import pandas as pd

import adapters
from analytic import batted_ball_speed, presets

from ..core import judge
from ..core.io import figure_png
from ..core.judge import Status


def render(table: pd.DataFrame, sweep, marks: dict) -> bytes:
    """The chart as PNG bytes."""
    import matplotlib.pyplot as plt

    fig = plot(table, sweep, marks)
    png = figure_png(fig)
    plt.close(fig)
    return png


def plot(table: pd.DataFrame, sweep, marks: dict):
    """v1 along the bat for a ``sweep.Sweep``: analytic curve, each engine's points, sweet spot
    and COP; a strip of failed impacts (no trustworthy v1, so kept off the v1 axis), one row
    per engine; errors."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    engines = list(table.engine.unique())
    fig, (top, strip, bottom) = plt.subplots(
        3,
        1,
        figsize=(11, 7.5 + 0.25 * len(engines)),
        sharex=True,
        gridspec_kw={"height_ratios": [3, 0.35 + 0.2 * len(engines), 2]},
    )
    _theory(top, table, sweep)
    any_ok = False
    for i, (name, df) in enumerate(table.groupby("engine", sort=False)):
        any_ok |= _engine(top, strip, bottom, i, adapters.record(name), df)
    strip.set_yticks(range(len(engines)), engines, fontsize=7)
    strip.set_ylim(-0.7, len(engines) - 0.3)
    strip.set_ylabel("failed", fontsize=8)
    if strip.get_legend_handles_labels()[0]:
        strip.legend(fontsize=7, loc="center left", bbox_to_anchor=(1.0, 0.5))
    else:
        strip.text(
            0.5,
            0.5,
            "no failed impacts",
            transform=strip.transAxes,
            ha="center",
            va="center",
            fontsize=8,
        )
    _marks(fig, (top, strip, bottom), sweep, marks)
    # legends beside the panels, never over the points
    top.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    top.grid(alpha=0.3)
    bottom.set_ylabel("|v1 engine - v1 rigid| (m/s)\nline: each row's tolerance")
    bottom.set_xlabel("impact point s from the COM toward the barrel (m)")
    bottom.grid(alpha=0.3, which="both")
    if any_ok:
        bottom.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    else:
        bottom.text(0.5, 0.5, "no ok impacts", transform=bottom.transAxes, ha="center")
    fig.tight_layout()
    return fig


def _theory(top, table: pd.DataFrame, sweep) -> None:
    """The single impulse's curve, and the compliant and rigid-episode answers at the grid."""
    f = sweep.firing
    s = np.linspace(f.bat.s_min_m, f.bat.s_max_m, 400)
    s = s[f.v0_mps * np.cos(f.theta_rad) + f.u0_mps + f.omega0_radps * s > 0.0]  # approaching
    top.plot(
        s,
        batted_ball_speed(
            f.bat,
            presets.BASEBALL,
            s,
            v0_mps=f.v0_mps,
            u0_mps=f.u0_mps,
            omega0_radps=f.omega0_radps,
            e=f.e,
            theta_rad=f.theta_rad,
        ),
        color="black",
        lw=1.5,
        label="single impulse (where the bodies approach)",
    )
    one = table.drop_duplicates("s_m")
    if "v1_compliant_mps" in one:
        top.plot(
            one.s_m,
            one.v1_compliant_mps,
            "--",
            color="tab:brown",
            lw=1.5,
            label=f"compliant contact ({sweep.law}), at the grid",
        )
    if ((one.rigid_impacts > 1) | (one.rigid_sustained_s > 0)).any():
        top.plot(
            one.s_m,
            one.v1_analytic_mps,
            "-",
            color="tab:gray",
            lw=2.5,
            alpha=0.6,
            zorder=0,
            label="rigid episode (re-contacts, sustained contact), at the grid",
        )


def _engine(top, strip, bottom, row: int, rec, df: pd.DataFrame) -> bool:
    """One engine's points: v1 where measured, a cross on the strip's ``row`` where not, the
    errors and tolerances; whether any v1 was measured."""
    floor = 1e-16
    name, mark, color = rec.name, rec.look.marker, rec.look.color
    ok = df.status.isin(judge.MEASURED)
    within = int((df.status == Status.OK).sum())
    others = "".join(
        f", {v} {k}" for k, v in df.status[ok & (df.status != Status.OK)].value_counts().items()
    )
    top.plot(
        df.s_m[ok],
        df.v1_engine_mps[ok],
        mark,
        ms=5,
        mfc="none",
        color=color,
        label=f"{name} ({within}/{len(df)} ok{others})",
    )
    if (~ok).any():  # no trustworthy v1: kept off the v1 axis
        statuses = ", ".join(f"{k} {v}" for k, v in df.status[~ok].value_counts().items())
        as_rigid = int(((df.status == Status.NO_SEPARATION) & (df.rigid_end == "time_limit")).sum())
        if as_rigid:
            statuses += f" ({as_rigid} still in contact in rigid theory too)"
        strip.plot(
            df.s_m[~ok],
            np.full((~ok).sum(), row),
            "x",
            ms=6,
            color=color,
            label=f"{name} failed: {statuses}",
        )
    bottom.semilogy(
        df.s_m[ok],
        np.maximum(df.v1_abs_err_mps[ok], floor),
        mark,
        ms=5,
        mfc="none",
        color=color,
        label=name,
    )
    bottom.semilogy(df.s_m, df.v1_tol_mps, "-", lw=0.8, color=color, alpha=0.6)
    return bool(ok.any())


def _marks(fig, axes, sweep, marks: dict) -> None:
    """The sweet spot and COP on every panel, the labels and the figure's title."""
    f, top = sweep.firing, axes[0]
    for key, label, color, ls, ha in (
        ("sweet_spot", "sweet spot", "tab:red", "--", "right"),
        ("cop", f"COP (hands {f.hands_from_knob_m} m)", "tab:purple", ":", "left"),
    ):
        s = marks[f"{key}_m"]
        if not math.isfinite(s):  # no reference applies (locate.analytic_marks says why)
            continue
        for ax in axes:
            ax.axvline(s, color=color, ls=ls, lw=1.1)
        ref = marks.get(f"{key}_reference", "single impulse")
        top.annotate(
            f"{label} {s * 1e3:.1f} mm ({ref})",
            (s, 0.03),
            xycoords=("data", "axes fraction"),
            rotation=90,
            color=color,
            fontsize=8,
            ha=ha,
            va="bottom",
        )
    top.set_ylabel("batted-ball speed v1 (m/s)")
    fig.suptitle(
        f"{f.bat.name}: v0 = {f.v0_mps:g} m/s, u0 = {f.u0_mps:.4g} m/s, "
        f"omega0 = {f.omega0_radps:g} rad/s, e = {f.e:g}; profile {sweep.profile}"
        + (f", dt = {sweep.dt_s:g} s" if sweep.dt_s else "")
        + (
            f"\nswung in the engine about the hands ({f.hands_from_knob_m:g} m from the "
            f"knob) by {f.swing.torque_nm:.1f} N m over {f.swing.angle_rad:.3g} rad"
            if f.swing
            else ""
        ),
        fontsize=10,
    )


def print_compliant(table: pd.DataFrame, law: str) -> None:
    """How far the rigid answer is from the compliant one along the bat."""
    one = table.drop_duplicates("s_m")
    worst = one.v1_rigid_minus_compliant_mps.abs().idxmax()
    print(
        f"compliant ({law}) vs rigid: max |v1 rigid - v1 compliant| "
        f"{abs(one.v1_rigid_minus_compliant_mps[worst]):.3f} m/s at s = {one.s_m[worst]:.3f} m; "
        f"contact {one.compliant_contact_s.min() * 1e3:.2f}-"
        f"{one.compliant_contact_s.max() * 1e3:.2f} ms; the bat turns up to "
        f"{one.compliant_bat_turn_rad.abs().max() * 1e3:.1f} mrad meanwhile"
    )
    finite = (one.v1_impulse_law_e_mps - one.v1_compliant_mps).abs()
    print(
        f"  of which the finite contact time is up to {finite.max():.3f} m/s (compliant against "
        f"impulse theory at the law's own e(v_c), {one.compliant_e.min():.3f}-"
        f"{one.compliant_e.max():.3f}); the rest is the ball's COR at these speeds"
    )


def print_summary(meta: dict, table: pd.DataFrame | None = None) -> None:
    """Per engine: errors, statuses, sweet spot and COP from engine data vs analytic (mm); the
    analytic marks and what each is located on (``locate.analytic_marks``: the single impulse,
    or the whole rigid episode where that impulse is not all of it; 'no ref' where neither
    applies); with the ``table``, each status other than ok, counted, with the first such
    row's reason."""
    marks = meta["analytic"]
    print(
        f"{'engine':9} {'ok':>7} {'max |dv1| m/s':>14} {'median':>10} {'max rel':>9} "
        f"{'sweet spot mm':>18} {'COP mm':>18} {'us/impact':>9}"
    )
    for name, s in meta["engines"].items():
        ok = s["status_counts"].get(Status.OK, 0)
        print(
            f"{name:9} {ok:>3}/{s['impacts']:<3} {s['v1_abs_err_max_mps']:>14.3e} "
            f"{s['v1_abs_err_median_mps']:>10.2e} {s['v1_rel_err_max']:>9.2e} "
            f"{_offset(s['sweet_spot_engine_m'], marks['sweet_spot_m']):>18} "
            f"{_offset(s['cop_engine_m'], marks['cop_m']):>18} "
            f"{s['wall_per_impact_median_s'] * 1e6:>9.1f}"
        )
    best = marks.get("sweet_spot_hittable_m", marks["sweet_spot_m"])
    off = (
        ""
        if best == marks["sweet_spot_m"] or not math.isfinite(best)
        else f" (off the bat's cylinder: the best point on it is its end, {best * 1e3:.4f} mm)"
    )
    print(
        f"analytic: sweet spot {_mm(marks['sweet_spot_m'])}{off}, "
        f"COP {_mm(marks['cop_m'])} from the COM"
    )
    print(
        "  located on: "
        + "; ".join(
            _reference(marks, k, label)
            for k, label in (("sweet_spot", "sweet spot"), ("cop", "COP"))
        )
    )
    if table is not None:
        for (name, status), rows in table[table.status != Status.OK].groupby(["engine", "status"]):
            print(f"{name}: {len(rows)} {status} ({rows.episode_end.iloc[0]})")


def _mm(x: float) -> str:
    return f"{x * 1e3:.4f} mm" if math.isfinite(x) else "n/a"


def _offset(x: float, ref: float) -> str:
    """An engine's mark (mm) and its offset from the analytic one; 'no ref' where there is
    none to compare with."""
    if not math.isfinite(x):
        return "n/a"
    if not math.isfinite(ref):
        return f"{x * 1e3:.4f} (no ref)"
    return f"{x * 1e3:.4f} ({(x - ref) * 1e3:+.1e})"


def _reference(marks: dict, key: str, label: str) -> str:
    """What the analytic ``key`` mark is located on, with the single impulse's beside it where
    that is not the reference (marks from before the references were recorded: the single
    impulse's COP, the sweet spot unsaid)."""
    ref = marks.get(f"{key}_reference", "single impulse" if key == "cop" else "unrecorded")
    single = marks.get(f"{key}_single_impulse_m", math.nan)
    text = f"{label}: {ref}"
    if ref == "none" or f"{key}_why" in marks:
        text += f" ({marks.get(f'{key}_why', 'no reference')})"
    if ref != "single impulse" and math.isfinite(single):
        text += f" (the single impulse's, which does not apply here: {single * 1e3:.4f} mm)"
    lo, hi = marks.get("cylinder_s_min_m", -math.inf), marks.get("cylinder_s_max_m", math.inf)
    if key == "cop" and not lo <= marks["cop_m"] <= hi and math.isfinite(marks["cop_m"]):
        text += " (off the bat's cylinder: no engine can locate it)"
    return text
