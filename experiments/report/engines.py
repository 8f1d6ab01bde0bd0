"""The engines: the scene, each reference profile, what had to be fixed, the soft calibration.

The settings come from the baseline sweep's record of them (sweep JSON), the engines' defaults
from their records (``adapters.record(name).engine_defaults``, each pinned by
tests/test_engine_defaults.py). What an adapter had to work around is explained without the
measurements no result file holds: each adapter's module docstring has them.
"""

from __future__ import annotations

import math

import numpy as np
import pandas as pd

import adapters
from analytic import presets

from ..core import judge
from .base import Results, bullets, dist, gnum, label, md_table, names, num, precision, span, step
from .data import need


def _defaults(engine: str) -> dict:
    try:
        return dict(adapters.record(engine).engine_defaults)
    except ValueError:
        return {}


def _package(engine: str) -> str:
    try:
        return adapters.record(engine).package
    except ValueError:
        return engine


def _profile(e: str, st: dict, d: dict) -> tuple[str, str]:
    """(the reference profile, what plays the role of e) in words, for a known engine."""
    dt = f"dt = {step(st['dt_s'])}"
    nan = math.nan
    if e == "pymunk":
        return (f"{dt}, Chipmunk's own solver values (exact for one contact)",
                "product of the shapes' `elasticity` (bat 1, ball e)")
    if e == "pybullet":
        return (f"{dt}, `contactERP = erp = 0`, `contactSlop = 0`, no restitution threshold, "
                "no damping", "product of both bodies' `restitution`; 0 below "
                "`restitutionVelocityThreshold`")
    if e == "mujoco":
        return (f"{dt}, {st.get('integrator')}, `impulse` contact: `solref = (0, -(1+e)/dt)`, "
                "constant impedance, `diagexact`", "none: mapped by the adapter (`impulse`, or "
                "`soft` spring-damper calibrated for e)")
    if e == "drake":
        return (f"{st.get('solver')} plant, RK3 with error control at "
                f"{gnum(st.get('accuracy', nan))}, read every {step(st['dt_s'])}; "
                f"{st.get('contact_model')} contact k = "
                f"{gnum(st.get('point_stiffness_npm', nan))} N/m",
                "none: Hunt-Crossley dissipation d chosen so that a "
                f"{gnum(st.get('restitution_speed_mps', nan))} m/s impact bounces with e; its e "
                "then falls with speed; judged against its own law")
    if e == "physx":
        return (f"{dt}, TGS, bounce threshold 0, spin cap lifted "
                f"({gnum(d.get('max_angular_velocity_radps', nan))} rad/s by default), no "
                "sleeping", "mean of both bodies' restitution (both set to e); 0 below "
                f"`bounce_threshold` ({gnum(d.get('bounce_threshold_mps', nan))} m/s)")
    if e == "rapier":
        return (f"{dt}, {st.get('solver_iterations')} substep, prediction distance "
                f"{dist(st.get('prediction_distance_m', nan))}, contact recycling off, speed "
                f"caps lifted, hinge a {st.get('hinge', '')} joint", "mean of both colliders' "
                "restitution (the default combine rule; both set to e); no threshold")
    if e == "box2d":
        return (f"{dt}, sub-steps of at most {step(st.get('max_sub_step_s') or nan)}, "
                "restitution threshold 0, speed clamp lifted", "max of the two shapes' "
                "restitution (bat 0, ball e); 0 below `restitutionThreshold` "
                f"({gnum(d.get('restitution_threshold_mps', nan))} m/s)")
    return dt, "see the adapter"


def section(res: Results) -> str:
    (swing,) = need(res, "swing")
    bat, ball = presets.R161, presets.BASEBALL
    rows = []
    for e in swing.engines:
        st = swing.summary(e)["settings"]
        prof, rule = _profile(e, st, _defaults(e))
        rows.append({"engine": f"{label(e)} (`{_package(e)}` "
                               f"{swing.summary(e)['engine_version']})",
                     "precision": precision(e), "reference profile": prof,
                     "what plays the role of e": rule})
    phase = {swing.setting(e, "contact_phase") for e in swing.engines}
    (default,) = need(res, "default")
    mid = {default.setting(e, "contact_phase") for e in default.engines}
    scene = (
        f"Same scene everywhere: a capsule bat ({bat.length_m:g} m long, radius "
        f"{bat.radius_m:g} m) whose mass ({bat.mass_kg:g} kg), COM and inertia are set (never "
        f"derived from density), a sphere ball ({ball.mass_kg:g} kg, radius {ball.radius_m:g} m),"
        " no gravity, no friction, motion in the x-y plane. Each adapter reads back the mass "
        "properties its engine holds and refuses to fire if they differ. The bodies are placed "
        "from the analytic free motion run backwards, so that the contact is seen on a step "
        "boundary at exactly the intended point with the bat aligned (`contact_phase = "
        f"{names(f'{p:g}' for p in sorted(phase))}`); the default profiles use `contact_phase = "
        f"{names(f'{p:g}' for p in sorted(mid))}`, a mid-step contact as an unaligned simulation "
        "meets it. Versions and settings as the baseline sweep recorded them "
        f"(`{swing.stem}.json`):")
    return "\n\n".join([scene, md_table(pd.DataFrame(rows)),
                        "What each adapter had to handle (each module's docstring has the "
                        "measurements):", bullets(fixes(res)), pinned(), soft(res)])


