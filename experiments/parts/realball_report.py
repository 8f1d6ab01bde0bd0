"""The words of ``experiments.realball``: the settings to copy for a fitted ball model, the
markdown table (each engine's best model, then its others) and the one-line summaries."""

from __future__ import annotations

import pandas as pd

from adapters import BallContact

from . import realball_fit as rf


def to_copy(engine: str, ball: BallContact, x) -> str:
    """The fitted ball as the settings a user writes (``adapters.settings_for`` keywords, the
    impact's ``e`` beside them), three significant digits: the overrides, the step and every
    field a knob moved."""
    settings, e = rf.settings_at(engine, ball, x)
    fields = dict.fromkeys([*dict(ball.overrides), "dt_s"])
    fields.update(dict.fromkeys(k.setting for k in ball.knobs if k.setting != rf.RESTITUTION_KNOB))
    parts = [f"{f}={_short(getattr(settings, f))}" for f in fields]
    if any(k.setting == rf.RESTITUTION_KNOB for k in ball.knobs):
        parts.append(f"e={_short(e)}")
    return ", ".join(parts)


def _short(v) -> str:
    if isinstance(v, tuple):
        return "(" + ", ".join(_short(a) for a in v) + ")"
    return f"{v:.3g}" if isinstance(v, float) else repr(v)


def _in_range(r: dict) -> str:
    return (
        f"{r['speeds_in_range']}/{r['speeds_checked']} ({r['held_out_in_range']}/{r['held_out']})"
    )


def markdown(table: pd.DataFrame) -> str:
    """The settings to copy per engine (its best model: the lowest fit cost), with how close
    each gets; then every other model with its cost and speeds in range (realball.md)."""
    lines = [
        "# A baseball in your engine",
        "",
        "Written by `python -m experiments.realball`. Each engine's ball contact fitted to a "
        "wall's COR_LAW at 10-60 m/s and 0.7 ms at 40 m/s (`analytic.ball`); in range: within "
        "COR_LAWS' range at the speeds from 15 to 55 m/s (held out: speeds the fit did not "
        "use); sweet spot of the paper's swing, cm from the COM (the realistic ball's beside). "
        "Where an engine offers several contact models each is fitted; the one with the lowest "
        "fit cost is listed here, the others below.",
        "",
        "| engine | model | settings to copy | COR at 85 ft/s | in range (held out) | contact "
        "at 40 m/s | sweet spot (ball) | cost |",
        "|---|---|---|---|---|---|---|---|",
    ]
    rows = table.to_dict("records")
    fd = [r for r in rows if r.get("method") == rf.METHODS[0]]
    for r in rows:
        if r.get("method") == rf.FAILED:
            lines.append(f"| {r['engine']} | {r['model']} | error: {r['message']} | | | | | |")
    for r in (r for r in fd if r["best"]):
        band = "" if r["in_mlb_band"] else " (out of MLB's band)"
        lines.append(
            f"| {r['engine']} | {r['model']} | `{r['settings']}` | {r['cor_85fps']:.3f}{band} "
            f"| {_in_range(r)} | {1e3 * r['contact_40_s']:.2f} ms | "
            f"{100 * r['sweet_spot_m']:.1f} ({100 * r['sweet_spot_ball_m']:.1f}) | "
            f"{r['cost']:.3g} |"
        )
    others = [r for r in fd if not r["best"]]
    if others:
        lines += [
            "",
            "The other models (not the best fit):",
            "",
            "| engine | model | settings | COR at 85 ft/s | in range (held out) | cost |",
            "|---|---|---|---|---|---|",
        ]
        lines += [
            f"| {r['engine']} | {r['model']} | `{r['settings']}` | {r['cor_85fps']:.3f} | "
            f"{_in_range(r)} | {r['cost']:.3g} |"
            for r in others
        ]
    return "\n".join(lines) + "\n"


def summary_text(table: pd.DataFrame) -> str:
    """One line per engine, model and fit."""
    lines = []
    for r in table.to_dict("records"):
        if r.get("method") == rf.FAILED:
            lines.append(f"{r['engine']} ({r['model']}): error: {r['message']}")
            continue
        lines.append(
            f"{r['engine']} ({r['model']}{', best' if r['best'] else ''}; {r['method']}): "
            f"{r['fitted']}; COR at 85 ft/s "
            f"{r['cor_85fps']:.3f} ({'in' if r['in_mlb_band'] else 'OUT of'} MLB's band), "
            f"in range at {r['speeds_in_range']}/{r['speeds_checked']} speeds "
            f"(held out {r['held_out_in_range']}/{r['held_out']}), contact "
            f"{1e3 * r['contact_40_s']:.2f} ms at 40 m/s, cost {r['cost']:.3g} "
            f"({r['impacts']} impacts, {r['fit_wall_s']:.1f} s), sweet spot "
            f"{100 * r['sweet_spot_m']:.1f} cm (ball {100 * r['sweet_spot_ball_m']:.1f})"
        )
    return "\n".join(lines)
