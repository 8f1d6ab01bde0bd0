"""``check_engine``: every conformance check of the test suite, for any registered engine.

    from experiments.core import check_engine
    report = check_engine("myengine")      # registered: built in, an entry point, or register()
    print(report)                          # one line per check: ok / FAILED and what it saw
    report.raise_if_failed()

Checks against closed form only (each engine within its bound of theory implies any two within
twice that of each other). Each states the equation it checks; every tolerance comes from
``judge``. An engine whose reference contact is a rigid impulse is held to rigid theory; one
whose contact converges to a continuous law (``ErrorModel.contact_law``) to that law.
"""

from __future__ import annotations

import dataclasses
import math
import time
from collections.abc import Callable
from dataclasses import dataclass, replace

import numpy as np
from scipy import optimize

import adapters
from adapters import ContactReference, Scene, clock
from analytic import ImpactCase, center_of_percussion, cork, predict, presets
from analytic.dynamics import HingedSwing

from . import friction_judge, judge
from .check_report import CheckFailed, CheckReport, CheckResult
from .endings import Physics
from .fire import Job, fire_jobs, guarded
from .hosting import Hosted, SceneMismatch, check_mass_properties, hosted
from .judge import Status
from .tables import table

R161, BALL = presets.R161, presets.BASEBALL
S_GRID = tuple(float(s) for s in np.linspace(-0.2, 0.25, 10))
SWING = dict(v0_mps=46.9, u0_mps=17.87, omega0_radps=32.0)
#: Outcomes of an impact with no measurement (nothing to compare, bit for bit).
UNMEASURED = (Physics.ERROR, Physics.TIMEOUT, Physics.UNSUPPORTED)
#: The longest a check may take (s): minutes for the slowest engine's (a batched one compiling
#: on a CPU); a hang within an impact is a timeout sooner (``fire.guarded``).
CHECK_LIMIT_S = 600.0


@dataclass(frozen=True, kw_only=True)
class Ctx:
    """What a check needs: the engine's name, record and reference settings."""

    name: str
    record: adapters.EngineRecord
    settings: adapters.Settings

    @property
    def rigid(self) -> bool:
        return adapters.contact_reference(self.name) is ContactReference.RIGID_IMPULSE

    def fire(self, cases, settings: adapters.Settings | None = None, swing=None):
        st = settings or self.settings
        return [
            f.outcome
            for f in fire_jobs(
                [Job(engine=self.name, settings=st, case=c, swing=swing) for c in cases]
            )
        ]


def _expect(ok: bool, message: str) -> None:
    if not ok:
        raise CheckFailed(message)


def _matches_theory(ctx: Ctx, cases, fields=("v1_mps", "u1_mps", "omega1_radps")) -> float:
    """Fire ``cases``: each must be sound and every field within ``judge.output_tolerance`` of the
    single impulse (analytic.predict). Returns the largest error in units of its tolerance."""
    worst = 0.0
    for case, out in zip(cases, ctx.fire(cases)):
        _expect(
            out.sound,
            f"s = {case.s_m:.3f} m, e = {case.e}: {out.physics.value} ({out.ended})",
        )
        ref = predict(case)
        for field in fields:
            allowed = judge.output_tolerance(case, ctx.settings, ctx.record.errors, field)
            err = abs(getattr(out, field) - getattr(ref, field))
            _expect(
                err <= allowed,
                f"{field} at s = {case.s_m:.3f} m: {getattr(out, field)!r} "
                f"vs theory {getattr(ref, field)!r} (|diff| {err:.3g} > "
                f"allowed {allowed:.3g})",
            )
            worst = max(worst, err / allowed)
    return worst


def mass_read_back(ctx: Ctx) -> str:
    """The engine holds the mass, COM and inertia each bat was built with, and reads back a
    changed bat as different (the read-back is the engine's, not the scene echoed)."""
    host = hosted(ctx.name, ctx.settings)
    for bat in (R161, cork.corked_bat(R161), presets.EASTON31):
        host.batch(Scene(bat=bat, ball=BALL, e=0.5), 1)  # builds and checks
    got = host.adapter.mass_properties()
    for field, changed in (
        ("bat_mass_kg", dict(mass_kg=0.9)),
        ("bat_com_from_knob_m", dict(com_from_knob_m=0.5)),
        ("bat_inertia_kgm2", dict(inertia_cm_kgm2=0.04)),
    ):
        try:
            check_mass_properties(
                ctx.name,
                got,
                Scene(bat=replace(presets.EASTON31, **changed), ball=BALL, e=0.5),
                ctx.record.eps,
            )
        except SceneMismatch as err:
            _expect(field in str(err), f"a changed {field} was reported as {err}")
            continue
        raise CheckFailed(f"a bat with another {field} reads back as the one built")
    return f"3 bats within {judge.mass_allowance(ctx.record.eps):.1g} relative"


