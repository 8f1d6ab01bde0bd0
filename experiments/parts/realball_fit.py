"""Fitting an engine's contact knobs to the declared baseball (``analytic.ball``).

The ball is fired centrally (s = 0) at a rigid wall (``analytic.ball.WALL``) at several speeds
and its COR = (v1 - u1)/v0 is held to a target law, each residual in units of COR_LAWS' half
range at its speed (MLB's +-0.032 at 85 ft/s [mlbcor]); where the contact lasts
(``BallContact.lasts``) the force's duration at CONTACT_SPEED_MPS (``CONTACT_DEFINITIONS``
"force") is held to CONTACT_S (0.7 ms at 40 m/s [nathan2000]) in units of CONTACT_TOL_S. The
knobs are searched by ``scipy.optimize.least_squares`` in unit coordinates (log where the
record says), by finite differences, or with a Jacobian from the engine's own derivative of
its end states along the knobs (an adapter's ``knob_derivative``).

What is fitted is reached through a ``Probe``: ``EngineProbe`` fires through the harness; a
test's probe may be a closed-form model whose Jacobian it knows.
"""

from __future__ import annotations

import math
import time
from collections.abc import Sequence
from dataclasses import dataclass, replace
from typing import Protocol

import numpy as np
from scipy.optimize import least_squares

import adapters
from adapters import RESTITUTION_KNOB, STATE_FIELDS, BallContact, ContactKnob, Scene
from analytic import ImpactCase, presets
from analytic.ball import CONTACT_S, CONTACT_SPEED_MPS, COR_LAW, WALL, CorLaw, cor_range

from ..core.endings import Physics
from ..core.fire import Job, fire_jobs
from ..core.hosting import hosted
from ..core.placement import start_state

#: How a fit is made: by finite differences (every engine), by the engine's own derivative.
METHODS = ("finite differences", "gradient")
#: The method of a model's row whose study raised (the row says why in ``message``).
FAILED = Physics.ERROR.value
#: Speeds the fit holds the COR at (m/s): the range a game has, 10-60 m/s.
FIT_SPEEDS_MPS = (10.0, 20.0, 30.0, 40.0, 50.0, 60.0)
#: Speeds kept out of the fit and fired again (m/s): MLB's 85 ft/s [mlbcor] among them.
HELD_OUT_SPEEDS_MPS = (15.0, 25.9, 35.0, 45.0, 55.0)
#: --quick: three fit speeds (the ends and the middle) and two held out.
QUICK_FIT_SPEEDS_MPS = (10.0, 40.0, 60.0)
QUICK_HELD_OUT_SPEEDS_MPS = (25.9, 45.0)
#: The contact time's tolerance (s): measured 0.6-1 ms [nathan2000], so 0.7 +- 0.1 ms stays
#: inside the measured range.
CONTACT_TOL_S = 1e-4
#: A residual for an impact that did not end sound (in half-bands): far worse than any bounce.
FAILED_RESIDUAL = 10.0
#: The restitution an impact is fired with when e is not one of the knobs (the contact's own
#: knobs then decide the bounce; the case's e is not read).
UNUSED_E = 0.5
#: Finite-difference step in unit coordinates (1% of a knob's range): far above the float32
#: engines' roundoff in a COR (1e-6) and a contact time read to one step (1e-5 s in 1e-4).
FD_STEP = 1e-2
#: Function evaluations the optimiser may spend (a fit ends sooner when it converges).
MAX_EVALUATIONS = 60


class Probe(Protocol):
    """What a fit moves and measures: ``knobs``, and at knob values ``x`` and ``speeds``
    (m/s) the COR, the contact time (s) and whether each impact ended sound; ``derivative``,
    dCOR/dx (n, k) at ``x``, or None where there is none."""

    knobs: tuple[ContactKnob, ...]
    impacts: int

    def measure(self, x: np.ndarray, speeds: Sequence[float]) -> Measured: ...

    def derivative(self, x: np.ndarray, speeds: Sequence[float]) -> np.ndarray | None: ...


@dataclass(frozen=True, kw_only=True)
class Measured:
    """One parameter vector fired at several speeds: COR (1), contact time (s), sound."""

    cor: np.ndarray
    contact_s: np.ndarray
    sound: np.ndarray