def fixes(res: Results) -> list[str]:
    (swing,) = need(res, "swing")
    conv = res.csv("convergence.csv")
    out = []
    for e in swing.compliant:
        st, p = swing.summary(e)["settings"], conv[conv.engine == e]
        law = p[p.family.str.startswith("discrete") & p.p_law.notna()].p_law
        out.append(
            f"**{label(e)}** has no coefficient of restitution: its point contact is "
            "Hunt-Crossley, F = k x (1 + d x'), whose e falls with the impact speed (d set for e "
            f"at {st.get('restitution_speed_mps', math.nan):g} m/s), so against rigid theory it "
            f"is up to {num(swing.err(e))} m/s off on the paper's swing by design; against its "
            "own law (`analytic.compliant.HuntCrossley`, exponent 1) the reference is within "
            f"{num(swing.law_err(e))} m/s. Every discrete approximation is about first order "
            f"against that law (fitted p_law {span(law.min(), law.max(), lambda v: f'{v:.2f}')} "
            "in `convergence.csv`); SAP replaces d by a linear damper (the adapter sets its "
            "relaxation time for e and judges it against `LinearSpringDamper`); hydroelastic "
            "contact states no closed law here (`unjudged`). The bat hangs on a planar joint "
            "chain whose pivot frame moves at run time, so the hands' hinge is a lock on that "
            "chain. A small e is floored (`E_FLOOR`): a Hunt-Crossley contact lets go with the "
            "overlap still open and cannot separate faster than 1/d (drake#19320), so a "
            "near-plastic ball is caught again and again.")
    known = {"physx": _physx, "rapier": _rapier, "box2d": _box2d}
    out += [known[e](swing, e) for e in swing.rigid if e in known]
    if any(precision(e) == "float32" for e in swing.engines):
        out.append(
            "The float32 engines need the harness's tolerances in their precision: the mass "
            f"read-back ({judge.MASS_CHECK_ULPS} ulps), the energy-gain verdict "
            f"({judge.ENERGY_GAIN_ULPS} ulps), the integrator checks. Engines with a "
            "speculative contact declare its margin (`speculative_margin_m`): the judge then "
            "allows the contact a whole step early, and the stability theory catches every "
            "phase below r_ball + r_bat + margin.")
    return out


def _physx(swing, e: str) -> str:
    d = _defaults(e)
    return (f"**{label(e)}**: restitution is dropped below the "
            f"{d.get('bounce_threshold_mps', math.nan):g} m/s bounce threshold (PhysX #351); the "
            f"default spin cap of {d.get('max_angular_velocity_radps', math.nan):g} rad/s clips a "
            "bat hit at the barrel after a fast swing; PGS splits an impact that falls late in a "
            "step over two steps, losing part of the rebound, where TGS is exact; contacts are "
            f"made `contact_offset` ({dist(d.get('contact_offset_m', math.nan))} per shape) ahead "
            "and solved with the step's starting geometry (a speculative contact, see the judge); "
            "SAPIEN's scene CCD flag does nothing without the per-body flag it does not expose.")


def _rapier(swing, e: str) -> str:
    d = _defaults(e)
    dt = d.get("dt_s", math.nan)
    return (f"**{label(e)}**: speculative contacts (prediction distance "
            f"{dist(d.get('prediction_distance_m', math.nan))} by default) solve the impact from "
            f"the step start's geometry (with "
            f"{dist(swing.setting(e, 'prediction_distance_m'))}, the reference is "
            f"{num(swing.err(e))} m/s off on the swing); contact recycling keeps stale points; a "
            "free body turns 2 atan(omega dt/2) per step, not omega dt; angular speed is clamped "
            "to (pi/4)/dt unless fast rotation is allowed (at its default "
            f"{step(dt)}: {math.pi / 4 / dt:.2f} rad/s); CCD between two \"bullets\" never "
            "sweeps (rapier#984); the relax pass costs an impulse joint first-order spin (hence "
            f"the multibody hinge). Restitution works in {swing.summary(e)['engine_version']} "
            "(rapier#974's loss is gone).")