def restitution(ctx: Ctx) -> str:
    """Central impacts (s = 0, no turn) separate at e times the approach: (v1 - u1)/v0 = e
    (at e = 0 ball and bat may move on together, to rounding: the episode then ends at the
    budget, no_separation: 2 ms of it, as long as 0.1 s would say); within
    ``judge.precision_rel``."""
    cases = [
        ImpactCase(bat=R161, ball=BALL, s_m=0.0, v0_mps=40.0, e=e) for e in (0.0, 0.3, 0.5, 1.0)
    ]
    tol = judge.precision_rel(ctx.settings, ctx.record.errors, cases[0])
    short = replace(ctx.settings, max_contact_s=2e-3)
    for case, out in zip(cases, ctx.fire(cases, settings=short)):
        e = (out.v1_mps - out.u1_mps) / case.v0_mps
        sound = (Physics.SOUND, Physics.NO_SEPARATION) if case.e == 0.0 else (Physics.SOUND,)
        _expect(
            out.physics in sound and abs(e - case.e) <= tol,
            f"e = {case.e}: measured {e!r} ({out.physics.value}), allowed +-{tol:.2g}",
        )
    return f"e = 0, 0.3, 0.5, 1 within {tol:.1g}"


def still_bat(ctx: Ctx) -> str:
    """A still bat across the barrel, e = 0.5 and 1: P = (1+e) v0 / (1/m + 1/M + s^2/J)."""
    worst = _matches_theory(
        ctx,
        [
            ImpactCase(bat=R161, ball=BALL, s_m=s, v0_mps=40.0, e=e)
            for e in (0.5, 1.0)
            for s in S_GRID
        ],
    )
    return f"20 impacts, worst {worst:.2g} of the tolerance"


def energy_at_e1(ctx: Ctx) -> str:
    """e = 1 on the paper's swing: kinetic energy after = before, to 10 ``judge.precision_rel``
    (rounding, and a mapping's known bias)."""
    case = ImpactCase(bat=R161, ball=BALL, s_m=0.15, e=1.0, **SWING)
    out = ctx.fire([case])[0]
    rel = abs(out.ke_after_j / out.ke_before_j - 1.0)
    allowed = max(
        10 * judge.precision_rel(ctx.settings, ctx.record.errors, case),
        judge.energy_allowance(ctx.record.errors, ctx.settings),
    )
    _expect(rel <= allowed, f"KE changed by {rel:.3g} relative (allowed {allowed:.2g})")
    return f"|dKE|/KE = {rel:.2g}"


def swinging_bat(ctx: Ctx) -> str:
    """The paper's swing across the barrel: v1 = q v0 + (1+q)(u0 + omega0 s)."""
    worst = _matches_theory(
        ctx, [ImpactCase(bat=R161, ball=BALL, s_m=s, e=0.5, **SWING) for s in S_GRID]
    )
    return f"10 impacts, worst {worst:.2g} of the tolerance"


#: Worlds in ``large_batch``: MJX's CPU step never returned from 512 (an XLA scheduler bug).
LARGE_BATCH = 512


def large_batch(ctx: Ctx) -> str:
    """A batched engine fires 512 of the paper's swings across the barrel as one batch, each
    as the answer that applies says: the single impulse v1 = q v0 + (1+q)(u0 + omega0 s)
    for a rigid contact, its own law (``judge.soft_judgement``) for a compliant one."""
    cases = [
        ImpactCase(bat=R161, ball=BALL, s_m=float(s), e=0.5, **SWING)
        for s in np.linspace(S_GRID[0], S_GRID[-1], LARGE_BATCH)
    ]
    if ctx.rigid:
        worst = _matches_theory(ctx, cases, fields=("v1_mps",))
    else:
        worst = 0.0
        for case, out in zip(cases, ctx.fire(cases)):
            want, allowed = judge.soft_judgement(case, out)
            _expect(
                out.sound and not abs(out.v1_mps - want) > allowed,
                f"s = {case.s_m:.3f}: {out.physics.value}, v1 {out.v1_mps!r} vs law {want!r}",
            )
            worst = max(worst, abs(out.v1_mps - want) / allowed if allowed > 0 else 0.0)
    return f"{LARGE_BATCH} impacts in one batch, worst {worst:.2g} of the tolerance"


