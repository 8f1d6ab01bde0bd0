"""The engines: the scene, each reference profile, what had to be fixed, the soft calibration.

The settings come from the baseline sweep's record of them (sweep JSON), the engines' defaults
from their records (``adapters.record(name).engine_defaults``, each pinned by
tests/test_engine_defaults.py). What an adapter had to work around is explained without the
measurements no result file holds: each adapter's module docstring has them.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

import adapters
from analytic import presets

from ..core import terms
from ..core.endings import Physics
from .base import (
    Results,
    alike,
    bullets,
    clauses,
    dist,
    engines_text,
    gnum,
    label,
    lead,
    md_table,
    names,
    num,
    precision,
    span,
    step,
)
from .data import need


def _record(engine: str):
    try:
        return adapters.record(engine)
    except ValueError:  # an engine no longer registered: its results stay readable
        return None


def _words(key: str, value) -> str:
    """A setting's value as the prose writes it, by its unit suffix (``_s``, ``_m``)."""
    if isinstance(value, bool) or not isinstance(value, int | float):
        return str(tuple(value) if isinstance(value, list) else value)
    if key.endswith("_s"):
        return step(value)
    if key.endswith("_m"):
        return dist(value)
    return gnum(value)


class _Values(dict):
    def __missing__(self, key: str) -> str:
        return "n/a"


def notes(engine: str, swing, field: str) -> str:
    """One of the engine's ``ReportNotes`` texts, filled (``adapters.ReportNotes``)."""
    rec = _record(engine)
    text = getattr(rec.look.notes, field, "") if rec and rec.look.notes else ""
    if not text:
        return ""
    summary = swing.summary(engine)
    values = _Values({k: _words(k, v) for k, v in summary["settings"].items()})
    values.update({f"default_{k}": _words(k, v) for k, v in rec.engine_defaults.items()})
    values.update(
        version=str(summary["engine_version"]),
        err_mps=num(swing.err(engine)),
        law_err_mps=num(swing.law_err(engine)),
    )
    return text.format_map(values)


def section(res: Results) -> str:
    (swing,) = need(res, "swing")
    bat, ball = presets.R161, presets.BASEBALL
    rows = []
    for e in swing.engines:
        rec = _record(e)
        rows.append(
            {
                "engine": f"{label(e)} (`{rec.install.package if rec else e}` "
                f"{swing.summary(e)['engine_version']})",
                "precision": precision(e),
                "reference profile": notes(e, swing, "profile") or "see the adapter",
                "what plays the role of e": (notes(e, swing, "restitution") or "see the adapter"),
            }
        )
    phase = {swing.setting(e, "contact_phase") for e in swing.engines}
    (default,) = need(res, "default")
    mid = {default.setting(e, "contact_phase") for e in default.engines}
    scene = lead(
        "Same scene everywhere:",
        [
            f"a capsule bat ({bat.length_m:g} m long, radius {bat.radius_m:g} m) whose mass "
            f"({bat.mass_kg:g} kg), COM and inertia are set, never derived from density",
            f"a sphere ball ({ball.mass_kg:g} kg, radius {ball.radius_m:g} m)",
            "no gravity, no friction, motion in the x-y plane",
            "each adapter reads back the mass properties its engine holds and refuses to fire if "
            "they differ",
            "the bodies are placed from the analytic free motion run backwards: the contact is "
            "seen "
            "on a step boundary at exactly the intended point with the bat aligned (`contact_phase "
            f"= {names(f'{p:g}' for p in sorted(phase))}`)",
            f"the default profiles use `contact_phase = {names(f'{p:g}' for p in sorted(mid))}`, a "
            "mid-step contact as an unaligned simulation meets it",
        ],
    )
    return "\n\n".join(
        [
            scene,
            f"Versions and settings as the baseline sweep recorded them (`{swing.stem}.json`):",
            md_table(pd.DataFrame(rows)),
            "What each adapter had to handle (each module's docstring has the measurements):",
            bullets(fixes(swing)),
            pinned(swing),
            soft(res),
        ]
    )