def _box2d(swing, e: str) -> str:
    d = _defaults(e)
    return (f"**{label(e)}**: restitution is the max of the two values and dropped below "
            f"{d.get('restitution_threshold_mps', math.nan):g} m/s; the speculative margin "
            "(compile-time) solves an impact with the step start's normal, an error first order "
            f"in dt (hence the {step(swing.setting(e, 'dt_s'))} reference); each sub-step turns a "
            "body by atan(omega h); `b2MakeRot` approximates cos/sin (the adapter builds "
            "rotations itself); its joints are soft (fixed in pyb2d3), so the hinge drifts at "
            "first order; float32 positions lose a long motion split into many tiny sub-steps; "
            "pyb2d3 exposes no per-body contact data, so the adapter calls a step a contact "
            "when the ball's velocity changed (only the bat acts on it).")


def pinned() -> str:
    pm, pb, mj = _defaults("pymunk"), _defaults("pybullet"), _defaults("mujoco")
    return (
        "Every engine default quoted here is in the engine's record (`engine_defaults`) and "
        "pinned by a test (`tests/test_engine_defaults.py`): read back from a fresh engine where "
        "it reports it (pymunk's slop and biases, which Chipmunk computes in single precision, "
        f"e.g. a bias of {pm.get('collision_bias', math.nan):.10f}, not 0.9^60 = "
        f"{0.9 ** 60:.10f}; MuJoCo's solref {tuple(mj.get('solref', ()))}, solimp, iterations, "
        f"step; PyBullet's {pb.get('solver_iterations')} solver iterations and "
        f"{step(pb.get('dt_s', math.nan))} step), measured where it does not (PyBullet's "
        f"contactERP {pb.get('contact_erp')} and contactSlop {pb.get('contact_slop')} m: set "
        "explicitly, they reproduce the default solver's impacts bit for bit, and another value "
        "changes them).")


def soft(res: Results) -> str:
    cal = res.csv("soft_calibration.csv")
    conv = res.csv("convergence.csv")
    parts = []
    for e, c in cal.groupby("engine"):
        half = c[np.isclose(c.e_target, 0.5)]
        by_dt = half.groupby("dt_s").residual.mean().sort_index(ascending=False)
        w = float((c.w_dt / c.dt_s).median())
        order = np.polyfit(np.log10(by_dt.index), np.log10(by_dt.abs().to_numpy()), 1)[0]
        spread = c.groupby(["dt_s", "e_target"]).residual.agg(lambda r: r.max() - r.min()).max()
        gained = c[c.status == "energy_gained"]
        softs = conv[(conv.engine == e) & conv.family.str.startswith("soft")]
        parts.append(
            f"{label(e)} `soft` mode (`solref = (-w^2, -2 zeta w)`, zeta from the closed-form "
            "restitution of a spring-damper released at zero force): "
            "`python -m experiments.calibrate_soft` measures the residual e_measured - e at "
            f"w = {w:g} rad/s as {names(num(r) for r in by_dt)} for e = 0.5 at dt = "
            f"{names(gnum(dt) for dt in by_dt.index)} s (order {order:.2f} in w dt), "
            f"independent of impact speed ({span(c.v0_mps.min(), c.v0_mps.max(), gnum)} m/s) and "
            f"bat mass ({span(c.bat_mass_kg.min(), c.bat_mass_kg.max(), gnum)} kg) to "
            f"{num(spread)} (`results/soft_calibration.csv`; the command covers every engine "
            "whose record declares a soft contact). The contact lasts about "
            f"{c.contact_duration_s.median() * 1e3:.1f} ms; on an off-centre impact the bat turns "
            "meanwhile, which leaves relative errors of "
            f"{span(softs.err_at_dt_min.min(), softs.err_at_dt_min.max())} at the smallest step "
            "(`convergence.csv`: see Speed vs accuracy)"
            + (f" and, at e = 1, a small energy gain ({len(gained)} of its "
               f"{int(np.isclose(c.e_target, 1).sum())} e = 1 calibration impacts are "
               "`energy_gained`)" if len(gained) else "") + ".")
    return "\n\n".join(parts)