def corked_bat(ctx: Ctx) -> str:
    """A corked bat's own M, x_cm and J go through the same impulse formula."""
    bat = cork.corked_bat(R161)
    worst = _matches_theory(
        ctx,
        [
            ImpactCase(bat=bat, ball=BALL, s_m=float(s), e=0.5, **SWING)
            for s in np.linspace(bat.s_min_m + 0.3, bat.s_max_m, 5)
        ],
    )
    return f"5 impacts, worst {worst:.2g} of the tolerance"


def oblique(ctx: Ctx) -> str:
    """Frictionless oblique impacts: normal parts as in a normal impact, tangential velocities
    kept (up to the impulse leaked through the normal the turning bat tilted)."""
    cases = [
        ImpactCase(bat=R161, ball=BALL, s_m=s, e=0.5, theta_rad=t, phi_rad=p, **SWING)
        for t, p in ((0.3, 0.0), (-0.4, 0.25), (0.6, -0.5))
        for s in (-0.1, 0.05, 0.2)
    ]
    worst = _matches_theory(ctx, cases)
    for case, out in zip(cases, ctx.fire(cases)):
        ref = predict(case)
        for field, mass in (("v1_t_mps", BALL.mass_kg), ("u1_t_mps", R161.mass_kg)):
            allowed = friction_judge.tangential_tolerance(
                case, ctx.settings, ctx.record.errors, ref.impulse_ns, mass
            )
            err = abs(getattr(out, field) - getattr(ref, field))
            _expect(
                err <= allowed,
                f"{field} at theta {case.theta_rad}: |diff| {err:.3g} > {allowed:.3g}",
            )
    return f"9 impacts, worst {worst:.2g} of the tolerance"


def cop_located(ctx: Ctx) -> str:
    """s_cop = J/(M d) is where the free bat's hand point (0.1 m from the knob) keeps its
    velocity: found from engine data by Brent's method (xtol 1e-9 m), within 1 um of theory
    (plus the engine's collision bias, ``ErrorModel.collision_slide_m``)."""

    def hand(s: float) -> float:
        return ctx.fire(
            [ImpactCase(bat=R161, ball=BALL, s_m=s, v0_mps=40.0, e=0.5, hands_from_knob_m=0.1)]
        )[0].hand_dv_mps

    root = optimize.brentq(hand, 0.0, 0.2, xtol=1e-9)
    want = center_of_percussion(R161, 0.1)
    allowed = 1e-6 + ctx.record.errors.collision_slide_m(ctx.settings, R161)
    _expect(abs(root - want) <= allowed, f"COP at {root:.9f} m, theory {want:.9f} m")
    return f"{(root - want) * 1e9:+.2g} nm from theory"


def tunnelling_bound(ctx: Ctx) -> str:
    """At 1 ms and 100 m/s (v dt = 1.5 R) a contact phase is caught iff theory says so
    (``judge.caught_in_theory``: seen shallower than R = r_ball + r_bat, or within the engine's
    speculative margin); at 1/60 s mid-step the ball tunnels. Never ok with a wrong answer.
    The phases are fired together (a batched engine: as one batch of 8 placements)."""
    reach = R161.radius_m + BALL.radius_m
    phases = judge.phases(8)
    case = ImpactCase(bat=R161, ball=BALL, s_m=0.1, v0_mps=100.0, e=1.0)
    each = [replace(ctx.settings, dt_s=1e-3, contact_phase=float(p)) for p in phases]
    fired = fire_jobs([Job(engine=ctx.name, settings=st, case=case) for st in each])
    for phase, st, f in zip(phases, each, fired):
        out = f.outcome
        want = bool(
            judge.caught_in_theory(
                100.0, 1e-3, phase, reach, st.overlap_m, ctx.record.errors.speculative_margin_m(st)
            )
        )
        # caught: any outcome but a miss (whether its energy is right is energy_at_e1's)
        caught = out.physics not in (Physics.TUNNELLED, Physics.NO_CONTACT)
        _expect(
            caught == want,
            f"phase {phase:.3f}: {out.physics.value}, theory says {'caught' if want else 'missed'}",
        )
    coarse = replace(ctx.settings, dt_s=1 / 60, contact_phase=0.5)
    out = ctx.fire([ImpactCase(bat=R161, ball=BALL, s_m=0.1, e=0.5, **SWING)], coarse)[0]
    _expect(out.physics is Physics.TUNNELLED, f"1/60 s mid-step: {out.physics.value}")
    return "8 phases as theory; 1/60 s tunnels"