def settings_at(
    engine: str, ball: BallContact, x: Sequence[float]
) -> tuple[adapters.Settings, float]:
    """The engine's settings for knob values ``x`` of one of its ball models (the reference
    profile, the model's overrides and step) and the e its impacts are fired with."""
    step = {} if ball.dt_s is None else {"dt_s": ball.dt_s}
    base = adapters.settings_for(engine, **step, **ball.overrides)
    fields: dict = {}
    e = UNUSED_E
    for knob, value in zip(ball.knobs, x):
        value = float(value)
        if knob.setting == RESTITUTION_KNOB:
            e = value
        elif knob.element is None:
            fields[knob.setting] = value
        else:
            held = list(fields.get(knob.setting, getattr(base, knob.setting)))
            held[knob.element] = value
            fields[knob.setting] = tuple(held)
    return replace(base, **fields), e


def wall_case(speed_mps: float, e: float) -> ImpactCase:
    """The baseball fired centrally at the rigid wall."""
    return ImpactCase(bat=WALL, ball=presets.BASEBALL, s_m=0.0, v0_mps=speed_mps, e=e)


class EngineProbe:
    """One of an engine's ball models (its record's ``balls``) fired through the harness; its
    own ``knob_derivative`` where its adapter has one and every knob is a settings field."""

    def __init__(self, engine: str, ball: BallContact) -> None:
        self.engine, self.ball = engine, ball
        self.knobs = ball.knobs
        self.impacts = 0  # impacts fired (and worlds differentiated) so far
        self._steps: dict[float, int] = {}

    def measure(self, x: np.ndarray, speeds: Sequence[float]) -> Measured:
        settings, e = settings_at(self.engine, self.ball, x)
        jobs = [Job(engine=self.engine, settings=settings, case=wall_case(v, e)) for v in speeds]
        fired = fire_jobs(jobs)
        self.impacts += len(jobs)
        outs = [f.outcome for f in fired]
        for v, o in zip(speeds, outs):
            self._steps[float(v)] = max(self._steps.get(float(v), 0), int(o.steps))
        return Measured(
            cor=np.array([(o.v1_mps - o.u1_mps) / v for v, o in zip(speeds, outs)]),
            contact_s=np.array([o.contact_duration_s for o in outs]),
            sound=np.array([o.physics == Physics.SOUND for o in outs]),
        )

    def has_derivative(self) -> bool:
        """Whether the engine's adapter differentiates its end states along these knobs."""
        if any(k.setting == RESTITUTION_KNOB for k in self.knobs):
            return False
        return bool(adapters.record(self.engine).can.knob_autodiff)

    def derivative(self, x: np.ndarray, speeds: Sequence[float]) -> np.ndarray | None:
        """dCOR/dx (n, k): (d ball_vy - d bat_vy)/v0 from the adapter's ``knob_derivative``
        over as many steps as the longest measured episode and its approach, and as many
        again (after the bounce the bodies fly apart at constant velocity)."""
        if not self.has_derivative():
            return None
        settings, e = settings_at(self.engine, self.ball, x)
        cases = [wall_case(v, e) for v in speeds]
        host = hosted(self.engine, settings)
        host.batch(Scene(bat=WALL, ball=presets.BASEBALL, e=e), len(cases))
        starts = np.array([start_state(c, settings)[0] for c in cases], dtype=float)
        steps = 2 * (max(self._steps.get(float(v), 0) for v in speeds) + settings.approach_steps)
        knobs = [(k.setting, k.element) for k in self.knobs]
        _, d_ends = host.adapter.knob_derivative(starts, steps, knobs)
        self.impacts += len(cases)
        ball_vy, bat_vy = STATE_FIELDS.index("ball_vy_mps"), STATE_FIELDS.index("bat_vy_mps")
        return (d_ends[:, ball_vy, :] - d_ends[:, bat_vy, :]) / np.asarray(speeds)[:, None]


def to_unit(knobs: Sequence[ContactKnob], x: Sequence[float]) -> np.ndarray:
    """Knob values -> unit coordinates in [1, 2] (log where declared): a finite-difference
    step relative to u is then one fraction of the range everywhere."""
    out = []
    for k, v in zip(knobs, x):
        f = math.log(v / k.lo) / math.log(k.hi / k.lo) if k.log else (v - k.lo) / (k.hi - k.lo)
        out.append(1.0 + f)
    return np.array(out)


def from_unit(knobs: Sequence[ContactKnob], u: Sequence[float]) -> np.ndarray:
    """Unit coordinates -> knob values (the inverse of ``to_unit``)."""
    f = np.clip(np.asarray(u, dtype=float) - 1.0, 0.0, 1.0)
    return np.array(
        [
            k.lo * (k.hi / k.lo) ** fi if k.log else k.lo + fi * (k.hi - k.lo)
            for k, fi in zip(knobs, f)
        ]
    )


