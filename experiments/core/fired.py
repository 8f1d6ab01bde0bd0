"""Fired impacts as the harness hands them on: one ``Fired`` per job, in order.

A batched engine's outcomes stay columns (``FiredBlock``: one array per outcome field) until a
reader asks for an impact; ``FiredSeq`` chains blocks and lists of ``Fired`` as one sequence.
Building ten thousand frozen outcomes costs more than stepping them (about 3 us each here),
so a batch pays for them only where they are read.
"""

from __future__ import annotations

import itertools
import math
from bisect import bisect_right
from collections.abc import Iterator, Sequence
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from adapters import Settings
from analytic import ImpactCase

from .endings import Physics
from .episode import SimOutcome

#: The outcome fields a block holds as float columns.
FLOAT_FIELDS = (
    "v1_mps",
    "u1_mps",
    "omega1_radps",
    "impulse_ns",
    "q",
    "closing_speed_mps",
    "hand_dv_mps",
    "ke_before_j",
    "ke_after_j",
    "v1_t_mps",
    "u1_t_mps",
    "contact_duration_s",
    "peak_penetration_m",
    "ball_side_m",
    "release_omega_radps",
    "release_angle_rad",
    "v1_z_mps",
    "spin1_radps",
    "backspin1_radps",
)


class Fired(NamedTuple):
    """A fired job: the case as simulated (re-planned under a swing), the engine's outcome, and
    with a swing the analytic omega and angle at release (rad/s, rad; NaN without)."""

    case: ImpactCase
    outcome: SimOutcome
    release_omega_radps: float
    release_angle_rad: float


def outcome(
    cols: dict, i: int | None, *, engine: str, settings: Settings, wall_s: float
) -> SimOutcome:
    """The outcome at row ``i`` of columns (``i`` None: the columns are one impact's values)."""
    pick = (lambda k: cols[k]) if i is None else (lambda k: cols[k][i])
    return SimOutcome(
        **{k: float(pick(k)) for k in FLOAT_FIELDS},
        physics=Physics(pick("physics")),
        steps=int(pick("steps")),
        ended=str(pick("ended")),
        engine=engine,
        settings=settings,
        wall_s=wall_s,
    )


class FiredBlock(Sequence):
    """One batch's fired impacts as columns (``FLOAT_FIELDS``, physics, steps, ended, and the
    analytic release as ``release_omega_analytic_radps``/``release_angle_analytic_rad``),
    each job's own settings (its worlds may differ in ``contact_phase``), and its distinct cases
    where known (``placement.distinct_cases``)."""

    def __init__(
        self,
        cases: Sequence[ImpactCase],
        cols: dict[str, np.ndarray],
        *,
        engine: str,
        settings: Sequence[Settings],
        wall_s: float,
        distinct: tuple[np.ndarray, np.ndarray] | None = None,
    ) -> None:
        self.cases, self.cols = list(cases), cols
        self.engine, self.settings, self.wall_s = engine, settings, wall_s
        self.distinct = distinct

    def __len__(self) -> int:
        return len(self.cases)

    def __getitem__(self, i):
        if isinstance(i, slice):
            return [self[k] for k in range(*i.indices(len(self)))]
        i = range(len(self))[i]
        out = outcome(
            self.cols, i, engine=self.engine, settings=self.settings[i], wall_s=self.wall_s
        )
        return Fired(
            self.cases[i],
            out,
            float(self.cols["release_omega_analytic_radps"][i]),
            float(self.cols["release_angle_analytic_rad"][i]),
        )


class NotFired(Exception):
    """A batch the engine did not fire to the end: each impact's row has ``physics`` and
    ``why`` as how its episode ended, and no measurement; ``cases`` and ``plans``: the cases as
    the batch re-planned them under a swing, and their swing plans, where it did."""

    def __init__(
        self,
        physics: Physics,
        why: str,
        cases: Sequence[ImpactCase] | None = None,
        plans: Sequence | None = None,
    ) -> None:
        super().__init__(why)
        self.physics, self.why, self.cases, self.plans = physics, why, cases, plans


def unmeasured(
    engine: str,
    cases: Sequence[ImpactCase],
    each: Sequence[Settings],
    plans,
    physics: Physics,
    why: str,
    wall_s: float,
) -> list[Fired]:
    """Every job of a batch with no measurement: ``physics``, NaN numbers, ``ended`` = why;
    ``plans``: their swing plans (``placement.SwingPlan``), or None."""
    nan = math.nan
    out = []
    for case, settings, plan in zip(cases, each, plans or [None] * len(cases)):
        o = SimOutcome(
            v1_mps=nan,
            u1_mps=nan,
            omega1_radps=nan,
            impulse_ns=nan,
            q=nan,
            closing_speed_mps=case.closing_speed_mps,
            hand_dv_mps=nan,
            ke_before_j=nan,
            ke_after_j=nan,
            v1_t_mps=nan,
            u1_t_mps=nan,
            engine=engine,
            physics=physics,
            contact_duration_s=0.0,
            peak_penetration_m=nan,
            steps=0,
            wall_s=wall_s,
            settings=settings,
            ended=why,
            ball_side_m=nan,
        )
        out.append(Fired(case, o, *analytic_release(plan)))
    return out


def analytic_release(plan) -> tuple[float, float]:
    """A swing plan's analytic omega and angle at release (rad/s, rad); NaN without one."""
    return (
        (math.nan, math.nan) if plan is None else (plan.omega_release_radps, plan.angle_release_rad)
    )