def stateless(ctx: Ctx) -> str:
    """After other impacts, on other bats and e (and a swing, if the engine drives the bat),
    the same case gives the same bits on a used adapter and on a fresh one (NaN for NaN, the
    same physical outcome): no warm start or cache leaks from one impact to the next. An impact that
    measured nothing (an error, a timeout) has no bits to compare: the check fails."""
    jobs = [
        Job(
            engine=ctx.name,
            settings=ctx.settings,
            case=ImpactCase(bat=bat, ball=BALL, s_m=s, e=e, **SWING),
        )
        for bat, s, e in (
            (R161, 0.1, 0.5),
            (R161, -0.2, 0.5),
            (R161, 0.2, 0.5),
            (R161, 0.0, 1.0),
            (cork.corked_bat(R161), 0.1, 0.3),
        )
    ]
    if ctx.record.drives_bat:  # a short swing (0.1 rad, 6 ms) uses the drive as a long one
        jobs.append(replace(jobs[0], swing=HingedSwing.for_omega(R161, 32.0, angle_rad=0.1)))
    used = fire_jobs(jobs + jobs)
    for i, job in enumerate(jobs):
        fresh = Hosted(ctx.name, ctx.settings)  # a new adapter, outside the process's cache
        want = guarded(fresh, [job])[0].outcome
        fresh.close()
        for out in (used[i].outcome, used[i + len(jobs)].outcome, want):
            _expect(
                out.physics not in UNMEASURED,
                f"impact {i}: {out.physics} ({out.ended}): nothing measured to compare",
            )
        for out in (used[i].outcome, used[i + len(jobs)].outcome):
            got = (out.physics, out.v1_mps, out.u1_mps, out.omega1_radps, out.steps)
            expected = (want.physics, want.v1_mps, want.u1_mps, want.omega1_radps, want.steps)
            _expect(
                all(a == b or a != a and b != b for a, b in zip(got, expected)),
                f"impact {i}: used {got} != fresh {expected}",
            )
    return f"{len(jobs)} impacts, twice, bit for bit"


def bad_settings_rejected(ctx: Ctx) -> str:
    """Settings are validated when made: a bad value names the field and what is allowed; every
    profile, knob family and integrator of the record is a valid setting."""
    for overrides, piece in (
        ({"dt_s": -1e-3}, "dt_s=-0.001 is out of range"),
        ({"contact_phase": 1.0}, "contact_phase=1.0 is out of range"),
        ({"no_such_knob": 1}, "setting 'no_such_knob' is unknown"),
    ):
        try:
            adapters.settings_for(ctx.name, **overrides)
        except ValueError as err:
            _expect(piece in str(err), f"{overrides}: {err}")
            continue
        raise CheckFailed(f"{overrides} was accepted")
    for family in ctx.record.studies.speed_accuracy:
        adapters.settings_for(ctx.name, family.profile, **dict(family.overrides))
    for integrator in ctx.record.can.integrators:
        adapters.settings_for(ctx.name, **dict(integrator.overrides))
    fields = {f.name for f in dataclasses.fields(ctx.settings)}
    unknown = sorted(set(ctx.record.engine_defaults) - fields)
    _expect(not unknown, f"engine_defaults quotes {unknown}, which are not settings")
    return "3 bad values refused; knobs and integrators valid"


def law_conformance(ctx: Ctx) -> str:
    """A compliant contact matches its own law (``analytic.compliant.predict``) within the
    judge's bound for it (``judge.soft_judgement``), still bat and paper's swing; near the
    barrel's end the ball slides onto the cap, which the law does not model (unjudged)."""
    judged = 0
    for e in (0.3, 0.5, 1.0):
        for kw in (SWING, dict(v0_mps=40.0)):
            cases = [ImpactCase(bat=R161, ball=BALL, s_m=s, e=e, **kw) for s in S_GRID]
            for case, out in zip(cases, ctx.fire(cases)):
                _expect(out.sound, f"s = {case.s_m:.3f}: {out.physics.value}")
                want, allowed = judge.soft_judgement(case, out)
                if math.isnan(allowed):
                    continue
                judged += 1
                _expect(
                    abs(out.v1_mps - want) <= allowed,
                    f"e = {e}, s = {case.s_m:.3f}: v1 {out.v1_mps!r} vs law {want!r} "
                    f"(allowed {allowed:.3g})",
                )
    _expect(judged >= 6 * (len(S_GRID) - 2), f"only {judged} impacts judged")
    return f"{judged} impacts within the law's bound"


