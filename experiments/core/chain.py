"""Firing a ball at an engine's segmented bat and judging it against the linear chain.

    row = fire_chain("mujoco", settings, impact)

The chain starts straight, moving rigidly, the ball ``APPROACH_STEPS`` steps short of the
touch; the engine steps until the episode is over (no contact for one period of the chain's
lowest mode after the reference's last release) and the row compares the ball's exit speed and
the energy left in bending with ``analytic.chain_impact``: Newton's restitution at every touch
for a rigid-contact engine, its own compliant law for a soft one (its error model's
``contact_law``). Each row has its physical outcome (``physics``) and its verdict
(``status``), as everywhere.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass

import numpy as np

import adapters
from adapters.segmented import ChainScene
from analytic.chain import Chain
from analytic.chain_impact import ChainImpact, ChainOutcome, compliant_reference, impulse_reference

from .answers import Held, Reference, held_to
from .endings import Physics
from .episode import Recorder, run_episode
from .terms import (
    CHAIN_ENERGY_SLACK,
    CHAIN_JUDGED_SHARE,
    CHAIN_MASS_ULPS,
    CHAIN_MAX_EPISODE_S,
    ROUND_OPS,
)

#: Free steps before the touch.
APPROACH_STEPS = 2


@dataclass(frozen=True, kw_only=True)
class ChainTolerance:
    """The exit speed an engine's chain may miss the linear chain by (m/s):

    - rounding: ``round_ops`` operations of the closing speed in the engine's float;
    - a step's stiffening, computed for the impact: a spring integrated implicitly and solved
      with the contact makes the impulse see the chain with dt^2 K added to its mass matrix,
      where the reference's springs pass no impulse; the gap between the two one-step answers,
      (1 + e) v (1/w' - 1/w) / m with w = 1/m + b M^-1 b^T and w' its stiffened value;
    - where the springs act while the ball can still meet the chain (a rigid contact that
      touches again), omega_max dt of the closing speed: in a step the contact point's velocity
      turns by up to that share of its amplitude, and a step is how far a re-touch may fall;
    - for a soft contact, the step's error of its law (``ErrorModel.law_restitution_error``),
      and the linear chain's own: a segment turned by theta moves its surface off the linear
      one's by (R + r) theta^2 / 2 along the normal, that share of the peak overlap.

    A tolerance over ``judged_share`` of the closing speed judges nothing: the step resolves
    the chain too coarsely for a verdict, and the row is 'unjudged'."""

    round_ops: float = ROUND_OPS
    judged_share: float = CHAIN_JUDGED_SHARE

    def mps(
        self, impact: ChainImpact, settings, errors: adapters.ErrorModel, ref: ChainOutcome
    ) -> float:
        chain, dt = impact.chain, settings.dt_s
        closing = impact.v0_mps + impact.u0_mps + impact.omega0_radps * impact.s_m
        M, K, _ = chain.matrices
        b, m = chain.point_row(impact.x_m), impact.ball.mass_kg
        w = 1 / m + b @ np.linalg.solve(M, b)
        w_stiff = 1 / m + b @ np.linalg.solve(M + dt * dt * K, b)
        stiffening = (1 + impact.e) * closing * abs(1 / w_stiff - 1 / w) / m
        tol = closing * self.round_ops * errors.eps + stiffening
        if errors.contact_law(settings, impact.e) is not None:
            reach = chain.bat.radius_m + impact.ball.radius_m
            geometric = reach * ref.peak_turn_rad**2 / 2 / max(ref.peak_overlap_m, 1e-12)
            return tol + closing * (
                errors.law_restitution_error(settings, dt / ref.contact_s) + geometric
            )
        if ref.contacts > 1:
            return tol + closing * float(chain.modes[0].max()) * dt
        return tol


def reference(errors: adapters.ErrorModel, settings, impact: ChainImpact) -> ChainOutcome:
    """The answer that applies to an engine with ``settings``: its compliant law's, or
    Newton's restitution at every touch."""
    return reference_for_law(impact, errors.contact_law(settings, impact.e))


def reference_for_law(impact: ChainImpact, law) -> ChainOutcome:
    """The chain's answer under ``law`` (None: Newton's restitution at every touch)."""
    if law is None:
        return impulse_reference(impact, max_s=CHAIN_MAX_EPISODE_S)
    return compliant_reference(impact, law, max_s=CHAIN_MAX_EPISODE_S)


def start_states(
    impact: ChainImpact, dt_s: float, overlap_m: float = 0.0
) -> tuple[np.ndarray, np.ndarray]:
    """The ball (4,) and segments (N, 6) ``APPROACH_STEPS`` steps before the touch, the ball
    ``overlap_m`` deeper (the settings' overlap at the first step that sees the contact: an
    engine that detects after it moves would otherwise meet the ball a whole step deep)."""
    chain = impact.chain
    x_cm = chain.bat.com_from_knob_m
    coms = np.asarray(chain.coms_m) - x_cm
    lead = APPROACH_STEPS * dt_s
    vy = impact.u0_mps + impact.omega0_radps * coms
    segs = np.zeros((chain.segments, 6))
    segs[:, 0] = coms
    segs[:, 1] = -vy * lead
    segs[:, 2] = -impact.omega0_radps * lead
    segs[:, 4] = vy
    segs[:, 5] = impact.omega0_radps
    reach = chain.bat.radius_m + impact.ball.radius_m
    ball = np.array([impact.s_m, reach + impact.v0_mps * lead - overlap_m, 0.0, -impact.v0_mps])
    return ball, segs


def bending_energy_j(chain: Chain, segments: np.ndarray) -> float:
    """Kinetic energy plus the springs' less the rigid motion's P^2/2M + L^2/2J (J of the
    straight chain: the chain bends by milliradians)."""
    m, inertia = np.asarray(chain.masses_kg), np.asarray(chain.inertias_kgm2)
    v, w = segments[:, 3:5], segments[:, 5]
    ke = 0.5 * float(np.sum(m * np.sum(v * v, axis=1)) + np.sum(inertia * w * w))
    bends = np.diff(segments[:, 2])
    pe = 0.5 * float(np.sum(np.asarray(chain.stiffnesses_nmprad) * bends * bends))
    total_m = float(m.sum())
    com = (m @ segments[:, 0:2]) / total_m
    p = m @ v
    r = segments[:, 0:2] - com
    ang = np.sum(m * (r[:, 0] * v[:, 1] - r[:, 1] * v[:, 0])) + np.sum(inertia * w)
    with np.errstate(over="ignore", invalid="ignore"):  # a blown-up chain: inf, not a raise
        return float(ke + pe - (p @ p) / (2 * total_m) - ang**2 / (2 * chain.bat.inertia_cm_kgm2))


def fire_chain(
    name: str,
    settings,
    impact: ChainImpact,
    tolerance: ChainTolerance = ChainTolerance(),
    known: ChainOutcome | None = None,
) -> dict:
    """One row: the engine's exit speed and bending energy beside the chain's reference
    (``known``, when the caller has solved it already). A reference that did not end
    (ever shorter bounces, or the time limit) judges nothing: the row is 'unjudged'."""
    rec = adapters.record(name)
    ref = known or reference(rec.errors, settings, impact)
    closing = impact.v0_mps + impact.u0_mps + impact.omega0_radps * impact.s_m
    row = {
        "engine": name,
        "segments": impact.chain.segments,
        "dt_s": settings.dt_s,
        "x_m": impact.x_m,
        "v0_mps": impact.v0_mps,
        "e": impact.e,
        "v1_ref_mps": ref.v1_mps,
        "vibration_ref_j": ref.vibration_j,
        "contacts_ref": ref.contacts,
        "ended_ref": ref.ended,
    }
    row["tol_mps"] = tolerance.mps(impact, settings, rec.errors, ref)
    row |= _fired(rec, settings, impact, ref)
    judged = math.nan
    if row["physics"] == Physics.SOUND.value:
        row["err_mps"] = abs(row["v1_mps"] - ref.v1_mps)
        if (
            ref.ended == "separated"
            and row["tol_mps"] <= tolerance.judged_share * closing
            and not _patch_reaches_a_joint(impact, ref)
        ):
            judged = row["tol_mps"]
    held = Held(reference=Reference.SEGMENTED, v1_mps=ref.v1_mps, tol_mps=np.array([judged]))
    row["status"] = held_to([row["physics"]], [row["v1_mps"]], [held]).status[0]
    return row


def _fired(rec, settings, impact: ChainImpact, ref: ChainOutcome) -> dict:
    """The engine's episode on the chain: what it measured and its physical outcome."""
    if rec.can.chain_adapter is None:
        return _failed(Physics.UNSUPPORTED, "no segmented-bat adapter")
    t0 = time.perf_counter()
    try:
        got = _run(rec, settings, impact, ref)
    except _Mismatch as err:
        return _failed(Physics.ERROR, f"scene mismatch: {err}")
    except Exception as err:  # noqa: BLE001 - an engine failure is a row, not a crash
        return _failed(Physics.ERROR, f"{type(err).__name__}: {err}"[:200])
    return got | {"wall_s": time.perf_counter() - t0}


def _patch_reaches_a_joint(impact: ChainImpact, ref: ChainOutcome) -> bool:
    """Whether a compliant contact, sunk ``ref.peak_overlap_m`` deep, reaches along the axis
    (sqrt(2 (R + r) depth)) to a joint, where the ball meets the neighbour's capsule too, or to
    an end, where the cylinder turns into its cap: the reference, one contact point on one
    cylinder, does not apply there."""
    chain = impact.chain
    reach = math.sqrt(2 * (chain.bat.radius_m + impact.ball.radius_m) * ref.peak_overlap_m)
    joints = chain.segment_length_m * np.arange(0, chain.segments + 1)
    return bool(np.any(np.abs(joints - impact.x_m) < reach))


class _Mismatch(RuntimeError):
    pass


def _failed(physics: Physics, why: str) -> dict:
    return {
        "physics": physics.value,
        "why": why,
        "v1_mps": math.nan,
        "vibration_j": math.nan,
        "err_mps": math.nan,
        "steps": 0,
        "wall_s": math.nan,
    }


def _run(rec, settings, impact: ChainImpact, ref: ChainOutcome) -> dict:
    engine = adapters.chain_class(rec.name)(settings)
    chain = impact.chain
    try:
        engine.build(ChainScene(chain=chain, ball=impact.ball, e=impact.e))
        _check_mass(engine.mass_properties(), chain, rec.eps)
        ball, segs = start_states(impact, settings.dt_s, settings.overlap_m)
        engine.set_state(ball, segs)
        before = (
            0.5 * impact.ball.mass_kg * impact.v0_mps**2
            + bending_energy_j(chain, segs)
            + _rigid_ke(chain, segs)
        )
        return _step(engine, chain, impact, ref, settings.dt_s, before)
    finally:
        engine.close()


def _rigid_ke(chain: Chain, segs: np.ndarray) -> float:
    m = np.asarray(chain.masses_kg)
    return 0.5 * float(
        np.sum(m * np.sum(segs[:, 3:5] ** 2, axis=1))
        + np.sum(np.asarray(chain.inertias_kgm2) * segs[:, 5] ** 2)
    )


def _check_mass(got: np.ndarray, chain: Chain, eps: float) -> None:
    want = np.column_stack([chain.masses_kg, chain.coms_m, chain.inertias_kgm2])
    if got.shape != want.shape or not np.allclose(got, want, rtol=CHAIN_MASS_ULPS * eps, atol=0.0):
        worst = np.max(np.abs(got / want - 1.0)) if got.shape == want.shape else math.inf
        raise _Mismatch(f"segment mass properties off by {worst:.1e} relative")


class _ChainEpisode:
    """The chain's episode as a task of ``episode.run_episode``: over when no contact has come
    for a lowest-mode period past the reference's end; ``row`` what it measured."""

    def __init__(
        self, chain: Chain, impact: ChainImpact, ref: ChainOutcome, dt: float, before: float
    ) -> None:
        self.chain, self.impact, self.dt, self.before = chain, impact, dt, before
        self.quiet = 2 * math.pi / float(chain.modes[0][chain.modes[0] > 0].min())
        self.end = APPROACH_STEPS * dt + ref.contact_s + self.quiet
        self.max_steps = math.ceil(CHAIN_MAX_EPISODE_S / dt) + 2  # 'no_separation' comes first
        self.touched, self.last_touch, self.row = False, -math.inf, {}

    def over(self, step: int, engine) -> bool:
        t = step * self.dt
        if engine.in_contact():
            self.touched, self.last_touch = True, t
        ball, segs = engine.read()
        if engine.failed() or not (np.all(np.isfinite(ball)) and np.all(np.isfinite(segs))):
            self.row = _failed(Physics.NON_FINITE, "non-finite state or engine failure")
        elif t >= self.end and t - self.last_touch >= self.quiet:
            self.row = self._ended(ball, segs, step)
        elif t > CHAIN_MAX_EPISODE_S:
            self.row = _failed(Physics.NO_SEPARATION, "still in contact")
        else:
            return False
        self.row["steps"] = step
        return True

    def budget_spent(self, engine) -> None:
        self.row = _failed(Physics.NO_SEPARATION, "still in contact") | {"steps": self.max_steps}

    def _ended(self, ball: np.ndarray, segs: np.ndarray, step: int) -> dict:
        if not self.touched:
            return _failed(Physics.NO_CONTACT, "no contact")
        chain = self.chain
        vib = bending_energy_j(chain, segs)
        with np.errstate(over="ignore", invalid="ignore"):  # a huge but finite chain: inf
            springs = np.asarray(chain.stiffnesses_nmprad) * np.diff(segs[:, 2]) ** 2
            after = (
                0.5 * self.impact.ball.mass_kg * float(ball[2:] @ ball[2:])
                + _rigid_ke(chain, segs)
                + 0.5 * float(np.sum(springs))
            )
        gained = after > self.before * (1 + CHAIN_ENERGY_SLACK)
        physics = Physics.ENERGY_GAINED if gained else Physics.SOUND
        return {
            "physics": physics.value,
            "why": "",
            "v1_mps": float(ball[3]),
            "vibration_j": vib,
            "err_mps": math.nan,
            "steps": step,
            "energy_before_j": self.before,
            "energy_after_j": after,
        }


def _step(engine, chain, impact, ref, dt, before) -> dict:
    """Step until the chain's episode is over (``_ChainEpisode``): its row."""
    task = _ChainEpisode(chain, impact, ref, dt, before)
    run_episode(engine, task, task.max_steps)
    return task.row


def mode_states(chain: Chain, mode: int, speed_mps: float) -> np.ndarray:
    """Segments (N, 6) of the straight chain moving in bending mode ``mode`` (0: the lowest),
    its fastest point at ``speed_mps``: velocities the joints agree with, for pinning an
    engine's springs by the mode's period."""
    omega, vec = chain.modes
    qd = vec[:, np.flatnonzero(omega > 0)[mode]]
    rows = np.array([chain.point_row(x) for x in np.linspace(0, chain.bat.length_m, 201)])
    qd = qd * speed_mps / np.max(np.abs(rows @ qd))
    x_cm = chain.bat.com_from_knob_m
    segs = np.zeros((chain.segments, 6))
    for i, c in enumerate(chain.coms_m):
        row = np.zeros(chain.segments + 1)
        row[0], row[1 : i + 1] = 1.0, chain.segment_length_m
        row[i + 1] = c - i * chain.segment_length_m
        segs[i] = (c - x_cm, 0.0, 0.0, 0.0, row @ qd, qd[i + 1])
    return segs


def measured_period_s(
    engine, chain: Chain, ball_parked: np.ndarray, segs: np.ndarray, dt_s: float, periods: int = 3
) -> float:
    """The period of the first joint's angle, from its zero crossings over ``periods``
    periods of the lowest mode (the ball parked out of reach)."""
    engine.set_state(ball_parked, segs)
    omega = chain.modes[0]
    steps = int(periods * 2 * math.pi / float(omega[omega > 0].min()) / dt_s) + 1
    angles: list[float] = []
    run_episode(
        engine, Recorder(lambda world: angles.append(np.diff(world.read()[1][:, 2])[0])), steps
    )
    a = np.asarray(angles)
    ups = np.flatnonzero((a[:-1] < 0.0) & (a[1:] >= 0.0))
    t = (ups + a[ups] / (a[ups] - a[ups + 1]) + 1) * dt_s
    return float(np.mean(np.diff(t)))