def nan_release(n: int) -> dict[str, np.ndarray]:
    """The analytic release columns of a batch fired without a swing."""
    return {
        "release_omega_analytic_radps": np.full(n, math.nan),
        "release_angle_analytic_rad": np.full(n, math.nan),
    }


class FiredSeq(Sequence):
    """Parts (``FiredBlock``s and lists of ``Fired``) read as one sequence, in order."""

    def __init__(self, parts: Sequence[Sequence[Fired]] = ()) -> None:
        self.parts = [p for p in parts if len(p)]
        self._ends = list(itertools.accumulate(len(p) for p in self.parts))

    def __len__(self) -> int:
        return self._ends[-1] if self._ends else 0

    def __getitem__(self, i):
        if isinstance(i, slice):
            return [self[k] for k in range(*i.indices(len(self)))]
        i = range(len(self))[i]
        k = bisect_right(self._ends, i)
        return self.parts[k][i - (self._ends[k - 1] if k else 0)]

    def __iter__(self) -> Iterator[Fired]:
        for part in self.parts:
            yield from part

    def __add__(self, other: Sequence[Fired]) -> FiredSeq:
        return FiredSeq([*self.parts, *(other.parts if isinstance(other, FiredSeq) else [other])])

    def __radd__(self, other: Sequence[Fired]) -> FiredSeq:
        return FiredSeq([list(other), *self.parts])


@dataclass(frozen=True, kw_only=True)
class Gathered:
    """Fired impacts as columns, whatever parts they came in: each impact's case, settings and
    engine, and ``cols``: FLOAT_FIELDS, physics (its value), steps, ended, wall_s and the
    analytic release (``release_omega_analytic_radps``, ``release_angle_analytic_rad``), one
    array each (units as in ``SimOutcome``); ``distinct``: the distinct cases, where known
    (``placement.distinct_cases``)."""

    cases: list[ImpactCase]
    settings: list[Settings]
    engines: list[str]
    cols: dict[str, np.ndarray]
    distinct: tuple[np.ndarray, np.ndarray] | None = None

    def outcomes(self, rows: Sequence[int]) -> list[SimOutcome]:
        """The outcomes of the impacts at ``rows``, as fired: each column picked at all rows at
        once (a third of the time of one ``outcome`` per row)."""
        rows = np.asarray(rows, dtype=np.intp)
        c = {k: self.cols[k][rows].astype(float).tolist() for k in (*FLOAT_FIELDS, "wall_s")}
        c.update({k: self.cols[k][rows].tolist() for k in ("steps", "ended")})
        physics = [Physics(v) for v in self.cols["physics"][rows].tolist()]
        return [
            SimOutcome(
                **{k: c[k][j] for k in FLOAT_FIELDS},
                physics=physics[j],
                steps=int(c["steps"][j]),
                ended=str(c["ended"][j]),
                engine=self.engines[i],
                settings=self.settings[i],
                wall_s=c["wall_s"][j],
            )
            for j, i in enumerate(rows.tolist())
        ]


#: The columns ``gather`` makes besides FLOAT_FIELDS.
_OTHER = (
    "physics",
    "steps",
    "ended",
    "wall_s",
    "release_omega_analytic_radps",
    "release_angle_analytic_rad",
)


def _block_columns(part: Sequence[Fired]) -> tuple[list, list, list, dict]:
    """One part's cases, settings, engines and columns (``Gathered``)."""
    if isinstance(part, FiredBlock):
        n = len(part)
        cols = {k: part.cols[k] for k in (*FLOAT_FIELDS, *_OTHER[:3], *_OTHER[4:])}
        cols["wall_s"] = np.full(n, part.wall_s)
        return part.cases, list(part.settings), [part.engine] * n, cols
    outs = [f.outcome for f in part]
    # one array for every float field (a view per field): one conversion, not one a field
    table = np.array([[getattr(o, k) for k in FLOAT_FIELDS] for o in outs], dtype=float)
    cols = dict(zip(FLOAT_FIELDS, table.reshape(-1, len(FLOAT_FIELDS)).T))
    cols.update(
        physics=np.array([o.physics.value for o in outs]),
        steps=np.array([o.steps for o in outs]),
        ended=np.array([o.ended for o in outs]),
        wall_s=np.array([o.wall_s for o in outs], dtype=float),
        release_omega_analytic_radps=np.array([f.release_omega_radps for f in part], dtype=float),
        release_angle_analytic_rad=np.array([f.release_angle_rad for f in part], dtype=float),
    )
    return ([f.case for f in part], [o.settings for o in outs], [o.engine for o in outs], cols)


def gather(fired: Sequence[Fired]) -> Gathered:
    """``fired`` as columns (a batch's block read as it is, without an outcome per impact)."""
    parts = [
        _block_columns(p)
        for p in (fired.parts if isinstance(fired, FiredSeq) else [fired])
        if len(p)
    ]
    if not parts:
        parts = [_block_columns([])]
    one = fired.parts[0] if isinstance(fired, FiredSeq) and len(fired.parts) == 1 else fired

    def joined(i: int) -> list:
        return list(itertools.chain.from_iterable(p[i] for p in parts))

    made_here = len(parts) == 1 and not isinstance(one, FiredBlock)  # (its columns are new)
    return Gathered(
        cases=joined(0),
        settings=joined(1),
        engines=joined(2),
        cols=parts[0][3]
        if made_here
        else {k: np.concatenate([p[3][k] for p in parts]) for k in (*FLOAT_FIELDS, *_OTHER)},
        distinct=one.distinct if isinstance(one, FiredBlock) else None,
    )