def friction_wall(ctx: Ctx) -> str:
    """A ball on a wall (a tonne, 1e3 kg m^2) with friction, 20 m/s at 0.5 rad, e = 0.5: one
    that slides throughout (mu = 0.05: dv_t = -mu dv_n, spin 5 mu dv_n / (2 r)) and one that
    leaves rolling (mu = 1: v_t = 5/7 of its own), each ok against the engine's frictional law
    (``friction_judge``; at a wall the one-step law meets Routh's and these closed forms)."""
    wall = replace(R161, name="wall", mass_kg=1e3, inertia_cm_kgm2=1e3, inertia_axial_kgm2=1e3)
    cases = [
        ImpactCase(bat=wall, ball=BALL, s_m=0.0, v0_mps=20.0, theta_rad=0.5, e=0.5, mu=mu)
        for mu in (0.05, 1.0)
    ]
    rows = table(
        fire_jobs([Job(engine=ctx.name, settings=ctx.settings, case=c) for c in cases]), "check"
    )
    for r in rows.itertuples():
        _expect(
            r.status == Status.OK.value,
            f"mu = {r.mu:g}: {r.status} ({r.episode_end}); vt1 {r.vt1_engine_mps!r} vs "
            f"{r.vt1_law_mps!r}, spin {r.spin1_engine_radps!r} vs {r.spin1_law_radps!r}",
        )
    return "a slide and a grip within their tolerance of the law"


#: Every check, and the engines it applies to: "all", "rigid" (held to rigid theory), "law"
#: (a compliant contact, held to its own law), "batched" (an engine that steps many worlds) or
#: "friction" (a rigid contact with friction and no declared friction defect).
CHECKS: dict[str, tuple[Callable[[Ctx], str], str]] = {
    f.__name__: (f, applies)
    for f, applies in (
        (mass_read_back, "all"),
        (bad_settings_rejected, "all"),
        (restitution, "rigid"),
        (still_bat, "rigid"),
        (energy_at_e1, "rigid"),
        (swinging_bat, "rigid"),
        (corked_bat, "rigid"),
        (large_batch, "batched"),
        (oblique, "rigid"),
        (cop_located, "rigid"),
        (tunnelling_bound, "rigid"),
        (stateless, "all"),
        (law_conformance, "law"),
        (friction_wall, "friction"),
    )
}


def _context(name: str) -> Ctx:
    return Ctx(name=name, record=adapters.record(name), settings=adapters.settings_for(name))


def applicable(name: str) -> tuple[str, ...]:
    """The checks that apply to an engine's reference contact and kind (reads its record)."""
    ctx = _context(name)
    kinds = {
        "all",
        "rigid" if ctx.rigid else "law",
        "batched" if ctx.record.batched else "",
        "friction"
        if ctx.rigid
        and ctx.record.can.friction_rule is not None
        and not ctx.record.errors.friction_defect
        else "",
    }
    return tuple(c for c, (_, applies) in CHECKS.items() if applies in kinds)


def run_check(name: str, check: str) -> CheckResult:
    """One check (a key of CHECKS) on a registered engine, at its reference profile."""
    ctx = _context(name)
    t0 = time.perf_counter()
    try:
        with clock.limited(CHECK_LIMIT_S), clock.exits_raise():
            detail, passed = CHECKS[check][0](ctx), True
    except (Exception, SystemExit, clock.TimedOut, clock.ProcessExit) as err:  # noqa: BLE001
        detail, passed = f"{type(err).__name__}: {err}", False  # the adapter's failure fails it
    return CheckResult(name=check, passed=passed, detail=detail, seconds=time.perf_counter() - t0)


def check_engine(name: str, checks: tuple[str, ...] | None = None) -> CheckReport:
    """Run every check that applies to the engine (or those named) at its reference profile;
    never raises for a failed check: the report says what failed and by how much."""
    return CheckReport(
        engine=name, results=tuple(run_check(name, c) for c in (checks or applicable(name)))
    )
