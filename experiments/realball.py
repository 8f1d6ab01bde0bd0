"""A real baseball in every engine: its contact knobs fitted to the ball's measured behaviour.

    python -m experiments.realball [--engine NAME[,NAME...]|all] [--quick]

For each engine and each ball model its record declares (``EngineRecord.balls``: a
restitution e, or a soft contact's stiffness, damping and impedance, each knob with its
range), the knobs are fitted by least
squares so that the baseball fired centrally at a rigid wall bounces with COR_LAW's COR at 10
to 60 m/s (each residual in units of COR_LAWS' half range, MLB's +-0.032 at 85 ft/s [mlbcor])
and, where its contact lasts, stays 0.7 ms in contact at 40 m/s ([nathan2000], the force's
duration: CONTACT_DEFINITIONS "force"); by finite differences, and also with the engine's own
derivative where its adapter has ``knob_derivative``; an engine's best model is the one
whose finite-difference fit costs least (``best``). Then, with each model's fitted knobs, fired
again: speeds the fit did not use, a still R161 (against the realistic ball and the band), and
the paper's swing along the bat against the realistic-ball reference (RealisticBall through
``analytic.compliant``), whose sweet spot each engine's ball moves. Writes realball.csv (per
engine, model and speed), realball_fits.csv (per engine, model and fit), realball_sweet.csv
(per engine, model and impact point), realball.md and realball.png.
"""

from __future__ import annotations

import json
import sys
import traceback
from dataclasses import replace

import numpy as np
import pandas as pd

import adapters
from adapters import BallContact
from analytic import ImpactCase, compliant, predict, presets
from analytic.ball import COR_LAW, REALISTIC_BALL, SPEED_REF_MPS, cor_range

from .core import firings
from .core.cli import Command
from .core.endings import Physics
from .core.fire import Job, fire_jobs
from .parts import realball_chart, realball_report
from .parts import realball_fit as rf

#: The bars (issue 59): the speeds the range is checked at lie in 15-55 m/s, at five or more.
BAR_LO_MPS, BAR_HI_MPS, BAR_SPEEDS = 15.0, 55.0, 5
#: The held-out bat impacts: a still R161 at its COM and 10 cm toward the barrel, 40 m/s.
BAT_POINTS_M, BAT_SPEED_MPS = (0.0, 0.1), 40.0
#: Impact points of the paper's swing (--quick: fewer).
SWEET_POINTS, QUICK_SWEET_POINTS = 21, 7
#: The gradient fit agrees with the finite-difference one when their CORs differ by at most
#: this share of the half band at every fit speed (both stop at the optimiser's tolerances,
#: whose knobs may differ along directions the COR hardly sees), and their costs by this.
AGREE_COR_BANDS, AGREE_COST_REL = 0.1, 0.1
#: --quick caps the optimiser's evaluations at this.
QUICK_EVALUATIONS = 12


def _fired_cor(engine: str, ball: BallContact, x, speeds) -> rf.Measured:
    """The fitted knobs fired at ``speeds`` through the harness."""
    return rf.EngineProbe(engine, ball).measure(np.asarray(x), speeds)


def speed_rows(engine: str, ball: BallContact, x, fit_speeds, held_speeds) -> list[dict]:
    """One row per speed: the model's COR and contact time against the law and its range."""
    speeds = (*fit_speeds, *held_speeds)
    m = _fired_cor(engine, ball, x, speeds)
    rows = []
    for i, v in enumerate(speeds):
        lo, hi = cor_range(v)
        c = float(m.cor[i])
        rows.append(
            {
                "engine": engine,
                "model": ball.label,
                "speed_mps": v,
                "role": "fit" if i < len(fit_speeds) else "held_out",
                "cor_engine": c,
                "cor_law": COR_LAW.cor(v),
                "cor_lo": lo,
                "cor_hi": hi,
                "in_range": bool(m.sound[i] and lo <= c <= hi),
                "contact_s": float(m.contact_s[i]),
                "sound": bool(m.sound[i]),
            }
        )
    return rows


def bat_rows(engine: str, ball: BallContact, x) -> list[dict]:
    """The still R161 hit at BAT_POINTS_M: v1 against the realistic ball and impulse theory's
    v1 at COR_LAWS' extremes (the band the engine's v1 should fall in)."""
    settings, e = rf.settings_at(engine, ball, x)
    cases = [
        ImpactCase(bat=presets.R161, ball=presets.BASEBALL, s_m=s, v0_mps=BAT_SPEED_MPS, e=e)
        for s in BAT_POINTS_M
    ]
    fired = fire_jobs([Job(engine=engine, settings=settings, case=c) for c in cases])
    lo_e, hi_e = cor_range(BAT_SPEED_MPS)
    rows = []
    for c, f in zip(cases, fired):
        lo, hi = (predict(replace(c, e=k)).v1_mps for k in (lo_e, hi_e))
        ok = f.outcome.physics == Physics.SOUND
        v1 = f.outcome.v1_mps
        rows.append(
            {
                "s_m": c.s_m,
                "v1_engine_mps": v1,
                "v1_ball_mps": compliant.predict(c, REALISTIC_BALL).v1_mps,
                "in_band": bool(ok and lo <= v1 <= hi),
            }
        )
    return rows