def dx_du(knobs: Sequence[ContactKnob], x: Sequence[float]) -> np.ndarray:
    """d(knob value)/d(unit coordinate) at ``x``."""
    return np.array([v * math.log(k.hi / k.lo) if k.log else k.hi - k.lo for k, v in zip(knobs, x)])


def half_band(speed_mps: float) -> float:
    """Half of COR_LAWS' range at a speed (1): MLB's 0.032 at 85 ft/s [mlbcor]."""
    lo, hi = cor_range(speed_mps)
    return 0.5 * (hi - lo)


def residuals(
    m: Measured, speeds: Sequence[float], law: CorLaw, lasts: bool, contact_s: float
) -> np.ndarray:
    """(COR - law) / half band at each speed, then (contact - target) / CONTACT_TOL_S at
    CONTACT_SPEED_MPS where the contact lasts; FAILED_RESIDUAL for an impact not sound."""
    r = [
        (c - law.cor(v)) / half_band(v) if ok and math.isfinite(c) else FAILED_RESIDUAL
        for v, c, ok in zip(speeds, m.cor, m.sound)
    ]
    if lasts:
        i = list(speeds).index(CONTACT_SPEED_MPS)
        t = m.contact_s[i]
        ok = m.sound[i] and math.isfinite(t)
        r.append((t - contact_s) / CONTACT_TOL_S if ok else FAILED_RESIDUAL)
    return np.array(r)


@dataclass(frozen=True, kw_only=True)
class Fit:
    """A fit's outcome: knob values ``x``, the cost (half the sum of squared residuals),
    the impacts it fired (and worlds differentiated), the optimiser's function evaluations,
    wall time (s), and how it ended."""

    x: tuple[float, ...]
    cost: float
    impacts: int
    evaluations: int
    wall_s: float
    method: str
    message: str


def fit(
    probe: Probe,
    speeds: Sequence[float],
    start: Sequence[float],
    *,
    lasts: bool,
    law: CorLaw = COR_LAW,
    contact_s: float = CONTACT_S,
    gradient: bool = False,
    max_evaluations: int = MAX_EVALUATIONS,
) -> Fit:
    """Least squares of ``residuals`` over the probe's knobs from ``start``, bounded by their
    ranges: by 2-point finite differences (FD_STEP), or with ``gradient`` a Jacobian from
    ``probe.derivative`` for the COR rows and finite differences at CONTACT_SPEED_MPS alone
    for the contact time's row."""
    knobs, t0, n0 = probe.knobs, time.perf_counter(), probe.impacts
    speeds = tuple(speeds) if not lasts or CONTACT_SPEED_MPS in speeds else (*speeds, 40.0)
    seen: dict[bytes, tuple[Measured, np.ndarray]] = {}

    def measured(u: np.ndarray) -> tuple[Measured, np.ndarray]:
        key = np.asarray(u, dtype=float).tobytes()
        if key not in seen:
            m = probe.measure(from_unit(knobs, u), speeds)
            seen[key] = (m, residuals(m, speeds, law, lasts, contact_s))
        return seen[key]

    def jac(u: np.ndarray) -> np.ndarray:
        x = from_unit(knobs, u)
        d_cor = probe.derivative(x, speeds) * dx_du(knobs, x)[None, :]
        rows = d_cor / np.array([half_band(v) for v in speeds])[:, None]
        if not lasts:
            return rows
        t = measured(u)[0].contact_s[speeds.index(CONTACT_SPEED_MPS)]
        d_t = []
        for j in range(len(knobs)):
            h = FD_STEP * (-1.0 if u[j] + FD_STEP > 2.0 else 1.0)
            moved = np.array(u, dtype=float)
            moved[j] += h
            got = probe.measure(from_unit(knobs, moved), (CONTACT_SPEED_MPS,)).contact_s[0]
            d_t.append((got - t) / h / CONTACT_TOL_S)
        return np.vstack([rows, np.array(d_t)[None, :]])

    res = least_squares(
        lambda u: measured(u)[1],
        to_unit(knobs, start),
        jac=jac if gradient else "2-point",
        bounds=(1.0, 2.0),
        diff_step=FD_STEP,
        max_nfev=max_evaluations,
        x_scale=1.0,
    )
    return Fit(
        x=tuple(float(v) for v in from_unit(knobs, res.x)),
        cost=float(res.cost),
        impacts=probe.impacts - n0,
        evaluations=int(res.nfev + (res.njev or 0)),
        wall_s=time.perf_counter() - t0,
        method=METHODS[1] if gradient else METHODS[0],
        message=str(res.message),
    )