def fixes(swing) -> list[str]:
    """What each adapter had to handle, in its record's words, a clause a line (engines with the
    same words together); the float32 engines' tolerances."""
    said = alike((e, text) for e in swing.engines if (text := notes(e, swing, "handled")))
    out = [lead(f"**{engines_text(who)}**:", clauses(text)) for who, text in said]
    if any(precision(e) == "float32" for e in swing.engines):
        out += [
            lead(
                "The float32 engines need the harness's tolerances in their precision:",
                [
                    f"the mass read-back ({terms.MASS_CHECK_ULPS} ulps)",
                    f"the energy-gain verdict ({terms.ENERGY_GAIN_ULPS} ulps)",
                    "the integrator checks",
                ],
            ),
            "Engines with a speculative contact declare its margin (`speculative_margin_m`): "
            "the judge then allows the contact a whole step early, and the stability theory "
            "catches every phase below r_ball + r_bat + margin.",
        ]
    return out


def pinned(swing) -> str:
    """Where the engine defaults quoted come from, in each record's words."""
    how = alike((e, text) for e in swing.engines if (text := notes(e, swing, "defaults")))
    return lead(
        "Every engine default quoted here is in the engine's record (`engine_defaults`) "
        "and pinned by a test (`tests/test_engine_defaults.py`): read back from a fresh "
        "engine where it reports it, measured where it does not" + (":" if how else "."),
        [f"**{engines_text(who)}**: {text}" for who, text in how],
    )


def soft(res: Results) -> str:
    """The soft contacts' calibration: what is measured, said once, and a row per engine."""
    cal = res.csv("soft_calibration.csv")
    conv = res.csv("convergence.csv")
    rows = []
    for e, c in cal.groupby("engine"):
        half = c[np.isclose(c.e_target, 0.5)]
        by_dt = half.groupby("dt_s").residual.mean().sort_index(ascending=False)
        order = np.polyfit(np.log10(by_dt.index), np.log10(by_dt.abs().to_numpy()), 1)[0]
        spread = c.groupby(["dt_s", "e_target"]).residual.agg(lambda r: r.max() - r.min()).max()
        gained = int((c.physics == Physics.ENERGY_GAINED).sum())
        softs = conv[(conv.engine == e) & conv.family.str.startswith("soft")]
        rows.append(
            f"| {label(e)} | {float((c.w_dt / c.dt_s).median()):g} | "
            f"{' / '.join(num(r) for r in by_dt)} at {' / '.join(gnum(d) for d in by_dt.index)} "
            f"| {order:.2f} | {num(spread)} | {c.contact_duration_s.median() * 1e3:.1f} | "
            f"{span(softs.err_at_dt_min.min(), softs.err_at_dt_min.max())} | {gained} of "
            f"{int(np.isclose(c.e_target, 1).sum())} |"
        )
    intro = lead(
        "A declared soft contact (the `soft` mode: `solref = (-w^2, -2 zeta w)`, zeta from the "
        "closed-form restitution of a spring-damper released at zero force) is calibrated by "
        "`python -m experiments.calibrate_soft` (`results/soft_calibration.csv`). Per engine:",
        [
            "the residual e_measured - e for e = 0.5 at each step, and its order in w dt",
            f"its spread over impact speeds ({span(cal.v0_mps.min(), cal.v0_mps.max(), gnum)} "
            f"m/s) and bat masses ({span(cal.bat_mass_kg.min(), cal.bat_mass_kg.max(), gnum)} "
            "kg)",
            "the contact's length",
            "the relative error an off-centre impact keeps at the smallest step, the bat turning "
            "during the contact (`convergence.csv`: see Speed vs accuracy)",
            "the e = 1 calibration impacts that gained energy",
        ],
    )
    return (
        intro + "\n\n"
        "| engine | w (rad/s) | residual at dt (s) | order | spread | contact (ms) | "
        "error at the smallest step | e = 1 `energy_gained` |\n|---|---|---|---|---|---|---|---|\n"
        + "\n".join(rows)
    )