def sweet_rows(engine: str, ball: BallContact, x, points: int) -> pd.DataFrame:
    """The paper's swing along the R161 with the fitted ball against the realistic ball."""
    settings, e = rf.settings_at(engine, ball, x)
    swing = presets.PAPER_SWING
    firing = firings.Firing(
        bat=presets.R161,
        s_m=firings.grid(presets.R161, points),
        v0_mps=presets.PAPER_PITCH_MPS,
        u0_mps=swing.u0_mps,
        omega0_radps=swing.omega0_radps,
        e=e,
    )
    fired = fire_jobs(firing.jobs(engine, settings))
    ref = [compliant.predict(firing.case(s), REALISTIC_BALL).v1_mps for s in firing.s_m]
    # a contact that outlives the ball's stay on the cylinder (a soft one at the barrel's
    # very end) ends 'left_cylinder' mid-contact: no exit speed to compare
    kept = [f.outcome.physics == Physics.SOUND and f.outcome.ended == "separated" for f in fired]
    v1 = [f.outcome.v1_mps if k else np.nan for f, k in zip(fired, kept)]
    return pd.DataFrame(
        {
            "engine": engine,
            "model": ball.label,
            "s_m": firing.s_m,
            "physics": [f.outcome.physics.value for f in fired],
            "ended": [f.outcome.ended for f in fired],
            "v1_engine_mps": v1,
            "v1_ball_mps": ref,
            "error_mps": np.array(v1) - np.array(ref),
        }
    )


def sweet_spot_m(s: np.ndarray, v1: np.ndarray) -> float:
    """Where v1 peaks (m from the COM): the parabola through the best grid point and its
    neighbours (the grid's end where it peaks there; NaN without a finite v1)."""
    if not np.isfinite(v1).any():
        return float("nan")
    i = int(np.nanargmax(v1))
    if i == 0 or i == len(s) - 1 or not np.isfinite(v1[i - 1 : i + 2]).all():
        return float(s[i])
    a, b, _ = np.polyfit(s[i - 1 : i + 2], v1[i - 1 : i + 2], 2)
    return float(-b / (2 * a)) if a < 0 else float(s[i])


def fits(engine: str, ball: BallContact, quick: bool) -> list[rf.Fit]:
    """A model's fits: finite differences, and with the engine's derivative where it has one."""
    speeds = rf.QUICK_FIT_SPEEDS_MPS if quick else rf.FIT_SPEEDS_MPS
    cap = QUICK_EVALUATIONS if quick else rf.MAX_EVALUATIONS
    probe = rf.EngineProbe(engine, ball)
    out = [rf.fit(probe, speeds, ball.start, lasts=ball.lasts, max_evaluations=cap)]
    if probe.has_derivative():
        out.append(
            rf.fit(probe, speeds, ball.start, lasts=ball.lasts, gradient=True, max_evaluations=cap)
        )
    return out


def study(
    engine: str, ball: BallContact, quick: bool
) -> tuple[list[dict], list[dict], pd.DataFrame]:
    """One model of an engine: its fits, its speeds (fitted and held out), bat and sweet-spot
    rows."""
    fit_speeds = rf.QUICK_FIT_SPEEDS_MPS if quick else rf.FIT_SPEEDS_MPS
    held = rf.QUICK_HELD_OUT_SPEEDS_MPS if quick else rf.HELD_OUT_SPEEDS_MPS
    done = fits(engine, ball, quick)
    best = done[0]
    speeds = speed_rows(engine, ball, best.x, fit_speeds, held)
    sweet = sweet_rows(engine, ball, best.x, QUICK_SWEET_POINTS if quick else SWEET_POINTS)
    bat = bat_rows(engine, ball, best.x)
    ref_spot = sweet_spot_m(sweet.s_m.to_numpy(), sweet.v1_ball_mps.to_numpy())
    ranged = [r for r in speeds if BAR_LO_MPS <= r["speed_mps"] <= BAR_HI_MPS]
    mlb = next(r for r in speeds if r["speed_mps"] == SPEED_REF_MPS)
    summary = {
        "engine": engine,
        "model": ball.label,
        "speed_dependent": ball.speed_dependent,
        "knobs": json.dumps(dict(zip((k.label for k in ball.knobs), best.x))),
        "settings": realball_report.to_copy(engine, ball, best.x),
        "overrides": json.dumps(dict(ball.overrides)),
        "cor_85fps": mlb["cor_engine"],
        "in_mlb_band": abs(mlb["cor_engine"] - 0.546) <= 0.032 and mlb["sound"],
        "speeds_in_range": sum(r["in_range"] for r in ranged),
        "speeds_checked": len(ranged),
        "held_out_in_range": sum(r["in_range"] for r in speeds if r["role"] == "held_out"),
        "held_out": len(held),
        "contact_40_s": next(r["contact_s"] for r in speeds if r["speed_mps"] == 40.0),
        "bat_in_band": all(r["in_band"] for r in bat),
        "bat_v1_error_mps": max(abs(r["v1_engine_mps"] - r["v1_ball_mps"]) for r in bat),
        "sweet_spot_m": sweet_spot_m(sweet.s_m.to_numpy(), sweet.v1_engine_mps.to_numpy()),
        "sweet_spot_ball_m": ref_spot,
        "sweet_max_error_mps": float(np.nanmax(np.abs(sweet.error_mps))),
        "sweet_points_apart": int(np.isfinite(sweet.error_mps).sum()),
        "sweet_points": len(sweet),
    }
    if not ball.speed_dependent:
        summary |= single_speed(engine, ball)
    fit_rows = [
        summary
        | {
            "method": f.method,
            "fitted": json.dumps(dict(zip((k.label for k in ball.knobs), f.x))),
            "cost": f.cost,
            "impacts": f.impacts,
            "evaluations": f.evaluations,
            "fit_wall_s": f.wall_s,
            "message": f.message,
        }
        for f in done
    ]
    if len(done) > 1:
        fit_rows[1] |= agreement(engine, ball, done, fit_speeds)
    return speeds, fit_rows, sweet


def single_speed(engine: str, ball: BallContact) -> dict:
    """A constant-e engine's best single-speed setting (COR_LAW's e at 85 ft/s) and how far
    it lands from the law at the other speeds, fired."""
    speeds = (*rf.FIT_SPEEDS_MPS,)
    e = COR_LAW.cor(SPEED_REF_MPS)
    m = _fired_cor(engine, ball, [e], speeds)
    err = m.cor - np.array([COR_LAW.cor(v) for v in speeds])
    return {"single_speed_e": e, "single_speed_max_error": float(np.max(np.abs(err)))}


def agreement(engine: str, ball: BallContact, done: list[rf.Fit], speeds) -> dict:
    """The gradient fit against the finite-difference one: largest COR difference in half
    bands over the fit speeds, and whether they agree (AGREE_COR_BANDS, AGREE_COST_REL)."""
    fd, grad = (_fired_cor(engine, ball, f.x, speeds).cor for f in done[:2])
    bands = np.array([rf.half_band(v) for v in speeds])
    gap = float(np.max(np.abs(fd - grad) / bands))
    cost_gap = abs(done[1].cost - done[0].cost) / max(done[0].cost, 1e-12)
    return {
        "cor_gap_bands": gap,
        "agrees_with_fd": gap <= AGREE_COR_BANDS or cost_gap <= AGREE_COST_REL,
    }


def failed_rows(engine: str, ball: BallContact, err: BaseException) -> list[dict]:
    """A model whose study raised: one row that says so."""
    why = "".join(traceback.format_exception_only(err)).strip().splitlines()[-1][:200]
    return [{"engine": engine, "model": ball.label, "method": rf.FAILED, "message": why}]


def best_models(table: pd.DataFrame) -> dict[str, str]:
    """Per engine, the model whose finite-difference fit has the lowest cost."""
    fd = table[table.method == rf.METHODS[0]]
    return {e: t.model[t.cost.idxmin()] for e, t in fd.groupby("engine", sort=False)}


def with_best(df: pd.DataFrame, best: dict[str, str]) -> pd.DataFrame:
    """``df`` with a ``best`` column after ``model``: whether the row is its engine's best."""
    if df.empty:
        return df
    out = df.copy()
    flags = [best.get(e) == m for e, m in zip(out.engine, out.model)]
    out.insert(out.columns.get_loc("model") + 1, "best", flags)
    return out


def produce(args) -> tuple[dict[str, bytes], str]:
    """Every model of every chosen engine: the tables, the chart and a summary."""
    speed_all, fit_all, sweet_all = [], [], []
    for name in args.engine:
        for ball in adapters.record(name).balls:
            try:
                speeds, fit_rows, sweet = study(name, ball, args.quick)
            except Exception as err:  # noqa: BLE001 - a model's failure is a row, not a crash
                fit_all += failed_rows(name, ball, err)
                continue
            speed_all += speeds
            fit_all += fit_rows
            sweet_all.append(sweet)
    table = pd.DataFrame(fit_all)
    best = best_models(table) if "cost" in table else {}
    speeds = with_best(pd.DataFrame(speed_all), best)
    table = with_best(table, best)
    sweet = with_best(pd.concat(sweet_all), best) if sweet_all else pd.DataFrame()
    files = {
        "realball.csv": _csv(speeds),
        "realball_fits.csv": _csv(table),
        "realball_sweet.csv": _csv(sweet),
        "realball.md": realball_report.markdown(table).encode(),
    }
    if len(speeds):
        files["realball.png"] = realball_chart.render(speeds)
    return files, realball_report.summary_text(table)


def _csv(df: pd.DataFrame) -> bytes:
    return df.to_csv(index=False, float_format="%.6g", lineterminator="\n").encode()


COMMAND = Command(
    name="realball",
    doc=__doc__,
    produce=produce,
    runner=False,
    quick=f"three fit speeds, two held out, at most {QUICK_EVALUATIONS} evaluations a fit, "
    f"{QUICK_SWEET_POINTS} impact points",
)
main = COMMAND.main


if __name__ == "__main__":
    sys.exit(main())
